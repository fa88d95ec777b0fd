"""Compiled short-film forces (Ocvirk's short bearing and the short squeeze-film damper), SI.

The journal's centre sits at ``(y, z)`` (m) from the bearing's centre and moves at ``(vy, vz)``
(m/s); the journal spins at ``omega`` (rad/s, positive from y towards z; 0 for a squeeze-film
damper, whose journal does not spin). The film thickness at the angle ``theta`` (from y towards
z) is ``h = c - y cos(theta) - z sin(theta)``. With the axial pressure flow alone (the short
film, ``L/D`` small) Reynolds' equation integrates over the length ``L`` to the mean pressure

    p_bar(theta) = mu L^2 N(theta) / (2 h^3),    N = -omega dh/dtheta - 2 dh/dt
                                                   = A cos(theta) + B sin(theta),
    A = omega z + 2 vy,    B = -omega y + 2 vz,

and the film pushes the journal with ``F = -R L int p_bar (cos, sin) dtheta``. The full film
integrates over the whole circle; the pi-film (Gumbel / half-Sommerfeld: negative pressures set
to zero) over the half circle where ``N > 0``, ``theta in [alpha - pi/2, alpha + pi/2]`` with
``alpha = atan2(B, A)``. ``N`` vanishes at both ends, so the Jacobian of the force is the integral
of the integrand's derivative (no boundary terms).

The integrals are evaluated in Sommerfeld's variable ``xi`` (``1 - eps cos(phi) =
(1 - eps^2)/(1 + eps cos(xi))``, ``phi = theta - beta`` measured from the minimum film): there every
integrand is a trigonometric polynomial of degree at most 4, so a fixed Gauss-Legendre rule of
:data:`NODES` points is exact to round-off for every eccentricity ratio below 1.

Parameters come as one :class:`Film` (a namedtuple numba compiles as a record): ``radius`` (m),
``length`` (m), ``clearance`` (m), ``viscosity`` (Pa s), ``cavitation`` (:data:`FULL_FILM` or
:data:`PI_FILM`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rubrotor.core.filmtypes import FULL_FILM, PI_FILM, Film

__all__ = ["Film", "FULL_FILM", "PI_FILM", "NODES", "film_force", "film_force_jac", "film_sums"]

NODES = 24
"""Gauss-Legendre points per film integral (exact to round-off: see the module docstring)."""

_X, _W = np.polynomial.legendre.leggauss(NODES)


@njit(cache=True)
def _xi_of(phi, k):
    """Sommerfeld's variable of the angle ``phi`` (rad) from the minimum film, unwrapped."""
    turns = math.floor((phi + math.pi) / (2.0 * math.pi))
    local = phi - 2.0 * math.pi * turns
    return 2.0 * math.atan(k * math.tan(0.5 * local)) + 2.0 * math.pi * turns


@njit(cache=True)
def _limits(y, z, vy, vz, omega, cavitation, beta, k):
    """The film's integration interval in Sommerfeld's variable, and whether it carries load."""
    if cavitation == FULL_FILM:
        return -math.pi, math.pi, True
    a = omega * z + 2.0 * vy
    b = -omega * y + 2.0 * vz
    if a == 0.0 and b == 0.0:
        return 0.0, 0.0, False
    alpha = math.atan2(b, a)
    phi0 = alpha - 0.5 * math.pi - beta
    return _xi_of(phi0, k), _xi_of(phi0 + math.pi, k), True


@njit(cache=True)
def film_sums(y, z, vy, vz, omega, film):
    """Force of a short film on the journal and its Jacobian, as scalars (no allocation).

    Arguments as :func:`film_force_jac`. Returns the 12-tuple ``(fy, fz, dfy/dy, dfy/dz,
    dfy/dvy, dfy/dvz, dfz/dy, dfz/dz, dfz/dvy, dfz/dvz, dfy/domega, dfz/domega)`` (N, N/m,
    N s/m, N s); all NaN when the journal touches the bearing (eccentricity ratio >= 1).
    """
    c = film.clearance
    e = math.hypot(y, z)
    eps = e / c
    if not eps < 1.0:
        nan = math.nan
        return nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan
    beta = math.atan2(z, y)
    cb, sb = math.cos(beta), math.sin(beta)
    s1 = math.sqrt(1.0 - eps * eps)
    k = math.sqrt((1.0 + eps) / (1.0 - eps))
    xa, xb, loaded = _limits(y, z, vy, vz, omega, film.cavitation, beta, k)
    if not loaded:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    a = omega * z + 2.0 * vy
    b = -omega * y + 2.0 * vz
    scale = -0.5 * film.viscosity * film.length**3 * film.radius
    half = 0.5 * (xb - xa)
    mid = 0.5 * (xb + xa)
    f0 = f1 = j00 = j01 = j02 = j03 = j10 = j11 = j12 = j13 = j04 = j14 = 0.0
    for i in range(NODES):
        xi = mid + half * _X[i]
        cx, sx = math.cos(xi), math.sin(xi)
        d = 1.0 + eps * cx
        cphi = (cx + eps) / d
        sphi = s1 * sx / d
        ct = cphi * cb - sphi * sb
        st = sphi * cb + cphi * sb
        inv_h = d / (c * (1.0 - eps * eps))
        w = scale * _W[i] * half * (s1 / d) * inv_h**3
        n = a * ct + b * st
        f0 += w * n * ct
        f1 += w * n * st
        # d/dy and d/dz: N and 1/h^3 (dh/dy = -cos theta, dh/dz = -sin theta)
        dn_y = -omega * st
        dn_z = omega * ct
        g = 3.0 * n * inv_h
        j00 += w * (dn_y + g * ct) * ct
        j10 += w * (dn_y + g * ct) * st
        j01 += w * (dn_z + g * st) * ct
        j11 += w * (dn_z + g * st) * st
        j02 += w * 2.0 * ct * ct
        j12 += w * 2.0 * ct * st
        j03 += w * 2.0 * st * ct
        j13 += w * 2.0 * st * st
        dn_w = z * ct - y * st
        j04 += w * dn_w * ct
        j14 += w * dn_w * st
    return f0, f1, j00, j01, j02, j03, j10, j11, j12, j13, j04, j14


@njit(cache=True)
def film_force_jac(y, z, vy, vz, omega, film):
    """Force of a short film on the journal and its Jacobian.

    Parameters
    ----------
    y, z : float
        Journal centre relative to the bearing centre (m); ``hypot(y, z)`` below the clearance.
    vy, vz : float
        Its velocity (m/s).
    omega : float
        Journal spin (rad/s), 0 for a squeeze-film damper.
    film : Film
        Parameters (SI).

    Returns
    -------
    f : ndarray, shape (2,)
        Force on the journal (N), y and z.
    jac : ndarray, shape (2, 5)
        Its derivatives with respect to ``y, z`` (N/m), ``vy, vz`` (N s/m) and ``omega`` (N s).
        All NaN when the journal touches the bearing (eccentricity ratio >= 1).
    """
    r = film_sums(y, z, vy, vz, omega, film)
    f = np.array([r[0], r[1]])
    jac = np.array([[r[2], r[3], r[4], r[5], r[10]], [r[6], r[7], r[8], r[9], r[11]]])
    return f, jac


@njit(cache=True)
def film_force(y, z, vy, vz, omega, film):
    """Force of a short film on the journal (N), y and z (see :func:`film_force_jac`)."""
    f, _ = film_force_jac(y, z, vy, vz, omega, film)
    return f
