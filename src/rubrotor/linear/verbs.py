"""Verbs of the modal analysis that take a :class:`~rubrotor.scenario.Scenario`, a bare
:class:`~rubrotor.rotors.shaft.Shaft`, a general :class:`~rubrotor.rotors.fe.Rotor` or any
:class:`~rubrotor.rotors.linear.LinearSystem`.
"""

from __future__ import annotations

from rubrotor.errors import InputError
from rubrotor.linear.modes import DampedModes
from rubrotor.linear.modes import damped_modes as _damped_modes
from rubrotor.linear.shaft import CriticalSpeed, Mode, natural_frequencies
from rubrotor.linear.shaft import critical_speeds as _critical_speeds
from rubrotor.rotors.linear import LinearSystem
from rubrotor.rotors.shaft import Shaft
from rubrotor.scenario.load import Scenario

__all__ = ["modes", "critical_speeds", "linear_system", "damped_modes"]


def _model(obj, name: str = "rotor"):
    """The :class:`~rubrotor.modelling.Model` of ``obj`` (a path is read as a scenario)."""
    from rubrotor.modelling import Model

    return Model.of(obj, name)


def _shaft_and_speed(obj) -> tuple[Shaft, float]:
    try:
        model = _model(obj)
    except InputError:
        model = None
    if model is not None and model.scenario is not None:
        return model.require_shaft("this analysis"), model.scenario.speed
    shaft = None if model is None else model.shaft
    if shaft is None:
        raise InputError(
            "scenario_or_shaft", obj, "a Scenario, a Shaft or a scenario file's path"
        )
    return shaft, 0.0


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
