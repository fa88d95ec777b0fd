"""Short fluid films: Ocvirk's short journal bearing and the short squeeze-film damper.

Both are the same film (:mod:`rubrotor.core.film`): a journal bearing's journal spins with the
rotor, a damper's journal does not (its outer ring is kept from turning) and it may sit on a
centring spring. This module holds their parameters (validated, SI), their static equilibrium
under a load and their linearised stiffness and damping there; as ``[[bearing]] type =
"short_journal"`` and ``"squeeze_film"`` they are support terms (:mod:`rubrotor.forces.supports`)
the Model linearises at the rotor's static equilibrium (:mod:`rubrotor.forces.equilibrium`).

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
from typing import ClassVar

import numpy as np

from rubrotor.core.filmtypes import FULL_FILM, PI_FILM, Film
from rubrotor.errors import InputError
from rubrotor.rotors.linear import Support

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
        pos = getattr(self, "position", 0.0)
        if isinstance(pos, bool) or not isinstance(pos, int | float) or not math.isfinite(pos):
            raise InputError(f"{self.name}.position", pos, "a finite axial station (m)")
        if self.radial_clearance >= 0.5 * self.diameter:
            raise InputError(f"{self.name}.radial_clearance", self.radial_clearance,
                             f"a clearance well below the radius {0.5 * self.diameter} m (m)")  # fmt: skip
        ratio = self.length / self.diameter
        if ratio > 1.0:
            raise InputError(f"{self.name}.length", self.length,
                             f"at most the diameter {self.diameter} m for the short-film model "
                             f"(L/D = {ratio:.3g} > 1)")  # fmt: skip

    # ---- the support-term protocol (rubrotor.forces.supports) ------------------------------
    kind: ClassVar[str] = "bearing"
    fail_time: ClassVar[None] = None
    on: ClassVar[None] = None  # between the rotor and the ground
    link: ClassVar[None] = None
    mass_matrix: ClassVar[np.ndarray] = np.zeros((2, 2))
    nonlinear: ClassVar[bool] = True
    """A nonlinear support: the Model linearises it at the rotor's static equilibrium."""

    @property
    def _table(self) -> tuple:
        """No table: the coefficients come from the static equilibrium at each speed."""
        return None, np.zeros((1, 2, 2)), np.zeros((1, 2, 2))

    def support(self, node: int, name: str, dofs=None, link=None) -> Support:
        """A placeholder :class:`rubrotor.rotors.linear.Support` on node ``node`` (or ``dofs``)
        with zero coefficients: :meth:`rubrotor.modelling.Model.linear_system` gives it its
        law (the film linearised at the rotor's static equilibrium at each speed)."""
        if link is not None:
            raise InputError("bearing.link", link, f'none with type = "{self.type}"')
        zero = np.zeros((1, 2, 2))
        return Support(dofs=tuple(dofs) if dofs is not None else (4 * node, 4 * node + 1),
                       k=zero, c=zero, position=float(self.position), name=name, term=self)  # fmt: skip

    def table_entry(self) -> dict:
        """The ``[[bearing]]`` table that builds this term again."""
        out = {"position": self.position, "type": self.type}
        for key in self._keys():
            out[key] = getattr(self, key)
        return out

    def _keys(self) -> tuple:
        return ("name", "diameter", "length", "radial_clearance", "viscosity", "cavitation")

    def engine_row(self, lin):
        """The film's row of the engine's implicit step, about its linearisation ``lin``
        (:class:`rubrotor.forces.equilibrium.SupportLinearisation` at the run's speed): the
        row carries the film's force less the film's part of ``K0``, ``C0`` (a damper's centring
        spring is linear, all in the linear system)."""
        from rubrotor.forces.film_row import FilmRow  # numba: time runs only

        spring = float(getattr(self, "centering_stiffness", 0.0)) * np.eye(2)
        return FilmRow(lin.name, float(lin.position), self.film, self.spins,
                       tuple(np.asarray(lin.p0, float)), np.asarray(lin.K0) - spring,
                       np.asarray(lin.C0))  # fmt: skip

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
        from rubrotor.core.film import film_force_jac  # compiled: loaded on first use

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
        The key prefix used in error messages, e.g. ``"bearing[1]"``; a label in a scenario.
    position : float
        Axial station (m) of a ``[[bearing]]`` table.
    """

    type: ClassVar[str] = "short_journal"
    spins: ClassVar[bool] = True
    position: float = 0.0

    @property
    def holds(self) -> bool:
        """True: a loaded journal bearing holds the rotor."""
        return True

    def static_force(self, position, spin: float) -> tuple[np.ndarray, np.ndarray]:
        """Film force (N) on the journal at rest at ``position`` (m) and spin ``spin`` (rad/s),
        and its stiffness ``K = -df/dq`` (N/m): the compiled film's exact Jacobian."""
        f, jac = self._force_jac(position, (0.0, 0.0), spin)
        return f, -jac[:, 0:2]

    def linearise(self, position, spin: float) -> tuple[np.ndarray, np.ndarray]:
        """``(K, C)`` (N/m, N s/m) of the film about the journal at rest at ``position`` (m),
        spin ``spin`` (rad/s): ``-df/dq`` and ``-df/dq'``, the compiled film's exact Jacobian."""
        co = self.coefficients(position, spin)
        return co.stiffness, co.damping

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
    position : float
        Axial station (m) of a ``[[bearing]]`` table.

    Notes
    -----
    At rest the film carries no load (no spin, no squeeze): the static position is set by the
    centring spring alone. Linearised there (:meth:`linearise`) the damper is the spring
    ``centering_stiffness I`` and the film's damping ``-df/dq'``: the full film's exact Jacobian,
    and for the pi-film (``"half_sommerfeld"``) half of it, the pi-film's equivalent damping of a
    small whirl (at the centre, ``pi mu R L^3 / (2 c^3)``: half the full film's). A pi-film's
    force is not differentiable at rest (its half circle turns with the velocity), so this is a
    choice, not a Jacobian; the time runs use the nonlinear force.
    """

    type: ClassVar[str] = "squeeze_film"
    spins: ClassVar[bool] = False
    centering_stiffness: float = 0.0
    position: float = 0.0

    def __post_init__(self):
        super().__post_init__()
        k = self.centering_stiffness
        if not (isinstance(k, (int, float)) and not isinstance(k, bool) and math.isfinite(k)
                and k >= 0.0):  # fmt: skip
            raise InputError(f"{self.name}.centering_stiffness", k, "a finite number >= 0 (N/m)")

    @property
    def holds(self) -> bool:
        """True with a centring spring (an uncentred damper does not hold the rotor)."""
        return self.centering_stiffness > 0.0

    def _keys(self) -> tuple:
        return super()._keys() + ("centering_stiffness",)

    def static_force(self, position, spin: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Force (N) of the centring spring on the journal at rest at ``position`` (m) and its
        stiffness (N/m); the film carries nothing at rest (``spin`` is ignored: the damper's
        journal does not spin)."""
        q = np.asarray(position, float)
        k = self.centering_stiffness * np.eye(2)
        return -k @ q, k

    def linearise(self, position, spin: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """``(K, C)`` (N/m, N s/m) about the journal at rest at ``position`` (m): the spring and
        the film's damping (class notes); ``spin`` is ignored."""
        from rubrotor.core.film import film_force_jac  # compiled: loaded on first use

        y, z = (float(v) for v in position)
        full = self.film._replace(cavitation=FULL_FILM)
        _, jac = film_force_jac(y, z, 0.0, 0.0, 0.0, full)
        c = -jac[:, 2:4]
        if CAVITATION[self.cavitation] == PI_FILM:
            c = 0.5 * c
        return self.centering_stiffness * np.eye(2), c
