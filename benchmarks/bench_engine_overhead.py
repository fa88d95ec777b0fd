"""Fixed cost per call of the general engine (issue 14, item 3).

Seed case 1 at default settings (adaptive, rtol 1e-6) for 1, 20 and 200 revolutions: median
wall time per ``simulate_general`` call, the compiled kernel's share (``stats["wall_s"]``) and
the rest (reduction, coefficient tables, buffers, result), plus ``to_dataset()`` separately.
The fixed cost is the intercept of the call time against the revolutions. Prints, never asserts.
Run: ``PYTHONPATH=src python benchmarks/bench_engine_overhead.py [--reps 5]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
from pathlib import Path

import numpy as np

import rubrotor
from rubrotor.engine.continuous import continuous_system
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.model import RubStation, Run
from rubrotor.integrator import Integrator
from rubrotor.scenario import load_scenario

SCEN = Path(rubrotor.__file__).parent / "scenarios" / "seed_case1.toml"


def main(reps: int) -> None:
    sc = load_scenario(SCEN)
    w = sc.speed
    system = continuous_system(sc.shaft)
    stn = [RubStation(dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2))]
    revs, calls = (1, 20, 200), []
    for rev in revs:
        integ = Integrator(revolutions=rev)
        run = Run(speed=w, duration=integ.total_time(w), step=integ.output_spacing(w),
                  rtol=integ.rtol, atol=integ.atol)  # fmt: skip

        def go(run=run):
            return simulate_general(system, run, stn, [sc.unbalance], progress=False)

        go()
        walls, kern, ds = [], [], []
        for _ in range(reps):
            t0 = time.perf_counter()
            r = go()
            walls.append(time.perf_counter() - t0)
            kern.append(r.stats["wall_s"])
            t0 = time.perf_counter()
            r.to_dataset()
            ds.append(time.perf_counter() - t0)
        c, k, d = (statistics.median(x) * 1e3 for x in (walls, kern, ds))
        calls.append(c)
        print(f"{rev:4d} rev: call {c:8.3f} ms  kernel loop {k:8.3f} ms  rest {c - k:6.3f} ms  "
              f"to_dataset {d:6.3f} ms")  # fmt: skip
    slope, icpt = np.polyfit(revs, calls, 1)
    print(f"fit: {icpt:.3f} ms fixed + {slope:.4f} ms per revolution")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=5)
    main(ap.parse_args().reps)
