"""Static analysis and frequency response: rubrotor against ROSS 3.1 on ``compressor_example``.

Run: ``OPENBLAS_NUM_THREADS=1 PYTHONPATH=src /work/venvs/ross3/bin/python
benchmarks/bench_static_response_vs_ross.py [--reps 3]`` (ROSS 3.1 on Python 3.13; any venv
with ``pip install "rubrotor[ross]"``). Prints, never asserts.

Rotor: ``ross.compressor_example()`` (56 nodes, bearings and seals), imported with
``rubrotor.from_ross``, for the times; the differences are printed for it and for
``ross.rotor_example_with_damping()`` (constant coefficients). On ``compressor_example`` the
frequency responses differ because ROSS evaluates its bearings at the excitation frequency
(``transfer_matrix(speed, frequency)``) and tabulates them against ``speed``, which ``from_ross``
does not read yet (issue 26), while rubrotor's supports depend on the spin only.

* Static: ROSS's ``run_static`` (bearings rigid, seals left out, ``g = 9.8065`` m/s^2 along its
  ``-y``) against :func:`rubrotor.linear.static.static_analysis` on the same model with the
  bearings pinned, the seals removed and the same gravity (our ``-z``), medians of ``--reps``.
* Frequency response: ROSS's ``run_freq_response(speed_range=w, speed=500)`` (201 frequencies,
  fixed spin: its full transfer matrix, every input and output DOF) against
  :func:`rubrotor.linear.response.frequency_response` for one force along ``x`` at a node a
  fifth along the rotor, read at every node (what one input column needs); the column ROSS
  computes for that force is compared.
  The two do different amounts of work: ROSS's is what a ROSS user runs to get that column.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
import warnings

import numpy as np

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    import ross

from rubrotor.linear.response import frequency_response
from rubrotor.linear.static import static_analysis
from rubrotor.rotors.ross import from_ross


def _median(fn, reps: int) -> float:
    times = []
    for _ in range(reps):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def _pinned(rotor, system):
    """``system`` with ROSS's bearings (not seals) pinned and every support removed."""
    seals = {int(b.n) for b in rotor.bearing_elements if isinstance(b, ross.SealElement)}
    fixed = tuple(d for s in system.supports if s.dofs[0] // 4 not in seals for d in s.dofs)
    return dataclasses.replace(system, supports=(), fixed=fixed)


def _compare(rotor, reps: int, label: str) -> None:
    system = from_ross(rotor)
    x, dof = system.basis.nodes, int(rotor.number_dof)
    pinned = _pinned(rotor, system)
    ref = rotor.run_static()
    mine = static_analysis(pinned, gravity=(0.0, -9.8065))
    defl = np.asarray(ref.deformation, float).ravel()
    err = np.abs(mine.deflection[:, 1] - defl).max() / np.abs(defl).max()
    t_ross = _median(rotor.run_static, reps)
    t_ours = _median(lambda: static_analysis(pinned, gravity=(0.0, -9.8065)), 5 * reps)
    print(f"{label} ({len(x)} nodes) static: ROSS {t_ross:.4f} s, rubrotor {t_ours:.5f} s, "
          f"ratio {t_ross / t_ours:.0f}x; deflection difference {err:.1e} of the largest")  # fmt: skip
    w = np.linspace(0.0, 2000.0, 201)
    k = len(x) // 5
    frequency_response(system, w[:2], x[k], list(x), speed=500.0)  # compile
    t = time.perf_counter()
    h = np.asarray(rotor.run_freq_response(speed_range=w, speed=500.0).freq_resp)
    t_ross = time.perf_counter() - t
    t_ours = _median(lambda: frequency_response(system, w, x[k], list(x), speed=500.0), reps)
    got = frequency_response(system, w, x[k], list(x), speed=500.0).complex_response[:, :, 0]
    col = h[dof * np.arange(len(x)), dof * k].T
    err = np.abs(got - col).max() / np.abs(col).max()
    print(f"{label} frequency response (201 frequencies): ROSS {t_ross:.3f} s, rubrotor "
          f"{t_ours:.4f} s, ratio {t_ross / t_ours:.0f}x; difference {err:.1e} of the largest")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--reps", type=int, default=3)
    reps = parser.parse_args().reps
    warnings.simplefilter("ignore")
    _compare(ross.rotor_example_with_damping(), reps, "rotor_example_with_damping")
    _compare(ross.compressor_example(), reps, "compressor_example")


if __name__ == "__main__":
    main()
