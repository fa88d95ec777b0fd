"""Synchronous orbits of an axisymmetric rotor, exactly: equilibria of the rotating frame.

The seed-form rotor is axisymmetric (complex modal coordinates ``q = y + i z``, complex-linear
equations) and its stator is a centred ring, whose contact law is equivariant under rotation:
``F(p e^{ia}, u e^{ia}) = F(p, u) e^{ia}`` (it depends only on the penetration, the radial
velocity and the sliding speed ``R Omega + t . u``). Without a constant load the only forcing is
the unbalance ``f_u e^{i Omega t}``. In the eigen-coordinates of the linear part, ``y' = lam y +
beta_u f_u e^{i Omega t} + beta_c F(c_d y, c_v y)``, the rotating coordinates ``w = y e^{-i Omega
t}`` therefore obey the AUTONOMOUS system

``w' = (lam - i Omega) w + beta_u f_u + beta_c F(c_d w, c_v w)``,

and every synchronous orbit (a circular whirl at the spin speed: the no-contact response and the
full annular rub) is one of its equilibria. It is found by Newton on this algebraic equation:
no time stepping, so to rounding (harmonic balance with one harmonic solves the same equation).

Stability: at ``t = T = 2 pi / Omega`` the rotating and fixed coordinates coincide
(``e^{-i Omega T} = 1``), so the fixed-frame monodromy matrix is ``exp(J T)``, with ``J`` the
real Jacobian of the rotating-frame field in the state coordinates of ``rubrotor.orbits.shooting``
(``[Re q, Im q, Re q', Im q']``); its eigenvalues, the Floquet multipliers, are ``exp(eig(J) T)``.
Without contact ``J`` has the eigenvalues ``lam - i Omega`` and the multipliers are
``exp(lam T)``, those of the linear system. The contact force is real-linearised with its exact
Jacobian (``rubrotor.core.contact.contact_force_jac_exact``, smoothed friction sign
included).

Orbits that are not circles (partial rub, a side load, gravity, sub- and super-harmonic
orbits) are not equilibria of this frame: they are found by shooting.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import scipy.linalg

from rubrotor.core.terms import term_jac_exact
from rubrotor.engine.simulate import _particular, contact_parameters
from rubrotor.errors import InputError
from rubrotor.orbits.shooting import (
    STEPS_PER_REVOLUTION,
    PeriodicOrbit,
    _gyroscopic,
    _Map,
    multipliers_of,
    state_vector,
    vector_state,
)
from rubrotor.rotors.forces import Unbalance

CIRCULAR_TOL = 1e-4
"""Relative size of the rotating-frame field (``|f(x)| / |x|``, one radian of spin) below which
a shot orbit counts as circular, so that :func:`synchronous_orbit` may refine it. A shot circle
is off by the map's step error (~1e-7 at 1024 steps per revolution); a partial rub's field is
of the order of its radius variation over the orbit (1e-2 or more)."""


def unsupported(scenario, k: int = 1) -> str | None:
    """Why the synchronous route does not apply (None when it does).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The rotor, speed, unbalance, contact, load.
    k : int
        Revolutions per period (the route finds period-1 orbits).
    """
    if k != 1:
        return f"k = {k}: synchronous orbits have one revolution per period"
    load = scenario.load
    if load is not None and (load.force_y != 0 or load.force_z != 0):
        return "a constant load (its orbit is not a circle)"
    return None


class Field:
    """The rotating-frame field of one scenario, on the prepared parts of a ``_Map``.

    The field ``f(x)`` is the time derivative of the state vector ``x`` (m, m/s) in the
    rotating coordinates divided by the spin speed (so in m and m/s per radian of spin, the
    units of the shooting residual ``P(x) - x``).

    Parameters
    ----------
    mp : rubrotor.orbits.shooting._Map
        The prepared map (modal system, contact rows, steady unbalance response, contact law).
    """

    def __init__(self, mp: _Map):
        sysm, beta_c, _, _, cdc, cvc, self._to_eig, _ = mp.fixed
        self.map, self.speed = mp, mp.speed
        self._shift = sysm.lam - 1j * mp.speed  # lam - i Omega
        self._beta_c, self._cdc, self._cvc, self._cp = beta_c, cdc, cvc, mp.cp
        self._y_u, self._part_c, self._vel_c = mp.y_u, mp.coef.part_c, mp.coef.vel_cz

    def at_speed(self, speed: float) -> Field:
        """The field at another spin speed (rad/s), rebuilding only what the speed changes.

        A gyroscopic modal system is re-assembled (``_Map.at_speed``); otherwise only the
        shift ``lam - i Omega``, the steady unbalance response and the surface speed change
        (no step coefficients: the field has no time step). Going through ``_Map.at_speed``
        every time would build those coefficients too: measured 13 % slower on the annular
        branch and a worst point 0.65-0.81 instead of 0.47-0.59 of pyHarm's best.
        """
        moving = self.map.__dict__.get("_gyro")
        if moving is None:
            moving = self.map._gyro = _gyroscopic(self.map.scenario.shaft)
        if moving:
            return Field(self.map.at_speed(speed))
        sc = self.map.scenario
        unb = sc.unbalance or Unbalance(0.0)
        sysm, _, beta_u, beta_l = self.map.fixed[:4]
        fu0 = unb.magnitude * speed**2 * complex(math.cos(unb.phase), math.sin(unb.phase))
        other = copy.copy(self)
        other.speed, other._shift = speed, sysm.lam - 1j * speed
        other._y_u = _particular(sysm, speed, beta_u, beta_l, fu0, 0j, unb)[0]
        other._part_c = complex(self._cdc @ other._y_u)
        other._vel_c = 1j * speed * other._part_c
        other._cp = contact_parameters(sc.shaft, speed, sc.contact)
        return other

    def _contact(self, ys):
        """Contact-station displacement (m) and velocity (m/s), force (N), 2 x 4 Jacobian."""
        p = self._part_c + self._cdc @ ys
        u = self._vel_c + self._cvc @ ys
        jk = np.zeros((2, 4))
        fy, fz, _, _ = term_jac_exact(p.real, p.imag, u.real, u.imag, self._cp, jk)
        return p, complex(fy, fz), jk

    def evaluate(self, x: np.ndarray, jacobian: bool = False):
        """``(f(x), df/dx or None, contact-station radius m)`` at the state vector ``x``."""
        ys = self._to_eig @ np.asarray(x, float) - self._y_u  # shifted by the steady response
        p, force, jk = self._contact(ys)
        rate = self._shift * ys + self._beta_c * force
        f = self.map.physical(rate)[0] / self.speed
        if not jacobian:
            return f, None, abs(p)
        du = self._to_eig  # columns: eigen-coordinates of the unit state components
        dp, dv = self._cdc @ du, self._cvc @ du
        parts = np.stack([dp.real, dp.imag, dv.real, dv.imag])
        dforce = (jk[0] @ parts) + 1j * (jk[1] @ parts)
        drate = self._shift[:, None] * du + self._beta_c[:, None] * dforce[None, :]
        return f, self.map.physical(drate.T).T / self.speed, abs(p)

    def monodromy(self, jac_field: np.ndarray, k: int = 1) -> np.ndarray:
        """``exp(J T)`` from the field's Jacobian (per radian): ``T Omega = 2 pi k``."""
        return scipy.linalg.expm(2 * math.pi * k * jac_field)


def newton_equilibrium(field: Field, x0, tol: float = 1e-13, max_iter: int = 30):
    """Newton on ``f(x) = 0``; returns ``(x, df/dx, |f| / |x|, iterations)``."""
    x = np.asarray(x0, float).copy()
    for it in range(1, max_iter + 1):
        f, jac, _ = field.evaluate(x, True)
        dx = np.linalg.solve(jac, -f)
        x = x + dx
        if not np.all(np.isfinite(x)):
            break
        if np.linalg.norm(dx) <= tol * max(np.linalg.norm(x), 1e-30):
            f, jac, _ = field.evaluate(x, True)
            return x, jac, np.linalg.norm(f) / max(np.linalg.norm(x), 1e-30), it
    raise InputError(
        "synchronous", f"no convergence in {max_iter} Newton iterations", "a closer guess"
    )


def synchronous_orbit(scenario, guess=None, *, tol: float = 1e-13) -> PeriodicOrbit:
    """The synchronous (circular, period-1) orbit near ``guess``, exactly.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A seed-form rotor without a constant load (``unsupported``), its speed (rad/s),
        unbalance and contact.
    guess : RotorState, optional
        Start of Newton (e.g. a shot orbit or a simulation's final state at unbalance angle
        0); default the steady no-contact response.
    tol : float
        Relative Newton step at which to stop (dimensionless).

    Returns
    -------
    PeriodicOrbit
        ``steps`` is 0 (no time stepping); ``residual`` is ``|f(x)| / |x|`` of the
        rotating-frame field; the multipliers are those of ``exp(J T)``.
    """
    why = unsupported(scenario)
    if why is not None:
        raise InputError("method", "synchronous", f"a scenario without {why}; use shooting")
    field = Field(_Map(scenario, 1, STEPS_PER_REVOLUTION))
    if guess is None:
        x0 = field.map.physical(field._y_u)[0]
    else:
        x0 = state_vector(guess)
    x, jac, residual, it = newton_equilibrium(field, x0, tol)
    mu = multipliers_of(field.monodromy(jac))
    return PeriodicOrbit(
        scenario=scenario,
        state=vector_state(x),
        k=1,
        period=2 * math.pi / scenario.speed,
        multipliers=mu,
        stable=bool(np.abs(mu[0]) < 1.0),
        residual=float(residual),
        iterations=it,
        steps=0,
    )


def is_circular(scenario, x: np.ndarray) -> bool:
    """Whether the state ``x`` (m, m/s) at unbalance angle 0 lies on a near-circular orbit."""
    f = Field(_Map(scenario, 1, STEPS_PER_REVOLUTION)).evaluate(x)[0]
    return bool(np.linalg.norm(f) <= CIRCULAR_TOL * np.linalg.norm(x))
