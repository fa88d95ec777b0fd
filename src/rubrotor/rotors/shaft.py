"""The continuous rotor: a uniform, simply supported shaft and its exact modal equations.

Physics
-------
Two-field Timoshenko beam (deflections ``v``, ``w`` and section rotations ``psi_v``, ``psi_w``) with
rotatory inertia and gyroscopic moments, simply supported at ``x = 0`` and ``x = L``. For these ends
the modal expansion is exact: deflection ``~ sin(k x)``, rotation ``~ cos(k x)``, ``k = n pi / L``.
In the complex coordinates ``P = v + i w`` and ``Psi = psi_v + i psi_w`` (``v`` towards ``w`` is the
spin direction, so ``P ~ exp(+i w t)`` with ``w > 0`` is forward whirl) each mode ``n`` obeys::

    (L/2) [rho A  P''  + kGA k^2 P - kGA k Psi]                             = sin(k a) F
    (L/2) [rho I  Psi'' - i Omega rho Ip Psi' + (EI k^2 + kGA) Psi - kGA k P] = 0

with ``F = F_y + i F_z`` a point force at ``x = a`` and ``Ip = 2 I``. In matrix form
``M q'' + (C + Omega G) q' + K q = b F`` with ``M``, ``K`` real symmetric positive definite, ``G``
``-i`` times a real diagonal matrix, ``C`` a real symmetric (modal) damping matrix. The factor
``L/2`` makes ``q^H M q' / 2`` the true kinetic energy in J.

Limits: ``"rayleigh"`` removes shear deformation (``Psi = k P``, one complex DOF per mode);
``"euler-bernoulli"`` also removes rotatory inertia, hence the gyroscopic moments.

This module never simulates or plots; it only turns a description into matrices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from rubrotor.errors import InputError

__all__ = [
    "Shaft",
    "ModalMatrices",
    "modal_matrices",
    "shear_coefficient_value",
    "THEORIES",
    "SHEAR_COEFFICIENTS",
    "FORMULATIONS",
    "Dimensionless",
]

THEORIES = ("timoshenko", "rayleigh", "euler-bernoulli")
SHEAR_COEFFICIENTS = ("cowper", "hutchinson", "seed")
FORMULATIONS = ("two-field", "seed-eq1")


# Physically meaningful ranges of the shaft's inputs (SI). Outside them no machine exists and the
# derived quantities (A, I, EI, rho A, ...) overflow or underflow double precision.
PLAUSIBLE_RANGES = {
    "m": (1e-6, 1e3),
    "Pa": (1.0, 1e16),
    "kg/m^3": (1e-12, 1e9),
    "kg": (1e-12, 1e9),
    "kg m^2": (1e-15, 1e9),
}


def _finite_positive(field_name: str, value, unit: str, allow_zero: bool = False) -> float:
    """Return ``value`` as float or raise :class:`~rubrotor.InputError` naming ``field_name``.

    Values must also lie in :data:`PLAUSIBLE_RANGES` of their unit (zero allowed where
    ``allow_zero``).
    """
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise InputError(field_name, value, f"a number ({unit})")
    v = float(value)
    lo, hi = PLAUSIBLE_RANGES.get(unit, (0.0, math.inf))
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        cmp = ">= 0" if allow_zero else "> 0"
        raise InputError(field_name, value, f"a finite number {cmp} ({unit})")
    if v != 0 and not lo <= v <= hi:
        zero = "0 or " if allow_zero else ""
        raise InputError(field_name, value, f"{zero}a number in [{lo:g}, {hi:g}] ({unit})")
    return v


def shear_coefficient_value(
    kind: str | float, poisson_ratio: float, bore_ratio: float = 0.0
) -> float:
    """Timoshenko shear coefficient ``kappa`` (dimensionless) of a circular section.

    Parameters
    ----------
    kind : {"cowper", "hutchinson", "seed"} or float
        ``"cowper"``: Cowper (1966), ``6(1+nu)(1+m^2)^2 / ((7+6nu)(1+m^2)^2 + (20+12nu) m^2)``
        with ``m`` the bore ratio (``6(1+nu)/(7+6nu)`` for a solid section).
        ``"hutchinson"``: Hutchinson (2001), solid section only, ``6(1+nu)^2/(7+12nu+4nu^2)``.
        ``"seed"``: ``10/9``, the convention of the seed paper, which makes
        ``delta = E/(kappa G) = (9/5)(1+nu)``. A number is used as given.
    poisson_ratio : float
        Poisson's ratio ``nu`` (dimensionless).
    bore_ratio : float
        Inner over outer diameter ``m`` (dimensionless), 0 for a solid shaft.

    Returns
    -------
    float
        ``kappa`` (dimensionless), the factor in ``kGA = kappa G A``.

    Examples
    --------
    >>> round(shear_coefficient_value("cowper", 0.3), 6)
    0.886364
    >>> shear_coefficient_value("seed", 0.3) == 10 / 9
    True
    """
    nu = poisson_ratio
    if isinstance(kind, str):
        if kind == "cowper":
            m2 = bore_ratio**2
            return (
                6 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)
            )
        if kind == "hutchinson":
            if bore_ratio > 0:
                raise InputError(
                    "shaft.shear_coefficient",
                    kind,
                    '"cowper", "seed" or a number for a hollow shaft',
                )
            return 6 * (1 + nu) ** 2 / (7 + 12 * nu + 4 * nu**2)
        if kind == "seed":
            return 10.0 / 9.0
        raise InputError(
            "shaft.shear_coefficient", kind, '"cowper", "hutchinson", "seed" or a number > 0'
        )
    kappa = _finite_positive("shaft.shear_coefficient", kind, "dimensionless")
    if not 1e-6 <= kappa <= 1e9:
        raise InputError("shaft.shear_coefficient", kind, "a number in [1e-06, 1e+09]")
    return kappa


@dataclass(frozen=True)
class Shaft:
    """A uniform circular shaft, simply supported at both ends.

    Parameters
    ----------
    length : float
        Span between the supports ``L`` (m).
    diameter : float
        Outer diameter ``D`` (m).
    youngs_modulus : float
        Young's modulus ``E`` (Pa).
    density : float
        Mass density ``rho`` (kg/m^3). Not a specific weight: aluminium is about 2700 kg/m^3.
    shear_modulus : float, optional
        Shear modulus ``G`` (Pa). Give exactly one of ``shear_modulus`` and ``poisson_ratio``.
    poisson_ratio : float, optional
        Poisson's ratio ``nu`` in (-1, 0.5); then ``G = E / (2 (1 + nu))``.
    bore_diameter : float
        Inner diameter (m), 0 for a solid shaft.
    shear_coefficient : {"cowper", "hutchinson", "seed"} or float
        See :func:`rubrotor.rotors.shaft.shear_coefficient_value`. Default ``"cowper"``.
    theory : {"timoshenko", "rayleigh", "euler-bernoulli"}
        Beam theory. Default ``"timoshenko"``.
    gyroscopic : bool
        Include gyroscopic moments (no effect for Euler-Bernoulli). Default True.
    modes : int
        Number of modes ``n = 1 .. modes`` kept in the expansion.
    formulation : {"two-field", "seed-eq1"}
        Equation form of a Timoshenko shaft in simulations: ``"two-field"`` (default, deflection
        and rotation, forces applied correctly) or ``"seed-eq1"``, the seed's single equation
        with the point forces on its right-hand side (:mod:`rubrotor.rotors.seed_form`, a reproduction
        switch). For Rayleigh and Euler-Bernoulli shafts both are the same one-field equation.

    Examples
    --------
    >>> s = Shaft(length=0.4, diameter=0.1, youngs_modulus=71e9, density=2660,
    ...           shear_modulus=26.2e9, shear_coefficient="seed")
    >>> round(s.slenderness, 4), round(s.shear_parameter, 4)
    (0.0625, 2.4389)
    """

    length: float
    diameter: float
    youngs_modulus: float
    density: float
    shear_modulus: float | None = None
    poisson_ratio: float | None = None
    bore_diameter: float = 0.0
    shear_coefficient: str | float = "cowper"
    theory: str = "timoshenko"
    gyroscopic: bool = True
    modes: int = 3
    formulation: str = "two-field"
    _kappa: float = field(init=False, repr=False, compare=False)
    _nu: float = field(init=False, repr=False, compare=False)
    _g: float = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        for name, unit in (
            ("length", "m"),
            ("diameter", "m"),
            ("youngs_modulus", "Pa"),
            ("density", "kg/m^3"),
        ):
            object.__setattr__(
                self, name, _finite_positive(f"shaft.{name}", getattr(self, name), unit)
            )
        bore = _finite_positive("shaft.bore_diameter", self.bore_diameter, "m", allow_zero=True)
        if bore >= self.diameter:
            raise InputError(
                "shaft.bore_diameter", self.bore_diameter, f"< diameter = {self.diameter} m"
            )
        object.__setattr__(self, "bore_diameter", bore)
        if (self.shear_modulus is None) == (self.poisson_ratio is None):
            raise InputError(
                "shaft.shear_modulus / shaft.poisson_ratio",
                (self.shear_modulus, self.poisson_ratio),
                "exactly one of the two (the other follows from E)",
            )
        if self.shear_modulus is not None:
            g = _finite_positive("shaft.shear_modulus", self.shear_modulus, "Pa")
            object.__setattr__(self, "shear_modulus", g)
            nu = self.youngs_modulus / (2 * g) - 1
            if not -1 < nu < 0.5:
                raise InputError(
                    "shaft.shear_modulus",
                    self.shear_modulus,
                    f"a value with E/(2G) - 1 in (-1, 0.5); it gives nu = {nu:.4g}",
                )
        else:
            nu = self.poisson_ratio
            if isinstance(nu, bool) or not isinstance(nu, int | float) or not -1 < nu < 0.5:
                raise InputError("shaft.poisson_ratio", nu, "a number in (-1, 0.5)")
        object.__setattr__(self, "_nu", float(nu))
        object.__setattr__(
            self,
            "_g",
            self.shear_modulus
            if self.shear_modulus is not None
            else self.youngs_modulus / (2 * (1 + nu)),
        )
        if self.theory not in THEORIES:
            raise InputError("shaft.theory", self.theory, " or ".join(f'"{t}"' for t in THEORIES))
        if not isinstance(self.gyroscopic, bool):
            raise InputError("shaft.gyroscopic", self.gyroscopic, "true or false")
        if (
            isinstance(self.modes, bool)
            or not isinstance(self.modes, int)
            or not 1 <= self.modes <= 200
        ):
            raise InputError("shaft.modes", self.modes, "an integer in 1..200")
        if self.formulation not in FORMULATIONS:
            raise InputError(
                "shaft.formulation", self.formulation, " or ".join(f'"{f}"' for f in FORMULATIONS)
            )
        kappa = shear_coefficient_value(self.shear_coefficient, nu, bore / self.diameter)
        object.__setattr__(self, "_kappa", kappa)

    # ---- section and material properties (SI) -------------------------------------------------
    @property
    def area(self) -> float:
        """Cross-section area ``A`` (m^2)."""
        return math.pi * (self.diameter**2 - self.bore_diameter**2) / 4

    @property
    def second_moment(self) -> float:
        """Area moment of inertia about a diameter ``I`` (m^4)."""
        return math.pi * (self.diameter**4 - self.bore_diameter**4) / 64

    @property
    def polar_moment(self) -> float:
        """Polar area moment ``Ip = 2 I`` (m^4)."""
        return 2 * self.second_moment

    @property
    def G(self) -> float:  # noqa: N802 - the symbol of the field
        """Shear modulus ``G`` (Pa), given or derived from ``E`` and ``nu``."""
        return self._g

    @property
    def nu(self) -> float:
        """Poisson's ratio (dimensionless), given or derived as ``E / (2 G) - 1``."""
        return self._nu

    @property
    def kappa(self) -> float:
        """Shear coefficient ``kappa`` (dimensionless)."""
        return self._kappa

    @property
    def shear_stiffness(self) -> float:
        """``kappa G A`` (N)."""
        return self._kappa * self._g * self.area

    @property
    def bending_stiffness(self) -> float:
        """``E I`` (N m^2)."""
        return self.youngs_modulus * self.second_moment

    @property
    def mass_per_length(self) -> float:
        """``rho A`` (kg/m)."""
        return self.density * self.area

    @property
    def radius_of_gyration(self) -> float:
        """``r0 = sqrt(I / A)`` (m); ``D / 4`` for a solid shaft."""
        return math.sqrt(self.second_moment / self.area)

    @property
    def slenderness(self) -> float:
        """Seed slenderness ratio ``r = r0 / L`` (dimensionless)."""
        return self.radius_of_gyration / self.length

    @property
    def shear_parameter(self) -> float:
        """Seed shear parameter ``delta = E / (kappa G)`` (dimensionless)."""
        return self.youngs_modulus / (self._kappa * self._g)

    def wavenumber(self, n: int) -> float:
        """``k_n = n pi / L`` (1/m)."""
        return n * math.pi / self.length

    @property
    def dofs_per_mode(self) -> int:
        """Complex degrees of freedom per mode: 2 (``P``, ``Psi``) for Timoshenko, else 1."""
        return 2 if self.theory == "timoshenko" else 1


@dataclass(frozen=True)
class ModalMatrices:
    """Matrices of one mode ``n``: ``M q'' + (C + Omega G) q' + K q = b F``.

    Attributes
    ----------
    n : int
        Mode number.
    M : ndarray, shape (m, m), float
        Mass matrix (kg for the deflection DOF, kg m^2 for the rotation DOF, each times L/2 per m).
    G : ndarray, shape (m, m), complex
        Gyroscopic matrix per unit spin: ``-1j`` times a real diagonal (kg m^2 scaled as ``M``).
    K : ndarray, shape (m, m), float
        Stiffness matrix (N/m and N m/rad, scaled as ``M``).
    """

    n: int
    M: np.ndarray
    G: np.ndarray
    K: np.ndarray

    @property
    def size(self) -> int:
        return self.M.shape[0]


def modal_matrices(shaft: Shaft, n: int) -> ModalMatrices:
    """Exact modal matrices of mode ``n`` (see the module docstring for the equations).

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    n : int
        Mode number, ``n >= 1``.

    Returns
    -------
    ModalMatrices
        ``M``, ``G``, ``K`` multiplied by ``L/2`` so that energies are in J.
    """
    k = shaft.wavenumber(n)
    half = shaft.length / 2
    rho, ei = shaft.density, shaft.bending_stiffness
    rho_a, rho_i, rho_ip = (
        shaft.mass_per_length,
        rho * shaft.second_moment,
        rho * shaft.polar_moment,
    )
    gyro = 1.0 if shaft.gyroscopic else 0.0
    if shaft.theory == "timoshenko":
        kga = shaft.shear_stiffness
        M = np.array([[rho_a, 0.0], [0.0, rho_i]])
        G = np.array([[0.0, 0.0], [0.0, -1j * gyro * rho_ip]])
        K = np.array([[kga * k**2, -kga * k], [-kga * k, ei * k**2 + kga]])
    elif shaft.theory == "rayleigh":
        M = np.array([[rho_a + rho_i * k**2]])
        G = np.array([[-1j * gyro * rho_ip * k**2]])
        K = np.array([[ei * k**4]])
    else:
        M = np.array([[rho_a]])
        G = np.zeros((1, 1), complex)
        K = np.array([[ei * k**4]])
    return ModalMatrices(n=n, M=half * M, G=half * G, K=half * K)


@dataclass(frozen=True)
class Dimensionless:
    """Exact conversions between SI and the seed's dimensionless form (seed eqs. 3-5).

    The seed scales ``v' = v / L``, ``chi = x / L``, ``tau = Omega t``,
    ``c^2 = rho A L^4 Omega^2 / (E I)``, ``r = r0 / L``, ``delta = E / (kappa G)`` and, dividing the
    equations by ``E I / L^3``, forces as ``F' = F L^2 / (E I)``. Contact constants then scale as
    ``k_h' = k_h L^3.5 / (E I)`` (from ``F' = k_h' eps'^1.5``), ``b_h' = b_h L Omega`` (from
    ``1 + b_h' d eps'/d tau``) and ``g' = g / L``.

    Parameters
    ----------
    shaft : Shaft
        Supplies ``L`` (m) and ``E I`` (N m^2), ``rho A`` (kg/m).
    speed : float
        Spin speed ``Omega`` (rad/s), needed for time, ``c`` and ``b_h``.

    Examples
    --------
    >>> s = Shaft(length=0.4, diameter=0.1, youngs_modulus=71e9, density=2660,
    ...           shear_modulus=26.2e9, shear_coefficient="seed")
    >>> nd = Dimensionless(s, 11613.8)
    >>> f"{nd.contact_stiffness_si(1e3):.4g}"
    '8.61e+09'
    >>> round(nd.clearance_si(3e-3), 15)
    0.0012
    """

    shaft: Shaft
    speed: float

    @property
    def force_scale(self) -> float:
        """``E I / L^2`` (N): ``F = F' * force_scale``."""
        return self.shaft.bending_stiffness / self.shaft.length**2

    @property
    def speed_parameter(self) -> float:
        """Seed ``c = Omega L^2 sqrt(rho A / (E I))`` (dimensionless)."""
        s = self.shaft
        return self.speed * s.length**2 * math.sqrt(s.mass_per_length / s.bending_stiffness)

    @staticmethod
    def speed_from_parameter(shaft: Shaft, c: float) -> float:
        """Spin speed ``Omega`` (rad/s) of the seed speed parameter ``c`` (dimensionless)."""
        return c / (shaft.length**2 * math.sqrt(shaft.mass_per_length / shaft.bending_stiffness))

    def time_si(self, tau):
        """Time ``t = tau / Omega`` (s) of dimensionless time ``tau`` (rad of spin)."""
        return tau / self.speed

    def tau(self, t):
        """Dimensionless time ``tau = Omega t`` of time ``t`` (s)."""
        return self.speed * t

    def length_si(self, x_nd):
        """Length (m) of a dimensionless length ``x / L``."""
        return x_nd * self.shaft.length

    def length_nd(self, x):
        """Dimensionless length ``x / L`` of a length ``x`` (m)."""
        return x / self.shaft.length

    clearance_si = length_si
    clearance_nd = length_nd

    def force_si(self, f_nd):
        """Force (N) of a dimensionless force ``F' = F L^2 / (E I)``."""
        return f_nd * self.force_scale

    def force_nd(self, f):
        """Dimensionless force ``F L^2 / (E I)`` of a force ``f`` (N)."""
        return f / self.force_scale

    def contact_stiffness_si(self, kh_nd):
        """Hertz stiffness ``k_h`` (N/m^1.5) of ``k_h'`` (dimensionless)."""
        return kh_nd * self.shaft.bending_stiffness / self.shaft.length**3.5

    def contact_stiffness_nd(self, kh):
        """Dimensionless Hertz stiffness ``k_h'`` of ``k_h`` (N/m^1.5)."""
        return kh * self.shaft.length**3.5 / self.shaft.bending_stiffness

    def linear_stiffness_si(self, k_nd):
        """Linear contact stiffness (N/m) of its dimensionless value ``k L^3 / (E I)``."""
        return k_nd * self.shaft.bending_stiffness / self.shaft.length**3

    def linear_stiffness_nd(self, k):
        """Dimensionless linear contact stiffness ``k L^3 / (E I)`` of ``k`` (N/m)."""
        return k * self.shaft.length**3 / self.shaft.bending_stiffness

    def contact_damping_si(self, bh_nd):
        """Hunt-Crossley ``b_h`` (s/m) of ``b_h'`` (dimensionless)."""
        return bh_nd / (self.shaft.length * self.speed)

    def contact_damping_nd(self, bh):
        """Dimensionless Hunt-Crossley ``b_h' = b_h L Omega`` of ``b_h`` (s/m)."""
        return bh * self.shaft.length * self.speed

    def unbalance_si(self, u_nd):
        """Unbalance ``m e`` (kg m) of its dimensionless force ``m e Omega^2 L^2/(E I)``."""
        return u_nd * self.force_scale / self.speed**2

    def unbalance_nd(self, me):
        """Dimensionless unbalance force amplitude ``m e Omega^2 L^2 / (E I)`` of ``m e`` (kg m)."""
        return me * self.speed**2 / self.force_scale


def damping_matrix(M: np.ndarray, K: np.ndarray, zeta: float) -> np.ndarray:
    """``C = M Phi diag(2 zeta omega) Phi^T M`` (N s/m) from the non-rotating modes of ``(K, M)``.

    Parameters
    ----------
    M, K : ndarray
        Mass (kg) and stiffness (N/m) matrices of one modal block.
    zeta : float
        Damping ratio of every mode of the block (1).

    Returns
    -------
    ndarray
    """
    if zeta == 0.0:
        return np.zeros_like(M)
    w2, phi = scipy.linalg.eigh(K, M)
    return M @ phi @ np.diag(2 * zeta * np.sqrt(w2)) @ phi.T @ M
