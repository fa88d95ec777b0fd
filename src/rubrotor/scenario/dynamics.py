"""Scenario keys of the general engine (:mod:`rubrotor.engine`): several contacts, flexible and
offset stators, gravity, several unbalance planes and loads, run-up and coast-down, restarts.

:func:`split_engine_keys` takes these keys out of a scenario mapping before
:mod:`rubrotor.scenario` validates the rest (so a seed scenario without them keeps the old
engine), and :func:`build_engine` validates them into a frozen :class:`EngineSpec`. Every
bad value raises :class:`~rubrotor.errors.ScenarioError` naming the key, the value and what is
allowed. The new keys, their kinds, units and ranges are listed in :data:`ENGINE_KEYS`::

    [[contact]]   the keys of [contact] plus offset_y, offset_z (m, stator centre);
                  stator_mass (kg), stator_stiffness (N/m), stator_damping (N s/m), each also
                  as _y / _z for an anisotropic stator (a flexible stator needs mass and
                  stiffness); a single [contact] table stays valid
    [[unbalance]] position (m), magnitude (kg m), phase (rad) | phase_deg (deg)
    [[load]]      position (m), force_y, force_z (N)
    [gravity]     y, z (m/s^2) on the rotor's shaft and disk masses
    [speed]       profile = "constant" (default) | "linear" with from, to (rad/s) over the run
                  | "table" with times (s) and speeds (rad/s), linear between rows; step
                  (rad/s, largest speed change between re-diagonalisations)
                  | "free": the speed is a state from rad_per_s (rpm, hz), with drive_torque
                  (N m) or drive_torques (N m) against drive_speeds (rad/s), and drag (N m s)
                  (:mod:`rubrotor.engine.spin`); then [[contact]] ring_inertia (kg m^2),
                  ring_radius (m), ring_drag (N m s) make a stator a touchdown ring and
                  [[bearing]] fail_time (s) switches a bearing off
    [initial]     state = "rest" | "steady" | "static" | "file" with path (a results file of
                  the general engine; the run continues from its final state) | "given" with
                  positions (m) and any of v, w (m), v_dot, w_dot (m/s), one per position: the
                  rotor starts in the least-strain-energy shape through those deflections and
                  with that velocity shape (a drop, a kick, a whirl to start from); or with
                  modes (1 = lowest undamped mode), amplitudes (m) and modal_velocities (m/s),
                  each the mode's deflection (velocity) at its largest point
    [simulation]  besides today's keys: modes (retained count), cutoff (rad/s), residual (bool)
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import NamedTuple

from rubrotor.engine.parts import RubStation, Stator
from rubrotor.errors import InputError, ScenarioError
from rubrotor.rotors.forces import RadialLoad, Unbalance
from rubrotor.scenario.schema import (
    ALTERNATIVES,
    SCHEMA,
    Key,
    check_value,
    key_row,
    unknown_key_text,
)

__all__ = ["ENGINE_KEYS", "EngineSpec", "split_engine_keys", "build_engine", "needs_engine"]

_ENGINE_NAMES = (
    "contact.offset_y", "contact.offset_z",
    *(f"contact.stator_{q}{a}" for q in ("mass", "stiffness", "damping") for a in ("", "_y", "_z")),
    "unbalance.position", "unbalance.magnitude", "unbalance.phase", "unbalance.phase_deg",
    "load.position", "load.force_y", "load.force_z", "gravity.y", "gravity.z",
    "speed.profile", "speed.from", "speed.to", "speed.step", "speed.times", "speed.speeds",
    "contact.ring_inertia", "contact.ring_radius", "contact.ring_drag",
    "speed.drive_torque", "speed.drive_torques", "speed.drive_speeds", "speed.drag",
    "initial.state", "initial.path", "initial.positions", "initial.v", "initial.w",
    "initial.v_dot", "initial.w_dot", "initial.modes", "initial.amplitudes",
    "initial.modal_velocities",
    "simulation.modes", "simulation.cutoff", "simulation.residual",
)  # fmt: skip
ENGINE_KEYS: dict[str, Key] = {n: key_row(*n.split(".")) for n in _ENGINE_NAMES}
"""Every key this module reads, as its row of the scenario schema (:mod:`rubrotor.scenario.schema`:
kind, unit, range, choices, description); the rows are the only definition."""


class Builders(NamedTuple):
    """The scenario module's builders this module needs (passed in, so that neither module
    imports the other): ``position(table, name, span)`` resolves a station (m);
    ``build_contact(table, span, speed)`` makes a :class:`~rubrotor.rotors.forces.Contact`."""

    position: Callable
    build_contact: Callable


PROFILES = ("constant", "linear", "table", "free")
ENGINE_INITIAL = ("static", "file", "given")
_GIVEN = ("v", "w", "v_dot", "w_dot")
_MODAL = ("modes", "amplitudes", "modal_velocities")
_CONTACT_NEW = tuple(k.split(".", 1)[1] for k in ENGINE_KEYS if k.startswith("contact."))
_SPEED_NEW = ("profile", "from", "to", "step", "times", "speeds")
_FREE_KEYS = ("drive_torque", "drive_torques", "drive_speeds", "drag")
_SIM_NEW = ("modes", "cutoff", "residual")


@dataclass(frozen=True)
class EngineSpec:
    """What the general engine simulates besides the rotor and the integrator (SI units).

    Attributes
    ----------
    stations : tuple of RubStation
        Contact stations (positions m, stator offsets m, flexible stators).
    unbalances : tuple of Unbalance
        Unbalance planes (kg m, m, rad).
    loads : tuple of RadialLoad
        Constant point loads (N, m).
    gravity : tuple of float
        ``(g_y, g_z)`` (m/s^2).
    speed_end : float or None
        End speed (rad/s) of a linear run-up or coast-down from ``Scenario.speed``.
    speed_step : float or None
        Largest speed change (rad/s) between re-diagonalisations (engine default 1/200 of the
        range).
    initial : str
        ``"rest"``, ``"steady"``, ``"static"`` or ``"file"``.
    initial_path : str or None
        Results file to restart from (``initial == "file"``).
    modes : int or None
        Retained rotor modes (all by default).
    cutoff : float or None
        Retain the modes with ``|lambda| <= cutoff`` (rad/s).
    residual : bool
        Static correction of the dropped modes at the contact stations.
    speed_table : tuple of (float, float) or None
        ``[speed] profile = "table"``: rows of time (s) and speed (rad/s).
    initial_given : tuple or None
        ``initial == "given"``: ``(positions, v, w, v_dot, w_dot)``, tuples of equal length
        (m, m, m, m/s, m/s; absent components 0).
    initial_modes : tuple or None
        ``initial == "given"`` by modes: ``(modes, amplitudes, modal_velocities)`` (1-based
        undamped mode numbers; m and m/s at each mode's largest deflection).
    """

    stations: tuple = ()
    unbalances: tuple = ()
    loads: tuple = ()
    gravity: tuple = (0.0, 0.0)
    speed_end: float | None = None
    speed_step: float | None = None
    initial: str = "rest"
    initial_path: str | None = None
    modes: int | None = None
    cutoff: float | None = None
    residual: bool = True
    speed_table: tuple | None = None
    initial_given: tuple | None = None
    initial_modes: tuple | None = None
    free_spin: object = None
    rings: tuple | None = None

    @property
    def positions(self) -> tuple[float, ...]:
        """Axial positions (m) of contacts, unbalances, loads and given start deflections
        (mesh nodes of a general rotor)."""
        parts = [s.contact for s in self.stations] + list(self.unbalances) + list(self.loads)
        given = self.initial_given[0] if self.initial_given else ()
        return tuple(float(p.position) for p in parts) + tuple(given)


def _err(name: str, value, allowed: str) -> ScenarioError:
    return ScenarioError(name, value, allowed)


def _value(name: str, value, key: str | None = None):
    """Check one key against its schema row (``key``: its entry in ENGINE_KEYS, default
    ``name``); errors name ``name`` (e.g. ``contact[2].friction``)."""
    check_value(name, value, ENGINE_KEYS[key or name])
    return value


def _table_list(mapping: Mapping, section: str) -> list[dict] | None:
    """``[[section]]`` entries as dicts (a single table as a one-item list), or None."""
    body = mapping.get(section)
    if body is None:
        return None
    items = [body] if isinstance(body, Mapping) else body
    if not isinstance(items, list) or not items or not all(isinstance(b, Mapping) for b in items):
        raise _err(section, body, f"a [{section}] table or a non-empty array of [[{section}]]")
    return [dict(b) for b in items]


def needs_engine(mapping: Mapping) -> bool:
    """True when a scenario mapping uses a key only the general engine supports."""
    _, extras = split_engine_keys(mapping)
    return bool(extras)


def split_engine_keys(mapping: Mapping) -> tuple[dict, dict]:
    """Take the general-engine keys out of a scenario mapping.

    Parameters
    ----------
    mapping : Mapping
        The parsed TOML.

    Returns
    -------
    base : dict
        What :mod:`rubrotor.scenario` validates: a single ``[contact]`` without new keys,
        ``[speed] rad_per_s = from`` for a linear profile, ``[initial] state = "rest"`` for the
        engine-only states.
    extras : dict
        The engine keys by section (empty when the scenario needs none of them).
    """
    if not isinstance(mapping, Mapping):
        return mapping, {}
    base = {k: (dict(v) if isinstance(v, Mapping) else v) for k, v in mapping.items()}
    extras: dict = {}
    contacts = _table_list(mapping, "contact")
    if contacts is not None:
        base["contact"] = contacts[0]
        if len(contacts) > 1 or any(k in c for c in contacts for k in _CONTACT_NEW):
            extras["contact"] = contacts
            del base["contact"]  # Scenario.engine.stations holds them all
    for section in ("unbalance", "load"):
        if isinstance(mapping.get(section), list):
            extras[section] = _table_list(mapping, section)
            base.pop(section)
    if "gravity" in base:
        extras["gravity"] = base.pop("gravity")
    _split_speed(base, extras)
    ini = base.get("initial")
    engine_ini = ("path", "positions", *_GIVEN, *_MODAL)
    if isinstance(ini, Mapping) and (ini.get("state") in ENGINE_INITIAL
                                     or any(k in ini for k in engine_ini)):  # fmt: skip
        extras["initial"] = dict(ini)
        base["initial"] = {"state": "rest"}
    sim = base.get("simulation")
    if isinstance(sim, Mapping) and any(k in sim for k in _SIM_NEW):
        extras["simulation"] = {k: sim[k] for k in _SIM_NEW if k in sim}
        base["simulation"] = {k: v for k, v in sim.items() if k not in _SIM_NEW}
    return base, extras


def _split_speed(base: dict, extras: dict) -> None:
    sp = base.get("speed")
    if not isinstance(sp, Mapping):
        return
    if not any(k in sp for k in _SPEED_NEW + _FREE_KEYS):
        return
    profile = _value("speed.profile", sp.get("profile", "constant"))
    if profile not in PROFILES:
        raise _err("speed.profile", profile, '"constant", "linear", "table" or "free"')
    if profile == "free" or any(k in sp for k in _FREE_KEYS):
        _split_free(sp, profile, base, extras)
        return
    rest = {k: v for k, v in sp.items() if k not in _SPEED_NEW}
    owners = {"from": "linear", "to": "linear", "step": "linear or table", "times": "table",
              "speeds": "table"}  # fmt: skip
    for k, owner in owners.items():
        if k in sp and profile not in owner.split(" or "):
            allowed = " or ".join(f'"{o}"' for o in owner.split(" or "))
            raise _err(f"speed.{k}", sp[k], f"to be given only with speed.profile = {allowed}")
    if profile == "constant":
        base["speed"] = rest
        return
    if profile == "table":
        _split_table(sp, rest, base, extras)
        return
    if "step" in sp:
        _value("speed.step", sp["step"])
    for k in ("from", "to"):
        if k not in sp:
            raise _err(f"speed.{k}", None, 'a value (rad/s) with speed.profile = "linear"')
        _value(f"speed.{k}", sp[k])
    if rest:
        raise _err(
            "speed." + ", speed.".join(rest),
            tuple(rest.values()),
            'no other speed key with speed.profile = "linear" (from and to give the speeds)',
        )
    base["speed"] = {"rad_per_s": sp["from"]}
    extras["speed"] = {k: sp[k] for k in _SPEED_NEW if k in sp}


def _split_free(sp: Mapping, profile: str, base: dict, extras: dict) -> None:
    """``[speed] profile = "free"``: the start speed stays in ``[speed]``; the drive and drag
    keys (:data:`_FREE_KEYS`) go to the engine."""
    for k in _FREE_KEYS:
        if k in sp and profile != "free":
            raise _err(f"speed.{k}", sp[k], 'to be given only with speed.profile = "free"')
    for k in _SPEED_NEW[1:]:
        if k in sp:
            raise _err(f"speed.{k}", sp[k], 'no profile key with speed.profile = "free" (give '
                       "rad_per_s, rpm or hz for the start speed)")  # fmt: skip
    free = {k: _value(f"speed.{k}", sp[k]) for k in _FREE_KEYS if k in sp}
    if ("drive_torques" in free) != ("drive_speeds" in free) or (
        "drive_torques" in free and "drive_torque" in free
    ):
        raise _err("speed.drive_torques / speed.drive_speeds", tuple(free.values()),
                   "both lists together (equal lengths >= 2), or drive_torque alone")  # fmt: skip
    base["speed"] = {k: v for k, v in sp.items() if k not in _SPEED_NEW + _FREE_KEYS}
    extras["speed"] = {"free": free}


def _split_table(sp: Mapping, rest: dict, base: dict, extras: dict) -> None:
    """``[speed] profile = "table"``: ``times`` (s) and ``speeds`` (rad/s), equal lengths >= 2."""
    for k in ("times", "speeds"):
        if k not in sp:
            raise _err(f"speed.{k}", None, 'a list of numbers with speed.profile = "table"')
        _value(f"speed.{k}", sp[k])
    if "step" in sp:
        _value("speed.step", sp["step"])
    times, speeds = list(sp["times"]), list(sp["speeds"])
    if len(times) < 2 or len(times) != len(speeds):
        raise _err("speed.times / speed.speeds", (times, speeds), "two lists of equal length >= 2")
    if rest:
        raise _err("speed." + ", speed.".join(rest), tuple(rest.values()),
                   'no other speed key with speed.profile = "table"')  # fmt: skip
    base["speed"] = {"rad_per_s": speeds[0]}
    extras["speed"] = {"table": tuple(zip(map(float, times), map(float, speeds), strict=True)),
                       **({"step": sp["step"]} if "step" in sp else {})}  # fmt: skip


def _renamed(exc: InputError, section: str, index: int) -> ScenarioError:
    name = exc.field.replace(f"{section}.", f"{section}[{index + 1}].", 1)
    return ScenarioError(name, exc.value, exc.allowed)


def _stator(c: dict, i: int) -> Stator | None:
    vals = {}
    for q in ("mass", "stiffness", "damping"):
        for a in ("y", "z"):
            for key in (f"stator_{q}_{a}", f"stator_{q}"):
                if key in c:
                    vals[f"{q}_{a}"] = _value(f"contact[{i + 1}].{key}", c[key], f"contact.{key}")
                    break
        if f"stator_{q}" in c and any(f"stator_{q}_{a}" in c for a in "yz"):
            raise _err(
                f"contact[{i + 1}].stator_{q}", c[f"stator_{q}"], f"stator_{q} or its _y/_z forms"
            )
    if not vals:
        return None
    for q in ("mass", "stiffness"):
        for a in ("y", "z"):
            if f"{q}_{a}" not in vals:
                raise _err(
                    f"contact[{i + 1}].stator_{q}_{a}",
                    None,
                    f"a value: a flexible stator needs stator_{q} (or _y and _z)",
                )
    return Stator(**vals)


def _contacts(items: list[dict], span, speed: float, builders: Builders) -> tuple:

    out = []
    for i, c in enumerate(items):
        base = {}
        try:
            for key, val in c.items():
                name = f"contact.{key}"
                if key in _CONTACT_NEW:
                    continue
                if key.endswith("_nd") and not hasattr(span, "slenderness"):
                    raise _err(name, val, f"contact.{key[:-3]} in SI units for a general rotor")
                if key not in SCHEMA["contact"]:
                    raise _err(name, val, unknown_key_text(key, SCHEMA["contact"], "[[contact]]"))
                base[key] = check_value(name, val, key_row("contact", key))
            for group, required in ALTERNATIVES["contact"]:
                given = [k for k in group if k in base]
                if len(given) > 1 or (required and not given):
                    raise _err("contact." + " / contact.".join(group), None, "exactly one")
            if base.get("radius") is None:
                if not hasattr(span, "slenderness"):
                    raise _err("contact.radius", None, "the rubbing radius (m) on a general rotor")
                base["radius"] = span.diameter / 2  # the uniform shaft's radius
            contact = builders.build_contact(base, span, speed)
            off = [_value(f"contact.offset_{a}", c.get(f"offset_{a}", 0.0)) for a in "yz"]
        except InputError as exc:
            raise _renamed(exc, "contact", i) from None
        out.append(RubStation(contact, off[0], off[1], _stator(c, i)))
    return tuple(out)


def _planes(items: list[dict], span, builders: Builders) -> tuple:

    out = []
    for i, u in enumerate(items):
        try:
            for key, val in u.items():
                if f"unbalance.{key}" not in ENGINE_KEYS:
                    raise _err(f"unbalance.{key}", val, "position, magnitude, phase or phase_deg")
                _value(f"unbalance.{key}", val)
            if "phase" in u and "phase_deg" in u:
                raise _err("unbalance.phase", (u["phase"], u["phase_deg"]), "phase or phase_deg")
            if "magnitude" not in u:
                raise _err("unbalance.magnitude", None, "a value (kg m)")
            phase = u.get("phase", math.radians(u.get("phase_deg", 0.0)))
            out.append(Unbalance(u["magnitude"], builders.position(u, "unbalance", span), phase))
        except InputError as exc:
            raise _renamed(exc, "unbalance", i) from None
    return tuple(out)


def _loads(items: list[dict], span, builders: Builders) -> tuple:

    out = []
    for i, ld in enumerate(items):
        try:
            for key, val in ld.items():
                if f"load.{key}" not in ENGINE_KEYS:
                    raise _err(f"load.{key}", val, "position, force_y or force_z")
                _value(f"load.{key}", val)
            pos = builders.position(ld, "load", span)
            out.append(RadialLoad(ld.get("force_y", 0.0), ld.get("force_z", 0.0), pos))
        except InputError as exc:
            raise _renamed(exc, "load", i) from None
    return tuple(out)


def _gravity(g) -> tuple[float, float]:
    if not isinstance(g, Mapping):
        raise _err("gravity", g, "a table with y and z (m/s^2)")
    for key, val in g.items():
        if key not in ("y", "z"):
            raise _err(f"gravity.{key}", val, unknown_key_text(key, ("y", "z"), "[gravity]"))
    return tuple(float(_value(f"gravity.{a}", g.get(a, 0.0))) for a in "yz")


def _modal(ini: dict) -> tuple:
    """``[initial] state = "given"`` by modes: mode numbers, amplitudes, modal velocities."""
    modes = _value("initial.modes", ini["modes"])
    if not modes or any(int(m) != m for m in modes) or len(set(modes)) != len(modes):
        raise _err("initial.modes", modes, "a non-empty list of distinct mode numbers >= 1")
    if "amplitudes" not in ini and "modal_velocities" not in ini:
        raise _err("initial.amplitudes", None, "amplitudes (m) or modal_velocities (m/s)")
    out = [tuple(int(m) for m in modes)]
    for key in _MODAL[1:]:
        vals = _value(f"initial.{key}", ini.get(key, [0.0] * len(modes)))
        if len(vals) != len(modes):
            raise _err(f"initial.{key}", vals, f"{len(modes)} values, one per initial.modes")
        out.append(tuple(float(v) for v in vals))
    return tuple(out)


def _given(ini: dict) -> tuple:
    """``[initial] state = "given"``: positions and equally long v, w, v_dot, w_dot lists."""
    if "positions" not in ini:
        raise _err("initial.positions", None, 'a list of stations (m) with initial.state = "given"')
    pos = _value("initial.positions", ini["positions"])
    if not pos or len(set(pos)) != len(pos):
        raise _err("initial.positions", pos, "a non-empty list of distinct stations (m)")
    if not any(k in ini for k in _GIVEN):
        raise _err("initial.v", None, 'at least one of initial.v, w, v_dot, w_dot with "given"')
    out = [tuple(float(p) for p in pos)]
    for key in _GIVEN:
        vals = _value(f"initial.{key}", ini.get(key, [0.0] * len(pos)))
        if len(vals) != len(pos):
            raise _err(f"initial.{key}", vals, f"{len(pos)} values, one per initial.positions")
        out.append(tuple(float(v) for v in vals))
    return tuple(out)


def _initial(ini: dict) -> tuple[str, str | None]:
    for key in ini:
        if key not in ("state", "path", "positions", *_GIVEN, *_MODAL):
            allowed = ("state", "path", "positions", *_GIVEN, *_MODAL)
            raise _err(f"initial.{key}", ini[key], unknown_key_text(key, allowed, "[initial]"))
    state = _value("initial.state", ini.get("state", "rest"))
    allowed = ("rest", "steady", *ENGINE_INITIAL)
    if state not in allowed:
        raise _err("initial.state", state, " or ".join(f'"{s}"' for s in allowed))
    if state != "given":
        for key in ("positions", *_GIVEN, *_MODAL):
            if key in ini:
                raise _err(
                    f"initial.{key}", ini[key], 'to be given only with initial.state = "given"'
                )
    if state == "file":
        if "path" not in ini:
            raise _err("initial.path", None, 'a results file (.nc) with initial.state = "file"')
        return state, _value("initial.path", ini["path"])
    if "path" in ini:
        raise _err("initial.path", ini["path"], 'to be given only with initial.state = "file"')
    return state, None


def build_engine(extras: dict, parts: dict, builders: Builders) -> EngineSpec:
    """Validate the engine keys into an :class:`EngineSpec`.

    Parameters
    ----------
    extras : dict
        Second output of :func:`split_engine_keys`.
    parts : dict
        The objects :mod:`rubrotor.scenario` built (``shaft`` or ``rotor``, ``speed``,
        ``contact``, ``unbalance``, ``load``, ``initial``).

    Returns
    -------
    EngineSpec
    """
    span = parts["rotor"] if parts["rotor"] is not None else parts["shaft"]
    speed = parts["speed"]
    if "contact" in extras:
        stations = _contacts(extras["contact"], span, speed, builders)
    elif parts["contact"] is not None:
        stations = _contacts([_contact_dict(parts["contact"])], span, speed, builders)
    else:
        stations = ()
    if "unbalance" in extras:
        unb = _planes(extras["unbalance"], span, builders)
    else:
        unb = () if parts["unbalance"] is None else (parts["unbalance"],)
    if "load" in extras:
        loads = _loads(extras["load"], span, builders)
    else:
        loads = () if parts["load"] is None else (parts["load"],)
    gravity = _gravity(extras["gravity"]) if "gravity" in extras else (0.0, 0.0)
    speed_end = extras.get("speed", {}).get("to")
    speed_table = extras.get("speed", {}).get("table")
    speed_step = extras.get("speed", {}).get("step")
    state, path = _initial(extras["initial"]) if "initial" in extras else (parts["initial"], None)
    ini = extras.get("initial", {})
    if state == "given" and "modes" in ini and any(k in ini for k in ("positions", *_GIVEN)):
        raise _err("initial.modes", ini["modes"], "either modes or positions, not both")
    modal = _modal(ini) if state == "given" and "modes" in ini else None
    given = _given(ini) if state == "given" and modal is None else None
    if given is not None:
        for x in given[0]:
            _position_on(span, x)
    if (speed_end is not None or speed_table) and state not in ("rest", "static"):
        raise _err("initial.state", state,
                   '"rest" or "static" with speed.profile = "linear" or "table"')  # fmt: skip
    sim = extras.get("simulation", {})
    modes = _value("simulation.modes", sim["modes"]) if "modes" in sim else None
    cutoff = _value("simulation.cutoff", sim["cutoff"]) if "cutoff" in sim else None
    if modes is not None and cutoff is not None:
        raise _err("simulation.modes / simulation.cutoff", (modes, cutoff), "at most one")
    residual = _value("simulation.residual", sim.get("residual", True))
    return EngineSpec(stations, unb, loads, gravity, speed_end, speed_step, state, path, modes,
                      cutoff, residual, speed_table, given, modal, _free_spin(extras),
                      _rings(extras, stations, parts["rotor"]))  # fmt: skip


def _rings(extras: dict, stations, rotor):
    """Per contact its :class:`~rubrotor.engine.spin.TouchdownRing` (None: a fixed stator), or
    None without rings; rings and failing bearings need ``speed.profile = "free"``."""
    free = extras.get("speed", {}).get("free") is not None
    fails = [b.fail_time for b in getattr(rotor, "bearings", ()) if b.fail_time is not None]
    if fails and not free:
        raise _err("bearing.fail_time", fails[0], 'a run with speed.profile = "free"')
    if len(set(fails)) > 1:
        raise _err("bearing.fail_time", tuple(fails), "one time shared by the failing bearings")
    items = extras.get("contact", [])
    if not any("ring_inertia" in c for c in items):
        for i, c in enumerate(items):
            for k in ("ring_radius", "ring_drag"):
                if k in c:
                    raise _err(f"contact[{i + 1}].{k}", c[k], "to be given with ring_inertia")
        return None
    if not free:
        raise _err("contact.ring_inertia", "set", 'a run with speed.profile = "free"')
    from rubrotor.rotors.forces import TouchdownRing

    out = []
    for i, (c, s) in enumerate(zip(items, stations, strict=True)):
        if "ring_inertia" not in c:
            out.append(None)
            continue
        vals = {k: _value(f"contact[{i + 1}].ring_{k}", c[f"ring_{k}"], f"contact.ring_{k}")
                for k in ("inertia", "radius", "drag") if f"ring_{k}" in c}  # fmt: skip
        vals.setdefault("radius", s.contact.radius + s.contact.clearance)
        out.append(TouchdownRing(**{k: float(v) for k, v in vals.items()}))
    return tuple(out)


def _free_spin(extras: dict):
    """The :class:`~rubrotor.engine.spin.FreeSpin` of ``[speed] profile = "free"``, else None."""
    free = extras.get("speed", {}).get("free")
    if free is None:
        return None
    from rubrotor.rotors.forces import FreeSpin

    if "drive_torques" in free:
        tq, w = tuple(map(float, free["drive_torques"])), tuple(map(float, free["drive_speeds"]))
        if (
            len(tq) != len(w)
            or len(w) < 2
            or any(b <= a for a, b in zip(w[:-1], w[1:], strict=True))
        ):
            raise _err("speed.drive_speeds", w, "increasing speeds (rad/s), one per "
                       "drive_torques value, at least two")  # fmt: skip
        return FreeSpin(tq, w, float(free.get("drag", 0.0)))
    return FreeSpin(float(free.get("drive_torque", 0.0)), None, float(free.get("drag", 0.0)))


def _position_on(span, x: float) -> None:
    """A given start station must lie on the rotor, ``[0, L]`` (m)."""
    length = span.length
    if not 0.0 <= x <= length:
        raise _err("initial.positions", x, f"stations on the rotor, 0 to {length:g} m")


def _contact_dict(contact) -> dict:
    """A built Contact back as [contact] keys in SI (for a single table without new keys)."""
    import dataclasses

    d = {k: v for k, v in dataclasses.asdict(contact).items() if v is not None}
    return d


def engine_spec_or_none(mapping: Mapping, extras: dict, parts: dict, builders: Builders):
    """The EngineSpec when the scenario needs the general engine (new keys or a general rotor),
    else None; the stored dict form keeps the engine keys (``mapping`` deep-copied)."""
    if not extras and parts["rotor"] is None:
        return None, None
    return build_engine(extras, parts, builders), copy.deepcopy(dict(mapping))
