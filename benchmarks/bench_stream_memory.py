"""Streamed ``rubrotor simulate`` of seal_rub.toml: peak memory against length, and a run killed
with ``kill -9`` and continued from its file against the uninterrupted run.

Run from the repository root: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_stream_memory.py
[--revs 5000 10000] [--dir /tmp]``. Prints, never asserts.

1. Memory. ``rubrotor simulate seal_rub.toml --out FILE.nc --figure`` with ``revolutions`` set
   to each of ``--revs`` (10,000 revolutions at 6000 rev/min and dt = 2e-5 s are 5 million
   samples, a 1.1 GiB file): each in a fresh child whose peak resident memory is read from
   ``os.wait4`` (the child's own ``ru_maxrss``). The run streams its samples to the file and
   the summary and figure read the file in pieces, so the peak should not grow with the length.
2. Kill and continue. The longest run again, killed with ``SIGKILL`` once its file has reached
   half the uninterrupted file's size; then ``rubrotor simulate`` of the same scenario with
   ``[initial] state = "file"`` on the killed file and ``duration`` the time left. Printed: the
   killed file's status, samples and restart time, and the largest difference between the
   continued and the uninterrupted final states (``final_state``, ``[q, q']`` on every DOF)
   relative to the largest entry.

Measured 2026-11-25 (2 cores shared with other jobs): 5,000 revolutions (2.5e6 samples, 539 MiB
file) 32.1 s, peak RSS 457.5 MiB; 10,000 revolutions (5e6 samples, 1077 MiB) 42.5 s, peak RSS
458.8 MiB (before, the CLI read the whole file back: 1.2 GB for a 449 MB file; the figure of the
last 2^18 samples is most of the peak). Killed at 541 MiB: status "partial", 2,490,369 samples
(152 chunks of 16,384 + 1) to t = 49.807360 s, its restart state at that time, no hidden file
left; continued for the 2,509,632 steps left: final state against the uninterrupted run,
max |diff| / max |x| = 1.4e-12 (2.7e-12 in an earlier run killed elsewhere).
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SEAL = ROOT / "src" / "rubrotor" / "scenarios" / "seal_rub.toml"
DT = 2e-5  # s, seal_rub's step and sample spacing


def _env() -> dict:
    return dict(os.environ, PYTHONPATH=str(ROOT / "src"), OPENBLAS_NUM_THREADS="1")


def _scenario(path: Path, revolutions: float | None = None, initial: str | None = None,
              duration: float | None = None) -> Path:  # fmt: skip
    text = SEAL.read_text()
    if revolutions is not None:
        text = text.replace("revolutions = 40", f"revolutions = {revolutions}")
    if duration is not None:
        text = text.replace("revolutions = 40", f"duration = {duration!r}")
    if initial is not None:
        text = text.replace('state = "static"', initial)
    path.write_text(text)
    return path


def _simulate(scenario: Path, out: Path, figure: bool = True) -> tuple[float, float, int]:
    """Run ``rubrotor simulate`` in a child: its wall time (s), peak RSS (MiB), exit status."""
    cmd = [sys.executable, "-m", "rubrotor", "simulate", str(scenario), "--out", str(out),
           "--no-progress"] + (["--figure"] if figure else [])  # fmt: skip
    t0 = time.perf_counter()
    child = subprocess.Popen(cmd, env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - t0
    return wall, usage.ru_maxrss / 1024, os.waitstatus_to_exitcode(status)


def memory(revs_list, directory: Path) -> Path:
    print("streamed rubrotor simulate seal_rub.toml --figure (dt = 2e-5 s, one sample per step)")
    print(f"{'revolutions':>12}{'samples':>10}{'file MiB':>10}{'wall s':>8}{'peak RSS MiB':>14}"
          "  status")  # fmt: skip
    for revs in sorted(revs_list):
        out = directory / f"seal_{revs}.nc"
        wall, rss, code = _simulate(_scenario(directory / f"seal_{revs}.toml", revs), out)
        import netCDF4

        with netCDF4.Dataset(out) as nc:
            n, status = nc.dimensions["time"].size, nc.status
        print(f"{revs:12d}{n:10d}{out.stat().st_size / 2**20:10.0f}{wall:8.1f}{rss:14.1f}"
              f"  {status} (exit {code})")  # fmt: skip
    return out


def kill_and_continue(revs: int, whole: Path, directory: Path) -> None:
    import xarray as xr

    scen = _scenario(directory / "killed.toml", revs)
    out = directory / "killed.nc"
    half = whole.stat().st_size // 2
    cmd = [sys.executable, "-m", "rubrotor", "simulate", str(scen), "--out", str(out),
           "--no-progress"]  # fmt: skip
    child = subprocess.Popen(cmd, env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    while not (out.exists() and out.stat().st_size >= half) and child.poll() is None:
        time.sleep(0.01)
    child.send_signal(signal.SIGKILL)
    child.wait()
    left = sorted(p.name for p in directory.iterdir() if p.name.startswith(".killed"))
    with xr.open_dataset(out) as ds:
        n, t_keep = ds.sizes["time"], float(ds["restart_time"].values[-1])
        print(
            f"\nkilled (SIGKILL) at {out.stat().st_size / 2**20:.0f} MiB: status "
            f"{ds.attrs['status']!r}, {n} samples to t = {float(ds['time'].values[-1]):.6f} s, "
            f"restart state at t = {t_keep:.6f} s, hidden files left: {left or 'none'}"
        )
    with xr.open_dataset(whole) as ds:
        steps = ds.sizes["time"] - 1
        ref = np.array(json.loads(ds.attrs["final_state"]))
    rest = steps - round(t_keep / DT)
    cont = _scenario(directory / "cont.toml", None, f'state = "file"\npath = "{out}"',
                     duration=rest * DT)  # fmt: skip
    wall, rss, code = _simulate(cont, directory / "cont.nc", figure=False)
    with xr.open_dataset(directory / "cont.nc") as ds:
        got = np.array(json.loads(ds.attrs["final_state"]))
        t_end = float(ds["time"].values[-1])
    diff = np.abs(got - ref).max() / np.abs(ref).max()
    print(
        f"continued {rest} steps to t = {t_end:.6f} s in {wall:.1f} s (peak RSS {rss:.1f} "
        f"MiB, exit {code}): final state against the uninterrupted run, max |diff| / max "
        f"|x| = {diff:.3e}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--revs", type=int, nargs="+", default=[5000, 10000])
    ap.add_argument("--dir", type=Path, default=Path("/tmp/rubrotor_bench_stream"))
    a = ap.parse_args()
    a.dir.mkdir(parents=True, exist_ok=True)
    whole = memory(a.revs, a.dir)
    kill_and_continue(max(a.revs), whole, a.dir)
    for p in a.dir.glob("*.nc"):
        p.unlink()


if __name__ == "__main__":
    main()
