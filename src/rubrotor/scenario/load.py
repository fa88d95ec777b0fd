"""Scenario files: one TOML file describes one rotor, its speed, forces, contact and integrator.

A scenario is the same set of objects as the Python API (:class:`rubrotor.rotors.shaft.Shaft`,
:class:`rubrotor.rotors.forces.Unbalance`, :class:`~rubrotor.rotors.forces.RadialLoad`,
:class:`~rubrotor.rotors.forces.Contact`, :class:`~rubrotor.rotors.forces.ModalDamping`,
:class:`rubrotor.engine.settings.Integrator`) plus the spin speed, read from a file and validated key
by key. Every unknown, missing, mistyped or non-physical key raises :class:`ScenarioError` naming
the key (``"shaft.length"``), the value and what is allowed.

Schema: every table and key, with its kind, unit, allowed range or choices, default and
description, is one row of the table of :mod:`rubrotor.scenario.schema`, from which this module's checks,
:data:`~rubrotor.scenario.schema.KEY_UNITS`, the JSON Schema (:mod:`rubrotor.scenario.export`) and the docs' key table are
generated. SI units unless the key ends in ``_nd``; ``_nd`` keys are the seed's dimensionless
form, converted exactly with :class:`rubrotor.rotors.shaft.Dimensionless`. In short::

    [meta]        name, description                                    (optional)
    [shaft]       length; diameter | slenderness; bore_diameter; youngs_modulus; density;
                  shear_modulus | poisson_ratio | shear_parameter; shear_coefficient;
                  theory; gyroscopic; modes; formulation
    [speed]       exactly one of rad_per_s, rpm, hz, critical_multiple, dimensionless
    [unbalance]   magnitude | magnitude_nd; position | position_nd; phase_deg  (optional)
    [load]        force_y, force_z; position | position_nd                  (optional)
    [contact]     law; position | position_nd; clearance | clearance_nd;
                  stiffness | stiffness_nd; damping | damping_nd | restitution (with
                  impact_speed, restitution_model); friction; friction_sign; radius;
                  friction_regularization                                   (optional)
    [damping]     ratio (a number or a list per mode)                       (optional)
    [simulation]  the fields of :class:`rubrotor.engine.settings.Integrator`      (optional)
    [initial]     state ("rest" | "steady": on the steady no-contact orbit)  (optional)

Positions default to midspan and are stored resolved, in m. Keys that need the speed
(``magnitude_nd``, ``damping_nd``) are converted with the resolved speed.

General rotor: instead of ``[shaft]`` (never with it), the tables ``[materials.NAME]``,
``[[section]]``, ``[[disk]]``, ``[[bearing]]`` and ``[rotor]`` of
:mod:`rubrotor.scenario.rotor` build :attr:`Scenario.rotor` (a :class:`rubrotor.rotors.fe.Rotor`).
Then ``[speed]`` takes ``rad_per_s``, ``rpm``, ``hz`` or ``critical_multiple`` (a multiple
of the rotor's first forward critical speed,
:func:`rubrotor.linear.critical.first_forward_critical_speed`; ``dimensionless`` is defined for
the uniform shaft only), positions of ``[unbalance]``, ``[load]``
and ``[contact]`` are required and lie in ``[0, L]``, ``_nd`` keys and ``[damping]`` are
rejected, and verbs that need the continuous shaft (time simulation, sweeps, the convergence
study) raise :class:`ScenarioError` on field ``"section"`` (:meth:`Scenario.require_shaft`).
"""

from __future__ import annotations

import copy
import dataclasses
import math
import os
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from rubrotor.engine.settings import Integrator
from rubrotor.errors import InputError, ScenarioError
from rubrotor.linear.shaft import first_forward_critical
from rubrotor.rotors.fe import Rotor
from rubrotor.rotors.forces import (
    Contact,
    ModalDamping,
    RadialLoad,
    ThermalBow,
    Unbalance,
    restitution_damping,
)
from rubrotor.rotors.shaft import Dimensionless, Shaft
from rubrotor.scenario import plausible
from rubrotor.scenario.dynamics import Builders, EngineSpec, engine_spec_or_none, split_engine_keys
from rubrotor.scenario.kind import Kind
from rubrotor.scenario.rotor import build_rotor, normalise_rotor_tables, rotor_to_dict
from rubrotor.scenario.schema import (
    ALTERNATIVES,
    KEY_UNITS,
    REQUIRED,
    ROTOR_TABLES,
    SCHEMA,
    TABLES,
    check_value,
    key_row,
    key_unit,
    table_row,
    unknown_key_text,
)

__all__ = [
    "Scenario",
    "as_scenario",
    "load_scenario",
    "find_scenario",
    "shipped_scenarios",
    "scenario_from_dict",
    "scenario_to_dict",
    "SCHEMA",
    "ALTERNATIVES",
    "KEY_UNITS",
    "key_unit",
]

# ---- schema ------------------------------------------------------------------------------------
# The tables of keys, kinds, units, ranges and alternatives are generated from the rows of
# rubrotor.scenario.schema (re-exported here: SCHEMA, ALTERNATIVES, KEY_UNITS, key_unit).
_REQUIRED_TABLES = tuple(t.name for t in TABLES if t.required)


def _err(field_name: str, value, allowed: str) -> ScenarioError:
    return ScenarioError(field_name, value, allowed)


def _missing_table(name: str, general: bool) -> ScenarioError | None:
    """The error for a required table ``name`` that is absent (None if it is not needed)."""
    rotor = table_row(name).rotor
    if rotor == "shaft" and general:
        return None
    if rotor == "general" and not general:
        return None
    if name == "shaft":
        return _err(name, None, "a [shaft] section (or [[section]] tables)")
    return _err(name, None, f"a [{name}] section")


def _check_groups(section: str, values: dict) -> None:
    """Required keys and groups of alternative keys of one table."""
    for key in REQUIRED.get(section, ()):
        if key not in values:
            raise _err(f"{section}.{key}", None, "a value (this key is required)")
    for group, required in ALTERNATIVES.get(section, []):
        given = [k for k in group if k in values]
        names = " / ".join(f"{section}.{k}" for k in group)
        if len(given) > 1:
            raise _err(names, tuple(values[k] for k in given), f"only one of {', '.join(group)}")
        if required and not given:
            raise _err(names, None, f"exactly one of {', '.join(group)} (one is required)")


def _normalise(mapping: Mapping) -> dict:
    """Check sections, keys, kinds, ranges and alternatives; return a plain nested dict copy."""
    if not isinstance(mapping, Mapping):
        raise _err("scenario", mapping, "a mapping of sections")
    out: dict = {}
    general = any(t in mapping for t in ROTOR_TABLES)
    if general:
        if "shaft" in mapping:
            raise _err(
                "shaft / section",
                "both",
                "either [shaft] (the uniform continuous shaft) or [[section]] tables (a general "
                "rotor), not both",
            )
        out.update(normalise_rotor_tables(mapping))
    for section, body in mapping.items():
        if section in ROTOR_TABLES:
            continue
        if section not in SCHEMA:
            raise _err(str(section), "...", unknown_key_text(section, [*SCHEMA, *ROTOR_TABLES],
                                                             "", "section"))
        if not isinstance(body, Mapping):
            raise _err(section, body, "a table of keys")
        allowed = SCHEMA[section]
        sec = {}
        for key, value in body.items():
            name = f"{section}.{key}"
            if key not in allowed:
                raise _err(name, value, unknown_key_text(key, allowed, f"[{section}]"))
            sec[key] = check_value(name, value, key_row(section, key))
        out[section] = sec
    for section in _REQUIRED_TABLES:
        if section not in out and (exc := _missing_table(section, general)) is not None:
            raise exc
    for section in SCHEMA:
        if section in out:
            _check_groups(section, out[section])
    return out


def _position(sec: dict, section: str, span: Shaft | Rotor) -> float:
    """Resolve ``position`` / ``position_nd`` to m: in (0, L) on a shaft (default midspan), in
    [0, L] on a general rotor (required there)."""
    length = span.length
    if isinstance(span, Rotor):
        if "position" not in sec:
            raise _err(f"{section}.position", None, "a value (m) on a general rotor")
        pos = float(sec["position"])
        if not 0 <= pos <= length:
            raise _err(f"{section}.position", sec["position"], f"in [0, {length:g}] m")
        return pos
    if "position" in sec:
        name, value, pos = f"{section}.position", sec["position"], float(sec["position"])
    elif "position_nd" in sec:
        name, value = f"{section}.position_nd", sec["position_nd"]
        pos = float(value) * length
    else:
        return length / 2
    if not 0 < pos < length:
        rng = f"(0, {length:g}) m" if name.endswith("position") else "(0, 1)"
        raise _err(name, value, f"a station inside the shaft, in {rng}")
    return pos


def _default(section: str, key: str):
    """The value of an absent key (its row's default)."""
    return key_row(section, key).default


_SPEED_ROW = key_row("speed", "rad_per_s")
SPEED_RANGE = (_SPEED_ROW.minimum, _SPEED_ROW.maximum)
"""Spin speeds (rad/s) a scenario may resolve to (besides 0)."""


def _build_shaft(sec: dict) -> Shaft:
    kwargs = {
        k: sec[k]
        for k in (
            "length",
            "youngs_modulus",
            "density",
            "theory",
            "gyroscopic",
            "modes",
            "formulation",
        )
        if k in sec
    }
    length = float(sec["length"])
    bore = float(sec.get("bore_diameter", _default("shaft", "bore_diameter")))
    if "diameter" in sec:
        kwargs["diameter"] = sec["diameter"]
    else:
        r = float(sec["slenderness"])
        # r0^2 = I/A = (D^2 + d^2)/16  ->  D = sqrt(16 r^2 L^2 - d^2)  (D = 4 r L when solid)
        d2 = 16 * (r * length) ** 2 - bore**2
        if d2 <= bore**2:
            raise _err(
                "shaft.slenderness",
                sec["slenderness"],
                f"a value giving a diameter > bore {bore} m",
            )
        kwargs["diameter"] = 4 * r * length if bore == 0 else math.sqrt(d2)
    kwargs["bore_diameter"] = bore
    coef = sec.get("shear_coefficient", _default("shaft", "shear_coefficient"))
    kwargs["shear_coefficient"] = coef
    if "shear_modulus" in sec:
        kwargs["shear_modulus"] = sec["shear_modulus"]
    elif "poisson_ratio" in sec:
        kwargs["poisson_ratio"] = sec["poisson_ratio"]
    else:
        delta = float(sec["shear_parameter"])
        if isinstance(coef, str) and coef != "seed":
            raise _err(
                "shaft.shear_coefficient",
                coef,
                '"seed" or a number when shaft.shear_parameter is given '
                "(Cowper's and Hutchinson's kappa depend on G)",
            )
        kappa = 10.0 / 9.0 if coef == "seed" else float(coef)
        e = float(sec["youngs_modulus"])
        kwargs["shear_modulus"] = e / (kappa * delta)
    return Shaft(**kwargs)


def _resolve_speed(sec: dict, shaft: Shaft | Rotor, stations: tuple = ()) -> tuple[float, tuple]:
    """The spin speed (rad/s) of ``[speed]``; a general rotor's critical multiple is taken on
    its mesh with nodes at ``stations`` (m), the mesh of :func:`rubrotor.linear_system`."""
    ((key, value),) = sec.items()
    name = f"speed.{key}"
    v = float(value)
    if key == "rad_per_s":
        om = v
    elif key == "rpm":
        om = v * 2 * math.pi / 60
    elif key == "hz":
        om = v * 2 * math.pi
    elif key == "critical_multiple" and isinstance(shaft, Rotor):
        from rubrotor.linear.critical import rotor_first_forward_critical

        om = v * rotor_first_forward_critical(shaft, stations) if v else 0.0
    elif key == "critical_multiple":
        om = v * first_forward_critical(shaft)
    else:
        om = Dimensionless.speed_from_parameter(shaft, v)
    if om != 0 and not SPEED_RANGE[0] <= om <= SPEED_RANGE[1]:
        raise _err(
            name,
            value,
            f"a value giving a spin speed in [{SPEED_RANGE[0]:g}, {SPEED_RANGE[1]:g}] rad/s",
        )
    return om, (key, value)


def _need_speed(name: str, value, speed: float):
    if speed <= 0:
        raise _err(name, value, "a speed > 0 to convert it (it scales with the spin speed)")


def _build_unbalance(sec: dict, shaft: Shaft, speed: float) -> Unbalance:
    if "magnitude" in sec:
        me = sec["magnitude"]
    else:
        _need_speed("unbalance.magnitude_nd", sec["magnitude_nd"], speed)
        me = Dimensionless(shaft, speed).unbalance_si(float(sec["magnitude_nd"]))
    return Unbalance(
        magnitude=me,
        position=_position(sec, "unbalance", shaft),
        phase=math.radians(sec.get("phase_deg", 0.0)),
    )


def _build_load(sec: dict, shaft: Shaft) -> RadialLoad:
    return RadialLoad(
        force_y=sec.get("force_y", 0.0),
        force_z=sec.get("force_z", 0.0),
        position=_position(sec, "load", shaft),
    )


def _build_contact(sec: dict, shaft: Shaft, speed: float) -> Contact:
    # the contact laws load the compiled contact kernels (numba): imported only for a contact
    from rubrotor.forces.contact import law_named

    law = sec.get("law", _default("contact", "law"))
    nd = Dimensionless(shaft, speed)
    if "clearance" in sec:
        clearance = sec["clearance"]
    else:
        clearance = nd.clearance_si(float(sec["clearance_nd"]))
    if "stiffness" in sec:
        stiffness = sec["stiffness"]
    else:
        k_nd = float(sec["stiffness_nd"])
        stiffness = law_named(law).stiffness_si(nd, k_nd)
    for key in ("impact_speed", "restitution_model"):
        if key in sec and "restitution" not in sec:
            raise _err(f"contact.{key}", sec[key], "to be given only with contact.restitution")
    if "damping" in sec:
        damping = sec["damping"]
    elif "damping_nd" in sec:
        if not law_named(law).restitution:
            raise _err(
                "contact.damping_nd", sec["damping_nd"], 'contact.damping (N s/m) for law "linear"'
            )
        _need_speed("contact.damping_nd", sec["damping_nd"], speed)
        damping = nd.contact_damping_si(float(sec["damping_nd"]))
    elif "restitution" in sec:
        if not law_named(law).restitution:
            raise _err(
                "contact.restitution", sec["restitution"], 'contact.damping for law "linear"'
            )
        if "impact_speed" not in sec:
            raise _err("contact.impact_speed", None, "a value (m/s) with contact.restitution")
        model = sec.get("restitution_model", _default("contact", "restitution_model"))
        damping = restitution_damping(sec["restitution"], sec["impact_speed"], model)
    else:
        damping = 0.0
    kwargs = {}
    if "friction_regularization" in sec:
        kwargs["friction_regularization"] = sec["friction_regularization"]
    return Contact(
        clearance=clearance,
        stiffness=stiffness,
        damping=damping,
        friction=sec.get("friction", _default("contact", "friction")),
        position=_position(sec, "contact", shaft),
        law=law,
        friction_sign=sec.get("friction_sign", _default("contact", "friction_sign")),
        radius=sec.get("radius"),
        **kwargs,
    )


def _build_simulation(sec: dict, shaft: Shaft, speed: float) -> Integrator:
    kwargs = dict(sec)
    if "probes" in kwargs:
        lo = -1e-12 if isinstance(shaft, Rotor) else 0.0
        for p in kwargs["probes"]:
            if not lo < p < shaft.length - lo:
                raise _err(
                    "simulation.probes", p, f"stations inside the shaft, in (0, {shaft.length:g}) m"
                )
        kwargs["probes"] = tuple(kwargs["probes"])
    for key in ("revolutions", "dtau", "output_dtau"):
        if key in sec:
            _need_speed(f"simulation.{key}", sec[key], speed)
    return Integrator(**kwargs)


def _mapping_stations(mapping: Mapping, length: float) -> tuple[float, ...]:
    """Positions (m, in ``[0, length]``) of every unbalance, load, contact and probe of a raw
    scenario mapping (single tables or arrays): the stations a general rotor is meshed at."""
    out = []
    for section in ("unbalance", "load", "contact"):
        body = mapping.get(section)
        for item in [body] if isinstance(body, Mapping) else body or []:
            if isinstance(item, Mapping):
                out.append(item.get("position"))
    sim = mapping.get("simulation")
    if isinstance(sim, Mapping) and isinstance(sim.get("probes"), list):
        out += sim["probes"]
    ok = [float(x) for x in out if isinstance(x, int | float) and not isinstance(x, bool)]
    return tuple(sorted({x for x in ok if 0 <= x <= length}))


def _build(spec: dict, mapping: Mapping | None = None) -> dict:
    """Build every object of a normalised spec; InputErrors become ScenarioErrors. ``mapping``
    (the raw scenario) gives a general rotor's stations for ``speed.critical_multiple``."""
    rotor = build_rotor(spec) if "section" in spec else None
    if rotor is not None:
        _check_general(spec)
    try:
        shaft = _build_shaft(spec["shaft"]) if rotor is None else None
        span = shaft if rotor is None else rotor
        stations = () if rotor is None else _mapping_stations(mapping or spec, rotor.length)
        speed, speed_spec = _resolve_speed(spec["speed"], span, stations)
        sec = spec.get("unbalance")
        unbalance = None if sec is None else _build_unbalance(sec, span, speed)
        sec = spec.get("load")
        load = None if sec is None else _build_load(sec, span)
        sec = spec.get("contact")
        contact = None if sec is None else _build_contact(sec, span, speed)
        sec = spec.get("damping")
        damping = ModalDamping() if sec is None else ModalDamping(_ratios(sec))
        sec = spec.get("simulation")
        simulation = None if sec is None else _build_simulation(sec, span, speed)
        initial = spec.get("initial", {}).get("state", _default("initial", "state"))
        sec = spec.get("thermal")
        thermal = None if sec is None else ThermalBow(**sec)
    except ScenarioError:
        raise
    except InputError as exc:
        raise ScenarioError(exc.field, exc.value, exc.allowed) from None
    meta = spec.get("meta", {})
    return dict(
        name=meta.get("name", ""),
        shaft=shaft,
        rotor=rotor,
        speed=speed,
        speed_spec=speed_spec,
        unbalance=unbalance,
        load=load,
        contact=contact,
        damping=damping,
        simulation=simulation,
        initial=initial,
        thermal=thermal,
    )


_GENERAL_SPEEDS = ("rad_per_s", "rpm", "hz", "critical_multiple")


def _check_general(spec: dict) -> None:
    """Keys that need the uniform shaft's scales are not allowed with a general rotor."""
    ((key, value),) = spec["speed"].items()
    if key not in _GENERAL_SPEEDS:
        raise _err(
            f"speed.{key}",
            value,
            "speed.rad_per_s, speed.rpm, speed.hz or speed.critical_multiple for a general "
            "rotor (the seed's dimensionless speed is defined for a uniform [shaft] only)",
        )
    for section in ("unbalance", "load", "contact"):
        for k, v in spec.get(section, {}).items():
            if k.endswith("_nd"):
                raise _err(
                    f"{section}.{k}",
                    v,
                    f"{section}.{k[:-3]} in SI units for a general rotor (the seed's "
                    "dimensionless scales belong to a uniform [shaft])",
                )
    if "damping" in spec:
        raise _err(
            "damping",
            spec["damping"],
            "no [damping] section for a general rotor (modal damping ratios belong to the "
            "continuous [shaft]; give bearing damping cyy ... czz)",
        )


def _ratios(sec: dict):
    if "ratio" not in sec:
        raise _err("damping.ratio", None, "a value (a number or a list per mode)")
    r = sec["ratio"]
    return tuple(r) if isinstance(r, list) else r


# ---- the Scenario ------------------------------------------------------------------------------
@dataclass(frozen=True)
class Scenario:
    """A validated scenario: rotor, resolved spin speed, forces, contact and integrator.

    Build it with :func:`load_scenario` or :func:`~rubrotor.scenario.scenario_from_dict`; its dict form
    (:func:`~rubrotor.scenario.scenario_to_dict`) is what was given, so ``with_changes`` keeps the input form
    (e.g. a dimensionless clearance stays dimensionless when the speed changes).

    Attributes
    ----------
    name : str
        ``meta.name`` (or the file stem, for files without one).
    shaft : Shaft or None
        The uniform continuous rotor (``[shaft]``), or None for a general rotor.
    speed : float
        Spin speed ``Omega`` (rad/s), resolved from ``speed_spec``.
    speed_spec : tuple
        ``(key, value)`` of the ``[speed]`` section as given, e.g. ``("critical_multiple", 1.5)``.
    unbalance : Unbalance or None
        Position resolved to m.
    load : RadialLoad or None
        Position resolved to m.
    contact : Contact or None
        All values in SI, position resolved to m.
    damping : ModalDamping
        Modal damping ratios (zero when the section is absent).
    simulation : Integrator or None
        Integrator settings.
    initial : {"rest", "steady"}
        ``[initial] state``: start at rest (default) or on the steady no-contact orbit.
    rotor : Rotor or None
        The general finite-element rotor (``[[section]]`` tables), or None for a ``[shaft]``.
    engine : rubrotor.scenario.dynamics.EngineSpec or None
        The general engine's contacts, stators, planes, gravity, speed profile and initial
        state (``rubrotor.scenario.dynamics``) when the scenario uses its keys or a general
        rotor; None for a scenario the seed's engine runs.
    thermal : rubrotor.rotors.forces.ThermalBow or None
        The ``[thermal]`` table: the thermal bow's time constant, bow per heat input, hot-spot
        lag and shape (``rubrotor thermal``, :mod:`rubrotor.studies.thermal`).
    model : rubrotor.scenario.kind.Kind
        What the scenario is (rotor kind, engine, formulation, general-engine features),
        decided once when the scenario is built. Verbs do not read it: they ask
        :meth:`rubrotor.modelling.Model.for_scenario`, which decides from it and builds.
    source : str
        TOML text the scenario was read from (provenance); not compared by ``==``.
    """

    name: str
    shaft: Shaft | None
    speed: float
    speed_spec: tuple
    unbalance: Unbalance | None = None
    load: RadialLoad | None = None
    contact: Contact | None = None
    damping: ModalDamping = field(default_factory=ModalDamping)
    simulation: Integrator | None = None
    initial: str = "rest"
    rotor: Rotor | None = None
    engine: EngineSpec | None = None
    thermal: ThermalBow | None = None
    source: str = field(default="", compare=False, repr=False)
    _spec: dict | None = field(default=None, compare=False, repr=False)
    model: Kind = field(init=False, compare=False, repr=False)
    _built: dict = field(init=False, compare=False, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "model", Kind.for_scenario(self))
        # rubrotor.modelling.Model.for_scenario keeps the Model it built here (once per scenario)
        object.__setattr__(self, "_built", {})

    def with_changes(self, **dotted) -> Scenario:
        """A new validated scenario with some keys changed.

        Parameters
        ----------
        **dotted
            ``"section.key": value`` pairs (pass them as ``**{"contact.clearance": 1e-3}``);
            ``"section[i].key"`` names the ``i``-th table of a ``[[section]]`` list
            (:mod:`rubrotor.scenario.keys`), ``"section.key"`` the only one.
            Setting one key of a group of alternatives removes the others
            (``"speed.critical_multiple"`` replaces ``speed.rad_per_s``); a value of ``None``
            removes the key; ``"section": None`` removes a whole optional section.

        Returns
        -------
        Scenario
            Re-validated from the edited dict form; ``source`` is empty (the text no longer
            describes it).

        Examples
        --------
        >>> s = scenario_from_dict({"shaft": {"length": 0.4, "diameter": 0.1,
        ...     "youngs_modulus": 71e9, "density": 2660, "shear_modulus": 26.2e9},
        ...     "speed": {"rad_per_s": 1000.0}})
        >>> s.with_changes(**{"speed.hz": 10.0}).speed_spec
        ('hz', 10.0)
        """
        from rubrotor.scenario.keys import resolve_key

        spec = scenario_to_dict(self)
        removed = {}  # "section.key" dropped as an alternative -> (the key that dropped it, value)
        for dotted_key, value in dotted.items():
            ref = resolve_key(spec, dotted_key, value)
            section, key = ref.section, ref.name
            if not key:
                if value is not None:
                    raise _err(dotted_key, value, "None (to remove the section) or 'section.key'")
                spec.pop(section, None)
                continue
            sec = spec.setdefault(section, {})
            if ref.index is not None:
                sec = sec[ref.index]
            if value is None:
                sec.pop(key, None)
                continue
            for group, _required in ALTERNATIVES.get(section, []):
                if key in group:
                    for other in group:
                        if other != key and other in sec:
                            removed[f"{section}.{other}"] = (dotted_key, sec.pop(other))
            sec[key] = value
        try:
            return scenario_from_dict(spec)
        except ScenarioError as exc:
            if exc.field not in removed:
                raise
            key, old = removed[exc.field]
            raise _err(
                key, dotted[key], f"a change this scenario can take: setting it removes "
                f"{exc.field} = {old!r}, which it needs ({exc.allowed})"
            ) from None  # fmt: skip

    @classmethod
    def from_ross(cls, rotor, speed: float = 0.0, name: str | None = None, speeds=None) -> Scenario:
        """The scenario of a ROSS rotor: a ``ross.Rotor`` (ROSS installed) or the file its
        ``Rotor.save`` wrote (read without ROSS); see :mod:`rubrotor.scenario.ross`.

        Parameters
        ----------
        rotor : ross.Rotor or str or Path
            The rotor, or its saved ``.toml``/``.json`` file.
        speed : float
            Spin speed (rad/s) of the scenario's ``[speed]`` table.
        name : str, optional
            ``[meta] name``.
        speeds : array_like, optional
            With a ROSS object: speeds (rad/s) at which to read its speed tables from ROSS
            (ROSS 2.3's smoothing splines, see :func:`rubrotor.rotors.ross.from_ross`).

        Returns
        -------
        Scenario
        """
        from rubrotor.scenario.ross import ross_mapping

        return scenario_from_dict(ross_mapping(rotor, speed=speed, name=name, speeds=speeds))

    def save(self, path, header: str = "") -> Path:
        """Write this scenario's tables as a TOML file (atomically); :func:`load_scenario` of
        it gives this scenario back (numbers written to the last bit).

        Parameters
        ----------
        path : str or Path
            The file to write.
        header : str
            Comment lines put first.

        Returns
        -------
        Path
        """
        from rubrotor.scenario.write import write_scenario

        return write_scenario(scenario_to_dict(self), path, header)

    @property
    def stations(self) -> tuple[float, ...]:
        """Axial positions (m) of the unbalances, loads, contacts and probes, in that order,
        each once: every ``[[unbalance]]``, ``[[load]]`` and ``[[contact]]`` table counts (a
        general rotor is meshed with a node at each, as the general engine meshes it)."""
        parts = (self.unbalance, self.load, self.contact)
        out = [p.position for p in parts if p is not None]
        if self.engine is not None:
            out += list(self.engine.positions)
        probes = self.simulation.probes if self.simulation is not None else ()
        return tuple(dict.fromkeys(float(x) for x in out + list(probes)))

    @property
    def unbalances(self) -> tuple[Unbalance, ...]:
        """Every unbalance plane (kg m, m, rad): the ``[[unbalance]]`` tables, or the single
        ``[unbalance]``; empty when there is none."""
        if self.engine is not None:
            return tuple(self.engine.unbalances)
        return () if self.unbalance is None else (self.unbalance,)

    @property
    def contacts(self) -> tuple[Contact, ...]:
        """Every contact (SI, position in m): the ``[[contact]]`` tables, or the single
        ``[contact]``; empty when there is none."""
        if self.engine is not None:
            return tuple(s.contact for s in self.engine.stations)
        return () if self.contact is None else (self.contact,)

    @property
    def loads(self) -> tuple[RadialLoad, ...]:
        """Every constant point load (N, m): the ``[[load]]`` tables, or the single ``[load]``."""
        if self.engine is not None:
            return tuple(self.engine.loads)
        return () if self.load is None else (self.load,)

    @property
    def gravity(self) -> tuple[float, float] | None:
        """``(g_y, g_z)`` (m/s^2) of the ``[gravity]`` table, or None when the scenario has none."""
        if self.engine is None or self._spec is None or "gravity" not in self._spec:
            return None
        return tuple(float(g) for g in self.engine.gravity)

    def require_shaft(self, what: str) -> Shaft:
        """The uniform shaft, or a ScenarioError saying ``what`` needs one.

        Parameters
        ----------
        what : str
            The verb that needs the continuous shaft, e.g. ``"time simulation"``.
        """
        if self.shaft is None:
            raise ScenarioError(
                "section",
                "[[section]] tables",
                f"a [shaft] scenario: {what} of a general rotor is not available yet "
                "(its linear model: Rotor.linear_system(); modes and Campbell diagrams of "
                "general rotors come from the linear analyses)",
            )
        return self.shaft

    def require_seed_engine(self, what: str) -> Shaft:
        """The uniform shaft of a scenario the seed shaft's engine runs, or a ScenarioError
        naming the key that needs the general engine (``rubrotor.scenario.kind.Kind.require_shaft_engine``).

        Parameters
        ----------
        what : str
            The verb, e.g. ``"a parameter sweep"``.
        """
        self.model.require_shaft_engine(what)
        return self.shaft

    def dimensionless(self) -> dict:
        """The seed's dimensionless groups of this scenario (seed eqs. 3-5, 10-16).

        Returns
        -------
        dict of str to float
            ``"r"`` slenderness ``r0/L``; ``"delta"`` shear parameter ``E/(kappa G)``; ``"c"``
            speed parameter ``Omega L^2 sqrt(rho A/(E I))``; ``"modes"``. With a contact:
            ``"a_contact"`` ``a/L``, ``"g"`` clearance ``g/L``, ``"mu"`` friction, and
            ``"k_h"`` ``k_h L^3.5/(E I)`` and ``"b_h"`` ``b_h L Omega`` (Hertz) or
            ``"k_linear"`` ``k L^3/(E I)`` (linear). With an unbalance: ``"a_unbalance"``
            and ``"unbalance_force"`` ``m e Omega^2 L^2/(E I)``. With a load: ``"a_load"``,
            ``"load_y"``, ``"load_z"`` ``F L^2/(E I)``. With a step: ``"dtau"`` ``Omega dt``.
        """
        s = self.require_shaft("the seed's dimensionless form")
        nd = Dimensionless(s, self.speed)
        out = {
            "r": s.slenderness,
            "delta": s.shear_parameter,
            "c": nd.speed_parameter,
            "modes": s.modes,
        }
        if self.contact is not None:
            c = self.contact
            out["a_contact"] = nd.length_nd(c.position)
            out["g"] = nd.clearance_nd(c.clearance)
            out["mu"] = c.friction
            from rubrotor.forces.contact import law_of

            out.update(law_of(c).dimensionless(nd, c))
        if self.unbalance is not None:
            out["a_unbalance"] = nd.length_nd(self.unbalance.position)
            out["unbalance_force"] = nd.unbalance_nd(self.unbalance.magnitude)
        if self.load is not None:
            out["a_load"] = nd.length_nd(self.load.position)
            out["load_y"] = nd.force_nd(self.load.force_y)
            out["load_z"] = nd.force_nd(self.load.force_z)
        if self.simulation is not None and self.speed > 0:
            step = self.simulation.step_seconds(self.speed)
            if step is not None:
                out["dtau"] = nd.tau(step)
        return out


def scenario_from_dict(mapping: Mapping, source_text: str = "") -> Scenario:
    """Validate a scenario given as a nested mapping (the parsed TOML) and build it.

    Parameters
    ----------
    mapping : Mapping
        ``{"shaft": {...}, "speed": {...}, ...}`` following the schema of this module.
    source_text : str
        The text it came from, kept as ``Scenario.source`` for provenance.

    Returns
    -------
    Scenario

    Raises
    ------
    ScenarioError
        Naming the offending key, its value and what is allowed.
    """
    base, extras = split_engine_keys(mapping)
    spec = _normalise(base)
    parts = _build(spec, mapping)
    engine, full = engine_spec_or_none(mapping, extras, parts, Builders(_position, _build_contact))
    spec = full if extras else spec
    scenario = Scenario(**parts, engine=engine, source=source_text, _spec=spec)
    plausible.check(scenario)  # across keys, before anything is meshed or solved
    return scenario


def scenario_to_dict(scenario: Scenario, resolved: bool = False) -> dict:
    """The dict form of a scenario, such that ``scenario_from_dict`` rebuilds it.

    Parameters
    ----------
    scenario : Scenario
        The scenario.
    resolved : bool
        False (default): the keys as given (SI or dimensionless, exact round trip).
        True: every value resolved to SI (``rad_per_s``, ``clearance``, ``damping`` ...), equal
        after a round trip up to rounding.

    Returns
    -------
    dict
        A fresh nested dict (safe to edit).
    """
    if not resolved and scenario._spec is not None:
        return copy.deepcopy(scenario._spec)
    return _resolved_dict(scenario)


def _resolved_dict(sc: Scenario) -> dict:
    if sc.rotor is not None:
        out = {**rotor_to_dict(sc.rotor), "speed": {"rad_per_s": sc.speed}}
        return _resolved_parts(sc, out)
    s = sc.shaft
    shaft = {
        "length": s.length,
        "diameter": s.diameter,
        "bore_diameter": s.bore_diameter,
        "youngs_modulus": s.youngs_modulus,
        "density": s.density,
        "shear_coefficient": s.shear_coefficient,
        "theory": s.theory,
        "gyroscopic": s.gyroscopic,
        "modes": s.modes,
        "formulation": s.formulation,
    }
    if s.shear_modulus is not None:
        shaft["shear_modulus"] = s.shear_modulus
    else:
        shaft["poisson_ratio"] = s.poisson_ratio
    out: dict = {"shaft": shaft, "speed": {"rad_per_s": sc.speed}}
    out = _resolved_parts(sc, out)
    out["damping"] = {"ratio": list(sc.damping.ratios)}
    return out


def _resolved_parts(sc: Scenario, out: dict) -> dict:
    """Add meta, unbalance, load, contact and simulation (resolved to SI) to ``out``."""
    if sc.name:
        out["meta"] = {"name": sc.name}
    if sc.unbalance is not None:
        u = sc.unbalance
        out["unbalance"] = {
            "magnitude": u.magnitude,
            "position": u.position,
            "phase_deg": math.degrees(u.phase),
        }
    if sc.load is not None:
        ld = sc.load
        out["load"] = {"force_y": ld.force_y, "force_z": ld.force_z, "position": ld.position}
    if sc.contact is not None:
        c = dataclasses.asdict(sc.contact)
        out["contact"] = {k: v for k, v in c.items() if v is not None}
    out["initial"] = {"state": sc.initial}
    if sc._spec and "checks" in sc._spec:  # the plausibility checks a study switched off
        out["checks"] = copy.deepcopy(sc._spec["checks"])
    if sc.thermal is not None:
        out["thermal"] = dataclasses.asdict(sc.thermal)
    if sc.simulation is not None:
        sim = dataclasses.asdict(sc.simulation)
        sim["probes"] = list(sim["probes"])
        out["simulation"] = {k: v for k, v in sim.items() if v is not None}
    return out


def shipped_scenarios() -> list[dict]:
    """The scenario files shipped with rubrotor: name, description and path.

    Returns
    -------
    list of dict
        ``{"name", "description", "path"}`` sorted by file name.
    """
    from importlib import resources

    folder = resources.files("rubrotor") / "scenarios"
    out = []
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        if not entry.name.endswith(".toml"):
            continue
        meta = tomllib.loads(entry.read_text(encoding="utf-8")).get("meta", {})
        description = " ".join(meta.get("description", "").split())
        out.append({"name": meta.get("name", entry.name[:-5]), "description": description,
                    "path": str(entry)})  # fmt: skip
    return out


def find_scenario(path) -> Path:
    """The scenario file a path or a shipped scenario's name means.

    A file that exists (relative to the working folder or absolute) is taken as it is, so a
    local file named like a shipped scenario takes precedence. Otherwise a bare name, with or
    without ``.toml`` (``"seed_case1"``, ``"seed_case1.toml"``), is looked up among the
    scenarios shipped with rubrotor (``rubrotor scenarios`` lists them).

    Parameters
    ----------
    path : str or os.PathLike
        A file path or the name of a shipped scenario.

    Returns
    -------
    pathlib.Path
        The file to read.

    Raises
    ------
    ScenarioError
        Field ``"scenario file"``: neither a file nor a shipped scenario's name; the message
        points to ``rubrotor scenarios``.
    """
    p = Path(path)
    if p.exists() or p.parent != Path("."):
        return p
    stem = p.name[:-5] if p.name.endswith(".toml") else p.name
    for item in shipped_scenarios():
        if Path(item["path"]).stem == stem:
            return Path(item["path"])
    raise _err(
        "scenario file", str(path),
        "an existing TOML file or the name of a shipped scenario (`rubrotor scenarios` lists "
        "them)",
    )  # fmt: skip


def load_scenario(path) -> Scenario:
    """Read and validate a scenario TOML file, or a shipped scenario given by name.

    Parameters
    ----------
    path : str or os.PathLike
        The file, or the name of a shipped scenario (``"seed_case1.toml"`` or ``"seed_case1"``,
        looked up when no such file exists in the working folder: :func:`rubrotor.scenario.load.find_scenario`).
        ``meta.name`` defaults to the file stem.

    Returns
    -------
    Scenario

    Raises
    ------
    ScenarioError
        The file cannot be read, is not valid TOML (the parser's message and the file name), or
        a key is invalid (the message starts with the file name and names the key).
    """
    from rubrotor.errors import path_argument

    p = find_scenario(path_argument("path", path, "a scenario TOML file path (str or "
                                    "os.PathLike) or a shipped scenario's name"))
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        err = _err("scenario file", str(p), "a readable UTF-8 TOML file")
        reason = exc.strerror if isinstance(exc, OSError) else None
        if isinstance(exc, UnicodeDecodeError):
            reason = f"not UTF-8 text (byte {exc.object[exc.start]:#04x} at offset {exc.start})"
        err.args = (f"{p}: cannot read scenario file: {reason or exc}",)
        raise err from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        err = _err("scenario file", str(p), "valid TOML")
        err.args = (f"{p}: invalid TOML: {exc}",)
        raise err from None
    try:
        scenario = scenario_from_dict(data, source_text=text)
    except ScenarioError as exc:
        exc.args = (f"{p}: {exc.args[0]}",)
        raise
    if not scenario.name:
        spec = scenario_to_dict(scenario)
        spec.setdefault("meta", {})["name"] = p.stem
        scenario = dataclasses.replace(scenario, name=p.stem, _spec=spec)
    return scenario


def as_scenario(obj, name: str = "scenario") -> Scenario:
    """The scenario a public verb was given: a :class:`Scenario`, or a path to a scenario file.

    Parameters
    ----------
    obj : Scenario or str or os.PathLike
        A loaded scenario, or the path of a TOML scenario file (read with :func:`load_scenario`).
    name : str
        The argument's name, used in the error message.

    Returns
    -------
    Scenario

    Raises
    ------
    InputError
        ``obj`` is neither (e.g. None); a path that cannot be read raises :class:`ScenarioError`.
    """
    if isinstance(obj, Scenario):
        return obj
    if isinstance(obj, str | os.PathLike):
        return load_scenario(obj)
    raise InputError(
        name,
        obj,
        "a Scenario (rubrotor.load_scenario) or the path of a scenario TOML file",
    )
