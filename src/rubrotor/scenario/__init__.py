"""Scenario files: TOML <-> :class:`~rubrotor.scenario.load.Scenario`, its schema and export.

* :mod:`rubrotor.scenario.load`: reading, validating and writing scenario files;
* :mod:`rubrotor.scenario.schema`: every key as a row (kind, unit, range);
* :mod:`rubrotor.scenario.rotor`: the general rotor's tables; :mod:`rubrotor.scenario.dynamics`:
  contacts, stators, gravity, unbalance planes, loads, speed laws and restarts;
* :mod:`rubrotor.scenario.export`: the JSON Schema of scenario files.

The names of :mod:`rubrotor.scenario.load` are read here too (``rubrotor.scenario.Scenario``).
"""


def __getattr__(name):
    import importlib

    load = importlib.import_module("rubrotor.scenario.load")

    try:
        return getattr(load, name)
    except AttributeError:
        raise AttributeError(f"module 'rubrotor.scenario' has no attribute {name!r}") from None
