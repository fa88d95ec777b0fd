"""What a scenario is, decided once when it is built: the rotor's kind, the features it uses and
the engine that runs it.

:attr:`Scenario.model <rubrotor.scenario.load.Scenario.model>` holds this :class:`Kind`; the
verbs do not read it: they ask :class:`rubrotor.modelling.Model` (built once per scenario from
it), which decides and builds. Its fields:

* ``rotor``: ``"shaft"`` (the continuous ``[shaft]``, exact modal expansion) or ``"fe"``
  (a finite-element ``[[section]]`` rotor);
* ``engine``: ``"shaft"`` (the seed shaft's exact complex path: one contact, constant speed,
  modal damping, the seed's formulations, exact variational maps) or ``"general"`` (any linear
  rotor through the general engine: several contacts, flexible offset stators, gravity, loads,
  several unbalance planes, run-up and coast-down, restarts, streaming);
* ``features``: the scenario keys that need the general engine (``gravity``, ``speed.profile``,
  ``contact`` arrays, ``contact.stator``, ``initial.state``, ``unbalance`` planes, ``load``
  arrays, ``reduction``), empty for a seed-shaft scenario.

A combination no engine honours is refused here, when the scenario is built, naming the key:
the seed's single-equation form (``shaft.formulation = "seed-eq1"``) runs only on the shaft's
engine, so with a general-engine key it is refused instead of silently running the two-field
model.
"""

from __future__ import annotations

from dataclasses import dataclass

from rubrotor.errors import ScenarioError

__all__ = ["Kind", "ROTORS", "ENGINES", "engine_features"]

ROTORS = ("shaft", "fe")
"""Kinds of rotor: the continuous shaft, a finite-element rotor."""

ENGINES = ("shaft", "general")
"""Engines: the seed shaft's exact complex path, the general engine."""


@dataclass(frozen=True)
class Kind:
    """What one scenario is (see the module docstring).

    Attributes
    ----------
    rotor : {"shaft", "fe"}
        Kind of rotor.
    engine : {"shaft", "general"}
        The engine that runs the scenario's time simulations and periodic orbits.
    formulation : {"two-field", "seed-eq1", "fe"}
        The shaft's formulation, ``"fe"`` for a finite-element rotor.
    features : tuple of str
        Scenario keys that need the general engine, in schema order (empty on the shaft's
        engine).
    spin : {"imposed", "free"}
        ``"free"`` when the spin speed is a state (``[speed] profile = "free"``, run by
        :mod:`rubrotor.engine.spin`), else ``"imposed"``.
    """

    rotor: str
    engine: str
    formulation: str
    features: tuple[str, ...] = ()
    spin: str = "imposed"

    @classmethod
    def for_scenario(cls, scenario) -> Kind:
        """Decide what ``scenario`` is; refuse what no engine honours (naming the key).

        Parameters
        ----------
        scenario : rubrotor.scenario.load.Scenario
            A validated scenario.

        Returns
        -------
        Kind

        Raises
        ------
        ScenarioError
            ``shaft.formulation = "seed-eq1"`` together with a key only the general engine has.
        """
        rotor = "shaft" if scenario.shaft is not None else "fe"
        features = engine_features(scenario.engine)
        engine = "general" if scenario.engine is not None else "shaft"
        formulation = scenario.shaft.formulation if rotor == "shaft" else "fe"
        if formulation == "seed-eq1" and engine == "general":
            key = features[0] if features else "scenario"
            raise ScenarioError(
                "shaft.formulation",
                "seed-eq1",
                f"\"two-field\" with the general engine's key {key} (the seed's single-equation "
                "form runs only on the shaft's engine: one [contact], [unbalance] and [load] "
                "table, no [gravity], constant speed)",
            )
        spin = "free" if getattr(scenario.engine, "free_spin", None) is not None else "imposed"
        return cls(rotor=rotor, engine=engine, formulation=formulation, features=features,
                   spin=spin)  # fmt: skip

    @property
    def general(self) -> bool:
        """True when the general engine runs the scenario."""
        return self.engine == "general"

    @property
    def fe_rotor(self) -> bool:
        """True for a finite-element (``[[section]]``) rotor."""
        return self.rotor == "fe"

    def require_shaft_engine(self, what: str) -> None:
        """Refuse, naming the scenario key, a verb only the shaft's engine has.

        Parameters
        ----------
        what : str
            The verb, e.g. ``"the convergence study"``.

        Raises
        ------
        ScenarioError
            On a finite-element rotor (key ``section``) or a scenario using a general-engine key
            (that key).
        """
        if self.fe_rotor:
            raise ScenarioError(
                "section",
                "[[section]] tables",
                f"a [shaft] scenario: {what} runs on the continuous shaft only",
            )
        if self.general:
            raise ScenarioError(
                self.features[0] if self.features else "scenario",
                "general-engine keys",
                f"a scenario without them for {what} (it runs the seed shaft's engine: one "
                "[contact], [unbalance] and [load] table, no [gravity], constant speed)",
            )


def engine_features(spec) -> tuple[str, ...]:
    """Scenario keys of an :class:`~rubrotor.scenario.dynamics.EngineSpec` that only the general
    engine honours (empty for None)."""
    if spec is None:
        return ()
    checks = (
        ("contact", len(spec.stations) > 1),
        (
            "contact.stator",
            any(s.stator is not None or s.offset_y != 0 or s.offset_z != 0 for s in spec.stations),
        ),
        ("unbalance", len(spec.unbalances) > 1),
        ("load", len(spec.loads) > 1),
        ("gravity", any(g != 0 for g in spec.gravity)),
        (
            "speed.profile",
            spec.speed_end is not None
            or spec.speed_table is not None
            or spec.free_spin is not None,
        ),
        ("initial.state", spec.initial not in ("rest", "steady")),
        ("reduction", spec.modes is not None or spec.cutoff is not None or not spec.residual),
    )
    return tuple(key for key, used in checks if used)
