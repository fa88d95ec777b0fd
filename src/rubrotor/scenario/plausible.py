"""Plausibility checks across keys: the unit slips one key's range cannot see.

Each key of a scenario is checked alone against its widest range by
:func:`rubrotor.scenario.schema.check_value`; a clearance of 0.25 m, a diameter of 90 m or a
speed of 6000 rad/s each pass that check, and only their relation to other keys shows the slip
(mm written as m, rpm written as rad/s, g as kg). :func:`check` compares them, once, when a
scenario is loaded (:func:`rubrotor.scenario.scenario_from_dict`), before any mesh is built:

========================  ========================================================================
check                     what is compared
========================  ========================================================================
clearance_vs_radius       each contact's radial clearance against the shaft (or seal) radius there
diameter_vs_length        each section's and disk's diameter against the rotor's length; the
                          rotor's length against the longest machine trains
disk_mass_vs_dimensions   a lumped disk's mass against the width a steel disk of that mass and
                          polar inertia would have (``w = m^2 / (2 pi rho Ip)``)
speed_vs_surface          the spin speed against the surface speed it gives the largest radius
bearing_sag               the bearings' vertical stiffness against the mean static sag of the
                          rotor's weight on them (``W / sum k``)
unbalance_grade           the unbalance against ISO 21940-11 balance grades (``G = e Omega``,
                          ``e = U / m``)
========================  ========================================================================

A finding either refuses the scenario (:class:`rubrotor.errors.ScenarioError`, exit status 2 at
the command line) or warns (:class:`PlausibilityWarning`). Each message names the key, its value,
what it implies and the likely slip. A deliberate study switches a check off by name in the
scenario file::

    [checks]
    skip = ["clearance_vs_radius"]
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from rubrotor.errors import InputError, ScenarioError

__all__ = ["CHECKS", "Finding", "PlausibilityWarning", "findings", "check"]

CHECKS: dict[str, str] = {
    "clearance_vs_radius": "contact clearance against the shaft radius at its station",
    "diameter_vs_length": "section and disk diameters against the rotor's length",
    "disk_mass_vs_dimensions": "lumped disk mass against the width its inertia implies",
    "speed_vs_surface": "spin speed against the surface speed it implies",
    "bearing_sag": "bearing stiffness against the static sag of the rotor's weight",
    "unbalance_grade": "unbalance against ISO 21940-11 balance grades",
}
"""The checks by name (the names ``[checks] skip`` accepts) and what each compares."""

# Limits. Refuse: no machine has it (a unit slip); warn: possible, but rare enough to say so.
CLEARANCE_RATIO = (0.05, 0.5)
"""Radial clearance / radius (1): warn above the first, refuse above the second (seals and
bearings run at 1e-3, touchdown bearings at about 1e-2; a casing or a contact parked out of
reach in a study may stand well off, but a gap wider than half the radius is a unit slip)."""
DIAMETER_RATIO = 2.0
"""A section or disk diameter above this many rotor lengths (1) is refused."""
ROTOR_LENGTH = 100.0
"""A rotor longer than this (m) is refused (the longest turbine-generator trains are ~60 m)."""
DISK_WIDTH_RATIO = 2.0
"""A lumped disk whose implied steel width exceeds this many rotor lengths (1) is refused."""
SURFACE_SPEED = (600.0, 800.0)
"""Surface speed (m/s): warn above the first (beyond steel impellers), refuse above the second
(the centre stress ``(3 + nu)/8 rho v^2`` of a solid steel disk then exceeds 2 GPa). Checked
on general rotors when the speed is given in rad/s, rpm or Hz (a multiple of a critical speed
has no unit to slip; the seed's uniform ``[shaft]`` runs at 2.4 times its first critical, 800
m/s on its surface, and its studies continue the speed further)."""
SAG = (1e-3, 3e-3)
"""Mean static sag (m) on the bearings: warn above the first, refuse above the second (bearing
clearances are 1e-4 to 1e-3 of the shaft diameter; ROSS's example rotors, on 1e6 N/m
supports, sag about 0.5 mm)."""
BALANCE_GRADE = (1e4, 1e5)
"""ISO 21940-11 grade ``G = e Omega`` (mm/s): warn above 2.5 times the coarsest grade of the
standard, G 4000 (rub studies go far beyond turbomachinery's G 2.5 on purpose: the seed cases
run at G 2085, and studies double their unbalance), refuse above 25 times it (a g mm figure in
kg m gives G in the millions). A mass eccentricity beyond the rotor's outer radius is refused at
any speed."""
_STEEL = 7850.0  # kg/m^3, the density a lumped disk is compared with (or a denser material)
_G = 9.81  # m/s^2, gravity when the scenario has none (the weight the bearings would carry)


class PlausibilityWarning(UserWarning):
    """A scenario value that is possible but unusual enough to say so (see :func:`check`)."""


@dataclass(frozen=True)
class Finding:
    """One implausible value.

    Parameters
    ----------
    check : str
        Name of the check (a key of :data:`CHECKS`).
    field : str
        The scenario key, e.g. ``"contact[1].clearance"``.
    value : float
        Its value, in the key's unit.
    message : str
        What the value implies and the likely slip.
    refuse : bool
        True: the scenario is refused; False: a warning.
    """

    check: str
    field: str
    value: float
    message: str
    refuse: bool


def _field(spec: dict, table: str, index: int, key: str) -> str:
    """``table[i].key`` (counted from 1) for an array of tables, ``table.key`` for one table."""
    return f"{table}[{index + 1}].{key}" if isinstance(spec.get(table), list) else f"{table}.{key}"


def _rows(spec: dict, table: str) -> list:
    """The tables ``[table]`` / ``[[table]]`` of the spec, as a list."""
    rows = spec.get(table, [])
    return rows if isinstance(rows, list) else [rows]


def _dimensionless(spec: dict, table: str, index: int, key: str) -> bool:
    """Whether ``table[index]`` gives ``key`` in the seed's dimensionless form (``key_nd``):
    such a value has no unit to slip, and resolves with the speed (a sweep of the speed at a
    fixed ``magnitude_nd`` moves the unbalance in kg m on purpose)."""
    rows = _rows(spec, table)
    return index < len(rows) and f"{key}_nd" in rows[index]


def _skip_text(name: str) -> str:
    return f' (if deliberate: [checks] skip = ["{name}"])'


@dataclass(frozen=True)
class _Geometry:
    """What the checks need of the rotor: length (m), radius at a station (m), outer radius
    (m), mass (kg), densest material (kg/m^3)."""

    length: float
    spans: tuple  # (start, end, radius) in m
    rim: float
    mass: float
    density: float

    def radius_at(self, x: float) -> float:
        inside = [r for a, b, r in self.spans if a - 1e-9 <= x <= b + 1e-9]
        return max(inside) if inside else max(r for _, _, r in self.spans)


def _geometry(sc) -> _Geometry:
    if sc.rotor is None:
        s = sc.shaft
        r = s.diameter / 2
        return _Geometry(s.length, ((0.0, s.length, r),), r, s.mass_per_length * s.length,
                         s.density)  # fmt: skip
    rot = sc.rotor
    spans, x = [], 0.0
    for s in rot.shaft_sections:
        spans.append((x, x + s.length, s.diameter / 2))
        x += s.length
    spans += [(v.position, v.position + v.length, v.diameter / 2) for v in rot.sleeves]
    rims = [r for *_, r in spans]
    disks = sc._spec.get("disk", []) if sc._spec else []
    for d, row in zip(rot.disks, disks if isinstance(disks, list) else [disks], strict=False):
        if "outer_diameter" in row:
            rims.append(row["outer_diameter"] / 2)
        elif d.mass > 0:
            rims.append(math.sqrt(2 * d.polar_inertia / d.mass))
    dens = max([_STEEL, *(s.material.density for s in rot.sections)])
    return _Geometry(rot.length, tuple(spans), max(rims), rot.mass, dens)


def _clearance(sc, geo: _Geometry, spec: dict) -> list[Finding]:
    out = []
    for i, c in enumerate(sc.contacts):
        if _dimensionless(spec, "contact", i, "clearance"):
            continue
        r = c.radius if getattr(c, "radius", None) else geo.radius_at(c.position)
        ratio = c.clearance / r
        if ratio <= CLEARANCE_RATIO[0]:
            continue
        refuse = ratio > CLEARANCE_RATIO[1]
        name = _field(spec, "contact", i, "clearance")
        v = c.clearance
        msg = (
            f"{name} = {v:g} m: a radial clearance of {ratio:.3g} times the {r:.4g} m "
            f"radius at x = {c.position:g} m (seals and bearings run at about 0.001)"
        )
        if refuse:
            msg += f": did you mean {v:g} mm = {v * 1e-3:g} m?"
        out.append(Finding("clearance_vs_radius", name, v, msg, refuse))
    return out


def _diameters(sc, geo: _Geometry, spec: dict) -> list[Finding]:
    out = []
    if geo.length > ROTOR_LENGTH:
        table = "shaft" if sc.rotor is None else "section"
        name = f"{table}.length" if sc.rotor is None else "section[*].length"
        msg = (
            f"{name}: a rotor {geo.length:g} m long (the longest machine trains are about "
            f"60 m): are the lengths in mm? {geo.length:g} mm = {geo.length * 1e-3:g} m"
        )
        out.append(Finding("diameter_vs_length", name, geo.length, msg, True))
    rows = []
    if sc.rotor is None:
        rows.append(("shaft.diameter", sc.shaft.diameter, "shaft"))
    else:
        for i, row in enumerate(spec.get("section", [])):
            rows.append((f"section[{i + 1}].diameter", row["diameter"], "section"))
        disks = spec.get("disk", [])
        for i, row in enumerate(disks if isinstance(disks, list) else [disks]):
            if "outer_diameter" in row:
                rows.append((f"disk[{i + 1}].outer_diameter", row["outer_diameter"], "disk"))
    for name, d, what in rows:
        if d > DIAMETER_RATIO * geo.length:
            msg = (
                f"{name} = {d:g} m: a {what} {d / geo.length:.3g} times as wide as the "
                f"rotor is long ({geo.length:.4g} m): did you mean {d:g} mm = {d * 1e-3:g} m?"
            )
            out.append(Finding("diameter_vs_length", name, d, msg, True))
    return out


def _disk_mass(sc, geo: _Geometry, spec: dict) -> list[Finding]:
    if sc.rotor is None:
        return []
    out = []
    disks = spec.get("disk", [])
    for i, (d, row) in enumerate(zip(sc.rotor.disks, disks if isinstance(disks, list)
                                     else [disks], strict=False)):  # fmt: skip
        if "mass" not in row or d.mass <= 0:
            continue
        if d.polar_inertia > 0:
            width = d.mass**2 / (2 * math.pi * geo.density * d.polar_inertia)
            implied = (
                f"a uniform disk of density {geo.density:g} kg/m^3 with that mass and "
                f"polar inertia {d.polar_inertia:g} kg m^2 is {width:.3g} m wide"
            )
        else:
            width = d.mass / (geo.density * geo.length**2)
            implied = (
                f"a block of density {geo.density:g} kg/m^3 as wide as the rotor is long "
                f"would be {width:.3g} m thick"
            )
        if width > DISK_WIDTH_RATIO * geo.length:
            name = _field(spec, "disk", i, "mass")
            msg = (
                f"{name} = {d.mass:g} kg: {implied}, on a {geo.length:.4g} m rotor: did you "
                f"mean {d.mass:g} g = {d.mass * 1e-3:g} kg?"
            )
            out.append(Finding("disk_mass_vs_dimensions", name, d.mass, msg, True))
    return out


def _speed(sc, geo: _Geometry, spec: dict) -> list[Finding]:
    omega = max(abs(sc.speed), abs(getattr(sc.engine, "speed_end", None) or 0.0))
    v = omega * geo.rim
    if v <= SURFACE_SPEED[0]:
        return []
    key, given = sc.speed_spec
    if key not in ("rad_per_s", "rpm", "hz") or sc.rotor is None:
        return []
    refuse = v > SURFACE_SPEED[1]
    name = f"speed.{key}"
    msg = (
        f"{name} = {given:g}: {omega:.4g} rad/s moves the {geo.rim:.4g} m radius at "
        f"{v:.4g} m/s (steel impellers stay below about 600 m/s)"
    )
    if refuse and key in ("rad_per_s", "hz"):
        unit = "rad/s" if key == "rad_per_s" else "Hz"
        msg += (
            f": is {given:g} an rpm figure in a {unit} key? {given:g} rpm = "
            f"{given * 2 * math.pi / 60:.4g} rad/s"
        )
    out = [Finding("speed_vs_surface", name, float(given), msg, refuse)]
    return out


def _vertical(sc) -> tuple[str, float]:
    g = sc.gravity
    if not g or (g[0] == 0 and g[1] == 0):
        return "y", _G
    return ("y", abs(g[0])) if abs(g[0]) >= abs(g[1]) else ("z", abs(g[1]))


def _sag(sc, geo: _Geometry, spec: dict) -> list[Finding]:
    if sc.rotor is None:
        return []
    axis, g = _vertical(sc)
    key = "kyy" if axis == "y" else "kzz"
    stiff = []
    for i, b in enumerate(sc.rotor.bearings):
        if getattr(b, "kind", "bearing") == "pinned":
            return []  # a pinned support: no sag
        if getattr(b, "kind", "bearing") != "bearing" or getattr(b, "link", None):
            continue
        k = getattr(b, key, None)
        if k is None:
            continue  # a bearing type without linear coefficients
        values = [float(x) for x in (k if isinstance(k, list | tuple) else [k])]
        if hasattr(k, "__len__") and not isinstance(k, list | tuple):
            values = [float(x) for x in k]
        stiff.append((i, max(values)))
    total = sum(k for _, k in stiff)
    if total <= 0:
        return []
    weight = (geo.mass + sum(getattr(p, f"mass_{axis}", 0.0) for p in sc.rotor.point_masses)) * g
    sag = weight / total
    if sag <= SAG[0]:
        return []
    refuse = sag > SAG[1]
    i, k = min(stiff, key=lambda t: t[1])
    name = f"bearing[{i + 1}].{key}"
    msg = (
        f"{name} = {k:g} N/m: the rotor's weight {weight:.4g} N on {len(stiff)} bearings of "
        f"total {key} {total:.4g} N/m sags {sag * 1e3:.3g} mm on average (fluid-film and "
        f"rolling bearings: micrometres to a tenth of a millimetre)"
    )
    if refuse:
        msg += f": did you mean {k:g} N/mm = {k * 1e3:g} N/m?"
    return [Finding("bearing_sag", name, k, msg, refuse)]


def _unbalance(sc, geo: _Geometry, spec: dict) -> list[Finding]:
    planes = sc.unbalances
    if not planes or geo.mass <= 0 or any(_dimensionless(spec, "unbalance", i, "magnitude")
                                          for i in range(len(planes))):  # fmt: skip
        return []
    total = sum(abs(u.magnitude) for u in planes)
    i, big = max(enumerate(planes), key=lambda t: abs(t[1].magnitude))
    name = _field(spec, "unbalance", i, "magnitude")
    e = total / geo.mass
    omega = max(abs(sc.speed), abs(getattr(sc.engine, "speed_end", None) or 0.0))
    grade = e * omega * 1e3  # mm/s
    slip = f": did you mean {big.magnitude:g} g mm = {big.magnitude * 1e-6:g} kg m?"
    u = big.magnitude
    if e > geo.rim:
        msg = (
            f"{name} = {u:g} kg m: a mass eccentricity U / m = {e:.4g} m on the "
            f"{geo.mass:.4g} kg rotor, beyond its {geo.rim:.4g} m outer radius" + slip
        )
        return [Finding("unbalance_grade", name, u, msg, True)]
    if grade <= BALANCE_GRADE[0]:
        return []
    refuse = grade > BALANCE_GRADE[1]
    msg = (
        f"{name} = {u:g} kg m: eccentricity e = U / m = {e:.4g} m on the {geo.mass:.4g} kg "
        f"rotor, balance grade G = e Omega = {grade:.4g} mm/s at {omega:.4g} rad/s "
        f"(ISO 21940-11: G 2.5 to G 6.3 for turbomachinery, G 4000 the coarsest grade)"
    )
    return [Finding("unbalance_grade", name, u, msg + (slip if refuse else ""), refuse)]


_RULES = {
    "clearance_vs_radius": _clearance,
    "diameter_vs_length": _diameters,
    "disk_mass_vs_dimensions": _disk_mass,
    "speed_vs_surface": _speed,
    "bearing_sag": _sag,
    "unbalance_grade": _unbalance,
}


def findings(scenario, skip=()) -> list[Finding]:
    """Every implausible value of a scenario, in the order of :data:`CHECKS`.

    Parameters
    ----------
    scenario : rubrotor.Scenario
        A built scenario (nothing is meshed or solved: the checks use its keys, masses and
        radii only).
    skip : iterable of str
        Names of checks (keys of :data:`CHECKS`) not to run.

    Returns
    -------
    list of Finding
    """
    if not hasattr(scenario, "_spec") or not hasattr(scenario, "contacts"):
        raise InputError("scenario", scenario, "a built rubrotor.Scenario")
    if isinstance(skip, str) or any(name not in CHECKS for name in skip):
        raise InputError("skip", skip, "names of checks: " + ", ".join(CHECKS))
    spec = scenario._spec or {}
    skip = set(skip) | set(spec.get("checks", {}).get("skip", ()))
    geo = _geometry(scenario)
    # the diameters first: the other checks' radii and masses mean little if they are wrong
    order = ["diameter_vs_length", *(n for n in CHECKS if n != "diameter_vs_length")]
    out = []
    for name in order:
        if name not in skip:
            out += _RULES[name](scenario, geo, spec)
    return out


def check(scenario, skip=()) -> None:
    """Refuse or warn on the implausible values of a scenario (see :func:`findings`).

    Raises
    ------
    ScenarioError
        For the first refused finding: naming its key and value, what it implies, the likely
        slip and how to switch the check off.

    Warns
    -----
    PlausibilityWarning
        For each finding that is only unusual.
    """
    found = findings(scenario, skip)
    for f in found:
        if f.refuse:
            err = ScenarioError(f.field, f.value, "a plausible value")
            err.args = (f"implausible {f.message}{_skip_text(f.check)}",)
            raise err
    for f in found:
        warnings.warn(f"{f.message}{_skip_text(f.check)}", PlausibilityWarning, stacklevel=3)
