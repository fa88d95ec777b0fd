"""Bounded-memory output of the general engine: size checks and a netCDF sink fed chunk by chunk.

:func:`check_size` refuses, before anything runs, a run whose output would not fit in memory
(or, streamed, on disk), naming the keys to change. :class:`NetcdfSink` appends each chunk of
samples to a netCDF-4 file with an unlimited ``time`` dimension (the variables, names and
attributes of the in-memory results Dataset). The file is written under its final name, its
attributes once at the start with ``status = "partial"`` (rewriting HDF5 attributes is what a
kill can leave half done, so they are not touched again until the run ends); after every chunk
the samples, the events and a row of the restart state (``restart_time``, ``restart_vector``,
:mod:`rubrotor.engine.restart`) are appended and the file is flushed to disk. A run killed at
any moment, even by ``kill -9``, leaves a readable file holding its completed chunks, from
which a run can continue (``[initial] state = "file"``). At the end the attributes get the
status, its message, ``end_time_s`` and ``final_state``.
:func:`file_summary` and :func:`tail_dataset` read such a file in bounded memory.
"""

from __future__ import annotations

import errno
import json
import os
import shutil
from pathlib import Path

import numpy as np

from rubrotor._memory import available_memory as _available_memory
from rubrotor.errors import InputError

__all__ = [
    "check_size",
    "NetcdfSink",
    "STATION_VARS",
    "CONTACT_VARS",
    "central_difference",
    "file_summary",
    "tail_dataset",
    "put_attrs",
]

TIME_CHUNK = 4096
"""Samples per HDF5 chunk of every time series (32 KiB of float64)."""
EVENT_CHUNK = 4096
"""Events per HDF5 chunk."""
CACHE_BYTES = 1 << 18
"""HDF5 chunk cache per variable (bytes): 8 chunks of a time series, enough for appending."""

STATION_VARS = (("v", "m"), ("w", "m"), ("v_dot", "m/s"), ("w_dot", "m/s"))
CONTACT_VARS = (
    ("stator_y", "m"), ("stator_z", "m"), ("stator_y_dot", "m/s"), ("stator_z_dot", "m/s"),
    ("force_y", "N"), ("force_z", "N"), ("normal_force", "N"), ("friction_force", "N"),
)  # fmt: skip


def check_size(n_samples: int, n_channels: int, n_state: int, stream: str | None) -> None:
    """Raise ``InputError`` when the output cannot fit (memory, or disk when streamed).

    Parameters
    ----------
    n_samples, n_channels : int
        Saved samples and channels (8 bytes each).
    n_state : int
        Complex modal coordinates kept per sample (``save_state``; 16 bytes each), or 0.
    stream : str, optional
        Target file of a streamed run.
    """
    need = n_samples * (8 * n_channels + 16 * n_state)
    keys = "simulation.duration (shorter), simulation.save_every (larger)"
    if stream is None:
        avail = _available_memory()
        if need > 0.8 * avail:
            raise InputError(
                "simulation.duration",
                f"{n_samples} samples",
                f"a run whose output fits in memory ({need / 2**30:.3g} GiB needed, "
                f"{avail / 2**30:.3g} GiB available): change {keys}, or stream it to a file",
            )
        return
    if n_state:
        raise InputError("save_state", True, "False when the output is streamed to a file")
    free = shutil.disk_usage(Path(stream).resolve().parent).free
    if need > 0.95 * free:
        raise InputError(
            "simulation.duration",
            f"{n_samples} samples",
            f"a run whose output fits on disk ({need / 2**30:.3g} GiB needed, "
            f"{free / 2**30:.3g} GiB free at {stream}): change {keys}",
        )


ACCEL_VARS = (("v_ddot", "v_dot", "y"), ("w_ddot", "w_dot", "z"))
"""Acceleration variables, the velocity each differentiates, and its axis."""


def accel_attrs(axis: str) -> dict:
    """Attributes of an acceleration variable (in-memory and streamed files alike)."""
    return {
        "units": "m/s^2",
        "long_name": f"acceleration along {axis} (central difference of the saved velocity)",
    }


def central_difference(f: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Derivative of ``f`` (``(..., T)``) against the times ``t`` (s) along the last axis.

    Second-order central differences on the (possibly uneven) spacing inside, first-order
    one-sided at both ends (as ``numpy.gradient(f, t, axis=-1)``, but always through the uneven
    formula, so a window of a record gives the same values as the whole record); zeros for one
    sample.
    """
    if t.size < 2:
        return np.zeros_like(f)
    out = np.empty_like(f)
    d = np.diff(t)
    out[..., 0] = (f[..., 1] - f[..., 0]) / d[0]
    out[..., -1] = (f[..., -1] - f[..., -2]) / d[-1]
    if t.size > 2:
        d1, d2 = d[:-1], d[1:]
        a = -d2 / (d1 * (d1 + d2))
        b = (d2 - d1) / (d1 * d2)
        c = d1 / (d2 * (d1 + d2))
        out[..., 1:-1] = a * f[..., :-2] + b * f[..., 1:-1] + c * f[..., 2:]
    return out


def put_attrs(nc, attrs: dict) -> None:
    """Set netCDF attributes: strings and numbers as they are, anything else as JSON."""
    for key, val in attrs.items():
        if isinstance(val, str | int | float | np.integer | np.floating) and not isinstance(
            val, bool
        ):
            nc.setncattr(key, val)
        else:
            nc.setncattr(key, json.dumps(val))


class NetcdfSink:
    """Append samples to a netCDF-4 file chunk by chunk (see the module docstring).

    Parameters
    ----------
    path : str or Path
        Target ``.nc`` file, written in place (an existing file is replaced).
    stations : ndarray
        Output positions (m).
    n_contacts : int
    sample_dt : float
        Sample spacing (s).
    speed : float
        Spin speed (rad/s), for ``tau``.
    t0 : float
        Time of the first sample (s): the start time of a restarted run.
    tau : callable, optional
        Spin angle (rad) at times from the run's start (s); default ``speed t``.
    attrs : dict, optional
        Attributes written at once (provenance); ``status`` is ``"partial"`` until
        :meth:`close`.
    restart_layout : dict, optional
        :func:`rubrotor.engine.restart.layout` of the restart states (none kept without it).
    supports : tuple, optional
        Nonlinear supports' rows (``rubrotor.forces.film_row.FilmRow``), whose stations are the
        last ones: their output variables are written on ``(bearing, time)``.
    """

    def __init__(self, path, stations, n_contacts: int, sample_dt: float, speed: float, *,
                 t0: float = 0.0, tau=None, attrs: dict | None = None,
                 restart_layout: dict | None = None, supports: tuple = ()):  # fmt: skip
        import netCDF4

        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        try:
            self.nc = netCDF4.Dataset(self.path, "w", format="NETCDF4")
        except OSError as exc:
            raise InputError("--out", str(path), f"a writable file, not in use ({exc})") from None
        self.S, self.nct, self.dt, self.t0 = len(stations), n_contacts, sample_dt, t0
        self.supports, self.speed = tuple(supports), speed
        self.tau = tau or (lambda t: speed * t)
        self.n = self.n_events = 0
        self._tail = (np.empty((2 * self.S, 0)), np.empty(0))  # last 2 velocities, times
        self._define(stations)
        self.n_checkpoints = 0
        if restart_layout is not None:
            define_restart(self.nc, restart_layout)
        put_attrs(self.nc, {**(attrs or {}), "status": "partial", "status_message":
                            f"running (pid {os.getpid()}) or killed: the data end at the last "
                            "completed chunk, the restart state at restart_time[-1]"})  # fmt: skip
        self.nc.sync()

    def _define(self, stations) -> None:
        """Dimensions and variables, with the in-memory Dataset's names and units."""
        nc = self.nc
        nc.createDimension("time", None)
        nc.createDimension("station", self.S)
        nc.createDimension("contact", self.nct)
        nc.createDimension("event", None)
        for name, typ, unit in (("event_time", "f8", "s"), ("event_contact", "i8", None),
                                ("event_kind", "i1", None)):  # fmt: skip
            ev = nc.createVariable(name, typ, ("event",), chunksizes=(EVENT_CHUNK,))
            if unit:
                ev.units = unit
        nc["event_kind"].long_name = "+1 onset"
        for name, long in (("time", "time"), ("tau", "spin angle")):
            v = nc.createVariable(name, "f8", ("time",), chunksizes=(TIME_CHUNK,))
            v.setncatts({"units": "s" if name == "time" else "rad", "long_name": long})
        st = nc.createVariable("station", "f8", ("station",))
        st.setncatts({"units": "m", "long_name": "axial position"})
        st[:] = stations
        nc.createVariable("contact", "i8", ("contact",))[:] = np.arange(self.nct)
        nc["contact"].long_name = "contact index"
        for name, unit in STATION_VARS:
            v = nc.createVariable(name, "f8", ("station", "time"), chunksizes=(1, TIME_CHUNK))
            v.units = unit
        for name, _, axis in ACCEL_VARS:
            v = nc.createVariable(name, "f8", ("station", "time"), chunksizes=(1, TIME_CHUNK))
            v.setncatts(accel_attrs(axis))
        chunks = (1, TIME_CHUNK) if self.nct else None
        for name, unit in CONTACT_VARS:
            v = nc.createVariable(name, "f8", ("contact", "time"), chunksizes=chunks)
            v.units = unit
        nc.createVariable("in_contact", "i1", ("contact", "time"), chunksizes=chunks)
        if self.supports:
            self._define_supports()
        self._bound_caches()

    def _define_supports(self) -> None:
        """The ``bearing`` dimension: names, positions and clearances, and each support
        term's output variables (``OUTPUT_UNITS``)."""
        nc, sup = self.nc, self.supports
        nc.createDimension("bearing", len(sup))
        nc.createVariable("bearing_name", str, ("bearing",))[:] = np.array(
            [b.name for b in sup], dtype=object)  # fmt: skip
        for name, values in (("bearing_position", [b.position for b in sup]),
                             ("bearing_clearance", [b.scale for b in sup])):  # fmt: skip
            v = nc.createVariable(name, "f8", ("bearing",))
            v.units = "m"
            v[:] = values
        for name, unit in type(sup[0]).OUTPUT_UNITS.items():
            v = nc.createVariable(name, "f8", ("bearing", "time"), chunksizes=(1, TIME_CHUNK))
            v.units = unit

    def _bound_caches(self) -> None:
        """A small HDF5 chunk cache per variable: samples are appended in time order, so a
        filled chunk is never read again; the default cache kept every chunk written (about
        20 MiB per 1e5 revolutions) until close."""
        for var in self.nc.variables.values():
            if var.chunking() != "contiguous":
                var.set_var_chunk_cache(size=CACHE_BYTES, nelems=127, preemption=1.0)

    def write(self, block: np.ndarray) -> None:
        """Append ``block`` (channels x samples, the kernel's layout).

        Raises
        ------
        DiskFull
            Before writing, when the disk cannot take the block with a margin: the file, closed
            by the caller with its final attributes, then stays readable, ending at the last
            completed chunk (an HDF5 file whose write failed for want of space is unreadable).
        """
        k = block.shape[1]
        if k == 0:
            return
        self._room(2 * block.nbytes)
        a, b = self.n, self.n + k
        rel = np.arange(a, b) * self.dt
        times = rel + self.t0
        nc = self.nc
        nc["time"][a:b] = times
        nc["tau"][a:b] = self.tau(rel)
        for i, (name, _) in enumerate(STATION_VARS):
            nc[name][:, a:b] = block[i : 4 * self.S : 4]
        self._accelerations(block, times)
        if self.nct:
            end = 4 * self.S + 8 * self.nct  # the supports' rows follow the contacts'
            for i, (name, _) in enumerate(CONTACT_VARS):
                nc[name][:, a:b] = block[4 * self.S + i : end : 8]
            nc["in_contact"][:, a:b] = (block[4 * self.S + 6 : end : 8] > 0).astype(np.int8)
        for j, sup in enumerate(self.supports):
            s = self.S - len(self.supports) + j
            out = sup.outputs(block[4 * s : 4 * s + 2], block[4 * s + 2 : 4 * s + 4], self.speed)
            for name, values in out.items():
                nc[name][j, a:b] = values
        self.n = b

    def _accelerations(self, block: np.ndarray, times: np.ndarray) -> None:
        """``v_ddot, w_ddot`` of the new samples, and the central value of the sample before
        them (written one-sided with the previous chunk)."""
        vel = np.concatenate([self._tail[0], block[np.r_[2 : 4 * self.S : 4, 3 : 4 * self.S : 4]]],
                             axis=1)  # fmt: skip
        t = np.concatenate([self._tail[1], times])
        acc = central_difference(vel, t)
        skip = max(self._tail[1].size - 1, 0)
        a = self.n - (self._tail[1].size - skip)
        for j, (name, _, _) in enumerate(ACCEL_VARS):
            self.nc[name][:, a : a + acc.shape[1] - skip] = acc[
                j * self.S : (j + 1) * self.S, skip:
            ]
        self._tail = (vel[:, -2:], t[-2:])

    def _room(self, nbytes: int) -> None:
        """Raise :class:`DiskFull` unless ``nbytes`` plus :data:`DISK_MARGIN` are free."""
        free = shutil.disk_usage(self.path.parent).free
        if free < nbytes + DISK_MARGIN:
            t = self.t0 + max(self.n - 1, 0) * self.dt
            raise DiskFull(errno.ENOSPC, f"no space left on device at {self.path.parent} "
                           f"({free / 2**20:.3g} MiB free, the next chunk needs "
                           f"{(nbytes + DISK_MARGIN) / 2**20:.3g} MiB): {self.path} is kept, "
                           f"partial, with the data up to t = {t:.6g} s")  # fmt: skip

    def write_events(self, events: np.ndarray) -> None:
        """Append contact events (``(n, 2)``: time (s), ``+/-(contact index + 1)``)."""
        k = len(events)
        if k == 0:
            return
        a, b = self.n_events, self.n_events + k
        self.nc["event_time"][a:b] = events[:, 0] + self.t0
        self.nc["event_contact"][a:b] = np.abs(events[:, 1]).astype(np.int64) - 1
        self.nc["event_kind"][a:b] = np.sign(events[:, 1]).astype(np.int8)
        self.n_events = b

    def checkpoint(self, time_s: float | None = None, vector: np.ndarray | None = None) -> None:
        """Append the restart state at the end of the chunk just written (time (s) and
        :func:`rubrotor.engine.restart.flatten` vector), if any, and flush the file to disk:
        from here on the file holds this chunk whatever happens to the process."""
        if vector is not None:
            k = self.n_checkpoints
            self.nc["restart_time"][k] = time_s
            self.nc["restart_vector"][k, :] = vector
            self.n_checkpoints = k + 1
        self.nc.sync()

    def close(self, attrs: dict) -> None:
        """Write the final attributes (``status`` among them) and close the file."""
        try:
            put_attrs(self.nc, attrs)
        finally:
            self.nc.close()


DISK_MARGIN = 1 << 20
"""Bytes kept free on the disk of a streamed file (HDF5 metadata, the closing attributes)."""


class DiskFull(OSError):
    """The disk of a streamed file is full: stopped before a write that would not fit (the file
    is closed by its writer and stays readable, partial). ``errno`` is ``ENOSPC``."""


def define_restart(nc, lay: dict) -> None:
    """The restart variables of an open netCDF file (see the module docstring)."""
    size = (lay["x"] + sum(lay["stators"]) + lay["F"] + lay["Fp"] + lay["dprev"] + 2
            + lay.get("checksum", 0))  # fmt: skip
    nc.createDimension("checkpoint", None)
    nc.createDimension("restart_component", size)
    t = nc.createVariable("restart_time", "f8", ("checkpoint",), chunksizes=(256,))
    t.setncatts({"units": "s", "long_name": "time of the restart state"})
    v = nc.createVariable("restart_vector", "f8", ("checkpoint", "restart_component"),
                          chunksizes=(1, size))  # fmt: skip
    v.setncatts(restart_vector_attrs(lay))


def restart_vector_attrs(lay: dict) -> dict:
    """Attributes of ``restart_vector`` (in-memory and streamed files alike)."""
    return {
        "long_name": "restart state: x = [q, q'], stator [u, u'], F, F_prev, gaps, h_prev, level",
        "units": "SI (m, rad, m/s, rad/s, N, s)",
        "layout": json.dumps(lay),
    }


def _slices(n: int, step: int):
    for a in range(0, n, step):
        yield slice(a, min(a + step, n))


def file_summary(path, block: int = 1 << 16) -> dict:
    """Peak displacement, peak normal force and contact fraction of a results file, read
    ``block`` samples at a time (memory bounded whatever the file's length).

    Parameters
    ----------
    path : str or Path
        A results file of the general engine (streamed or not).
    block : int
        Samples read at once.

    Returns
    -------
    dict
        ``samples``, ``duration_s`` (last time, s), ``max_displacement_m`` (largest
        ``hypot(v, w)`` over stations, m), ``max_normal_force_N`` (N), ``contact_fraction``
        (share of contact-time samples with a positive normal force) and the file's attributes
        ``attrs``.
    """
    import netCDF4

    with netCDF4.Dataset(path, "r") as nc:
        for name in ("v", "w", "normal_force"):  # each chunk is read once: no cache needed
            nc[name].set_var_chunk_cache(size=CACHE_BYTES, nelems=127, preemption=1.0)
        n = nc.dimensions["time"].size
        p_max, f_max, touching = -np.inf, -np.inf, 0
        nct = nc.dimensions["contact"].size
        for sl in _slices(n, block):
            p_max = max(p_max, float(np.hypot(nc["v"][:, sl], nc["w"][:, sl]).max()))
            if nct:
                fn = np.asarray(nc["normal_force"][:, sl])
                f_max = max(f_max, float(fn.max()))
                touching += int(np.count_nonzero(fn > 0))
        return {
            "samples": n,
            "duration_s": float(nc["time"][n - 1]) if n else 0.0,
            "max_displacement_m": p_max,
            "max_normal_force_N": f_max if nct else None,
            "contact_fraction": touching / (n * nct) if nct and n else None,
            "attrs": {k: nc.getncattr(k) for k in nc.ncattrs()},
        }


def tail_dataset(path, samples: int):
    """The last ``samples`` samples of a results file as an in-memory Dataset (all its
    variables and attributes; the events inside the window), for figures of long runs. Only
    the window is read (not even the whole ``time`` coordinate).

    Parameters
    ----------
    path : str or Path
        A results file.
    samples : int
        Samples kept from the end.

    Returns
    -------
    xarray.Dataset
    """
    import netCDF4
    import xarray as xr

    with netCDF4.Dataset(path, "r") as nc:
        nc.set_auto_mask(False)
        n = nc.dimensions["time"].size
        win = slice(max(n - samples, 0), n)
        t_first = float(nc["time"][win.start]) if n else 0.0
        keep = None
        if "event_time" in nc.variables:
            ev = _event_window(nc["event_time"], t_first)
            keep = slice(ev, nc.dimensions["event"].size)
        data = {}
        for name, var in nc.variables.items():
            dims = var.dimensions
            key = tuple(win if d == "time" else keep if d == "event" else slice(None) for d in dims)
            data[name] = xr.Variable(dims, var[key] if dims else var[...],
                                     {a: var.getncattr(a) for a in var.ncattrs()})  # fmt: skip
        attrs = {a: nc.getncattr(a) for a in nc.ncattrs()}
    coords = {k: data.pop(k) for k in ("time", "tau", "station", "contact") if k in data}
    return xr.Dataset(data, coords, attrs)


def _event_window(var, t_first: float, block: int = 1 << 16) -> int:
    """Index of the first event at or after ``t_first`` (s), scanning ``block`` at a time
    (events are stored in time order)."""
    n = var.shape[0]
    for sl in _slices(n, block):
        hit = np.flatnonzero(np.asarray(var[sl]) >= t_first)
        if hit.size:
            return sl.start + int(hit[0])
    return n
