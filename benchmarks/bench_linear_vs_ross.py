"""rubrotor linear analyses vs ROSS on ROSS's own rotors, imported with ``rubrotor.from_ross``.

Run: ``PYTHONPATH=src /work/venvs/ross23/bin/python benchmarks/bench_linear_vs_ross.py [example] [60]`` (a venv
with ``pip install "rubrotor[ross]"``). Ours and ROSS in one process, medians of 3 repetitions.

Rotors: ``ross.rotor_example()`` and a 60-element hollow steel rotor with two disks and
anisotropic, cross-coupled, damped bearings built in ROSS. Ours is the same model (``from_ross``),
so the frequency differences measure the import and the eigen-solvers, not the elements.
ROSS runs single-threaded (``OPENBLAS_NUM_THREADS=1``); our compiled sweeps share the speeds
among numba threads, so they are timed on one thread and on all cores.
Our side is timed twice: plain SciPy on ``LinearSystem.matrices(speed)`` (dense ``eigvals`` of
the first-order matrix; one complex solve per speed) and rubrotor's own ``damped_modes``,
``campbell_data`` and ``unbalance_response`` (which also classify whirl and damping).
"""

from __future__ import annotations

import contextlib
import io
import statistics
import time
import warnings
from sys import argv

import numba
import numpy as np
import scipy.linalg as sl

with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
    warnings.simplefilter("ignore")
    import ross

from rubrotor.interop import from_ross
from rubrotor.linear_analysis import campbell_data, damped_modes, unbalance_response

warnings.simplefilter("ignore")


def thread_counts():
    """1 thread (like ROSS, whose BLAS is pinned to one thread here), then all cores."""
    return sorted({1, numba.config.NUMBA_NUM_THREADS})


def median_time(fn, reps=3):
    out, times = None, []
    for _ in range(reps):
        t0 = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()):
            out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def rotor_60():
    """60 hollow steel elements (1.2 m), disks at nodes 20 and 40, anisotropic bearings."""
    steel = ross.Material(name="steel_b60", rho=7810, E=211e9, Poisson=0.3)
    shaft = [ross.ShaftElement(L=0.02, idl=0.01, odl=0.06, material=steel) for _ in range(60)]
    disks = [
        ross.DiskElement(n=20, m=10.0, Id=0.05, Ip=0.1),
        ross.DiskElement(n=40, m=7, Id=0.04, Ip=0.07),
    ]
    brg = [
        ross.BearingElement(n=n, kxx=3e7, kyy=6e7, kxy=5e6, kyx=-5e6, cxx=2e3, cyy=3e3)
        for n in (2, 58)
    ]
    return ross.Rotor(shaft, disks, brg)


def our_frequencies(sys, speed, n):
    lam = sl.eigvals(sys.matrices(speed).first_order()[0])
    wd = np.sort(lam.imag[lam.imag > 1e-3])
    return wd[:n]


def our_campbell(sys, speeds, n=6):
    out = []
    for w in speeds:
        lam = sl.eigvals(sys.matrices(w).first_order()[0])
        lam = lam[lam.imag > 1e-3]
        lam = lam[np.argsort(lam.imag)][:n]
        out.append((lam.imag, -lam.real / np.abs(lam)))
    return out


def our_unbalance(sys, node_pos, speeds):
    rows = sys.output_rows(node_pos)
    b = sys.force_map(node_pos) @ np.array([1.0, -1j])  # rotating unit force (y, z)
    amp = np.empty((len(speeds), 2), complex)
    for i, w in enumerate(speeds):
        m = sys.matrices(w)
        z = m.K - w**2 * m.M + 1j * w * m.damping
        amp[i] = rows @ np.linalg.solve(z, b * w**2)
    return amp


def run_case(name, r):
    """Print the frequency difference and the three timings for one ROSS rotor."""
    sys = from_ross(r)
    print(f"\n== {name}: {len(r.nodes_pos)} nodes, {sys.n_dof} lateral DOFs (ROSS {r.ndof})")
    speed = 500.0
    t_ross, modal = median_time(
        lambda r=r: (
            r.run_modal.cache_clear() if hasattr(r.run_modal, "cache_clear") else None,
            r.run_modal(speed, num_modes=24),
        )[1]
    )
    t_ours, ours = median_time(lambda sys=sys: our_frequencies(sys, speed, 8))
    lam = np.asarray(modal.evalues)
    wd = np.sort(lam.imag[lam.imag > 1e-3])
    diff = max(np.min(np.abs(wd - f)) / f for f in ours)
    print(f"modal @ {speed} rad/s: max rel. freq. diff (8 modes) {diff:.2e}")
    print(
        f"  one modal analysis: ROSS {t_ross * 1e3:.1f} ms, ours {t_ours * 1e3:.2f} ms, ratio {t_ross / t_ours:.1f}x"
    )
    t_dm, dm = median_time(lambda sys=sys: damped_modes(sys, speed, n=12), reps=7)
    f_dm = np.array([m.frequency_hz for m in dm.modes]) * 2 * np.pi
    diff_dm = max(np.min(np.abs(wd - f)) / f for f in f_dm)
    print(
        f"  damped_modes (n=12, as ROSS's 24 eigenvalues): {t_dm * 1e3:.2f} ms, "
        f"ratio {t_ross / t_dm:.1f}x (goal 30x); freq. diff {diff_dm:.2e}"
    )
    speeds = np.linspace(0, 1000, 200)
    if r.ndof > 100:  # ROSS needs ~13 s per speed here: time 4 speeds once, scale to 200
        t4, _ = median_time(lambda r=r: r.run_campbell(speeds[::50], frequencies=6), reps=1)
        t_rc = t4 * 50
        print(f"  ROSS Campbell EXTRAPOLATED: 4 speeds took {t4:.1f} s, x50")
    else:
        t_rc, _ = median_time(lambda r=r: r.run_campbell(speeds, frequencies=6))
    t_oc, _ = median_time(lambda sys=sys: our_campbell(sys, speeds))
    print(f"  Campbell 200 speeds: ROSS {t_rc:.2f} s, ours {t_oc:.3f} s, ratio {t_rc / t_oc:.1f}x")
    campbell_data(sys, speeds, n=6)  # compile / load the kernels outside the timing
    for threads in thread_counts():
        numba.set_num_threads(threads)
        t_cd, _ = median_time(lambda sys=sys: campbell_data(sys, speeds, n=6), reps=5)
        print(
            f"  campbell_data (n=6), {threads} numba thread(s): {t_cd:.3f} s, "
            f"ratio {t_rc / t_cd:.1f}x (goal 100x)"
        )
    n = r.disk_elements[0].n
    sp = np.linspace(1, 1000, 500)
    t_ru, _ = median_time(lambda r=r: r.run_unbalance_response(n, 1e-3, 0.0, sp))
    t_ou, _ = median_time(lambda sys=sys: our_unbalance(sys, float(r.nodes_pos[n]), sp))
    print(f"  unbalance 500 speeds: ROSS {t_ru:.2f} s, ours {t_ou:.3f} s, ratio {t_ru / t_ou:.1f}x")
    x = float(r.nodes_pos[n])
    unbalance_response(sys, sp, [(x, 1e-3, 0.0)], [x])
    for threads in thread_counts():
        numba.set_num_threads(threads)
        t_ur, _ = median_time(lambda: unbalance_response(sys, sp, [(x, 1e-3, 0.0)], [x]), reps=7)
        print(
            f"  unbalance_response, {threads} numba thread(s): {t_ur * 1e3:.2f} ms, "
            f"ratio {t_ru / t_ur:.1f}x (goal 100x)"
        )


def main():
    print(f"ROSS {ross.__version__}; numpy {np.__version__}")
    print("ours: plain scipy.linalg.eigvals / numpy.linalg.solve, then rubrotor.linear_analysis")
    which = argv[1:] or ["example", "60"]
    if "example" in which:
        run_case("rotor_example", ross.rotor_example())
    if "60" in which:
        run_case("60 elements, 2 disks, aniso", rotor_60())


if __name__ == "__main__":
    main()
