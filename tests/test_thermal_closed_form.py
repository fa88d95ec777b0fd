"""The thermal-rub closed form (rubrotor.studies.thermal.closed_form) of a Jeffcott rotor.

References: (1) a second numerical route written here from the model's definition only: the
steady synchronous orbit of the Jeffcott rotor with a bow, solved by scipy.optimize.root on
its two real equations, and the slow dynamics' Jacobian by central differences of that solve;
(2) the textbook result for the heat vector proportional to the vibration vector (clearance
0): lambda = (-1 + G kappa e^{-i phi}/(D + k_c (1 + i mu)))/tau, derived on
docs/guide/thermal.md, whose real part is < -1/tau above sqrt((k + k_c)/m).
"""

import math

import numpy as np
import pytest
import scipy.optimize

from rubrotor.rotors.forces import ThermalBow
from rubrotor.studies.thermal import closed_form, jeffcott_receptances

M, K, C = 10.0, 4e5, 80.0  # kg, N/m, N s/m: first critical 200 rad/s
KC, MU, R, G = 1e5, 0.2, 0.05, 20e-6  # N/m, 1, m, m
UNB = 5e-4  # kg m
TH = ThermalBow(time_constant=120.0, bow_per_heat=2e-6, hot_spot_lag=0.3)


def _orbit(b, speed):
    """Steady synchronous deflection Z (m) under bow b (m): fsolve on the force balance."""
    d = K - M * speed**2 + 1j * C * speed
    f = UNB * speed**2 + K * b

    def res(x):
        z = complex(x[0], x[1])
        pen = max(abs(z) - G, 0.0)
        r = d * z + KC * pen * (1 + 1j * MU) * z / abs(z) - f
        return [r.real / K, r.imag / K]

    z0 = f / (d + KC * (1 + 1j * MU))
    x = scipy.optimize.root(res, [z0.real, z0.imag], tol=1e-15).x
    return complex(x[0], x[1])


def _rate(bv, speed):
    b = complex(bv[0], bv[1])
    z = _orbit(b, speed)
    heat = MU * KC * max(abs(z) - G, 0.0) * R * speed * z / abs(z)
    db = (-b + TH.bow_per_heat * np.exp(-1j * TH.hot_spot_lag) * heat) / TH.time_constant
    return np.array([db.real, db.imag])


@pytest.mark.parametrize("speed", [150.0, 185.0, 240.0])
def test_closed_form_equals_a_numerical_route(speed):
    """Steady bow and both eigenvalues equal those of fsolve + central differences to 1e-6."""
    hc, hb, zu = jeffcott_receptances(M, K, C, speed, UNB)
    lin = closed_form(hc, hb, zu, speed=speed, clearance=G, contact_stiffness=KC,
                      friction=MU, radius=R, thermal=TH)  # fmt: skip
    b0 = scipy.optimize.root(
        lambda v: _rate(v, speed) * TH.time_constant,
        [lin.bow[0].real * 1.1, lin.bow[0].imag * 0.9],
        tol=1e-15,
    ).x
    assert abs(complex(*b0) - lin.bow[0]) < 1e-7 * abs(lin.bow[0])
    assert abs(abs(lin.high_spot[0]) - G) > 0.05 * G  # well in contact: the law is exercised
    h = 1e-4 * abs(lin.bow[0])
    jac = np.column_stack([(_rate(b0 + e, speed) - _rate(b0 - e, speed)) / (2 * h)
                           for e in (np.array([h, 0]), np.array([0, h]))])  # fmt: skip
    lam = np.linalg.eigvals(jac)
    for ref in lin.eigenvalues:  # the pair (conjugates), or two real roots
        assert np.min(np.abs(lam - ref)) < 1e-6 * abs(ref)


def test_vector_heat_grows_only_below_the_critical():
    """Clearance 0 (heat proportional to the vibration vector): the closed form is the complex
    formula, and with the hot spot at the high spot it grows only below sqrt((k + k_c)/m)."""
    at_spot = ThermalBow(time_constant=60.0, bow_per_heat=2e-4, hot_spot_lag=0.0)
    crit = math.sqrt((K + KC) / M)
    rates = []
    for speed in np.linspace(0.3, 2.0, 35) * crit:
        hc, hb, zu = jeffcott_receptances(M, K, C, speed, UNB)
        lin = closed_form(hc, hb, zu, speed=speed, clearance=0.0, contact_stiffness=KC,
                          friction=MU, radius=R, thermal=at_spot)  # fmt: skip
        d = K - M * speed**2 + 1j * C * speed + KC * (1 + 1j * MU)
        gain = at_spot.bow_per_heat * MU * R * speed * KC
        lam = (-1 + gain * K / d) / at_spot.time_constant
        assert abs(lin.eigenvalues[0] - lam) < 1e-12 * abs(lam)
        rates.append((speed, lin.growth_rate))
    below = [r for s, r in rates if s < crit]
    above = [r for s, r in rates if s > crit]
    assert max(below) > 0.0  # this gain makes the spiral grow somewhere below the critical
    assert max(above) < -1 / at_spot.time_constant  # damped above, faster than tau alone
