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

from rubrotor.errors import InputError

__all__ = ["check_size", "NetcdfSink", "STATION_VARS", "CONTACT_VARS"]

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
        t = self.nc.createVariable("time", "f8", ("time",))
        t.units = "s"
        tau = self.nc.createVariable("tau", "f8", ("time",))
        tau.units = "rad"
        st = self.nc.createVariable("station", "f8", ("station",))
        st.units = "m"
        st[:] = stations
        self.nc.createVariable("contact", "i8", ("contact",))[:] = np.arange(n_contacts)
        for name, unit in STATION_VARS:
            self.nc.createVariable(
                name, "f8", ("station", "time"), chunksizes=(1, 4096)
            ).units = unit
        for name, unit in CONTACT_VARS:
            v = self.nc.createVariable(name, "f8", ("contact", "time"),
                                       chunksizes=(1, 4096) if n_contacts else None)  # fmt: skip
            v.units = unit

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

    def close(self, events: np.ndarray, attrs: dict, ok: bool = True) -> None:
        """Write the events and attributes, close and rename onto the target (or discard)."""
        try:
            if ok:
                self.nc.createDimension("event", len(events))
                self.nc.createVariable("event_time", "f8", ("event",))[:] = events[:, 0]
                kind = self.nc.createVariable("event_contact", "i8", ("event",))
                kind[:] = np.abs(events[:, 1]).astype(int) - 1
                self.nc.createVariable("event_kind", "i1", ("event",))[:] = np.sign(events[:, 1])
                for key, val in attrs.items():
                    self.nc.setncattr(key, val if isinstance(val, str) else json.dumps(val))
        finally:
            self.nc.close()
        if ok:
            os.replace(self.tmp, self.path)
        elif os.path.exists(self.tmp):
            os.remove(self.tmp)
