"""A ROSS rotor as plain data: from a ROSS ``Rotor`` object or from its saved file, without ROSS.

:func:`read_ross_file` reads the TOML (or JSON) file that ROSS 3.x's ``Rotor.save`` writes (and
ROSS 2.x's TOML, which has the same element tables) with the standard library only: ROSS need
not be installed. :func:`ross_model` reads the same data off a ROSS ``Rotor`` object (ROSS 2.3
or 3.x). Both give a :class:`RossModel`: ROSS's element parameters (shaft elements, disks,
point masses) and every bearing and seal as a lateral 2x2 stiffness/damping table in rubrotor's
directions (``v = x``, ``w = y``; see :func:`rubrotor.rotors.ross.from_ross`), from which
:func:`rubrotor.scenario.ross.ross_scenario_dict` writes scenario tables.

Tables
------
A 1-D ``speed=`` table is kept on the speed axis and a 1-D ``frequency=`` table on the whirl
frequency axis (ROSS 3.x; ROSS 2.x's ``frequency=`` tables are read synchronously, as ROSS 2.x
reads them, i.e. on the speed axis). A 2-D (speed x frequency) table of ROSS 3.x is read on its
synchronous diagonal (frequency = speed) at the union of its axes, PCHIP (or linear) along each
axis with linear end extrapolation as ROSS 3.x evaluates it; the scenario then holds that
synchronous table (what ``run_modal``, ``run_campbell`` and ``run_unbalance_response`` use).
"""

from __future__ import annotations

import json
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rubrotor.errors import InputError

__all__ = ["RossModel", "RossSupport", "read_ross_file", "ross_model"]

_PAIRS = (("xx", 0, 0), ("xy", 0, 1), ("yx", 1, 0), ("yy", 1, 1))


@dataclass(frozen=True)
class RossSupport:
    """One ROSS bearing or seal on rubrotor's lateral DOFs.

    Attributes
    ----------
    name : str
        ROSS's tag (or class and node).
    n : int
        ROSS node it acts on (a shaft node or a point mass's node).
    n_link : int or None
        Second node (a housing's point mass) or None for the ground.
    k, c : ndarray, shape (m, 2, 2)
        ``[[kxx, kxy], [kyx, kyy]]`` (N/m) and damping (N s/m) at each table point.
    axis : ndarray or None
        Table points (rad/s), None for constant coefficients.
    kind : {"speed", "frequency"}
        What ``axis`` tabulates.
    interpolation : {"pchip", "linear"}
        ROSS's interpolation between table points.
    mass : ndarray, shape (2, 2)
        Constant bearing mass (kg).
    seal : bool
        A ROSS ``SealElement`` (no static load in API 617's check).
    """

    name: str
    n: int
    n_link: int | None
    k: np.ndarray
    c: np.ndarray
    axis: np.ndarray | None
    kind: str
    interpolation: str
    mass: np.ndarray
    seal: bool = False


@dataclass(frozen=True)
class RossModel:
    """A ROSS rotor's data (SI units, ROSS's node numbering)."""

    shafts: list = field(default_factory=list)
    """Shaft elements: dicts with ``L, idl, odl, idr, odr, n, shear_effects, rotary_inertia,
    gyroscopic, shear_method_calc, alpha, beta, material`` (``name, E, G_s, rho``)."""
    disks: list = field(default_factory=list)
    """Disks: dicts with ``n, m, Id, Ip, tag``."""
    supports: list = field(default_factory=list)
    """Bearings and seals (:class:`RossSupport`)."""
    point_masses: list = field(default_factory=list)
    """Point masses: dicts with ``n, mx, my, tag``."""
    version: str = ""
    damping: tuple = (0.0, 0.0)
    """Rotor-wide ``(alpha, beta)`` (1/s, s): ROSS's ``Rotor(alpha=, beta=)``."""

    @property
    def nodes_pos(self) -> np.ndarray:
        """Shaft node positions (m): ROSS's cumulative element lengths (parallel elements on
        the same nodes counted once)."""
        lengths = {}
        for e in self.shafts:
            lengths.setdefault(int(e["n"]), float(e["L"]))
        n = max(lengths) + 1
        if sorted(lengths) != list(range(n)):
            raise InputError(
                "ShaftElement.n", sorted(lengths), "shaft elements on nodes 0, 1, 2 ..."
            )
        return np.concatenate([[0.0], np.cumsum([lengths[i] for i in range(n)])])


def _axis_values(axis, values, x, interpolation: str) -> np.ndarray:
    """ROSS 3.x's interpolation of ``values`` (along their first axis) tabulated at ``axis``, at
    ``x``: PCHIP (linear with two points or on request) with linear end extrapolation."""
    from scipy.interpolate import PchipInterpolator, interp1d

    axis, values, x = np.asarray(axis, float), np.asarray(values, float), np.asarray(x, float)
    if axis.size == 1:
        return np.broadcast_to(values[0], x.shape + values.shape[1:]).copy()
    if axis.size == 2 or interpolation == "linear":
        return interp1d(axis, values, axis=0, fill_value="extrapolate")(x)
    f = PchipInterpolator(axis, values, axis=0)
    w = np.clip(x, axis[0], axis[-1])
    d = f.derivative()
    slope = np.where((x < axis[0])[(...,) + (None,) * (values.ndim - 1)], d(axis[0]), d(axis[-1]))
    return f(w) + (x - w)[(...,) + (None,) * (values.ndim - 1)] * slope


def _table(data: dict, prefix: str, speed, freq, interpolation: str, ross3: bool):
    """``(m, 2, 2)`` table of ``prefix`` (``"k"``, ``"c"``) and its axis points and kind."""
    raw = {p: np.asarray(data.get(prefix + p, 0.0), float) for p, _, _ in _PAIRS}
    if speed is not None and freq is not None:  # ROSS 3.x 2-D: the synchronous diagonal
        pts = np.unique(np.concatenate([speed, freq]))
        out = np.zeros((pts.size, 2, 2))
        for p, i, j in _PAIRS:
            grid = np.broadcast_to(raw[p], (speed.size, freq.size)) if raw[p].ndim < 2 else raw[p]
            for a, w in enumerate(pts):
                row = _axis_values(speed, grid, w, interpolation)
                out[a, i, j] = _axis_values(freq, row, w, interpolation)
        return out, pts, "speed"
    axis = speed if speed is not None else freq
    kind = "frequency" if (freq is not None and ross3) else "speed"
    m = 1 if axis is None else axis.size
    out = np.zeros((m, 2, 2))
    for p, i, j in _PAIRS:
        out[:, i, j] = np.broadcast_to(raw[p].ravel() if raw[p].ndim else raw[p], (m,))
    return out, axis, kind


def _axis(data: dict, name: str):
    a = data.get(name)
    if a is None:
        return None
    a = np.atleast_1d(np.asarray(a, float))
    return a if a.size > 1 else None


def _support(data: dict, cls: str, ross3: bool) -> RossSupport:
    """A saved bearing or seal table as a :class:`RossSupport`."""
    name = str(data.get("tag") or f"{cls} at node {data.get('n')}")
    speed, freq = _axis(data, "speed"), _axis(data, "frequency")
    if not ross3 and speed is None:
        speed, freq = freq, None  # ROSS 2.x: one axis, read synchronously
    interpolation = "linear" if data.get("interpolation") == "linear" else "pchip"
    if not ross3:
        interpolation = "linear"
    k, axis, kind = _table(data, "k", speed, freq, interpolation, ross3)
    c, _, _ = _table(data, "c", speed, freq, interpolation, ross3)
    mass = np.zeros((2, 2))
    for p, i, j in _PAIRS:
        v = np.atleast_1d(np.asarray(data.get("m" + p, 0.0) or 0.0, float))
        if np.ptp(v) != 0.0:
            raise InputError(f"{name}.m{p}", v.tolist(), "a constant bearing mass (kg)")
        mass[i, j] = v.flat[0]
    if mass[0, 1] != mass[1, 0]:
        raise InputError(f"{name}.mxy", (mass[0, 1], mass[1, 0]), "mxy = myx (symmetric)")
    link = data.get("n_link")
    return RossSupport(name, int(data["n"]), None if link is None else int(link), k, c, axis,
                       kind, interpolation, mass, cls == "SealElement")  # fmt: skip


def _damping(params: dict, where: str) -> tuple[float, float]:
    """ROSS's rotor-wide ``(alpha, beta)``; a default (modal) damping ratio is refused."""
    if float(params.get("default_damping_ratio", 0.0) or 0.0) != 0.0:
        raise InputError(
            f"{where}: parameters.default_damping_ratio",
            params["default_damping_ratio"],
            "0 (modal damping is not mapped)",
        )
    return float(params.get("alpha", 0.0) or 0.0), float(params.get("beta", 0.0) or 0.0)


_SHAFT_KEYS = ("L", "idl", "odl", "idr", "odr", "n", "alpha", "beta")


def _from_data(data: dict, where: str) -> RossModel:
    """A :class:`RossModel` of the mapping a ROSS file holds."""
    version = str(data.get("ross_version", "2"))
    ross3 = int(version.split(".")[0]) >= 3 if version[:1].isdigit() else True
    params = data.get("parameters", {}) or {}
    model = RossModel(version=version, damping=_damping(params, where))
    for label, body in data.items():
        if label in ("parameters", "ross_version") or label.startswith("_"):
            continue
        if not isinstance(body, dict):
            continue
        cls = label.split("_")[0]
        if cls == "ShaftElement":
            model.shafts.append(_shaft(body, label))
        elif cls == "DiskElement":
            model.disks.append({k: body.get(k, 0.0) for k in ("n", "m", "Id", "Ip")}
                               | {"tag": str(body.get("tag", label))})  # fmt: skip
        elif cls == "PointMass":
            m = float(body.get("m") or 0.0)
            model.point_masses.append({"n": int(body["n"]), "mx": float(body.get("mx") or m),
                                       "my": float(body.get("my") or m),
                                       "tag": str(body.get("tag") or label)})  # fmt: skip
        elif cls.endswith("BearingElement") or cls == "SealElement" or "Bearing" in cls:
            model.supports.append(_support(body, cls, ross3))
        else:
            raise InputError(
                f"{where}: [{label}]",
                cls,
                "shaft, disk, bearing, seal or point-mass elements (not mapped)",
            )
    if not model.shafts:
        raise InputError(where, "no ShaftElement tables", "a rotor saved by ROSS's Rotor.save")
    return model


def _shaft(body: dict, label: str) -> dict:
    out = {k: body.get(k, 0.0) for k in _SHAFT_KEYS}
    for flag in ("shear_effects", "rotary_inertia", "gyroscopic"):
        out[flag] = bool(body.get(flag, True))
    out["shear_method_calc"] = str(body.get("shear_method_calc", "cowper"))
    mat = body.get("material")
    if not isinstance(mat, dict):
        raise InputError(f"[{label}].material", mat, "a material table (name, E, G_s, rho)")
    out["material"] = {"name": str(mat.get("name", "steel")), "E": float(mat["E"]),
                       "G_s": float(mat["G_s"]), "rho": float(mat["rho"])}  # fmt: skip
    out["tag"] = str(body.get("tag", label))
    return out


def read_ross_file(path) -> RossModel:
    """Read a rotor file written by ROSS's ``Rotor.save`` (``.toml`` or ``.json``), without ROSS.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    RossModel

    Raises
    ------
    InputError
        An unreadable file, or an element that cannot be mapped (named by its table).
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(
            "ROTOR_FILE", str(path), f"a readable ROSS rotor file ({exc.strerror})"
        ) from None
    except UnicodeDecodeError as exc:  # an image, an archive, a pickle: not text
        raise InputError(
            "ROTOR_FILE", str(path), "a TOML or JSON file saved by ROSS (this one is not UTF-8 "
            f"text: byte {exc.object[exc.start]:#04x} at offset {exc.start})",
        ) from None
    try:
        data = json.loads(text) if p.suffix.lower() == ".json" else tomllib.loads(text)
    except (ValueError, tomllib.TOMLDecodeError) as exc:
        raise InputError(
            "ROTOR_FILE", str(path), f"a TOML or JSON file saved by ROSS ({exc})"
        ) from None
    return _from_data(data, str(path))


def ross_model(rotor, speeds=None) -> RossModel:
    """The :class:`RossModel` of a ROSS ``Rotor`` object (ROSS 2.3 or 3.x).

    Parameters
    ----------
    rotor : ross.Rotor
    speeds : array_like, optional
        Speeds (rad/s) at which to read every speed table from ROSS's own interpolant (as
        :func:`rubrotor.rotors.ross.from_ross`'s ``speeds``; ROSS 2.3's smoothing splines).

    Returns
    -------
    RossModel
    """
    import ross

    from rubrotor.rotors.ross import _check_elements, _coefficient, _table_speeds

    _check_elements(rotor)
    ross3 = int(ross.__version__.split(".")[0]) >= 3
    params = getattr(rotor, "parameters", {}) or {}
    if getattr(rotor, "modal_damping_ratio", None) is not None:
        raise InputError(
            "Rotor.modal_damping_ratio",
            rotor.modal_damping_ratio,
            "none (modal damping is not mapped)",
        )
    model = RossModel(version=str(ross.__version__), damping=_damping(params, "Rotor"))
    for e in rotor.shaft_elements:
        body = {k: getattr(e, k, 0.0) for k in _SHAFT_KEYS}
        body |= {f: getattr(e, f, True) for f in ("shear_effects", "rotary_inertia", "gyroscopic")}
        body["shear_method_calc"] = getattr(e, "shear_method_calc", "cowper")
        mat = e.material
        body["material"] = {"name": mat.name, "E": mat.E, "G_s": mat.G_s, "rho": mat.rho}
        model.shafts.append(_shaft(body, str(e.tag)))
    for d in rotor.disk_elements:
        model.disks.append({"n": d.n, "m": d.m, "Id": d.Id, "Ip": d.Ip, "tag": str(d.tag)})
    for p in getattr(rotor, "point_mass_elements", []):
        model.point_masses.append({"n": int(p.n), "mx": float(p.mx), "my": float(p.my),
                                   "tag": str(p.tag)})  # fmt: skip
    for b in rotor.bearing_elements:
        model.supports.append(_object_support(b, ross3, _coefficient, _table_speeds, speeds))
    return model


def _object_support(b, ross3: bool, coefficient, table_speeds, speeds=None) -> RossSupport:
    """A ROSS bearing object as a :class:`RossSupport`, its values read from ROSS itself."""
    from rubrotor.rotors.ross import _bearing_mass, _label

    dof = b.dof_global_index
    keys = list(dof)
    lateral = [keys.index(f"{q}_{b.n}") for q in ("x", "y")]
    if getattr(b, "n_link", None) is not None:
        lateral += [keys.index(f"{q}_{b.n_link}") for q in ("x", "y")]
    speed = getattr(b, "speed", None) if ross3 else None
    freq = getattr(b, "frequency", None)
    speed = None if speed is None or np.size(speed) < 2 else np.asarray(speed, float)
    freq = None if freq is None or np.size(freq) < 2 else np.asarray(freq, float)
    one_frequency_axis = ross3 and freq is not None and speed is None
    if one_frequency_axis:
        axis, kind = freq, "frequency"
    else:
        axis, kind = table_speeds(b, speeds), "speed"
    at = np.array([0.0]) if axis is None else axis
    kw = (lambda w: {"frequency": w}) if not ross3 else (lambda w: {"frequency": w, "speed": w})
    if one_frequency_axis:
        kw = lambda w: {"frequency": w, "speed": 0.0}  # noqa: E731 - constant along speed
    k = np.array([_lat(b, "K", kw(w), lateral, coefficient) for w in at])
    c = np.array([_lat(b, "C", kw(w), lateral, coefficient) for w in at])
    interpolation = "pchip" if getattr(b, "interpolation", "") == "pchip" else "linear"
    link = getattr(b, "n_link", None)
    from rubrotor.rotors.ross import _is_seal

    return RossSupport(_label_name(b, _label), int(b.n), None if link is None else int(link), k,
                       c, axis, kind, interpolation, _bearing_mass(b), _is_seal(b))  # fmt: skip


def _lat(b, name: str, kw: dict, lateral: list, coefficient) -> np.ndarray:
    """The lateral 2x2 block of ROSS's ``b.K``/``b.C`` at ``kw`` (frequency, speed)."""
    try:
        a = np.asarray(getattr(b, name)(**kw), float)
    except TypeError:  # ROSS 2.x: one argument
        a = np.asarray(getattr(b, name)(kw["frequency"]), float)
    other = np.setdiff1d(np.arange(a.shape[0]), lateral)
    if np.any(a[np.ix_(lateral, other)] != 0.0) or np.any(a[np.ix_(other, lateral)] != 0.0):
        coefficient(b, name, kw["frequency"], lateral)  # raises, naming the element
    return a[np.ix_(lateral[:2], lateral[:2])]


def _label_name(b, label) -> str:
    return str(getattr(b, "tag", None) or f"{type(b).__name__} at node {b.n}")
