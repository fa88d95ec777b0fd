"""Run-up through the first critical speed: how to re-diagonalise as the speed changes.

Run from the repository root: ``python benchmarks/bench_engine_runup.py [--reps 3]``.
Prints, never asserts; the table is copied into docs/guide/simulation.md.

Alternatives (``Run.runup_reduction``), both with the speed frozen per segment at its mid-speed:

* ``full``: re-diagonalise the full model (a ``2 n``-sized eigenproblem per segment; ARPACK on
  a large model with few modes kept).
* ``ritz``: project ``M``, ``C + Omega G`` and the supports at each segment's speed on ONE basis
  (kept modes, right and left, at the start, middle and end speeds plus the static responses to
  unit forces at the contacts and unbalance planes) and diagonalise that small system.

1. Accuracy against the full-DOF SciPy reference (DOP853, rtol 1e-9, atol 1e-13, the gyroscopic
   matrix at the current speed in every evaluation): the run-up rotor of tests/test_engine.py
   (1 m shaft, 6 elements, 10 kg disk, anisotropic bearings; no contact), 0.6 to 1.4 times the
   steady peak speed in 0.3 s, 200 segments, 4 retained modes. Error: max over the run of the
   midspan ``(v, w)`` deviation relative to the largest amplitude.
2. Cost on a large model: the 60-element rotor of benchmarks/bench_engine.py (244 DOFs, gravity,
   two unbalances), without contact and with rub at a disk against a flexible offset stator,
   300 to 500 rad/s in 0.2 s, 8 modes, 100 segments: wall time of the whole call (median of
   ``--reps``) and the deviation of ``ritz`` from ``full`` relative to the orbit (the SciPy
   reference of this stiff 244-DOF model takes too long).
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))

from bench_engine import general_rotor  # noqa: E402
from engine_reference import reference_run  # noqa: E402

from rubrotor.engine.driver import simulate_general  # noqa: E402
from rubrotor.engine.parts import Run  # noqa: E402
from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section  # noqa: E402
from rubrotor.rotors.forces import Unbalance  # noqa: E402


def _median_call(fn, reps):
    fn()  # warm-up (compilation or cache load)
    out = []
    for _ in range(reps):
        t0 = time.perf_counter()
        r = fn()
        out.append(time.perf_counter() - t0)
    return statistics.median(out), r


def small_rotor():
    steel = Material("steel", 211e9, 7810, poisson_ratio=0.3)
    rotor = Rotor(
        [Section(1.0, 0.04, steel, elements=6)],
        disks=[Disk(0.5, 10.0, 0.05, 0.025)],
        bearings=[
            Bearing(0.0, kyy=1e6, kzz=1.2e6, cyy=200, czz=200),
            Bearing(1.0, kyy=1e6, kzz=1.2e6, cyy=200, czz=200),
        ],
    )
    return rotor.linear_system(), [Unbalance(1e-4, 0.5, 0.0)]


def _peak_speed(system, unb, speeds):
    amp = []
    for w in speeds:
        sm = system.matrices(w)
        b = unb[0].magnitude * w**2 * (system.force_map(0.5) @ np.array([1, -1j]))
        q = np.linalg.solve(sm.K - w**2 * sm.M + 1j * w * sm.damping, b)
        amp.append(np.max(np.abs(system.output_rows(0.5) @ q)))
    return speeds[int(np.argmax(amp))]


def accuracy(reps: int) -> None:
    system, unb = small_rotor()
    wc = _peak_speed(system, unb, np.linspace(100, 600, 501))
    base = Run(speed=0.6 * wc, speed_end=1.4 * wc, duration=0.3, step=5e-5, save_every=2,
               initial="static", probes=(0.5,), speed_step=0.8 * wc / 200)  # fmt: skip
    t0 = time.perf_counter()
    _, rot, _, _ = reference_run(system, base, [], unb, rtol=1e-9, atol=1e-13)
    print(f"1. small rotor ({system.n_dof} DOFs), run-up {base.speed:.0f} -> {base.speed_end:.0f}"
          f" rad/s in 0.3 s, 200 segments; SciPy reference {time.perf_counter() - t0:.0f} s")  # fmt: skip
    print(f"{'modes':>6}{'reduction':>11}{'basis':>7}{'rel error':>11}{'call ms':>10}")
    for modes in (2, 4, None):
        for red in ("full", "ritz") if modes else ("full",):
            run = dataclasses.replace(base, modes=modes, runup_reduction=red)
            wall, res = _median_call(
                lambda run=run: simulate_general(system, run, unbalances=unb, progress=False), reps
            )
            err = np.max(np.abs(rot[0] - res.channels[:2])) / np.max(np.abs(rot[0]))
            print(f"{modes or 'all':>6}{res.stats['runup_reduction']:>11}"
                  f"{res.stats['ritz_basis_size']:>7}{err:11.2e}{wall * 1e3:10.1f}")  # fmt: skip


def cost(reps: int) -> None:
    system, stations, unb = general_rotor()
    base = Run(speed=300.0, speed_end=500.0, duration=0.2, step=2e-5, save_every=5, modes=8,
               initial="static", speed_step=2.0)  # fmt: skip
    print(f"\n2. 60-element rotor ({system.n_dof} DOFs), run-up 300 -> 500 rad/s in 0.2 s, "
          f"100 segments, 8 modes, gravity")  # fmt: skip
    print(f"{'case':>12}{'reduction':>10}{'basis':>7}{'call s':>9}{'events':>8}"
          f"{'deviation from full':>21}")  # fmt: skip
    for case, st in (("no contact", []), ("rub at disk", stations)):
        ref = None
        for red in ("full", "ritz"):
            run = dataclasses.replace(base, runup_reduction=red, probes=() if st else (0.5,))

            def go(run=run, st=st):
                return simulate_general(system, run, st, unb, gravity=(-9.81, 0.0),
                                        progress=False)  # fmt: skip

            wall, res = _median_call(go, reps)
            x = res.channels[:2]
            ref = x if ref is None else ref
            dev = np.max(np.abs(x - ref)) / np.max(np.abs(ref))
            print(f"{case:>12}{red:>10}{res.stats['ritz_basis_size']:>7}{wall:9.2f}"
                  f"{res.stats['contact_events']:8d}{dev:21.2e}")  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=3)
    a = ap.parse_args()
    accuracy(a.reps)
    cost(a.reps)


if __name__ == "__main__":
    main()
