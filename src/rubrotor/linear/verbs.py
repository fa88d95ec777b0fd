"""Verbs of the modal analysis that take a :class:`~rubrotor.scenario.Scenario`, a bare
:class:`~rubrotor.rotors.shaft.Shaft`, a general :class:`~rubrotor.rotors.fe.Rotor` or any
:class:`~rubrotor.rotors.linear.LinearSystem`.
"""

from __future__ import annotations

import math

from rubrotor.errors import InputError
from rubrotor.linear.modes import DampedModes
from rubrotor.linear.modes import damped_modes as _damped_modes
from rubrotor.linear.shaft import CriticalSpeed, Mode, natural_frequencies  # noqa: F401
from rubrotor.linear.shaft import critical_speeds as _critical_speeds
from rubrotor.rotors.linear import LinearSystem
from rubrotor.rotors.shaft import Shaft

__all__ = [
    "modes",
    "critical_speeds",
    "linear_system",
    "damped_modes",
]


def _model(obj, name: str = "rotor"):
    """The :class:`~rubrotor.modelling.Model` of ``obj`` (a path is read as a scenario)."""
    from rubrotor.modelling import Model

    return Model.of(obj, name)


def _loaded(obj):
    """``obj``, or the scenario read from it when it is a path to a scenario file."""
    import os

    from rubrotor.scenario.load import load_scenario

    return load_scenario(obj) if isinstance(obj, str | os.PathLike) else obj


def _shaft_and_speed(model) -> tuple[Shaft, float]:
    """The continuous shaft of a closed-form ``model`` and its default speed (rad/s)."""
    if model.scenario is not None:
        return model.require_shaft("this analysis"), model.scenario.speed
    return model.shaft, 0.0


def _speed(model, speed, field: str = "speed") -> float:
    """``speed`` (rad/s), or the scenario's (0 for a bare rotor), checked finite and >= 0."""
    default = model.scenario.speed if model.scenario is not None else 0.0
    value = default if speed is None else speed
    if isinstance(value, bool) or not isinstance(value, int | float) or not (
        math.isfinite(value) and value >= 0
    ):
        raise InputError(field, speed, "a finite spin speed >= 0 (rad/s)")
    return float(value)


def modes(scenario_or_shaft, speed: float | None = None, n: int | None = 20, order: str = "ross"):
    """The modes of any rotor at one spin speed, as ``rubrotor modes`` prints them.

    Parameters
    ----------
    scenario_or_shaft : Scenario, Shaft, Rotor, LinearSystem or path-like
        The rotor; a path is read with :func:`~rubrotor.load_scenario`.
    speed : float, optional
        Spin speed ``Omega`` (rad/s), ``>= 0``. Default: the scenario's speed, or 0 (at rest)
        for a bare rotor.
    n : int or None
        Any other rotor than the continuous shaft: keep the ``n`` lowest modes (default 20,
        as the command's table; None for all).
    order : {"ross", "natural"}
        Any other rotor: ROSS 3.1's selection and order (the default, as the command prints
        them) or by ``|lambda|`` (:func:`rubrotor.linear.modes.damped_modes`).

    Returns
    -------
    list of Mode or DampedModes
        The continuous shaft: every whirl frequency in closed form (``Mode``, sorted by
        mode number, branch and whirl; Hz). Any other rotor: its damped modes
        (``rubrotor.linear.modes.DampedModes``: frequency, damping ratio, log dec, whirl
        and shape of each, ranked by undamped natural frequency).

    Examples
    --------
    >>> s = Shaft(length=0.4, diameter=0.1, youngs_modulus=71e9, density=2660,
    ...           shear_modulus=26.2e9, shear_coefficient="seed")
    >>> round(modes(s)[0].frequency_hz, 1)
    1193.2
    """
    model = _model(scenario_or_shaft, "scenario_or_shaft")
    if model.linear == "closed-form":
        shaft, default = _shaft_and_speed(model)
        return natural_frequencies(shaft, default if speed is None else speed)
    return _damped_modes(model.linear_system(), _speed(model, speed), n, order)


def critical_speeds(scenario_or_shaft, max_speed: float | None = None, n: int = 8) -> list:
    """Critical speeds of any rotor, as ``rubrotor critical`` prints them.

    Parameters
    ----------
    scenario_or_shaft : Scenario, Shaft, Rotor, LinearSystem or path-like
        The rotor; a path is read with :func:`~rubrotor.load_scenario`.
    max_speed : float, optional
        Any other rotor than the continuous shaft: search up to this speed (rad/s); default
        3 x the scenario's speed (at least 100 rad/s).
    n : int
        Modes followed on such a rotor (default 8).

    Returns
    -------
    list of CriticalSpeed or LinearCritical
        The continuous shaft: forward and backward critical speeds of every mode and branch in
        closed form (``CriticalSpeed``), sorted by speed (rad/s). Any other rotor: the
        speeds where a damped frequency equals the spin
        (``rubrotor.linear.critical.LinearCritical``, with damping ratio and whirl).
    """
    from rubrotor.linear.critical import linear_critical_speeds

    model = _model(scenario_or_shaft, "scenario_or_shaft")
    if model.linear == "closed-form":
        shaft, _ = _shaft_and_speed(model)
        return _critical_speeds(shaft)
    top = max_speed if max_speed is not None else max(3.0 * _speed(model, None), 100.0)
    if not (isinstance(top, int | float) and math.isfinite(top) and top > 0):
        raise InputError("max_speed", max_speed, "a finite speed > 0 (rad/s)")
    return linear_critical_speeds(model.linear_system(), float(top), n=n)


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
    return _model(obj).linear_system(tuple(stations))


def damped_modes(
    obj, speed: float | None = None, n: int | None = None, order: str = "natural"
) -> DampedModes:
    """Damped modes (frequency, damping ratio, log dec, whirl, shape) of any rotor at a speed.

    Parameters
    ----------
    obj : Scenario, Rotor, Shaft, LinearSystem or path-like
        The rotor (see :func:`linear_system`).
    speed : float, optional
        Spin speed (rad/s); default the scenario's, or 0.
    n : int, optional
        Keep the ``n`` lowest modes (default all).
    order : {"natural", "ross"}
        By ``|lambda|`` (default) or ROSS 3.1's selection and order; see
        :func:`rubrotor.linear.modes.damped_modes`.

    Returns
    -------
    DampedModes
    """
    model = _model(obj)
    default = model.scenario.speed if model.scenario is not None else 0.0
    return _damped_modes(model.linear_system(), default if speed is None else speed, n, order)
