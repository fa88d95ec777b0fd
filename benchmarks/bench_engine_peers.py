"""The general engine against compiled ODE solvers (issue 14): numbalsoda DOP853 and LSODA,
nbkode DOP853 and diffrax Dopri8.

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

Peers (every one with ``atol = 1e-4 rtol``):

- numbalsoda ``dop853`` and ``lsoda`` (compiled Fortran/C), the right-hand side a numba
  ``cfunc``;
- nbkode's ``DOP853`` (numba-compiled Runge-Kutta; PyPI name ``numbakit-ode``): the same
  inlined numba core as an njit ``f(t, u)``, a new solver per call, ``solver.run(t_eval)``. It
  writes the requested times from its dense output, so writing only the compared samples leaves
  its steps unchanged. nbkode 0.5 calls SciPy's ``select_initial_step`` with the arguments of
  SciPy < 1.11 (a ``TypeError`` with SciPy 1.17), so each call computes the first step with
  SciPy's own rule and passes it in (``first_step``);
- diffrax ``Dopri8`` with ``PIDController(rtol, atol)``, ``SaveAt(ts=t_eval)``,
  ``ForwardMode()`` (no adjoint bookkeeping), float64 (``jax_enable_x64``), ``jax.jit``-compiled
  once per length of ``t_eval`` with the tolerances as arguments (compilation excluded by a
  warm-up call), results waited for with ``block_until_ready``. Its right-hand side is the same
  law written in jax.numpy (:func:`make_jax_rhs`); its difference from the numba one on 200
  reference states is printed.

A peer whose work-precision call takes more than 60 s is timed by that one call, not per round
(marked ``(1 call)``); a peer that does not import is printed as ``not installed``.

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
source and needs Debian's ``gfortran``; jax runs on the CPU; nbkode and diffrax are optional
here: without them their rows say ``not installed``). Run:
``OPENBLAS_NUM_THREADS=1 PYTHONPATH=src python benchmarks/bench_engine_peers.py [--reps 3]
[--case seed|general|all]`` (``seed``: case 1 and the floor). Prints, never asserts.
"""

from __future__ import annotations

import argparse
import dataclasses
import gc
import math
import statistics
import time
import warnings
from pathlib import Path

import numba as nb
import numpy as np
from bench_engine import sixty_element_rotor  # the 60-element rotor of bench_engine.py

import rubrotor
from rubrotor.core.contact import _law
from rubrotor.engine.driver import build_plant, simulate_general
from rubrotor.engine.parts import RubStation, Run, Stator
from rubrotor.engine.settings import Integrator
from rubrotor.rotors.forces import Contact, Unbalance
from rubrotor.rotors.shaft_system import continuous_system
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
    """numba right-hand side of the plant's modal equations on ``[Re y, Im y]``: a ``cfunc`` for
    numbalsoda and, around the same inlined core, an njit ``f(t, u) -> du`` for nbkode."""
    from numbalsoda import lsoda_sig

    c = plant.contacts
    lam = plant.lam.copy()
    beta = plant.beta.copy()
    Cd, Cv, Pu, Pv, d0, cp = c.Cd.copy(), c.Cv.copy(), c.Pu.copy(), c.Pv.copy(), c.d0.copy(), c.cp
    cp = cp.copy()
    ns, m = beta.shape
    nc = cp.shape[0]
    omega = plant.speed

    @nb.njit(inline="always")
    def core(t, u, du):
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

    @nb.cfunc(lsoda_sig)
    def rhs(t, u_, du_, p_):
        core(t, nb.carray(u_, (2 * ns,)), nb.carray(du_, (2 * ns,)))

    @nb.njit
    def f(t, u):
        du = np.empty(2 * ns)
        core(t, u, du)
        return du

    return rhs, f


def _jax_law(py, pz, uy, uz, cp):
    """``(fy, fz)`` of :func:`rubrotor.core.contact._law` in jax.numpy (N); the law's kind and
    friction sign are read from ``cp`` when tracing, the contact test by ``where``."""
    import jax.numpy as jnp

    if cp[0] == 0.0:
        return 0.0 * py, 0.0 * pz
    d = jnp.sqrt(py * py + pz * pz)
    g = cp[4]
    dd = jnp.maximum(d, g)  # the clearance is positive: no division by zero off contact
    ny, nz = py / dd, pz / dd
    eps = jnp.maximum(d - g, 0.0)
    epsd = ny * uy + nz * uz
    k, c = cp[2], cp[3]
    fn = k * eps * jnp.sqrt(eps) * (1.0 + c * epsd) if cp[1] == 0.0 else k * eps + c * epsd
    fn = jnp.where((d > g) & (fn > 0.0), fn, 0.0)
    if cp[6] == 0.0:
        vs = cp[7] - nz * uy + ny * uz
        sig = vs / jnp.sqrt(vs * vs + cp[8] * cp[8])
    else:
        sig = -1.0
    ms = cp[5] * sig
    return -fn * (ny - ms * nz), -fn * (nz + ms * ny)


def make_jax_rhs(plant):
    """The right-hand side of :func:`make_rhs` in jax.numpy, ``f(t, u, args) -> du``."""
    import jax.numpy as jnp

    c = plant.contacts
    ns = plant.lam.size
    lr, li = jnp.asarray(plant.lam.real), jnp.asarray(plant.lam.imag)
    br, bi = jnp.asarray(plant.beta.real), jnp.asarray(plant.beta.imag)
    cdr, cdi = jnp.asarray(c.Cd.real), jnp.asarray(c.Cd.imag)
    cvr, cvi = jnp.asarray(c.Cv.real), jnp.asarray(c.Cv.imag)
    Pu, Pv, d0, cps = c.Pu.copy(), c.Pv.copy(), c.d0.copy(), c.cp.copy()
    omega = plant.speed

    def f(t, u, args):
        yr, yi = u[:ns], u[ns:]
        cz, sz = jnp.cos(omega * t), jnp.sin(omega * t)
        d = d0 + Pu.real * cz - Pu.imag * sz + cdr @ yr - cdi @ yi
        v = Pv.real * cz - Pv.imag * sz + cvr @ yr - cvi @ yi
        F = []
        for i, cp in enumerate(cps):
            F.extend(_jax_law(d[2 * i], d[2 * i + 1], v[2 * i], v[2 * i + 1], cp))
        F = jnp.stack(F)
        return jnp.concatenate([lr * yr - li * yi + br @ F, li * yr + lr * yi + bi @ F])

    return f


def contact_disp(plant, Y, t):
    """``(2, T)`` rotor displacement (m) at the first output station from modal states."""
    o = plant.outputs
    z = np.exp(1j * plant.speed * t)
    return np.real(o.Od[:2] @ Y.T) + np.real(np.outer(o.OPu[:2], z)) + o.Od0[:2, None]


def _y0(plant):
    return np.concatenate([plant.y0.real, plant.y0.imag])


def _modal(usol, ns):
    return usol[:, :ns] + 1j * usol[:, ns:]


def peer_run(solver, rhs, plant, t_eval, rtol, atol):
    usol, ok = solver(rhs.address, _y0(plant), t_eval, rtol=rtol, atol=atol, mxstep=10**9)
    return _modal(usol, plant.lam.size), ok


def nbkode_runner(plant, f):
    """``run(t_eval, rtol, atol) -> (Y, ok)`` with nbkode's DOP853 (a new solver per call, its
    dense output at ``t_eval``), or the reason it cannot run."""
    try:
        import nbkode  # PyPI name numbakit-ode
    except ImportError as e:
        return f"not installed ({e})"
    from scipy.integrate._ivp.common import select_initial_step

    y0 = _y0(plant)

    def run(tt, rtol, atol):
        # nbkode 0.5 calls SciPy's select_initial_step with the arguments of SciPy < 1.11
        # (TypeError with SciPy 1.17): its first step is passed in, chosen by SciPy's own rule
        # for an order-7 error estimate (one rhs evaluation more than nbkode's call would take)
        h0 = select_initial_step(f, tt[0], y0, tt[-1], np.inf, f(tt[0], y0), 1, 7, rtol, atol)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", nb.NumbaWarning)  # compile-time notes
                solver = nbkode.DOP853(f, tt[0], y0, rtol=rtol, atol=atol, first_step=h0)
                _, usol = solver.run(tt)
        except Exception:  # step size underflow and the like: no result at this tolerance
            return None, False
        return _modal(usol, plant.lam.size), bool(np.all(np.isfinite(usol)))

    return run


def diffrax_runner(plant):
    """``run(t_eval, rtol, atol) -> (Y, ok)`` with diffrax's Dopri8 under a PID step-size
    controller, saving at ``t_eval``; jit-compiled once per length of ``t_eval`` (float64)."""
    try:
        import jax

        jax.config.update("jax_enable_x64", True)
        import diffrax
        import jax.numpy as jnp
    except ImportError as e:
        return f"not installed ({e})"
    term = diffrax.ODETerm(make_jax_rhs(plant))
    y0 = jnp.asarray(_y0(plant))

    @jax.jit
    def solve(ts, rtol, atol):
        sol = diffrax.diffeqsolve(
            term, diffrax.Dopri8(), ts[0], ts[-1], None, y0,
            saveat=diffrax.SaveAt(ts=ts),
            stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol),
            max_steps=10**9, adjoint=diffrax.ForwardMode(), throw=False,
        )  # fmt: skip
        return sol.ys, sol.result == diffrax.RESULTS.successful

    def run(tt, rtol, atol):
        ys, ok = solve(jnp.asarray(tt), rtol, atol)
        ys = np.asarray(ys.block_until_ready())
        return _modal(ys, plant.lam.size), bool(ok) and bool(np.all(np.isfinite(ys)))

    run.rhs = term.vector_field
    return run


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


SLOW = 60.0  # s: a peer call longer than this runs once (its work-precision call), not per round


def _runners(plant, rhs, f_nb):
    """Peer name -> ``run(t_eval, rtol, atol) -> (Y, ok)``, or why that peer cannot run."""
    from numbalsoda import dop853, lsoda

    def numbalsoda(solver):
        return lambda tt, rtol, atol: peer_run(solver, rhs, plant, tt, rtol, atol)

    return {"DOP853": numbalsoda(dop853), "LSODA": numbalsoda(lsoda),
            "nbkode DOP853": nbkode_runner(plant, f_nb), "diffrax Dopri8": diffrax_runner(plant)}  # fmt: skip


def _rhs_check(runners, f_nb, ref_u, t_all):
    """Largest difference of the jax right-hand side from the numba one on reference states,
    relative to the numba one's size."""
    run = runners["diffrax Dopri8"]
    if isinstance(run, str):
        return None
    idx = np.linspace(0, t_all.size - 1, 200).astype(int)
    a = np.array([f_nb(t_all[i], ref_u[i]) for i in idx])
    b = np.array([np.asarray(run.rhs(t_all[i], ref_u[i], None)) for i in idx])
    return float(np.max(np.abs(a - b)) / np.max(np.abs(a)))


def _work_precision(runners, plant, t_all, t_cmp, err_of, errs):
    """Each peer at the loosest tolerance of ``TOLS`` at least as accurate as each stepper."""
    peers, chosen, perr, once = {}, {}, {}, {}
    for name, run in runners.items():
        if isinstance(run, str):
            continue
        for what, tt in (("all samples", t_all), ("compared only", t_cmp)):
            stride = EVERY if tt is t_all else 1
            run(tt, TOLS[0], TOLS[0] * 1e-4)  # warm-up: compilation excluded
            errors, walls = {}, {}
            for tol in TOLS:
                t0 = time.perf_counter()
                y, ok = run(tt, tol, tol * 1e-4)
                walls[tol] = time.perf_counter() - t0
                errors[tol] = err_of(contact_disp(plant, y[::stride], t_cmp)) if ok else np.inf
                if errors[tol] <= min(errs.values()):
                    break
            for meth in METHODS:
                tol = next((t for t in TOLS if errors.get(t, np.inf) <= errs[meth]), None)
                chosen[name, what, meth] = tol
                if tol is None:
                    continue
                perr[name, what, tol] = errors[tol]
                if walls[tol] > SLOW:
                    once[name, what, tol] = walls[tol]
                else:
                    peers[name, what, tol] = lambda r=run, tt=tt, tol=tol: r(tt, tol, tol * 1e-4)
    return peers, chosen, perr, once


def _flop_rate(reps=3) -> float:
    """Flop/s of a compiled scalar dot product in cache (the arithmetic floors' yardstick)."""
    x = np.random.default_rng(0).standard_normal(1 << 12)
    _dot(x, 1)
    tm, _ = _median(lambda: _dot(x, 1000), reps)
    return 2 * x.size * 1000 / tm


def goal_check(label, factor, tpeer, chosen, ours, samples, ns):
    """Time the goal ``factor`` x DOP853 (all samples) allows against our arithmetic floor.

    The floor is a lower bound for ANY method that writes these samples: each sample needs at
    least a free sample's arithmetic (advance ``ns`` complex modes, 6 flops each, and four
    output rows, 2 flops per mode each), however few steps the contact takes, plus our fixed
    cost per call (setup, measured). When the allowed time is below it, no stepper can meet
    the goal at this output density.
    """
    tol = chosen.get(("DOP853", "all samples", "collocation"))
    if tol is None:
        return
    allowed = tpeer["DOP853", "all samples", tol] / factor
    rate = _flop_rate()
    flops = 6 * ns + 4 * 2 * ns
    fixed = ours["collocation"][0] - ours["collocation"][1]
    floor_t = samples * flops / rate
    verdict = "reachable" if floor_t + fixed < allowed else "UNREACHABLE at this output density"
    print(f"  goal {factor}x DOP853 (all samples) on {label}: our call must take <= "
          f"{allowed * 1e3:.3f} ms; writing its {samples} samples costs >= {floor_t * 1e3:.3f} ms "
          f"of arithmetic ({flops} flops each at {rate / 1e9:.2f} Gflop/s) plus our fixed "
          f"{fixed * 1e3:.3f} ms per call (measured): {verdict}")  # fmt: skip


def compare(label, system, stations, unb, run, revs, reps, gravity=(0.0, 0.0), factor=10):
    from numbalsoda import dop853

    plant = build_plant(system, run, stations, unb, gravity=gravity)
    rhs, f_nb = make_rhs(plant)
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
    runners = _runners(plant, rhs, f_nb)
    drhs = _rhs_check(runners, f_nb, np.concatenate([ref_y.real, ref_y.imag], axis=1), t_all)
    peers, chosen, perr, once = _work_precision(runners, plant, t_all, t_cmp, err_of, errs)
    ours, tpeer = _interleaved(fns, peers, reps)
    tpeer.update(once)
    print(f"{label}: {revs} rev, {t_all.size} samples, {plant.lam.size} complex modes, "
          f"rtol {run.rtol:.0e}; medians of {reps} interleaved rounds")  # fmt: skip
    for meth, (tc, tk, r) in ours.items():
        s = r.stats
        print(f"  rubrotor {meth:12s}: {tc * 1e3 / revs:8.4f} ms/rev call, {tk * 1e3 / revs:8.4f} "
              f"kernel, fixed {(tc - tk) * 1e3:6.3f} ms/call  error {errs[meth]:.2e}  (contact "
              f"steps {s['accepted_steps']} + {s['rejected_steps']} rejected, Newton "
              f"{s['newton_iterations']}, free jumps {s.get('free_advances')})")  # fmt: skip
    for name, why in runners.items():
        if isinstance(why, str):
            print(f"  {name:14s}: {why}")
    if drhs is not None:
        print(f"  diffrax rhs (jax) vs numba rhs on 200 reference states: {drhs:.1e} relative")
    for (name, what, meth), tol in chosen.items():
        if tol is None:
            print(f"  {name:14s} {what:13s} vs {meth:12s}: no rtol down to 1e-11 reaches its error")
            continue
        tp = tpeer[name, what, tol]
        tc, tk = ours[meth][0], ours[meth][1]
        n1 = " (1 call)" if (name, what, tol) in once else ""
        print(f"  {name:14s} rtol {tol:.0e} {what:13s}: {tp * 1e3 / revs:8.4f} ms/rev error "
              f"{perr[name, what, tol]:.2e}  vs {meth:12s} ratio peer/ours {tp / tc:6.1f} "
              f"(call), {tp / tk:6.1f} (kernel){n1}")  # fmt: skip
    goal_check(label, factor, tpeer, chosen, ours, t_all.size, plant.lam.size)
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
    rate = _flop_rate(reps)  # compiled scalar dot, in cache
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
    compare("60-element rotor, 20 modes, seal rub", rotor.linear_system(), st, unb, run, revs, reps,
            factor=30)  # fmt: skip


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
