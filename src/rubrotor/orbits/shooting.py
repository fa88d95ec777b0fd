"""Periodic orbits by shooting: Newton on the stroboscopic map over k revolutions.

The map ``P(x)`` takes the physical modal state ``x`` (real vector ``[Re q, Im q, Re q', Im q']``,
m and m/s) at unbalance angle 0 to the state ``k`` revolutions later by the fixed-step
exponential scheme of the simulation (:func:`rubrotor.core.integrate.expo_fixed`, same
arithmetic), run by ``_Map``: the modal system, contact law and step coefficients are
prepared once per parameter value and the compiled kernel :func:`rubrotor.core.shoot.expo_strobe`
runs on plain arrays. A fixed step makes ``P`` a smooth function of ``x`` (an adaptive step
sequence changes discontinuously with the start state, which breaks Newton's quadratic
convergence). The fixed point is the periodic orbit of the discrete scheme, second order in the
step.

Monodromy: the exact Jacobian of the discrete map, propagated in the same compiled run by the
variational equations of the scheme (:mod:`rubrotor.core.shoot`, which says why the full matrix
needs no re-orthonormalisation over ``k`` revolutions): one run instead of the ``2 dim + 1`` of
central differences, and no difference error. :func:`monodromy_fd` keeps the central
differences as a second route for the tests.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.core.shoot import expo_strobe, phi12
from rubrotor.engine.settings import Integrator
from rubrotor.engine.shaft_steppers import MapStep
from rubrotor.engine.simulate import (
    RotorState,
    _particular,
    _positions,
    assemble,
    contact_parameters,
    simulate_scenario,
)
from rubrotor.errors import InputError
from rubrotor.modelling import model_of
from rubrotor.rotors.forces import Unbalance
from rubrotor.rotors.shaft import modal_matrices

STEPS_PER_REVOLUTION = 1024
FD_STEP = 6e-6


def state_vector(state: RotorState) -> np.ndarray:
    """Real vector ``[Re q, Im q, Re q', Im q']`` (m, m/s) of a :class:`RotorState`.

    A general rotor's state is already such a vector (``[Re y, Im y, F]`` of
    ``rubrotor.orbits.general_map``) and is returned as it is.
    """
    if isinstance(state, np.ndarray):
        return np.asarray(state, float)
    q, qd = np.asarray(state.q, complex), np.asarray(state.qd, complex)
    return np.concatenate([q.real, q.imag, qd.real, qd.imag])


def vector_state(x: np.ndarray) -> RotorState:
    """The :class:`RotorState` (unbalance angle 0) of a real vector from :func:`state_vector`."""
    n = x.size // 4
    return RotorState(q=x[:n] + 1j * x[n : 2 * n], qd=x[2 * n : 3 * n] + 1j * x[3 * n :], phase=0.0)


def _integrator(k: int, steps: int, save: bool) -> Integrator:
    return Integrator(
        revolutions=float(k),
        dtau=2 * math.pi / steps,
        save_every=1 if save else steps * k,
        max_displacement=1.0,
    )




def _gyroscopic(shaft) -> bool:
    """Whether the modal system changes with the spin speed (gyroscopic terms, seed form)."""
    if shaft.formulation == "seed-eq1" and shaft.theory == "timoshenko":
        return True
    return any(np.any(modal_matrices(shaft, n).G != 0) for n in range(1, shaft.modes + 1))


class _Map:
    """The stroboscopic map of one scenario, prepared once for many runs.

    Holds the assembled modal system, the contact law and the step coefficients, and runs the
    compiled kernel :func:`rubrotor.core.shoot.expo_strobe` on plain arrays (no simulation
    driver, no result objects). :meth:`at_speed` re-derives only what depends on the spin speed
    (step in seconds, propagators, unbalance force and its steady response, surface speed),
    reusing the modal system unless it is gyroscopic.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        Rotor, speed (rad/s), unbalance, contact, load, damping.
    k : int
        Revolutions per map.
    steps : int
        Fixed steps per revolution.
    speed : float, optional
        Spin speed (rad/s) instead of the scenario's.
    base : _Map, optional
        A map of the same rotor whose modal system is reused (a non-gyroscopic rotor's modes
        do not change with the speed).
    """

    def __init__(self, scenario, k: int, steps: int, speed: float | None = None, base=None):
        if base is None:
            model_of(scenario).require_shaft_engine("periodic orbits (shooting, continuation)")
        self.scenario, self.k, self.steps = scenario, int(k), int(steps)
        speed = float(scenario.speed if speed is None else speed)
        sc = scenario
        unb = sc.unbalance or Unbalance(0.0)
        if base is None:  # the modal system and what only it and the positions fix
            a_u, a_c, a_l, _ = _positions(sc.shaft, _integrator(k, steps, False), unb,
                                          sc.contact, sc.load)  # fmt: skip
            sysm = assemble(sc.shaft, speed, sc.damping)
            beta_c, beta_u, beta_l = (sysm.force_input(a) for a in (a_c, a_u, a_l))
            cdc = np.ascontiguousarray(sysm.displacement_row(a_c))
            cvc = np.ascontiguousarray(sysm.velocity_row(a_c))
            qi, qdi, vinv = sysm.q_index, sysm.qd_index, sysm.Vinv
            # real state vector -> eigen-coordinates (columns: unit Re q, Im q, Re q', Im q')
            to_eig = np.hstack([vinv[:, qi], 1j * vinv[:, qi], vinv[:, qdi], 1j * vinv[:, qdi]])
            from_eig = np.ascontiguousarray(sysm.V[np.concatenate([qi, qdi])].T)
            self.fixed = (sysm, beta_c, beta_u, beta_l, cdc, cvc, to_eig, from_eig)
        else:
            self.fixed = base.fixed
        sysm, beta_c, beta_u, beta_l, cdc, cvc, self._to_eig, self._from_eig = self.fixed
        self.sysm, self.speed = sysm, speed
        fu0 = unb.magnitude * speed**2 * complex(math.cos(unb.phase), math.sin(unb.phase))
        fl = complex(sc.load.force_y, sc.load.force_z) if sc.load is not None else 0j
        self.y_u, self.y_l = _particular(sysm, speed, beta_u, beta_l, fu0, fl, unb)
        self.cp = contact_parameters(sc.shaft, speed, sc.contact)
        h = 2 * math.pi / steps / speed
        p1, p2 = np.empty_like(sysm.lam), np.empty_like(sysm.lam)
        phi12(sysm.lam * h, p1, p2)
        g1 = h * p2 * beta_c
        part_c = complex(cdc @ self.y_u)
        self.coef = MapStep(
            np.exp(sysm.lam * h), (h * p1 - h * p2) * beta_c, g1, complex(cdc @ g1),
            complex(cvc @ g1), cdc, cvc, part_c, complex(cdc @ self.y_l), 1j * speed * part_c,
            speed, h, self.k * self.steps, 1.0,
        )  # fmt: skip

    def at_speed(self, speed: float) -> _Map:
        """The same map at another spin speed (rad/s): only speed-dependent parts rebuilt."""
        moving = self.__dict__.get("_gyro")
        if moving is None:
            moving = self._gyro = _gyroscopic(self.scenario.shaft)
        other = _Map(self.scenario, self.k, self.steps, speed, None if moving else self)
        other._gyro = moving
        return other

    def eigen(self, x: np.ndarray) -> np.ndarray:
        """Shifted eigen-coordinates of a state vector (m, m/s) at unbalance angle 0."""
        return self._to_eig @ x - self.y_u - self.y_l

    def physical(self, ys: np.ndarray) -> np.ndarray:
        """State vectors (m, m/s, rows) of unshifted eigen-coordinates ``ys`` (rows)."""
        xs = np.atleast_2d(ys) @ self._from_eig
        n = xs.shape[1] // 2
        return np.concatenate([xs.real[:, :n], xs.imag[:, :n], xs.real[:, n:], xs.imag[:, n:]],
                              axis=1)  # fmt: skip

    def run(self, x: np.ndarray, jacobian: bool = False):
        """``(P(x), dP/dx or None, largest contact-station radius m)`` of one map run."""
        x = np.asarray(x, float)
        y = self.eigen(x)
        if jacobian:  # unit perturbations of each real state component, in eigen-coordinates
            q = np.array(self._to_eig.T, order="C")  # a copy: the kernel overwrites it
        else:
            q = np.zeros((0, y.size), complex)
        out = np.zeros(2)
        z = expo_strobe(y, q, self.coef, self.cp, out)
        if out[1] != 0:
            raise InputError("shooting.start", "a diverging run", "a guess near a bounded orbit")
        px = self.physical(y + self.y_u * z + self.y_l)[0]
        return px, (self.physical(q).T if jacobian else None), float(out[0])


def strobe(scenario, x: np.ndarray, k: int = 1, steps: int = STEPS_PER_REVOLUTION) -> np.ndarray:
    """The stroboscopic map: the state vector ``k`` revolutions after ``x``.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The rotor, speed (rad/s), unbalance, contact, damping.
    x : ndarray
        State vector (m, m/s), see :func:`state_vector`, at unbalance angle 0.
    k : int
        Revolutions.
    steps : int
        Fixed exponential steps per revolution.

    Returns
    -------
    ndarray
        The state vector after ``k`` revolutions (m, m/s).
    """
    return _Map(scenario, k, steps).run(x)[0]


def monodromy(scenario, x: np.ndarray, k: int = 1, steps: int = STEPS_PER_REVOLUTION):
    """``P(x)`` and the exact Jacobian ``dP/dx`` of the discrete map (one compiled run).

    Returns
    -------
    px : ndarray
        ``P(x)``.
    jac : ndarray, shape (4n, 4n)
        The monodromy matrix of the discrete map (variational equations of the scheme,
        :mod:`rubrotor.core.shoot`).
    """
    px, jac, _ = _Map(scenario, k, steps).run(x, True)
    return px, jac


def monodromy_fd(scenario, x: np.ndarray, k: int = 1, steps: int = STEPS_PER_REVOLUTION):
    """``P(x)`` and ``dP/dx`` by central differences of the map (the second route, for checks).

    Between contacts the map is affine, so central differences are exact to rounding; in
    contact their error is ``O(d^2 P''') + O(eps |x| / d)`` for an increment ``d``, balanced
    at a relative increment ``d ~ eps^(1/3) ~ 6e-6`` (:data:`FD_STEP`).
    """
    mp = _Map(scenario, k, steps)
    px = mp.run(x)[0]
    scale = np.full(x.size, max(np.max(np.abs(x[: x.size // 2])), 1e-9))
    scale[x.size // 2 :] = max(np.max(np.abs(x[x.size // 2 :])), 1e-9 * scenario.speed)
    jac = np.empty((x.size, x.size))
    for j in range(x.size):
        e = np.zeros(x.size)
        e[j] = FD_STEP * scale[j]
        jac[:, j] = (mp.run(x + e)[0] - mp.run(x - e)[0]) / (2 * e[j])
    return px, jac


@dataclass(frozen=True)
class PeriodicOrbit:
    """A periodic orbit found by shooting (the verb's one result type).

    Attributes
    ----------
    scenario : rubrotor.scenario.Scenario
        Where it was found.
    state : RotorState or ndarray
        State at unbalance angle 0 on the orbit (a general rotor's: ``[Re y, Im y, F]``).
    k : int
        Revolutions per period.
    period : float
        ``k 2 pi / Omega`` (s).
    multipliers : ndarray, complex
        Floquet multipliers (eigenvalues of the monodromy matrix), by decreasing modulus.
    stable : bool
        All multipliers inside the unit circle.
    residual : float
        ``|P(x) - x| / |x|`` at the solution (dimensionless).
    iterations : int
        Newton iterations.
    steps : int
        Fixed steps per revolution of the map (0: found without time steps, by
        :func:`rubrotor.orbits.synchronous.synchronous_orbit`; :meth:`dataset` then samples the orbit
        with ``STEPS_PER_REVOLUTION``).
    """

    scenario: object
    state: RotorState
    k: int
    period: float
    multipliers: np.ndarray
    stable: bool
    residual: float
    iterations: int
    steps: int

    def dataset(self, samples_per_revolution: int = 256):
        """The orbit over its ``k`` revolutions as a results Dataset (like ``simulate``)."""
        from rubrotor.engine.result import to_dataset
        from rubrotor.engine.simulate import scenario_parameters

        if model_of(self.scenario).maps == "general":
            from rubrotor.engine.driver import result_dataset

            mp = prepared_map(self.scenario, self.k, self.steps)
            return result_dataset(mp.orbit_result(self.state, samples_per_revolution))
        steps = self.steps or STEPS_PER_REVOLUTION  # 0: found without time steps
        save = max(1, steps // samples_per_revolution)
        integ = _integrator(self.k, steps, True)
        integ = Integrator(**{**integ.__dict__, "save_every": save})
        res = simulate_scenario(self.scenario, integ, progress=False, start=self.state)
        return to_dataset(res, scenario_parameters(self.scenario), "", "periodic orbit")

    def max_radius(self, samples_per_revolution: int = 256) -> float:
        """Largest shaft-centre distance (m) at the contact station (or midspan) on the orbit."""
        if model_of(self.scenario).maps == "general":
            return prepared_map(self.scenario, self.k, self.steps).run(self.state)[2]
        res = simulate_scenario(
            self.scenario,
            _integrator(self.k, self.steps or STEPS_PER_REVOLUTION, True),
            progress=False,
            start=self.state,
        )
        return float(np.max(np.hypot(res.channels[0], res.channels[1])))


def multipliers_of(jac: np.ndarray) -> np.ndarray:
    """Eigenvalues of a monodromy matrix sorted by decreasing modulus."""
    mu = np.linalg.eigvals(jac)
    return mu[np.argsort(-np.abs(mu), kind="stable")]


def prepared_map(scenario, k: int, steps: int, reference=None):
    """The prepared ``k``-revolution map of a scenario: ``_Map`` for the continuous rotor,
    ``rubrotor.orbits.general_map.GeneralMap`` for a general one (same ``run`` interface; its
    modes aligned with those of the map ``reference`` when given)."""
    from rubrotor.orbits.general_map import GeneralMap

    if model_of(scenario).maps == "general":
        return GeneralMap(scenario, k, steps, reference=reference)
    return _Map(scenario, k, steps)


STALL = 1e-9
"""Newton on a periodic orbit also stops when its step stops shrinking (no longer quadratic:
round-off) below this fraction of the state."""


def newton_orbit(scenario, x0, k=1, steps=STEPS_PER_REVOLUTION, tol=1e-12, max_iter=30):
    """Newton iterations on ``P(x) - x = 0``; returns ``(x, jac, residual, iterations)``.

    ``scenario`` may also be a prepared map (of ``k`` revolutions, ``steps``).
    """
    mp = scenario if hasattr(scenario, "run") else prepared_map(scenario, k, steps)
    x = np.asarray(x0, float).copy()
    last = math.inf
    for it in range(1, max_iter + 1):
        px, jac, _ = mp.run(x, True)
        r = px - x
        dx = np.linalg.solve(jac - np.eye(x.size), -r)
        x = x + dx
        step, size = np.linalg.norm(dx), max(np.linalg.norm(x), 1e-30)
        # converged: below the tolerance, or stalled at the round-off floor of a state near
        # zero (a nearly linear orbit is the particular solution: x ~ 0) far below 1e-9 of it
        if step <= tol * size or (step >= 0.5 * last and step <= STALL * size):
            px, jac, _ = mp.run(x, True)
            res = np.linalg.norm(px - x) / size
            return x, jac, res, it
        last = step
    raise InputError(
        "shooting", f"no convergence in {max_iter} Newton iterations", "a closer guess"
    )


def shoot(scenario, guess=None, k: int = 1, *, steps: int = STEPS_PER_REVOLUTION,
          transient_revolutions: int = 0, tol: float = 1e-12) -> PeriodicOrbit:  # fmt: skip
    """Find a periodic orbit of ``k`` revolutions by Newton shooting.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        Rotor, speed (rad/s), unbalance, contact, damping (no side load needed; with a load the
        guess must be at unbalance angle 0). A general rotor (``[[section]]`` tables, the
        general engine at constant speed) is shot on its reduced modal state (the map of
        ``rubrotor.orbits.general_map``, its monodromy propagated in the compiled run); its
        states are the vectors ``[Re y, Im y, F]`` of that module.
    guess : RotorState, optional
        Start of Newton (e.g. a previous orbit's state or a simulation's ``final_state``);
        default the steady no-contact orbit's state.
    k : int
        Revolutions per period (>= 1).
    steps : int
        Fixed exponential steps per revolution (>= 16).
    transient_revolutions : int
        Revolutions simulated from the guess before Newton (a time-simulation guess).
    tol : float
        Relative Newton step size at which to stop (dimensionless).

    Returns
    -------
    PeriodicOrbit
    """
    from rubrotor.scenario.load import as_scenario

    scenario = as_scenario(scenario)
    general = model_of(scenario).require_maps("periodic orbits (shooting, continuation)") == "general"
    if isinstance(k, bool) or not isinstance(k, int) or k < 1:
        raise InputError("k", k, "an integer >= 1 (revolutions per period)")
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 16:
        raise InputError("steps", steps, "an integer >= 16 (steps per revolution)")
    mp = prepared_map(scenario, k, steps)
    if guess is None and general:
        guess = mp.start()
    elif guess is None:
        res = simulate_scenario(
            scenario, _integrator(1, steps, False), progress=False, initial="steady"
        )
        guess = res.final_state
        if guess is None:  # the start run itself did not complete: no orbit to start from
            raise InputError("scenario", getattr(scenario, "name", ""),
                             "a rotor whose one-revolution start run (from the steady response "
                             f"without contact) completes; it stopped: {res.message or res.status}"
                             )  # fmt: skip
    x0 = state_vector(guess)
    if transient_revolutions and not general:
        x0 = strobe(scenario, x0, int(transient_revolutions), steps)
    elif transient_revolutions:
        x0 = mp.repeat(int(transient_revolutions)).run(x0)[0]
    x, jac, residual, it = newton_orbit(mp, x0, k, steps, tol)
    mu = multipliers_of(jac)
    return PeriodicOrbit(
        scenario=scenario,
        state=x.copy() if general else vector_state(x),
        k=k,
        period=k * 2 * math.pi / scenario.speed,
        multipliers=mu,
        stable=bool(np.abs(mu[0]) < 1.0),
        residual=float(residual),
        iterations=it,
        steps=steps,
    )
