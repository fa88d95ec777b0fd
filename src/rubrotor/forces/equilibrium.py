"""Nonlinear static equilibrium of a rotor on fluid-film supports, and their linearisation there.

A rotor's linear system (:class:`rubrotor.rotors.linear.LinearSystem`) may hold nonlinear
supports: a :class:`~rubrotor.rotors.linear.Support` whose ``term`` is a fluid film
(``short_journal``, ``finite_journal``, ``squeeze_film``). At spin ``Omega`` (rad/s) the static
displacement ``q`` (free DOFs) solves

    R(q) = K_lin(Omega) q - f - sum_b B_b^T F_b(B_b q, Omega) = 0,

``K_lin`` the shaft and the linear supports, ``f`` the constant loads (gravity on the shaft and
disk masses, the consistent load ``M r``; point loads), ``B_b`` the two deflection DOFs of support
``b`` and ``F_b`` its force on the journal at rest (the film, or a damper's centring spring). It is
solved by Newton's method with the exact Jacobian ``K_lin + sum_b B_b^T K_b B_b`` (``K_b =
-dF_b/dp``: the compiled short film's analytic Jacobian; the finite film's central differences),
the step halved until the residual decreases and every film stays below the eccentricity ratio
:data:`rubrotor.forces.fluid_film.MAX_ECCENTRICITY`. The start: each film at its own equilibrium
under the load it carries when the films are replaced by equal isotropic springs (for a
statically determinate rotor, two bearings, that load is exact and Newton converges in a step or
two); at a speed near one already solved, Newton starts from that solution instead. The
residual ends below ``1e-12`` of the applied load.

At that position each support is linearised (:class:`SupportLinearisation`): ``K0``, ``C0`` (2x2)
enter the linear system at that speed, so every linear analysis uses the coefficients at the
static equilibrium of the speed it asks, evaluated there exactly (no table, no interpolation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError
from rubrotor.forces.fluid_film import MAX_ECCENTRICITY

__all__ = ["SupportLinearisation", "Linearisation", "nonlinear_supports", "solve_equilibrium",
           "first_speed"]


@dataclass(frozen=True)
class SupportLinearisation:
    """One nonlinear support at the rotor's static equilibrium at one speed (SI).

    Attributes
    ----------
    name : str
        The support's label.
    position : float
        Axial station (m).
    dofs : tuple of int
        Indices ``(i_v, i_w)`` in the full ``q`` of the journal's deflections.
    speed_rad_s : float
        Rotor spin (rad/s); the journal spins with it (a damper's journal does not).
    p0 : ndarray, shape (2,)
        Journal centre relative to the bearing centre, y and z (m).
    force : ndarray, shape (2,)
        The support's force on the journal there (N): ``-load``.
    K0, C0 : ndarray, shape (2, 2)
        Stiffness (N/m) and damping (N s/m) of the linearisation,
        ``F(p, u) ~ force - K0 (p - p0) - C0 u``.
    eccentricity_ratio : float
        ``|p0| / radial_clearance`` (1).
    attitude_angle_rad : float
        Angle from the load on the journal (``-force``) to ``p0``, positive in the spin's sense
        (rad); NaN without load.
    film : object
        The film's kernel parameters (:class:`rubrotor.core.film.Film` for the short films).
    term : object
        The support term (``ShortJournal``, ``SqueezeFilm``, ``FiniteJournal``).
    """

    name: str
    position: float
    dofs: tuple
    speed_rad_s: float
    p0: np.ndarray
    force: np.ndarray
    K0: np.ndarray
    C0: np.ndarray
    eccentricity_ratio: float
    attitude_angle_rad: float
    film: object
    term: object


def nonlinear_supports(system) -> tuple:
    """The supports of ``system`` that carry a nonlinear term, in their order."""
    return tuple(s for s in system.supports if getattr(s.term, "nonlinear", False))


def first_speed(system, max_speed: float, points: int) -> float:
    """Where a speed scan from rest starts (rad/s): 0, or with journal bearings (no film
    without spin) the scan's first step ``max_speed / (points - 1)``."""
    if any(s.term.spins for s in nonlinear_supports(system)):
        return float(max_speed) / max(points - 1, 1)
    return 0.0


def _linear_stiffness(system, speed: float) -> np.ndarray:
    """``K`` (all DOFs) of the shaft and the linear supports at ``speed`` (rad/s)."""
    k = system.K.copy()
    for s in system.supports:
        if getattr(s.term, "nonlinear", False):
            continue
        ks, _ = s.coefficients(speed)
        ix = np.ix_(s.all_dofs, s.all_dofs)
        k[ix] += s.block(ks)
    return k


def _journal_speed(sup, speed: float) -> float:
    return speed if sup.term.spins else 0.0


def _film_sum(system, sups, q_full, speed):
    """``sum B^T F_b`` (N, all DOFs) and ``sum B^T K_b B`` (N/m) at ``q_full``."""
    n = len(system.M)
    f = np.zeros(n)
    k = np.zeros((n, n))
    for s in sups:
        p = q_full[list(s.dofs)]
        fb, kb = s.term.static_force(p, _journal_speed(s, speed))
        f[list(s.dofs)] += fb
        k[np.ix_(s.dofs, s.dofs)] += kb
    return f, k


def _admissible(sups, q_full) -> bool:
    for s in sups:
        c = s.term.radial_clearance
        if not math.hypot(*q_full[list(s.dofs)]) < MAX_ECCENTRICITY * c:
            return False
    return True


def _start(system, sups, k_lin, f_full, speed):
    """The first iterate: each film at its own equilibrium under the load it carries when all
    films are replaced by equal isotropic springs (module docstring)."""
    free = system.free
    w = float(np.linalg.norm(f_full)) or 1.0
    k = k_lin.copy()
    springs = {}
    for s in sups:
        kg = w / (0.3 * s.term.radial_clearance)
        springs[s.name] = kg
        k[np.ix_(s.dofs, s.dofs)] += kg * np.eye(2)
    q = system.expand(np.linalg.solve(k[np.ix_(free, free)], f_full[free]))
    for s in sups:
        if not s.term.spins:
            continue  # a damper's spring is linear: Newton's first step is exact
        load = springs[s.name] * q[list(s.dofs)]
        w = float(np.hypot(*load))
        c = s.term.radial_clearance
        if w > 0:
            try:
                q[list(s.dofs)] = s.term.equilibrium(load, speed).position
            except InputError:  # more than it carries alone: start deep along the load
                q[list(s.dofs)] = 0.9 * c * load / w
        else:
            q[list(s.dofs)] = 0.5 * c * np.array([1.0, 0.0])
    return q


def _check_loaded(system, sups, f_full, speed):
    if any(s.term.spins for s in sups):
        if not speed > 0.0:
            raise InputError("speed", speed, "a spin speed > 0 rad/s: a journal bearing's film "
                             "carries no load without spin")  # fmt: skip
        if not np.any(f_full != 0.0):
            raise InputError("gravity", (0.0, 0.0), "a [gravity] table or [[load]] tables: a "
                             "journal bearing's coefficients are those of the static load it "
                             "carries, and it carries none")  # fmt: skip


def solve_equilibrium(system, speed: float, f_full: np.ndarray, start=None) -> np.ndarray:
    """The static displacement (all DOFs, m and rad) of ``system`` under ``f_full`` (N, all
    DOFs) at ``speed`` (rad/s), its nonlinear supports carrying their part (module docstring).
    ``start`` (all DOFs): a first iterate, e.g. the solution at a nearby speed; if Newton fails
    from it, the start of the module docstring is used.

    Raises
    ------
    InputError
        Naming ``speed`` (0 with journal bearings), ``gravity`` (no load on journal bearings) or
        the support whose film cannot carry its load below the largest eccentricity ratio.
    """
    sups = nonlinear_supports(system)
    k_lin = _linear_stiffness(system, speed)
    free = system.free
    if not sups:
        return system.expand(np.linalg.solve(k_lin[np.ix_(free, free)], f_full[free]))
    _check_loaded(system, sups, f_full, speed)
    if start is not None and _admissible(sups, start):
        try:
            return _newton_system(system, sups, k_lin, f_full, speed, np.array(start, float))
        except InputError:
            pass
    q = _start(system, sups, k_lin, f_full, speed)
    return _newton_system(system, sups, k_lin, f_full, speed, q)


def _newton_system(system, sups, k_lin, f_full, speed, q):
    """Damped Newton on the static problem from ``q`` (module docstring)."""
    free = system.free
    scale = max(float(np.linalg.norm(f_full)), 1e-300)

    def residual(qf):
        fb, kb = _film_sum(system, sups, qf, speed)
        return (k_lin @ qf - f_full - fb)[free], kb

    r, kb = residual(q)
    for _ in range(100):
        if np.linalg.norm(r) <= 1e-12 * scale:
            return q
        jac = (k_lin + kb)[np.ix_(free, free)]
        try:
            dq = system.expand(np.linalg.solve(jac, -r))
        except np.linalg.LinAlgError:  # a film without stiffness there: refused below
            break
        step, norm = 1.0, np.linalg.norm(r)
        while step > 1e-10:
            trial = q + step * dq
            if _admissible(sups, trial):
                rt, kt = residual(trial)
                if np.linalg.norm(rt) < norm:
                    break
            step *= 0.5
        else:
            break
        q, r, kb = trial, rt, kt
        if np.linalg.norm(step * dq) <= 1e-15 * (np.linalg.norm(q) + 1e-300):
            break
    if np.linalg.norm(r) <= 1e-9 * scale:
        return q
    worst = max(sups, key=lambda s: math.hypot(*q[list(s.dofs)]) / s.term.radial_clearance)
    raise InputError(f"bearing {worst.name!r}", float(speed),
                     f"a speed at which its film carries its load below an eccentricity ratio of "
                     f"{MAX_ECCENTRICITY} (rad/s); the static equilibrium was not found")  # fmt: skip


def linearise(sup, q_full: np.ndarray, speed: float) -> SupportLinearisation:
    """Support ``sup`` (a nonlinear one) linearised at the static displacement ``q_full``."""
    p = np.array(q_full[list(sup.dofs)], float)
    spin = _journal_speed(sup, speed)
    force, _ = sup.term.static_force(p, spin)
    k0, c0 = sup.term.linearise(p, spin)
    load = -force
    eps = float(np.hypot(*p)) / sup.term.radial_clearance
    if np.hypot(*load) > 0:
        att = math.atan2(load[0] * p[1] - load[1] * p[0], float(load @ p))
    else:
        att = math.nan
    return SupportLinearisation(sup.name, float(sup.position), tuple(sup.dofs), float(speed), p,
                                np.asarray(force, float), np.asarray(k0, float),
                                np.asarray(c0, float), eps, float(att),
                                getattr(sup.term, "film", None), sup.term)  # fmt: skip


def gravity_load(system, gravity, loads=()) -> np.ndarray:
    """The constant load (N, all DOFs): gravity ``(g_y, g_z)`` (m/s^2) on the nodal masses (the
    consistent load ``M r``) and point loads (``RadialLoad``, N at m; midspan without a position)."""
    g = np.asarray(gravity, float)
    labels = system.dof_labels
    r = np.array([g[0] if s.startswith("v@") else g[1] if s.startswith("w@") else 0.0
                  for s in labels])  # fmt: skip
    f = system.M @ r if len(r) == len(system.M) else np.zeros(len(system.M))
    nodes = getattr(system.basis, "nodes", None)
    for ld in loads:
        x = ld.position
        if x is None:
            x = 0.5 * (float(nodes[0]) + float(nodes[-1])) if nodes is not None else 0.5 * system.basis.length
        f = f + system.basis.rows(float(x)).T @ np.array([ld.force_y, ld.force_z], float)
    return f


class Linearisation:
    """The static equilibria of one rotor at the speeds asked, kept (one per speed).

    ``law(i)`` gives the ``i``-th nonlinear support's law ``speed -> (K0, C0)``;
    :meth:`states` all nonlinear supports at a speed.

    Parameters
    ----------
    system : LinearSystem
        The rotor with its nonlinear supports (their own ``k``, ``c`` unused).
    f_full : ndarray
        The constant load (N, all DOFs).
    """

    def __init__(self, system, f_full: np.ndarray):
        self.system = system
        self.f_full = np.asarray(f_full, float)
        self._cache: dict = {}

    def solve(self, speed: float) -> tuple[np.ndarray, tuple]:
        """``(q_full, states)`` at ``speed`` (rad/s)."""
        key = float(speed)
        if key not in self._cache:
            near = min(self._cache, key=lambda w: abs(w - key), default=None)
            start = self._cache[near][0] if near is not None else None
            q = solve_equilibrium(self.system, key, self.f_full, start)
            states = tuple(linearise(s, q, key) for s in nonlinear_supports(self.system))
            if len(self._cache) > 4096:
                self._cache.clear()
            self._cache[key] = (q, states)
        return self._cache[key]

    def states(self, speed: float) -> tuple:
        """The :class:`SupportLinearisation` of every nonlinear support at ``speed`` (rad/s)."""
        return self.solve(speed)[1]

    def law(self, index: int) -> _Law:
        """``speed -> (K0, C0)`` of the ``index``-th nonlinear support (:func:`nonlinear_supports`)."""
        return _Law(self, index)


@dataclass(frozen=True)
class _Law:
    """One support's coefficients at each speed: ``law(speed) -> (K0, C0)`` (N/m, N s/m)."""

    linearisation: Linearisation
    index: int

    def __call__(self, speed: float):
        st = self.linearisation.states(speed)[self.index]
        return st.K0, st.C0
