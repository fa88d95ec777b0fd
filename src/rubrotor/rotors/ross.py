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
lateral ones (true for ROSS's shaft, disk and bearing elements), else :func:`from_ross` refuses.
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


def _bearing_table(b, speeds) -> tuple[np.ndarray | None, np.ndarray, np.ndarray]:
    """Speeds (rad/s) and the 2x2 lateral ``K``, ``C`` of one ROSS bearing at each."""
    if b.frequency is None or np.size(b.frequency) <= 1:
        table = np.array([0.0])
    else:
        table = np.atleast_1d(np.asarray(b.frequency if speeds is None else speeds, float))
    k = np.array([np.asarray(b.K(f), float)[:2, :2] for f in table])
    c = np.array([np.asarray(b.C(f), float)[:2, :2] for f in table])
    return (None if len(table) == 1 else table), k, c


def _check_elements(rotor) -> None:
    for name in ("point_mass_elements", "disk_elements", "bearing_elements"):
        if name == "point_mass_elements" and getattr(rotor, name, []):
            raise InputError(
                "rotor.point_mass_elements",
                len(rotor.point_mass_elements),
                "none (point masses and extra DOFs are not supported by from_ross)",
            )
    for b in rotor.bearing_elements:
        if getattr(b, "n_link", None) is not None:
            raise InputError(
                "bearing.n_link", b.n_link, "None (bearings linked to extra DOFs are unsupported)"
            )
        m = np.asarray(b.M(0.0), float)
        if np.any(m != 0.0):
            raise InputError("bearing mass", m.tolist(), "zero (bearing masses are unsupported)")


def from_ross(rotor, speeds=None) -> LinearSystem:
    """Turn a ROSS ``Rotor`` into a :class:`~rubrotor.rotors.linear.LinearSystem` with the same matrices.

    Parameters
    ----------
    rotor : ross.Rotor
        A ROSS rotor made of shaft, disk and bearing/seal elements (no point masses, no bearings
        linked to extra DOFs).
    speeds : array_like, optional
        Speeds (rad/s) at which to tabulate each speed-dependent bearing from ROSS's own
        interpolant. By default each bearing's own ``frequency`` table is used (between table
        points ROSS interpolates with splines, ours linearly, so pass a finer grid to follow ROSS
        between its points).

    Returns
    -------
    LinearSystem
        ``M`` (kg, kg m^2), ``K`` (N/m), ``C`` (N s/m: shaft and disk damping only), ``G``
        (kg m^2 per rad/s of spin) on our DOFs ``[v, w, psi_v, psi_w]`` per node; the bearings as
        :class:`~rubrotor.rotors.linear.Support` with their speed tables; ``basis`` on ROSS's node
        positions (m).

    Raises
    ------
    ImportError
        ROSS is not installed (the message gives the install command).
    InputError
        The rotor holds unsupported elements or couples lateral and axial/torsional DOFs.
    """
    _import_ross()
    _check_elements(rotor)
    nodes = np.asarray(rotor.nodes_pos, float)
    idx, sign = ross_dof_map(len(nodes), int(rotor.number_dof))
    full = int(rotor.ndof)
    if full != int(rotor.number_dof) * len(nodes):
        raise InputError(
            "rotor.ndof", full, f"{rotor.number_dof} x {len(nodes)} nodes (no extra DOFs)"
        )
    t = np.zeros((full, len(idx)))
    t[idx, np.arange(len(idx))] = sign

    k_b = np.zeros((full, full))
    c_b = np.zeros((full, full))
    for b in rotor.bearing_elements:
        d = list(b.dof_global_index.values())
        k_b[np.ix_(d, d)] += np.asarray(b.K(0.0), float)
        c_b[np.ix_(d, d)] += np.asarray(b.C(0.0), float)
    ross_mats = {
        "M": np.asarray(rotor.M(0.0), float),
        "K": np.asarray(rotor.K(0.0), float) - k_b,
        "C": np.asarray(rotor.C(0.0), float) - c_b,
        "G": np.asarray(rotor.G(), float),
    }
    other = np.setdiff1d(np.arange(full), idx)
    for nm, a in ross_mats.items():
        scale = max(np.abs(a).max(), 1e-300)
        if np.abs(a[np.ix_(idx, other)]).max(initial=0.0) > 1e-12 * scale:
            raise InputError(
                f"ROSS {nm}", "lateral-axial/torsional coupling", "uncoupled lateral DOFs"
            )
    mats = {nm: t.T @ a @ t for nm, a in ross_mats.items()}

    supports = []
    for i, b in enumerate(rotor.bearing_elements):
        n = int(b.n)
        table, k, c = _bearing_table(b, speeds)
        supports.append(
            Support(
                dofs=(4 * n, 4 * n + 1),
                k=k,
                c=c,
                speeds=table,
                position=float(nodes[n]),
                name=str(getattr(b, "tag", None) or f"bearing {i + 1}"),
            )
        )
    labels = tuple(f"{q}@{x:g}" for x in nodes for q in ("v", "w", "psi_v", "psi_w"))
    return LinearSystem(
        M=mats["M"],
        K=mats["K"],
        C=mats["C"],
        G=mats["G"],
        basis=NodalBasis(nodes),
        supports=tuple(supports),
        dof_labels=labels,
        name="ross",
    )
