"""Short fluid films (rubrotor.core.film, rubrotor.forces.fluid_film) against closed forms.

References, each derived independently of the compiled quadrature:

* Ocvirk's short bearing, pi-film, journal at rest: radial and tangential forces
  ``F_r = mu U L^3 eps^2 / (c^2 (1 - eps^2)^2)``, ``F_t = pi mu U L^3 eps / (4 c^2 (1 - eps^2)^1.5)``
  with ``U = R omega`` (Childs 1993, eq. 3.38; Friswell et al. 2010, sec. 5.5.2); the load
  ``W = hypot(F_r, F_t)`` gives the Sommerfeld relation
  ``S (L/D)^2 = (1 - eps^2)^2 / (pi eps sqrt(16 eps^2 + pi^2 (1 - eps^2)))`` solved here for eps
  by SciPy's brentq at xtol 1e-15, and the attitude angle ``tan(phi) = pi sqrt(1 - eps^2) / (4 eps)``.
* The short bearing's linearised stiffness and damping in the load frame (Friswell et al. 2010,
  table 5.1, as also coded in ROSS's fluid_flow module), and central differences of the force.
* The short pi-film squeeze-film damper on a circular centred orbit of whirl speed Omega:
  ``F_r = -2 mu R L^3 Omega eps^2 / (c^2 (1 - eps^2)^2)``,
  ``F_t = -pi mu R L^3 Omega eps / (2 c^2 (1 - eps^2)^1.5)`` (San Andres 2010, eq. 9).
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rubrotor.core.film import FULL_FILM, PI_FILM, Film, film_force, film_force_jac
from rubrotor.errors import InputError
from rubrotor.forces.fluid_film import ShortJournal, SqueezeFilm

R, L, C, MU = 0.05, 0.02, 100e-6, 0.02
FILM = Film(R, L, C, MU, PI_FILM)
EPS = (0.05, 0.3, 0.6, 0.9, 0.99)


def _rel(a, b):
    return abs(a - b) / abs(b)


@pytest.mark.parametrize("eps", EPS)
def test_journal_at_rest_equals_ocvirk(eps):
    """Radial and tangential forces of the pi-film short bearing, any direction of eccentricity."""
    omega = 300.0
    u = R * omega
    fr = mu_u = MU * u * L**3 / C**2
    fr = mu_u * eps**2 / (1 - eps**2) ** 2
    ft = mu_u * math.pi * eps / (4 * (1 - eps**2) ** 1.5)
    for beta in (0.0, 1.0, -2.5):
        e = np.array([math.cos(beta), math.sin(beta)])
        f = film_force(eps * C * e[0], eps * C * e[1], 0.0, 0.0, omega, FILM)
        radial = f @ e
        tangential = f @ np.array([-e[1], e[0]])  # 90 degrees ahead in the spin's sense
        assert _rel(-radial, fr) < 1e-12
        assert _rel(tangential, ft) < 1e-12


@pytest.mark.parametrize("eps", EPS)
def test_full_film_has_no_radial_force_and_twice_the_tangential(eps):
    omega = 300.0
    f = film_force(eps * C, 0.0, 0.0, 0.0, omega, Film(R, L, C, MU, FULL_FILM))
    ft = math.pi * MU * R * omega * L**3 * eps / (4 * C**2 * (1 - eps**2) ** 1.5)
    assert abs(f[0]) < 1e-12 * ft
    assert _rel(f[1], 2 * ft) < 1e-12


@pytest.mark.parametrize("eps", EPS)
def test_squeeze_film_circular_centred_orbit(eps):
    """pi-film damper forces on a circular centred orbit, at several points of the orbit."""
    whirl = 120.0
    base = MU * R * L**3 * whirl / C**2
    fr = -2 * base * eps**2 / (1 - eps**2) ** 2
    ft = -math.pi * base * eps / (2 * (1 - eps**2) ** 1.5)
    for phase in (0.0, 2.0, 4.0):
        e = np.array([math.cos(phase), math.sin(phase)])
        t = np.array([-e[1], e[0]])
        pos, vel = eps * C * e, eps * C * whirl * t
        f = film_force(pos[0], pos[1], vel[0], vel[1], 0.0, FILM)
        assert _rel(f @ e, fr) < 1e-8
        assert _rel(f @ t, ft) < 1e-8


def _ocvirk_eps(sommerfeld, l_over_d):
    def g(e):
        q = math.sqrt(16 * e * e + math.pi**2 * (1 - e * e))
        return (1 - e * e) ** 2 / (math.pi * e * q) - sommerfeld * l_over_d**2

    return brentq(g, 1e-12, 1 - 1e-14, xtol=1e-15, rtol=4 * np.finfo(float).eps)


@pytest.mark.parametrize("load", [20.0, 300.0, 2000.0, 2e4, 2e5])
def test_equilibrium_equals_ocvirk_against_sommerfeld(load):
    bearing = ShortJournal(2 * R, L, C, MU)
    omega = 300.0
    eq = bearing.equilibrium([0.0, -load], omega)
    expected_s = MU * omega / (2 * math.pi) * L * 2 * R / load * (R / C) ** 2
    assert _rel(eq.sommerfeld, expected_s) < 1e-14
    eps = _ocvirk_eps(eq.sommerfeld, L / (2 * R))
    assert _rel(eq.eccentricity_ratio, eps) < 1e-8
    attitude = math.atan(math.pi * math.sqrt(1 - eps**2) / (4 * eps))
    assert _rel(eq.attitude_angle_rad, attitude) < 1e-8
    # the film carries the load there
    f = bearing.force(eq.position, spin=omega)
    assert np.hypot(*(f + [0.0, -load])) < 1e-10 * load


def _friswell(load, eps, omega):
    """Short-bearing K and C in the frame (horizontal, vertical) of a vertical load."""
    h0 = 1 / (math.pi**2 * (1 - eps**2) + 16 * eps**2) ** 1.5
    s = math.sqrt(1 - eps**2)
    a = load / C
    k = a * h0 * np.array([
        [4 * (math.pi**2 * (2 - eps**2) + 16 * eps**2),
         math.pi * (math.pi**2 * (1 - eps**2) ** 2 - 16 * eps**4) / (eps * s)],
        [-math.pi * (math.pi**2 * (1 - eps**2) * (1 + 2 * eps**2) + 32 * eps**2 * (1 + eps**2)) / (eps * s),
         4 * (math.pi**2 * (1 + 2 * eps**2) + 32 * eps**2 * (1 + eps**2) / (1 - eps**2))],
    ])  # fmt: skip
    b = load / (C * omega) * h0
    cxy = -8 * (math.pi**2 * (1 + 2 * eps**2) - 16 * eps**2)
    c = b * np.array([
        [2 * math.pi * s * (math.pi**2 * (1 + 2 * eps**2) - 16 * eps**2) / eps, cxy],
        [cxy, 2 * math.pi * (math.pi**2 * (1 - eps**2) ** 2 + 48 * eps**2) / (eps * s)],
    ])  # fmt: skip
    return k, c


@pytest.mark.parametrize("load", [300.0, 2000.0, 2e4])
def test_coefficients_equal_closed_form_and_differences(load):
    bearing = ShortJournal(2 * R, L, C, MU)
    omega = 300.0
    eq = bearing.equilibrium([0.0, -load], omega)
    co = bearing.coefficients(eq.position, omega)
    k, c = _friswell(load, eq.eccentricity_ratio, omega)
    assert np.abs(co.stiffness - k).max() < 1e-6 * np.abs(k).max()
    assert np.abs(co.damping - c).max() < 1e-6 * np.abs(c).max()
    # second route: central differences of the force (steps 1e-6 of the clearance / velocity scale)
    state = np.array([*eq.position, 0.0, 0.0])
    scales = np.array([C, C, C * omega, C * omega]) * 1e-6
    num = np.zeros((2, 4))
    for j in range(4):
        up, dn = state.copy(), state.copy()
        up[j] += scales[j]
        dn[j] -= scales[j]
        num[:, j] = -(film_force(*up, omega, FILM) - film_force(*dn, omega, FILM)) / (2 * scales[j])
    assert np.abs(co.stiffness - num[:, :2]).max() < 1e-6 * np.abs(k).max()
    assert np.abs(co.damping - num[:, 2:]).max() < 1e-6 * np.abs(c).max()


def test_jacobian_equals_differences_off_equilibrium():
    """Whirling, off-centre, spinning: every column of the Jacobian (y, z, vy, vz, omega)."""
    omega = 400.0
    state = np.array([0.3 * C, -0.7 * C, 0.2 * C * omega, -0.4 * C * omega, omega])
    _, jac = film_force_jac(*state, FILM)
    h = np.array([C, C, C * omega, C * omega, omega]) * 1e-6
    for j in range(5):
        up, dn = state.copy(), state.copy()
        up[j] += h[j]
        dn[j] -= h[j]
        col = (film_force(*up, FILM) - film_force(*dn, FILM)) / (2 * h[j])
        assert np.abs(jac[:, j] - col).max() < 1e-6 * np.abs(jac[:, j]).max()


def test_touching_the_bearing_gives_nan_not_a_number():
    f, jac = film_force_jac(C, 0.0, 0.0, 0.0, 300.0, FILM)
    assert np.isnan(f).all() and np.isnan(jac).all()


@pytest.mark.parametrize(
    ("key", "kwargs", "match"),
    [
        ("radial_clearance", {"radial_clearance": -1e-4}, "bearing.radial_clearance = -0.0001"),
        ("viscosity", {"viscosity": 0.0}, "bearing.viscosity = 0.0"),
        ("length", {"length": 0.3}, "L/D = 3"),
        ("cavitation", {"cavitation": "reynolds"}, "bearing.cavitation = 'reynolds'"),
        ("viscosity", {"viscosity": float("nan")}, "bearing.viscosity = nan"),
    ],
)
def test_bad_input_names_the_key(key, kwargs, match):
    args = {"diameter": 0.1, "length": 0.02, "radial_clearance": 1e-4, "viscosity": 0.02,
            "name": "bearing"}  # fmt: skip
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        ShortJournal(**args)


def test_squeeze_film_refuses_negative_centering_stiffness():
    with pytest.raises(InputError, match="damper.centering_stiffness = -5"):
        SqueezeFilm(0.1, 0.02, 1e-4, 0.02, name="damper", centering_stiffness=-5.0)


def test_overload_is_refused_with_the_key():
    bearing = ShortJournal(2 * R, L, C, MU, name="bearing[2]")
    with pytest.raises(InputError, match=r"bearing\[2\].load"):
        bearing.equilibrium([0.0, -1e12], 300.0)
