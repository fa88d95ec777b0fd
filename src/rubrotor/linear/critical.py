"""The first forward critical speed of any linear rotor: what ``[speed] critical_multiple``
multiplies.

A critical speed is a spin speed ``Omega`` at which a mode's damped natural frequency equals
``Omega`` (synchronous excitation by unbalance,
:func:`rubrotor.linear.analysis.linear_critical_speeds`). The first forward one is the lowest
such speed whose mode

* whirls predominantly forward: the amplitude-weighted ratio of minor to major orbit axis over
  the stations is positive (on anisotropic bearings the first mode's orbits are ellipses that
  may turn backward at a few stations: "mixed" at every station, yet the mode unbalance
  excites);
* is not critically damped: damping ratio at most 0.2 (API 617: an amplification factor
  ``1 / (2 zeta)`` below 2.5 makes no critical speed; heavily damped bearings give such modes,
  e.g. ``general_rotor.toml``'s two near 370 rad/s with ``zeta`` about 0.98).
"""

from __future__ import annotations

import functools
import math

from rubrotor.errors import InputError
from rubrotor.linear.analysis import (
    CRITICALLY_DAMPED,
    LinearCritical,
    damped_modes,
    linear_critical_speeds,
)
from rubrotor.linear.shapes import mode_shapes
from rubrotor.rotors.linear import LinearSystem

__all__ = ["first_forward_critical_speed", "rotor_first_forward_critical"]

MAX_SEARCH = 1e7
"""Highest spin speed (rad/s) searched for a forward critical speed (the scenario's limit)."""
MAX_DAMPING_RATIO = CRITICALLY_DAMPED
"""Modes damped beyond this ratio make no critical speed (API 617's amplification factor 2.5;
the limit :func:`rubrotor.linear.analysis.linear_critical_speeds` flags)."""


def _counts(system: LinearSystem, crit: LinearCritical) -> bool:
    """True when the mode crossing at ``crit`` whirls predominantly forward and is not
    critically damped. Modes are ranked by ``|lambda|`` and ``crit.index`` is the rank by
    frequency, so the mode is the one whose damped frequency equals the speed."""
    if crit.critically_damped:
        return False
    speed = crit.speed_rad_s
    for n in (crit.index + 4, 3 * crit.index + 12):
        shapes = mode_shapes(system, speed, n)
        gap = [abs(2 * math.pi * m.frequency_hz - speed) for m in shapes.modes.modes]
        k = min(range(len(gap)), key=gap.__getitem__)
        if gap[k] <= 1e-6 * speed:
            return shapes.minor[k].sum() / shapes.major[k].sum() > 0
    return False


def first_forward_critical_speed(system: LinearSystem, modes: int = 6) -> float:
    """The lowest spin speed (rad/s) at which the damped frequency of a mode whirling
    predominantly forward, not critically damped, equals the spin (module docstring).

    The search runs up to twice the lowest natural frequency at rest, then doubles its range
    until a forward crossing appears (each crossing refined by ``brentq`` to 1e-10 relative).

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    modes : int
        Modes searched (the lowest ``modes`` at each speed).

    Returns
    -------
    float
        Critical speed (rad/s).

    Raises
    ------
    InputError
        No forward critical speed below ``MAX_SEARCH`` (1e7) rad/s.
    """
    lowest = damped_modes(system, 0.0, n=1).modes
    top = 4 * math.pi * lowest[0].frequency_hz if lowest else 100.0
    while top <= 2 * MAX_SEARCH:
        found = [
            c
            for c in linear_critical_speeds(system, top, n=modes)
            if c.speed_rad_s <= MAX_SEARCH and _counts(system, c)
        ]
        if found:
            return float(found[0].speed_rad_s)
        top *= 2.0
    raise InputError(
        "speed.critical_multiple",
        system.name,
        f"a rotor with a forward critical speed below {MAX_SEARCH:g} rad/s",
    )


@functools.lru_cache(maxsize=32)
def rotor_first_forward_critical(rotor, stations: tuple[float, ...] = ()) -> float:
    """``first_forward_critical_speed`` of a ``Rotor`` meshed with
    nodes at ``stations`` (m), remembered per rotor and stations (rad/s)."""
    return first_forward_critical_speed(rotor.linear_system(stations))
