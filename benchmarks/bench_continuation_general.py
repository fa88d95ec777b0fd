"""Continuation of a general rotor's rub branch in speed: the previous route against today's.

``seal_rub.toml`` (284-DOF finite-element rotor, 16 kept modes, flexible offset stator, friction,
speed-tabulated cross-coupled bearings), continued in ``speed.rad_per_s`` from 600 rad/s at
128 fixed steps per revolution, by both routes in one process:

* previous: every key value rebuilt the plant (dense eigen-decomposition of the 568 x 568
  first-order matrix, dense inverses) and the monodromy came from central differences
  (``2 dim`` extra map runs per Jacobian) -- reproduced here by patching
  ``GeneralMap.at_speed`` and ``GeneralMap.run`` back to that;
* today: a speed key updates only the speed-dependent parts of the plant
  (:class:`rubrotor.orbits.speed_family.SpeedFamily`), the monodromy is propagated exactly in
  the compiled run (:func:`rubrotor.core.engine_tangent.map_tangent`) and the corrector is
  Newton in the state at the predicted speed (two plants per point).

Marginal cost per point: (time of an 8-point run - time of a 2-point run) / 6, so that the
shared start (shooting the first orbit, the first dense plant, the first basis) cancels; wall
time and this process's CPU time (on a shared machine the CPU time is the steadier measure).
The routes' correctors place their points at different speeds, so each route's points are
re-shot (Newton to 1e-12) on the other route's maps at their speeds. Then a 200-point branch
over 600-800 rad/s on today's route, timed.

Measured 2026-11-25 on the shared 2-core machine (load 7-9; least of 3 runs each): marginal
2883 ms wall (1485 ms CPU) per point on the previous route, 26.8 ms wall (13.0 ms CPU) today:
107x wall, 114x CPU (single runs under heavier load gave 40x-130x). Today's points equal the
previous route's fixed points to 1.2e-9; the previous route's own points sit 1.7e-7 from its
maps' fixed points and from today's alike (its corrector stops at 1e-6). 200 points from 600
to 798 rad/s in 5.5 s wall (3.8 s CPU). Today's six points cost about as much as the jitter
of the runs' fixed part (~1 s: the first orbit, dense plant and basis), so the marginal is
noisy on a loaded machine (a later run gave 5.7 ms CPU per point, and an 8-point run faster
than the 2-point one in wall time); the 200-point branch, every cost included (31 ms per
point wall in that run), is the steadier figure.

Run: ``PYTHONPATH=src OPENBLAS_NUM_THREADS=1 python benchmarks/bench_continuation_general.py``.
"""

from __future__ import annotations

import contextlib
import time
from importlib import resources

import numpy as np

from rubrotor.orbits import continuation, shooting
from rubrotor.orbits.continuation import continue_orbit
from rubrotor.orbits.general_map import GeneralMap
from rubrotor.scenario import load_scenario

KEY, STEPS = "speed.rad_per_s", 128
REPEATS = 3
"""Runs of each length per route; the least time counts."""
DS_LONG = 0.083
"""Arclength step (scaled) of the long branch: about 200 points from 600 to 800 rad/s."""


@contextlib.contextmanager
def previous_route():
    """``GeneralMap`` and the corrector as they were: a dense rebuild per speed, the difference
    monodromy, the key's central difference and Broyden updates of the whole Jacobian."""
    at_speed, run, problem = GeneralMap.at_speed, GeneralMap.run, continuation._problem

    def rebuilt(self, speed):
        return GeneralMap(self.scenario, self.k, self.steps, speed, self.reference or self)

    def differences(self, x, jacobian=False):
        return self.differences(x) if jacobian else run(self, x)

    def old_problem(*args, **kw):
        prob = problem(*args, **kw)
        prob.central, prob.exact_gx = True, False
        return prob

    GeneralMap.at_speed, GeneralMap.run = rebuilt, differences
    continuation._problem = old_problem
    try:
        yield
    finally:
        GeneralMap.at_speed, GeneralMap.run = at_speed, run
        continuation._problem = problem


def timed(sc, points, **kw):
    """``(wall s, CPU s, branch)`` of a continuation from 600 rad/s of ``points`` points."""
    t0, c0 = time.perf_counter(), time.process_time()
    branch = continuation.continue_orbit(sc, KEY, 600.0, 620.0, points=points, steps=STEPS, **kw)
    return time.perf_counter() - t0, time.process_time() - c0, branch


def marginal(sc, label, repeats=REPEATS):
    """Marginal wall and CPU time per point (s): (8-point run - 2-point run) / 6, each run's
    time the least of ``repeats`` (the least disturbed by other processes)."""
    timed(sc, 2)  # warm-up: numba compilation and caches
    two = [timed(sc, 2) for _ in range(repeats)]
    eight = [timed(sc, 8) for _ in range(repeats)]
    w2, c2 = min(t[0] for t in two), min(t[1] for t in two)
    w8, c8 = min(t[0] for t in eight), min(t[1] for t in eight)
    wall, cpu = (w8 - w2) / 6, (c8 - c2) / 6
    print(f"{label}: 2 points {w2:.2f} s, 8 points {w8:.2f} s (wall, least of {repeats}); "
          f"marginal {1e3 * wall:.1f} ms/point wall, {1e3 * cpu:.1f} ms/point CPU")  # fmt: skip
    return (wall, cpu), eight[-1][2]


def reshot(branch, first, route):
    """Largest relative change of a branch's states when each is re-shot (Newton to 1e-12) on
    the map of ``route`` ("previous": dense rebuild; "today": speed family) at its key value."""
    worst = 0.0
    for p in branch.points[1:]:
        if route == "previous":
            with previous_route():
                mp = GeneralMap(first.scenario, 1, STEPS, p.value, first)
                x = shooting.newton_orbit(mp, p.state, tol=1e-12)[0]
        else:
            x = shooting.newton_orbit(first.at_speed(p.value), p.state, tol=1e-12)[0]
        worst = max(worst, float(np.max(np.abs(x - p.state)) / np.max(np.abs(x))))
    return worst


def compare(old, new, sc):
    """Each route's points re-shot on the other route's maps (the routes' correctors place
    their points at different key values, so points are compared at equal key values)."""
    first = GeneralMap(sc.with_changes(**{KEY: 600.0}), 1, STEPS)
    print(f"today's points re-shot on the previous route's maps: states equal to "
          f"{reshot(new, first, 'previous'):.1e}; the previous route's points on today's "
          f"maps: {reshot(old, first, 'today'):.1e}, on its own: "
          f"{reshot(old, first, 'previous'):.1e} (relative; its corrector stops at 1e-6)")  # fmt: skip


def long_branch(sc):
    t0, c0 = time.perf_counter(), time.process_time()
    branch = continue_orbit(sc, KEY, 600.0, 800.0, points=200, steps=STEPS, ds=DS_LONG,
                            ds_max=DS_LONG)  # fmt: skip
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    vals = [p.value for p in branch.points]
    print(f"today's route, 600-800 rad/s: {len(vals)} points ({vals[0]:.1f} to {vals[-1]:.1f} "
          f"rad/s) in {wall:.1f} s wall ({cpu:.1f} s CPU), {1e3 * wall / len(vals):.0f} ms/point; "
          f"bifurcations: {[(b.type, round(b.value, 3)) for b in branch.bifurcations]}")  # fmt: skip


def main() -> None:
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / "seal_rub.toml")
    with previous_route():
        old, old_branch = marginal(sc, "previous route (dense rebuild per speed, differences)")
    new, new_branch = marginal(sc, "today (speed family, propagated monodromy)")
    print(f"ratio previous / today per point: {old[0] / new[0]:.0f}x wall, "
          f"{old[1] / new[1]:.0f}x CPU")  # fmt: skip
    compare(old_branch, new_branch, sc)
    long_branch(sc)


if __name__ == "__main__":
    main()
