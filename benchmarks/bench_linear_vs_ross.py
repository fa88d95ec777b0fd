"""rubrotor linear analyses vs ROSS on ROSS's own rotors, imported with ``rubrotor.from_ross``.

Run: ``OPENBLAS_NUM_THREADS=1 PYTHONPATH=src .ci/.venv-ross3/bin/python
benchmarks/bench_linear_vs_ross.py [example] [60] [compressor] [modal]`` (``modal``: the modal
analysis only; ROSS 3.1 on Python 3.13; ROSS 2.3 on 3.11 works too; any venv with
``pip install "rubrotor[ross]"``). Ours and ROSS in one process,
medians of 3 repetitions (ROSS's 200-speed Campbell of the 60-element rotor: one run).

Rotors: ``ross.rotor_example()`` and a 60-element hollow steel rotor with two disks and
anisotropic, cross-coupled, damped bearings built in ROSS. Ours is the same model (``from_ross``),
so the frequency differences measure the import and the eigen-solvers, not the elements.
ROSS runs single-threaded (``OPENBLAS_NUM_THREADS=1``); our compiled sweeps share the speeds
among numba threads, so they are timed on one thread and on all cores.
Our side is timed twice: plain SciPy on ``LinearSystem.matrices(speed)`` (dense ``eigvals`` of
the first-order matrix; one complex solve per speed) and rubrotor's own ``damped_modes``,
``campbell_data`` and ``unbalance_response`` (which also classify whirl and damping).
ROSS and ours run in turns (interleaved repeats, medians; the garbage collector is run before
and disabled during each timed call, as ``timeit`` does, so that neither side pays for
collecting the other's objects) and every line gives the ratio of wall times and of process
CPU times: on a shared, loaded machine the CPU ratio is the steadier one
(both sides are single-threaded there); the goals are read on the 1-thread lines.
"""

from __future__ import annotations

import contextlib
import gc
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

from rubrotor.linear.campbell import campbell_data
from rubrotor.linear.modes import damped_modes
from rubrotor.linear.response import unbalance_response
from rubrotor.rotors.ross import from_ross

warnings.simplefilter("ignore")


def thread_counts():
    """1 thread (like ROSS, whose BLAS is pinned to one thread here), then all cores."""
    return sorted({1, numba.config.NUMBA_NUM_THREADS})


def median_time(fn, reps=3):
    out, times = None, []
    for _ in range(reps):
        gc.collect()
        gc.disable()
        t0 = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()):
            out = fn()
        times.append(time.perf_counter() - t0)
        gc.enable()
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


def interleaved(fns, reps):
    """Time ``fns`` (name -> callable) in turns, ``reps`` rounds: each round runs every one once,
    so a load change on the shared machine hits all of them alike. Returns name -> (median wall
    s, median CPU s of this process, last result). CPU time is the load-proof figure for
    single-threaded runs (ROSS here, ours on one numba thread)."""
    wall = {k: [] for k in fns}
    cpu = {k: [] for k in fns}
    out = {}
    for _ in range(reps):
        for k, fn in fns.items():
            gc.collect()  # as timeit: no collection of the other side's garbage inside a timing
            gc.disable()
            t0, c0 = time.perf_counter(), time.process_time()
            with contextlib.redirect_stdout(io.StringIO()):
                out[k] = fn()
            wall[k].append(time.perf_counter() - t0)
            cpu[k].append(time.process_time() - c0)
            gc.enable()
    return {k: (statistics.median(wall[k]), statistics.median(cpu[k]), out[k]) for k in fns}


def show(label, res, peer, ours, goal=None, unit=1e3, suffix="ms"):
    """One line: ROSS and ours, wall and CPU, and their ratios."""
    (wr, cr, _), (wo, co, _) = res[peer], res[ours]
    g = f" (goal {goal}x)" if goal else ""
    print(
        f"  {label}: ROSS {wr * unit:.4g} {suffix} (CPU {cr * unit:.4g}), ours {wo * unit:.4g} "
        f"{suffix} (CPU {co * unit:.4g}): ratio {wr / wo:.1f}x wall, {cr / co:.1f}x CPU{g}"
    )


def run_case(name, r, modal_only=False):
    """Print the frequency difference and the three timings for one ROSS rotor (the modal
    analysis only with ``modal_only``)."""
    sys = from_ross(r)
    print(f"\n== {name}: {len(r.nodes_pos)} nodes, {sys.n_dof} lateral DOFs (ROSS {r.ndof})")
    numba.set_num_threads(1)
    speed = 500.0
    speeds = np.linspace(0, 1000, 200)
    n = r.disk_elements[0].n
    x = float(r.nodes_pos[n])
    sp = np.linspace(1, 1000, 500)
    # compile / load the kernels outside the timing
    damped_modes(sys, speed, n=12), campbell_data(sys, speeds[:3], n=6)
    unbalance_response(sys, sp[:3], [(x, 1e-3, 0.0)], [x])

    def ross_modal():
        if hasattr(r.run_modal, "cache_clear"):
            r.run_modal.cache_clear()
        return r.run_modal(speed, num_modes=24)

    res = interleaved(
        {
            "ross": ross_modal,
            "plain": lambda: our_frequencies(sys, speed, 8),
            "ours": lambda: damped_modes(sys, speed, n=12),
        },
        reps=7,
    )
    lam = np.asarray(res["ross"][2].evalues)
    wd = np.sort(lam.imag[lam.imag > 1e-3])
    diff = max(np.min(np.abs(wd - f)) / f for f in res["plain"][2])
    f_dm = np.array([m.frequency_hz for m in res["ours"][2].modes]) * 2 * np.pi
    diff_dm = max(np.min(np.abs(wd - f)) / f for f in f_dm)
    print(f"modal @ {speed} rad/s: max rel. freq. diff (8 modes) {diff:.2e}; ours {diff_dm:.2e}")
    show("one modal analysis, plain SciPy eigvals", res, "ross", "plain")
    show(
        "one modal analysis, damped_modes (n=12, as ROSS's 24 eigenvalues)", res, "ross", "ours", 30
    )
    if modal_only:
        return

    t4, _ = median_time(lambda: r.run_campbell(speeds[::50], frequencies=6), reps=1)
    camp = {"ross": lambda: r.run_campbell(speeds, frequencies=6)}
    if t4 > 4.0:  # ROSS 2.3 needs ~13 s per speed on the 60-element rotor: scale 4 speeds
        camp = {}
        print(f"  ROSS Campbell EXTRAPOLATED: 4 speeds took {t4:.1f} s, x50")
    if sys.n_dof < 100:
        camp["plain"] = lambda: our_campbell(sys, speeds)
    camp["ours"] = lambda: campbell_data(sys, speeds, n=6)
    res = interleaved(camp, reps=3 if t4 < 0.5 else 1)
    if t4 > 4.0:
        res["ross"] = (t4 * 50, t4 * 50, None)
    if "plain" in res:
        show("Campbell 200 speeds, plain SciPy eigvals", res, "ross", "plain", unit=1, suffix="s")
    show("campbell_data (n=6), 1 numba thread", res, "ross", "ours", 100, unit=1, suffix="s")
    for threads in thread_counts()[1:]:
        numba.set_num_threads(threads)
        t_cd, _ = median_time(lambda: campbell_data(sys, speeds, n=6), reps=5)
        print(f"  campbell_data (n=6), {threads} numba threads: {t_cd:.3f} s, "
              f"ratio {res['ross'][0] / t_cd:.1f}x wall")  # fmt: skip
        numba.set_num_threads(1)

    res = interleaved(
        {
            "ross": lambda: r.run_unbalance_response(n, 1e-3, 0.0, sp),
            "plain": lambda: our_unbalance(sys, x, sp),
            "ours": lambda: unbalance_response(sys, sp, [(x, 1e-3, 0.0)], [x]),
        },
        reps=5,
    )
    show("unbalance 500 speeds, plain numpy.linalg.solve", res, "ross", "plain")
    show("unbalance_response, 1 numba thread", res, "ross", "ours", 100)
    for threads in thread_counts()[1:]:
        numba.set_num_threads(threads)
        t_ur, _ = median_time(lambda: unbalance_response(sys, sp, [(x, 1e-3, 0.0)], [x]), reps=7)
        print(f"  unbalance_response, {threads} numba threads: {t_ur * 1e3:.2f} ms, "
              f"ratio {res['ross'][0] / t_ur:.1f}x wall")  # fmt: skip
        numba.set_num_threads(1)


def _lateral_wd(r, modal, lateral=True) -> np.ndarray:
    """ROSS's damped frequencies (rad/s) of its lateral modes (eigenvectors mostly lateral), or
    of the others with ``lateral=False``."""
    from rubrotor.rotors.ross import ross_dof_map

    idx, _ = ross_dof_map(len(r.nodes_pos), r.number_dof)
    v = np.asarray(modal.evectors)[: r.ndof]
    lateral = (np.linalg.norm(v[idx], axis=0) > 0.5 * np.linalg.norm(v, axis=0)) == lateral
    lam = np.asarray(modal.evalues)[lateral]
    return lam.imag[lam.imag > 1e-3]


def run_compressor(reps=5):
    """ROSS's ``compressor_example`` (56 nodes; 2 bearings and 12 seals tabulated against speed,
    PCHIP in ROSS 3.x): one modal analysis at 838 rad/s (ROSS's default 12 eigenvalues = 6
    modes against our 6 modes ranked by |lambda|; then 24 against 12) and a 61-speed Campbell
    diagram of 6 modes, 0-1100 rad/s; the frequency differences on the lateral modes."""
    r = ross.compressor_example()
    sys = from_ross(r)
    print(f"\n== compressor_example: {len(r.nodes_pos)} nodes, {len(r.bearing_elements)} "
          f"bearings and seals, {sys.n_dof} lateral DOFs (ROSS {r.ndof})")  # fmt: skip
    numba.set_num_threads(1)
    speed, speeds = 838.0, np.linspace(0.0, 1100.0, 61)
    damped_modes(sys, speed, n=6), campbell_data(sys, speeds[:3], n=6)  # compile outside

    def ross_modal(k):
        if hasattr(r.run_modal, "cache_clear"):
            r.run_modal.cache_clear()
        return r.run_modal(speed, num_modes=k)

    for k in (12, 24):
        res = interleaved(
            {
                "ross": lambda k=k: ross_modal(k),
                "ours": lambda k=k: damped_modes(sys, speed, k // 2),
            },
            reps=reps,
        )
        wd = _lateral_wd(r, res["ross"][2])
        ours = [2 * np.pi * m.frequency_hz for m in res["ours"][2].modes if not m.overdamped]
        diff = max(np.min(np.abs(wd - f)) / f for f in ours)
        print(f"modal @ {speed} rad/s, {k // 2} modes: max rel. freq. diff {diff:.1e}")
        show(f"one modal analysis, damped_modes (n={k // 2}, ROSS num_modes={k})", res,
             "ross", "ours", 30)  # fmt: skip
    res = interleaved(
        {
            "ross": lambda: r.run_campbell(speeds, frequencies=6),
            "ours": lambda: campbell_data(sys, speeds, n=6),
        },
        reps=max(1, reps // 2),
    )
    # accuracy on ROSS's lateral rows (its diagram also holds a torsional mode, 3341 rad/s at
    # every speed: ROSS's non-lateral eigenvalues at rest tell them apart); ours with 10 branches
    other = _lateral_wd(r, r.run_modal(0.0, num_modes=2 * r.ndof, sparse=False), lateral=False)
    ross_wd = np.asarray(res["ross"][2].wd)
    ours_w = 2 * np.pi * campbell_data(sys, speeds, n=10).frequency_hz
    lateral = np.min(np.abs(ross_wd[..., None] - other), axis=-1) > 1e-6 * ross_wd
    near = np.min(np.abs(ours_w[:, None, :] - ross_wd[:, :, None]), axis=2) / ross_wd
    print(f"Campbell 61 speeds: max rel. diff of ROSS's {lateral.sum()} lateral points to our "
          f"branches {near[lateral].max():.1e}")  # fmt: skip
    show("Campbell 61 speeds, campbell_data (n=6), 1 numba thread", res, "ross", "ours", 100,
         unit=1, suffix="s")  # fmt: skip


def main():
    print(f"ROSS {ross.__version__}; numpy {np.__version__}")
    print("ours: plain scipy.linalg.eigvals / numpy.linalg.solve, then rubrotor.linear (modes, campbell, response)")
    which = [a for a in argv[1:] if a != "modal"] or ["example", "60", "compressor"]
    modal_only = "modal" in argv[1:]
    if "example" in which:
        run_case("rotor_example", ross.rotor_example(), modal_only)
    if "60" in which:
        run_case("60 elements, 2 disks, aniso", rotor_60(), modal_only)
    if "compressor" in which:
        run_compressor()


if __name__ == "__main__":
    main()
