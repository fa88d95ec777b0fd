"""The finite plain journal bearing: Reynolds' equation on a grid of the film (SciPy sparse).

Dimensionless, isothermal, incompressible film of a plain journal bearing of radius ``R``, length
``L`` and radial clearance ``c``, journal at rest (no squeeze) spinning at ``omega``: with the film
thickness ``h = c H``, ``H = 1 + eps cos(theta)`` (``theta`` from the thickest film, in the spin's
sense), ``Z = z / L`` in ``[-1/2, 1/2]`` and the pressure ``p = 6 mu omega (R / c)^2 P``,

    d/dtheta (H^3 dP/dtheta) + (R / L)^2 d/dZ (H^3 dP/dZ) = dH/dtheta,    P(Z = +-1/2) = 0,

periodic in ``theta``. It is discretised by conservative central differences (``H^3`` at the
cell faces, second order) on ``n_theta x n_z`` cells and solved with a sparse LU factorisation.
Cavitation:

* ``"full_film"``: negative pressures kept (Sommerfeld);
* ``"half_sommerfeld"``: the full film's negative pressures set to zero (Gumbel);
* ``"reynolds"``: ``P >= 0`` with zero pressure gradient at film rupture (Swift-Stieber), solved
  as the linear complementarity problem of the discrete operator by a primal-dual active set
  (each iteration one sparse solve; it stops when the active set repeats).

The film force on the journal, ``F = -R L int int p (cos, sin) dtheta dZ``, is returned along the
line of centres (along the eccentricity, ``radial``) and at right angles ahead of it in the spin's sense
(``tangential``), dimensionless by ``mu omega R L (R / c)^2`` (so that the Sommerfeld number is
``S = 1 / (pi W)`` for a load ``W`` in these units).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from rubrotor.errors import InputError

__all__ = ["FiniteFilm", "finite_film"]

CAVITATION_MODELS = ("full_film", "half_sommerfeld", "reynolds")


@dataclass(frozen=True)
class FiniteFilm:
    """The solution of one finite film.

    Attributes
    ----------
    pressure : ndarray, shape (n_theta, n_z)
        Dimensionless pressure ``P`` at the cell centres (``p = 6 mu omega (R/c)^2 P``).
    theta : ndarray, shape (n_theta,)
        Angles of the cell centres from the thickest film (rad).
    z : ndarray, shape (n_z,)
        Axial positions of the cell centres over the length (1, from -1/2 to 1/2).
    radial, tangential : float
        Film force on the journal along the eccentricity (negative: towards the bearing's
        centre) and 90 degrees ahead of it in the spin's sense, per ``mu omega R L (R/c)^2`` (1).
    iterations : int
        Sparse solves used (1 without the Reynolds condition).
    """

    pressure: np.ndarray
    theta: np.ndarray
    z: np.ndarray
    radial: float
    tangential: float
    iterations: int

    @property
    def load(self) -> float:
        """Load capacity per ``mu omega R L (R/c)^2`` (1)."""
        return math.hypot(self.radial, self.tangential)

    @property
    def sommerfeld(self) -> float:
        """Sommerfeld number ``mu N L D / W (R/c)^2`` (``N`` in rev/s) of this film (1)."""
        return 1.0 / (math.pi * self.load)

    @property
    def attitude_angle_rad(self) -> float:
        """Angle from the load line to the line of centres, in the spin's sense (rad)."""
        return math.atan2(self.tangential, -self.radial)


def _operator(eps: float, n_theta: int, n_z: int, r_over_l: float):
    """The discrete Reynolds operator (sparse, negative definite) and its right-hand side."""
    dth = 2.0 * math.pi / n_theta
    dz = 1.0 / n_z
    th = (np.arange(n_theta) + 0.5) * dth
    h3_face = (1.0 + eps * np.cos(th + 0.5 * dth)) ** 3  # face i + 1/2
    h3_c = (1.0 + eps * np.cos(th)) ** 3
    n = n_theta * n_z
    idx = np.arange(n).reshape(n_theta, n_z)
    rows, cols, vals = [], [], []
    ax = np.repeat(h3_face / dth**2, n_z).reshape(n_theta, n_z)  # coupling to i+1
    axm = np.roll(ax, 1, axis=0)  # coupling to i-1 (face i - 1/2)
    az = np.repeat(r_over_l**2 * h3_c / dz**2, n_z).reshape(n_theta, n_z)
    diag = -(ax + axm)
    for sh, a in ((-1, ax), (1, axm)):
        rows.append(idx.ravel())
        cols.append(np.roll(idx, sh, axis=0).ravel())
        vals.append(a.ravel())
    # axial: interior faces couple, the two ends hold P = 0 half a cell beyond the last centre
    up = idx[:, 1:].ravel()
    dn = idx[:, :-1].ravel()
    a_in = az[:, 1:].ravel()
    rows += [up, dn]
    cols += [dn, up]
    vals += [a_in, a_in]
    # an axial face couples two cells (az); an end face lies half a cell from P = 0 (2 az)
    diag = diag - 2.0 * az
    diag[:, 0] -= az[:, 0]
    diag[:, -1] -= az[:, -1]
    rows.append(idx.ravel())
    cols.append(idx.ravel())
    vals.append(diag.ravel())
    a = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n, n))  # fmt: skip
    # dH/dtheta at the centre, conservative: (H(i+1/2) - H(i-1/2)) / dth
    hf = 1.0 + eps * np.cos(th + 0.5 * dth)
    rhs = (hf - np.roll(hf, 1)) / dth
    b = np.repeat(rhs, n_z)
    return a, b, th, (np.arange(n_z) + 0.5) * dz - 0.5


def _active_set(a, b, max_iter=100):
    """Solve ``a p = b`` subject to ``p >= 0`` (Swift-Stieber), ``a`` negative definite."""
    n = b.size
    free = np.ones(n, dtype=bool)
    p = np.zeros(n)
    for it in range(1, max_iter + 1):
        sub = a[free][:, free].tocsc()
        p = np.zeros(n)
        p[free] = splu(sub).solve(b[free])
        # multiplier of p >= 0 on the closed nodes: residual of the equation there
        lam = -(a @ p - b)
        new_free = np.where(free, p > 0.0, lam < 0.0)
        if np.array_equal(new_free, free):
            return np.maximum(p, 0.0), it
        free = new_free
    raise RuntimeError("Reynolds cavitation: the active set did not settle")


def finite_film(eps: float, l_over_d: float, *, n_theta: int = 72, n_z: int = 24,
                cavitation: str = "reynolds") -> FiniteFilm:  # fmt: skip
    """Solve the finite plain journal bearing's film at the eccentricity ratio ``eps``.

    Parameters
    ----------
    eps : float
        Eccentricity ratio (1), in ``[0, 1)``.
    l_over_d : float
        Length over diameter (1), > 0.
    n_theta, n_z : int
        Cells around the circumference and over the length.
    cavitation : {"reynolds", "half_sommerfeld", "full_film"}
        Cavitation model (module docstring).

    Returns
    -------
    FiniteFilm
    """
    if not (isinstance(eps, (int, float)) and 0.0 <= eps < 1.0):
        raise InputError("eccentricity_ratio", eps, "a number in [0, 1) (1)")
    if not (isinstance(l_over_d, (int, float)) and math.isfinite(l_over_d) and l_over_d > 0):
        raise InputError("length / diameter", l_over_d, "a finite number > 0 (1)")
    if cavitation not in CAVITATION_MODELS:
        raise InputError("cavitation", cavitation, "one of " + ", ".join(CAVITATION_MODELS))
    for key, n in (("n_theta", n_theta), ("n_z", n_z)):
        if not (isinstance(n, int) and n >= 4):
            raise InputError(key, n, "a whole number >= 4")
    a, b, th, z = _operator(float(eps), n_theta, n_z, 0.5 / l_over_d)
    if cavitation == "reynolds":
        p, iterations = _active_set(a, b)
    else:
        p, iterations = splu(a).solve(b), 1
        if cavitation == "half_sommerfeld":
            p = np.maximum(p, 0.0)
    p = p.reshape(n_theta, n_z)
    # F / (mu omega R L (R/c)^2) = -6 int int P (cos, sin) dtheta dZ (midpoint rule, 2nd order);
    # the eccentricity points to theta = pi: e = (-1, 0), 90 degrees ahead of it (0, -1)
    w = (2.0 * math.pi / n_theta) * (1.0 / n_z)
    mean = p.sum(axis=1) * w
    radial = 6.0 * float(mean @ np.cos(th))
    tangential = 6.0 * float(mean @ np.sin(th))
    return FiniteFilm(p, th, z, radial, tangential, iterations)
