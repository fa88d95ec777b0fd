"""Periodic orbits by shooting: Newton on the stroboscopic map over k revolutions.

The map ``P(x)`` takes the physical modal state ``x`` (real vector ``[Re q, Im q, Re q', Im q']``,
m and m/s) at unbalance angle 0 to the state ``k`` revolutions later, by
:func:`rubrotor.simulation.simulate_system` with ``start=`` and the fixed-step exponential
integrator. A fixed step makes ``P`` a smooth function of ``x`` (an adaptive step sequence
changes discontinuously with the start state, which breaks Newton's quadratic convergence).
The fixed point is the periodic orbit of the discrete scheme, second order in the step.

Monodromy: central finite differences of ``P``. Between contacts the scheme propagates the
linear rotor exactly, so ``P`` is affine there and central differences are exact to rounding;
in contact the truncation error is ``O(h^2 P''')`` and the rounding error ``O(eps |x| / h)``,
balanced at a relative increment ``h ~ eps^(1/3) ~ 6e-6`` (measured in the tests: the
no-contact multipliers equal ``exp(lambda T)`` to 1e-12).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError
from rubrotor.integrator import Integrator
from rubrotor.simulation import PreparedRun, RotorState, simulate_scenario

STEPS_PER_REVOLUTION = 1024
FD_STEP = 6e-6


def state_vector(state: RotorState) -> np.ndarray:
    """Real vector ``[Re q, Im q, Re q', Im q']`` (m, m/s) of a :class:`RotorState`."""
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
    res = _prepared(scenario, k, steps).run(start=vector_state(x))
    if res.final_state is None:
        raise InputError("shooting.start", "a diverging run", "a guess near a bounded orbit")
    return state_vector(res.final_state)


@functools.lru_cache(maxsize=8)
def _cached_run(scenario, k: int, steps: int) -> PreparedRun:
    return PreparedRun.from_scenario(scenario, _integrator(k, steps, False))


def _prepared(scenario, k: int, steps: int) -> PreparedRun:
    """The map's simulation, set up once per (equal) scenario: a Newton step's ``4 n`` finite
    differences all run the same model from different states (the array-level path)."""
    try:
        return _cached_run(scenario, k, steps)
    except TypeError:  # an unhashable scenario: set up each time
        return PreparedRun.from_scenario(scenario, _integrator(k, steps, False))


def monodromy(scenario, x: np.ndarray, k: int = 1, steps: int = STEPS_PER_REVOLUTION):
    """Jacobian ``dP/dx`` of :func:`strobe` by central differences (dimensionless blocks).

    Returns
    -------
    px : ndarray
        ``P(x)``.
    jac : ndarray, shape (4n, 4n)
        The monodromy matrix of the discrete map.
    """
    px = strobe(scenario, x, k, steps)
    scale = np.full(x.size, max(np.max(np.abs(x[: x.size // 2])), 1e-9))
    scale[x.size // 2 :] = max(np.max(np.abs(x[x.size // 2 :])), 1e-9 * scenario.speed)
    jac = np.empty((x.size, x.size))
    for j in range(x.size):
        h = FD_STEP * scale[j]
        e = np.zeros(x.size)
        e[j] = h
        jac[:, j] = (strobe(scenario, x + e, k, steps) - strobe(scenario, x - e, k, steps)) / (
            2 * h
        )
    return px, jac


@dataclass(frozen=True)
class PeriodicOrbit:
    """A periodic orbit found by shooting (the verb's one result type).

    Attributes
    ----------
    scenario : rubrotor.scenario.Scenario
        Where it was found.
    state : RotorState
        State at unbalance angle 0 on the orbit.
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
        Fixed steps per revolution of the map.
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
        from rubrotor.results import to_dataset
        from rubrotor.simulation import scenario_parameters

        save = max(1, self.steps // samples_per_revolution)
        integ = _integrator(self.k, self.steps, True)
        integ = Integrator(**{**integ.__dict__, "save_every": save})
        res = simulate_scenario(self.scenario, integ, progress=False, start=self.state)
        return to_dataset(res, scenario_parameters(self.scenario), "", "periodic orbit")

    def max_radius(self, samples_per_revolution: int = 256) -> float:
        """Largest shaft-centre distance (m) at the contact station (or midspan) on the orbit."""
        res = simulate_scenario(
            self.scenario,
            _integrator(self.k, self.steps, True),
            progress=False,
            start=self.state,
        )
        return float(np.max(np.hypot(res.channels[0], res.channels[1])))


def multipliers_of(jac: np.ndarray) -> np.ndarray:
    """Eigenvalues of a monodromy matrix sorted by decreasing modulus."""
    mu = np.linalg.eigvals(jac)
    return mu[np.argsort(-np.abs(mu), kind="stable")]


def newton_orbit(scenario, x0, k=1, steps=STEPS_PER_REVOLUTION, tol=1e-12, max_iter=30):
    """Newton iterations on ``P(x) - x = 0``; returns ``(x, jac, residual, iterations)``."""
    x = np.asarray(x0, float).copy()
    for it in range(1, max_iter + 1):
        px, jac = monodromy(scenario, x, k, steps)
        r = px - x
        dx = np.linalg.solve(jac - np.eye(x.size), -r)
        x = x + dx
        if np.linalg.norm(dx) <= tol * max(np.linalg.norm(x), 1e-30):
            px, jac = monodromy(scenario, x, k, steps)
            res = np.linalg.norm(px - x) / max(np.linalg.norm(x), 1e-30)
            return x, jac, res, it
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
        guess must be at unbalance angle 0).
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
    if isinstance(k, bool) or not isinstance(k, int) or k < 1:
        raise InputError("k", k, "an integer >= 1 (revolutions per period)")
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 16:
        raise InputError("steps", steps, "an integer >= 16 (steps per revolution)")
    if guess is None:
        res = simulate_scenario(
            scenario, _integrator(1, steps, False), progress=False, initial="steady"
        )
        guess = res.final_state
    x0 = state_vector(guess)
    if transient_revolutions:
        x0 = strobe(scenario, x0, int(transient_revolutions), steps)
    x, jac, residual, it = newton_orbit(scenario, x0, k, steps, tol)
    mu = multipliers_of(jac)
    return PeriodicOrbit(
        scenario=scenario,
        state=vector_state(x),
        k=k,
        period=k * 2 * math.pi / scenario.speed,
        multipliers=mu,
        stable=bool(np.abs(mu[0]) < 1.0),
        residual=float(residual),
        iterations=it,
        steps=steps,
    )
