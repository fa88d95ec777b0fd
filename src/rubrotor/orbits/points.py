"""The scenario at each point of a sweep or a continuation: the base scenario with some of its
keys changed, validated as :meth:`rubrotor.scenario.Scenario.with_changes` does, with the
unswept shaft's critical speed solved once (:class:`PointScenarios`).

Used by continuation (:mod:`rubrotor.orbits.continuation`) and by the sweeps
(:mod:`rubrotor.sweeps.sweep`, :mod:`rubrotor.sweeps.follow`, a layer above): it lives in the
lowest layer that may both read scenarios and solve the shaft's critical speed.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

from rubrotor.modelling import model_of

__all__ = ["PointScenarios"]


def _point_scenario(base, keys: Sequence[str], values: Sequence[float]):
    from rubrotor.scenario.keys import base_key
    from rubrotor.scenario.schema import ROTOR_SCHEMA, SCHEMA

    changes = {}
    for key, value in zip(keys, values, strict=True):
        section, _, name = base_key(key).partition(".")
        kind = {**SCHEMA, **ROTOR_SCHEMA}.get(section, {}).get(name)
        changes[key] = int(round(value)) if kind == "int" else float(value)
    return base.with_changes(**changes)


class PointScenarios:
    """The scenario of each point of a sweep, equal to ``base.with_changes(...)`` of its keys.

    Validating a scenario with its speed given as ``speed.critical_multiple`` computes the
    shaft's first forward critical speed (a root search on the whirl frequencies, about 5 ms);
    when no ``shaft.*`` key is swept that speed is the same at every point, so it is computed
    once here and each point is built with ``speed.rad_per_s = multiple x critical`` (the same
    product the scenario loader forms, so the same bits), then given back its
    ``critical_multiple`` form.

    Parameters
    ----------
    base : rubrotor.scenario.Scenario
        The sweep's base scenario.
    keys : sequence of str
        The swept ``"section.key"`` names.
    """

    def __init__(self, base, keys: Sequence[str]) -> None:
        self.base, self.keys = base, list(keys)
        self.critical = None
        spec = getattr(base, "speed_spec", None) or ("", None)
        swept_speed = [k for k in self.keys if k.startswith("speed.")]
        by_multiple = swept_speed == ["speed.critical_multiple"] or (
            not swept_speed and spec[0] == "critical_multiple"
        )
        if (
            by_multiple
            and model_of(base).linear == "closed-form"
            and not any(k.startswith("shaft.") for k in keys)
        ):
            from rubrotor.linear.shaft import first_forward_critical

            self.critical = first_forward_critical(base.shaft)

    def __call__(self, values: Sequence[float]):
        """The point's validated scenario (``values`` in the order of ``keys``)."""
        if self.critical is None:
            return _point_scenario(self.base, self.keys, values)
        changes = dict(zip(self.keys, values, strict=True))
        multiple = changes.pop("speed.critical_multiple", self.base.speed_spec[1])
        keys, vals = list(changes), list(changes.values())
        keys.append("speed.rad_per_s")
        vals.append(float(multiple) * self.critical)
        sc = _point_scenario(self.base, keys, vals)
        spec = dict(sc._spec, speed={"critical_multiple": multiple})
        return dataclasses.replace(sc, speed_spec=("critical_multiple", multiple), _spec=spec)
