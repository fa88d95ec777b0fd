"""A short fluid film as a row of the engine's implicit step (journal bearing or damper).

The film's linearisation about its static position goes into the rotor's linear system (a
support with stiffness ``K0`` and damping ``C0``, N/m and N s/m), so a rotor on film bearings
alone is not free-free and the modal reduction with its residual flexibility stays valid. The
row carries the rest of the film's force (:mod:`rubrotor.core.terms`, code ``SHORT_FILM``)::

    f_row(p, u) = f_film(p, u) - F0 + K0 (p - P0) + C0 u

and the static load carries ``F0 + K0 P0``: at the static position the row exerts nothing, and
the sum of the three is the film's force everywhere. ``P0`` (m) is the journal's static position
relative to the bearing centre and ``F0 = f_film(P0, 0)`` (N).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numba import njit

from rubrotor.core import terms as T
from rubrotor.core.film import Film, film_sums
from rubrotor.errors import InputError

__all__ = ["FilmRow", "FILM_OUTPUTS"]

FILM_OUTPUTS = (
    ("film_force_y", "N"), ("film_force_z", "N"), ("eccentricity_ratio", "1"),
)  # fmt: skip
"""Output variables of a film row on ``(bearing, time)``."""


@njit(cache=True)
def _film_forces(p, u, omega, film, out):
    """Film force (N) for each sample of ``p``, ``u`` (2, T) (m, m/s) into ``out`` (2, T)."""
    for k in range(p.shape[1]):
        r = film_sums(p[0, k], p[1, k], u[0, k], u[1, k], omega, film)
        out[0, k] = r[0]
        out[1, k] = r[1]


@dataclass(frozen=True)
class FilmRow:
    """A short film at a rotor station, linearised about its static position (SI).

    Parameters
    ----------
    name : str
        The bearing's name (outputs and messages).
    position : float
        Axial position of the bearing on the rotor (m).
    film : rubrotor.core.film.Film
        Radius, length, radial clearance (m), viscosity (Pa s), cavitation code.
    spins : bool
        True for a journal bearing (the journal spins with the rotor), False for a
        squeeze-film damper (it does not).
    p0 : array_like, shape (2,)
        Static journal position relative to the bearing centre, y and z (m).
    stiffness, damping : array_like, shape (2, 2)
        ``K0`` (N/m) and ``C0`` (N s/m), the film's linearisation at ``p0`` at the run's speed,
        which the rotor's linear system holds.
    """

    OUTPUT_UNITS: ClassVar[dict] = dict(FILM_OUTPUTS)

    name: str
    position: float
    film: Film
    spins: bool
    p0: tuple
    stiffness: tuple
    damping: tuple

    def __post_init__(self):
        p0 = np.asarray(self.p0, float)
        if p0.shape != (2,) or not np.all(np.isfinite(p0)):
            raise InputError(f"{self.name}.p0", self.p0, "a finite static position (y, z) (m)")
        if not np.hypot(*p0) < self.film.clearance:
            raise InputError(f"{self.name}.p0", self.p0,
                             f"a static position inside the clearance {self.film.clearance} m")  # fmt: skip
        for key, unit in (("stiffness", "N/m"), ("damping", "N s/m")):
            a = np.asarray(getattr(self, key), float)
            if a.shape != (2, 2) or not np.all(np.isfinite(a)):
                raise InputError(f"{self.name}.{key}", getattr(self, key), f"a finite 2x2 ({unit})")

    def spin(self, speed: float) -> float:
        """The journal's spin (rad/s) at the rotor's ``speed`` (rad/s)."""
        return float(speed) if self.spins else 0.0

    def static_film_force(self, speed: float) -> np.ndarray:
        """``F0 = f_film(P0, 0)`` (N) at ``speed`` (rad/s)."""
        r = film_sums(float(self.p0[0]), float(self.p0[1]), 0.0, 0.0, self.spin(speed), self.film)
        return np.array([r[0], r[1]])

    def static_force(self, speed: float) -> np.ndarray:
        """The constant ``F0 + K0 P0`` (N) the static load carries (see the module docstring)."""
        return self.static_film_force(speed) + np.asarray(self.stiffness) @ np.asarray(self.p0)

    def row(self, speed: float) -> np.ndarray:
        """The packed row (``rubrotor.core.terms``, :data:`~rubrotor.core.terms.ROW_WIDTH`) at
        ``speed`` (rad/s)."""
        r = np.zeros(T.ROW_WIDTH)
        f = self.film
        r[T.ACTIVE], r[T.CODE], r[T.FREE_RADIUS] = 1.0, T.SHORT_FILM, -1.0
        w = self.spin(speed)
        # Newton's force scale: the film's force at half the clearance, or its load
        r[T.FORCE_SCALE] = max(float(np.hypot(*self.static_film_force(speed))),
                               f.viscosity * max(w, 1.0) * f.radius * f.length**3 / f.clearance**2)  # fmt: skip
        r[T.FILM_RADIUS], r[T.FILM_LENGTH], r[T.FILM_CLEARANCE] = f.radius, f.length, f.clearance
        r[T.FILM_VISCOSITY], r[T.FILM_CAVITATION], r[T.SPIN] = f.viscosity, f.cavitation, w
        r[T.P0 : T.P0 + 2] = self.p0
        r[T.F0 : T.F0 + 2] = self.static_film_force(speed)
        r[T.K0 : T.K0 + 4] = np.asarray(self.stiffness, float).ravel()
        r[T.C0 : T.C0 + 4] = np.asarray(self.damping, float).ravel()
        return r

    def outputs(self, p: np.ndarray, u: np.ndarray, speed: float) -> dict:
        """:data:`FILM_OUTPUTS` of samples ``p`` (2, T) (m) and ``u`` (2, T) (m/s) of the
        journal relative to the bearing centre."""
        p = np.ascontiguousarray(p, float)
        u = np.ascontiguousarray(u, float)
        f = np.empty_like(p)
        _film_forces(p, u, self.spin(speed), self.film, f)
        eps = np.hypot(p[0], p[1]) / self.film.clearance
        return {"film_force_y": f[0], "film_force_z": f[1], "eccentricity_ratio": eps}

    @property
    def scale(self) -> float:
        """Length scale (m): the radial clearance."""
        return self.film.clearance
