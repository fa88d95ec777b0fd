"""Verbs of the modal analysis that take a :class:`~rubrotor.scenario.Scenario`, a bare
:class:`~rubrotor.rotors.shaft.Shaft`, a general :class:`~rubrotor.rotors.fe.Rotor` or any
:class:`~rubrotor.rotors.linear.LinearSystem`.
"""

from __future__ import annotations

import os

from rubrotor.errors import InputError
from rubrotor.linear.modes import DampedModes
from rubrotor.linear.modes import damped_modes as _damped_modes
from rubrotor.linear.shaft import CriticalSpeed, Mode, natural_frequencies
from rubrotor.linear.shaft import critical_speeds as _critical_speeds
from rubrotor.rotors.linear import LinearSystem
from rubrotor.rotors.shaft import Shaft
from rubrotor.scenario.load import Scenario, load_scenario

__all__ = ["modes", "critical_speeds", "linear_system", "damped_modes"]


def _loaded(obj):
    """``obj``, or the scenario read from it when it is a path to a scenario file."""
    return load_scenario(obj) if isinstance(obj, str | os.PathLike) else obj


def _shaft_and_speed(obj) -> tuple[Shaft, float]:
    obj = _loaded(obj)
    if isinstance(obj, Scenario):
        return obj.require_shaft("this analysis"), obj.speed
    if isinstance(obj, Shaft):
        return obj, 0.0
    raise InputError("scenario_or_shaft", obj, "a Scenario, a Shaft or a scenario file's path")


def modes(scenario_or_shaft: Scenario | Shaft, speed: float | None = None) -> list[Mode]:
    """Every whirl frequency of every mode at one spin speed.

    Parameters
    ----------
    scenario_or_shaft : Scenario, Shaft or path-like
        The rotor; a path is read with :func:`~rubrotor.load_scenario`.
    speed : float, optional
        Spin speed ``Omega`` (rad/s), ``>= 0``. Default: the scenario's speed, or 0 (at rest) for
        a bare shaft.

    Returns
    -------
    list of Mode
        Sorted by mode number, branch (bending first) and whirl (backward first); frequencies in
        Hz, positive.

    Examples
    --------
    >>> s = Shaft(length=0.4, diameter=0.1, youngs_modulus=71e9, density=2660,
    ...           shear_modulus=26.2e9, shear_coefficient="seed")
    >>> round(modes(s)[0].frequency_hz, 1)
    1193.2
    """
    shaft, default = _shaft_and_speed(scenario_or_shaft)
    return natural_frequencies(shaft, default if speed is None else speed)


def critical_speeds(scenario_or_shaft: Scenario | Shaft) -> list[CriticalSpeed]:
    """Forward and backward critical speeds of every mode and branch, in closed form.

    Parameters
    ----------
    scenario_or_shaft : Scenario, Shaft or path-like
        The rotor; a path is read with :func:`~rubrotor.load_scenario`.

    Returns
    -------
    list of CriticalSpeed
        Sorted by speed (rad/s).
    """
    shaft, _ = _shaft_and_speed(scenario_or_shaft)
    return _critical_speeds(shaft)


def linear_system(obj, stations=()) -> LinearSystem:
    """The :class:`~rubrotor.rotors.linear.LinearSystem` of a scenario, rotor, shaft or system.

    Parameters
    ----------
    obj : Scenario, Rotor, Shaft, LinearSystem or path-like
        A general rotor is meshed with a node at each of the scenario's stations (unbalance,
        load, contact and probe positions); a continuous shaft keeps its exact modal model.
    stations : sequence of float
        Further positions (m) a general rotor gets nodes at (e.g. the probes of a verb).

    Returns
    -------
    LinearSystem
    """
    from rubrotor.rotors.fe import Rotor
    from rubrotor.rotors.shaft_system import continuous_system

    obj = _loaded(obj)
    if isinstance(obj, LinearSystem):
        return obj
    if isinstance(obj, Scenario):
        if obj.model.fe_rotor:
            return obj.rotor.linear_system(tuple(obj.stations) + tuple(stations))
        return continuous_system(obj.shaft, obj.damping)
    if isinstance(obj, Rotor):
        return obj.linear_system(tuple(stations))
    if isinstance(obj, Shaft):
        return continuous_system(obj)
    raise InputError(
        "rotor", obj, "a Scenario, Rotor, Shaft, LinearSystem or a scenario file's path"
    )


def damped_modes(obj, speed: float | None = None, n: int | None = None) -> DampedModes:
    """Damped modes (frequency, damping ratio, log dec, whirl, shape) of any rotor at a speed.

    Parameters
    ----------
    obj : Scenario, Rotor, Shaft, LinearSystem or path-like
        The rotor (see :func:`linear_system`).
    speed : float, optional
        Spin speed (rad/s); default the scenario's, or 0.
    n : int, optional
        Keep the ``n`` lowest modes (default all).

    Returns
    -------
    DampedModes
    """
    obj = _loaded(obj)
    default = obj.speed if isinstance(obj, Scenario) else 0.0
    return _damped_modes(linear_system(obj), default if speed is None else speed, n)
