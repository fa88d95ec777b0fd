"""Import a ROSS rotor (``ross-rotordynamics``) as a :class:`rubrotor.rotors.linear.LinearSystem`.

ROSS is an optional dependency (``pip install "rubrotor[ross]"``); it is imported only when
:func:`from_ross` is called. Tested with ROSS 2.3.0 (what pip resolves on Python 3.11) and
ROSS 3.1.0 (Python 3.13): both lines have the same element, rotor-matrix and ``run_modal`` API
for what is used here, so one code path serves both.

DOF mapping
-----------
ROSS puts the rotor axis along its ``z`` and gives each node 6 DOFs ``[x, y, z, alpha, beta,
theta]`` (4 DOFs ``[x, y, alpha, beta]`` in older lines), with ``alpha`` and ``beta`` the
rotations about ``x`` and ``y``. Its spin turns ``+x`` towards ``+y``. Ours (see
:mod:`rubrotor.rotors.linear`) has the axis along ``x`` and ``[v, w, psi_v, psi_w]`` per node with spin
from ``+y`` towards ``+z``. The cyclic relabelling ROSS ``(z, x, y)`` -> ours ``(x, y, z)`` keeps
both frames right-handed and both spins positive, so::

    v = x,   w = y,   psi_v = dx/dz = beta,   psi_w = dy/dz = -alpha

i.e. ``q_ours = T^T q_ross`` with ``T`` a signed selection matrix and every ROSS matrix ``A``
becomes ``T^T A T``. The axial and torsional DOFs are dropped; they must be uncoupled from the
lateral ones (true for ROSS's shaft, disk, bearing and point-mass elements), else
:func:`from_ross` refuses, naming the element that couples them. A point mass (ROSS
``PointMass``, e.g. a bearing housing) adds its two lateral DOFs ``[v, w] = [x, y]`` after the
nodal ones (``NodalBasis.extra``).

What is imported
----------------
* Shaft and disk elements: ``M``, ``K``, ``C`` (ROSS's shaft damping), ``G``.
* Bearings and seals (every ``BearingElement`` subclass: seals, magnetic, fluid-film bearings):
  their lateral 2x2 stiffness and damping as a :class:`~rubrotor.rotors.linear.Support`, to the
  ground or, with ``n_link``, between the node and the linked node. Tables against ``speed``
  (ROSS 3.x), ``frequency`` (ROSS 2.3 and 3.x) or both (ROSS 3.x 2-D seal tables) are read at
  their synchronous value, the coefficient at whirl frequency = spin speed: that is how every
  rubrotor analysis and ROSS's ``run_modal``, ``run_campbell``, ``run_critical_speed`` and
  ``run_unbalance_response`` evaluate them. The table speeds are the union of the element's axes
  (or ``speeds=``); the values there are ROSS's own, so both codes agree exactly at table points.
  Between them the support interpolates as ROSS 3.x does (PCHIP, or the element's
  ``interpolation="linear"``), or linearly on request; outside, it extrapolates linearly from the
  end slope as ROSS 3.x does.
* Bearing mass (``mxx``, ``myy``, ``mxy = myx``): constant, added to ``M``.
* Point masses (``mx``, ``my``): in ``M`` on their own DOFs.

Refused, with the element's class, tag and node: speed-dependent or non-symmetric bearing mass,
a motor element, and any element coupling lateral with axial or torsional DOFs (ROSS's gear
elements, 6-DOF couplings with such terms).
"""

from __future__ import annotations

import numpy as np

from rubrotor.errors import InputError
from rubrotor.rotors.linear import LinearSystem, NodalBasis, Support

__all__ = ["from_ross", "ross_dof_map"]

INSTALL = 'pip install "rubrotor[ross]"  (ross-rotordynamics>=2.3 and plotly<7)'


def _import_ross():
    try:
        import ross
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(f"from_ross needs ROSS: {INSTALL}") from exc
    return ross


def ross_dof_map(n_nodes: int, dofs_per_node: int) -> tuple[np.ndarray, np.ndarray]:
    """ROSS DOF index and sign for each of our DOFs.

    Parameters
    ----------
    n_nodes : int
        Number of shaft nodes.
    dofs_per_node : int
        ROSS's ``rotor.number_dof`` (6 in ROSS 2.x/3.x, 4 in older lines).

    Returns
    -------
    index : ndarray of int, shape (4 n_nodes,)
        ROSS global DOF of our DOF ``j``.
    sign : ndarray of float, shape (4 n_nodes,)
        ``q_ours[j] = sign[j] * q_ross[index[j]]``.
    """
    if dofs_per_node == 6:
        local = np.array([0, 1, 4, 3])  # x, y, beta, alpha
    elif dofs_per_node == 4:
        local = np.array([0, 1, 3, 2])
    else:
        raise InputError("rotor.number_dof", dofs_per_node, "4 or 6 DOFs per node")
    index = (dofs_per_node * np.arange(n_nodes)[:, None] + local[None, :]).ravel()
    sign = np.tile([1.0, 1.0, 1.0, -1.0], n_nodes)
    return index, sign


def _label(e) -> str:
    """``'SealElement "seal3" at node 12'``: how an error names a ROSS element."""
    tag = getattr(e, "tag", None)
    return f"{type(e).__name__} {tag!r} at node {getattr(e, 'n', '?')}"


def _table_speeds(b, speeds) -> np.ndarray | None:
    """Speeds (rad/s) at which to read a ROSS bearing, ``None`` when its coefficients are constant."""
    axes = [getattr(b, "speed", None), getattr(b, "frequency", None)]
    axes = [np.atleast_1d(np.asarray(a, float)) for a in axes if a is not None]
    axes = [a for a in axes if a.size > 1]
    if not axes:
        return None
    if speeds is not None:
        return np.unique(np.asarray(speeds, float))
    return np.unique(np.concatenate(axes))


def _coefficient(b, name: str, w: float, lateral: list[int]) -> np.ndarray:
    """ROSS's ``K``, ``C`` or ``M`` of bearing ``b`` at speed = frequency ``w`` (rad/s), refused
    when it couples its lateral DOFs with the others."""
    a = np.asarray(getattr(b, name)(w), float)
    other = np.setdiff1d(np.arange(a.shape[0]), lateral)
    if np.any(a[np.ix_(lateral, other)] != 0.0) or np.any(a[np.ix_(other, lateral)] != 0.0):
        raise InputError(_label(b), f"{name} couples x, y with z", "uncoupled lateral DOFs")
    return a


def _bearing_mass(b) -> np.ndarray:
    """The constant lateral 2x2 mass (kg) of bearing ``b``; refused when it varies or is skew."""
    values = {}
    for nm in ("mxx", "myy", "mxy", "myx"):
        v = getattr(b, nm, None)
        values[nm] = np.atleast_1d(np.asarray(0.0 if v is None else v, float))
    for nm, v in values.items():
        if np.ptp(v) != 0.0:
            raise InputError(
                f"{_label(b)}.{nm}", v.tolist(), "a constant bearing mass (kg), not a table"
            )
    m = np.array([[values["mxx"].flat[0], values["mxy"].flat[0]],
                  [values["myx"].flat[0], values["myy"].flat[0]]])  # fmt: skip
    if m[0, 1] != m[1, 0]:
        raise InputError(f"{_label(b)}.mxy", (m[0, 1], m[1, 0]), "mxy = myx (a symmetric mass)")
    return m


def _support(b, rotor_bearings, index: dict, nodes, speeds, interpolation: str) -> Support:
    """One ROSS bearing or seal as a :class:`Support` on our DOFs (``index``: ROSS DOF -> ours)."""
    dof = b.dof_global_index
    ends = [b.n] + ([b.n_link] if getattr(b, "n_link", None) is not None else [])
    ross = [(dof[f"x_{n}"], dof[f"y_{n}"]) for n in ends]
    keys = list(dof)
    lateral = [keys.index(f"{q}_{n}") for n in ends for q in ("x", "y")]
    table = _table_speeds(b, speeds)
    at = np.array([0.0]) if table is None else table
    k = np.array([_coefficient(b, "K", w, lateral)[np.ix_(lateral[:2], lateral[:2])] for w in at])
    c = np.array([_coefficient(b, "C", w, lateral)[np.ix_(lateral[:2], lateral[:2])] for w in at])
    if interpolation == "ross":
        interpolation = "pchip" if getattr(b, "interpolation", "") == "pchip" else "linear"
    n = int(b.n)
    while n >= len(nodes):  # a housing's support: at the shaft node its housing is linked to
        n = next(int(o.n) for o in rotor_bearings if getattr(o, "n_link", None) == n)
    return Support(
        dofs=tuple(index[i] for i in ross[0]),
        k=k,
        c=c,
        speeds=table,
        position=float(nodes[n]),
        name=str(getattr(b, "tag", None) or f"{type(b).__name__} at node {b.n}"),
        interpolation=interpolation,
        extrapolation="linear",
        link=tuple(index[i] for i in ross[1]) if len(ross) > 1 else None,
        axis="frequency" if _frequency_only(b) else "speed",
        kind="seal" if _is_seal(b) else "bearing",
    )


def _is_seal(b) -> bool:
    """ROSS's ``SealElement`` (or a subclass): no static load in API 617's check."""
    return any(c.__name__ == "SealElement" for c in type(b).__mro__)


def _masses(rotor, nodes: np.ndarray) -> tuple:
    """``(left, right, mass)`` of ROSS's shaft elements and lumped masses (m, m, kg), for
    :attr:`LinearSystem.masses`; a point mass sits at the shaft node its housing joins."""
    out = [(float(nodes[e.n]), float(nodes[e.n + 1]), float(e.m)) for e in rotor.shaft_elements]
    out += [(float(nodes[d.n]), float(nodes[d.n]), float(d.m)) for d in rotor.disk_elements]
    links = {b.n_link: b.n for b in rotor.bearing_elements if getattr(b, "n_link", None)}
    for p in getattr(rotor, "point_mass_elements", []):
        n, seen = int(p.n), set()
        while n >= len(nodes) and n in links and n not in seen:
            seen.add(n)
            n = int(links[n])
        if n < len(nodes):
            out.append((float(nodes[n]), float(nodes[n]), 0.5 * (float(p.mx) + float(p.my))))
    return tuple(out)


def _frequency_only(b) -> bool:
    """ROSS 3.x element tabulated against the whirl frequency only (``frequency=``, no
    ``speed=``): its table is read at the excitation frequency (ROSS 2.3's ``frequency=`` is
    read synchronously: it is a speed table)."""
    import ross

    if int(ross.__version__.split(".")[0]) < 3:
        return False
    speed, freq = getattr(b, "speed", None), getattr(b, "frequency", None)
    return (speed is None or np.size(speed) < 2) and freq is not None and np.size(freq) > 1


def _ours(rotor, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[int], list[str]]:
    """ROSS DOF index and sign of each of our DOFs (nodal, then point masses' ``[v, w]``), the
    point-mass nodes and our DOF labels."""
    idx, sign = ross_dof_map(len(nodes), int(rotor.number_dof))
    labels = [f"{q}@{x:g}" for x in nodes for q in ("v", "w", "psi_v", "psi_w")]
    extra_nodes = sorted({int(p.n) for p in getattr(rotor, "point_mass_elements", [])})
    extra = []
    for n in extra_nodes:
        p = next(p for p in rotor.point_mass_elements if int(p.n) == n)
        extra += [p.dof_global_index[f"x_{n}"], p.dof_global_index[f"y_{n}"]]
        labels += [f"v@mass node {n}", f"w@mass node {n}"]
    idx = np.concatenate([idx, np.array(extra, int)])
    sign = np.concatenate([sign, np.ones(len(extra))])
    return idx, sign, extra_nodes, labels


def _refuse_coupling(rotor, name: str, a: np.ndarray, idx: np.ndarray) -> None:
    """Refuse a base matrix that couples our DOFs with ROSS's dropped ones, naming the element."""
    other = np.setdiff1d(np.arange(a.shape[0]), idx)
    block = np.abs(a[np.ix_(idx, other)])
    scale = max(np.abs(a).max(), 1e-300)
    if block.max(initial=0.0) <= 1e-12 * scale:
        return
    i, j = np.unravel_index(np.argmax(block), block.shape)
    pair = (int(idx[i]), int(other[j]))
    held = [e for e in rotor.elements if set(pair) <= set(_dofs(e).values())]
    culprit = next((e for e in held if _couples(e, name, pair)), held[0] if held else None)
    where = _label(culprit) if culprit is not None else f"ROSS DOFs {sorted(pair)}"
    raise InputError(
        where, f"{name} couples lateral with axial/torsional DOFs", "uncoupled lateral DOFs"
    )


def _dofs(e) -> dict:
    return getattr(e, "dof_global_index", None) or {}


def _couples(e, name: str, pair: tuple[int, int]) -> bool:
    """Whether element ``e``'s own matrix ``name`` (``M``, ``K``, ``C`` or ``G``) holds the
    entry between the global DOFs ``pair``."""
    where = list(_dofs(e).values())
    for args in ((), (0.0,)):
        try:
            a = np.asarray(getattr(e, name)(*args), float)
        except TypeError:
            continue
        if a.shape[0] == len(where):
            return bool(a[where.index(pair[0]), where.index(pair[1])] != 0.0)
    return False


def _check_elements(rotor) -> None:
    if getattr(rotor, "motor_element", None) is not None:
        raise InputError(_label(rotor.motor_element), "a motor element", "no motor (not mapped)")
    known = ("shaft_elements", "disk_elements", "bearing_elements", "point_mass_elements")
    listed = {id(e) for nm in known for e in getattr(rotor, nm, [])}
    for e in getattr(rotor, "elements", []):
        if id(e) not in listed:
            raise InputError(
                _label(e), type(e).__name__, "shaft, disk, bearing, seal or point mass"
            )


INTERPOLATION = ("ross", "linear", "pchip")


def from_ross(rotor, speeds=None, interpolation: str = "ross") -> LinearSystem:
    """Turn a ROSS ``Rotor`` into a :class:`~rubrotor.rotors.linear.LinearSystem` with the same matrices.

    Parameters
    ----------
    rotor : ross.Rotor
        A ROSS 2.3 or 3.x rotor of shaft, disk, bearing/seal (also linked to housings) and point
        mass elements (see the module docstring for what is refused).
    speeds : array_like, optional
        Speeds (rad/s) at which to tabulate every speed- or frequency-dependent bearing and seal
        from ROSS's own interpolant (synchronous: frequency = speed). Default: each element's
        own table points (the union of its ``speed`` and ``frequency`` axes). Pass a fine grid to
        follow ROSS 2.3's smoothing splines between their points.
    interpolation : str
        Between table speeds: ``"ross"`` (default: as the element does in ROSS 3.x, PCHIP unless
        it was built with ``interpolation="linear"``; linear for ROSS 2.3, whose smoothing
        splines no interpolant reproduces), ``"linear"`` or ``"pchip"``.

    Returns
    -------
    LinearSystem
        ``M`` (kg, kg m^2; point masses and bearing masses included), ``K`` (N/m), ``C`` (N s/m:
        shaft and disk damping only), ``G`` (kg m^2 per rad/s of spin) on our DOFs
        ``[v, w, psi_v, psi_w]`` per node, then ``[v, w]`` per point mass; the bearings and
        seals as :class:`~rubrotor.rotors.linear.Support` with their speed tables; ``basis`` on
        ROSS's node positions (m).

    Raises
    ------
    ImportError
        ROSS is not installed (the message gives the install command).
    InputError
        An element that cannot be mapped, named with its class, tag and node.
    """
    _import_ross()
    if interpolation not in INTERPOLATION:
        raise InputError("interpolation", interpolation, " or ".join(map(repr, INTERPOLATION)))
    if speeds is not None:
        grid = np.atleast_1d(np.asarray(speeds, float))
        if grid.ndim != 1 or grid.size == 0 or not np.all(np.isfinite(grid)):
            raise InputError("speeds", speeds, "a non-empty list of finite speeds (rad/s)")
    _check_elements(rotor)
    nodes = np.asarray(rotor.nodes_pos, float)
    idx, sign, extra_nodes, labels = _ours(rotor, nodes)
    full = int(rotor.ndof)
    t = np.zeros((full, len(idx)))
    t[idx, np.arange(len(idx))] = sign
    index = {int(r): j for j, r in enumerate(idx)}

    bases = {"K": np.zeros((full, full)), "C": np.zeros((full, full))}
    m_b = np.zeros((full, full))
    for b in rotor.bearing_elements:
        d = list(b.dof_global_index.values())
        for nm, a in bases.items():
            a[np.ix_(d, d)] += np.asarray(getattr(b, nm)(0.0), float)
        m_b[np.ix_(d, d)] += np.asarray(b.M(0.0), float)
        _bearing_mass(b)  # refuse a variable or skew mass before it reaches M
    ross_mats = {
        "M": np.asarray(rotor.M(0.0), float),
        "K": np.asarray(rotor.K(0.0), float) - bases["K"],
        "C": np.asarray(rotor.C(0.0), float) - bases["C"],
        "G": np.asarray(rotor.G(), float),
    }
    for nm, a in ross_mats.items():
        _refuse_coupling(rotor, nm, a - (m_b if nm == "M" else 0.0), idx)
    mats = {nm: t.T @ a @ t for nm, a in ross_mats.items()}
    supports = tuple(
        _support(b, rotor.bearing_elements, index, nodes, speeds, interpolation)
        for b in rotor.bearing_elements
    )
    return LinearSystem(
        M=mats["M"],
        K=mats["K"],
        C=mats["C"],
        G=mats["G"],
        basis=NodalBasis(nodes, extra=2 * len(extra_nodes)),
        supports=supports,
        dof_labels=tuple(labels),
        name="ross",
        masses=_masses(rotor, nodes),
    )
