"""Seed case 1 at default settings: the old complex path, the general engine and numbalsoda DOP853.

Run from the repository root: ``PYTHONPATH=src python benchmarks/bench_engine_seed.py [--reps 5]``.
Prints, never asserts.

Issue 10 asks that seed case 1 at default settings be no slower than today, with the ratio
against numbalsoda's DOP853 (the strongest compiled peer measured so far). Seed scenarios run
today on the old complex-coordinate path (``rubrotor.engine.simulate.simulate_system``, what
``rubrotor simulate seed_case1.toml`` calls); the general engine (``simulate_general``) runs the
same shaft as a :class:`rubrotor.rotors.linear.LinearSystem`. Both at default settings (adaptive,
rtol 1e-6, default output spacing), whole calls (the general engine's includes building its
plant), medians of ``--reps`` after a warm-up (numba compilation excluded).

DOP853 integrates the general engine's reduced equations through the right-hand side of
benchmarks/bench_engine_peers.py (imported, not copied), at the loosest rtol in 1e-3 ... 1e-11
that is at least as accurate as the general engine, writing every output sample. Errors: largest
contact displacement error over every 8th sample, relative to the orbit's size, against
numbalsoda DOP853 at rtol 1e-12, atol 1e-16 on the same equations.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_engine_peers import (  # noqa: E402
    EVERY,
    SCEN,
    TOLS,
    _median,
    contact_disp,
    make_rhs,
    peer_run,
)

from rubrotor.engine.driver import build_plant, simulate_general  # noqa: E402
from rubrotor.engine.parts import RubStation, Run  # noqa: E402
from rubrotor.engine.settings import Integrator  # noqa: E402
from rubrotor.engine.simulate import simulate_system  # noqa: E402
from rubrotor.rotors.shaft_system import continuous_system  # noqa: E402
from rubrotor.scenario import load_scenario  # noqa: E402


def case(revs: int, reps: int) -> None:
    from numbalsoda import dop853

    sc = load_scenario(SCEN)
    w = sc.speed
    integ = Integrator(revolutions=revs)
    system = continuous_system(sc.shaft)
    stn = [RubStation(dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2))]
    run = Run(speed=w, duration=integ.total_time(w), step=integ.output_spacing(w),
              rtol=integ.rtol, atol=integ.atol)  # fmt: skip

    def old():
        return simulate_system(sc.shaft, w, integ, sc.unbalance, sc.contact, None, sc.damping,
                               progress=False)  # fmt: skip

    def new():
        return simulate_general(system, run, stn, [sc.unbalance], progress=False)

    old(), new()
    plant = build_plant(system, run, stn, [sc.unbalance])
    rhs = make_rhs(plant)
    r_new = new()
    t_all = r_new.time
    ref_y, _ = peer_run(dop853, rhs, plant, t_all, 1e-12, 1e-16)
    ref = contact_disp(plant, ref_y[::EVERY], t_all[::EVERY])
    scale = np.max(np.abs(ref))

    def err(x):
        n = min(x.shape[1], ref.shape[1])
        return float(np.max(np.abs(x[:, :n] - ref[:, :n])) / scale)

    # interleaved repeats: old, new, old, new ...
    pairs = [(_median(old, 1), _median(new, 1)) for _ in range(reps)]
    t_old = float(np.median([p[0][0] for p in pairs]))
    t_new = float(np.median([p[1][0] for p in pairs]))
    e_old = err(pairs[-1][0][1].channels[:2, ::EVERY])
    e_new = err(pairs[-1][1][1].channels[:2, ::EVERY])
    chosen = None
    for tol in TOLS:
        y, ok = peer_run(dop853, rhs, plant, t_all, tol, tol * 1e-4)
        if ok and err(contact_disp(plant, y[::EVERY], t_all[::EVERY])) <= e_new:
            chosen = tol
            break
    print(f"seed case 1, default settings, {revs} rev ({t_all.size} samples)")
    print(f"  old complex path     {t_old * 1e3 / revs:8.4f} ms/rev  error {e_old:.2e}")
    print(f"  general engine       {t_new * 1e3 / revs:8.4f} ms/rev  error {e_new:.2e}  "
          f"new/old {t_new / t_old:5.2f} ({'no slower' if t_new <= t_old else 'SLOWER'} than "
          f"the old path)")  # fmt: skip
    if chosen is None:
        print("  DOP853: no rtol down to 1e-11 reaches the general engine's error")
        return
    tp, (y, _) = _median(lambda: peer_run(dop853, rhs, plant, t_all, chosen, chosen * 1e-4), reps)
    e = err(contact_disp(plant, y[::EVERY], t_all[::EVERY]))
    print(f"  numbalsoda DOP853    {tp * 1e3 / revs:8.4f} ms/rev  error {e:.2e}  (rtol {chosen:.0e})"
          f"  DOP853/old {tp / t_old:6.1f}  DOP853/new {tp / t_new:6.1f}")  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--revs", type=int, nargs="+", default=[20, 200])
    a = ap.parse_args()
    for revs in a.revs:
        case(revs, a.reps)


if __name__ == "__main__":
    main()
