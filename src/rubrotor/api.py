"""Verbs of the modal analysis that take either a :class:`~rubrotor.scenario.Scenario` or a bare
:class:`~rubrotor.model.Shaft`.
"""

from __future__ import annotations

from rubrotor.errors import InputError
from rubrotor.modal import CriticalSpeed, Mode, natural_frequencies
from rubrotor.modal import critical_speeds as _critical_speeds
from rubrotor.model import Shaft
from rubrotor.scenario import Scenario

__all__ = ["modes", "critical_speeds"]


def _shaft_and_speed(obj) -> tuple[Shaft, float]:
    if isinstance(obj, Scenario):
        return obj.require_shaft("this analysis"), obj.speed
    if isinstance(obj, Shaft):
        return obj, 0.0
    raise InputError("scenario_or_shaft", obj, "a Scenario or a Shaft")


def modes(scenario_or_shaft: Scenario | Shaft, speed: float | None = None) -> list[Mode]:
    """Every whirl frequency of every mode at one spin speed.

    Parameters
    ----------
    scenario_or_shaft : Scenario or Shaft
        The rotor.
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
    scenario_or_shaft : Scenario or Shaft
        The rotor.

    Returns
    -------
    list of CriticalSpeed
        Sorted by speed (rad/s).
    """
    shaft, _ = _shaft_and_speed(scenario_or_shaft)
    return _critical_speeds(shaft)
