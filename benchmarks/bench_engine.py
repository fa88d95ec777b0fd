"""General engine speed: seed case 1 against the old engine, and throughput against retained modes.

Run: ``python benchmarks/bench_engine.py [--reps 3]``. Prints, never asserts.

0. Seed case 1 at default settings (adaptive, rtol 1e-6, default output spacing), 20 revolutions:
   old adaptive kernel against the new engine's default stepper for runs with rtol
   (``"collocation"``: exact free flight, order-4 contact steps chosen by the error estimate).
1. Seed case 1 (3 continuous modes, d(tau) = 0.001, 20 revolutions, every 32nd step saved) through
   the old complex-coordinate engine (rubrotor.engine.simulate) and the general engine (the same shaft
   as a LinearSystem): median wall time per call, steps per second, ratio new/old; also with the
   clearance opened (free flight only). Both agree to rounding (tests/test_engine.py).
2. A 60-element rotor with two disks, anisotropic cross-coupled bearings and rub at one disk
   against a flexible offset stator: fixed-step steps per second against the retained modes.
Numba compilation is excluded (a warm-up call first) and printed separately.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
from pathlib import Path

import rubrotor
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.parts import RubStation, Run, Stator
from rubrotor.engine.settings import Integrator
from rubrotor.engine.simulate import simulate_system
from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section
from rubrotor.rotors.forces import Contact, Unbalance
from rubrotor.rotors.shaft_system import continuous_system
from rubrotor.scenario import load_scenario

SCEN = Path(rubrotor.__file__).parent / "scenarios" / "seed_case1.toml"


def _median(fn, reps):
    walls, out = [], None
    for _ in range(reps):
        t0 = time.perf_counter()
        out = fn()
        walls.append(time.perf_counter() - t0)
    return statistics.median(walls), out


def seed_case(reps: int) -> None:
    sc = load_scenario(SCEN)
    w = sc.speed
    integ = Integrator(revolutions=20, dtau=1e-3, save_every=32)
    system = continuous_system(sc.shaft)
    print("seed case 1, 20 rev, dtau 1e-3 (125,664 steps), save every 32")
    for label, clearance in (("with rub", None), ("free flight", 1.0)):
        con = (
            sc.contact
            if clearance is None
            else dataclasses.replace(sc.contact, clearance=clearance)
        )
        run = Run(speed=w, duration=integ.total_time(w), step=1e-3 / w, save_every=32)
        stn = [RubStation(dataclasses.replace(con, radius=sc.shaft.diameter / 2))]

        def old(con=con):
            return simulate_system(sc.shaft, w, integ, sc.unbalance, con, None, sc.damping,
                                   progress=False)  # fmt: skip

        def new(run=run, stn=stn):
            return simulate_general(system, run, stn, [sc.unbalance], progress=False)

        t0 = time.perf_counter()
        new()
        old()
        print(f"  [{label}] first calls (compile or cache load): {time.perf_counter() - t0:.2f} s")
        t_old, r_old = _median(old, reps)
        t_new, r_new = _median(new, reps)
        steps = r_new.stats["steps"]
        print(f"  [{label}] old {t_old * 1e3:8.2f} ms  new {t_new * 1e3:8.2f} ms  "
              f"ratio new/old {t_new / t_old:5.2f}  new kernel {steps / r_new.stats['wall_s']:.3g} "
              f"steps/s, old kernel {steps / r_old.stats['wall_s']:.3g} steps/s")  # fmt: skip


def seed_default(reps: int) -> None:
    sc = load_scenario(SCEN)
    w = sc.speed
    integ = Integrator(revolutions=20)
    H = integ.output_spacing(w)
    system = continuous_system(sc.shaft)
    stn = [RubStation(dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2))]
    run = Run(speed=w, duration=integ.total_time(w), step=H, rtol=integ.rtol, atol=integ.atol)

    def old():
        return simulate_system(sc.shaft, w, integ, sc.unbalance, sc.contact, None, sc.damping,
                               progress=False)  # fmt: skip

    def new():
        return simulate_general(system, run, stn, [sc.unbalance], progress=False)

    old(), new()
    t_old, r_old = _median(old, reps)
    t_new, r_new = _median(new, reps)
    print("seed case 1, default settings (adaptive rtol 1e-6), 20 rev")
    print(f"  old {t_old * 1e3:.2f} ms ({r_old.stats['accepted_steps']} steps)  new "
          f"{t_new * 1e3:.2f} ms ({r_new.stats['accepted_steps']} steps)  ratio new/old "
          f"{t_new / t_old:.2f}")  # fmt: skip


def sixty_element_rotor():
    """1.5 m steel shaft (50 mm, 60 elements), disks at 0.5 and 1 m, anisotropic cross-coupled
    bearings at both ends (244 DOFs)."""
    steel = Material("steel", 211e9, 7810, poisson_ratio=0.3)
    return Rotor(
        [Section(1.5, 0.05, steel, elements=60)],
        disks=[Disk(0.5, 15.0, 0.1, 0.05), Disk(1.0, 10.0, 0.08, 0.04)],
        bearings=[
            Bearing(0.0, kyy=5e6, kzz=7e6, kyz=1e6, kzy=-8e5, cyy=500, czz=600),
            Bearing(1.5, kyy=6e6, kzz=5e6, kyz=5e5, kzy=-5e5, cyy=500, czz=500),
        ],
    )


def general_rotor():
    rotor = sixty_element_rotor()
    contact = Contact(clearance=1e-4, stiffness=5e7, damping=300, friction=0.2, position=0.5,
                      law="linear", radius=0.12)  # fmt: skip
    st = RubStation(contact, offset_y=-5e-5, stator=Stator(30, 30, 2e7, 2e7, 800, 800))
    return rotor.linear_system(), [st], [Unbalance(5e-4, 0.5), Unbalance(3e-4, 1.0, 1.0)]


def modes_throughput(reps: int) -> None:
    system, stations, unb = general_rotor()
    print(f"60-element rotor ({system.n_dof} DOFs), rub at a disk, step 2e-6 s, 0.05 s")
    for modes in (10, 20, 40, 80):
        run = Run(speed=400.0, duration=0.05, step=2e-6, save_every=10, modes=modes)

        def go(run=run):
            return simulate_general(system, run, stations, unb, gravity=(-9.81, 0.0),
                                    progress=False)  # fmt: skip

        go()
        t, r = _median(go, reps)
        s = r.stats
        print(
            f"  modes {modes:3d}: {s['steps'] / s['wall_s']:.3g} steps/s (kernel), "
            f"call {t * 1e3:.1f} ms, contact events {s['contact_events']}, status {r.status}"
        )


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=3)
    a = ap.parse_args()
    seed_default(a.reps)
    seed_case(a.reps)
    modes_throughput(a.reps)
