"""One time-run result (``TimeRun``), its one Dataset builder, and netCDF I/O.

Every time run (the seed shaft's engine, the general engine, the free-spin engine) returns a
frozen ``TimeRun``; :func:`to_dataset` builds its ``xarray.Dataset`` from the table
``LAYOUTS``, which says where each variable sits in the run's channel buffer (the Datasets
keep the layout and attributes each engine wrote before, so files written before still load).

Files are written atomically: to a temporary file in the target directory, then renamed, so a
reader never sees a half-written result.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr
from xarray.backends import BackendArray
from xarray.core import indexing

from rubrotor import __version__
from rubrotor.core.status import Status
from rubrotor.engine.output import usual_mode
from rubrotor.engine.stream import CONTACT_VARS, STATION_VARS
from rubrotor.errors import InputError

__all__ = ["TimeRun", "Layout", "LAYOUTS", "STATUSES", "to_dataset", "from_shaft_layout",
           "save_dataset", "load_dataset", "atomic_write"]  # fmt: skip

STATUSES = ("complete", "partial")
"""Status of a time run: it ran to its end, or it stopped early (``message`` says why)."""


@dataclass(frozen=True)
class TimeRun:
    """The result of every time run (SI units, frozen): one type for every engine.

    The sample arrays are views of the compiled kernel's output buffer (no copy); where each
    variable sits in ``channels`` is the engine's ``Layout`` (``LAYOUTS``).

    Attributes
    ----------
    time : ndarray
        Sample times (s), from 0.
    stations : ndarray
        Axial positions (m) of the output stations: contact stations first, then probes.
    n_contacts : int
        Contacts.
    channels : ndarray
        Saved channels, ``(rows, T)`` in the engine's layout.
    events : ndarray
        Contact events: ``(n, 2)`` time (s) and ``+/-(contact + 1)`` (general engine), or
        signed times (s, ``+`` onset, ``-`` separation) on the seed shaft's engine.
    status : {"complete", "partial"}
        The run reached its end, or stopped early.
    message : str
        Why a partial run stopped (empty when complete).
    stats : dict
        Integrator statistics.
    speed : float
        Spin speed (rad/s; the start speed of a run-up or of a free spin).
    final_state : RotorState or ndarray or None
        The state at the end (see the engine), None when unknown.
    restart : dict or None
        The general engine's full restart state (``rubrotor.engine.restart``).
    states : ndarray
        Modal states per sample when saved (general engine), else empty.
    engine : {"shaft", "general", "free-spin"}
        The engine that ran, which names the layout of ``channels``.
    code : rubrotor.core.status.Status
        How the kernel's run ended, from the one enumeration (``code.message`` says what it
        means): ``Status.OK`` for a complete run, and for a run stopped from outside (an
        interrupt; then ``status`` is ``"partial"`` and ``message`` says why).
    extras : Mapping
        What only one engine has, read as attributes: the shaft's ``work`` (J),
        ``unbalance_force`` (N, complex), ``unbalance_position`` (m) and ``contact``; the free
        spin's ``state``, ``contact`` (forces), ``basis``, ``reduced``, ``J`` (kg m^2),
        ``radius`` (m) and ``rings``.
    """

    time: np.ndarray
    stations: np.ndarray
    n_contacts: int
    channels: np.ndarray
    events: np.ndarray
    status: str
    message: str
    stats: dict
    speed: float
    final_state: object = None
    restart: dict | None = None
    states: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    engine: str = "general"
    code: Status = Status.OK
    extras: Mapping = field(default_factory=dict)

    def __getattr__(self, name):
        extras = self.__dict__.get("extras")
        if extras is not None and name in extras:
            return extras[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    @property
    def r(self) -> int:
        """Retained modal coordinates of a free-spin run."""
        return self.basis.shape[1]

    @property
    def spin_speed(self) -> np.ndarray:
        """Spin speed (rad/s) per sample of a free-spin run."""
        return self.state[2 * self.r]

    @property
    def spin_angle(self) -> np.ndarray:
        """Integrated spin angle (rad) per sample of a free-spin run."""
        return self.state[2 * self.r + 1]

    @property
    def ring_speed(self) -> np.ndarray:
        """Ring speeds (rad/s), ``(n_c, n)``, of a free-spin run (zero for a fixed stator)."""
        return self.state[2 * self.r + 2 :]

    def to_dataset(self, parameters: dict | None = None, scenario_text: str = "",
                   name: str = "", **kw):  # fmt: skip
        """The results Dataset (:func:`to_dataset`)."""
        return to_dataset(self, parameters, scenario_text, name, **kw)


@dataclass(frozen=True)
class Layout:
    """Where an engine's variables sit in :attr:`TimeRun.channels`, and their attributes.

    Attributes
    ----------
    station : tuple of (name, attrs)
        Rows of each station, station ``s`` starting at row ``len(station) * s``.
    contact : tuple of (name, attrs)
        Rows of each contact after the stations, contact ``i`` at ``per_contact * i``.
    per_contact : int
        Rows per contact.
    coords : dict
        Attributes of the ``time`` and ``tau`` coordinates; ``"event"``: those of an
        ``event`` coordinate (None: no such coordinate); ``"contact"``, ``"tau"`` present or not.
    in_contact : dict
        Attributes of ``in_contact`` (None: no such variable).
    extra : callable
        ``(run, time) -> dict`` of further variables (the shaft's unbalance force).
    events : callable
        ``(run) -> dict`` of the event variables.
    attrs : callable
        ``(run, parameters, scenario_text, name) -> dict`` of the Dataset's attributes.
    """

    station: tuple
    contact: tuple
    per_contact: int
    coords: dict
    in_contact: dict | None
    extra: Callable
    events: Callable
    attrs: Callable


_STATION_VARS = (
    ("v", "m", "deflection along y (v)"),
    ("w", "m", "deflection along z (w)"),
    ("v_dot", "m/s", "velocity along y"),
    ("w_dot", "m/s", "velocity along z"),
    ("v_ddot", "m/s^2", "acceleration along y"),
    ("w_ddot", "m/s^2", "acceleration along z"),
)


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        return float(obj)
    if isinstance(obj, complex | np.complexfloating):
        return [float(obj.real), float(obj.imag)]
    return obj


class _Phasor:
    """``amplitude e^{i speed t}`` (N) at the sample times, computed on first use, then kept."""

    def __init__(self, amplitude: complex, speed: float, t: np.ndarray) -> None:
        self.amplitude, self.speed, self.t = amplitude, speed, t
        self._values = None

    def values(self) -> np.ndarray:
        if self._values is None:
            self._values = self.amplitude * np.exp(1j * self.speed * self.t)
        return self._values


class _LazyPart(BackendArray):
    """The real or imaginary part of a :class:`_Phasor`, as a lazily loaded xarray array.

    A derived variable the user may never read (the unbalance force, one complex exponential
    per sample) costs nothing until it is read; then it is computed once for both parts.
    """

    def __init__(self, phasor: _Phasor, part: str) -> None:
        self.phasor, self.part = phasor, part
        self.shape = phasor.t.shape
        self.dtype = np.dtype(float)

    def _raw(self, key):
        return getattr(self.phasor.values(), self.part)[key]

    def __getitem__(self, key):
        return indexing.explicit_indexing_adapter(
            key, self.shape, indexing.IndexingSupport.BASIC, self._raw
        )


def _lazy(array: BackendArray) -> indexing.LazilyIndexedArray:
    return indexing.LazilyIndexedArray(array)


def _var(dims, data, attrs: dict) -> xr.Variable:
    return xr.Variable(dims, data, attrs, fastpath=True)


def _contacts_attr(result) -> str:
    """The ``contacts`` attribute of the general layout: one rigid, centred stator or none."""
    c = getattr(result, "contact", None)
    if c is None:
        return "[]"
    return json.dumps([{
        "position": float(result.stations[0]), "clearance": float(c.clearance),
        "radius": None if c.radius is None else float(c.radius), "offset_y": 0.0,
        "offset_z": 0.0, "flexible_stator": False,
    }])  # fmt: skip


def _event_vars(ev: np.ndarray, nc: int) -> dict:
    """``event_time`` (s), ``event_contact`` and ``event_kind`` (+1 onset, -1 separation)."""
    return {
        "event_time": _var("event", np.abs(ev), {"units": "s", "long_name": "contact event time"}),
        "event_contact": _var("event", np.zeros(len(ev), dtype=np.int64),
                              {"long_name": "contact index"}),
        "event_kind": _var("event", np.sign(ev).astype(np.int8),
                           {"units": "1", "long_name": "+1 contact onset, -1 separation"}),
    }  # fmt: skip


def _shaft_extra(run, t) -> dict:
    """The unbalance force (N) on ``time``, computed when first read (a closed form of t)."""
    fu = _Phasor(run.unbalance_force, run.speed, t)
    return {
        f"unbalance_force_{axis}": _var(
            "time", _lazy(_LazyPart(fu, part)), {"units": "N", "long_name": f"unbalance force, {axis}"}
        )
        for axis, part in (("y", "real"), ("z", "imag"))
    }


def _shaft_attrs(run, parameters, scenario_text, name) -> dict:
    t = run.time
    return {
        "title": f"rubrotor simulation {name}".strip(),
        "scenario_name": name,
        "status": run.status,
        "status_message": run.message,
        "speed_rad_s": run.speed,
        "speed_hz": run.speed / (2 * math.pi),
        "start_time_s": 0.0,
        "end_time_s": float(t[-1]) if t.size else 0.0,
        "engine": "shaft",
        "contact_position_m": float(run.stations[0]),
        "contacts": _contacts_attr(run),
        "rubrotor_version": __version__,
        "integrator_stats": json.dumps(_jsonable(run.stats)),
        "work": json.dumps(_jsonable(run.work)),
        "parameters": json.dumps(_jsonable(parameters or {})),
        "scenario": scenario_text,
        "Conventions": "CF-1.8",
    }


def _general_events(run) -> dict:
    ev = run.events
    return {
        "event_time": _var("event", ev[:, 0], {"units": "s"}),
        "event_contact": _var("event", np.abs(ev[:, 1]).astype(int) - 1, {}),
        "event_kind": _var("event", np.sign(ev[:, 1]).astype(np.int8), {"long_name": "+1 onset"}),
    }


def _general_attrs(run, parameters, scenario_text, name) -> dict:
    return {
        "status": run.status,
        "status_message": run.message,
        "speed_rad_s": run.speed,
        "integrator_stats": json.dumps(_jsonable(run.stats)),
        "rubrotor_version": __version__,
    }


def _general_extra(run, t) -> dict:
    """The nonlinear supports' outputs on ``(bearing, time)``: each support term's own
    variables (``outputs``) of its journal's samples (its station, after the probes)."""
    supports = run.extras.get("supports", ())
    if not supports:
        return {}
    ch, S, nb = run.channels, len(run.stations), len(supports)
    per = {}
    for j, b in enumerate(supports):
        s = S - nb + j
        p, u = ch[4 * s : 4 * s + 2], ch[4 * s + 2 : 4 * s + 4]
        for key, value in b.outputs(p, u, run.speed).items():
            per.setdefault(key, []).append(value)
    units = dict(getattr(type(supports[0]), "OUTPUT_UNITS", {}))
    out = {k: _var(("bearing", "time"), np.array(v), {"units": units.get(k, "")})
           for k, v in per.items()}  # fmt: skip
    out["bearing_name"] = _var("bearing", np.array([b.name for b in supports]), {})
    out["bearing_position"] = _var("bearing", np.array([b.position for b in supports]),
                                   {"units": "m"})  # fmt: skip
    out["bearing_clearance"] = _var("bearing", np.array([b.scale for b in supports]),
                                    {"units": "m", "long_name": "radial clearance"})  # fmt: skip
    return out


def _spin_extra(run, t) -> dict:
    return {
        "spin_speed": _var("time", run.spin_speed, {"units": "rad/s", "long_name": "spin speed"}),
        "spin_angle": _var("time", run.spin_angle, {"units": "rad"}),
    }


def _spin_attrs(run, parameters, scenario_text, name) -> dict:
    touching = run.contact[:, 0] > 0
    events = int(np.sum(touching[:, 1:] & ~touching[:, :-1]))  # contact onsets between samples
    return {"status": run.status, "status_message": run.message, "engine": "free-spin",
            "polar_inertia_kg_m2": run.J, "speed_rad_s": float(run.spin_speed[0]),
            "speed_end_rad_s": float(run.spin_speed[-1]),
            "integrator_stats": json.dumps({**run.stats, "contact_events": events})}  # fmt: skip


def _units(*pairs) -> tuple:
    return tuple((n, {"units": u}) for n, u in pairs)


_STATION_GENERAL = _units(*STATION_VARS)

LAYOUTS = {
    "shaft": Layout(
        station=tuple((n, {"units": u, "long_name": lg}) for n, u, lg in _STATION_VARS),
        contact=(
            ("normal_force", {"units": "N", "long_name": "normal contact force"}),
            ("friction_force", {"units": "N", "long_name": "friction force along the tangent "
                                "i*n (positive = spin direction)"}),
        ),  # fmt: skip
        per_contact=2,
        coords={"time": {"units": "s", "long_name": "time"},
                "tau": {"units": "rad", "long_name": "dimensionless time Omega t"},
                "station": {"units": "m", "long_name": "axial position"},
                "contact": {"long_name": "contact index"},
                "event": {"long_name": "contact event index"}},  # fmt: skip
        in_contact={"units": "1", "long_name": "rotor touches the stator", "flag_values": "0 1"},
        extra=_shaft_extra,
        events=lambda run: _event_vars(run.events, run.n_contacts),
        attrs=_shaft_attrs,
    ),
    "general": Layout(
        station=_STATION_GENERAL,
        contact=_units(*CONTACT_VARS),
        per_contact=len(CONTACT_VARS),
        coords={"time": {"units": "s"}, "tau": {"units": "rad", "long_name": "Omega t"},
                "station": {"units": "m", "long_name": "axial position"},
                "contact": {"long_name": "contact index"}},  # fmt: skip
        in_contact={},
        extra=_general_extra,
        events=_general_events,
        attrs=_general_attrs,
    ),
    "free-spin": Layout(
        station=_STATION_GENERAL,
        contact=_units(
            ("ring_speed", "rad/s"), ("normal_force", "N"), ("friction_force", "N"),
            ("sliding_speed", "m/s"), ("force_y", "N"), ("force_z", "N"), ("friction_torque", "N m"),
        ),  # fmt: skip
        per_contact=7,
        coords={"time": {"units": "s"}, "station": {"units": "m"}},
        in_contact=None,
        extra=_spin_extra,
        events=lambda run: {},
        attrs=_spin_attrs,
    ),
}
"""Engine (:attr:`TimeRun.engine`) -> ``Layout`` of its channels and Dataset."""


def to_dataset(
    result, parameters: dict | None = None, scenario_text: str = "", name: str = "", *,
    coords: dict | None = None, data: dict | None = None, attrs: dict | None = None,
) -> xr.Dataset:  # fmt: skip
    """Build the results Dataset of any time run (``TimeRun``): the one builder.

    The sample variables are views of the run's channels (no copy); the seed shaft's unbalance
    force is computed when first read (a closed form of the time). Where each variable sits,
    and its attributes, is the engine's ``Layout`` (``LAYOUTS``).

    Parameters
    ----------
    result : TimeRun
        A time run.
    parameters : dict, optional
        Every model parameter, as ``{"section.key": [value, "unit"]}``; stored as JSON in the
        ``parameters`` attribute (seed shaft's engine).
    scenario_text : str
        The scenario file text, stored for provenance (seed shaft's engine).
    name : str
        Scenario name (seed shaft's engine).
    coords, data : dict of str to xarray.Variable, optional
        Coordinates and variables that replace or extend the layout's.
    attrs : dict, optional
        Attributes added to the layout's.

    Returns
    -------
    xarray.Dataset
        Coordinates ``time`` (s), ``tau = Omega t`` (rad), ``station`` (axial position, m:
        contact stations first, then probes), ``contact`` (index). Variables on ``(station,
        time)``: ``v, w`` (m), ``v_dot, w_dot`` (m/s), and ``v_ddot, w_ddot`` (m/s^2) on the
        seed shaft's engine; on ``(contact, time)``: ``normal_force``, ``friction_force`` (N,
        along the tangent ``i n``, ``n = P/|P|``: the force on the rotor is ``-(F_n + i F_t)
        n``), ``in_contact`` (0/1), and the general engine's stator motion and force
        components; on ``event``: ``event_time`` (s), ``event_contact`` and ``event_kind``
        (+1 onset, -1 separation). The seed shaft's engine adds ``unbalance_force_y``,
        ``unbalance_force_z`` (N) on ``time``; a free-spin run ``spin_speed`` (rad/s),
        ``spin_angle`` (rad) on ``time`` and ``ring_speed`` (rad/s), ``sliding_speed`` (m/s),
        ``friction_torque`` (N m) on ``(contact, time)``. Attributes hold the status,
        message, speed (rad/s), integrator statistics and provenance.
    """
    lay = LAYOUTS[result.engine]
    ch, t = result.channels, result.time
    S, nc = len(result.stations), result.n_contacts
    ca = lay.coords
    crd = {"time": _var("time", t, ca["time"])}
    if "tau" in ca:
        crd["tau"] = _var("time", result.speed * t, ca["tau"])
    crd["station"] = _var("station", np.asarray(result.stations, dtype=float), ca["station"])
    if "contact" in ca:
        crd["contact"] = _var("contact", np.arange(nc), ca["contact"])
    if "event" in ca:
        crd["event"] = _var("event", np.arange(len(result.events)), ca["event"])
    crd.update(coords or {})
    dv = {}
    ps, pc = len(lay.station), lay.per_contact
    for k, (nm, at) in enumerate(lay.station):  # rows ps * s + k: strided views
        dv[nm] = _var(("station", "time"), ch[k : ps * S : ps], at)
    for k, (nm, at) in enumerate(lay.contact):  # rows ps * S + pc * i + k
        dv[nm] = _var(("contact", "time"), ch[ps * S + k : ps * S + pc * nc : pc], at)
    if lay.in_contact is not None:  # 0/1 bytes, no second pass
        dv["in_contact"] = _var(("contact", "time"), (dv["normal_force"].data > 0).view(np.int8),
                                lay.in_contact)  # fmt: skip
    dv.update(lay.extra(result, t))
    dv.update(lay.events(result))
    dv.update(data or {})
    at = {**lay.attrs(result, parameters, scenario_text, name), **(attrs or {})}
    return xr.Dataset(data_vars=dv, coords=crd, attrs=at)


def atomic_write(path: str | os.PathLike, write) -> Path:
    """Call ``write(tmp_path)`` then rename the temporary file onto ``path``.

    Parameters
    ----------
    path : path-like
        Final file path.
    write : callable
        Writes the whole file to the path it is given.

    Returns
    -------
    Path
        ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        write(tmp)
        usual_mode(tmp)  # mkstemp makes 0600; give the usual permissions
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
    return path


def save_dataset(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """Save a results Dataset as netCDF-4, atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        Results.
    path : path-like
        Target ``.nc`` file.

    Returns
    -------
    Path
    """
    if not isinstance(ds, xr.Dataset):
        raise InputError("ds", _short(ds), "an xarray.Dataset (a result of rubrotor.simulate)")
    if not isinstance(path, str | os.PathLike):
        raise InputError("path", _short(path), "a file path (str or os.PathLike) ending in .nc")
    try:
        return atomic_write(path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4",
                                                           format="NETCDF4"))  # fmt: skip
    except (FileNotFoundError, NotADirectoryError, PermissionError) as exc:
        raise InputError("path", str(path), f"a file in a folder that exists or can be made "
                         f"and written ({exc.strerror}: {exc.filename})") from None  # fmt: skip


def from_shaft_layout(ds: xr.Dataset) -> xr.Dataset:
    """A Dataset of the old continuous-shaft layout, in the one layout.

    The one layout is that of :func:`~rubrotor.engine.result.to_dataset`.

    Files written before the layouts were merged kept ``v, w, ...`` on ``time`` (the contact
    station), probes as ``probe_v, ...`` on a ``probe`` dimension and the forces on ``time``.
    Here the contact station and the probes become rows of a ``station`` dimension (axial
    position, m) and the forces rows of a ``contact`` dimension (one entry when the file's
    parameters name a contact, none otherwise). A Dataset already in the one layout is returned
    as it is.

    Parameters
    ----------
    ds : xarray.Dataset
        Results read from a file.

    Returns
    -------
    xarray.Dataset
    """
    if "station" in ds.dims or "v" not in ds or ds["v"].dims != ("time",):
        return ds
    probes = ds["probe"].values.tolist() if "probe" in ds.dims else []
    stations = np.array([float(ds.attrs.get("contact_position_m", np.nan)), *probes])
    params = json.loads(ds.attrs.get("parameters", "{}") or "{}")
    nc = int(any(k.startswith("contact.") for k in params))
    out = ds.drop_vars([k for k in ds.variables if k.startswith("probe")])
    for name_v, unit, long in _STATION_VARS:
        rows = [ds[name_v].values] + ([*ds[f"probe_{name_v}"].values] if probes else [])
        out[name_v] = _var(("station", "time"), np.stack(rows), {"units": unit, "long_name": long})
    for name_v in ("normal_force", "friction_force", "in_contact"):  # (nc, time): nc is 0 or 1
        out[name_v] = _var(("contact", "time"), ds[name_v].values[None][:nc], ds[name_v].attrs)
    out = out.assign_coords(
        station=_var("station", stations, {"units": "m", "long_name": "axial position"}),
        contact=_var("contact", np.arange(nc), {"long_name": "contact index"}),
    )
    if "event_time" in ds:
        out["event_contact"] = _var("event", np.zeros(ds.sizes["event"], dtype=np.int64),
                                    {"long_name": "contact index"})  # fmt: skip
    t = ds["time"].values
    out.attrs.update(engine="shaft", start_time_s=0.0, end_time_s=float(t[-1]) if t.size else 0.0)
    if nc and "contacts" not in out.attrs:  # a rigid, centred stator (the only one it had)
        radius = params.get("contact.radius", [None])[0]
        out.attrs["contacts"] = json.dumps([{
            "position": float(stations[0]), "clearance": float(params["contact.clearance"][0]),
            "radius": radius, "offset_y": 0.0, "offset_z": 0.0, "flexible_stator": False,
        }])  # fmt: skip
    out.attrs.setdefault("contacts", "[]")
    return out


def _short(obj):
    """``obj`` itself when its repr is short, else its repr cut to 60 characters (a message's
    value)."""
    r = repr(obj)
    return obj if len(r) <= 60 else r[:57] + "..."


def load_dataset(path: str | os.PathLike) -> xr.Dataset:
    """Load a results Dataset saved by :func:`~rubrotor.save_dataset` (fully into memory).

    A file of the old continuous-shaft layout is converted
    (:func:`~rubrotor.engine.result.from_shaft_layout`).

    Parameters
    ----------
    path : path-like
        A ``.nc`` file.

    Returns
    -------
    xarray.Dataset
    """
    p = Path(path)
    if not p.is_file():
        raise InputError("results", str(path), "an existing netCDF file written by rubrotor")
    try:
        with xr.open_dataset(p, engine="netcdf4") as ds:
            return from_shaft_layout(ds.load())
    except (OSError, ValueError) as exc:
        raise InputError("results", str(path), f"a readable netCDF file ({exc})") from None
