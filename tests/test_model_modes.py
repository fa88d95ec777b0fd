"""Natural frequencies and critical speeds against independent references.

References: docs/model-notes.md section 2 (figures computed for the seed rotor, 5 significant
figures, so tolerances of half a unit in the last digit), closed forms derived here by hand, and
agreement of the two independent routes of :mod:`rubrotor.linear.shaft`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from seed import seed_shaft

from rubrotor.linear.shaft import (
    critical_speeds,
    critical_speeds_numeric,
    first_forward_critical,
    natural_frequencies,
    whirl_frequencies,
    whirl_frequencies_eig,
)
from rubrotor.rotors.shaft import Shaft

TWO_PI = 2 * math.pi


def freqs(shaft, branch, whirl="forward", speed=0.0):
    return [
        m.frequency_hz
        for m in natural_frequencies(shaft, speed)
        if m.branch == branch and m.whirl == whirl
    ]


# ---- figures of model-notes section 2 ----------------------------------------------------------
def test_seed_bending_at_rest():
    for whirl in ("forward", "backward"):
        got = freqs(seed_shaft(), "bending", whirl)
        assert got == pytest.approx([1193.2, 4153.2, 7970.7], abs=0.05)


def test_seed_shear_branch_at_rest():
    got = freqs(seed_shaft(), "shear")
    assert got == pytest.approx([22381, 25720, 30154], abs=0.5)


def test_seed_euler_bernoulli():
    got = freqs(seed_shaft(theory="euler-bernoulli"), "bending")
    assert got == pytest.approx([1268.0, 5072.1, 11412.2], abs=0.05)


def test_seed_first_forward_critical():
    om = first_forward_critical(seed_shaft())
    assert om == pytest.approx(7742.5, abs=0.05)
    assert om / TWO_PI == pytest.approx(1232.3, abs=0.05)
    # "1.5 times the first critical" is 1848 Hz (the seed's 2.6 kHz is not reproducible)
    assert 1.5 * om / TWO_PI == pytest.approx(1848, abs=0.5)


def test_cowper_coefficient():
    s = seed_shaft(shear_coefficient="cowper")
    assert freqs(s, "bending") == pytest.approx([1181.4, 4038.2, 7626.3], abs=0.05)
    assert first_forward_critical(s) / TWO_PI == pytest.approx(1218.5, abs=0.05)


# ---- closed forms --------------------------------------------------------------------------------
@pytest.mark.parametrize("coef", ["seed", "cowper", 0.5])
@pytest.mark.parametrize("bore", [0.0, 0.06])
def test_timoshenko_at_rest_closed_form(coef, bore):
    """At Omega = 0 the determinant of the two-field mode n is a quadratic in w^2.

    det [[kGA k^2 - rho A w^2, -kGA k], [-kGA k, EI k^2 + kGA - rho I w^2]] = 0
    => rhoA rhoI W^2 - (rhoA (EI k^2 + kGA) + rhoI kGA k^2) W + kGA EI k^4 = 0,  W = w^2.
    """
    s = seed_shaft(shear_coefficient=coef, bore_diameter=bore, modes=5)
    area = math.pi * (0.1**2 - bore**2) / 4
    inertia = math.pi * (0.1**4 - bore**4) / 64
    ei = 71e9 * inertia
    kga = s.kappa * 26.2e9 * area
    rho_a, rho_i = 2660 * area, 2660 * inertia
    for n in range(1, 6):
        k = n * math.pi / 0.4
        a = rho_a * rho_i
        b = -(rho_a * (ei * k**2 + kga) + rho_i * kga * k**2)
        c = kga * ei * k**4
        q = -0.5 * (b - math.sqrt(b * b - 4 * a * c))  # b < 0: no cancellation
        w_shear, w_bend = math.sqrt(q / a), math.sqrt(c / q)
        w = np.abs(whirl_frequencies(s, n, 0.0))
        assert w[1] == pytest.approx(w_bend, rel=1e-12)
        assert w[2] == pytest.approx(w_bend, rel=1e-12)
        assert w[0] == pytest.approx(w_shear, rel=1e-12)
        assert w[3] == pytest.approx(w_shear, rel=1e-12)
        assert np.abs(whirl_frequencies_eig(s, n, 0.0)) == pytest.approx(
            [w_shear, w_bend, w_bend, w_shear], rel=1e-12
        )


def test_euler_bernoulli_closed_form():
    s = seed_shaft(theory="euler-bernoulli", modes=6)
    ei = 71e9 * math.pi * 0.1**4 / 64
    rho_a = 2660 * math.pi * 0.1**2 / 4
    for n in range(1, 7):
        exact = (n * math.pi / 0.4) ** 2 * math.sqrt(ei / rho_a)
        for speed in (0.0, 30000.0):
            w = whirl_frequencies(s, n, speed)
            assert w == pytest.approx([-exact, exact], rel=1e-14)


# ---- two routes ----------------------------------------------------------------------------------
SPEEDS = np.linspace(0.0, 60000.0, 13)


def _assert_routes_agree(shaft):
    for n in range(1, shaft.modes + 1):
        poly = whirl_frequencies(shaft, n, SPEEDS)
        for i, om in enumerate(SPEEDS):
            eig = whirl_frequencies_eig(shaft, n, om)
            np.testing.assert_allclose(poly[i], eig, rtol=1e-9, atol=0)


@pytest.mark.parametrize("theory", ["timoshenko", "rayleigh", "euler-bernoulli"])
@pytest.mark.parametrize("bore", [0.0, 0.07])
def test_routes_agree_seed(theory, bore):
    _assert_routes_agree(seed_shaft(theory=theory, bore_diameter=bore))


@settings(max_examples=40, deadline=None)
@given(
    length=st.floats(0.2, 3.0),
    diameter=st.floats(0.01, 0.3),
    bore_ratio=st.sampled_from([0.0, 0.0, 0.3, 0.8]),
    youngs=st.floats(50e9, 250e9),
    nu=st.floats(0.2, 0.45),
    density=st.floats(1500.0, 9000.0),
    coef=st.sampled_from(["cowper", "seed"]),
    theory=st.sampled_from(["timoshenko", "rayleigh", "euler-bernoulli"]),
    gyroscopic=st.booleans(),
)
def test_routes_agree_random_shafts(
    length, diameter, bore_ratio, youngs, nu, density, coef, theory, gyroscopic
):
    s = Shaft(
        length=length,
        diameter=diameter,
        bore_diameter=bore_ratio * diameter,
        youngs_modulus=youngs,
        poisson_ratio=nu,
        density=density,
        shear_coefficient=coef,
        theory=theory,
        gyroscopic=gyroscopic,
        modes=3,
    )
    _assert_routes_agree(s)


# ---- critical speeds ---------------------------------------------------------------------------
@pytest.mark.parametrize("coef", ["seed", "cowper"])
def test_critical_speeds_two_routes(coef):
    s = seed_shaft(shear_coefficient=coef)
    crits = critical_speeds(s)
    # 3 modes x (forward bending, backward bending, backward shear): forward shear never crosses
    assert len(crits) == 9
    assert sorted((c.n, c.branch, c.whirl) for c in crits) == sorted(
        (n, b, w)
        for n in (1, 2, 3)
        for b, w in (("bending", "forward"), ("bending", "backward"), ("shear", "backward"))
    )
    for c in crits:
        numeric = critical_speeds_numeric(s, c.n, c.whirl, c.branch)
        assert numeric == pytest.approx(c.speed_rad_s, rel=1e-9)
        # definition: the whirl frequency of that branch equals the spin there
        w = whirl_frequencies_eig(s, c.n, c.speed_rad_s)
        assert np.min(np.abs(np.abs(w) - c.speed_rad_s)) == pytest.approx(0, abs=1e-6 * w.max())


def test_critical_speeds_rayleigh_and_eb_two_routes():
    for theory in ("rayleigh", "euler-bernoulli"):
        s = seed_shaft(theory=theory)
        for c in critical_speeds(s):
            numeric = critical_speeds_numeric(s, c.n, c.whirl, c.branch)
            assert numeric == pytest.approx(c.speed_rad_s, rel=1e-9)


# ---- limits ------------------------------------------------------------------------------------
def test_timoshenko_to_rayleigh_as_shear_stiffness_grows():
    """Bending frequencies -> Rayleigh with an error proportional to 1/(kappa G)."""
    speed = 20000.0
    ray = seed_shaft(theory="rayleigh")
    errs = []
    kappas = [1e3, 1e4, 1e5]
    for kappa in kappas:
        tim = seed_shaft(shear_coefficient=kappa)
        err = []
        for n in (1, 2, 3):
            wt = whirl_frequencies(tim, n, speed)[1:3]  # bending backward, forward
            wr = whirl_frequencies(ray, n, speed)
            err.append(np.max(np.abs(wt / wr - 1)))
        errs.append(max(err))
    assert errs[-1] < 1e-5
    # error x kappa is constant: first order in 1/(kappa G)
    for e1, e2 in zip(errs, errs[1:], strict=False):
        assert e1 / e2 == pytest.approx(10, rel=0.01)


def test_rayleigh_to_euler_bernoulli_as_slenderness_vanishes():
    """f_R/f_EB - 1 ~ -(n pi r)^2 / 2 (rotatory inertia) at rest: error ~ r^2."""
    rel = []
    rs = []
    for d in (0.01, 0.001, 0.0001):
        ray = seed_shaft(diameter=d, theory="rayleigh")
        eb = seed_shaft(diameter=d, theory="euler-bernoulli")
        f_r = whirl_frequencies(ray, 1, 0.0)[1]
        f_eb = whirl_frequencies(eb, 1, 0.0)[1]
        rel.append(abs(f_r / f_eb - 1))
        rs.append(ray.slenderness)
    for e, r in zip(rel, rs, strict=True):
        assert e / r**2 == pytest.approx(math.pi**2 / 2, rel=1e-3)
    assert rel[-1] < 1e-7


def test_timoshenko_to_euler_bernoulli_as_slenderness_vanishes():
    for n in (1, 2, 3):
        scaled = []
        for d in (0.002, 0.001, 0.0005):
            tim = seed_shaft(diameter=d)
            eb = seed_shaft(diameter=d, theory="euler-bernoulli")
            ratio = whirl_frequencies(tim, n, 0.0)[2] / whirl_frequencies(eb, n, 0.0)[1]
            scaled.append((1 - ratio) / tim.slenderness**2)
        # (1 - f/f_EB) / r^2 tends to a constant: (n pi)^2 (1 + delta) / 2
        assert scaled[-1] == pytest.approx(
            (n * math.pi) ** 2 * (1 + tim.shear_parameter) / 2, rel=1e-3
        )
        assert scaled[0] == pytest.approx(scaled[-1], rel=2e-3)


@pytest.mark.parametrize("theory", ["timoshenko", "rayleigh"])
def test_no_gyroscopic_forward_equals_backward(theory):
    s = seed_shaft(theory=theory, gyroscopic=False)
    for om in (0.0, 15000.0, 60000.0):
        for n in (1, 2, 3):
            w = whirl_frequencies(s, n, om)
            np.testing.assert_allclose(w, -w[::-1], rtol=1e-12)
    g = seed_shaft(theory=theory)
    w = whirl_frequencies(g, 1, 60000.0)
    assert abs(w[-1]) > abs(w[0]) if theory == "rayleigh" else abs(w[2]) > abs(w[1])


def test_shaft_replace_revalidates():
    s = seed_shaft()
    assert dataclasses.replace(s, modes=2).modes == 2
