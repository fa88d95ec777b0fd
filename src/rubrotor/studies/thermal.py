"""Thermal rub (the Newkirk effect): a rubbing rotor bows towards its hot spot and spirals.

A light rub heats the rotor at the part of its surface that touches the stator (the hot spot);
the rotor bows towards it, the bow changes the synchronous response, which moves the rub. The
model has two time scales (the derivation, the assumptions and the literature are on the
documentation page ``docs/guide/thermal.md``):

* fast (one revolution): for a given bow ``b_j`` (m, complex, rotor-fixed frame) at every
  contact station ``j``, the steady rub orbit of the rotor, on which the bow acts as a bent
  shaft does: a forcing ``K_s Phi_j b_j`` turning with the rotor (``K_s`` the shaft's own
  stiffness without bearings, ``Phi_j`` the bow shape scaled to 1 at station ``j``);
* slow (the thermal time constant ``tau``, minutes): the bow relaxes towards the bow driven by
  the heat input, ``tau b_j' = -b_j + beta exp(-i phi) H_j``, with ``H_j`` (W) the friction power
  ``mu N R Omega`` at station ``j`` averaged over one revolution of the steady orbit, as a
  vector pointing at the contact point in the rotor-fixed frame (the high spot).

:func:`closed_form` solves the Jeffcott rotor (or any isotropic rotor through its receptances at
the contact station) with a linear contact law exactly: steady state, eigenvalues of the slow
dynamics, growth rate and spiral period. :class:`ThermalModel` solves any general rotor the
engine runs: steady orbits by shooting on the engine's map
(:mod:`rubrotor.orbits.general_map`), the slow dynamics by :func:`scipy.integrate.solve_ivp`,
the linearisation about the steady bow by central differences.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from rubrotor.errors import InputError, ScenarioError
from rubrotor.rotors.forces import ThermalBow

__all__ = [
    "SlowLinear",
    "closed_form",
    "jeffcott_receptances",
    "ThermalModel",
    "growth_against_speed",
    "slow_run",
]


@dataclass(frozen=True)
class SlowLinear:
    """A steady state of the slow (thermal) dynamics and its linearisation.

    Attributes
    ----------
    speed : float
        Spin speed (rad/s).
    bow : ndarray of complex
        Steady bow per contact station (m, rotor-fixed frame).
    high_spot : ndarray of complex
        Synchronous deflection of the rotor at each contact station relative to its stator
        centre (m, rotor-fixed frame: the high spot's direction and the orbit radius).
    heat : ndarray of complex
        Revolution-averaged heat input per station (W), pointing at the hot spot's high spot.
    eigenvalues : ndarray of complex
        Eigenvalues of the linearised slow dynamics (1/s), largest real part first; of a
        complex pair the one whose ``Im`` has the sign of the sense the bow turns in
        (rotor-fixed frame: > 0 with the spin, < 0 against it).
    growth_rate : float
        Largest real part (1/s): > 0 the spiral grows.
    spiral_frequency : float
        ``Im`` of that eigenvalue (rad/s, signed as above).
    spiral_period : float
        ``2 pi / |Im lambda|`` (s) of the eigenvalue with the largest real part (inf if real).
    """

    speed: float
    bow: np.ndarray
    high_spot: np.ndarray
    heat: np.ndarray
    eigenvalues: np.ndarray
    growth_rate: float
    spiral_period: float

    @property
    def spiral_frequency(self) -> float:
        """``Im`` of the leading eigenvalue (rad/s, signed: > 0 turning with the spin)."""
        return float(self.eigenvalues[0].imag)


def _signed(jac: np.ndarray) -> np.ndarray:
    """Eigenvalues of the real slow Jacobian ``jac`` (1/s, on ``[Re b, Im b]``), largest real
    part first; of a complex pair the one whose sign of ``Im`` is the sense in which the bow
    vectors turn (``e^{i Im(lambda) t}``: > 0 with the spin, < 0 against it)."""
    lam, vec = np.linalg.eig(jac)
    n = jac.shape[0] // 2
    out = []
    for k in np.argsort(-lam.real, kind="stable"):
        w = vec[:, k]
        forward = np.sum(np.abs(w[:n] + 1j * w[n:]) ** 2)  # turns as e^{i Im(lam) t}
        backward = np.sum(np.abs(np.conj(w[:n]) + 1j * np.conj(w[n:])) ** 2)
        out.append(lam[k] if forward >= backward else np.conj(lam[k]))
    return np.array(out, complex)


def _summary(speed, bow, high, heat, jac) -> SlowLinear:
    lam = _signed(np.asarray(jac, float))
    period = 2 * math.pi / abs(lam[0].imag) if lam[0].imag != 0 else math.inf
    return SlowLinear(float(speed), np.atleast_1d(bow), np.atleast_1d(high),
                      np.atleast_1d(heat), lam, float(lam[0].real), float(period))  # fmt: skip


def jeffcott_receptances(mass, stiffness, damping, speed, unbalance=0.0):
    """Receptances of a Jeffcott rotor for :func:`closed_form`.

    Parameters
    ----------
    mass : float
        Disk mass ``m`` (kg).
    stiffness : float
        Shaft stiffness ``k`` (N/m) between the disk and rigid bearings.
    damping : float
        Viscous damping ``c`` (N s/m) on the disk.
    speed : float
        Spin speed ``Omega`` (rad/s).
    unbalance : float
        ``m e`` (kg m) at angle 0 of the rotor-fixed frame.

    Returns
    -------
    contact, bow, unbalance_response : complex
        ``1/D`` (m/N), ``k/D`` (1) and ``m e Omega^2 / D`` (m), ``D = k - m Omega^2 + i c Omega``:
        the forward synchronous deflection per unit contact force, per unit bow, and under the
        unbalance.
    """
    d = stiffness - mass * speed**2 + 1j * damping * speed
    return 1 / d, stiffness / d, unbalance * speed**2 / d


def _steady_amplitude(d, e, f, clearance) -> float:
    """Largest root ``rho > clearance`` of ``|(D + E) rho - E g| = |f|``; nan if none."""
    a = abs(d + e) ** 2
    b = -2 * clearance * (np.conj(e) * (d + e)).real
    c = abs(e) ** 2 * clearance**2 - abs(f) ** 2
    disc = b * b - 4 * a * c
    if disc < 0:
        return math.nan
    rho = (-b + math.sqrt(disc)) / (2 * a)
    return rho if rho > clearance else math.nan


def closed_form(contact, bow, unbalance_response, *, speed, clearance, contact_stiffness,
                friction, radius, thermal: ThermalBow) -> SlowLinear:  # fmt: skip
    """Steady thermal bow and its linear stability for one contact with a linear law, exactly.

    The rotor is isotropic and linear, its stator rigid and centred; at the contact station its
    forward synchronous deflection is ``Z = Z_u + H_b b + H_c F`` (rotor-fixed frame, m) with
    the contact force ``F = -k_c (|Z| - g)(1 + i mu) Z/|Z|`` (N). With ``D = 1/H_c``,
    ``kappa = H_b/H_c``, ``f = Z_u/H_c``, ``G = beta mu R Omega k_c`` and
    ``E = k_c (1 + i mu) - kappa G e^{-i phi}``, the steady radius ``rho`` solves
    ``|(D + E) rho - E g| = |f|`` (a quadratic) and the slow dynamics linearised about it, in the
    frame of the high spot ``v = e^{-i theta} delta b``, is
    ``tau v' = -v + G e^{-i phi} (s a v + c Re(a v))`` with ``s = 1 - g/rho``,
    ``D_s = D + s k_c (1 + i mu)``, ``a = kappa/D_s`` and ``c`` from the radial constraint (see the
    documentation page), a real 2x2 system (its eigenvalues: :func:`numpy.linalg.eigvals`
    on the 2x2 matrix, whose trace and determinant are explicit). With ``g = 0``
    (``s = 1``) they are ``(-1 + G e^{-i phi} kappa/(D + k_c (1 + i mu)))/tau`` and its conjugate.

    Parameters
    ----------
    contact, bow, unbalance_response : complex
        ``H_c`` (m/N), ``H_b`` (1), ``Z_u`` (m): e.g. :func:`jeffcott_receptances`.
    speed : float
        ``Omega`` (rad/s).
    clearance : float
        ``g`` (m), >= 0.
    contact_stiffness : float
        ``k_c`` (N/m).
    friction : float
        ``mu`` (1).
    radius : float
        ``R`` (m), the rubbing surface radius (sliding speed ``R Omega``).
    thermal : ThermalBow
        ``tau`` (s), ``beta`` (m/W), ``phi`` (rad).

    Returns
    -------
    SlowLinear
        ``high_spot`` is ``Z`` (m); nan everywhere when the steady orbit does not touch.
    """
    d, kap, f = 1 / contact, bow / contact, unbalance_response / contact
    kc, mu, g = contact_stiffness, friction, clearance
    gain = thermal.bow_per_heat * mu * radius * speed * kc
    rot = complex(math.cos(thermal.hot_spot_lag), -math.sin(thermal.hot_spot_lag))
    e = kc * (1 + 1j * mu) - kap * gain * rot
    rho = _steady_amplitude(d, e, f, g)
    if math.isnan(rho):
        nan = complex(math.nan, math.nan)
        return SlowLinear(float(speed), *(np.array([nan]),) * 3, np.array([nan, nan]),
                          math.nan, math.nan)  # fmt: skip
    direction = f / ((d + e) * rho - e * g)
    direction /= abs(direction)
    heat = mu * radius * speed * kc * (rho - g) * direction
    s = 1 - g / rho
    ds = d + s * kc * (1 + 1j * mu)
    kappa_r = (1 - s) * kc * (1 + 1j * mu)
    a = kap / ds
    den = 1 + (kappa_r / ds).real
    p = gain * rot * s * a
    cc = gain * rot * ((1 - s) - s * kappa_r / ds) / den
    m = np.array([[p.real, -p.imag], [p.imag, p.real]])
    m += np.outer([cc.real, cc.imag], [a.real, -a.imag])
    bow0 = thermal.bow_per_heat * rot * heat
    jac = (m - np.eye(2)) / thermal.time_constant  # on [Re v, Im v]; a rotation of delta b
    return _summary(speed, bow0, rho * direction, heat, jac)
