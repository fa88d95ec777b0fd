"""Benchmark of rubrotor.sweeps.sweep: a 400-point speed sweep, 1 vs 2 local workers vs a plain loop.

Seed case 1 (3 modes) with the spin speed swept over 0.5 .. 3 x the first forward critical,
300 revolutions per point of which 100 are discarded, 128 samples per revolution (adaptive
exponential integrator, the scenario's tolerances). Prints the median of REPEATS runs of:

* ``sweep(..., workers=1)`` (in process), ``sweep(..., workers=2)`` (process pool, pool start-up
  included), and a plain Python loop of ``simulate(scenario)`` calls with the same integrator
  settings (which also builds the full results Dataset per point, as a user would);
* ratios: speed-up 1 -> 2 workers (goal >= 1.8) and sweep (2 workers) vs the loop;
* the split of one point's time: compiled kernel (``stats["wall_s"]``) and the rest.

``--baseline DIR`` (issue 14: sweep throughput at least 2x): also runs the same sweeps with the
package at ``DIR`` (e.g. ``DIR/rubrotor`` a copy of main's ``src/rubrotor``: ``git archive main
src | tar -x -C /tmp/main``, then ``--baseline /tmp/main/src``), each sweep in a fresh process,
ours and the baseline's interleaved in every repeat (same machine, same load), checks that the
two give identical Datasets and prints points per second of each and their ratio.

Numba compilation is excluded (a warm-up point runs first). Timings are never asserted.
Run: ``PYTHONPATH=src python benchmarks/bench_sweep.py [POINTS] [REPEATS] [--baseline DIR]``.
"""

from __future__ import annotations

import argparse
import math
import os
import pickle
import statistics
import subprocess
import sys
import tempfile
import time
from importlib import resources
from pathlib import Path

import numpy as np

KW = dict(transient_revolutions=100, revolutions=300, samples_per_revolution=128)


def _scenario():
    from rubrotor.scenario import load_scenario

    return load_scenario(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")


def _vary(points: int) -> dict:
    # 0.5..3 x critical crosses the first forward critical exactly at 1.0; the undamped modal
    # system is singular there, so such points are recorded as "not classified"
    return {"speed.critical_multiple": np.linspace(0.5, 3.0, points)}


def _cpu() -> float:
    """CPU seconds of this process and of its finished (joined) children."""
    import resource

    a, b = (resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return a.ru_utime + a.ru_stime + b.ru_utime + b.ru_stime


def child(points: int, workers: int, out: str) -> None:
    """One timed sweep in this process (after a warm-up point); pickles
    ``((wall seconds, CPU seconds), Dataset)``; the pool's workers are joined by ``sweep``."""
    from rubrotor.sweeps.sweep import sweep

    sc = _scenario()
    sweep(sc, {"speed.critical_multiple": [1.5]}, workers=1, **KW)
    t, c = time.perf_counter(), _cpu()
    ds = sweep(sc, _vary(points), workers=workers, **KW)
    el = (time.perf_counter() - t, _cpu() - c)
    with open(out, "wb") as fh:
        pickle.dump((el, ds), fh)


def _run_child(src: str, points: int, workers: int):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "r.pkl")
        env = dict(os.environ, PYTHONPATH=src)
        cmd = [sys.executable, __file__, str(points), "--child", str(workers), out]
        subprocess.run(cmd, env=env, check=True)
        with open(out, "rb") as fh:
            return pickle.load(fh)


def against_baseline(points: int, repeats: int, baseline: str) -> None:
    """Ours vs the baseline package, each sweep in a fresh process, interleaved."""
    import xarray as xr

    ours_src = str(Path(__file__).resolve().parents[1] / "src")
    times = {(who, w): [] for who in ("ours", "baseline") for w in (1, 2)}
    for _ in range(repeats):
        for w in (1, 2):
            res = {}
            for who, src in (("baseline", baseline), ("ours", ours_src)):
                el, ds = _run_child(src, points, w)
                times[(who, w)].append(el)
                res[who] = ds
            xr.testing.assert_identical(res["ours"], res["baseline"])
    print(f"against the baseline package {baseline} (fresh process per sweep, interleaved):")
    print("  Datasets of ours and the baseline: identical (xarray.testing.assert_identical)")
    print(f"  load average at the end: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    for w in (1, 2):
        for k, what in ((0, "wall"), (1, "CPU ")):
            b = [x[k] for x in times[("baseline", w)]]
            o = [x[k] for x in times[("ours", w)]]
            mb, mo = statistics.median(b), statistics.median(o)
            print(
                f"  {w} worker{'s' if w > 1 else ' '} {what}: baseline {points / mb:6.1f} "
                f"points/s, ours {points / mo:6.1f} points/s, ratio {mb / mo:5.2f}x  "
                f"(s: baseline {[round(x, 2) for x in b]}, ours {[round(x, 2) for x in o]})"
            )
    print("  (CPU = points per CPU second of the sweep's processes: the measure that other")
    print("   jobs on a shared machine disturb least; wall = points per elapsed second)")


def point_split(sc, reps: int = 20) -> None:
    """Median time of one sweep point (simulate_point) and of its compiled kernel."""
    from rubrotor.sweeps.sweep import simulate_point

    pt = sc.with_changes(**{"speed.critical_multiple": 2.0})
    args = (KW["transient_revolutions"], KW["revolutions"], KW["samples_per_revolution"])
    simulate_point(pt, *args)
    calls = []
    for _ in range(reps):
        t = time.perf_counter()
        simulate_point(pt, *args)
        calls.append(time.perf_counter() - t)
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate_scenario

    integ = Integrator(revolutions=300, output_dtau=2 * math.pi / 128, rtol=sc.simulation.rtol,
                       atol=sc.simulation.atol)  # fmt: skip
    kern = statistics.median(
        simulate_scenario(pt, integ, progress=False).stats["wall_s"] for _ in range(reps)
    )
    c = statistics.median(calls)
    print(f"one point (2.0 x critical): {c * 1e3:.2f} ms, of which compiled kernel "
          f"{kern * 1e3:.2f} ms, rest (scenario, modal system, metrics) {(c - kern) * 1e3:.2f} ms")  # fmt: skip


def main(points: int, repeats: int) -> None:
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate
    from rubrotor.sweeps.sweep import regime_labels, sweep

    sc = _scenario()
    speeds = _vary(points)["speed.critical_multiple"]

    t = time.perf_counter()
    sweep(sc, {"speed.critical_multiple": [1.5]}, workers=1, **KW)
    print(f"warm-up (numba load/compile + 1 point): {time.perf_counter() - t:.2f} s")

    def run_sweep(workers):
        t = time.perf_counter()
        ds = sweep(sc, _vary(points), workers=workers, **KW)
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
    labels, counts = np.unique(np.asarray(regime_labels(ds2)), return_counts=True)
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
    point_split(sc)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("points", nargs="?", type=int, default=400)
    ap.add_argument("repeats", nargs="?", type=int, default=3)
    ap.add_argument("--baseline", help="src directory of the package to compare against")
    ap.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        child(a.points, int(a.child[0]), a.child[1])
    elif a.baseline:
        against_baseline(a.points, a.repeats, a.baseline)
    else:
        main(a.points, a.repeats)
