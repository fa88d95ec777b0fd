"""Continuation of the one-mode rotor's rub branch against a state-carrying sweep of its range.

By default (``method="auto"``) this circular branch is continued as equilibria of the rotating
frame (:mod:`rubrotor.orbits.synchronous`, exact); the shooting route (``method="shooting"``) runs the
stroboscopic map prepared once per key value (only its
speed-dependent coefficients rebuilt when the speed is continued) with the monodromy from the
map's variational equations in the same compiled run, corrects each predictor by Broyden
iterations from the previous point's Jacobian (one map run each), and locates contact onset on
the free orbit's grazing condition.
Run: ``PYTHONPATH=src python benchmarks/bench_continuation.py [POINTS] [REPEATS]``.

Measured 2026-11-23 (2 cores, quiet, 200 points, medians of 3): follow sweep up+down 9.69 s;
continuation on the default (synchronous, exact) route 0.23 s, 198 points, 1.1 ms per point
(ratio 42.8), on the shooting route at 1024 steps per revolution 0.47 s, 2.4 ms per point
(ratio 20.6; 279 ms per point before the prepared map and the compiled monodromy). Both find
both turning points: contact onset 1.377674297309 (equal to the closed form to 1e-15, located on
the free orbit's grazing condition), the fold at 1.6413038556 (synchronous, exact) or 1.6413022533
(shooting, second order in the step), and no other bifurcation; 49 (synchronous) and 55
(shooting: its points are spaced differently) unstable orbits between them. The sweep's jumps
lag the fold and onset by up to two sweep steps (slow drift near a turning point).

pyHarm (``pyharm-os`` 1.2.2, optional group ``pyharm``) on the same rotor with a radial penalty
contact: ``benchmarks/bench_continuation_vs_pyharm.py``. Prints the
median wall time of each (same process, side by side) and what each finds: the continuation's
folds and stability against the closed form, the sweep's jumps (up: last rub point, down: last
no-contact point). Numba compilation is excluded by a warm-up run of each.
"""

from __future__ import annotations

import statistics
import sys
import time
from importlib import resources

import numpy as np

from rubrotor.orbits.continuation import continue_orbit
from rubrotor.scenario import load_scenario
from rubrotor.sweeps.follow import follow_sweep
from rubrotor.sweeps.sweep import regime_labels

KEY = "speed.critical_multiple"
FOLD, ONSET = 1.6413, 1.3777  # x critical, the one_mode_annular_rub.toml closed form (rounded)


def main(points: int = 200, repeats: int = 3) -> None:
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / "one_mode_annular_rub.toml")
    values = np.linspace(1.2, 1.8, points)
    methods = ("auto", "shooting")  # auto: the exact synchronous route on this circular branch
    for m in methods:
        continue_orbit(sc, KEY, 1.8, 1.7, points=3, method=m)
    follow_sweep(sc, KEY, values[:2], direction="both", workers=1)
    t_c, t_s, branch = {m: [] for m in methods}, [], {}
    for _ in range(repeats):
        for m in methods:
            t0 = time.perf_counter()
            branch[m] = continue_orbit(sc, KEY, 1.8, 1.2, points=points, method=m)
            t_c[m].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        ds = follow_sweep(sc, KEY, values, direction="both", workers=1)
        t_s.append(time.perf_counter() - t0)
    s = statistics.median(t_s)
    print(f"follow sweep up+down, {points} values: {s:.2f} s (median of {repeats})")
    for m in methods:
        c, b = statistics.median(t_c[m]), branch[m]
        print(f"continuation ({b.method}), {len(b.points)} points: {c:.2f} s, "
              f"{1e3 * c / len(b.points):.1f} ms per branch point; ratio sweep/continuation "
              f"{s / c:.1f}")  # fmt: skip
        print("  finds:", [(x.type, round(x.value, 10)) for x in b.bifurcations])
        print("  unstable points:", sum(not p.stable for p in b.points))
        print("  contact onset (grazing of the free orbit):", [round(g, 12) for g in b.grazings])
    print(f"closed form (tests/test_follow_sweep.py): fold {FOLD}, onset {ONSET}")
    labels = regime_labels(ds)
    up = values[np.flatnonzero(labels[0] == "no contact")[0]]
    down = values[np.flatnonzero(labels[1] == "full annular rub")[-1]]
    print(f"sweep finds: up jump between {up - values[1] + values[0]:.5f} and {up:.5f}; "
          f"down jump between {down:.5f} and {down + values[1] - values[0]:.5f}")  # fmt: skip


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
