"""The shipped touchdown drop (``scenarios/touchdown_drop.toml``): the free-spin kernel against
the full-DOF SciPy reference (``tests/spin_reference.py``, DOP853 in physical coordinates) at
equal error.

Both run every mode (the scenario's ``modes = 16`` is lifted so the two solve the same
equations). The truth is our run at rtol 1e-11; the reference runs at rtol 1e-6, and ours at
rtol 1e-4, 1e-5, ... until its orbit error (largest displacement error at the contacts over the
run, relative to the largest displacement) is no larger than the reference's. Prints both wall times (after
a warm-up that compiles the kernel) and their ratio.
Measured 2026-11-25 (2 shared cores, 0.04 s of machine time: the drop and first bounces):
reference DOP853 rtol 1e-6 20.4 s, orbit error 2.3e-7; ours rtol 1e-5 1.54 s, orbit error 5.5e-8
(rtol 1e-4: 0.97 s, 5.6e-7); ratio 13.3 at equal or smaller error of ours.
1 s of machine time (the full default run, bouncing and rolling in): reference DOP853 rtol 1e-6
208 s, orbit error 8.0e-2; ours rtol 1e-4 6.9 s, orbit error 2.2e-2 (262k steps); ratio 30.0.
Over 1 s both errors are large because the bouncing drop separates nearby trajectories (the
errors grow from 1e-7 at 0.04 s); compare the two at short durations for accuracy.
Run: ``PYTHONPATH=src python benchmarks/bench_touchdown.py [DURATION_S]`` (default 1 s of machine
time; the reference takes minutes per second of machine time on one core).
"""

from __future__ import annotations

import sys
import time
from importlib import resources
from pathlib import Path

import numpy as np

from rubrotor.engine.spin import free_problem, simulate_spin
from rubrotor.scenario import load_scenario

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from spin_reference import free_spin_reference  # noqa: E402


def _orbit(system, positions, q):
    rows = np.vstack([system.output_rows(x) for x in positions])
    return rows @ q


def main(duration: float = 1.0) -> None:
    """Print ours vs the reference at equal error on ``duration`` s of the shipped drop."""
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / "touchdown_drop.toml")
    system, kw, positions = free_problem(sc)
    kw.update(duration=duration, modes=None)
    simulate_spin(system, **{**kw, "duration": 1e-3})  # warm-up (compile)
    truth = simulate_spin(system, **{**kw, "rtol": 1e-11, "atol": 1e-14})
    ref_orbit = _orbit(system, positions, truth.basis @ truth.state[: truth.r])
    scale = np.abs(ref_orbit).max()
    ref_kw = {k: kw[k] for k in ("stations", "rings", "unbalances", "gravity", "fail_time",
                                 "failing", "initial")}  # fmt: skip
    t0 = time.perf_counter()
    q, _, _, _ = free_spin_reference(system, kw["J"], kw["speed"], truth.time, **ref_kw,
                                     rtol=1e-6, atol=1e-10 * scale)  # fmt: skip
    t_ref = time.perf_counter() - t0
    err_ref = np.abs(_orbit(system, positions, q) - ref_orbit).max() / scale
    print(f"reference DOP853: rtol 1e-06, {t_ref:.3f} s, orbit error {err_ref:.2e}")
    for rtol in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10):
        t0 = time.perf_counter()
        ours = simulate_spin(system, **{**kw, "rtol": rtol, "atol": 1e-4 * rtol * scale})
        t_ours = time.perf_counter() - t0
        q = ours.basis @ ours.state[: ours.r]
        err = np.abs(_orbit(system, positions, q) - ref_orbit).max() / scale
        print(f"ours: rtol {rtol:g}, {t_ours:.3f} s, orbit error {err:.2e}, "
              f"{ours.stats['accepted']} steps, status {ours.status}")  # fmt: skip
        if err <= err_ref:
            break
    print(f"ratio reference / ours at equal (or smaller) error of ours: {t_ref / t_ours:.1f}")


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 1.0)
