"""The scenario schema as data: one row per key of every scenario table.

Every key a scenario file may hold is one :class:`Key` row of :data:`KEYS` (its table, name, kind
of value, unit, allowed range or choices, default, whether it is required, and a description);
every table is one :class:`Table` row of :data:`TABLES` (its form, whether it is required, which
rotor it belongs to, its groups of alternative keys). Everything else is generated from them:

- the checks of :func:`rubrotor.load_scenario` (:func:`check_value`: unknown key, wrong kind,
  outside the range, not one of the choices; ``rubrotor.scenario`` and
  ``rubrotor.scenario.rotor`` call it for every key),
- the unit table :data:`KEY_UNITS` (also the ``units`` attribute of swept keys and of the
  provenance of results) and the per-table views :data:`SCHEMA`, :data:`ROTOR_SCHEMA`,
  :data:`ALTERNATIVES`, :data:`REQUIRED`,
- the JSON Schema shipped for editors (``rubrotor.scenario.export``),
- the key tables of the documentation (:func:`markdown_table`, written to
  ``docs/_generated/schema.md`` by ``docs/conf.py`` when the site is built).

Rules that need more than one key's value (a position inside the shaft's length, a speed that
resolves to a plausible spin speed, a bore smaller than the diameter) stay in the builders of
``rubrotor.scenario``; the table records the widest range a value may take on its own.

Adding keys
-----------
The rows are data only, so extending the schema is adding rows here; the code that turns the
values into objects lives with the builders (``rubrotor.scenario``,
``rubrotor.scenario.rotor``, or a new module such as ``scenario_engine``, which imports
:func:`check_value` and :func:`key_row` from here and never the other way round).

- A new key of an existing table: one more :class:`Key` row in that table's tuple (``_CONTACT``
  ...). Give it a unit (``"1"`` if dimensionless), a range (``_closed``, ``_positive`` or a
  ``(min, max, min_open, max_open)`` tuple) or choices, a default if the object has one, and a
  description; ``phrase`` when errors need context ("a station inside the shaft").
- A new table: a :class:`Table` row in :data:`TABLES` (``form="array"`` for ``[[name]]``,
  ``"named"`` for ``[name.LABEL]``, ``"table|array"`` for a table that may also be repeated,
  e.g. ``[contact]`` or ``[[contact]]``; ``rotor="any"`` if it goes with both the ``[shaft]`` and
  the general rotor; ``groups`` of alternative keys) and its key rows in :data:`KEYS`.
- Then regenerate the shipped JSON Schema with ``python -m rubrotor.scenario.export``
  (``tests/test_schema_export.py`` fails until it is current). The unit table, the loader's key,
  kind, range and choice checks, the JSON Schema and the docs' key table need no other change;
  ``tests/test_schema.py`` checks every row (known kind, unit on numbers, choices on strings,
  defaults inside the range and equal to the built object's field default).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from rubrotor.engine.settings import METHODS
from rubrotor.errors import ScenarioError
from rubrotor.forces.supports import DEFAULT_SUPPORT, SUPPORT_TYPES
from rubrotor.rotors.fe import BEARING_KINDS, COEFFICIENTS
from rubrotor.rotors.forces import BOW_SHAPES, CONTACT_LAWS, FRICTION_SIGNS, RESTITUTION_MODELS
from rubrotor.rotors.linear import EXTRAPOLATIONS, INTERPOLATIONS
from rubrotor.rotors.shaft import FORMULATIONS, PLAUSIBLE_RANGES, SHEAR_COEFFICIENTS, THEORIES
from rubrotor.scenario.plausible import CHECKS

__all__ = [
    "Key",
    "Table",
    "KEYS",
    "TABLES",
    "KINDS",
    "SCHEMA",
    "ROTOR_SCHEMA",
    "ROTOR_TABLES",
    "ALTERNATIVES",
    "REQUIRED",
    "KEY_UNITS",
    "key_unit",
    "key_row",
    "table_row",
    "check_value",
    "allowed_text",
    "markdown_table",
    "unknown_key_text",
]

KINDS = ("number", "int", "bool", "str", "number|str", "list", "number|list", "strlist")
"""Kinds of values: a finite number (int or float, not bool), an integer, true/false, a string,
a number or a string (a named choice), a non-empty list of numbers, a number or such a list, a
list of strings (each one of the choices)."""

_NUMERIC = ("number", "int", "number|str", "list", "number|list")


@dataclass(frozen=True)
class Key:
    """One key of one scenario table.

    Parameters
    ----------
    table : str
        Table it belongs to, e.g. ``"shaft"``, ``"section"`` (for ``[[section]]``).
    key : str
        Key name inside the table.
    kind : str
        One of :data:`KINDS`.
    unit : str
        SI unit of a numeric value (``"1"`` dimensionless); ``""`` for strings and flags.
    description : str
        One line for the docs and the JSON Schema.
    minimum, maximum : float or None
        Allowed range of a numeric value (of each element of a list), in ``unit``; None: unbounded.
    exclusive_minimum, exclusive_maximum : bool
        Whether the bound itself is excluded.
    zero : bool
        Whether 0 is allowed although it lies outside ``[minimum, maximum]`` (e.g. a speed of 0,
        a bore of 0).
    choices : tuple of str
        Allowed strings (for ``"str"`` and ``"number|str"`` kinds); empty: any string.
    default : bool, int, float, str or None
        Value taken when the key is absent; None: no default (absent means "not given", or the
        default depends on other keys, see the description).
    required : bool
        Whether the table must hold this key.
    phrase : str
        What errors say is allowed, when the generated text (:func:`allowed_text`) needs context
        (e.g. ``"a station inside the shaft"``); the range is appended.
    """

    table: str
    key: str
    kind: str
    unit: str
    description: str
    minimum: float | None = None
    maximum: float | None = None
    exclusive_minimum: bool = False
    exclusive_maximum: bool = False
    zero: bool = False
    choices: tuple[str, ...] = ()
    default: bool | int | float | str | None = None
    required: bool = False
    phrase: str = ""

    @property
    def dotted(self) -> str:
        """``"table.key"``, the name errors and unit tables use."""
        return f"{self.table}.{self.key}"


@dataclass(frozen=True)
class Table:
    """One scenario table.

    Parameters
    ----------
    name : str
        Table name in the TOML file.
    form : {"table", "array", "table|array", "named"}
        ``[name]``, ``[[name]]`` (an array of tables), either of the two, or ``[name.LABEL]``
        (tables by label).
    rotor : {"any", "shaft", "general"}
        Which rotor description it goes with: the uniform ``[shaft]``, the general rotor of
        ``[[section]]`` tables, or both.
    description : str
        One line for the docs and the JSON Schema.
    required : bool
        Whether a scenario (of its rotor) must hold it.
    groups : tuple of (tuple of str, bool)
        Groups of alternative keys: at most one of each group may be given; exactly one when the
        flag is true.
    """

    name: str
    form: str
    rotor: str
    description: str
    required: bool = False
    groups: tuple[tuple[tuple[str, ...], bool], ...] = ()


def _k(table, key, kind, unit, description, rng=None, **kw) -> Key:
    """A :class:`Key`; ``rng`` is ``"(lo, hi]"``-like shorthand: ``(lo, hi, lo_open, hi_open)``."""
    if rng is not None:
        lo, hi, lo_open, hi_open = rng
        kw.update(minimum=lo, maximum=hi, exclusive_minimum=lo_open, exclusive_maximum=hi_open)
    return Key(table, key, kind, unit, description, **kw)


def _closed(lo, hi=None):
    """Range ``[lo, hi]`` (``[lo, inf)`` without ``hi``)."""
    return (lo, hi, False, False)


def _positive(hi=None):
    """Range ``(0, hi]`` (``(0, inf)`` without ``hi``)."""
    return (0.0, hi, True, False)


# Widest plausible ranges (SI), shared with the model objects' own checks
# (rubrotor.rotors.shaft.PLAUSIBLE_RANGES): outside them no machine exists and derived quantities
# overflow double precision, so a value of 1e300 is refused, not crashed on.
_LENGTH = _closed(*PLAUSIBLE_RANGES["m"])
_MODULUS = _closed(*PLAUSIBLE_RANGES["Pa"])
_DENSITY = _closed(*PLAUSIBLE_RANGES["kg/m^3"])
_MASS = _closed(*PLAUSIBLE_RANGES["kg"])
_INERTIA = _closed(*PLAUSIBLE_RANGES["kg m^2"])
_NU = (-1.0, 0.5, True, True)
_POS_ND = (0.0, 1.0, True, True)
_STATION = (0.0, 1e3, False, False)  # m, refined against the rotor's length by the builder
_INSIDE = "a station inside the shaft"

_SHAFT = (
    _k("shaft", "length", "number", "m", "Length L between the simple supports",
       _LENGTH, required=True),
    _k("shaft", "diameter", "number", "m", "Outer diameter D", _LENGTH),
    _k("shaft", "slenderness", "number", "1",
       "Slenderness r = r0/L (radius of gyration over length), instead of diameter",
       _closed(1e-6, 10.0)),
    _k("shaft", "bore_diameter", "number", "m", "Bore (inner) diameter of a hollow shaft",
       _LENGTH, zero=True, default=0.0),
    _k("shaft", "youngs_modulus", "number", "Pa", "Young's modulus E", _MODULUS, required=True),
    _k("shaft", "shear_modulus", "number", "Pa", "Shear modulus G", _MODULUS),
    _k("shaft", "poisson_ratio", "number", "1", "Poisson's ratio nu (G = E/(2(1+nu)))", _NU),
    _k("shaft", "shear_parameter", "number", "1",
       "The seed's shear parameter delta = E/(kappa G), instead of G",
       _closed(0.001, 1e6)),
    _k("shaft", "density", "number", "kg/m^3", "Density rho", _DENSITY, required=True),
    _k("shaft", "shear_coefficient", "number|str", "1",
       "Timoshenko shear coefficient kappa: a rule or a number",
       _closed(1e-6, 1e9), choices=SHEAR_COEFFICIENTS, default="cowper"),
    _k("shaft", "theory", "str", "", "Beam theory", choices=THEORIES, default="timoshenko"),
    _k("shaft", "gyroscopic", "bool", "", "Include the gyroscopic coupling", default=True),
    _k("shaft", "modes", "int", "1", "Number of modes per plane of the Galerkin model",
       _closed(1, 200), default=3),
    _k("shaft", "formulation", "str", "", "Equations of motion: two fields or the seed's eq. 1",
       choices=FORMULATIONS, default="two-field"),
)  # fmt: skip
_SPEED = (
    _k("speed", "rad_per_s", "number", "rad/s", "Spin speed Omega", _closed(1e-6, 1e7), zero=True),
    _k("speed", "rpm", "number", "rev/min", "Spin speed in revolutions per minute",
       _closed(1e-5, 1e8), zero=True),
    _k("speed", "hz", "number", "Hz", "Spin speed in revolutions per second",
       _closed(1e-7, 2e6), zero=True),
    _k("speed", "critical_multiple", "number", "x first forward critical",
       "Spin speed as a multiple of the first forward critical speed (general rotors: "
       "the lowest forward crossing of damped frequency and spin)",
       _closed(1e-6, 1000.0), zero=True),
    _k("speed", "dimensionless", "number", "1",
       "The seed's speed parameter c = Omega L^2 sqrt(rho A/(E I)) ([shaft] only)",
       _closed(1e-9, 1e9), zero=True),
)  # fmt: skip
_UNBALANCE = (
    _k("unbalance", "magnitude", "number", "kg m", "Unbalance m e", _closed(0.0)),
    _k("unbalance", "magnitude_nd", "number", "1",
       "Dimensionless unbalance force m e Omega^2 L^2/(E I)",
       _closed(0.0)),
    _k("unbalance", "position", "number", "m",
       "Axial station (default midspan on a [shaft], required on a general rotor)",
       _STATION, phrase=_INSIDE),
    _k("unbalance", "position_nd", "number", "1", "Axial station a/L", _POS_ND, phrase=_INSIDE),
    _k("unbalance", "phase_deg", "number", "deg", "Angular position of the unbalance", default=0.0),
)  # fmt: skip
_LOAD = (
    _k("load", "force_y", "number", "N", "Constant radial force, y component", default=0.0),
    _k("load", "force_z", "number", "N", "Constant radial force, z component", default=0.0),
    _k("load", "position", "number", "m",
       "Axial station (default midspan on a [shaft], required on a general rotor)",
       _STATION, phrase=_INSIDE),
    _k("load", "position_nd", "number", "1", "Axial station a/L", _POS_ND, phrase=_INSIDE),
)  # fmt: skip
_CONTACT = (
    _k("contact", "law", "str", "", "Normal contact law", choices=CONTACT_LAWS, default="hertz"),
    _k("contact", "position", "number", "m",
       "Axial station (default midspan on a [shaft], required on a general rotor)",
       _STATION, phrase=_INSIDE),
    _k("contact", "position_nd", "number", "1", "Axial station a/L", _POS_ND, phrase=_INSIDE),
    _k("contact", "clearance", "number", "m", "Radial clearance g", _positive(1000.0)),
    _k("contact", "clearance_nd", "number", "1", "Dimensionless clearance g/L", _positive()),
    _k("contact", "stiffness", "number", "N/m^1.5 (hertz) or N/m (linear)",
       "Contact stiffness k_h (hertz) or k (linear)",
       _positive()),
    _k("contact", "stiffness_nd", "number", "1",
       "Dimensionless stiffness k_h L^3.5/(E I) (hertz) or k L^3/(E I) (linear)",
       _positive()),
    _k("contact", "damping", "number", "s/m (hertz) or N s/m (linear)",
       "Hunt-Crossley factor b_h (hertz) or dashpot c (linear)",
       _closed(0.0), default=0.0),
    _k("contact", "damping_nd", "number", "1", "Dimensionless Hunt-Crossley factor b_h L Omega",
       _closed(0.0)),
    _k("contact", "restitution", "number", "1",
       "Coefficient of restitution e, instead of damping (hertz)",
       _positive(1.0)),
    _k("contact", "impact_speed", "number", "m/s", "Impact speed v0 with restitution", _positive()),
    _k("contact", "restitution_model", "str", "", "Damping of a coefficient of restitution",
       choices=RESTITUTION_MODELS, default="hunt-crossley"),
    _k("contact", "friction", "number", "1", "Coulomb friction coefficient mu",
       _closed(0.0), default=0.0),
    _k("contact", "friction_sign", "str", "",
       "Sign of the friction force: physical, or the seed's literal (non-physical) sign",
       choices=FRICTION_SIGNS, default="physical"),
    _k("contact", "radius", "number", "m",
       "Radius of the rubbing surface for the sliding speed (default the shaft radius)",
       _positive()),
    _k("contact", "friction_regularization", "number", "m/s",
       "Velocity scale of the smoothed sign of the sliding velocity",
       _positive(), default=0.001),
)  # fmt: skip
_DAMPING = (
    _k("damping", "ratio", "number|list", "1", "Modal damping ratio, one or one per mode",
       _closed(0.0, 0.999999), default=0.0),
)  # fmt: skip
_INITIAL = (
    _k("initial", "state", "str", "",
       "Start at rest, on the steady no-contact orbit, in static equilibrium, from a results "
       "file, or from a given deflection and velocity at stations (static, file and given: "
       "general engine)",
       choices=("rest", "steady", "static", "file", "given"), default="rest"),
)  # fmt: skip
_SIMULATION = (
    _k("simulation", "revolutions", "number", "rev", "Length of the run in revolutions",
       _positive()),
    _k("simulation", "duration", "number", "s", "Length of the run in seconds", _positive()),
    _k("simulation", "method", "str", "", "Time integrator",
       choices=tuple(METHODS), default="exponential"),
    _k("simulation", "dtau", "number", "rad", "Fixed step in rad of spin", _positive()),
    _k("simulation", "dt", "number", "s", "Fixed step in seconds", _positive()),
    _k("simulation", "rtol", "number", "1", "Relative tolerance of the adaptive step",
       _positive(), default=1e-06),
    _k("simulation", "atol", "number", "m", "Absolute tolerance of the adaptive step",
       _positive(), default=1e-10),
    _k("simulation", "output_dtau", "number", "rad", "Output interval in rad of spin", _positive()),
    _k("simulation", "sample_rate", "number", "Hz", "Output sampling rate", _positive()),
    _k("simulation", "save_every", "int", "1", "Keep every n-th output sample",
       _closed(1), default=1),
    _k("simulation", "probes", "list", "m", "Axial stations of extra displacement outputs",
       _STATION, phrase="a list of stations inside the shaft"),
    _k("simulation", "max_displacement", "number", "m",
       "Displacement at which a run stops as diverged (default 1000 x clearance)",
       _positive()),
)  # fmt: skip
_META = (
    _k("meta", "name", "str", "", "Name of the scenario (default the file stem)"),
    _k("meta", "description", "str", "", "Free text"),
)  # fmt: skip
_MATERIALS = (
    _k("materials", "youngs_modulus", "number", "Pa", "Young's modulus E", _MODULUS, required=True),
    _k("materials", "poisson_ratio", "number", "1", "Poisson's ratio nu", _NU),
    _k("materials", "shear_modulus", "number", "Pa", "Shear modulus G", _MODULUS),
    _k("materials", "density", "number", "kg/m^3", "Density rho", _DENSITY, required=True),
)  # fmt: skip
_SECTION = (
    _k("section", "length", "number", "m", "Length of the section", _LENGTH, required=True),
    _k("section", "diameter", "number", "m", "Outer diameter", _LENGTH, required=True),
    _k("section", "bore_diameter", "number", "m", "Bore diameter", _LENGTH, zero=True, default=0.0),
    _k("section", "material", "str", "", "Label of a [materials.LABEL] table", required=True),
    _k("section", "elements", "int", "1", "Finite elements (default from the mesh rule)",
       _closed(1, 10000)),
    _k("section", "position", "number", "m", "Left end of a sleeve laid over the shaft (an "
       "impeller hub; ROSS's second shaft element on the same nodes); none for a shaft section",
       _STATION),
    _k("section", "mass_damping", "number", "1/s",
       "alpha of the proportional damping alpha M + beta K of its elements", _closed(0.0),
       default=0.0),
    _k("section", "stiffness_damping", "number", "s",
       "beta of the proportional damping alpha M + beta K of its elements", _closed(0.0),
       default=0.0),
)  # fmt: skip
_DISK = (
    _k("disk", "position", "number", "m", "Axial station", _STATION, required=True),
    _k("disk", "mass", "number", "kg", "Mass (lumped form)", _MASS, zero=True),
    _k("disk", "polar_inertia", "number", "kg m^2", "Polar moment of inertia (lumped form)",
       _INERTIA, zero=True, default=0.0),
    _k("disk", "diametral_inertia", "number", "kg m^2", "Diametral moment of inertia (lumped form)",
       _INERTIA, zero=True, default=0.0),
    _k("disk", "outer_diameter", "number", "m", "Outer diameter (geometry form)", _LENGTH),
    _k("disk", "width", "number", "m",
       "Axial width (required with the geometry form; used for overlap checks)",
       _LENGTH, zero=True, default=0.0),
    _k("disk", "bore_diameter", "number", "m", "Bore diameter (geometry form)", _LENGTH, zero=True),
    _k("disk", "material", "str", "", "Label of a [materials.LABEL] table (geometry form)"),
    _k("disk", "name", "str", "", "Label", default=""),
)  # fmt: skip


def _coefficient(c: str) -> Key:
    """Row of a bearing coefficient (direct ones, kyy, czz ..., are checked >= 0 by
    :class:`rubrotor.rotors.fe.Bearing` unless tabulated against frequencies)."""
    stiff = c[0] == "k"
    direct = c[1] == c[2]
    return _k(
        "bearing",
        c,
        "number|list",
        "N/m" if stiff else "N s/m",
        f"{'Stiffness' if stiff else 'Damping'} {c}: a number or one value per speed (or "
        "frequency)" + (" (>= 0 unless tabulated against frequencies)" if direct else ""),
        None,
        default=0.0,
    )


_BEARING = (
    _k("bearing", "position", "number", "m", "Axial station", _STATION, required=True),
    *(_coefficient(c) for c in COEFFICIENTS),
    _k("bearing", "speeds", "list", "rad/s", "Speeds at which the coefficients are tabulated",
       _closed(0.0)),
    _k("bearing", "kind", "str", "", "A bearing of coefficients, or a pinned support",
       choices=BEARING_KINDS, default="bearing"),
    _k("bearing", "name", "str", "", "Label", default=""),
    _k("bearing", "fail_time", "number", "s", "Time at which the bearing stops holding the "
       'rotor (a magnetic bearing losing levitation; speed.profile = "free")', _closed(0.0)),
    _k("bearing", "frequencies", "list", "rad/s", "Whirl (excitation) frequencies at which the "
       "coefficients are tabulated (a magnetic bearing, a squeeze-film damper)", _closed(0.0)),
    _k("bearing", "interpolation", "str", "", "Between table points",
       choices=INTERPOLATIONS, default="linear"),
    _k("bearing", "extrapolation", "str", "", "Outside the table: the end values, or on along "
       "the end slope (as ROSS 3.x)", choices=EXTRAPOLATIONS, default="hold"),
    _k("bearing", "myy", "number", "kg", "Bearing mass along y", _closed(0.0), default=0.0),
    _k("bearing", "myz", "number", "kg", "Bearing mass, cross term (symmetric)", default=0.0),
    _k("bearing", "mzz", "number", "kg", "Bearing mass along z", _closed(0.0), default=0.0),
    _k("bearing", "link", "str", "", "Name of the [[point_mass]] (a housing) the bearing joins "
       "the shaft to, instead of the ground"),
    _k("bearing", "on", "str", "", "Name of the [[point_mass]] the bearing holds to the ground "
       "(a housing's support; position: the housing's station)"),
    _k("bearing", "type", "str", "", "Support model: coefficients (kyy ... czz), or a force term "
       "of rubrotor.forces.supports", choices=tuple(SUPPORT_TYPES), default=DEFAULT_SUPPORT),
    # type = "muszynska" (rubrotor.forces.muszynska): a fluid ring swirling at lambda Omega
    _k("bearing", "fluid_stiffness", "number", "N/m", 'Direct fluid stiffness K_f (type = '
       '"muszynska")', _closed(0.0), default=0.0),
    _k("bearing", "fluid_damping", "number", "N s/m", 'Direct fluid damping D_f (type = '
       '"muszynska"); the cross-coupled stiffness is swirl_ratio Omega D_f', _positive()),
    _k("bearing", "swirl_ratio", "number", "1", 'Average circumferential fluid speed over the '
       'spin, lambda (type = "muszynska")', (0.0, 1.0, False, True), default=0.5),
    # type = "short_journal" | "squeeze_film" (rubrotor.forces.fluid_film) | "finite_journal"
    # (rubrotor.forces.finite_journal): fluid films linearised at the static equilibrium
    _k("bearing", "diameter", "number", "m", 'Journal diameter D (type = "short_journal", '
       '"squeeze_film", "finite_journal")', _LENGTH),
    _k("bearing", "length", "number", "m", "Film length L (fluid films; L/D <= 1 for the short "
       'films, 1/16 to 4 for "finite_journal")', _LENGTH),
    _k("bearing", "radial_clearance", "number", "m", "Radial clearance c (fluid films), below "
       "the journal's radius", _positive(1.0)),
    _k("bearing", "viscosity", "number", "Pa s", "Lubricant dynamic viscosity mu (fluid films)",
       _positive(1e3)),
    _k("bearing", "cavitation", "str", "", 'Cavitation: "half_sommerfeld" (Gumbel, pi-film), '
       '"full_film" (Sommerfeld); "reynolds" (Swift-Stieber) for "finite_journal" only',
       choices=("half_sommerfeld", "gumbel", "pi_film", "full_film", "sommerfeld", "reynolds")),
    _k("bearing", "groove_angles", "list", "rad", "Axial oil-feed grooves' angles in the "
       'bearing\'s frame, from y towards z (type = "finite_journal")', _closed(-1e3, 1e3)),
    _k("bearing", "supply_pressure", "number", "Pa", "Oil supply pressure held in the grooves "
       '(type = "finite_journal")', _closed(0.0, 1e9), default=0.0),
    _k("bearing", "centering_stiffness", "number", "N/m", "Centring spring in parallel with a "
       'squeeze-film damper, 0 for an uncentred one (type = "squeeze_film")', _closed(0.0, 1e13)),
)  # fmt: skip
_POINT_MASS = (
    _k("point_mass", "name", "str", "", "Label the bearings' link and on refer to",
       required=True),
    _k("point_mass", "position", "number", "m", "Axial station it sits at (labels)", _STATION,
       required=True),
    _k("point_mass", "mass_y", "number", "kg", "Mass along y", _MASS, zero=True, default=0.0),
    _k("point_mass", "mass_z", "number", "kg", "Mass along z", _MASS, zero=True, default=0.0),
)  # fmt: skip
_ROTOR = (
    _k("rotor", "theory", "str", "", "Beam theory", choices=THEORIES, default="timoshenko"),
    _k("rotor", "gyroscopic", "bool", "", "Include the gyroscopic coupling", default=True),
    _k("rotor", "shear_coefficient", "number|str", "1", "Timoshenko shear coefficient kappa",
       _closed(1e-6, 1e9), choices=SHEAR_COEFFICIENTS, default="cowper"),
    _k("rotor", "max_element_length", "number", "m", "Upper bound of the element length", _LENGTH),
    _k("rotor", "mass_damping", "number", "1/s", "alpha of a rotor-wide damping alpha M + beta K "
       "(shaft, disks, point masses; ROSS's Rotor(alpha=))", _closed(0.0), default=0.0),
    _k("rotor", "stiffness_damping", "number", "s", "beta of a rotor-wide damping alpha M + "
       "beta K (ROSS's Rotor(beta=))", _closed(0.0), default=0.0),
)  # fmt: skip

_STATOR_PARTS = (("mass", "kg", "Mass", _closed(1e-6, 1e7)),
                 ("stiffness", "N/m", "Stiffness to ground", _closed(1.0, 1e13)),
                 ("damping", "N s/m", "Damping to ground", _closed(0.0, 1e9)))  # fmt: skip
_ENGINE = (
    _k("contact", "offset_y", "number", "m", "Stator centre offset from the bearing axis, y "
       "(general engine)", _closed(-1.0, 1.0), default=0.0),
    _k("contact", "offset_z", "number", "m", "Stator centre offset from the bearing axis, z "
       "(general engine)", _closed(-1.0, 1.0), default=0.0),
    *(_k("contact", f"stator_{part}{axis}", "number", unit,
         f"{text} of a flexible stator{' along ' + axis[1] if axis else ''} (general engine)", rng)
      for part, unit, text, rng in _STATOR_PARTS for axis in ("", "_y", "_z")),
    _k("unbalance", "phase", "number", "rad", "Angular position of the unbalance (instead of "
       "phase_deg; general engine)", _closed(-1e3, 1e3)),
    _k("gravity", "y", "number", "m/s^2", "Gravity along y on the shaft and disk masses",
       _closed(-1e4, 1e4), default=0.0),
    _k("gravity", "z", "number", "m/s^2", "Gravity along z on the shaft and disk masses",
       _closed(-1e4, 1e4), default=0.0),
    _k("speed", "profile", "str", "", "Speed against time: constant, linear from ... to over "
       "the run (run-up, coast-down), or a table of times and speeds (linear between rows)",
       choices=("constant", "linear", "table", "free"), default="constant"),
    _k("contact", "ring_inertia", "number", "kg m^2", "Polar inertia of a touchdown bearing's "
       'inner ring, the spinning stator of this contact (speed.profile = "free")',
       _positive(1e6)),
    _k("contact", "ring_radius", "number", "m", "Bore radius of the touchdown ring (default "
       "radius + clearance)", _positive(1e3)),
    _k("contact", "ring_drag", "number", "N m s", "Drag coefficient of the touchdown ring's "
       "bearing: torque -ring_drag omega_ring", _closed(0.0, 1e9), default=0.0),
    _k("speed", "drive_torque", "number", "N m", 'Constant motor torque of a free spin speed '
       '(profile = "free")', _closed(-1e9, 1e9), default=0.0),
    _k("speed", "drive_torques", "list", "N m", "Motor torque table of a free spin speed, one "
       "per drive_speeds row (linear between rows, held beyond)", _closed(-1e9, 1e9)),
    _k("speed", "drive_speeds", "list", "rad/s", "Speeds of the drive_torques table, increasing",
       _closed(0.0, 1e7)),
    _k("speed", "drag", "number", "N m s", 'Drag coefficient of a free spin speed: torque '
       '-drag Omega (profile = "free")', _closed(0.0, 1e9), default=0.0),
    _k("speed", "times", "list", "s", "Times of a speed table (from 0, increasing, up to "
       "simulation.duration, on the sample grid)", _closed(0.0)),
    _k("speed", "speeds", "list", "rad/s", "Speeds of a speed table, one per time",
       _closed(1e-6, 1e7)),
    _k("speed", "from", "number", "rad/s", "Speed at the start of a linear profile",
       _closed(1e-6, 1e7)),
    _k("speed", "to", "number", "rad/s", "Speed at the end of a linear profile",
       _closed(1e-6, 1e7)),
    _k("speed", "step", "number", "rad/s",
       "Largest speed change between re-diagonalisations (default 1/200 of the range)",
       _closed(1e-6, 1e7)),
    _k("initial", "path", "str", "",
       'Results file of the general engine whose final state starts the run (state = "file")'),
    _k("initial", "positions", "list", "m",
       'Stations where the start deflection and velocity are given (state = "given")',
       _closed(0.0)),
    _k("initial", "v", "list", "m", "Start deflection along y, one per initial.positions",
       _closed(-1.0, 1.0)),
    _k("initial", "w", "list", "m", "Start deflection along z, one per initial.positions",
       _closed(-1.0, 1.0)),
    _k("initial", "v_dot", "list", "m/s", "Start velocity along y, one per initial.positions",
       _closed(-1e4, 1e4)),
    _k("initial", "w_dot", "list", "m/s", "Start velocity along z, one per initial.positions",
       _closed(-1e4, 1e4)),
    _k("initial", "modes", "list", "1", 'Undamped modes (1 = lowest) the start state is made of '
       '(state = "given", instead of positions)', _closed(1, 1e5)),
    _k("initial", "amplitudes", "list", "m",
       "Start deflection of each of initial.modes at its largest point", _closed(-1.0, 1.0)),
    _k("initial", "modal_velocities", "list", "m/s",
       "Start velocity of each of initial.modes at its largest point", _closed(-1e4, 1e4)),
    _k("simulation", "modes", "int", "1", "Retained modes of the general engine",
       _closed(1, 100000)),
    _k("simulation", "cutoff", "number", "rad/s",
       "Keep the modes below this frequency (general engine)", _closed(1e-3, 1e9)),
    _k("simulation", "residual", "bool", "",
       "Static correction of the dropped modes at force and contact stations", default=True),
)  # fmt: skip
"""Keys of the general engine (:mod:`rubrotor.scenario.dynamics` builds them)."""

_THERMAL = (
    _k("thermal", "time_constant", "number", "s", "Thermal time constant tau of the bow",
       _positive(), required=True),
    _k("thermal", "bow_per_heat", "number", "m/W",
       "Steady bow at the rubbing station per watt of heat input (beta)", _closed(0.0),
       required=True),
    _k("thermal", "hot_spot_lag", "number", "rad",
       "Angle by which the hot spot lags the high spot, against the spin",
       (-math.pi, math.pi, True, True), default=0.0),
    _k("thermal", "bow_shape", "str", "",
       "Bow shape along the rotor: uniform curvature through the outermost bearings",
       choices=BOW_SHAPES, default="arc"),
)  # fmt: skip
"""Keys of the thermal bow (:class:`rubrotor.rotors.forces.ThermalBow`)."""

_CHECKS = (
    _k("checks", "skip", "strlist", "",
       "Plausibility checks across keys to switch off, by name (rubrotor.scenario.plausible)",
       choices=tuple(CHECKS)),
)  # fmt: skip
"""Keys of ``[checks]`` (:mod:`rubrotor.scenario.plausible`)."""

TABLES: tuple[Table, ...] = (
    Table("meta", "table", "any", "Name and description"),
    Table("shaft", "table", "shaft", "A uniform, simply supported continuous shaft",
          required=True,
          groups=((("diameter", "slenderness"), True),
                  (("shear_modulus", "poisson_ratio", "shear_parameter"), True))),
    Table("speed", "table", "any", "Spin speed (exactly one key, or a linear profile from ... to)",
          required=True,
          groups=((("rad_per_s", "rpm", "hz", "critical_multiple", "dimensionless", "from"),
                   True),)),
    Table("unbalance", "table|array", "any", "A mass unbalance (several planes as [[unbalance]])",
          groups=((("magnitude", "magnitude_nd"), True), (("position", "position_nd"), False))),
    Table("load", "table|array", "any", "A constant radial load (several as [[load]])",
          groups=((("position", "position_nd"), False),)),
    Table("contact", "table|array", "any",
          "Rotor-stator contact (several stations as [[contact]]; offset and flexible stators "
          "with the general engine)",
          groups=((("position", "position_nd"), False), (("clearance", "clearance_nd"), True),
                  (("stiffness", "stiffness_nd"), True),
                  (("damping", "damping_nd", "restitution"), False))),
    Table("damping", "table", "shaft", "Modal damping of the continuous shaft"),
    Table("initial", "table", "any", "Initial state"),
    Table("gravity", "table", "any", "Gravity on the rotor (general engine)"),
    Table("simulation", "table", "any", "Integrator settings",
          groups=((("revolutions", "duration"), True), (("dtau", "dt"), False),
                  (("output_dtau", "sample_rate"), False))),
    Table("materials", "named", "general", "Materials of a general rotor, by label"),
    Table("section", "array", "general", "Shaft sections of a general rotor, left to right",
          required=True),
    Table("disk", "array", "general", "Rigid disks"),
    Table("bearing", "array", "general", "Bearings and supports",
          groups=((("speeds", "frequencies"), False), (("link", "on"), False))),
    Table("point_mass", "array", "general", "Lumped masses with their own DOFs (bearing "
          "housings), joined by bearings' link and on"),
    Table("rotor", "table", "general", "Settings of the general rotor"),
    Table("thermal", "table", "any",
          "Thermal bow at the rubbing stations (rubrotor thermal; general rotors)"),
    Table("checks", "table", "any",
          "Plausibility checks across keys (a clearance against the radius, a speed against the "
          "surface speed ...) a deliberate study switches off"),
)  # fmt: skip
"""Every scenario table, in the order the docs list them."""

_ORDER = {t.name: i for i, t in enumerate(TABLES)}
KEYS: tuple[Key, ...] = tuple(sorted((
    *_META, *_SHAFT, *_SPEED, *_UNBALANCE, *_LOAD, *_CONTACT, *_DAMPING, *_INITIAL,
    *_SIMULATION, *_ENGINE, *_MATERIALS, *_SECTION, *_DISK, *_BEARING, *_POINT_MASS, *_ROTOR, *_THERMAL, *_CHECKS,
), key=lambda row: _ORDER[row.table]))  # fmt: skip
"""Every key of every scenario table, grouped by table: the one source of the schema."""

_TABLE_ROWS = {t.name: t for t in TABLES}
_KEY_ROWS = {(k.table, k.key): k for k in KEYS}

ROTOR_TABLES = tuple(t.name for t in TABLES if t.rotor == "general")
"""Tables of the general rotor (``[materials.NAME]``, ``[[section]]`` ...)."""


def _kinds(tables) -> dict[str, dict[str, str]]:
    return {t: {k.key: k.kind for k in KEYS if k.table == t} for t in tables}


SCHEMA: dict[str, dict[str, str]] = _kinds(t.name for t in TABLES if t.rotor != "general")
"""Tables of a scenario besides the general rotor's, their keys and the kind of each key."""

ROTOR_SCHEMA: dict[str, dict[str, str]] = _kinds(ROTOR_TABLES)
"""Tables of the general rotor, their keys and the kind of each key."""

ALTERNATIVES: dict[str, list[tuple[tuple[str, ...], bool]]] = {
    t.name: list(t.groups) for t in TABLES if t.groups
}
"""Per table: groups of alternative keys and whether one of the group is required."""

REQUIRED: dict[str, tuple[str, ...]] = {
    t.name: keys
    for t in TABLES
    if (keys := tuple(k.key for k in KEYS if k.table == t.name and k.required))
}
"""Per table: the keys it must hold."""

KEY_UNITS: dict[str, str] = {k.dotted: k.unit for k in KEYS if k.kind in _NUMERIC}
"""Unit of each numeric scenario key (``"1"``: dimensionless)."""


def key_unit(key: str) -> str:
    """Unit of a dotted scenario key (``"shaft.length"`` -> ``"m"``, an indexed key
    ``"unbalance[2].magnitude"`` as ``"unbalance.magnitude"``); ``"1"`` if not listed."""
    import re

    key = re.sub(r"^([A-Za-z_]+)\[\d+\]\.", r"\1.", key)
    return KEY_UNITS.get(key, "1")


def table_row(name: str) -> Table:
    """The :class:`Table` row of table ``name`` (KeyError if there is none)."""
    return _TABLE_ROWS[name]


def key_row(table: str, key: str) -> Key:
    """The :class:`Key` row of ``table.key`` (KeyError if there is none)."""
    return _KEY_ROWS[(table, key)]


def _g(x: float) -> str:
    return f"{x:g}"


def range_text(row: Key) -> str:
    """The allowed range of a numeric key as text, e.g. ``"in [1e-09, 1000]"``, ``"> 0"``."""
    lo, hi = row.minimum, row.maximum
    if lo is None and hi is None:
        return ""
    if row.kind == "int":
        return f"in {lo}..{hi}" if hi is not None else f">= {lo}"
    if hi is None:
        return f"{'>' if row.exclusive_minimum else '>='} {_g(lo)}"
    if lo is None:
        return f"{'<' if row.exclusive_maximum else '<='} {_g(hi)}"
    left = "(" if row.exclusive_minimum else "["
    right = ")" if row.exclusive_maximum else "]"
    return f"in {left}{_g(lo)}, {_g(hi)}{right}"


def allowed_text(row: Key) -> str:
    """What ``row`` accepts, as error messages say it (``"a number in [1e-09, 1000] (m)"``)."""
    if row.kind == "bool":
        return "true or false"
    if row.kind == "strlist":
        return "a list of " + (" / ".join(f'"{c}"' for c in row.choices) or "strings")
    if row.kind == "str":
        return " or ".join(f'"{c}"' for c in row.choices) if row.choices else "a string"
    what = {
        "number": "a number",
        "int": "an integer",
        "number|str": "a number",
        "list": "a list of numbers",
        "number|list": "a number or a non-empty list of numbers",
    }[row.kind]
    rng = range_text(row)
    if row.phrase:
        what = row.phrase + ","
    text = f"{'0 or ' if row.zero else ''}{what}{' ' + rng if rng else ''}"
    if row.unit not in ("", "1"):
        text += f" ({row.unit})"
    if row.kind == "number|str":
        text = " or ".join([*(f'"{c}"' for c in row.choices), text])
    return text


def unknown_key_text(key: str, allowed, table: str, what: str = "key") -> str:
    """What an error says is allowed instead of an unknown ``key`` of ``[table]``: the nearest
    valid key (``difflib.get_close_matches``, case-insensitive) when one is near, e.g.
    ``"a key of [contact]: did you mean `clearance`?"``, else the list of valid keys.

    Parameters
    ----------
    key : str
        The key that was given.
    allowed : iterable of str
        The valid keys (or tables, with ``what="table"``).
    table : str
        How the message names where the key was, e.g. ``"[contact]"``; ``""`` for the file's
        top level.
    what : str
        ``"key"`` or ``"table"``.
    """
    import difflib

    allowed = list(allowed)
    lower = {a.lower(): a for a in allowed}
    near = difflib.get_close_matches(str(key).lower(), list(lower), n=3, cutoff=0.6)
    score = [difflib.SequenceMatcher(None, str(key).lower(), n).ratio() for n in near]
    near = [n for n, r in zip(near, score, strict=True) if r == score[0]]  # the nearest, ties
    where = f" of {table}" if table else ""
    if near:
        names = " or ".join(f"`{lower[n]}`" for n in near)
        return f"a {what}{where}: did you mean {names}?"
    return f"one of the {what}s {', '.join(allowed)}{where}"


def _is_number(v) -> bool:
    return not isinstance(v, bool) and isinstance(v, int | float | np.integer | np.floating)


def _in_range(row: Key, v: float) -> bool:
    if v == 0 and row.zero:
        return True
    lo, hi = row.minimum, row.maximum
    if lo is not None and (v <= lo if row.exclusive_minimum else v < lo):
        return False
    return not (hi is not None and (v >= hi if row.exclusive_maximum else v > hi))


def _number(name: str, row: Key, value, v) -> float:
    if not _is_number(v):
        raise ScenarioError(name, value, allowed_text(row))
    if not math.isfinite(float(v)):
        raise ScenarioError(name, value, "a finite number (not nan or inf)")
    if not _in_range(row, float(v)):
        raise ScenarioError(name, value, allowed_text(row))
    return v


def check_value(name: str, value, row: Key):
    """Check one value against its row: kind, finiteness, range, choices.

    Parameters
    ----------
    name : str
        How errors name the key (``"shaft.length"``, ``"section[2].diameter"``).
    value : object
        The value read from the file.
    row : Key
        Its row of :data:`KEYS`.

    Returns
    -------
    object
        The value (integers as int, lists as lists).

    Raises
    ------
    ScenarioError
        Naming ``name``, the value and :func:`allowed_text` of the row.
    """
    kind = row.kind
    if kind == "strlist":
        ok = isinstance(value, list | tuple) and all(isinstance(v, str) for v in value)
        if not ok or any(row.choices and v not in row.choices for v in value):
            raise ScenarioError(name, value, allowed_text(row))
        return list(value)
    if kind == "bool":
        if not isinstance(value, bool):
            raise ScenarioError(name, value, allowed_text(row))
        return value
    if kind in ("str", "number|str") and isinstance(value, str):
        if row.choices and value not in row.choices:
            raise ScenarioError(name, value, allowed_text(row))
        return value
    if kind == "str":
        raise ScenarioError(name, value, "a string")
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int | np.integer):
            raise ScenarioError(name, value, allowed_text(row))
        _number(name, row, value, value)
        return int(value)
    if kind == "list" or (kind == "number|list" and not _is_number(value)):
        if not isinstance(value, list | tuple) or (kind == "number|list" and not value):
            raise ScenarioError(name, value, allowed_text(row))
        for v in value:
            _number(name, row, value, v)
        return list(value)
    return _number(name, row, value, value)


def _toml(value) -> str:
    """A default as it is written in a TOML file."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return f'"{value}"' if isinstance(value, str) else repr(value)


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def _allowed_cell(row: Key) -> str:
    """The "allowed" column of the docs: the kind with its choices or range (no unit)."""
    if row.kind == "bool":
        text = "true or false"
    elif row.kind == "strlist":
        text = allowed_text(row)
    elif row.kind in ("str", "number|str") and row.choices:
        text = " or ".join(f'"{c}"' for c in row.choices)
        if row.kind == "number|str":
            text += f" or a number {range_text(row)}"
    elif row.kind == "str":
        text = "a string"
    else:
        text = allowed_text(dataclasses.replace(row, unit="", phrase=""))
    return text + ("; **required**" if row.required else "")


def markdown_table() -> str:
    """The docs page's key tables (MyST markdown): a level-1 heading and a table per table.

    Returns
    -------
    str
        For each table of :data:`TABLES`: a heading, its description, and a table of its keys
        with the columns key, unit, allowed (kind, choices or range), default and description.
    """
    forms = {"table": "[{}]", "array": "[[{}]]", "table|array": "[[{}]]", "named": "[{}.LABEL]"}
    rotors = {"any": "", "shaft": " (with a `[shaft]` only)", "general": " (general rotor)"}
    out = []
    for t in TABLES:
        out += [
            f"# `{forms[t.form].format(t.name)}`",
            "",
            f"{t.description}{rotors[t.rotor] if t.name != 'shaft' else ''}"
            f"{'; required' if t.required else ''}.",
            "",
            "| key | unit | allowed | default | description |",
            "|---|---|---|---|---|",
        ]
        for k in (k for k in KEYS if k.table == t.name):
            default = "-" if k.default is None else f"`{_toml(k.default)}`"
            cells = [f"`{k.key}`", k.unit or "-", _allowed_cell(k), default, k.description]
            out.append("| " + " | ".join(_cell(c) for c in cells) + " |")
        if t.groups:
            out.append("")
            for group, needed in t.groups:
                keys = ", ".join(f"`{g}`" for g in group)
                out.append(f"- {'exactly' if needed else 'at most'} one of {keys}")
        out.append("")
    return "\n".join(out)
