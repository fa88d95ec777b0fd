"""The Timoshenko beam element of rotordynamics (Nelson & McVaugh 1976, Nelson 1980).

One element of length ``l`` joins two nodes with four DOFs each, ordered
``[v1, w1, psi_v1, psi_w1, v2, w2, psi_v2, psi_w2]`` (deflections in m, section rotations in
rad; see ``rubrotor.rotors.linear``). Because the rotations of both planes are taken with the same
sign as the slopes (``psi_v ~ dv/dx``, ``psi_w ~ dw/dx``), both bending planes have the same
4x4 matrices on ``[v1, psi1, v2, psi2]``; only the gyroscopic matrix couples them.

Shape functions
---------------
With ``xi = x / l`` and the shear parameter ``Phi = 12 E I / (kappa G A l^2)`` the deflection
and rotation are interpolated by the static solution of the Timoshenko beam (constant shear)::

    v   = [ (1 - 3xi^2 + 2xi^3 + Phi (1 - xi)),  l (xi - 2xi^2 + xi^3 + Phi (xi - xi^2)/2),
            (3xi^2 - 2xi^3 + Phi xi),            l (-xi^2 + xi^3 - Phi (xi - xi^2)/2) ] / (1 + Phi)
    psi = [ 6 (xi^2 - xi) / l,  1 - 4xi + 3xi^2 + Phi (1 - xi),
            6 (xi - xi^2) / l,  -2xi + 3xi^2 + Phi xi ] / (1 + Phi)

so that the shear strain ``dv/dx - psi = -Phi / ((1 + Phi) l) [1, l/2, -1, l/2] . q_e`` is
constant along the element.

Matrices (per plane, from these shape functions, as in Friswell et al. 2010, *Dynamics of
Rotating Machines*, section 5.4.6)::

    M_T = rho A  int N_v^T N_v dx        translational inertia (kg)
    M_R = rho I  int N_psi^T N_psi dx    rotatory inertia (kg m^2)
    K   = E I int N_psi'^T N_psi' dx + kappa G A int (N_v' - N_psi)^T (N_v' - N_psi) dx

and the gyroscopic matrix per unit spin, coupling the planes as in the continuous model
(``-i Omega rho Ip Psi'`` with ``Psi = psi_v + i psi_w``, ``Ip = 2 I``)::

    G[v-plane rotations, w-plane rotations] = + rho Ip int N_psi^T N_psi dx = + 2 M_R
    G[w-plane, v-plane]                     = - 2 M_R

``"rayleigh"`` sets ``Phi = 0`` and keeps ``M_R`` and ``G``; ``"euler-bernoulli"`` sets ``Phi = 0``
and drops both. This module only builds element matrices; :mod:`rubrotor.rotors.fe` assembles them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["ElementMatrices", "beam_element", "plane_matrices", "circle_section"]

PLANE_DOFS = ((0, 2, 4, 6), (1, 3, 5, 7))
"""Element DOFs ``[v1, psi1, v2, psi2]`` of the ``v`` plane and of the ``w`` plane."""


@dataclass(frozen=True)
class ElementMatrices:
    """The 8x8 matrices of one element on ``[v1, w1, psi_v1, psi_w1, v2, w2, psi_v2, psi_w2]``.

    Attributes
    ----------
    M : ndarray
        Mass matrix (kg, kg m, kg m^2 blocks), symmetric.
    K : ndarray
        Stiffness matrix (N/m, N, N m blocks), symmetric.
    G : ndarray
        Gyroscopic matrix per unit spin (kg m^2 blocks), skew-symmetric.
    """

    M: np.ndarray
    K: np.ndarray
    G: np.ndarray


def circle_section(diameter: float, bore_diameter: float = 0.0) -> tuple[float, float]:
    """Area ``A`` (m^2) and second moment ``I`` (m^4) of a hollow circle (diameters in m)."""
    area = math.pi * (diameter**2 - bore_diameter**2) / 4
    second = math.pi * (diameter**4 - bore_diameter**4) / 64
    return area, second


def plane_matrices(length: float, phi: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit-property matrices of one plane on ``[v1, psi1, v2, psi2]``.

    Parameters
    ----------
    length : float
        Element length ``l`` (m).
    phi : float
        Shear parameter ``Phi = 12 E I / (kappa G A l^2)`` (dimensionless), 0 without shear.

    Returns
    -------
    mt, mr, k : ndarray, shape (4, 4)
        ``int N_v^T N_v dx`` (m, m^2, m^3 blocks), ``int N_psi^T N_psi dx`` (m^-1, 1, m
        blocks) and the stiffness per unit ``E I``, bending and shear energy together
        (m^-3, m^-2, m^-1 blocks), in closed form.
    """
    l, p = length, phi
    d = 1 + p
    m1, m3 = 312 + 588 * p + 280 * p**2, 108 + 252 * p + 140 * p**2
    m2, m4 = (44 + 77 * p + 35 * p**2) * l, -(26 + 63 * p + 35 * p**2) * l
    m5, m6 = (8 + 14 * p + 7 * p**2) * l**2, -(6 + 14 * p + 7 * p**2) * l**2
    mt = (l / (840 * d**2)) * np.array(
        [[m1, m2, m3, m4], [m2, m5, -m4, m6], [m3, -m4, m1, -m2], [m4, m6, -m2, m5]]
    )
    a, b = 36.0, (3 - 15 * p) * l
    c, e = (4 + 5 * p + 10 * p**2) * l**2, (-1 - 5 * p + 5 * p**2) * l**2
    mr = (1 / (30 * d**2 * l)) * np.array(
        [[a, b, -a, b], [b, c, -b, e], [-a, -b, a, -b], [b, e, -b, c]]
    )
    k = (1 / (d * l**3)) * np.array(
        [
            [12, 6 * l, -12, 6 * l],
            [6 * l, (4 + p) * l**2, -6 * l, (2 - p) * l**2],
            [-12, -6 * l, 12, -6 * l],
            [6 * l, (2 - p) * l**2, -6 * l, (4 + p) * l**2],
        ]
    )
    return mt, mr, k


def beam_element(
    length: float,
    youngs_modulus: float,
    shear_modulus: float,
    density: float,
    diameter: float,
    bore_diameter: float = 0.0,
    kappa: float = 1.0,
    theory: str = "timoshenko",
    gyroscopic: bool = True,
) -> ElementMatrices:
    """Matrices of one shaft element (Nelson 1980), for our DOF convention.

    Parameters
    ----------
    length : float
        Element length (m).
    youngs_modulus, shear_modulus : float
        ``E`` and ``G`` (Pa).
    density : float
        ``rho`` (kg/m^3).
    diameter, bore_diameter : float
        Outer and inner diameter (m).
    kappa : float
        Shear coefficient (dimensionless), used by ``"timoshenko"`` only.
    theory : {"timoshenko", "rayleigh", "euler-bernoulli"}
        Beam theory.
    gyroscopic : bool
        Include the gyroscopic matrix (never for Euler-Bernoulli).

    Returns
    -------
    ElementMatrices
        ``M``, ``K``, ``G`` (8x8).
    """
    area, second = circle_section(diameter, bore_diameter)
    ei = youngs_modulus * second
    phi = 12 * ei / (kappa * shear_modulus * area * length**2) if theory == "timoshenko" else 0.0
    mt, mr, kb = plane_matrices(length, phi)
    rotary = density * second if theory != "euler-bernoulli" else 0.0
    gyro = 2 * rotary if gyroscopic else 0.0
    m_plane = density * area * mt + rotary * mr
    k_plane = ei * kb
    M = np.zeros((8, 8))
    K = np.zeros((8, 8))
    G = np.zeros((8, 8))
    pv, pw = PLANE_DOFS
    for dofs in PLANE_DOFS:
        ix = np.ix_(dofs, dofs)
        M[ix] = m_plane
        K[ix] = k_plane
    G[np.ix_(pv, pw)] = gyro * mr
    G[np.ix_(pw, pv)] = -gyro * mr
    return ElementMatrices(M=M, K=K, G=G)
