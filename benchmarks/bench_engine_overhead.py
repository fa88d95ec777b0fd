"""Fixed cost per call (issue 14: per-call overhead, the Dataset built cheaply).

Seed case 1 at default settings (adaptive, rtol 1e-6) for 1, 20 and 200 revolutions, median
of ``--reps`` calls (one core, CPU time of this process, which other jobs on a shared machine
disturb least; wall time in brackets):

* the user's call ``rubrotor.simulate(scenario)`` (seed engine) and its parts: the array-level
  run ``simulate_scenario`` and ``to_dataset``; with ``PreparedRun`` (when the package has it)
  a run of a prepared model (set up once: modal system, rows, coefficients);
* the general engine ``simulate_general`` on the same problem, the compiled kernel's share
  (``stats["wall_s"]``) and ``to_dataset()``.

The fixed cost is the intercept of the call time against the revolutions. ``--baseline DIR``
runs the same measurements with the package at ``DIR`` (e.g. main's ``src``) in a fresh process,
interleaved with ours (``--rounds`` times), and prints both side by side with their ratio.
Prints, never asserts. Run: ``PYTHONPATH=src python benchmarks/bench_engine_overhead.py
[--reps 15] [--baseline DIR --rounds 3]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REVS = (1, 20, 200)


def _median_ms(fn, reps: int) -> tuple[float, float]:
    """Median CPU and wall milliseconds of ``fn()`` (after one warm-up call)."""
    fn()
    cpu, wall = [], []
    for _ in range(reps):
        c, w = time.process_time(), time.perf_counter()
        fn()
        cpu.append(time.process_time() - c)
        wall.append(time.perf_counter() - w)
    return statistics.median(cpu) * 1e3, statistics.median(wall) * 1e3


def measure(reps: int) -> dict:
    """``{row: {revolutions: (cpu ms, wall ms)}}`` for every row this package can run."""
    import rubrotor
    from rubrotor.engine.driver import simulate_general
    from rubrotor.engine.parts import RubStation, Run
    from rubrotor.engine.result import to_dataset
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate, simulate_scenario
    from rubrotor.rotors.shaft_system import continuous_system
    from rubrotor.scenario import load_scenario

    sc = load_scenario(Path(rubrotor.__file__).parent / "scenarios" / "seed_case1.toml")
    w = sc.speed
    system = continuous_system(sc.shaft)
    stn = [RubStation(dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2))]
    rows: dict = {}
    for rev in REVS:
        integ = Integrator(revolutions=rev)
        res = simulate_scenario(sc, integ, progress=False)
        run = Run(speed=w, duration=integ.total_time(w), step=integ.output_spacing(w),
                  rtol=integ.rtol, atol=integ.atol)  # fmt: skip
        eng = simulate_general(system, run, stn, [sc.unbalance], progress=False)
        cases = {
            "simulate() seed engine": lambda i=integ: simulate(sc, integrator=i, progress=False),
            "  simulate_scenario (arrays)": lambda i=integ: simulate_scenario(
                sc, i, progress=False
            ),
            "  to_dataset": lambda r=res: to_dataset(r, {}, sc.source, sc.name),
            "simulate_general": lambda r=run: simulate_general(
                system, r, stn, [sc.unbalance], progress=False
            ),
            "  EngineResult.to_dataset": eng.to_dataset,
        }
        try:
            from rubrotor.engine.simulate import PreparedRun

            prepared = PreparedRun.from_scenario(sc, integ)
            cases["  PreparedRun.run (set up once)"] = prepared.run
        except ImportError:  # a baseline without the array-level entry
            pass
        for name, fn in cases.items():
            rows.setdefault(name, {})[rev] = _median_ms(fn, reps)
        kern = [simulate_general(system, run, stn, [sc.unbalance], progress=False).stats["wall_s"]
                for _ in range(reps)]  # fmt: skip
        rows.setdefault("  engine kernel loop (wall)", {})[rev] = (np.nan, statistics.median(kern) * 1e3)  # fmt: skip
    return rows


def _fit(row: dict) -> str:
    cpu = [row[r][0] for r in REVS]
    if not np.all(np.isfinite(cpu)):
        return ""
    slope, icpt = np.polyfit(REVS, cpu, 1)
    return f"fit {icpt:7.3f} ms fixed + {slope:.4f} ms/rev"


def report(rows: dict) -> None:
    print("CPU ms per call, median (wall ms in brackets)")
    print(f"{'':34s}" + "".join(f"{r:>20d} rev" for r in REVS))
    for name, row in rows.items():
        cells = "".join(f"{row[r][0]:13.3f} ({row[r][1]:8.3f})" for r in REVS)
        print(f"{name:34s}{cells}   {_fit(row)}")


def against_baseline(baseline: str, reps: int, rounds: int) -> None:
    ours = str(Path(__file__).resolve().parents[1] / "src")
    got: dict = {"baseline": [], "ours": []}
    for _ in range(rounds):
        for who, src in (("baseline", baseline), ("ours", ours)):
            cmd = [sys.executable, __file__, "--reps", str(reps), "--json"]
            out = subprocess.run(cmd, env=dict(os.environ, PYTHONPATH=src), check=True,
                                 capture_output=True, text=True).stdout  # fmt: skip
            got[who].append(json.loads(out.strip().splitlines()[-1]))
    print(f"baseline {baseline} vs ours, {rounds} interleaved rounds of {reps} calls each, "
          "CPU ms per call (median of the rounds' medians):")  # fmt: skip
    print(f"{'':34s}" + "".join(f"{r:>26d} rev" for r in REVS))
    for name in got["ours"][0]:
        cells = []
        col = 1 if "(wall)" in name else 0  # the kernel loop is timed by wall clock only
        for r in REVS:
            o = statistics.median(x[name][str(r)][col] for x in got["ours"])
            b = [x[name][str(r)][col] for x in got["baseline"] if name in x]
            if b and np.isfinite(o):
                m = statistics.median(b)
                cells.append(f"{m:8.3f} -> {o:8.3f} {m / o:5.2f}x")
            else:
                cells.append(f"{'-':>8s} -> {o:8.3f} {'':6s}")
        print(f"{name:34s}" + "".join(f"{c:>30s}" for c in cells))


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=15)
    ap.add_argument("--baseline", help="src directory of the package to compare against")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.baseline:
        against_baseline(a.baseline, a.reps, a.rounds)
    elif a.json:
        print(json.dumps(measure(a.reps)))
    else:
        report(measure(a.reps))
