"""Long runs streamed to disk with bounded memory, and fixed-step throughput against retained modes.

Run from the repository root: ``python benchmarks/bench_engine_stream.py [--revs 1e4 1e5 1e6]
[--reps 3] [--dir /tmp]``. Prints, never asserts.

1. Streaming. The 60-element rotor of benchmarks/bench_engine.py (two disks, anisotropic
   cross-coupled bearings, unbalance at both disks, gravity) rubbing at a disk against a flexible
   offset stator, 400 rad/s, 8 retained modes with the residual correction, 64 fixed steps per
   revolution from rest, 2 samples per revolution written to a netCDF file chunk by chunk
   (``simulate_general(..., stream=path)``). Each length runs in a fresh process that reports its
   peak resident memory (``resource.getrusage(RUSAGE_SELF).ru_maxrss``) before and after the run,
   so the increase is what the run itself costs; wall time and file size are printed too.
   At 400 rad/s this rotor is linearly unstable (its cross-coupled bearings give two whirl modes
   growth rates of +0.9 and +4.7 1/s): the rub bounds the self-excited whirl, so the run rubs
   some 4.7 times per revolution throughout; the events go to the file with every chunk of
   samples, and each netCDF variable has a bounded (1 MiB) HDF5 chunk cache, so the peak
   memory should not grow with the length of the run (compare the 1e5 and 1e6 rows).
2. Throughput. The same run (64 steps per revolution from rest) over 1000 revolutions, in which
   the self-excited whirl grows into rub within the first revolutions: microseconds per step of
   the compiled time loop (median of ``--reps``, after a warm-up call) against the number of
   retained modes (the full model has 244 DOFs, 244 stored modes).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

SPEED = 400.0  # rad/s
STEPS_PER_REV = 64
SAVE_EVERY = 32


def _rss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # Linux: KiB


def child(revs: float, path: str) -> None:
    """One streamed run in this (fresh) process; prints a JSON line."""
    import math

    from bench_engine import general_rotor

    from rubrotor.engine.driver import simulate_general
    from rubrotor.engine.parts import Run

    system, stations, unb = general_rotor()
    period = 2 * math.pi / SPEED
    step = period / STEPS_PER_REV

    def go(n_rev, out):
        run = Run(speed=SPEED, duration=n_rev * period, step=step, save_every=SAVE_EVERY,
                  modes=8, initial="rest")  # fmt: skip
        return simulate_general(system, run, stations, unb, gravity=(-9.81, 0.0),
                                progress=False, stream=out)  # fmt: skip

    go(10, path)  # warm-up: compilation or cache load, netCDF library
    before = _rss_mib()
    t0 = time.perf_counter()
    res = go(revs, path)
    wall = time.perf_counter() - t0
    after = _rss_mib()
    print(json.dumps({"revs": revs, "wall_s": wall, "kernel_s": res.stats["wall_s"],
                      "steps": res.stats["steps"], "rss_before_mib": before,
                      "rss_peak_mib": after, "file_mib": os.path.getsize(path) / 2**20,
                      "status": res.status, "events": res.stats["contact_events"]}))  # fmt: skip


def streaming(revs_list, directory: Path) -> None:
    print(f"streamed runs: 60-element rotor, rub at a disk, {SPEED} rad/s, 8 modes, "
          f"{STEPS_PER_REV} steps/rev, {STEPS_PER_REV // SAVE_EVERY} samples/rev")  # fmt: skip
    print(f"{'revolutions':>12}{'steps':>12}{'wall s':>10}{'us/step':>9}{'RSS before MiB':>16}"
          f"{'RSS peak MiB':>14}{'increase MiB':>14}{'file MiB':>10}{'events':>10}  status")  # fmt: skip
    for revs in revs_list:
        path = directory / f"rubrotor_stream_{int(revs)}.nc"
        env = dict(os.environ, PYTHONPATH=str(HERE.parent / "src"))
        out = subprocess.run([sys.executable, __file__, "--child", str(revs), str(path)],
                             capture_output=True, text=True, env=env, check=False)  # fmt: skip
        if out.returncode:
            print(f"{revs:12.0e}  failed: {out.stderr.strip().splitlines()[-1:]}")
            continue
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"{r['revs']:12.0e}{r['steps']:12d}{r['wall_s']:10.1f}"
              f"{1e6 * r['kernel_s'] / r['steps']:9.3f}{r['rss_before_mib']:16.1f}"
              f"{r['rss_peak_mib']:14.1f}{r['rss_peak_mib'] - r['rss_before_mib']:14.1f}"
              f"{r['file_mib']:10.1f}{r['events']:10d}  {r['status']}")  # fmt: skip
        path.unlink(missing_ok=True)


def throughput(reps: int) -> None:
    import math

    from bench_engine import general_rotor

    from rubrotor.engine.driver import simulate_general
    from rubrotor.engine.parts import Run

    system, stations, unb = general_rotor()
    period = 2 * math.pi / SPEED
    print(f"\nfixed-step throughput: 60-element rotor ({system.n_dof} DOFs), rub at a disk, "
          f"{STEPS_PER_REV} steps/rev, 1000 rev from rest")  # fmt: skip
    print(f"{'modes':>6}{'us/step':>10}{'steps':>9}{'contact events':>16}{'Newton it/step':>16}",
          flush=True)  # fmt: skip
    for modes in (4, 8, 16, 32, 64, 128, None):
        run = Run(speed=SPEED, duration=1000 * period, step=period / STEPS_PER_REV,
                  save_every=SAVE_EVERY, modes=modes, initial="rest")  # fmt: skip

        def go(run=run):
            return simulate_general(system, run, stations, unb, gravity=(-9.81, 0.0),
                                    progress=False)  # fmt: skip

        go()
        walls, r = [], None
        for _ in range(reps):
            r = go()
            walls.append(r.stats["wall_s"])
        s = r.stats
        label = "all" if modes is None else str(modes)
        print(f"{label:>6}{1e6 * statistics.median(walls) / s['steps']:10.3f}{s['steps']:9d}"
              f"{s['contact_events']:16d}{s['newton_iterations'] / s['steps']:16.2f}",
              flush=True)  # fmt: skip


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        child(float(sys.argv[2]), sys.argv[3])
        return
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--revs", type=float, nargs="+", default=[1e4, 1e5, 1e6])
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--dir", type=Path, default=Path("/tmp"))
    ap.add_argument("--skip-throughput", action="store_true")
    ap.add_argument("--skip-streaming", action="store_true")
    a = ap.parse_args()
    if not a.skip_streaming:
        streaming(a.revs, a.dir)
    if not a.skip_throughput:
        throughput(a.reps)


if __name__ == "__main__":
    main()
