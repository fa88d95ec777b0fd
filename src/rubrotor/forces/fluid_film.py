"""Short fluid films: Ocvirk's short journal bearing and the short squeeze-film damper.

Both are the same film (:mod:`rubrotor.core.film`): a journal bearing's journal spins with the
rotor, a damper's journal does not (its outer ring is kept from turning) and it may sit on a
centring spring. This module holds their parameters (validated, SI), their static equilibrium
under a load and their linearised stiffness and damping there; the time runs evaluate the same
compiled force.

References
----------
Ocvirk, F. W. (1952). Short-bearing approximation for full journal bearings. NACA TN 2808.
Childs, D. (1993). *Turbomachinery Rotordynamics*, ch. 3. Wiley.
Friswell, M. I., Penny, J. E. T., Garvey, S. D., Lees, A. W. (2010). *Dynamics of Rotating
Machines*, sec. 5.5. Cambridge University Press.
San Andres, L. (2010). Squeeze film dampers: operation, models and technical issues. Modern
Lubrication Theory, Texas A&M University.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.core.film import FULL_FILM, PI_FILM, Film, film_force_jac
from rubrotor.errors import InputError

__all__ = [
    "CAVITATION",
    "ShortJournal",
    "SqueezeFilm",
    "JournalEquilibrium",
    "FilmCoefficients",
]

CAVITATION = {
    "half_sommerfeld": PI_FILM,
    "gumbel": PI_FILM,
    "pi_film": PI_FILM,
    "full_film": FULL_FILM,
    "sommerfeld": FULL_FILM,
}
"""Cavitation models by name: negative pressures set to zero (pi-film) or kept (full film)."""

MAX_ECCENTRICITY = 0.999
"""Static solutions beyond this eccentricity ratio are refused (the film would be metal contact)."""


def _positive(field: str, value, unit: str) -> float:
    """``value`` as a finite float > 0, or an ``InputError`` naming ``field``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(field, value, f"a finite number > 0 ({unit})") from None
    if not (math.isfinite(x) and x > 0.0):
        raise InputError(field, value, f"a finite number > 0 ({unit})")
    return x


def _cavitation(field: str, value) -> int:
    if value not in CAVITATION:
        raise InputError(field, value, "one of " + ", ".join(f'"{k}"' for k in CAVITATION))
    return CAVITATION[value]


@dataclass(frozen=True)
class JournalEquilibrium:
    """A film's static position under a load.

    Attributes
    ----------
    position : ndarray, shape (2,)
        Journal centre relative to the bearing centre, y and z (m).
    eccentricity_ratio : float
        ``|position| / radial_clearance`` (1).
    attitude_angle_rad : float
        Angle from the load's direction to the eccentricity, positive in the spin's sense (rad).
    sommerfeld : float
        Sommerfeld number ``mu N L D / W (R / c)^2`` with ``N`` in rev/s (1); NaN without spin.
    """

    position: np.ndarray
    eccentricity_ratio: float
    attitude_angle_rad: float
    sommerfeld: float


@dataclass(frozen=True)
class FilmCoefficients:
    """A film linearised about a static position: ``f ~ f0 - K dq - C dq_dot``.

    Attributes
    ----------
    stiffness : ndarray, shape (2, 2)
        ``K[i, j] = -d f_i / d q_j`` (N/m), rows and columns y, z.
    damping : ndarray, shape (2, 2)
        ``C[i, j] = -d f_i / d q_dot_j`` (N s/m).
    """

    stiffness: np.ndarray
    damping: np.ndarray


@dataclass(frozen=True)
class _ShortFilm:
    """What the journal bearing and the damper share: one short film (SI)."""

    diameter: float
    length: float
    radial_clearance: float
    viscosity: float
    cavitation: str = "half_sommerfeld"
    name: str = "film"

    def __post_init__(self):
        for key, unit in (("diameter", "m"), ("length", "m"), ("radial_clearance", "m"),
                          ("viscosity", "Pa s")):  # fmt: skip
            object.__setattr__(self, key, _positive(f"{self.name}.{key}", getattr(self, key), unit))
        _cavitation(f"{self.name}.cavitation", self.cavitation)
        if self.radial_clearance >= 0.5 * self.diameter:
            raise InputError(f"{self.name}.radial_clearance", self.radial_clearance,
                             f"a clearance well below the radius {0.5 * self.diameter} m (m)")  # fmt: skip
        ratio = self.length / self.diameter
        if ratio > 1.0:
            raise InputError(f"{self.name}.length", self.length,
                             f"at most the diameter {self.diameter} m for the short-film model "
                             f"(L/D = {ratio:.3g} > 1)")  # fmt: skip

    @property
    def film(self) -> Film:
        """The compiled kernel's parameters."""
        return Film(0.5 * self.diameter, self.length, self.radial_clearance, self.viscosity,
                    _cavitation("cavitation", self.cavitation))  # fmt: skip

    def force(self, position, velocity=(0.0, 0.0), spin: float = 0.0) -> np.ndarray:
        """Film force on the journal (N), y and z.

        Parameters
        ----------
        position : array_like, shape (2,)
            Journal centre relative to the bearing centre (m).
        velocity : array_like, shape (2,)
            Its velocity (m/s).
        spin : float
            Journal spin (rad/s).
        """
        f, _ = self._force_jac(position, velocity, spin)
        return f

    def _force_jac(self, position, velocity, spin):
        y, z = (float(v) for v in position)
        vy, vz = (float(v) for v in velocity)
        return film_force_jac(y, z, vy, vz, float(spin), self.film)

    def coefficients(self, position, spin: float = 0.0) -> FilmCoefficients:
        """Stiffness and damping of the film about a static ``position`` (m) at ``spin`` (rad/s)."""
        _, jac = self._force_jac(position, (0.0, 0.0), spin)
        return FilmCoefficients(stiffness=-jac[:, 0:2], damping=-jac[:, 2:4])


@dataclass(frozen=True)
class ShortJournal(_ShortFilm):
    """Ocvirk's short plain journal bearing (``[[bearing]] type = "short_journal"``).

    Parameters
    ----------
    diameter : float
        Journal diameter ``D`` (m).
    length : float
        Bearing length ``L`` (m), at most ``D`` (the short-film model).
    radial_clearance : float
        ``c`` (m).
    viscosity : float
        Lubricant dynamic viscosity ``mu`` (Pa s).
    cavitation : str
        ``"half_sommerfeld"`` (Gumbel, pi-film: the default) or ``"full_film"``.
    name : str
        The key prefix used in error messages, e.g. ``"bearing[1]"``.
    """

    def equilibrium(self, load, spin: float) -> JournalEquilibrium:
        """Static position under the external ``load`` (N, y and z) at ``spin`` (rad/s).

        Solved by Newton's method on the force balance with the compiled film's exact Jacobian,
        the step halved to keep the eccentricity ratio below :data:`MAX_ECCENTRICITY`.

        Raises
        ------
        InputError
            ``spin`` not > 0, or no position inside the clearance carries the load.
        """
        spin = _positive(f"{self.name}.speed", spin, "rad/s")
        load = np.asarray(load, dtype=float)
        w = float(np.hypot(*load))
        if not (np.isfinite(w) and w > 0.0):
            raise InputError(f"{self.name}.load", load.tolist(), "a finite, non-zero load (N)")
        q = _newton(self, load, spin)
        eps = float(np.hypot(*q)) / self.radial_clearance
        att = math.atan2(load[0] * q[1] - load[1] * q[0], float(load @ q))
        r = 0.5 * self.diameter
        som = self.viscosity * spin / (2 * math.pi) * self.length * self.diameter / w
        return JournalEquilibrium(q, eps, att, som * (r / self.radial_clearance) ** 2)


def _newton(film: _ShortFilm, load: np.ndarray, spin: float) -> np.ndarray:
    """The position where the film balances ``load`` (damped Newton, exact Jacobian)."""
    c = film.radial_clearance
    w = float(np.hypot(*load))
    q = 0.5 * c * load / w  # half the clearance along the load: the film's stiff side is ahead
    for _ in range(200):
        f, jac = film._force_jac(q, (0.0, 0.0), spin)
        r = f + load
        if np.hypot(*r) <= 1e-13 * w:
            return q
        dq = np.linalg.solve(jac[:, 0:2], -r)
        step = 1.0
        while step > 1e-12:
            trial = q + step * dq
            if np.hypot(*trial) < MAX_ECCENTRICITY * c:
                ft, _ = film._force_jac(trial, (0.0, 0.0), spin)
                if np.hypot(*(ft + load)) < np.hypot(*r):
                    break
            step *= 0.5
        q = trial
    raise InputError(f"{film.name}.load", load.tolist(),
                     f"a load the film carries below an eccentricity ratio of {MAX_ECCENTRICITY} "
                     f"at {spin} rad/s (N)")  # fmt: skip


@dataclass(frozen=True)
class SqueezeFilm(_ShortFilm):
    """A short squeeze-film damper (``[[bearing]] type = "squeeze_film"``).

    The journal (the damper's inner ring) does not spin; the film acts on its whirl alone.

    Parameters
    ----------
    diameter, length, radial_clearance, viscosity, cavitation, name
        As :class:`ShortJournal`; ``cavitation = "half_sommerfeld"`` is the pi-film damper.
    centering_stiffness : float
        The centring spring in parallel with the film (N/m); 0 for an uncentred damper.
    """

    centering_stiffness: float = 0.0

    def __post_init__(self):
        super().__post_init__()
        k = self.centering_stiffness
        if not (isinstance(k, (int, float)) and math.isfinite(k) and k >= 0.0):
            raise InputError(f"{self.name}.centering_stiffness", k, "a finite number >= 0 (N/m)")
