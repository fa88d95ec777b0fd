"""Rub on a ROSS example rotor: the general engine against ROSS ``run_rubbing``, in one process.

Run with a Python that has ROSS and rubrotor's dependencies, from the repository root::

    PYTHONPATH=src /work/venvs/ross23/bin/python benchmarks/bench_engine_vs_ross.py [--reps 3]

Prints, never asserts.

Rotor: ``ross.rotor_example_with_damping()`` (33 Timoshenko elements, 34 nodes, two disks, two
anisotropic bearings; the rotor of ROSS's own ``run_rubbing`` example), read into rubrotor with
:func:`rubrotor.interop.from_ross` (136 lateral DOFs). Rub at node 12 (disk 1), clearance
79.5 um, contact stiffness 1.1e6 N/m, unbalance 5e-4 kg m at node 12 with phase -90 deg,
1200 rpm, from rest, output every 1e-4 s (ROSS's time step).

* Accuracy, on the SAME contact: ROSS's law with zero contact damping and zero friction is
  ``F = -k (|r| - g) r / |r|``, our linear law exactly (ROSS damps the full velocity vector and
  applies its friction per component, not along the tangent, so with either on the two models
  differ). Error: max over the run of the contact node's ``(v, w)`` deviation from the full-DOF
  reference, relative to its largest amplitude. Reference (``--reference``): ``scipy`` (default),
  solve_ivp DOP853 rtol 1e-10, atol 1e-14 on all 136 DOFs (tests/engine_reference.py; this
  rotor's Rayleigh-damped shaft has overdamped modes near -7e6 1/s, so DOP853 needs steps below
  1e-6 s: 529 s for 0.1 s on this loaded machine); ``engine``: our engine with every mode kept
  (no reduction) and adaptive steps at rtol 1e-10, atol 1e-15, seconds (its agreement with
  DOP853 full-DOF runs is tested in tests/test_engine.py and tests/test_engine_multi.py).
* Time, on ROSS's contact as it is (damping 40 N s/m, friction 0.3; ours: radial dashpot 40 N s/m,
  Coulomb friction 0.3 along the tangent at the shaft radius): seconds per revolution, medians.
  ROSS variants: its default (Newmark average acceleration on all DOFs, contact force taken from
  the previous step) and its pseudo-modal reduction to 12 modes (its docstring example); when the
  installed ROSS has ``newmark_type`` (ROSS 3.x), also ``newmark_type="robust"``. Ours: fixed
  step 1e-4 s with all modes and with 12 modes, and adaptive steps (rtol 1e-6).

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

from rubrotor.engine.driver import simulate_general  # noqa: E402
from rubrotor.engine.model import RubStation, Run  # noqa: E402
from rubrotor.forces import Contact, Unbalance  # noqa: E402
from rubrotor.interop import from_ross  # noqa: E402

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
    """The general engine: (wall s, kernel wall s, t, v and w at the contact (m), stats)."""
    con = Contact(clearance=CLEARANCE, stiffness=STIFFNESS, damping=damping, friction=friction,
                  position=position, law="linear", radius=radius)  # fmt: skip
    run = Run(speed=SPEED, duration=duration, step=DT, initial="rest", **kw)
    unb = [Unbalance(UNBALANCE, position, PHASE)]
    t0 = time.perf_counter()
    res = simulate_general(system, run, [RubStation(con)], unb, progress=False)
    wall = time.perf_counter() - t0
    assert res.status == "complete", res.message
    return wall, res.stats["wall_s"], res.time, res.channels[:2], res.stats


def _median(fn, reps):
    out = [fn() for _ in range(reps)]
    return statistics.median(o[0] for o in out), out[-1]


def _error(x, ref):
    n = min(x.shape[1], ref.shape[1])
    return float(np.max(np.abs(x[:, :n] - ref[:, :n])) / np.max(np.abs(ref[:, :n])))


def ross_variants(ross):
    """(label, kwargs) of the ROSS integrations to run."""
    out = [("ROSS default (Newmark, all DOFs, lagged contact)", {}),
           ("ROSS pseudo-modal 12 modes", {"model_reduction": {"num_modes": 12}})]  # fmt: skip
    if "newmark_type" in inspect.getsource(ross.utils):
        out.append(("ROSS newmark_type='robust'", {"newmark_type": "robust"}))
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--duration", type=float, default=0.1, help="simulated time (s)")
    ap.add_argument("--ross-reps", type=int, default=1, help="repetitions of ROSS's full run")
    ap.add_argument("--reference", choices=("scipy", "engine"), default="scipy")
    a = ap.parse_args(argv)
    ross = _ross()
    rotor = ross.rotor_example_with_damping()
    system = from_ross(rotor)
    pos = float(rotor.nodes_pos[NODE])
    radius = float(rotor.shaft_elements[NODE].odl / 2)
    revs = a.duration * SPEED / (2 * np.pi)
    print(f"ROSS {ross.__version__}: rotor_example_with_damping, {system.n_dof} lateral DOFs, "
          f"rub at node {NODE} ({pos} m), {SPEED:.2f} rad/s, {a.duration} s = {revs:.2f} rev, "
          f"dt {DT} s")  # fmt: skip
    t0 = time.perf_counter()
    ours(system, pos, radius, 0.01, 40.0, 0.3)  # warm-up: numba compilation
    ours(system, pos, radius, 0.01, 40.0, 0.3, rtol=1e-6)
    print(f"numba warm-up (compile or cache load): {time.perf_counter() - t0:.1f} s")

    # accuracy on the same contact (no contact damping, no friction)
    t0 = time.perf_counter()
    if a.reference == "scipy":
        con = Contact(clearance=CLEARANCE, stiffness=STIFFNESS, position=pos, law="linear",
                      radius=radius)  # fmt: skip
        run = Run(speed=SPEED, duration=a.duration, step=DT, initial="rest")
        _, ref, _, _ = reference_run(system, run, [RubStation(con)],
                                     [Unbalance(UNBALANCE, pos, PHASE)])  # fmt: skip
        ref = ref[0]
        label = "SciPy DOP853 rtol 1e-10, atol 1e-14, all 136 DOFs"
    else:
        r = ours(system, pos, radius, a.duration, 0.0, 0.0, rtol=1e-10, atol=1e-15)
        ref = r[3]
        label = f"our engine, all modes, adaptive rtol 1e-10 ({r[4]['accepted_steps']} steps)"
    print(f"reference {label}: {time.perf_counter() - t0:.1f} s; peak |r| "
          f"{np.max(np.hypot(*ref)) * 1e6:.1f} um (clearance {CLEARANCE * 1e6} um)")  # fmt: skip
    ours_cases = [("ours fixed 1e-4 s, all modes", {}),
                  ("ours fixed 1e-4 s, 12 modes", {"modes": 12}),
                  ("ours adaptive rtol 1e-6, all modes", {"rtol": 1e-6})]  # fmt: skip
    rows = []
    for label, kw in ours_cases:
        x = ours(system, pos, radius, a.duration, 0.0, 0.0, **kw)
        err = _error(x[3], ref)
        w, o = _median(lambda kw=kw: ours(system, pos, radius, a.duration, 40.0, 0.3, **kw), a.reps)
        rows.append((label, w / revs, o[1] / revs, err, o[4]["contact_events"]))
    for label, kw in ross_variants(ross):
        w0, t, xy = ross_run(rotor, a.duration, 0.0, 0.0, **kw)
        err = _error(xy, ref)
        reps = a.ross_reps if not kw else a.reps
        w, _ = _median(lambda kw=kw: ross_run(rotor, a.duration, 40.0, 0.3, **kw), reps)
        rows.append((label, w / revs, float("nan"), err, None))
    ross_default = next(r[1] for r in rows if r[0].startswith("ROSS default"))
    print(f"\n{'variant':<50}{'s/rev':>10}{'kernel s/rev':>13}{'rel error':>10}"
          f"{'ROSS default/this':>19}{'(kernel)':>10}")  # fmt: skip
    for label, spr, kern, err, _ in rows:
        kr = f"{ross_default / kern:10.0f}" if np.isfinite(kern) else f"{'':10}"
        print(f"{label:<50}{spr:10.3e}{kern:13.3e}{err:10.2e}{ross_default / spr:19.1f}{kr}")
    print("\ns/rev: whole call (ours: modal reduction + time loop, so short runs are dominated by")
    print("the reduction); kernel: our compiled time loop only. Times on ROSS's contact as it is")
    print("(damping 40, friction 0.3); errors on the common contact (no damping, no friction)")
    print(f"against the reference ({a.reference}).")


if __name__ == "__main__":
    main()
