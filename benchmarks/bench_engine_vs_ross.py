"""Rub on a ROSS example rotor: the general engine against ROSS ``run_rubbing``, in one process.

Run with a Python that has ROSS and rubrotor's dependencies, from the repository root::

    PYTHONPATH=src /work/venvs/ross3/bin/python benchmarks/bench_engine_vs_ross.py [--reps 3]

Prints, never asserts.

Rotor: ``ross.rotor_example_with_damping()`` (33 Timoshenko elements, 34 nodes, two disks, two
anisotropic bearings; the rotor of ROSS's own ``run_rubbing`` example), read into rubrotor with
:func:`rubrotor.rotors.ross.from_ross` (136 lateral DOFs). Rub at node 12 (disk 1), clearance
79.5 um, contact stiffness 1.1e6 N/m, unbalance 5e-4 kg m at node 12 with phase -90 deg,
1200 rpm, from rest, output every 1e-4 s (ROSS's time step).

* Accuracy, on the SAME contact: ROSS's law with zero contact damping and zero friction is
  ``F = -k (|r| - g) r / |r|``, our linear law exactly (ROSS damps the full velocity vector and
  applies its friction per component, not along the tangent, so with either on the two models
  differ). Error: max over the run of the contact node's ``(v, w)`` deviation from the full-DOF
  reference, relative to its largest amplitude. Reference (``--reference``): ``scipy`` (default),
  solve_ivp DOP853 rtol 1e-10, atol 1e-14 on all 136 DOFs (tests/engine_reference.py; this
  rotor's Rayleigh-damped shaft has overdamped modes near -7e6 1/s, so DOP853 needs steps below
  1e-6 s: 312-529 s for 0.1 s on this loaded machine); ``engine``: our engine with every mode kept
  (no reduction) and adaptive steps at rtol 1e-10, atol 1e-15, seconds (its agreement with
  DOP853 full-DOF runs is tested in tests/test_engine.py and tests/test_engine_multi.py).
* Time, on ROSS's contact as it is (damping 40 N s/m, friction 0.3; ours: radial dashpot 40 N s/m,
  Coulomb friction 0.3 along the tangent at the shaft radius): seconds per revolution, medians.
  ROSS variants: its default (``newmark_type="simple"``: Newmark average acceleration on all
  DOFs, the contact force evaluated from the previous step's state) and its pseudo-modal
  reduction to 12 modes (its docstring example); when the installed ROSS has ``newmark_type``
  (ROSS 3.x), also ``newmark_type="robust"`` (the contact force re-evaluated in its Newton
  iterations, the implicit variant). Ours: fixed step 1e-4 s with all modes and with 12 modes,
  adaptive steps (rtol 1e-6) with all modes and with 12 modes.
* Per revolution, three ways: the whole call of a short run (``--duration``, 2 revolutions)
  and of a long one (``--long``, 40 revolutions) divided by its revolutions, and the marginal
  cost (the difference of the two calls per added revolution; ours: each call minus its own
  setup, so that the setup's jitter on this shared machine cancels too). Our setup
  (``build_plant``: modal reduction, rows, particular solutions; median) is printed separately. The
  last lines say which of these ratios meets the 1000x goal against each implicit ROSS variant.

BLAS threads are pinned to one (set before NumPy loads): on this loaded 2-core machine OpenBLAS
with its default threads took 15 s for the 272x272 eigen-decomposition that takes 0.1 s on one.
"""

from __future__ import annotations

import os

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import inspect  # noqa: E402
import io  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from rubrotor.engine.driver import build_plant, simulate_general  # noqa: E402
from rubrotor.engine.parts import RubStation, Run  # noqa: E402
from rubrotor.rotors.forces import Contact, Unbalance  # noqa: E402
from rubrotor.rotors.ross import from_ross  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from engine_reference import reference_run  # noqa: E402

SPEED = 1200 * np.pi / 30  # rad/s
DT = 1e-4  # s
NODE = 12
CLEARANCE, STIFFNESS = 7.95e-5, 1.1e6
UNBALANCE, PHASE = 5e-4, -np.pi / 2


def _ross():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        import ross

    return ross


def ross_run(rotor, duration, damping, friction, **kw):
    """ROSS ``run_rubbing``: (wall s, t, x and y of the contact node (m))."""
    t = np.arange(0, duration + DT / 2, DT)
    t0 = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = rotor.run_rubbing(n=NODE, distance=CLEARANCE, contact_stiffness=STIFFNESS,
                                contact_damping=damping, friction_coeff=friction, node=[NODE],
                                unbalance_magnitude=[UNBALANCE], unbalance_phase=[PHASE],
                                speed=SPEED, t=t, **kw)  # fmt: skip
    wall = time.perf_counter() - t0
    nd = rotor.number_dof
    return wall, t, res.yout[:, nd * NODE : nd * NODE + 2].T


def ours(system, position, radius, duration, damping, friction, **kw):
    """The general engine: (wall s, kernel wall s, t, v and w at the contact (m), stats,
    setup s). Setup (reduction, rows, coefficients) is timed by building the plant first."""
    con = Contact(clearance=CLEARANCE, stiffness=STIFFNESS, damping=damping, friction=friction,
                  position=position, law="linear", radius=radius)  # fmt: skip
    run = Run(speed=SPEED, duration=duration, step=DT, initial="rest", **kw)
    unb = [Unbalance(UNBALANCE, position, PHASE)]
    t0 = time.perf_counter()
    plant = build_plant(system, run, [RubStation(con)], unb)
    setup = time.perf_counter() - t0
    res = simulate_general(system, run, [RubStation(con)], unb, progress=False, plant=plant)
    wall = time.perf_counter() - t0
    assert res.status == "complete", res.message
    return wall, res.stats["wall_s"], res.time, res.channels[:2], res.stats, setup


def _error(x, ref):
    n = min(x.shape[1], ref.shape[1])
    return float(np.max(np.abs(x[:, :n] - ref[:, :n])) / np.max(np.abs(ref[:, :n])))


def ross_variants(ross):
    """(label, kwargs) of the ROSS integrations to run."""
    out = [("ROSS default (Newmark, all DOFs)", {}),
           ("ROSS pseudo-modal 12 modes", {"model_reduction": {"num_modes": 12}})]  # fmt: skip
    if "newmark_type" in inspect.getsource(ross.utils):
        out.append(("ROSS newmark_type='robust'", {"newmark_type": "robust"}))
    return out


def _reference(a, system, pos, radius):
    t0 = time.perf_counter()
    if a.reference == "scipy":
        con = Contact(clearance=CLEARANCE, stiffness=STIFFNESS, position=pos, law="linear",
                      radius=radius)  # fmt: skip
        run = Run(speed=SPEED, duration=a.duration, step=DT, initial="rest")
        _, ref, _, _ = reference_run(system, run, [RubStation(con)],
                                     [Unbalance(UNBALANCE, pos, PHASE)])  # fmt: skip
        ref = ref[0]
        label = f"SciPy DOP853 rtol 1e-10, atol 1e-14, all {system.n_dof} DOFs"
    else:
        r = ours(system, pos, radius, a.duration, 0.0, 0.0, rtol=1e-10, atol=1e-15)
        ref = r[3]
        label = f"our engine, all modes, adaptive rtol 1e-10 ({r[4]['accepted_steps']} steps)"
    print(f"reference {label}: {time.perf_counter() - t0:.1f} s; peak |r| "
          f"{np.max(np.hypot(*ref)) * 1e6:.1f} um (clearance {CLEARANCE * 1e6} um)")  # fmt: skip
    return ref


def _measure(a, rotor, system, pos, radius, ref, ross):
    """Rows (label, whole s/rev short, whole s/rev long, marginal s/rev, setup s, error).

    Repeats are interleaved: every repetition runs every variant at both lengths, so that the
    load of this shared machine falls on ours and ROSS's alike; medians over repetitions."""
    revs = [d * SPEED / (2 * np.pi) for d in (a.duration, a.long)]
    cases = [("ours fixed 1e-4 s, all modes", {}), ("ours fixed 1e-4 s, 12 modes", {"modes": 12}),
             ("ours adaptive rtol 1e-6, all modes", {"rtol": 1e-6}),
             ("ours adaptive rtol 1e-6, 12 modes", {"rtol": 1e-6, "modes": 12})]  # fmt: skip
    variants = [(lb, kw, True) for lb, kw in cases]
    variants += [(lb, kw, False) for lb, kw in ross_variants(ross)]
    errs, runs = {}, {lb: ([], [], [], []) for lb, _, _ in variants}  # walls, loops per length
    for lb, kw, mine in variants:
        x = ours(system, pos, radius, a.duration, 0.0, 0.0, **kw)[3] if mine else (
            ross_run(rotor, a.duration, 0.0, 0.0, **kw)[2])  # fmt: skip
        errs[lb] = _error(x, ref)
    setups = {lb: [] for lb, _, _ in variants}
    for _ in range(a.reps):
        for lb, kw, mine in variants:
            for j, d in enumerate((a.duration, a.long)):
                if mine:
                    o = ours(system, pos, radius, d, 40.0, 0.3, **kw)
                    runs[lb][j].append(o[0])
                    runs[lb][2 + j].append(o[0] - o[5])  # the call minus its own setup
                    setups[lb].append(o[5])
                else:
                    w = ross_run(rotor, d, 40.0, 0.3, **kw)[0]
                    runs[lb][j].append(w)
                    runs[lb][2 + j].append(w)
    rows = []
    med = statistics.median
    for lb, _, mine in variants:
        w0, w1, l0, l1 = (med(v) for v in runs[lb])
        marg = (l1 - l0) / (revs[1] - revs[0])
        st = med(setups[lb]) if mine else float("nan")
        rows.append((lb, w0 / revs[0], w1 / revs[1], marg, st, errs[lb]))
    return rows, revs


def _verdict(rows, revs) -> None:
    """Which ratio meets the 1000x goal, against each implicit ROSS variant."""
    ours12 = next(r for r in rows if r[0] == "ours fixed 1e-4 s, 12 modes")
    print(f"\nGoal: time per revolution at least 1000x below ROSS run_rubbing. Ours = {ours12[0]}:")
    for r in rows:
        if not r[0].startswith("ROSS") or "pseudo" in r[0]:
            continue
        short, long_, marg = r[1] / ours12[1], r[2] / ours12[2], r[2] / ours12[3]
        need = ours12[4] / max(r[2] / 1000 - ours12[3], 1e-300) if r[2] / 1000 > ours12[3] else None
        print(f"  vs {r[0]}: whole call {short:.0f}x at {revs[0]:.0f} rev, {long_:.0f}x at "
              f"{revs[1]:.0f} rev; marginal (time loop per added revolution) {marg:.0f}x -> "
              f"{'meets' if marg >= 1000 else 'does NOT meet'} the goal on the marginal cost, "
              f"{'meets' if long_ >= 1000 else 'does NOT meet'} it on the whole call at "
              f"{revs[1]:.0f} rev"
              + (f"; extrapolated (setup {ours12[4] * 1e3:.0f} ms + marginal per rev), the "
                 f"whole call would reach 1000x from about {need:.0f} rev" if need else ""))  # fmt: skip


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=3, help="interleaved repetitions (medians)")
    ap.add_argument("--duration", type=float, default=0.1, help="simulated time (s), short run")
    ap.add_argument("--long", type=float, default=2.0, help="simulated time (s), long run")
    ap.add_argument("--reference", choices=("scipy", "engine"), default="scipy")
    a = ap.parse_args(argv)
    ross = _ross()
    rotor = ross.rotor_example_with_damping()
    system = from_ross(rotor)
    pos = float(rotor.nodes_pos[NODE])
    radius = float(rotor.shaft_elements[NODE].odl / 2)
    print(f"ROSS {ross.__version__}: rotor_example_with_damping, {system.n_dof} lateral DOFs, "
          f"rub at node {NODE} ({pos} m), {SPEED:.2f} rad/s, dt {DT} s; runs of {a.duration} s "
          f"and {a.long} s")  # fmt: skip
    t0 = time.perf_counter()
    ours(system, pos, radius, 0.01, 40.0, 0.3)  # warm-up: numba compilation
    ours(system, pos, radius, 0.01, 40.0, 0.3, rtol=1e-6)
    print(f"numba warm-up (compile or cache load): {time.perf_counter() - t0:.1f} s")
    ref = _reference(a, system, pos, radius)
    rows, revs = _measure(a, rotor, system, pos, radius, ref, ross)
    rd = next(r for r in rows if r[0].startswith("ROSS default"))
    print(f"\n{'variant':<38}{'s/rev':>10}{'s/rev':>10}{'marginal':>10}{'setup':>9}"
          f"{'rel':>9}{'ROSS default / this':>29}")  # fmt: skip
    print(f"{'':<38}{f'{revs[0]:.0f} rev':>10}{f'{revs[1]:.0f} rev':>10}{'s/rev':>10}{'s':>9}"
          f"{'error':>9}{'short':>9}{'long':>10}{'marginal':>10}")  # fmt: skip
    for label, s1, s2, mg, st, err in rows:
        print(f"{label:<38}{s1:10.2e}{s2:10.2e}{mg:10.2e}{st:9.4f}{err:9.1e}"
              f"{rd[1] / s1:9.0f}{rd[2] / s2:10.0f}{rd[2] / mg:10.0f}")  # fmt: skip
    print("\ns/rev: whole call (ours: setup = modal reduction, rows and coefficients, plus the")
    print("time loop) divided by the revolutions of the run; marginal: difference of the two run")
    print("lengths per added revolution (setup excluded); setup: our build_plant alone. Times on")
    print("ROSS's contact as it is (damping 40, friction 0.3); errors on the common contact (no")
    print(f"damping, no friction, {a.duration} s) against the reference ({a.reference}).")
    _verdict(rows, revs)


if __name__ == "__main__":
    main()
