"""Critical speeds of any linear rotor: the speeds where a mode's damped frequency equals a
multiple of the spin, and the first forward one, what ``[speed] critical_multiple`` multiplies.

A critical speed is a spin speed ``Omega`` at which a mode's damped natural frequency equals
``harmonic`` times ``Omega`` (1 for synchronous excitation by unbalance,
:func:`linear_critical_speeds`). The first forward one is the lowest such speed whose mode

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
from dataclasses import dataclass

import numpy as np
import scipy.optimize

from rubrotor.errors import InputError
from rubrotor.linear.campbell import campbell_data
from rubrotor.linear.modes import damped_modes
from rubrotor.linear.roots import TWO_PI, _check_speed
from rubrotor.linear.shapes import mode_shapes
from rubrotor.rotors.linear import LinearSystem

__all__ = [
    "CRITICALLY_DAMPED",
    "LinearCritical",
    "linear_critical_speeds",
    "first_forward_critical_speed",
    "rotor_first_forward_critical",
]

CRITICALLY_DAMPED = 0.2
"""Damping ratio above which a critical speed is flagged as critically damped (no resonance to
avoid). API 684 (Tutorial on the API Standard Paragraphs Covering Rotor Dynamics, 2nd ed.) and
API 617 call a mode "critically damped" when its amplification factor ``AF < 2.5``; with the
single-mode estimate ``AF = 1 / (2 zeta)`` that is ``zeta > 0.2``. The estimate is the
half-power one (``AF = N_c / (N_2 - N_1)``) for a lightly damped mode; near 0.2 it is an
approximation, so a value close to the limit deserves the unbalance response's own peak."""


@dataclass(frozen=True)
class LinearCritical:
    """A critical speed: mode ``index`` (by frequency) crosses ``harmonic`` times the spin.

    Attributes
    ----------
    index : int
        Mode rank by frequency at the crossing.
    whirl : str
        Whirl of the mode at the crossing.
    harmonic : float
        The excitation order (1 for unbalance).
    speed_rad_s : float
        Spin speed (rad/s).
    damping_ratio : float
        Damping ratio ``zeta`` of the mode at the crossing (dimensionless).
    """

    index: int
    whirl: str
    harmonic: float
    speed_rad_s: float
    damping_ratio: float = float("nan")

    def to_dict(self) -> dict:
        """JSON form (one of the ``critical_speeds`` of ``rubrotor critical --json``)."""
        return {"index": self.index, "whirl": self.whirl, "speed_rad_s": self.speed_rad_s,
                "damping_ratio": self.damping_ratio, "critically_damped": self.critically_damped}  # fmt: skip

    @property
    def critically_damped(self) -> bool:
        """True when ``damping_ratio > CRITICALLY_DAMPED`` (API 684's ``AF < 2.5``)."""
        return self.damping_ratio > CRITICALLY_DAMPED

    @property
    def speed_rpm(self) -> float:
        """The speed in rev/min."""
        return self.speed_rad_s * 60 / TWO_PI


def linear_critical_speeds(
    system: LinearSystem, max_speed: float, n: int = 6, harmonic: float = 1.0, points: int = 200
) -> list[LinearCritical]:
    """Speeds where a mode's damped frequency equals ``harmonic`` times the spin.

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    max_speed : float
        Upper end of the search (rad/s), > 0.
    n : int
        Modes searched (the lowest ``n``).
    harmonic : float
        Excitation order (> 0).
    points : int
        Scan points before the roots are refined by ``brentq`` (to 1e-10 relative); the scan
        starts at rest, or at ``max_speed / (points - 1)`` with journal bearings (whose film
        carries nothing at rest: a critical speed below that is not found).

    Returns
    -------
    list of LinearCritical
        Sorted by speed, each with the mode's damping ratio there; those above
        ``CRITICALLY_DAMPED`` are flagged by ``LinearCritical.critically_damped``.
    """
    max_speed = _check_speed("max_speed", max_speed)
    if max_speed <= 0 or not harmonic > 0:
        raise InputError("max_speed / harmonic", (max_speed, harmonic), "values > 0")
    from rubrotor.forces.equilibrium import first_speed

    # from rest, or from the first step with journal bearings (no film without spin)
    grid = np.linspace(first_speed(system, max_speed, points), max_speed, points)
    data = campbell_data(system, grid, n=n)
    out = []
    for j in range(n):
        g = TWO_PI * data.frequency_hz[:, j] - harmonic * grid
        for i in np.flatnonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0):

            def h(w, j=j):  # the Campbell route itself, so the bracket's signs are g's
                one = campbell_data(system, [w, w * (1 + 1e-12) + 1e-12], n=n)
                d = one.log_dec[0, j]
                zeta = d / math.sqrt(4 * math.pi**2 + d * d)
                return TWO_PI * one.frequency_hz[0, j] - harmonic * w, one.whirl[0, j], zeta

            lo, hi = float(grid[i]), float(grid[i + 1])
            if not h(lo)[0] * h(hi)[0] < 0:  # a branch that appears or vanishes in between
                continue
            w = scipy.optimize.brentq(lambda x: h(x)[0], lo, hi, xtol=1e-12, rtol=1e-10)
            _, whirl, zeta = h(w)
            out.append(LinearCritical(j + 1, whirl, float(harmonic), float(w), float(zeta)))
    return sorted(out, key=lambda c: c.speed_rad_s)


MAX_SEARCH = 1e7
"""Highest spin speed (rad/s) searched for a forward critical speed (the scenario's limit)."""
MAX_DAMPING_RATIO = CRITICALLY_DAMPED
"""Modes damped beyond this ratio make no critical speed (API 617's amplification factor 2.5;
the limit :func:`linear_critical_speeds` flags)."""


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
