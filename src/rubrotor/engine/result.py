"""Simulation results as an ``xarray.Dataset`` with units and provenance, and netCDF I/O.

Files are written atomically: to a temporary file in the target directory, then renamed, so a
reader never sees a half-written result.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr
from xarray.backends import BackendArray
from xarray.core import indexing

from rubrotor import __version__
from rubrotor.engine.output import usual_mode
from rubrotor.errors import InputError

__all__ = ["to_dataset", "from_shaft_layout", "save_dataset", "load_dataset", "atomic_write"]

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


def _contact_vars(ch: np.ndarray, row: int, nc: int) -> dict:
    """``normal_force``, ``friction_force`` (N) and ``in_contact`` on ``(contact, time)``."""
    fn = ch[row : row + nc]  # (nc, T) views: nc is 0 or 1
    ft = ch[row + 1 : row + 1 + nc]
    return {
        "normal_force": _var(("contact", "time"), fn, {"units": "N", "long_name": "normal contact force"}),
        "friction_force": _var(("contact", "time"), ft, {
            "units": "N",
            "long_name": "friction force along the tangent i*n (positive = spin direction)",
        }),
        "in_contact": _var(("contact", "time"), (fn > 0).view(np.int8),  # 0/1 bytes, no 2nd pass
                           {"units": "1", "long_name": "rotor touches the stator", "flag_values": "0 1"}),
    }  # fmt: skip


def _event_vars(ev: np.ndarray, nc: int) -> dict:
    """``event_time`` (s), ``event_contact`` and ``event_kind`` (+1 onset, -1 separation)."""
    return {
        "event_time": _var("event", np.abs(ev), {"units": "s", "long_name": "contact event time"}),
        "event_contact": _var("event", np.zeros(len(ev), dtype=np.int64),
                              {"long_name": "contact index"}),
        "event_kind": _var("event", np.sign(ev).astype(np.int8),
                           {"units": "1", "long_name": "+1 contact onset, -1 separation"}),
    }  # fmt: skip


def to_dataset(
    result, parameters: dict | None = None, scenario_text: str = "", name: str = ""
) -> xr.Dataset:
    """Build the results Dataset of a :class:`rubrotor.engine.simulate.SimulationResult`.

    The layout is the general engine's (``rubrotor.engine.driver.result_dataset``): output
    stations on a ``station`` dimension, contacts on a ``contact`` dimension. The sample
    variables are views of the result's arrays (no copy); the unbalance force is computed when
    first read (it is a closed form of the time).

    Parameters
    ----------
    result : SimulationResult
        Raw output of :func:`rubrotor.engine.simulate.simulate_system`.
    parameters : dict, optional
        Every model parameter, as ``{"section.key": [value, "unit"]}``; stored as JSON in the
        ``parameters`` attribute.
    scenario_text : str
        The scenario file text, stored for provenance.
    name : str
        Scenario name.

    Returns
    -------
    xarray.Dataset
        Coordinates ``time`` (s), ``tau = Omega t`` (rad), ``station`` (axial position, m: the
        contact station, midspan without contact, then the probes) and ``contact`` (index; one
        entry with a contact, none without). Variables on ``(station, time)``: ``v, w`` (m),
        ``v_dot, w_dot`` (m/s), ``v_ddot, w_ddot`` (m/s^2); on ``(contact, time)``:
        ``normal_force``, ``friction_force`` (N, along the tangent ``i n``, ``n = P/|P|``: the
        force on the rotor is ``-(F_n + i F_t) n``) and ``in_contact`` (0/1); on ``time``:
        ``unbalance_force_y``, ``unbalance_force_z`` (N); on ``event``: ``event_time`` (s),
        ``event_contact`` and ``event_kind`` (+1 onset, -1 separation). Attributes hold the
        status, message, speed (rad/s, Hz), integrator statistics, the contacts (JSON), the
        end time (s), work terms, parameters and scenario text.
    """
    ch, t = result.channels, result.time
    nst = len(result.stations)
    nc = 0 if getattr(result, "contact", None) is None else 1
    coords = {
        "time": _var("time", t, {"units": "s", "long_name": "time"}),
        "tau": _var(
            "time", result.speed * t, {"units": "rad", "long_name": "dimensionless time Omega t"}
        ),
        "station": _var("station", np.asarray(result.stations, dtype=float),
                        {"units": "m", "long_name": "axial position"}),
        "contact": _var("contact", np.arange(nc), {"long_name": "contact index"}),
    }  # fmt: skip
    data = {}
    for i, (name_v, unit, long) in enumerate(_STATION_VARS):  # rows 6 s + i: strided views
        data[name_v] = _var(
            ("station", "time"), ch[i : 6 * nst : 6], {"units": unit, "long_name": long}
        )
    data.update(_contact_vars(ch, 6 * nst, nc))
    fu = _Phasor(result.unbalance_force, result.speed, t)
    for axis, part in (("y", "real"), ("z", "imag")):
        data[f"unbalance_force_{axis}"] = _var(
            "time",
            _lazy(_LazyPart(fu, part)),
            {"units": "N", "long_name": f"unbalance force, {axis}"},
        )
    coords["event"] = _var(
        "event", np.arange(len(result.events)), {"long_name": "contact event index"}
    )
    data.update(_event_vars(result.events, nc))
    attrs = {
        "title": f"rubrotor simulation {name}".strip(),
        "scenario_name": name,
        "status": result.status,
        "status_message": result.message,
        "speed_rad_s": result.speed,
        "speed_hz": result.speed / (2 * math.pi),
        "start_time_s": 0.0,
        "end_time_s": float(t[-1]) if t.size else 0.0,
        "engine": "shaft",
        "contact_position_m": float(result.stations[0]),
        "contacts": _contacts_attr(result),
        "rubrotor_version": __version__,
        "integrator_stats": json.dumps(_jsonable(result.stats)),
        "work": json.dumps(_jsonable(result.work)),
        "parameters": json.dumps(_jsonable(parameters or {})),
        "scenario": scenario_text,
        "Conventions": "CF-1.8",
    }
    return xr.Dataset(data_vars=data, coords=coords, attrs=attrs)


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
