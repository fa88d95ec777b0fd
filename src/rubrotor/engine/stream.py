"""Bounded-memory output of the general engine: size checks and a netCDF sink fed chunk by chunk.

:func:`check_size` refuses, before anything runs, a run whose output would not fit in memory
(or, streamed, on disk), naming the keys to change. :class:`NetcdfSink` appends each chunk of
samples to a netCDF-4 file with an unlimited ``time`` dimension (the variables and names of
:meth:`rubrotor.engine.driver.EngineResult.to_dataset`), written to a temporary file and renamed
on close, so a reader never sees a half-written result.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from rubrotor.engine.output import usual_mode
from rubrotor.errors import InputError

__all__ = ["check_size", "NetcdfSink", "STATION_VARS", "CONTACT_VARS"]

TIME_CHUNK = 4096
"""Samples per HDF5 chunk of every time series (32 KiB of float64)."""
EVENT_CHUNK = 4096
"""Events per HDF5 chunk."""
CACHE_BYTES = 1 << 20
"""HDF5 chunk cache per variable (bytes)."""

STATION_VARS = (("v", "m"), ("w", "m"), ("v_dot", "m/s"), ("w_dot", "m/s"))
CONTACT_VARS = (
    ("stator_y", "m"), ("stator_z", "m"), ("stator_y_dot", "m/s"), ("stator_z_dot", "m/s"),
    ("force_y", "N"), ("force_z", "N"), ("normal_force", "N"), ("friction_force", "N"),
)  # fmt: skip


def _available_memory() -> int:
    """Bytes of memory available now (Linux ``/proc/meminfo``; physical memory otherwise)."""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def check_size(n_samples: int, n_channels: int, n_state: int, stream: str | None) -> None:
    """Raise :class:`InputError` when the output cannot fit (memory, or disk when streamed).

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


class NetcdfSink:
    """Append samples to a netCDF-4 file chunk by chunk (see the module docstring).

    Parameters
    ----------
    path : str or Path
        Target ``.nc`` file.
    stations : ndarray
        Output positions (m).
    n_contacts : int
    sample_dt : float
        Sample spacing (s).
    speed : float
        Spin speed (rad/s), for ``tau``.
    """

    def __init__(self, path, stations, n_contacts: int, sample_dt: float, speed: float):
        import netCDF4

        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, self.tmp = tempfile.mkstemp(prefix=f".{self.path.name}.", suffix=".tmp",
                                        dir=self.path.parent)  # fmt: skip
        os.close(fd)
        self.nc = netCDF4.Dataset(self.tmp, "w", format="NETCDF4")
        self.S, self.nct, self.dt, self.speed, self.n = (
            len(stations),
            n_contacts,
            sample_dt,
            speed,
            0,
        )
        self.nc.createDimension("time", None)
        self.nc.createDimension("station", self.S)
        self.nc.createDimension("contact", n_contacts)
        self.nc.createDimension("event", None)
        self.n_events = 0
        for name, typ, unit in (("event_time", "f8", "s"), ("event_contact", "i8", None),
                                ("event_kind", "i1", None)):  # fmt: skip
            ev = self.nc.createVariable(name, typ, ("event",), chunksizes=(EVENT_CHUNK,))
            if unit:
                ev.units = unit
        t = self.nc.createVariable("time", "f8", ("time",), chunksizes=(TIME_CHUNK,))
        t.units = "s"
        tau = self.nc.createVariable("tau", "f8", ("time",), chunksizes=(TIME_CHUNK,))
        tau.units = "rad"
        st = self.nc.createVariable("station", "f8", ("station",))
        st.units = "m"
        st[:] = stations
        self.nc.createVariable("contact", "i8", ("contact",))[:] = np.arange(n_contacts)
        for name, unit in STATION_VARS:
            self.nc.createVariable(
                name, "f8", ("station", "time"), chunksizes=(1, TIME_CHUNK)
            ).units = unit
        for name, unit in CONTACT_VARS:
            v = self.nc.createVariable(name, "f8", ("contact", "time"),
                                       chunksizes=(1, TIME_CHUNK) if n_contacts else None)  # fmt: skip
            v.units = unit
        self._bound_caches()

    def _bound_caches(self) -> None:
        """A small HDF5 chunk cache per variable: samples are appended in time order, so a
        filled chunk is never read again; the default cache kept every chunk written (about
        20 MiB per 1e5 revolutions) until close."""
        for var in self.nc.variables.values():
            if var.chunking() != "contiguous":
                var.set_var_chunk_cache(size=CACHE_BYTES, nelems=127, preemption=1.0)

    def write(self, block: np.ndarray) -> None:
        """Append ``block`` (channels x samples, the kernel's layout)."""
        k = block.shape[1]
        if k == 0:
            return
        a, b = self.n, self.n + k
        times = np.arange(a, b) * self.dt
        self.nc["time"][a:b] = times
        self.nc["tau"][a:b] = self.speed * times
        for i, (name, _) in enumerate(STATION_VARS):
            self.nc[name][:, a:b] = block[[4 * s + i for s in range(self.S)]]
        for i, (name, _) in enumerate(CONTACT_VARS):
            if self.nct:
                self.nc[name][:, a:b] = block[[4 * self.S + 8 * c + i for c in range(self.nct)]]
        self.n = b

    def write_events(self, events: np.ndarray) -> None:
        """Append contact events (``(n, 2)``: time (s), ``+/-(contact index + 1)``)."""
        k = len(events)
        if k == 0:
            return
        a, b = self.n_events, self.n_events + k
        self.nc["event_time"][a:b] = events[:, 0]
        self.nc["event_contact"][a:b] = np.abs(events[:, 1]).astype(np.int64) - 1
        self.nc["event_kind"][a:b] = np.sign(events[:, 1]).astype(np.int8)
        self.n_events = b

    def close(self, attrs: dict, ok: bool = True) -> None:
        """Write the attributes, close and rename onto the target (or discard)."""
        try:
            if ok:
                for key, val in attrs.items():
                    self.nc.setncattr(key, val if isinstance(val, str) else json.dumps(val))
        finally:
            self.nc.close()
        if ok:
            usual_mode(self.tmp)  # mkstemp made it 0600
            os.replace(self.tmp, self.path)
        elif os.path.exists(self.tmp):
            os.remove(self.tmp)
