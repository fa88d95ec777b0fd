"""The general engine against compiled ODE solvers (issue 14): numbalsoda DOP853 and LSODA.

Every solver integrates the SAME reduced equations: the plant's diagonal modal system
``y' = lam y + beta F(p, u)`` (complex ``y`` as ``[Re y, Im y]`` for the peers, right-hand side a
numba ``cfunc``), contact law :func:`rubrotor.core.contact._law` on the relative contact
displacement ``p = d0 + Re(Pu e^{i Omega t}) + Re(Cd y)`` (no residual feed-through, so that no
algebraic loop remains for the peers), the same initial state. Errors are the largest
displacement error at the contact over the compared samples (every 8th output sample), relative
to the orbit's size, against a tight reference (numbalsoda DOP853, rtol 1e-12, atol 1e-16: an
independent integrator). Each peer runs at the loosest tolerance of 1e-3 ... 1e-11 that is at
least as accurate as ours (work-precision), (a) writing every output sample we write and (b)
writing only the compared samples. Ours: the three steppers of the general engine
(``"exponential"``; ``"free-flight"``, order-2 contact steps; ``"collocation"``, order-4, the
default with ``rtol``), each timed as the whole call (plant prebuilt, as the peers get their
``cfunc`` prebuilt) and as its compiled chunk calls alone (``kernel``). Times are medians of
``--reps`` rounds after a warm-up (compilation excluded), each round running every stepper and
every peer once (interleaved); ``ms/rev`` is per revolution.

Cases:
1. seed case 1 (3 continuous modes as 12 complex modes, Hertz rub, 128 samples per revolution),
   default settings (rtol 1e-6), 20 and 200 revolutions;
2. a 60-element rotor on anisotropic cross-coupled bearings, 20 retained modes plus the
   flexible stator, rub at a seal (linear law with friction), 20 revolutions.

The floor: the arithmetic a free sample cannot avoid (advance ``ns`` complex modes, 6 flops each,
and ``4 ns`` real-complex products for the two displacement and two velocity rows, 2 flops
each) against the measured time per free-flight sample (clearance opened); and a contact step's
Newton solve plus its ``m x ns`` rows.

Requires the optional group ``bench`` (``pip install -e ".[bench]"``; numbalsoda builds from
source and needs Debian's ``gfortran``). Run:
``PYTHONPATH=src python benchmarks/bench_engine_peers.py [--reps 3]``. Prints, never asserts.
"""

from __future__ import annotations

import argparse
import dataclasses
import gc
import math
import statistics
import time
from pathlib import Path

import numba as nb
import numpy as np
from bench_engine import sixty_element_rotor  # the 60-element rotor of bench_engine.py

import rubrotor
from rubrotor.core.contact import _law
from rubrotor.engine.continuous import continuous_system
from rubrotor.engine.driver import build_plant, simulate_general
from rubrotor.engine.model import RubStation, Run, Stator
from rubrotor.forces import Contact, Unbalance
from rubrotor.integrator import Integrator
from rubrotor.scenario import load_scenario

SCEN = Path(rubrotor.__file__).parent / "scenarios" / "seed_case1.toml"
EVERY = 8  # compared samples: every 8th output sample
TOLS = [10.0**-k for k in range(3, 12)]


def _median(fn, reps):
    walls, out = [], None
    for _ in range(reps):
        t0 = time.perf_counter()
        out = fn()
        walls.append(time.perf_counter() - t0)
    return statistics.median(walls), out


def make_rhs(plant):
    """numba cfunc right-hand side of the plant's modal equations on ``[Re y, Im y]``."""
    from numbalsoda import lsoda_sig

    c = plant.contacts
    lam = plant.lam.copy()
    beta = plant.beta.copy()
    Cd, Cv, Pu, Pv, d0, cp = c.Cd.copy(), c.Cv.copy(), c.Pu.copy(), c.Pv.copy(), c.d0.copy(), c.cp
    cp = cp.copy()
    ns, m = beta.shape
    nc = cp.shape[0]
    omega = plant.speed

    @nb.cfunc(lsoda_sig)
    def rhs(t, u_, du_, p_):
        u = nb.carray(u_, (2 * ns,))
        du = nb.carray(du_, (2 * ns,))
        z = complex(math.cos(omega * t), math.sin(omega * t))
        F = np.zeros(m)
        for i in range(nc):
            pp = np.zeros(4)
            for a in range(2):
                r = 2 * i + a
                d = d0[r] + (Pu[r] * z).real
                v = (Pv[r] * z).real
                for j in range(ns):
                    d += Cd[r, j].real * u[j] - Cd[r, j].imag * u[ns + j]
                    v += Cv[r, j].real * u[j] - Cv[r, j].imag * u[ns + j]
                pp[a] = d
                pp[2 + a] = v
            law = _law(pp[0], pp[1], pp[2], pp[3], cp[i])
            F[2 * i] = law[0]
            F[2 * i + 1] = law[1]
        for j in range(ns):
            y = complex(u[j], u[ns + j])
            dy = lam[j] * y
            for k in range(m):
                dy += beta[j, k] * F[k]
            du[j] = dy.real
            du[ns + j] = dy.imag

    return rhs


def contact_disp(plant, Y, t):
    """``(2, T)`` rotor displacement (m) at the first output station from modal states."""
    o = plant.outputs
    z = np.exp(1j * plant.speed * t)
    return np.real(o.Od[:2] @ Y.T) + np.real(np.outer(o.OPu[:2], z)) + o.Od0[:2, None]


def peer_run(solver, rhs, plant, t_eval, rtol, atol):
    y0 = np.concatenate([plant.y0.real, plant.y0.imag])
    usol, ok = solver(rhs.address, y0, t_eval, rtol=rtol, atol=atol, mxstep=10**9)
    ns = plant.lam.size
    return usol[:, :ns] + 1j * usol[:, ns:], ok


METHODS = ("exponential", "free-flight", "collocation")


def _ours_fn(system, plant, run, stations, unb, gravity):
    """One call per stepper (the user-level entry with the plant prebuilt)."""

    def make(meth):
        return lambda: simulate_general(system, run, stations, unb, gravity=gravity,
                                        progress=False, plant=plant, method=meth)  # fmt: skip

    return {meth: make(meth) for meth in METHODS}


def _interleaved(ours, peers, reps):
    """Medians over ``reps`` rounds, each round timing every stepper of ours (whole call and
    ``stats['wall_s']``, the compiled chunk calls with their numba dispatch) and every peer
    run once, so that a load spike on this shared machine hits all of them alike; the garbage
    collector is off inside a round (as in ``timeit``)."""
    t_call = {k: [] for k in ours}
    t_kern = {k: [] for k in ours}
    t_peer = {k: [] for k in peers}
    last = {}
    for _ in range(reps):
        gc.collect()
        gc.disable()  # as timeit: a collection would land on whichever call allocates next
        for k, fn in ours.items():
            t0 = time.perf_counter()
            last[k] = fn()
            t_call[k].append(time.perf_counter() - t0)
            t_kern[k].append(last[k].stats["wall_s"])
        for k, fn in peers.items():
            t0 = time.perf_counter()
            fn()
            t_peer[k].append(time.perf_counter() - t0)
        gc.enable()
    med = statistics.median
    return ({k: (med(t_call[k]), med(t_kern[k]), last[k]) for k in ours},
            {k: med(v) for k, v in t_peer.items()})  # fmt: skip


def compare(label, system, stations, unb, run, revs, reps, gravity=(0.0, 0.0)):
    from numbalsoda import dop853, lsoda

    plant = build_plant(system, run, stations, unb, gravity=gravity)
    rhs = make_rhs(plant)
    fns = _ours_fn(system, plant, run, stations, unb, gravity)
    first = {meth: fn() for meth, fn in fns.items()}  # warm-up (compilation excluded)
    t_all = first["exponential"].time
    t_cmp = t_all[::EVERY]
    # the reference writes every sample: with only the compared ones (8x sparser) DOP853 takes
    # steps long enough to pass over short contacts and ends on another orbit, even at 1e-12
    ref_y, ok = peer_run(dop853, rhs, plant, t_all, 1e-12, 1e-16)
    ref = contact_disp(plant, ref_y[::EVERY], t_cmp)
    scale = np.max(np.abs(ref))

    def err_of(disp):
        return float(np.max(np.abs(disp - ref)) / scale)

    errs = {meth: err_of(r.channels[:2, ::EVERY]) for meth, r in first.items()}
    # each peer at the loosest tolerance at least as accurate as each of our steppers
    peers, chosen, perr = {}, {}, {}
    for name, solver in (("DOP853", dop853), ("LSODA", lsoda)):
        for what, tt in (("all samples", t_all), ("compared only", t_cmp)):
            stride = EVERY if tt is t_all else 1
            errors = {}
            for tol in TOLS:
                y, ok = peer_run(solver, rhs, plant, tt, tol, tol * 1e-4)
                errors[tol] = err_of(contact_disp(plant, y[::stride], t_cmp)) if ok else np.inf
                if errors[tol] <= min(errs.values()):
                    break
            for meth in METHODS:
                tol = next((t for t in TOLS if errors.get(t, np.inf) <= errs[meth]), None)
                chosen[name, what, meth] = tol
                if tol is not None:
                    perr[name, what, tol] = errors[tol]
                    peers[name, what, tol] = (lambda s=solver, tt=tt, tol=tol:
                                              peer_run(s, rhs, plant, tt, tol, tol * 1e-4))  # fmt: skip
    ours, tpeer = _interleaved(fns, peers, reps)
    print(f"{label}: {revs} rev, {t_all.size} samples, {plant.lam.size} complex modes, "
          f"rtol {run.rtol:.0e}; medians of {reps} interleaved rounds")  # fmt: skip
    for meth, (tc, tk, r) in ours.items():
        s = r.stats
        print(f"  rubrotor {meth:12s}: {tc * 1e3 / revs:8.4f} ms/rev call, {tk * 1e3 / revs:8.4f} "
              f"kernel, fixed {(tc - tk) * 1e3:6.3f} ms/call  error {errs[meth]:.2e}  (contact "
              f"steps {s['accepted_steps']} + {s['rejected_steps']} rejected, Newton "
              f"{s['newton_iterations']}, free jumps {s.get('free_advances')})")  # fmt: skip
    for (name, what, meth), tol in chosen.items():
        if tol is None:
            print(f"  {name:7s} {what:13s} vs {meth:12s}: no rtol down to 1e-11 reaches its error")
            continue
        tp = tpeer[name, what, tol]
        tc, tk = ours[meth][0], ours[meth][1]
        print(f"  {name:7s} rtol {tol:.0e} {what:13s}: {tp * 1e3 / revs:8.4f} ms/rev error "
              f"{perr[name, what, tol]:.2e}  vs {meth:12s} ratio peer/ours {tp / tc:6.1f} "
              f"(call), {tp / tk:6.1f} (kernel)")  # fmt: skip
    return ours


def seed_case(revs, reps):
    sc = load_scenario(SCEN)
    integ = Integrator(revolutions=revs)
    w = sc.speed
    stn = [RubStation(dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2))]
    run = Run(speed=w, duration=integ.total_time(w), step=integ.output_spacing(w),
              rtol=integ.rtol, atol=integ.atol)  # fmt: skip
    system = continuous_system(sc.shaft)
    ours = compare("seed case 1", system, stn, [sc.unbalance], run, revs, reps)
    return system, sc, run, ours


@nb.njit(cache=True)
def _dot(x, reps):
    acc = 0.0
    for _ in range(reps):
        for i in range(x.size):
            acc += x[i] * x[i]
    return acc


def floor(system, sc, run, reps, ours, meth="collocation"):
    """The arithmetic a free sample and a contact step cannot avoid against the measured time."""
    far = [RubStation(dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2, clearance=1.0))]
    plant = build_plant(system, run, far, [sc.unbalance])
    walls = []
    for _ in range(reps + 1):
        gc.collect()
        gc.disable()
        r = simulate_general(system, run, far, [sc.unbalance], progress=False, plant=plant,
                             method=meth)  # fmt: skip
        gc.enable()
        walls.append(r.stats["wall_s"])
    ns = plant.lam.size
    m = plant.beta.shape[1]
    n = r.time.size - 1
    per = statistics.median(walls[1:]) / n
    x = np.random.default_rng(0).standard_normal(1 << 12)
    _dot(x, 1)
    tm, _ = _median(lambda: _dot(x, 1000), reps)  # compiled scalar dot, in cache
    rate = 2 * x.size * 1000 / tm
    flops = 6 * ns + 4 * 2 * ns  # advance ns complex modes; v, w, v', w' rows (real parts)
    print(f"floor ({meth}), free flight (clearance opened): {per * 1e9:.0f} ns per sample "
          f"measured (kernel); unavoidable arithmetic {flops} flops per sample ({ns} complex "
          f"modes advanced + 4 output rows) = {flops / rate * 1e9:.0f} ns at the measured "
          f"{rate / 1e9:.2f} Gflop/s of a compiled dot product; measured / floor = "
          f"{per * rate / flops:.1f}")  # fmt: skip
    tc, tk, rc = ours[meth]
    s = rc.stats
    attempts = s["accepted_steps"] + s["rejected_steps"]
    if not attempts:
        return
    S = rc.stations.size
    n_cs = int(np.sum(rc.channels[4 * S + 6, 1:] > 0.0))  # samples written in contact
    n_free = rc.time.size - 1 - n_cs
    t_contact = tk - per * n_free  # beyond the free samples at their measured cost
    it = s["newton_iterations"] / attempts
    q = 2 * m  # stacked stage unknowns
    # a step: stage rows (2 stages x d, v x m rows x ns, 2 flops), per Newton iteration two law
    # evaluations (~30 flops each), the q x q Jacobian (4 q^2) and its LU (2 q^3 / 3), the
    # update (3 complex multiply-adds per mode) and the stage inputs beta F (2 m ns, 2 flops)
    cflops = 8 * m * ns + it * (60 + 4 * q * q + 2 * q**3 / 3) + 24 * ns + 4 * m * ns
    # a sample in contact: the interpolant advanced one spacing (4 complex products and three
    # 3-term real combinations per mode, 42 flops), the output rows as a free sample, the
    # contact rows (2 m ns) and the law (~30 flops)
    sflops = 42 * ns + 8 * ns + 4 * m * ns + 30
    floor_t = (attempts * cflops + n_cs * sflops) / rate
    print(f"floor ({meth}), contact: {t_contact * 1e3:.2f} ms measured beyond the free samples "
          f"({attempts} step attempts, {it:.1f} Newton iterations each, and {n_cs} samples "
          f"written in contact = {t_contact / attempts * 1e9:.0f} ns per attempt with its "
          f"samples); unavoidable arithmetic {cflops:.0f} flops per attempt + {sflops} per "
          f"contact sample = {floor_t * 1e3:.2f} ms; measured / floor = {t_contact / floor_t:.1f}")  # fmt: skip
    print(f"  whole run: kernel {tk * 1e3:.2f} ms = free samples {per * n_free * 1e3:.2f} ms "
          f"({n_free} at {per * 1e9:.0f} ns) + contact {t_contact * 1e3:.2f} ms")  # fmt: skip


def general_rotor(reps, revs=20):
    rotor = sixty_element_rotor()
    seal = Contact(clearance=1e-4, stiffness=5e7, damping=300, friction=0.2, position=0.75,
                   law="linear", radius=0.05)  # fmt: skip
    st = [RubStation(seal, offset_y=-5e-5, stator=Stator(30, 30, 2e7, 2e7, 800, 800))]
    unb = [Unbalance(5e-4, 0.5), Unbalance(3e-4, 1.0, 1.0)]
    speed = 400.0
    T = 2 * math.pi / speed
    run = Run(speed=speed, duration=revs * T, step=T / 128, modes=20, residual=False,
              initial="rest", rtol=1e-6)  # fmt: skip
    compare("60-element rotor, 20 modes, seal rub", rotor.linear_system(), st, unb, run, revs, reps)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--case", choices=["seed", "general", "all"], default="all")
    a = ap.parse_args()
    if a.case in ("seed", "all"):
        for revs in (20, 200):
            system, sc, run, ours = seed_case(revs, a.reps)
        floor(system, sc, run, a.reps, ours)
    if a.case in ("general", "all"):
        general_rotor(a.reps)
