"""The one compiled dispatch over force-term rows: the only place that lists term codes.

Every row the engine's implicit step solves for is a force acting at one rotor station,
relative to a stator or the ground: ``F = f(p, u)`` with ``p`` the relative displacement (m) and
``u`` its velocity (m/s), two components each. A row is one float64 array of
:data:`ROW_WIDTH` columns, named below: its ``CODE`` says which kernel computes its force, its
``FREE_RADIUS`` whether it can be free (a contact inside its clearance exerts no force, so free
flight, contact events and the graze fallback apply; a fluid film or a magnet always acts,
``FREE_RADIUS < 0``), its ``FORCE_SCALE`` (N) sizes Newton's tolerance.

:func:`term` returns the force and its Jacobian as the 12-tuple ``(fy, fz, fn, ft, dfy/dpy,
dfy/dpz, dfy/duy, dfy/duz, dfz/dpy, dfz/dpz, dfz/duy, dfz/duz)``; ``fn`` is a contact's normal
force, ``ft`` its friction force (N), and a row that is not a contact reports the magnitude of its
physical force as ``fn`` and 0 as ``ft``. A switch over codes, not first-class functions: an
indirect call costs several times a branch in numba, and is an experimental feature there.

Codes
-----
``HERTZ`` (0) and ``LINEAR`` (1): the contact laws of :mod:`rubrotor.core.contact`, parameter
columns as its ``CP_FIELDS`` (columns 0-9).

``SHORT_FILM`` (2): a short fluid film (:mod:`rubrotor.core.film`: Ocvirk's journal bearing
spinning at ``SPIN``, a squeeze-film damper at ``SPIN = 0``) whose linearisation about the static
position ``P0`` (m) is in the rotor's linear system. The row carries the remainder::

    f_row(p, u) = f_film(p, u) - F0 + K0 (p - P0) + C0 u

with ``F0 = f_film(P0, 0)`` (N) and ``K0``, ``C0`` (N/m, N s/m, row-major 2x2) the film's
stiffness and damping at ``P0``: the linear system holds ``-K0 p - C0 u`` and the static load
holds ``F0 + K0 P0``, so the sum is the film's force and the remainder vanishes, with its
derivatives, at the static position.
"""

import math

import numpy as np
from numba import njit

from rubrotor.core.contact import _law, contact_force_jac_exact
from rubrotor.core.film import Film, film_sums

__all__ = [
    "HERTZ", "LINEAR", "SHORT_FILM", "CODES", "ROW_WIDTH", "ACTIVE", "CODE", "FREE_RADIUS",
    "FORCE_SCALE", "FILM_RADIUS", "FILM_LENGTH", "FILM_CLEARANCE", "FILM_VISCOSITY",
    "FILM_CAVITATION", "SPIN", "P0", "F0", "K0", "C0", "term", "term_jac", "term_jac_exact", "term_force", "can_be_free", "length_scale", "length_scales",
]  # fmt: skip

HERTZ, LINEAR, SHORT_FILM = 0, 1, 2
CODES = {"hertz": HERTZ, "linear": LINEAR, "short_film": SHORT_FILM}
"""Term codes by name."""

# Columns every row has
ACTIVE, CODE, FREE_RADIUS, FORCE_SCALE = 0, 1, 4, 9
# Columns of a short-film row (the contact block, 2-8, stays zero but FREE_RADIUS = -1)
FILM_RADIUS, FILM_LENGTH, FILM_CLEARANCE, FILM_VISCOSITY, FILM_CAVITATION = 10, 11, 12, 13, 14
SPIN, P0, F0, K0, C0 = 15, 16, 18, 20, 24
ROW_WIDTH = 28


@njit(cache=True)
def _short_film(py, pz, uy, uz, row):
    """The short-film row's remainder force and Jacobian (see the module docstring)."""
    film = Film(row[FILM_RADIUS], row[FILM_LENGTH], row[FILM_CLEARANCE], row[FILM_VISCOSITY],
                int(row[FILM_CAVITATION]))  # fmt: skip
    r = film_sums(py, pz, uy, uz, row[SPIN], film)
    dy = py - row[P0]
    dz = pz - row[P0 + 1]
    fy = r[0] - row[F0] + row[K0] * dy + row[K0 + 1] * dz + row[C0] * uy + row[C0 + 1] * uz
    fz = r[1] - row[F0 + 1] + row[K0 + 2] * dy + row[K0 + 3] * dz + row[C0 + 2] * uy \
        + row[C0 + 3] * uz
    return (fy, fz, math.sqrt(r[0] * r[0] + r[1] * r[1]), 0.0,
            r[2] + row[K0], r[3] + row[K0 + 1], r[4] + row[C0], r[5] + row[C0 + 1],
            r[6] + row[K0 + 2], r[7] + row[K0 + 3], r[8] + row[C0 + 2], r[9] + row[C0 + 3])  # fmt: skip


@njit(cache=True, inline="always")
def term(py, pz, uy, uz, row):
    """Force of one row on the rotor and its Jacobian (the 12-tuple of the module docstring).

    ``py, pz`` (m) and ``uy, uz`` (m/s): the row's relative displacement and velocity; ``row``
    its :data:`ROW_WIDTH` parameters. Contact codes are inlined (the common case); the others
    are calls.
    """
    if row[CODE] <= LINEAR:
        return _law(py, pz, uy, uz, row)
    if row[ACTIVE] == 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return _short_film(py, pz, uy, uz, row)


@njit(cache=True, inline="always")
def term_jac(py, pz, uy, uz, row):
    """:func:`term` with the full Newton Jacobian: a contact adds the derivative of its smoothed
    friction sign (near rolling the quasi-Newton Jacobian of the law alone stalls); the other
    codes' Jacobians are exact already."""
    r = term(py, pz, uy, uz, row)
    if row[CODE] > LINEAR:
        return r
    fn = r[2]
    if fn == 0.0 or row[6] != 0.0 or row[5] == 0.0:
        return r
    d = math.sqrt(py * py + pz * pz)
    ny = py / d
    nz = pz / d
    vs = row[7] - nz * uy + ny * uz
    if vs * vs > 1e6 * row[8] * row[8]:
        return r  # far from rolling: d sigma / d v_s < 1e-9 / v_r, negligible
    q = vs * vs + row[8] * row[8]
    ds = row[8] * row[8] / (q * math.sqrt(q))  # d sigma / d v_s
    # dF/dsigma = -fn mu J n = -fn mu (-nz, ny)
    gy = fn * row[5] * nz * ds
    gz = -fn * row[5] * ny * ds
    p11 = (1.0 - ny * ny) / d
    p12 = -ny * nz / d
    p22 = (1.0 - nz * nz) / d
    # dv_s/dp = -uy dnz/dp + uz dny/dp ; dv_s/du = (-nz, ny)
    vpy = -uy * p12 + uz * p11
    vpz = -uy * p22 + uz * p12
    return (r[0], r[1], r[2], r[3],
            r[4] + gy * vpy, r[5] + gy * vpz, r[6] - gy * nz, r[7] + gy * ny,
            r[8] + gz * vpy, r[9] + gz * vpz, r[10] - gz * nz, r[11] + gz * ny)  # fmt: skip


@njit(cache=True, inline="always")
def can_be_free(row):
    """True when the row exerts no force inside a radius (a contact: its clearance)."""
    return row[FREE_RADIUS] >= 0.0


@njit(cache=True, inline="always")
def length_scale(row):
    """The row's length scale (m) for step tolerances: a contact's clearance, a film's radial
    clearance."""
    if row[CODE] <= LINEAR:
        return row[FREE_RADIUS]
    return row[FILM_CLEARANCE]


@njit(cache=True, inline="always")
def term_force(py, pz, uy, uz, row):
    """``(fy, fz, fn, ft)`` of :func:`term`, for callers that need no Jacobian."""
    r = term(py, pz, uy, uz, row)
    return r[0], r[1], r[2], r[3]


@njit(cache=True)
def term_jac_exact(py, pz, uy, uz, row, jac):
    """Force and exact Jacobian, for tangent (variational) dynamics: ``jac`` (2 x 4, filled)
    ``= d(fy, fz) / d(py, pz, uy, uz)``; a contact's smoothed friction sign differentiated
    everywhere (:func:`rubrotor.core.contact.contact_force_jac_exact`). Returns
    ``(fy, fz, fn, ft)``."""
    if row[CODE] <= LINEAR:
        return contact_force_jac_exact(py, pz, uy, uz, row, jac)
    r = term(py, pz, uy, uz, row)
    for k in range(4):
        jac[0, k] = r[4 + k]
        jac[1, k] = r[8 + k]
    return r[0], r[1], r[2], r[3]


def length_scales(rows: np.ndarray) -> np.ndarray:
    """:func:`length_scale` (m) of each row of ``rows`` (n, width), in NumPy (nothing compiled)."""
    rows = np.atleast_2d(rows)
    if rows.shape[1] <= FILM_CLEARANCE:  # contact rows only
        return rows[:, FREE_RADIUS].copy()
    return np.where(rows[:, CODE] <= LINEAR, rows[:, FREE_RADIUS], rows[:, FILM_CLEARANCE])
