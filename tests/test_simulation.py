"""Simulation against independent references (see rubrotor/reference.py for their provenance)."""

import math

import numpy as np
import pytest

from rubrotor.engine.settings import Integrator
from rubrotor.engine.simulate import simulate_system
from rubrotor.errors import InputError
from rubrotor.linear.shaft import first_forward_critical
from rubrotor.reference import exact_unbalance_response, solve_ivp_reference
from rubrotor.rotors.forces import Contact, ModalDamping, RadialLoad, Unbalance
from rubrotor.rotors.shaft import Dimensionless, Shaft

SEED = Shaft(
    length=0.4,
    diameter=0.1,
    youngs_modulus=71e9,
    density=2660,
    shear_modulus=26.2e9,
    shear_coefficient="seed",
)
OMEGA = 1.5 * first_forward_critical(SEED)


def orbit(r, station=0):
    return r.channels[6 * station] + 1j * r.channels[6 * station + 1]


# a case that stays in contact most of the time: a side load presses the rotor on the stator
PRESSED = dict(
    contact=Contact(clearance=1e-4, stiffness=8.6e9, damping=0.02, friction=0.1),
    load=RadialLoad(5e4, 0.0),
    unbalance=Unbalance(1e-4),
)
PRESSED_REF = dict(
    law="hertz", k=8.6e9, c=0.02, g=1e-4, mu=0.1, surface_speed=0.05 * OMEGA, v_reg=1e-3
)


@pytest.fixture(scope="module")
def pressed_reference():
    times = np.arange(0, 10 * 2 * math.pi / OMEGA * (1 + 1e-12), 0.01 / OMEGA)
    ref = solve_ivp_reference(SEED, OMEGA, times, me=1e-4, load=5e4 + 0j, contact=PRESSED_REF)
    return times, ref


@pytest.mark.parametrize("kw", [{}, {"dtau": 1e-3}], ids=["default-adaptive", "dtau=0.001"])
def test_no_contact_matches_exact_linear_solution(kw):
    integ = Integrator(revolutions=5, **kw)
    r = simulate_system(SEED, OMEGA, integ, Unbalance(1e-4, position=0.15))
    ref = exact_unbalance_response(SEED, OMEGA, 1e-4, 0.15, 0.2, r.time)
    err = np.max(np.abs(orbit(r) - ref)) / np.max(np.abs(ref))
    assert r.status == "complete"
    assert err < 1e-6


def test_no_contact_with_damping_and_probe():
    integ = Integrator(revolutions=3, dtau=2e-3, probes=(0.1,))
    r = simulate_system(SEED, OMEGA, integ, Unbalance(1e-4), damping=ModalDamping((0.02,)))
    for station, x in ((0, 0.2), (1, 0.1)):
        ref = exact_unbalance_response(SEED, OMEGA, 1e-4, 0.2, x, r.time, zeta=0.02)
        assert np.max(np.abs(orbit(r, station) - ref)) < 1e-6 * np.max(np.abs(ref))


def test_velocity_and_acceleration_are_derivatives_of_displacement():
    r = simulate_system(SEED, OMEGA, Integrator(revolutions=2, dtau=1e-3), Unbalance(1e-4))
    dt = r.time[1] - r.time[0]
    p, v, a = (r.channels[i] for i in (0, 2, 4))
    dp = (p[2:] - p[:-2]) / (2 * dt)
    dv = (v[2:] - v[:-2]) / (2 * dt)
    assert np.max(np.abs(dp - v[1:-1])) < 1e-4 * np.max(np.abs(v))
    assert np.max(np.abs(dv - a[1:-1])) < 1e-3 * np.max(np.abs(a))


def _slope(hs, errs):
    return np.polyfit(np.log(hs), np.log(errs), 1)[0]


def test_exponential_is_second_order_in_contact(pressed_reference):
    times, ref = pressed_reference
    hs, errs = [], []
    for dtau in (5e-3, 2.5e-3, 1.25e-3, 6.25e-4):
        every = round(0.01 / dtau)
        r = simulate_system(
            SEED, OMEGA, Integrator(revolutions=10, dtau=dtau, save_every=every), **PRESSED
        )
        p = orbit(r)
        n = min(len(p), len(ref))
        hs.append(dtau)
        errs.append(np.max(np.abs(p[:n] - ref[:n])))
    assert Integrator(revolutions=1).order == 2
    assert _slope(hs, errs) == pytest.approx(2.0, abs=0.2)


def test_abm_is_fourth_order():
    hs, errs = [], []
    for dtau in (0.008, 0.004, 0.002):
        r = simulate_system(
            SEED, OMEGA, Integrator(revolutions=3, method="abm", dtau=dtau), Unbalance(1e-4)
        )
        ref = exact_unbalance_response(SEED, OMEGA, 1e-4, 0.2, 0.2, r.time)
        hs.append(dtau)
        errs.append(np.max(np.abs(orbit(r) - ref)))
    assert Integrator(revolutions=1, method="abm", dtau=1e-3).order == 4
    assert _slope(hs, errs) == pytest.approx(4.0, abs=0.3)


def test_contact_matches_solve_ivp(pressed_reference):
    times, ref = pressed_reference
    r = simulate_system(
        SEED, OMEGA, Integrator(revolutions=10, dtau=1e-3, save_every=10), **PRESSED
    )
    assert np.mean(r.channels[6] > 0) > 0.8  # most of the time in contact
    p = orbit(r)
    assert np.max(np.abs(p - ref)) < 1e-6 * np.max(np.abs(ref))
    ra = simulate_system(SEED, OMEGA, Integrator(revolutions=10, output_dtau=0.01), **PRESSED)
    assert np.max(np.abs(orbit(ra) - ref)) < 3e-5 * np.max(np.abs(ref))
    rb = simulate_system(
        SEED, OMEGA, Integrator(revolutions=10, method="abm", dtau=1e-3, save_every=10), **PRESSED
    )
    assert np.max(np.abs(orbit(rb) - ref)) < 1e-6 * np.max(np.abs(ref))


def _energy_residual(dtau):
    c = Contact(clearance=1e-4, stiffness=8.6e9, damping=0.05, friction=0.1)
    r = simulate_system(
        SEED,
        OMEGA,
        Integrator(revolutions=3, dtau=dtau),
        Unbalance(2e-4),
        c,
        RadialLoad(3e4, 1e4),
        ModalDamping((0.01,)),
        track_energy=True,
    )
    w = r.work
    assert np.mean(r.channels[6] > 0) > 0.3
    assert w["dissipated_modal_damping_J"] > 0 and w["work_friction_J"] < 0
    assert w["dissipated_contact_damping_J"] > 0
    # the contact work includes its elastic part, so the balance is on the rotor's own energy
    lhs = w["mechanical_energy_end_J"] - w["mechanical_energy_start_J"]
    rhs = (
        w["work_unbalance_J"]
        + w["work_load_J"]
        + w["work_contact_J"]
        - w["dissipated_modal_damping_J"]
    )
    scale = max(abs(w["work_unbalance_J"]), abs(w["work_load_J"]), w["mechanical_energy_end_J"])
    return abs(lhs - rhs) / scale


def test_energy_balance_with_contact():
    """Work of unbalance, load, contact (elastic, Hunt-Crossley, friction) and modal damping equals
    the change of the rotor's energy. The works are trapezoidal sums over the steps (O(h^2)), the
    energy is exact at the steps, so the residual must fall 4x per halving and be < 1e-6."""
    coarse = _energy_residual(2e-4)
    fine = _energy_residual(1e-4)
    assert fine < 1e-6
    assert coarse / fine == pytest.approx(4.0, rel=0.25)


def _friction_power(r):
    p = orbit(r)
    v = r.channels[2] + 1j * r.channels[3]
    t = 1j * p / np.abs(p)
    return r.channels[7], (np.conj(t) * v).real


def test_physical_friction_never_feeds_forward_whirl():
    nd = Dimensionless(SEED, OMEGA)
    c = Contact(
        clearance=nd.clearance_si(3e-3),
        stiffness=nd.contact_stiffness_si(1e3),
        damping=nd.contact_damping_si(1e2),
        friction=0.2,
    )
    r = simulate_system(SEED, OMEGA, Integrator(revolutions=20, dtau=1e-3), Unbalance(2e-3), c)
    ft, vt = _friction_power(r)
    touching = r.channels[6] > 0
    forward = touching & (vt > 0)
    assert forward.sum() > 100
    assert np.all(ft[forward] * vt[forward] <= 0)
    seed = simulate_system(
        SEED,
        OMEGA,
        Integrator(revolutions=20, dtau=1e-3),
        Unbalance(2e-3),
        Contact(**{**c.__dict__, "friction_sign": "seed"}),
    )
    ft_s, vt_s = _friction_power(seed)
    fwd_s = (seed.channels[6] > 0) & (vt_s > 0)
    assert np.all(ft_s[fwd_s] > 0)  # the seed's sign pushes along the whirl


@pytest.mark.parametrize(
    "gap,bh", [(3e-3, 1e2), (3.5e-3, 1e2), (3.5e-3, 1e3)], ids=["case1", "case2", "case3"]
)
@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
def test_seed_cases_stay_bounded_for_1000_revolutions(gap, bh):
    nd = Dimensionless(SEED, OMEGA)
    c = Contact(
        clearance=nd.clearance_si(gap),
        stiffness=nd.contact_stiffness_si(1e3),
        damping=nd.contact_damping_si(bh),
        friction=0.02,
    )
    r = simulate_system(SEED, OMEGA, Integrator(revolutions=1000), Unbalance(2e-3), c)
    assert r.status == "complete"
    d = np.abs(orbit(r))
    assert np.all(np.isfinite(d))
    assert (r.channels[6] > 0).any()
    # the late orbit is no larger than the early one: no growth without bound
    n = len(d) // 10
    assert d[-n:].max() < 1.5 * d[:n].max() + c.clearance


def test_divergence_is_reported_and_data_kept():
    integ = Integrator(revolutions=10, dtau=1e-3, max_displacement=1e-5)
    r = simulate_system(SEED, OMEGA, integ, Unbalance(1e-3))
    assert r.status == "partial"
    assert "diverged" in r.message and "t =" in r.message
    assert 1 < len(r.time) < 10 * 2 * math.pi / 1e-3
    assert np.all(np.abs(orbit(r)) <= 1e-5)


@pytest.mark.parametrize(
    "make,field",
    [
        (lambda: Contact(clearance=0.0, stiffness=1e9), "contact.clearance"),
        (lambda: Contact(clearance=1e-3, stiffness=-1.0), "contact.stiffness"),
        (lambda: Contact(clearance=1e-3, stiffness=1e9, friction=-0.1), "contact.friction"),
        (lambda: Contact(clearance=float("nan"), stiffness=1e9), "contact.clearance"),
        (
            lambda: Shaft(
                length=0.4,
                diameter=0.1,
                youngs_modulus=71e9,
                density=2660,
                poisson_ratio=0.3,
                modes=0,
            ),
            "shaft.modes",
        ),
        (lambda: Integrator(revolutions=-1), "simulation.revolutions"),
        (lambda: Integrator(revolutions=1, method="rk45"), "simulation.method"),
        (
            lambda: simulate_system(
                SEED,
                OMEGA,
                Integrator(revolutions=1),
                contact=Contact(clearance=1e-3, stiffness=1e9, position=0.5),
            ),
            "contact.position",
        ),
        (lambda: simulate_system(SEED, float("nan"), Integrator(revolutions=1)), "speed"),
        (
            lambda: simulate_system(SEED, OMEGA, Integrator(revolutions=1, probes=(-0.1,))),
            "simulation.probes",
        ),
    ],
)
def test_bad_input_names_the_field(make, field):
    with pytest.raises(InputError) as exc:
        make()
    assert field in str(exc.value)


def test_adaptive_error_follows_tolerance(pressed_reference):
    """Tightening rtol/atol 100x must cut the error against the reference at least 10x, and the
    steps taken must grow sub-linearly (the third-order hold in contact)."""
    _, ref = pressed_reference
    errs, steps = [], []
    for rtol in (1e-5, 1e-7):
        # coarse output (0.2 rad) so that the steps are chosen by the error control
        integ = Integrator(revolutions=10, output_dtau=0.2, rtol=rtol, atol=rtol * 1e-4)
        r = simulate_system(SEED, OMEGA, integ, **PRESSED)
        p = orbit(r)
        errs.append(np.max(np.abs(p - ref[::20][: len(p)])) / np.max(np.abs(ref)))
        steps.append(r.stats["accepted_steps"])
    assert errs[1] < errs[0] / 10
    assert steps[1] < 100 * steps[0] / 10


def test_phi_functions_match_direct_quadrature():
    from rubrotor.engine.simulate import phi_functions

    z = np.array([1e-6 + 1e-6j, 0.1j, -0.3 + 2j, 3.0 - 1j])
    p1, p2, p3 = phi_functions(z, third=True)
    s = np.linspace(0, 1, 20001)
    for k, pk in ((1, p1), (2, p2), (3, p3)):
        # phi_k(z) = int_0^1 e^{(1-s) z} s^{k-1} / (k-1)! ds
        integrand = np.exp(np.outer(z, 1 - s)) * s ** (k - 1) / math.factorial(k - 1)
        np.testing.assert_allclose(pk, np.trapezoid(integrand, s, axis=1), rtol=1e-7)
