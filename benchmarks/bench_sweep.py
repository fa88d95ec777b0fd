"""Benchmark of rubrotor.sweep: a 400-point speed sweep, 1 vs 2 local workers vs a plain loop.

Seed case 1 (3 modes) with the spin speed swept over 0.5 .. 3 x the first forward critical,
300 revolutions per point of which 100 are discarded, 128 samples per revolution (adaptive
exponential integrator, the scenario's tolerances). Prints the median of REPEATS runs of:

* ``sweep(..., workers=1)`` (in process), ``sweep(..., workers=2)`` (process pool, pool start-up
  included), and a plain Python loop of ``simulate(scenario)`` calls with the same integrator
  settings (which also builds the full results Dataset per point, as a user would);
* ratios: speed-up 1 -> 2 workers (goal >= 1.8) and sweep (2 workers) vs the loop.

Numba compilation is excluded (a warm-up point runs first). Timings are never asserted.
Run: ``PYTHONPATH=src python benchmarks/bench_sweep.py [POINTS] [REPEATS]``.
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from importlib import resources

import numpy as np


def main() -> None:
    from rubrotor.integrator import Integrator
    from rubrotor.scenario import load_scenario
    from rubrotor.simulation import simulate
    from rubrotor.sweep import sweep

    points = int(sys.argv[1]) if len(sys.argv) > 1 else 400
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")
    speeds = np.linspace(0.5, 3.0, points)
    # 0.5..3 x critical crosses the first forward critical exactly at 1.0; the undamped modal
    # system is singular there, so such points are recorded as "not classified"
    vary = {"speed.critical_multiple": speeds}
    kw = dict(transient_revolutions=100, revolutions=300, samples_per_revolution=128)

    t = time.perf_counter()
    sweep(sc, {"speed.critical_multiple": [1.5]}, workers=1, **kw)
    print(f"warm-up (numba load/compile + 1 point): {time.perf_counter() - t:.2f} s")

    def run_sweep(workers):
        t = time.perf_counter()
        ds = sweep(sc, vary, workers=workers, **kw)
        return time.perf_counter() - t, ds

    def run_loop():
        t = time.perf_counter()
        integ = Integrator(revolutions=300, output_dtau=2 * math.pi / 128)
        for s in speeds:
            try:
                simulate(sc.with_changes(**{"speed.critical_multiple": float(s)}), integrator=integ)
            except ValueError:
                pass
        return time.perf_counter() - t

    t1, t2, tl = [], [], []
    for _ in range(repeats):
        a, ds1 = run_sweep(1)
        b, ds2 = run_sweep(2)
        t1.append(a)
        t2.append(b)
        tl.append(run_loop())
    import xarray as xr

    xr.testing.assert_identical(ds1, ds2)
    m1, m2, ml = (statistics.median(x) for x in (t1, t2, tl))
    labels, counts = np.unique(
        np.asarray(__import__("rubrotor.sweep").sweep.regime_labels(ds2)), return_counts=True
    )
    print(f"points: {points}, 300 revolutions each (100 discarded), 3 modes, 2 cores")
    print(f"regimes: {dict(zip(labels.tolist(), counts.tolist(), strict=True))}")
    print(
        f"sweep, 1 worker (in process): median {m1:7.2f} s  ({points / m1:6.1f} points/s)  runs {[round(x, 2) for x in t1]}"
    )
    print(
        f"sweep, 2 workers (processes): median {m2:7.2f} s  ({points / m2:6.1f} points/s)  runs {[round(x, 2) for x in t2]}"
    )
    print(
        f"plain loop of simulate():     median {ml:7.2f} s  ({points / ml:6.1f} points/s)  runs {[round(x, 2) for x in tl]}"
    )
    print(f"speed-up 1 -> 2 workers: {m1 / m2:.2f}x (goal >= 1.8x)")
    print(f"sweep (2 workers) vs plain loop: {ml / m2:.2f}x points per second")
    print(f"sweep (1 worker) vs plain loop:  {ml / m1:.2f}x points per second")


if __name__ == "__main__":
    main()
