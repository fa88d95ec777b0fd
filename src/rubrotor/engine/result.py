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

__all__ = ["to_dataset", "save_dataset", "load_dataset", "atomic_write"]

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


def to_dataset(
    result, parameters: dict | None = None, scenario_text: str = "", name: str = ""
) -> xr.Dataset:
    """Build the results Dataset of a :class:`rubrotor.engine.simulate.SimulationResult`.

    The sample variables are views of the result's arrays (no copy); the unbalance force is
    computed when first read (it is a closed form of the time).

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
        Coordinates ``time`` (s) and ``tau = Omega t`` (rad); variables at the contact station
        (midspan without contact) ``v, w`` (m), ``v_dot, w_dot`` (m/s), ``v_ddot, w_ddot``
        (m/s^2), ``normal_force``, ``friction_force`` (along the tangent ``i n``, ``n = P/|P|``:
        the force on the rotor is ``-(F_n + i F_t) n``),
        ``unbalance_force_y``, ``unbalance_force_z`` (N), ``in_contact`` (0/1); probes on a
        ``probe`` dimension (axial position, m) as ``probe_v`` etc.; contact events as
        ``event_time`` (s) and ``event_kind`` (+1 onset, -1 separation). Attributes hold the
        status, message, integrator statistics, work terms, parameters and scenario text.
    """
    ch = result.channels
    t = result.time
    nst = len(result.stations)
    coords = {
        "time": _var("time", t, {"units": "s", "long_name": "time"}),
        "tau": _var(
            "time", result.speed * t, {"units": "rad", "long_name": "dimensionless time Omega t"}
        ),
    }
    data = {}
    for i, (name_v, unit, long) in enumerate(_STATION_VARS):
        data[name_v] = _var(
            "time", ch[i], {"units": unit, "long_name": f"{long} at the contact station"}
        )
    b = 6 * nst
    data["normal_force"] = _var("time", ch[b], {"units": "N", "long_name": "normal contact force"})
    data["friction_force"] = _var(
        "time",
        ch[b + 1],
        {
            "units": "N",
            "long_name": "friction force along the tangent i*n (positive = spin direction)",
        },
    )
    data["in_contact"] = _var(
        "time",
        (ch[b] > 0).view(np.int8),  # a bool array read as 0/1 bytes: no second pass
        {"units": "1", "long_name": "rotor touches the stator", "flag_values": "0 1"},
    )
    fu = _Phasor(result.unbalance_force, result.speed, t)
    for axis, part in (("y", "real"), ("z", "imag")):
        data[f"unbalance_force_{axis}"] = _var(
            "time",
            _lazy(_LazyPart(fu, part)),
            {"units": "N", "long_name": f"unbalance force, {axis}"},
        )
    if nst > 1:
        coords["probe"] = _var(
            "probe", result.stations[1:], {"units": "m", "long_name": "probe axial position"}
        )
        for i, (name_v, unit, long) in enumerate(_STATION_VARS):
            rows = ch[6 + i : b : 6]  # stations 1 .. S - 1: a strided view
            data[f"probe_{name_v}"] = _var(
                ("probe", "time"), rows, {"units": unit, "long_name": f"{long} at probe"}
            )
    ev = result.events
    coords["event"] = _var("event", np.arange(len(ev)), {"long_name": "contact event index"})
    data["event_time"] = _var(
        "event", np.abs(ev), {"units": "s", "long_name": "contact event time"}
    )
    data["event_kind"] = _var(
        "event",
        np.sign(ev).astype(np.int8),
        {"units": "1", "long_name": "+1 contact onset, -1 separation"},
    )
    attrs = {
        "title": f"rubrotor simulation {name}".strip(),
        "scenario_name": name,
        "status": result.status,
        "status_message": result.message,
        "speed_rad_s": result.speed,
        "speed_hz": result.speed / (2 * math.pi),
        "contact_position_m": float(result.stations[0]),
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
    return atomic_write(path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4"))


def _short(obj):
    """``obj`` itself when its repr is short, else its repr cut to 60 characters (a message's
    value)."""
    r = repr(obj)
    return obj if len(r) <= 60 else r[:57] + "..."


def load_dataset(path: str | os.PathLike) -> xr.Dataset:
    """Load a results Dataset saved by :func:`~rubrotor.save_dataset` (fully into memory).

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
            return ds.load()
    except (OSError, ValueError) as exc:
        raise InputError("results", str(path), f"a readable netCDF file ({exc})") from None
