"""A sweep point of a general (finite-element) rotor: its fixed-step map run and reduced.

The general engine's stroboscopic map (:class:`rubrotor.orbits.general_map.GeneralMap`, the
compiled fixed-step exponential scheme with the implicit contact step) runs the point's
transient and kept revolutions; the kept window is reduced by
:func:`rubrotor.sweeps.metrics.window_metrics`, as every sweep's points are. Plain sweeps start
each point from the steady no-contact response; state-carrying sweeps
(:func:`rubrotor.sweeps.follow.follow_general`) carry the state from point to point.
"""

from __future__ import annotations

import numpy as np

from rubrotor.errors import InputError
from rubrotor.sweeps.metrics import _empty_metrics, window_metrics

__all__ = ["GENERAL_STEPS", "window", "simulate_point_general"]

GENERAL_STEPS = 256
"""Fixed steps per revolution of a general rotor's sweep point (``samples_per_revolution`` must
divide it)."""


def window(mp, x: np.ndarray, samples_per_revolution: int, lyapunov: bool):
    """End vector and metrics of one run of ``mp`` (its ``k`` revolutions are all kept).

    Parameters
    ----------
    mp : rubrotor.orbits.general_map.GeneralMap
        The map over the kept revolutions.
    x : numpy.ndarray
        Start vector (modal state and contact forces, SI).
    samples_per_revolution : int
        Kept samples per revolution (a divisor of ``mp.steps``).
    lyapunov : bool
        Also the largest Lyapunov exponent (1/s) over the same revolutions
        (:func:`rubrotor.orbits.lyapunov.benettin`).

    Returns
    -------
    x_end : numpy.ndarray
        The vector after the kept revolutions.
    metrics : dict
        :func:`rubrotor.sweeps.metrics.window_metrics` of the first contact station.
    """
    from rubrotor.orbits.lyapunov import benettin

    lam = np.nan
    if lyapunov:
        lam = benettin(mp.repeat(1), x, 1, 0, mp.k).exponents[0]
    save = mp.steps // samples_per_revolution
    px, out, events = mp._kernel(x, save)
    nst = len(mp.plant.stations)
    pw = out[0, 1:] + 1j * out[1, 1:]  # the first contact station, samples 1 .. k N
    fn = out[4 * nst + 6, 1:]
    mine = events[np.abs(events[:, 1]) == 1]
    signed = mine[:, 0] * np.sign(mine[:, 1])
    m = window_metrics(pw, fn, signed, mp.speed, 0, mp.k, samples_per_revolution, lam)
    return px, m


def simulate_point_general(scenario, transient_revolutions: int, revolutions: int,
                           samples_per_revolution: int, lyapunov: bool = False,
                           steps: int = GENERAL_STEPS) -> tuple[dict, None]:  # fmt: skip
    """Run and reduce one sweep point of a general rotor (from the steady no-contact response).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The point's scenario (a finite-element rotor with a contact, at constant speed).
    transient_revolutions, revolutions : int
        Revolutions discarded (``T``) and in total (``R``).
    samples_per_revolution : int
        Kept samples per revolution (a divisor of ``steps``).
    lyapunov : bool
        Also the largest Lyapunov exponent (1/s).
    steps : int
        Fixed steps per revolution.

    Returns
    -------
    metrics : dict
        The kept window's metrics; not classified (``status`` 0) when the run diverged.
    final_state : None
        General points carry no :class:`~rubrotor.engine.simulate.RotorState`.
    """
    from rubrotor.orbits.general_map import GeneralMap

    if steps % samples_per_revolution:
        raise InputError(
            "samples_per_revolution",
            samples_per_revolution,
            f"a divisor of the {steps} fixed steps per revolution of a general rotor's sweep",
        )
    one = GeneralMap(scenario, 1, steps)
    x = one.start()
    try:
        if transient_revolutions:
            x = one.repeat(transient_revolutions).run(x)[0]
        _, m = window(
            one.repeat(revolutions - transient_revolutions), x, samples_per_revolution, lyapunov
        )
    except InputError:  # the run diverged: the point is not classified
        return _empty_metrics(revolutions - transient_revolutions), None
    return m, None
