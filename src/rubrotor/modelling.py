"""The Model: what a scenario is, decided once, and what builds it.

Every verb (linear analyses, simulate, orbits, continuation, sweeps, thermal, free spin) asks
:meth:`Model.for_scenario` (built once per scenario and kept with it) and nothing else; no
module outside this one tests which kind of rotor it has (``tests/test_architecture.py``).

What the Model decides, as values the verbs look up in their tables:

* :attr:`Model.runner`: the engine of a time run, ``"shaft"`` (the seed shaft's exact complex
  path), ``"general"`` (any linear rotor, several contacts, gravity, speed laws, restarts) or
  ``"free-spin"`` (the spin speed a state);
* :attr:`Model.maps`: the engine of the periodic maps (shooting, continuation, Lyapunov
  exponents, sweeps, the thermal bow), ``"shaft"`` or ``"general"``; :meth:`Model.require_maps`
  refuses, naming the key, a scenario no map honours;
* :attr:`Model.linear`: the route of the linear analyses, ``"closed-form"`` (the continuous
  shaft's exact modes and critical speeds) or ``"matrix"`` (any :class:`LinearSystem`).

What it builds:

* :meth:`Model.linear_system`: the rotor's :class:`~rubrotor.rotors.linear.LinearSystem` from
  its builder (the continuous shaft's exact modal model, a finite-element rotor meshed at its
  stations, or a system imported from ROSS, :meth:`Model.from_ross`);
* :meth:`Model.forces`: the force terms the engine applies (contacts and stators, unbalance
  planes, loads, gravity), as the scenario's builders make them today;
* :meth:`Model.speed_law`: the spin speed against time.

The engine problem of a time run (:func:`rubrotor.engine.general.engine_problem`) is assembled
by the engine from these three.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field

from rubrotor.errors import InputError
from rubrotor.scenario.kind import ENGINES, ROTORS, Kind, engine_features

__all__ = ["Model", "Forces", "SpeedLaw", "ROTORS", "ENGINES", "RUNNERS", "engine_features"]

RUNNERS = ("shaft", "general", "free-spin")
"""Engines of a time run: the seed shaft's, the general one, the free-spin one."""


@dataclass(frozen=True)
class Forces:
    """The force terms of a scenario (SI), as its builders make them.

    Attributes
    ----------
    stations : tuple of rubrotor.engine.parts.RubStation
        Contacts and their stators (empty on the seed shaft's engine, whose single contact is
        ``contact``).
    unbalances : tuple of rubrotor.rotors.forces.Unbalance
        Unbalance planes (kg m, m, rad).
    loads : tuple of rubrotor.rotors.forces.RadialLoad
        Constant point loads (N, m).
    gravity : (float, float)
        ``(g_y, g_z)`` (m/s^2).
    contact : rubrotor.rotors.forces.Contact or None
        The seed shaft engine's one contact (None on the general engine).
    supports : tuple of rubrotor.forces.film_row.FilmRow
        The nonlinear supports' rows of the implicit step at the run's speed (fluid films,
        linearised in the linear system; empty without them).
    """

    stations: tuple = ()
    unbalances: tuple = ()
    loads: tuple = ()
    gravity: tuple = (0.0, 0.0)
    contact: object = None
    supports: tuple = ()


@dataclass(frozen=True)
class SpeedLaw:
    """The spin speed against time.

    Attributes
    ----------
    speed : float
        Speed at the start (rad/s).
    speed_end : float or None
        End speed of a linear run-up or coast-down (rad/s).
    step : float or None
        Speed step of a stepped profile (rad/s).
    table : tuple or None
        Rows ``(time (s), speed (rad/s))`` of a tabulated profile.
    free : rubrotor.engine.spin.FreeSpin or None
        Drive torque and drag when the speed is a state.
    """

    speed: float
    speed_end: float | None = None
    step: float | None = None
    table: tuple | None = None
    free: object = None


@dataclass(frozen=True)
class Geometry:
    """A rotor's geometry, as a drawing needs it.

    Attributes
    ----------
    sections : tuple of (float, float, float, float)
        ``(start, length, outer radius, bore radius)`` of each shaft section (m).
    length : float
        The rotor's length (m).
    disks : tuple
        Its disks (objects with ``position`` m, ``mass`` kg, ``polar_inertia`` kg m^2,
        ``width`` m and ``name``).
    supports : tuple of (float, str, bool)
        ``(position m, label, pinned)`` of each bearing or pinned end.
    mass : float or None
        The rotor's mass (kg), None where the model does not state it.
    nodes : tuple of float
        Finite-element nodes (m), empty for the continuous shaft.
    """

    sections: tuple
    length: float
    disks: tuple
    supports: tuple
    mass: float | None
    nodes: tuple


@dataclass(frozen=True)
class Model:
    """What one scenario (or rotor) is, and the builder of its parts (see the module docstring).

    Build it with :meth:`for_scenario` (or :meth:`of`, which also takes a path, a rotor, a
    shaft or a linear system); the fields are those of the scenario's
    ``rubrotor.scenario.kind.Kind``.

    Attributes
    ----------
    rotor : {"shaft", "fe", "system"}
        Kind of rotor: the continuous shaft, a finite-element rotor, or a given linear system
        (e.g. imported from ROSS).
    engine : {"shaft", "general"}
        The engine of the scenario's time runs at imposed speed.
    formulation : {"two-field", "seed-eq1", "fe"}
        The shaft's formulation, ``"fe"`` otherwise.
    features : tuple of str
        Scenario keys that need the general engine.
    spin : {"imposed", "free"}
        Whether the spin speed is imposed or a state.
    scenario : rubrotor.scenario.load.Scenario or None
        The scenario it was built from.
    """

    rotor: str
    engine: str
    formulation: str
    features: tuple[str, ...] = ()
    spin: str = "imposed"
    scenario: object = field(default=None, compare=False, repr=False)
    source: object = field(default=None, compare=False, repr=False)

    # ---- building it -----------------------------------------------------------------------
    @classmethod
    def for_scenario(cls, scenario) -> Model:
        """The Model of ``scenario``, built once and kept with it.

        Parameters
        ----------
        scenario : rubrotor.scenario.load.Scenario
            A validated scenario.

        Returns
        -------
        Model
        """
        built = getattr(scenario, "_built", None)
        if built is not None and "model" in built:
            return built["model"]
        kind = getattr(scenario, "model", None)
        if not isinstance(kind, Kind):  # a scenario-like object: decide here
            kind = Kind.for_scenario(scenario)
        model = cls(rotor=kind.rotor, engine=kind.engine, formulation=kind.formulation,
                    features=kind.features, spin=kind.spin, scenario=scenario)  # fmt: skip
        if built is not None:
            built["model"] = model
        return model

    @classmethod
    def of(cls, obj, name: str = "rotor") -> Model:
        """The Model of a scenario, a scenario file, a rotor, a shaft or a linear system.

        Parameters
        ----------
        obj : Scenario, path-like, Rotor, Shaft or LinearSystem
            What to model; a path is read with :func:`rubrotor.load_scenario`.
        name : str
            The argument's name, for the error message.

        Returns
        -------
        Model

        Raises
        ------
        InputError
            ``obj`` is none of these.
        """
        from rubrotor.rotors.fe import Rotor
        from rubrotor.rotors.linear import LinearSystem
        from rubrotor.rotors.shaft import Shaft
        from rubrotor.scenario.load import Scenario, load_scenario

        if isinstance(obj, str | os.PathLike):
            obj = load_scenario(obj)
        if isinstance(obj, Scenario):
            return cls.for_scenario(obj)
        if isinstance(obj, LinearSystem):
            return cls("system", "general", "fe", source=obj)
        if isinstance(obj, Rotor):
            return cls("fe", "general", "fe", source=obj)
        if isinstance(obj, Shaft):
            return cls("shaft", "shaft", obj.formulation, source=obj)
        raise InputError(name, obj, "a Scenario, Rotor, Shaft, LinearSystem or a scenario file's path")

    @classmethod
    def from_ross(cls, rotor, speeds=None, interpolation: str = "ross") -> Model:
        """The Model of a ROSS rotor (:func:`rubrotor.rotors.ross.from_ross`).

        Parameters
        ----------
        rotor : ross.Rotor
            The ROSS rotor.
        speeds : sequence of float, optional
            Speeds (rad/s) at which speed-dependent bearings are tabulated.
        interpolation : str
            As in :func:`~rubrotor.rotors.ross.from_ross`.

        Returns
        -------
        Model
        """
        from rubrotor.rotors.ross import from_ross

        return cls("system", "general", "fe",
                   source=from_ross(rotor, speeds=speeds, interpolation=interpolation))  # fmt: skip

    # ---- what it decides -------------------------------------------------------------------
    @property
    def general(self) -> bool:
        """True when the general engine runs the scenario's time runs (old name)."""
        return self.engine == "general"

    @property
    def fe_rotor(self) -> bool:
        """True for a finite-element rotor (old name)."""
        return self.rotor == "fe"

    @property
    def runner(self) -> str:
        """The engine of a time run, one of ``RUNNERS``."""
        return "free-spin" if self.spin == "free" else self.engine

    @property
    def maps(self) -> str:
        """The engine of the periodic maps, orbits and sweeps: ``"general"`` for a
        finite-element rotor or a given system, ``"shaft"`` for the continuous shaft (which
        :meth:`require_maps` checks)."""
        return "shaft" if self.rotor == "shaft" else "general"

    @property
    def linear(self) -> str:
        """The route of the linear analyses: ``"closed-form"`` (the continuous shaft) or
        ``"matrix"`` (a finite-element rotor or a given system)."""
        return "closed-form" if self.rotor == "shaft" else "matrix"

    def require_maps(self, what: str) -> str:
        """:attr:`maps`, refusing (naming the key) a shaft scenario with general-engine keys.

        Parameters
        ----------
        what : str
            The verb, e.g. ``"periodic orbits (shooting, continuation)"``.

        Returns
        -------
        str
            ``"shaft"`` or ``"general"``.

        Raises
        ------
        ScenarioError
            A ``[shaft]`` scenario using a key only the general engine has (that key).
        """
        if self.maps == "shaft":
            self.require_shaft_engine(what)
        return self.maps

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
        Kind.require_shaft_engine(self, what)

    def require_general_rotor(self, error: Exception) -> None:
        """Raise ``error`` unless the rotor is a finite-element rotor (the verbs that need its
        sections, disks and bearings: free spin, thermal bow, the general map)."""
        if self.rotor != "fe":
            raise error

    def require_shaft(self, what: str):
        """The continuous shaft (:class:`rubrotor.rotors.shaft.Shaft`), or a ScenarioError
        saying ``what`` needs one."""
        if self.scenario is not None:
            return self.scenario.require_shaft(what)
        if self.rotor != "shaft":
            raise InputError("rotor", self.rotor, f"a continuous Shaft for {what}")
        return self.source

    # ---- what it builds --------------------------------------------------------------------
    @property
    def shaft(self):
        """The continuous shaft, or None for any other rotor."""
        if self.rotor != "shaft":
            return None
        return self.scenario.shaft if self.scenario is not None else self.source

    def span(self) -> tuple[float, bool]:
        """The rotor's length (m) and whether its ends are stations (a finite-element rotor:
        ``[0, L]``; the continuous shaft, pinned at its ends: ``(0, L)``)."""
        if self.rotor == "fe":
            return float(self._fe().length), True
        return float(self.shaft.length), False

    def heaviest_disk(self) -> float | None:
        """Axial position (m) of a finite-element rotor's heaviest disk (None without disks)."""
        if self.rotor != "fe" or not self._fe().disks:
            return None
        return float(max(self._fe().disks, key=lambda d: d.mass).position)

    def geometry(self) -> Geometry:
        """What a drawing of the rotor needs (see ``Geometry``), for any rotor."""
        if self.rotor == "fe":
            fe = self._fe()
            sections, x0 = [], 0.0
            for s in fe.sections:
                sections.append((x0, s.length, s.diameter / 2, s.bore_diameter / 2))
                x0 += s.length
            stations = tuple(self.scenario.stations) if self.scenario is not None else ()
            supports = tuple((b.position, b.name or b.kind, b.kind == "pinned")
                             for b in fe.bearings)  # fmt: skip
            return Geometry(tuple(sections), float(fe.length), tuple(fe.disks), supports,
                            float(fe.mass), tuple(float(x) for x in fe.nodes(stations)))  # fmt: skip
        sh = self.shaft
        ends = ((0.0, "pinned end", True), (float(sh.length), "pinned end", True))
        return Geometry(((0.0, sh.length, sh.diameter / 2, sh.bore_diameter / 2),),
                        float(sh.length), (), ends, None, ())  # fmt: skip

    def carrying_bearings(self) -> tuple:
        """Stations (m) of the supports that carry the rotor to the ground: bearings, not seals
        nor supports on a housing (the continuous shaft: its pinned ends)."""
        if self.rotor == "fe":
            return tuple(b.position for b in self._fe().bearings
                         if b.kind != "seal" and b.on is None)  # fmt: skip
        return tuple(s.position for s in self.linear_system().supports if s.kind != "seal")

    def _fe(self):
        return self.scenario.rotor if self.scenario is not None else self.source

    def linear_system(self, stations=(), *, only: bool = False):
        """The rotor's :class:`~rubrotor.rotors.linear.LinearSystem`.

        Parameters
        ----------
        stations : sequence of float
            Positions (m) a finite-element rotor gets nodes at, besides the scenario's stations
            (unbalance, load, contact and probe positions).
        only : bool
            Mesh at ``stations`` alone (the engine's own station set).

        Returns
        -------
        LinearSystem
            The continuous shaft's exact modal model (with the scenario's modal damping), the
            finite-element rotor meshed at the stations, or the given system.
        """
        from rubrotor.rotors.shaft_system import continuous_system

        if self.rotor == "system":
            return self.source
        if self.rotor == "fe":
            sc = self.scenario
            base = () if only or sc is None else tuple(sc.stations)
            return self._linearised(self._fe().linear_system(base + tuple(stations)))
        if self.scenario is None:
            return continuous_system(self.source)
        return continuous_system(self.scenario.shaft, self.scenario.damping)

    def _linearised(self, system):
        """``system`` with its nonlinear supports (fluid films) given their law: linearised at
        the rotor's static equilibrium under the scenario's gravity and loads (those of its time
        runs) at each speed asked (:mod:`rubrotor.forces.equilibrium`)."""
        import dataclasses

        from rubrotor.forces.equilibrium import Linearisation, gravity_load, nonlinear_supports

        sups = nonlinear_supports(system)
        if not sups:
            return system
        sc = self.scenario
        gravity = (sc.gravity if sc is not None else None) or (0.0, 0.0)
        loads = tuple(sc.loads) if sc is not None else ()
        lin = Linearisation(system, gravity_load(system, gravity, loads))
        index = {id(s): i for i, s in enumerate(sups)}
        new = tuple(dataclasses.replace(s, law=lin.law(index[id(s)]), term=s.term)
                    if id(s) in index else s for s in system.supports)  # fmt: skip
        out = dataclasses.replace(system, supports=new)
        lin.system = out
        return out

    def support_linearisation(self, speed: float, system=None) -> tuple:
        """Each nonlinear support (fluid film) at the rotor's static equilibrium at ``speed``.

        Parameters
        ----------
        speed : float
            Spin speed (rad/s), > 0 with journal bearings.
        system : LinearSystem, optional
            A system this Model built (:meth:`linear_system`, e.g. the engine's own mesh);
            default the scenario's.

        Returns
        -------
        tuple of rubrotor.forces.equilibrium.SupportLinearisation
            In the order of the supports: node DOFs, static journal position ``p0`` (m, from the
            bearing centre), ``K0`` (N/m) and ``C0`` (N s/m) as they enter the linear system at
            that speed, the film's parameters; empty without nonlinear supports.
        """
        from rubrotor.forces.equilibrium import nonlinear_supports

        system = self.linear_system() if system is None else system
        sups = nonlinear_supports(system)
        if not sups:
            return ()
        return sups[0].law.linearisation.states(float(speed))

    def nonlinear_supports(self) -> tuple:
        """``(index, type)`` of each ``[[bearing]]`` whose support is nonlinear (a fluid film:
        ``short_journal``, ``squeeze_film``, ``finite_journal``), index counted from 1."""
        if self.rotor != "fe":
            return ()
        return tuple((i + 1, b.type) for i, b in enumerate(self._fe().bearings)
                     if getattr(b, "nonlinear", False))  # fmt: skip

    def forces(self, speed: float | None = None, system=None) -> Forces:
        """The force terms of the scenario (see ``Forces``).

        Parameters
        ----------
        speed : float, optional
            The run's constant spin speed (rad/s): the fluid-film supports become rows of the
            implicit step, linearised at the rotor's static equilibrium at this speed
            (:meth:`support_linearisation`). Without it a scenario with a film is refused.
        system : LinearSystem, optional
            The system the run uses (the engine's mesh), built by this Model.

        Raises
        ------
        ScenarioError
            A fluid-film support without ``speed`` (the free-speed run, whose speed is a
            state), or a support whose force has no compiled row (``finite_journal``).
        """
        films = self.nonlinear_supports()
        if not films:
            return self._forces()
        from rubrotor.errors import ScenarioError

        i, kind = films[0]
        if speed is None:
            raise ScenarioError(f"bearing[{i}].type", kind,
                                "a linear support type for a free-speed run (its speed is a "
                                "state; fluid films run at a constant speed)")  # fmt: skip
        rows = []
        for (i, kind), lin in zip(films, self.support_linearisation(speed, system), strict=True):
            row = getattr(lin.term, "engine_row", None)
            if row is None:
                raise ScenarioError(f"bearing[{i}].type", kind,
                                    '"short_journal" or "squeeze_film" for a time run (this '
                                    "film's force has no compiled row: use it in static, "
                                    "bearings and the linear verbs)")  # fmt: skip
            rows.append(row(lin))
        return dataclasses.replace(self._forces(), supports=tuple(rows))

    def _forces(self) -> Forces:
        sc = self.scenario
        eng = sc.engine
        if self.engine == "general":
            return Forces(stations=tuple(eng.stations), unbalances=tuple(eng.unbalances),
                          loads=tuple(eng.loads), gravity=tuple(eng.gravity))  # fmt: skip
        return Forces(unbalances=sc.unbalances, loads=sc.loads, contact=sc.contact)

    @property
    def contact_stations(self) -> tuple:
        """The general engine's contact stations (empty on the seed shaft's engine)."""
        return self._forces().stations if self.engine == "general" else ()

    @property
    def first_contact(self):
        """The scenario's ``[contact]`` or its first ``[[contact]]`` table (None without)."""
        sc = self.scenario
        if sc.contact is not None:
            return sc.contact
        st = self.contact_stations
        return st[0].contact if st else None

    @property
    def seed_contact(self):
        """The seed shaft engine's one contact (None on the general engine)."""
        return self.scenario.contact if self.engine == "shaft" else None

    def speed_law(self) -> SpeedLaw:
        """The spin speed against time (see ``SpeedLaw``)."""
        sc = self.scenario
        eng = sc.engine
        if eng is None:
            return SpeedLaw(sc.speed)
        return SpeedLaw(sc.speed, eng.speed_end, eng.speed_step, eng.speed_table,
                        eng.free_spin)  # fmt: skip


def model_of(scenario) -> Model:
    """:meth:`Model.for_scenario` (the short spelling the verbs use)."""
    return Model.for_scenario(scenario)

