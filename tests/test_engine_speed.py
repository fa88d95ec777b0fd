"""The adaptive stepper of the general engine (issue 14): exact free flight, located onsets,
steps decoupled from the output samples.

References:

* the exact free trajectory of the reduced model in closed form (NumPy on the plant's modes,
  ``p(t) = d0 + Re(Pu e^{i Omega t}) + Re(Cd e^{lam t} y0)``), its crossing of the clearance by
  SciPy's ``brentq`` (xtol 1e-15 s): independent of the kernel's stepping and root finding;
* the same engine at rtol 1e-10, atol 1e-14 for the error against tolerance.
"""

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from rubrotor.engine.driver import build_plant, simulate_general
from rubrotor.engine.parts import RubStation, Run
from rubrotor.engine.settings import Integrator
from rubrotor.rotors.shaft_system import continuous_system
from rubrotor.scenario import load_scenario

FREE = "free-flight"  # exact free flight between contacts, order-2 contact steps
EXACT_FREE = ["free-flight", "collocation"]  # "collocation": order 4, the default with rtol

SEED1 = Path(__file__).parents[1] / "src/rubrotor/scenarios/seed_case1.toml"


@pytest.fixture(scope="module")
def seed():
    sc = load_scenario(SEED1)
    return sc, continuous_system(sc.shaft)


def _station(sc, **kw):
    return RubStation(dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2, **kw))


def _free_radius(plant, speed):
    """``|p(t)|`` (m) at the contact on the exact free trajectory (closed form)."""
    c = plant.contacts

    def radius(t):
        p = c.d0 + np.real(c.Pu * np.exp(1j * speed * t))
        p = p + np.real(c.Cd @ (np.exp(plant.lam * t) * plant.y0))
        return float(np.hypot(p[0], p[1]))

    return radius


@pytest.mark.parametrize("method", EXACT_FREE)
def test_grazing_contact_between_two_samples_is_found(seed, method):
    """The clearance is set just below a local maximum of the free orbit radius, so that the
    orbit dips into the stator for less than a tenth of the output spacing, between two
    samples that both lie outside the contact. The adaptive run finds this contact: its onset
    matches the closed-form crossing (brentq) to 1e-12 s, its separation the free orbit's to
    1e-3 of the dip (the contact force itself shifts it), and the sampled
    normal force is zero at every sample. A fixed-step run at the output spacing (the step
    checks the gap at its ends only) misses it."""
    sc, system = seed
    w = sc.speed
    far = _station(sc, clearance=1.0)
    probe = Run(speed=w, duration=1e-3, step=1e-6, rtol=1e-6)
    plant = build_plant(system, probe, [far], [sc.unbalance])
    radius = _free_radius(plant, w)
    tt = np.linspace(0.0, 1e-3, 20001)
    rr = np.array([radius(t) for t in tt])
    k = 1 + int(np.argmax((rr[1:-1] > rr[:-2]) & (rr[1:-1] >= rr[2:]) & (tt[1:-1] > 2e-4)))
    from scipy.optimize import minimize_scalar

    opt = minimize_scalar(lambda t: -radius(t), bracket=(tt[k - 1], tt[k], tt[k + 1]), tol=1e-14)
    t_star, r_max = opt.x, -opt.fun
    curv = (radius(t_star + 1e-7) + radius(t_star - 1e-7) - 2 * r_max) / 1e-14  # d2|p|/dt2
    n = 40
    H = t_star / (n + 0.5)  # t_star midway between samples n and n + 1
    dip = 0.1 * H  # the contact lasts about 0.1 H
    g = r_max + 0.5 * curv * (dip / 2) ** 2
    assert g < r_max and radius(n * H) < g and radius((n + 1) * H) < g
    on = brentq(lambda t: radius(t) - g, t_star - H / 2, t_star, xtol=1e-15)
    off = brentq(lambda t: radius(t) - g, t_star, t_star + H / 2, xtol=1e-15)
    assert off - on < 0.2 * H
    stn = [_station(sc, clearance=g)]
    run = Run(speed=w, duration=(n + 3) * H, step=H, rtol=1e-6)
    res = simulate_general(system, run, stn, [sc.unbalance], method=method, progress=False)
    assert res.status == "complete"
    ev = res.events
    print("events", ev, "closed form", on, off, "H", H)
    assert ev.shape == (2, 2) and ev[0, 1] == 1 and ev[1, 1] == -1
    assert abs(ev[0, 0] - on) < 1e-12
    # the (tiny) contact force bends the orbit: separation within 1e-3 of the dip's length
    assert abs(ev[1, 0] - off) < 1e-3 * (off - on)
    S = len(res.stations)
    assert np.all(res.channels[4 * S + 6] == 0.0)  # no sample sees the contact
    fixed = simulate_general(system, Run(speed=w, duration=(n + 3) * H, step=H), stn,
                             [sc.unbalance], progress=False)  # fmt: skip
    assert fixed.stats["contact_events"] == 0


@pytest.mark.parametrize("method", EXACT_FREE)
def test_free_flight_is_exact_and_costs_no_steps(seed, method):
    """Without contact the adaptive run takes no step at all (one exact jump per sample) and
    its samples equal the closed-form free trajectory to rounding."""
    sc, system = seed
    w = sc.speed
    far = _station(sc, clearance=1.0)
    H = Integrator(revolutions=2).output_spacing(w)
    run = Run(speed=w, duration=256 * H, step=H, rtol=1e-6)
    res = simulate_general(system, run, [far], [sc.unbalance], method=method, progress=False)
    plant = build_plant(system, run, [far], [sc.unbalance])
    c = plant.contacts
    p = c.d0[:, None] + np.real(np.outer(c.Pu, np.exp(1j * w * res.time)))
    p = p + np.real(c.Cd @ (np.exp(np.outer(plant.lam, res.time)) * plant.y0[:, None]))
    assert res.stats["accepted_steps"] == 0 and res.stats["free_advances"] == 256
    err = np.max(np.abs(res.channels[:2] - p)) / np.max(np.abs(p))
    print("free flight error", err)
    assert err < 1e-12


def test_rtol_sets_the_steps_not_the_samples(seed):
    """Seed case 1, 20 revolutions, the default output spacing: the number of contact steps
    grows with the tolerance (they no longer follow the samples) and the error against a
    tight run (rtol 1e-10) falls with it; the samples are the same."""
    sc, system = seed
    integ = Integrator(revolutions=20)
    H = integ.output_spacing(sc.speed)
    stn = [_station(sc)]

    def go(rtol, atol=1e-10):
        run = Run(speed=sc.speed, duration=integ.total_time(sc.speed), step=H, rtol=rtol,
                  atol=atol)  # fmt: skip
        return simulate_general(system, run, stn, [sc.unbalance], method=FREE, progress=False)

    ref = go(1e-10, 1e-14)
    scale = np.max(np.abs(ref.channels[:2]))
    steps, errs = [], []
    for rtol in (1e-4, 1e-5, 1e-6, 1e-7):
        r = go(rtol)
        assert r.time.size == ref.time.size
        steps.append(r.stats["accepted_steps"] + r.stats["rejected_steps"])
        errs.append(np.max(np.abs(r.channels[:2] - ref.channels[:2])) / scale)
    slope = np.polyfit(np.log([1e-4, 1e-5, 1e-6, 1e-7]), np.log(errs), 1)[0]
    print("steps", steps, "errors", errs, "slope of error against rtol", slope)
    assert all(a < b for a, b in zip(steps, steps[1:], strict=False))
    assert all(a > b for a, b in zip(errs, errs[1:], strict=False))
    assert steps[0] < ref.time.size / 4  # at loose tolerance far fewer steps than samples
    assert slope > 0.5
