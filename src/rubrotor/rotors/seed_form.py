"""The seed's single-equation Timoshenko form (seed eq. 1, eqs. 4-5), modally expanded.

Selected with ``[shaft] formulation = "seed-eq1"`` (``Shaft(formulation="seed-eq1")``); the
default ``"two-field"`` is ``rubrotor.rotors.shaft``. This is a reproduction switch, not physics:
eq. (1) puts the point forces on the right-hand side of the equation obtained by eliminating the
section rotation, which drops the derivatives of the load (model-notes section 2, 6).

Per mode ``n`` (``k = n pi / L``, deflection ``p = sin(k x) P(t)``, ``P = v + i w``), projecting
eq. (1) on ``sin(k x)`` and keeping the ``L/2`` scaling of ``rubrotor.rotors.shaft``::

    c4 P'''' + c3 P''' + c2 P'' + c1 P' + c0 P = sin(k a) F

    c4 = (L/2) rho^2 I / (kappa G)                 c3 = -i Omega (L/2) rho^2 Ip / (kappa G)
    c2 = (L/2) [rho A + rho I k^2 (1 + E / (kappa G))]
    c1 = -i Omega (L/2) rho Ip k^2                 c0 = (L/2) E I k^4

(``Ip = 2 I``; with ``gyroscopic = false`` the ``Omega`` terms vanish). Its characteristic
polynomial is ``det(M s^2 + Omega G s + K) / ((L/2) kappa G A)`` of the two-field mode: the same
free frequencies. Modal damping (a ratio per mode) is added so that the characteristic polynomial
stays that of the damped two-field mode: the terms of
``[det(M s^2 + (C + Omega G) s + K) - det(M s^2 + Omega G s + K)] / ((L/2) kappa G A)`` are added
to ``c1 .. c3``; at rest each branch is then a damped oscillator of ratio ``zeta``.

The first-order system per mode uses the scaled state ``z = [P, P'/w0, P''/w0^2, P'''/w0^3]``
with ``w0 = (c0/c4)^(1/4)`` (rad/s) so that its eigenvectors are well conditioned; it is
diagonalised and returned as the :class:`~rubrotor.engine.simulate.ModalSystem` the engine runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rubrotor.errors import InputError
from rubrotor.rotors.shaft import FORMULATIONS, Shaft, modal_matrices

__all__ = [
    "FORMULATIONS",
    "seed_coefficients",
    "two_field_determinant",
    "assemble_seed",
    "SeedModalSystem",
]


def _check(shaft: Shaft) -> None:
    if shaft.theory != "timoshenko":
        raise InputError(
            "shaft.theory",
            shaft.theory,
            '"timoshenko" for the seed form (for Rayleigh and Euler-Bernoulli shafts the '
            "single equation is the one-field beam: use rubrotor.engine.simulate.assemble)",
        )


def _poly2(a: np.ndarray) -> np.ndarray:
    """Polynomial (highest power first) of ``det`` of a 2x2 matrix of quadratics ``a[i][j]``."""
    return np.polysub(np.polymul(a[0][0], a[1][1]), np.polymul(a[0][1], a[1][0]))


def two_field_determinant(shaft: Shaft, n: int, speed: float, C=None) -> np.ndarray:
    """``det(M s^2 + (C + Omega G) s + K) / ((L/2) kappa G A)`` of two-field mode ``n``.

    Parameters
    ----------
    shaft : Shaft
        Timoshenko rotor.
    n : int
        Mode number.
    speed : float
        Spin speed ``Omega`` (rad/s).
    C : ndarray, shape (2, 2), optional
        Modal damping matrix of the mode (as ``rubrotor.engine.simulate.assemble`` builds it).

    Returns
    -------
    ndarray, shape (5,), complex
        Coefficients of ``s^4 .. s^0`` in the units of :func:`seed_coefficients`.
    """
    mm = modal_matrices(shaft, n)
    D = speed * mm.G + (np.zeros((2, 2)) if C is None else C)
    a = [[np.array([mm.M[i, j], D[i, j], mm.K[i, j]]) for j in range(2)] for i in range(2)]
    return _poly2(a) / (shaft.length / 2 * shaft.shear_stiffness)


def seed_coefficients(shaft: Shaft, n: int, speed: float, C=None) -> np.ndarray:
    """Coefficients ``[c4, c3, c2, c1, c0]`` of the seed's modal equation of mode ``n``.

    Written term by term from seed eq. (1) (module docstring), plus the damping terms.

    Parameters
    ----------
    shaft : Shaft
        Timoshenko rotor.
    n : int
        Mode number.
    speed : float
        Spin speed ``Omega`` (rad/s).
    C : ndarray, shape (2, 2), optional
        Two-field modal damping matrix of the mode; its terms are carried over (module docstring).

    Returns
    -------
    ndarray, shape (5,), complex
        ``c4`` (kg s^2/m ... scaled by ``L/2``), ``c3``, ``c2`` (kg/m times m), ``c1``, ``c0``
        (N/m times m): the force ``sin(k a) F`` (N) balances ``sum_j c_j P^(j)``.
    """
    _check(shaft)
    k = shaft.wavenumber(n)
    h = shaft.length / 2
    rho, ei = shaft.density, shaft.bending_stiffness
    rho_i = rho * shaft.second_moment
    rho_ip = rho * shaft.polar_moment * (1.0 if shaft.gyroscopic else 0.0)
    kg = shaft.kappa * shaft.G
    c = np.array(
        [
            h * rho * rho_i / kg,
            -1j * speed * h * rho * rho_ip / kg,
            h * (shaft.mass_per_length + rho_i * k**2 * (1 + shaft.youngs_modulus / kg)),
            -1j * speed * h * rho_ip * k**2,
            h * ei * k**4,
        ],
        dtype=complex,
    )
    if C is not None and np.any(C != 0):
        c = c + (two_field_determinant(shaft, n, speed, C) - two_field_determinant(shaft, n, speed))
    return c


@dataclass
class SeedModalSystem:
    """The seed form in diagonal coordinates; same interface as the two-field ``ModalSystem``.

    State per mode ``z = [P, P'/w0, P''/w0^2, P'''/w0^3]`` (``w0`` in ``scales``, rad/s),
    ``z = V y``, ``y' = lam y + beta(a) F``. ``M``, ``K``, ``C`` and the index arrays of the
    two-field system have no meaning here (the form has no mechanical energy); energy tracking
    is refused for it.
    """

    shaft: Shaft
    speed: float
    lam: np.ndarray
    V: np.ndarray
    Vinv: np.ndarray
    coefficients: np.ndarray  # (modes, 5), c4 .. c0
    scales: np.ndarray  # (modes,), w0 (rad/s)
    wavenumbers: np.ndarray
    cond: float = field(default=1.0)

    @property
    def q_index(self) -> np.ndarray:
        """Slots of ``P`` and ``P''/w0^2`` of every mode in ``z``.

        With :attr:`qd_index` (``P'/w0`` and ``P'''/w0^3``) they carry the whole of ``z`` in a
        :class:`~rubrotor.engine.simulate.RotorState`, so runs of the seed form can be continued.
        """
        n = self.V.shape[0]
        return np.sort(np.concatenate([np.arange(0, n, 4), np.arange(2, n, 4)]))

    @property
    def qd_index(self) -> np.ndarray:
        """Slots of ``P'/w0`` and ``P'''/w0^3`` of every mode in ``z`` (see :attr:`q_index`)."""
        return self.q_index + 1

    def _row(self, position: float, slot: int, factor) -> np.ndarray:
        r = np.zeros(self.V.shape[0], complex)
        for i, k in enumerate(self.wavenumbers):
            r[4 * i + slot] = math.sin(k * position) * factor[i]
        return r

    def force_input(self, position: float) -> np.ndarray:
        """``beta`` (eigen-coordinates per N) of a point force at ``position`` (m)."""
        b = self._row(position, 3, 1.0 / (self.coefficients[:, 0] * self.scales**3))
        return self.Vinv @ b

    def displacement_row(self, position: float) -> np.ndarray:
        """Row mapping ``y`` to the complex deflection ``v + i w`` (m) at ``position`` (m)."""
        return self._row(position, 0, np.ones(len(self.scales))) @ self.V

    def velocity_row(self, position: float) -> np.ndarray:
        """Row mapping ``y`` to the complex velocity (m/s) at ``position`` (m)."""
        return self._row(position, 1, self.scales) @ self.V

    def energy(self, y: np.ndarray) -> float:
        """Not defined for the seed form: raises :class:`~rubrotor.InputError`."""
        raise InputError(
            "track_energy", True, 'shaft.formulation = "two-field" (the seed form has no energy)'
        )


def companion(coefficients: np.ndarray, scale: float) -> np.ndarray:
    """First-order matrix (1/s) of one mode in the scaled state ``[P, P'/w0, P''/w0^2, P'''/w0^3]``.

    Parameters
    ----------
    coefficients : ndarray, shape (5,)
        ``c4 .. c0`` of :func:`seed_coefficients`.
    scale : float
        ``w0`` (rad/s).

    Returns
    -------
    ndarray, shape (4, 4), complex
    """
    c4 = coefficients[0]
    a = np.zeros((4, 4), complex)
    a[0, 1] = a[1, 2] = a[2, 3] = scale
    for j in range(4):  # column j holds P^(j) / w0^j
        a[3, j] = -coefficients[4 - j] * scale**j / (c4 * scale**3)
    return a


def assemble_seed(shaft: Shaft, speed: float, damping=None) -> SeedModalSystem:
    """Assemble and diagonalise the seed form at spin ``speed`` (rad/s).

    Parameters
    ----------
    shaft : Shaft
        Timoshenko rotor (``formulation`` is not read: this always builds the seed form).
    speed : float
        Spin speed ``Omega`` (rad/s).
    damping : ModalDamping, optional
        Modal damping ratios (carried over as described in the module docstring).

    Returns
    -------
    SeedModalSystem
    """
    from rubrotor.rotors.shaft import damping_matrix

    _check(shaft)
    nm = shaft.modes
    coefs = np.empty((nm, 5), complex)
    scales = np.empty(nm)
    lam = np.empty(4 * nm, complex)
    V = np.zeros((4 * nm, 4 * nm), complex)
    Vinv = np.zeros_like(V)
    cond = 1.0
    for i, n in enumerate(range(1, nm + 1)):
        mm = modal_matrices(shaft, n)
        zeta = damping.ratio(n) if damping is not None else 0.0
        c = seed_coefficients(shaft, n, speed, damping_matrix(mm.M, mm.K, zeta))
        w0 = float((c[4].real / c[0].real) ** 0.25)
        lam_b, v = np.linalg.eig(companion(c, w0))
        v = v / np.linalg.norm(v, axis=0)
        vinv = np.linalg.inv(v)
        cond = max(cond, np.abs(v).sum(axis=0).max() * np.abs(vinv).sum(axis=0).max())
        sl = slice(4 * i, 4 * i + 4)
        coefs[i], scales[i], lam[sl], V[sl, sl], Vinv[sl, sl] = c, w0, lam_b, v, vinv
    if cond > 1e12:
        raise InputError(
            "speed", speed, "a speed where the modal system is diagonalisable (move it slightly)"
        )
    return SeedModalSystem(
        shaft=shaft,
        speed=speed,
        lam=lam,
        V=V,
        Vinv=Vinv,
        coefficients=coefs,
        scales=scales,
        wavenumbers=np.array([shaft.wavenumber(n) for n in range(1, nm + 1)]),
        cond=cond,
    )
