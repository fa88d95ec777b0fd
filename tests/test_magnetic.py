"""Magnetic bearing axis (rubrotor.core.amb) and its PID controller (rubrotor.forces.magnetic).

References: the linearised gains ``ki = 4 k i0 / g0^2``, ``ks = 4 k i0^2 / g0^3`` derived in the
module docstring against central differences of the nonlinear force; the closed loop's eigenvalues
against the roots of its characteristic polynomial
``(m s^2 - ks) s (s + wc) + ki wc (kd s^2 + kp s + ki_c) = 0`` (numpy.roots: a second route that
never forms the state matrix).
"""

import math

import numpy as np
import pytest

from rubrotor.core.amb import magnet_force
from rubrotor.errors import InputError
from rubrotor.forces.magnetic import MagneticBearing

BUILT = {"nominal_gap": 0.5e-3, "bias_current": 2.0, "max_current": 5.0, "kp": 20000.0,
         "ki": 1e5, "kd": 20.0, "cutoff_hz": 2000.0, "coil_turns": 200, "pole_area": 4e-4,
         "pole_angle_rad": math.pi / 8}  # fmt: skip


def _diff(fun, x, h):
    return (fun(x + h) - fun(x - h)) / (2 * h)


def test_linear_gains_equal_differences_of_the_force():
    b = MagneticBearing(**BUILT)
    ki, ks = b.linear_gains
    ax = b.axis
    assert abs(_diff(lambda x: magnet_force(x, 0.0, ax)[0], 0.0, 1e-9) - ks) < 1e-7 * ks
    assert abs(_diff(lambda i: magnet_force(0.0, i, ax)[0], 0.0, 1e-6) - ki) < 1e-7 * ki
    # and the kernel's own derivatives off the centre, below saturation
    x, i = 0.1e-3, 0.7
    f, dfx, dfi = magnet_force(x, i, ax)
    assert abs(_diff(lambda u: magnet_force(u, i, ax)[0], x, 1e-9) - dfx) < 1e-6 * abs(dfx)
    assert abs(_diff(lambda u: magnet_force(x, u, ax)[0], i, 1e-6) - dfi) < 1e-6 * abs(dfi)


def test_saturation_caps_the_force():
    ax = MagneticBearing(**BUILT).axis
    top = magnet_force(0.0, 3.0, ax)[0]  # i0 + i = 5 A = max, i0 - i < 0: one coil only
    assert magnet_force(0.0, 10.0, ax)[0] == top
    assert magnet_force(0.0, 10.0, ax)[2] == 0.0
    assert abs(top - ax.k * 25.0 / ax.gap**2) < 1e-12 * top


def test_given_gains_define_the_same_magnet():
    built = MagneticBearing(**BUILT)
    ki, ks = built.linear_gains
    kw = {k: v for k, v in BUILT.items() if k not in ("coil_turns", "pole_area", "pole_angle_rad")}
    given = MagneticBearing(**kw, current_gain=ki, position_stiffness=ks)
    assert abs(given.pole_constant / built.pole_constant - 1) < 1e-12
    with pytest.raises(InputError, match="bearing.position_stiffness"):
        MagneticBearing(**kw, current_gain=ki, position_stiffness=2 * ks)


@pytest.mark.parametrize("mass", [2.0, 10.0, 40.0])
def test_closed_loop_equals_the_characteristic_polynomial(mass):
    b = MagneticBearing(**BUILT)
    ki, ks = b.linear_gains
    wc = 2 * math.pi * b.cutoff_hz
    lam = np.sort_complex(np.linalg.eigvals(b.closed_loop(mass)))
    # (m s^2 - ks)(s^2 + wc s) + ki wc (kd s^2 + kp s + ki_c)
    poly = np.polyadd(np.polymul([mass, 0.0, -ks], [1.0, wc, 0.0]),
                      ki * wc * np.array([b.kd, b.kp, b.ki]))  # fmt: skip
    roots = np.sort_complex(np.roots(poly))
    assert np.abs(lam - roots).max() < 1e-9 * np.abs(roots).max()
    assert lam.real.max() < 0  # these gains hold the mass


def test_controller_unstable_at_rest_is_refused_with_its_eigenvalue():
    b = MagneticBearing(**{**BUILT, "kp": 100.0, "name": "bearing[2]"})
    with pytest.raises(InputError, match=r"bearing\[2\].kp = 100.0 .*eigenvalue [0-9.e+]+"):
        b.check_stable_at_rest(10.0)


@pytest.mark.parametrize(
    ("change", "match"),
    [({"nominal_gap": -1e-3}, "bearing.nominal_gap = -0.001"),
     ({"max_current": 1.0}, "bearing.max_current = 1.0"),
     ({"cutoff_hz": 0.0}, "bearing.cutoff_hz = 0.0"),
     ({"kd": float("nan")}, "bearing.kd = nan"),
     ({"current_gain": 100.0}, "not both")],
)  # fmt: skip
def test_bad_input_names_the_key(change, match):
    with pytest.raises(InputError, match=match):
        MagneticBearing(**{**BUILT, **change})
