"""Lyapunov exponents of the rubbing rotor from the compiled tangent dynamics.

:func:`lyapunov_exponents` runs the fixed-step exponential integrator (the one of
:func:`rubrotor.engine.simulate.simulate_system` with ``dtau``) together with ``count`` tangent
vectors propagated by the exact derivative of that step
(``rubrotor.core.tangent.expo_tangent``: the exponential propagator is linear, the
implicit contact solve is differentiated by the implicit function theorem with the same
Newton matrix), re-orthonormalised every few steps (Benettin et al., Meccanica 15, 1980). The
exponents are those of the discrete map; they approach the flow's as the step shrinks.

Why the tangent dynamics is well defined here. A Lyapunov exponent needs the derivative of the
step along the orbit, i.e. a contact force that is differentiable in the state:

* Friction: the Coulomb law's sign of the sliding speed is smoothed,
  ``s(v) = v / sqrt(v^2 + v_r^2)`` with ``v_r = contact.friction_regularization`` (m/s): a
  smooth function, so the friction force is differentiable in the velocity everywhere (with the
  true sign function the derivative would not exist at stick). Its derivative is included
  (``rubrotor.core.contact.contact_force_jac_exact``), unlike the Newton solver's
  quasi-Newton Jacobian.
* Normal force: the Hertz law ``k eps^1.5 (1 + b eps')`` (Hunt-Crossley) is continuously
  differentiable across contact onset: its derivative ``1.5 k eps^0.5 (...)`` tends to 0 as the
  penetration ``eps -> 0``, the same value as out of contact, so the step map is C1 and its
  Jacobian is continuous along an orbit that touches or leaves the stator. The linear law
  ``k eps + c eps'`` is only Lipschitz (its derivative jumps by ``k`` at onset; with ``c > 0``
  the force itself jumps): the step map is then piecewise smooth, its Jacobian exists except
  on the grazing set (which an orbit crosses at isolated steps), and the exponents are those
  of the piecewise derivative; with a force jump at onset the saltation of the flow is not in
  the discrete map's derivative (use the Hertz law or ``c = 0`` for exponents).

Units: exponents in 1/s (``exp(lambda t)`` growth); times ``2 pi / Omega`` they are the growth
per revolution, which :func:`rubrotor.sweeps.regimes.classify` compares with
:data:`rubrotor.sweeps.regimes.CHAOS_MARGIN_PER_REV` to label a motion chaotic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.core.status import MESSAGES as _STATUS
from rubrotor.errors import InputError

__all__ = ["LyapunovResult", "lyapunov_exponents"]


@dataclass(frozen=True)
class LyapunovResult:
    """Lyapunov exponents of one run.

    Attributes
    ----------
    exponents : ndarray
        The ``count`` largest exponents (1/s), in decreasing order.
    per_revolution : ndarray
        The same times the revolution period ``2 pi / Omega`` (dimensionless growth per rev).
    averaging_time : float
        Time over which the log growths were averaged (s).
    step : float
        Fixed step of the map (s).
    status : str
        ``"complete"``; ``"partial: ..."`` when the run stopped while averaging (it diverged, a
        contact solve failed, the tangent vectors degenerated), the exponents then averaged
        over the chunks of ``CHUNK_REVOLUTIONS`` completed before (``averaging_time``);
        or why it stopped during the transient, with NaN exponents.
    final_state : rubrotor.engine.simulate.RotorState or None
        The state at the end (None when not complete).
    """

    exponents: np.ndarray
    per_revolution: np.ndarray
    averaging_time: float
    step: float
    status: str
    final_state: object = None


CHUNK_REVOLUTIONS = 16
"""Revolutions per kernel call while averaging: when a run stops (it diverged, a contact solve
failed), the exponents averaged over the chunks completed before it are kept."""


def _setup(scenario, h: float):
    """Modal system, step coefficients and start-independent parts of the tangent kernel."""
    from rubrotor.engine.simulate import _check_station, assemble, contact_parameters, phi_functions

    sh, speed = scenario.shaft, float(scenario.speed)
    L = sh.length
    unb, contact, load = scenario.unbalance, scenario.contact, scenario.load
    pos = lambda obj, name: _check_station(  # noqa: E731
        f"{name}.position", obj.position if obj is not None and obj.position else L / 2, L
    )
    a_c, a_u, a_l = pos(contact, "contact"), pos(unb, "unbalance"), pos(load, "load")
    sysm = assemble(sh, speed, scenario.damping)
    lam = sysm.lam
    beta_c = sysm.force_input(a_c)
    fu0 = unb.magnitude * speed**2 * complex(math.cos(unb.phase), math.sin(unb.phase))
    fl = complex(load.force_y, load.force_z) if load is not None else 0j
    res = 1j * speed - lam
    if np.min(np.abs(res) / np.abs(lam)) < 1e-9 and unb.magnitude > 0:
        raise InputError("speed", speed, "a speed that is not exactly an undamped critical speed")
    y_u = sysm.force_input(a_u) * fu0 / res
    y_l = -sysm.force_input(a_l) * fl / lam
    cdc = np.ascontiguousarray(sysm.displacement_row(a_c))
    cvc = np.ascontiguousarray(sysm.velocity_row(a_c))
    E = np.exp(lam * h)
    p1, p2 = phi_functions(lam * h)
    G0 = (h * p1 - h * p2) * beta_c
    G1 = h * p2 * beta_c
    part_c = complex(cdc @ y_u)
    part = (part_c, complex(cdc @ y_l), 1j * speed * part_c)
    cp = contact_parameters(sh, speed, contact)
    return sysm, y_u, y_l, cdc, cvc, E, G0, G1, part, cp


def lyapunov_exponents(
    scenario,
    *,
    count: int = 1,
    revolutions: int = 100,
    transient_revolutions: int = 0,
    steps_per_revolution: int = 512,
    renorm_every: int = 8,
    start=None,
    seed: int = 0,
) -> LyapunovResult:
    """The ``count`` largest Lyapunov exponents of a scenario's motion (see module docstring).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario or path-like
        Shaft, speed, unbalance, contact, load, damping; a path is read with
        :func:`~rubrotor.load_scenario`.
    count : int
        Number of exponents, 1 .. ``2 ns`` (``ns`` complex modal state coordinates; the real
        state dimension is ``2 ns``).
    revolutions : int
        Revolutions over which the log growths are averaged (>= 1).
    transient_revolutions : int
        Revolutions run first (state and tangent vectors) and not averaged (>= 0).
    steps_per_revolution : int
        Fixed steps per revolution (>= 16): the step is ``2 pi / (steps_per_revolution Omega)``.
    renorm_every : int
        Steps between re-orthonormalisations (>= 1).
    start : rubrotor.engine.simulate.RotorState, optional
        Start state (default rest).
    seed : int
        Seed of the random initial tangent vectors.

    Returns
    -------
    LyapunovResult
    """
    from rubrotor.core.tangent import expo_tangent, orthonormalise
    from rubrotor.engine.shaft_steppers import MapStep
    from rubrotor.engine.simulate import _start_coordinates, _start_force, _state_of
    from rubrotor.scenario.load import as_scenario

    scenario = as_scenario(scenario)
    for name, v, lo in (
        ("revolutions", revolutions, 1),
        ("transient_revolutions", transient_revolutions, 0),
        ("steps_per_revolution", steps_per_revolution, 16),
        ("renorm_every", renorm_every, 1),
        ("count", count, 1),
    ):
        if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < lo:
            raise InputError(name, v, f"an integer >= {lo}")
    from rubrotor.modelling import model_of

    if model_of(scenario).require_maps("Lyapunov exponents") == "general":  # tangents propagated
        return lyapunov_general(scenario, count=count, revolutions=revolutions,
                                transient_revolutions=transient_revolutions,
                                steps=steps_per_revolution, start=start, seed=seed)  # fmt: skip
    speed = float(scenario.speed)
    h = 2 * math.pi / (steps_per_revolution * speed)
    sysm, y_u, y_l, cdc, cvc, E, G0, G1, part, cp = _setup(scenario, h)
    ns = E.size
    if count > 2 * ns:
        raise InputError("count", count, f"at most {2 * ns} (the real state dimension)")
    if start is None:
        y = -(y_u + y_l)
    else:
        y = _start_coordinates(sysm, start, scenario.load) - (y_u + y_l)
    y = np.ascontiguousarray(y, dtype=complex)
    orows = (cdc[None, :], cvc[None, :], None, None, [part[0]], [part[1]], [part[2]])
    cstate = np.array([_start_force(y, cp, orows), 1 + 0j, 0j, 0j])
    istate = np.zeros(2, np.int64)
    rng = np.random.default_rng(seed)
    Q = rng.normal(size=(count, ns)) + 1j * rng.normal(size=(count, ns))
    logs = np.zeros(count)
    orthonormalise(Q, logs)
    max_disp = 1000 * scenario.contact.clearance if scenario.contact else 0.1 * sysm.shaft.length
    k = MapStep(E, G0, G1, complex(cdc @ G1), complex(cvc @ G1), cdc, cvc, *part, speed, h, 0,
                max_disp)  # fmt: skip
    n_tr = transient_revolutions * steps_per_revolution
    n_av = revolutions * steps_per_revolution
    if n_tr:
        expo_tangent(y, cstate, istate, Q, logs, k._replace(n_steps=n_tr), cp, renorm_every)
    logs[:] = 0.0
    done = 0
    while istate[1] == 0 and done < n_av:  # chunks: a failure keeps the average so far
        n = min(CHUNK_REVOLUTIONS * steps_per_revolution, n_av - done)
        kept = logs.copy()
        expo_tangent(y, cstate, istate, Q, logs, k._replace(n_steps=n), cp, renorm_every)
        if istate[1] != 0:
            logs[:] = kept
        else:
            done += n
    status = _STATUS[int(istate[1])]
    if done == 0:
        nan = np.full(count, np.nan)
        return LyapunovResult(nan, nan, n_av * h, h, status, None)
    lam = np.sort(logs / (done * h))[::-1]
    final = None
    if status == "complete":
        final = _state_of(sysm, y + y_u * cstate[1] + y_l, speed * int(istate[0]) * h)
    else:
        status = (f"partial: {status} after {done // steps_per_revolution} of {revolutions} "
                  "revolutions (exponents averaged over those)")  # fmt: skip
    return LyapunovResult(lam, lam * 2 * math.pi / speed, done * h, h, status, final)


def lyapunov_general(scenario, *, count: int = 1, revolutions: int = 100,
                     transient_revolutions: int = 0, steps: int = 256, start=None,
                     seed: int = 0, reference=None):  # fmt: skip
    """The ``count`` largest Lyapunov exponents of a general rotor's one-revolution map.

    Benettin's method on the map of ``rubrotor.orbits.general_map.GeneralMap`` (:func:`benettin`):
    every revolution the ``count`` tangent vectors (in coordinates scaled by the start state's
    modal amplitude and contact force, so that both weigh alike) are carried exactly by the
    map's variational equations in the same compiled run (central differences of the map along
    each of them only in a revolution with a grazing step) and re-orthonormalised (QR), their
    log growths summed. The exponents are those of the discrete
    map, per revolution and per second.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A general rotor at constant speed with at least one contact.
    count : int
        Exponents (at most ``2 ns``, the modal state's real dimension).
    revolutions, transient_revolutions : int
        Averaged and discarded revolutions.
    steps : int
        Fixed steps per revolution.
    start : ndarray, optional
        Start vector ``[Re y, Im y, F]`` (default the steady no-contact response).
    seed : int
        Seed of the random first tangent vectors.
    reference : rubrotor.orbits.general_map.GeneralMap, optional
        The map whose modal coordinates ``start`` is given in (its ``aligned``).

    Returns
    -------
    rubrotor.orbits.lyapunov.LyapunovResult
        ``final_state`` is the end vector; a run that stops while averaging keeps the average
        of its completed revolutions, marked partial.
    """
    from rubrotor.orbits.general_map import GeneralMap

    mp = GeneralMap(scenario, 1, steps, reference=reference)
    if not 1 <= count <= 2 * mp.ns:
        raise InputError("count", count, f"1 .. {2 * mp.ns} (the modal state's real dimension)")
    x = mp.start() if start is None else np.asarray(start, float)
    return benettin(mp, x, count, transient_revolutions, revolutions, seed)


def benettin(mp, x, count: int, transient_revolutions: int, revolutions: int, seed: int = 0):
    """Benettin's iteration on a prepared one-revolution general map ``mp`` from the vector
    ``x`` (:func:`lyapunov_general`, which checks the arguments); a ``LyapunovResult``."""
    steps = mp.steps
    rng = np.random.default_rng(seed)
    Q = np.linalg.qr(rng.standard_normal((mp.dim, count)))[0]
    logs, done, status = np.zeros(count), 0, "complete"
    # the transient carries the vectors too: they align with the leading directions before the
    # average starts (otherwise their start biases it by ~ 1 / revolutions)
    scale = mp._scales(x)
    for i in range(int(transient_revolutions) + int(revolutions)):
        try:
            px, Q, growth = _tangent_revolution(mp, x, Q, scale)
        except InputError:
            if i < transient_revolutions:
                done = 0
            else:
                status = f"partial: diverged after {done} of {revolutions} revolutions"
            break
        x = px
        if i >= transient_revolutions:
            logs += growth
            done += 1
    period = 2 * math.pi / mp.speed
    if done == 0:
        nan = np.full(count, np.nan)
        return LyapunovResult(nan, nan, 0.0, period / steps, "diverged", None)
    per_rev = np.sort(logs / done)[::-1]
    return LyapunovResult(per_rev / period, per_rev, done * period, period / steps, status, x)


def _tangent_revolution(mp, x: np.ndarray, Q: np.ndarray, scale: np.ndarray):
    """One revolution of the state and of the orthonormal tangent vectors ``Q`` (columns, in
    the coordinates ``x / scale``, so that modal amplitudes and forces weigh alike):
    ``(P(x), Q', log growths)`` with ``J Q = Q' R``, ``J Q`` propagated exactly in the compiled
    run (``GeneralMap.tangent``), by central differences along each vector in a revolution
    that closed a grazing contact by its set-valued rule."""
    from rubrotor.orbits.general_map import FD_STEP as _FD_STEP

    px, JV, _, grazes = mp.tangent(x, scale[:, None] * Q)
    if not grazes:
        Q, R = np.linalg.qr(JV / scale[:, None])
        return px, Q, np.log(np.abs(np.diag(R)))
    JQ = np.column_stack([(mp.run(x + _FD_STEP * scale * q)[0]
                           - mp.run(x - _FD_STEP * scale * q)[0]) / (2 * _FD_STEP * scale)
                          for q in Q.T])  # fmt: skip
    Q, R = np.linalg.qr(JQ)
    return px, Q, np.log(np.abs(np.diag(R)))
