"""The general engine's order-4 contact steps (stepper ``"collocation"``, issue 14).

References:

* ``phi_k`` functions against mpmath at 60 digits (closed forms ``(e^z - 1)/z`` ... evaluated
  with enough digits that their cancellation does not matter);
* the collocation weights against the integral ``int_0^s e^{lam (s - r)} F(r) dr`` of a quadratic
  force by SciPy's adaptive quadrature (``quad``, epsabs 1e-15);
* the kernel's state after a permanent smooth contact against SciPy's DOP853 at rtol 1e-12 on the
  same modal equations (right-hand side written here in NumPy from the plant's rows and the
  contact law), the measured order being the slope of the error against the step;
* whole runs against the ``"exponential"`` stepper at rtol 1e-10 (another force hold and step
  control).
"""

import dataclasses
import math
from pathlib import Path

import mpmath
import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from rubrotor.core.contact import _law
from rubrotor.core.engine import EVENT_MARGIN, I_STATUS, N_ISTATE, OK
from rubrotor.core.engine_adaptive import (
    LEVELS_UP,
    N_TSTATE,
    T_HPREV,
    T_LEVEL,
    colloc_weights,
    expo_adaptive,
    phi0123,
)
from rubrotor.engine.driver import _plan, build_plant, simulate_general
from rubrotor.engine.parts import RubStation, Run
from rubrotor.engine.settings import Integrator
from rubrotor.engine.structs import Control, Sink, State, span
from rubrotor.rotors.shaft_system import continuous_system
from rubrotor.scenario import load_scenario

SEED1 = Path(__file__).parents[1] / "src/rubrotor/scenarios/seed_case1.toml"


@pytest.fixture(scope="module")
def seed():
    sc = load_scenario(SEED1)
    return sc, continuous_system(sc.shaft)


@pytest.mark.parametrize(
    "z", [0.0, 1e-9, 1e-3 + 0.2j, -0.3 + 0.9j, 0.99j, -0.999, 1.0001j, 5 + 3j, -20 + 1j, -300.0]
)
def test_phi0123_against_mpmath(z):
    """``phi1..phi3`` on both sides of the series/closed-form switch at ``|z| = 1`` to 1e-14."""
    mpmath.mp.dps = 60
    Z = mpmath.mpc(complex(z).real, complex(z).imag)
    if Z == 0:
        ref = [mpmath.mpf(1), mpmath.mpf(1) / 2, mpmath.mpf(1) / 6]
    else:
        p1 = (mpmath.exp(Z) - 1) / Z
        p2 = (p1 - 1) / Z
        ref = [p1, p2, (p2 - mpmath.mpf(1) / 2) / Z]
    got = phi0123(complex(z))
    assert abs(got[0] - complex(mpmath.exp(Z))) <= 1e-15 * abs(complex(mpmath.exp(Z)))
    for g, r in zip(got[1:], ref, strict=True):
        assert abs(g - complex(r)) <= 1e-14 * abs(complex(r))


@pytest.mark.parametrize("lam", [-50.0 + 3e3j, -2e4 + 1e5j, -3.0 + 0j])
def test_colloc_weights_integrate_a_quadratic_force(lam):
    """``e^{lam s} y0 + w0 F0 + wm Fm + w1 F1`` is the exact solution of ``y' = lam y + F(t)``
    for the quadratic ``F`` through ``F0, Fm, F1`` at ``0, h/2, h``, at any ``s`` in the step
    (reference: SciPy ``quad`` of the variation-of-constants integral)."""
    h = 1.3e-4
    F0, Fm, F1 = 2.0, -1.0, 0.5

    def force(t):
        th = t / h
        return (F0 * 2 * (th - 0.5) * (th - 1) - Fm * 4 * th * (th - 1)
                + F1 * 2 * th * (th - 0.5))  # fmt: skip

    for s in (0.3 * h, 0.5 * h, h):

        def f(r, part, s=s):
            v = np.exp(lam * (s - r)) * force(r)
            return v.real if part == 0 else v.imag

        ref = complex(*(quad(f, 0, s, args=(p,), epsabs=1e-15, epsrel=1e-13)[0] for p in (0, 1)))
        e, w0, wm, w1 = colloc_weights(lam, s, h)
        assert abs(e - np.exp(lam * s)) < 1e-14
        got = w0 * F0 + wm * Fm + w1 * F1
        assert abs(got - ref) <= 1e-11 * abs(ref)


def _pressed(sc, system, H, revs=1.0):
    """Seed case 1 with a softer contact (Hertz stiffness / 100) and the stator centre offset
    by the clearance plus twice the unbalance orbit, so that the rotor stays pressed for the
    whole run (normal force 1.3 ... 7.4 kN: a smooth force, no onset); rigid stator, no
    residual feed-through."""
    w = sc.speed
    probe = Run(speed=w, duration=1e-3, step=1e-6, residual=False, initial="steady")
    law = dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2,
                              stiffness=0.01 * sc.contact.stiffness)  # fmt: skip
    pl = build_plant(system, probe, [RubStation(law)], [sc.unbalance])
    orbit = float(np.max(np.abs(pl.contacts.Pu)))
    st = RubStation(law, offset_y=sc.contact.clearance + 2.0 * orbit)
    T = 2 * math.pi / w
    run = Run(speed=w, duration=revs * T, step=H, residual=False, initial="steady", rtol=1e6)
    return build_plant(system, run, [st], [sc.unbalance]), run


def _kernel_run(plant, run, order):
    """The adaptive kernel at fixed steps ``2^LEVELS_UP H`` (rtol so loose that no step is
    rejected), started from the consistent contact force ``F = law(p(0), u(0))``. Returns
    the final modal state and the final time (s)."""
    c = plant.contacts
    ns, m = plant.beta.shape
    plan = _plan(plant, run, 21, order)
    y = plant.y0.copy()
    p = c.d0 + np.real(c.Pu) + np.real(c.Cd @ y)
    u = np.real(c.Pv) + np.real(c.Cv @ y)
    law = _law(p[0], p[1], u[0], u[1], c.cp[0])
    F = np.array([law[0], law[1]])
    assert law[2] > 0.0
    tst = np.zeros(N_TSTATE)
    tst[T_HPREV] = run.step
    tst[T_LEVEL] = -LEVELS_UP
    ist = np.zeros(N_ISTATE, np.int64)
    n = int(round(run.duration / run.step))
    out = np.empty((4 + 8, n + 1))
    control = Control(1.0, float(run.rtol), float(run.atol), 1.0, np.zeros(1))
    state = State(y, F, np.zeros(m), np.zeros(1), tst, ist, np.zeros(1))
    sink = Sink(out, np.zeros((0, ns), complex), np.zeros((4 * EVENT_MARGIN, 2)))
    written = expo_adaptive(state, span(n, 1, 1, plant.speed), sink, plan, c, plant.outputs,
                            control)  # fmt: skip
    assert written == n and ist[I_STATUS] == OK
    assert np.all(out[10, 1:] > 0.0)  # the normal force never vanished
    return y, tst[0]


def _reference(plant, t_end):
    """DOP853 (rtol 1e-12) on ``y' = lam y + beta law(p, u)`` in real form."""
    c = plant.contacts
    lam, beta, w = plant.lam, plant.beta, plant.speed
    ns = lam.size

    def rhs(t, x):
        y = x[:ns] + 1j * x[ns:]
        z = np.exp(1j * w * t)
        p = c.d0 + np.real(c.Pu * z) + np.real(c.Cd @ y)
        u = np.real(c.Pv * z) + np.real(c.Cv @ y)
        law = _law(p[0], p[1], u[0], u[1], c.cp[0])
        dy = lam * y + beta @ np.array([law[0], law[1]])
        return np.concatenate([dy.real, dy.imag])

    x0 = np.concatenate([plant.y0.real, plant.y0.imag])
    sol = solve_ivp(rhs, (0.0, t_end), x0, method="DOP853", rtol=1e-12, atol=1e-18)
    return sol.y[:ns, -1] + 1j * sol.y[ns:, -1]


def test_collocation_order_four_on_a_smooth_contact(seed):
    """On a contact that stays closed (a smooth force), the error of the final modal state
    against DOP853 falls as ``h^4`` for the collocation step (measured slope > 3.5 over the
    three finer steps; at ``T/16`` it is not yet asymptotic) and as ``h^2`` for the linear
    force hold (slope 1.7 ... 2.5), steps ``h = 16 H`` of ``T/16 ... T/128`` over one
    revolution ``T``."""
    sc, system = seed
    T = 2 * math.pi / sc.speed
    hs, errs = [], {2: [], 4: []}
    ref = None
    for n in (16, 32, 64, 128):  # steps per revolution
        plant, run = _pressed(sc, system, T / (16 * n))
        if ref is None:
            ref = _reference(plant, T)
        hs.append(T / n)
        for order in (2, 4):
            y, t = _kernel_run(plant, run, order)
            assert abs(t - T) < 1e-9 * T  # the kernel's time: a sum of steps
            errs[order].append(np.max(np.abs(y - ref)) / np.max(np.abs(ref)))
    s2 = np.polyfit(np.log(hs), np.log(errs[2]), 1)[0]
    s4 = np.polyfit(np.log(hs[1:]), np.log(errs[4][1:]), 1)[0]  # past T/16: asymptotic
    print("h", hs, "errors order 2", errs[2], "order 4", errs[4], "slopes", s2, s4)
    assert 1.7 < s2 < 2.5
    assert s4 > 3.5
    assert errs[4][-1] < 0.01 * errs[2][-1]


def test_collocation_is_more_accurate_per_step(seed):
    """Seed case 1, 20 revolutions, rtol 1e-6: against a tight run of the ``"exponential"``
    stepper (rtol 1e-10), the collocation stepper is at least as accurate as the
    ``"free-flight"`` stepper (order 2) with fewer than a third of its contact steps; the
    same contact events, their times within 5 % of an output spacing of the reference's."""
    sc, system = seed
    integ = Integrator(revolutions=20)
    stn = [RubStation(dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2))]
    H = integ.output_spacing(sc.speed)
    run = Run(speed=sc.speed, duration=integ.total_time(sc.speed), step=H, rtol=1e-6)
    plant = build_plant(system, run, stn, [sc.unbalance])

    def go(method, rtol=1e-6, atol=1e-10):
        r = dataclasses.replace(run, rtol=rtol, atol=atol)
        return simulate_general(system, r, stn, [sc.unbalance], method=method, plant=plant,
                                progress=False)  # fmt: skip

    ref = go("exponential", 1e-10, 1e-14)
    scale = np.max(np.abs(ref.channels[:2]))
    err, steps = {}, {}
    for meth in ("free-flight", "collocation"):
        r = go(meth)
        assert r.status == "complete"
        assert r.events.shape == ref.events.shape
        assert np.max(np.abs(r.events[:, 0] - ref.events[:, 0])) < 0.05 * run.step
        err[meth] = np.max(np.abs(r.channels[:2] - ref.channels[:2])) / scale
        steps[meth] = r.stats["accepted_steps"] + r.stats["rejected_steps"]
    print("errors", err, "contact steps", steps)
    assert err["collocation"] <= err["free-flight"]
    assert 3 * steps["collocation"] < steps["free-flight"]
