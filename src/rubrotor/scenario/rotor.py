"""Scenario tables of a general rotor: ``[materials.NAME]``, ``[[section]]``, ``[[disk]]``,
``[[bearing]]`` and ``[rotor]``, checked key by key and built into a :class:`rubrotor.rotors.fe.Rotor`.

Schema (SI units; every key is a row of :mod:`rubrotor.scenario.schema`, with its kind, unit, range and
description)::

    [materials.NAME]  youngs_modulus (Pa); density (kg/m^3); poisson_ratio | shear_modulus (Pa)
    [[section]]       length (m); diameter (m); bore_diameter (m, default 0); material (a NAME);
                      elements (optional, default from the mesh rule)
    [[disk]]          position (m); mass (kg), polar_inertia, diametral_inertia (kg m^2, default 0)
                      | outer_diameter (m), width (m), material, bore_diameter (m); name;
                      width (m) is also allowed with the mass form (overlap checks only)
    [[bearing]]       position (m); kyy, kyz, kzy, kzz (N/m); cyy, cyz, czy, czz (N s/m): numbers,
                      or lists tabulated against speeds or frequencies (rad/s); interpolation,
                      extrapolation; myy, myz, mzz (kg); link, on (a point mass); kind
                      ("bearing" | "pinned"); name; type ("coefficients", or a support model of
                      rubrotor.forces.supports, e.g. "muszynska" with fluid_stiffness,
                      fluid_damping, swirl_ratio)
    [[point_mass]]    name; position (m); mass_y, mass_z (kg)
    [rotor]           theory; gyroscopic; shear_coefficient; max_element_length (m)  (optional)

Errors name the key as ``materials.steel.density``, ``section[2].diameter``, ``disk[1].mass``,
``bearing[1].kyy`` (tables counted from 1 in file order) or ``rotor.theory``.
"""

from __future__ import annotations

from collections.abc import Mapping

from rubrotor.errors import InputError, ScenarioError
from rubrotor.forces.supports import support_term
from rubrotor.rotors.fe import COEFFICIENTS, Disk, Material, PointMass, Rotor, Section
from rubrotor.scenario.schema import (
    REQUIRED,
    ROTOR_SCHEMA,
    ROTOR_TABLES,
    check_value,
    key_row,
    unknown_key_text,
)

__all__ = ["ROTOR_TABLES", "ROTOR_SCHEMA", "normalise_rotor_tables", "build_rotor", "rotor_to_dict"]

_MASS_KEYS = ("mass", "polar_inertia", "diametral_inertia")
_GEOMETRY_KEYS = ("outer_diameter", "material", "bore_diameter")


def _keys(name: str, body, table: str) -> dict:
    """Check one table's keys, kinds and ranges (rows of :mod:`rubrotor.scenario.schema`); ``name`` is
    how errors call it."""
    if not isinstance(body, Mapping):
        raise ScenarioError(name, body, "a table of keys")
    allowed = ROTOR_SCHEMA[table]
    out = {}
    for key, value in body.items():
        if key not in allowed:
            raise ScenarioError(f"{name}.{key}", value, unknown_key_text(key, allowed, f"[{table}]"))
        out[key] = check_value(f"{name}.{key}", value, key_row(table, key))
    for key in REQUIRED.get(table, ()):
        if key not in out:
            raise ScenarioError(f"{name}.{key}", None, "a value (this key is required)")
    return out


def normalise_rotor_tables(mapping: Mapping) -> dict:
    """Check the general-rotor tables of a scenario mapping; return them as plain dicts.

    Parameters
    ----------
    mapping : Mapping
        The whole scenario; only the keys of :data:`ROTOR_TABLES` are read.

    Returns
    -------
    dict
        ``{"materials": {NAME: {...}}, "section": [...], "disk": [...], "bearing": [...],
        "rotor": {...}}`` with the tables present.
    """
    out: dict = {}
    if "materials" in mapping:
        mats = mapping["materials"]
        if not isinstance(mats, Mapping) or not mats:
            raise ScenarioError("materials", mats, "tables [materials.NAME] of material keys")
        out["materials"] = {
            str(n): _keys(f"materials.{n}", body, "materials") for n, body in mats.items()
        }
    for table in ("section", "disk", "bearing", "point_mass"):
        if table not in mapping:
            continue
        items = mapping[table]
        if not isinstance(items, list) or not items:
            raise ScenarioError(table, items, f"an array of tables [[{table}]]")
        out[table] = [_keys(f"{table}[{i + 1}]", body, table) for i, body in enumerate(items)]
    if "rotor" in mapping:
        out["rotor"] = _keys("rotor", mapping["rotor"], "rotor")
    if "section" not in out:
        present = ", ".join(f"[{t}]" for t in out)
        raise ScenarioError("section", None, f"[[section]] tables with {present}")
    return out


def _renamed(exc: InputError, name: str) -> ScenarioError:
    """``exc`` with its field put under ``name`` (``section.length`` -> ``section[2].length``)."""
    field = exc.field
    if field.split(".")[0] in ("section", "disk", "bearing"):
        field = f"{name}.{field.partition('.')[2]}"
    return ScenarioError(field, exc.value, exc.allowed)


def _materials(spec: dict) -> dict[str, Material]:
    out = {}
    for name, m in spec.get("materials", {}).items():
        out[name] = Material(
            name,
            m["youngs_modulus"],
            m["density"],
            shear_modulus=m.get("shear_modulus"),
            poisson_ratio=m.get("poisson_ratio"),
        )
    return out


def _material(materials: dict, name: str, value) -> Material:
    if value not in materials:
        known = ", ".join(materials) or "none defined: add a [materials.NAME] table"
        raise ScenarioError(name, value, f"one of the materials {known}")
    return materials[value]


def _disk(d: dict, name: str, materials: dict) -> Disk:
    geometry = [k for k in _GEOMETRY_KEYS if k in d]
    lumped = [k for k in _MASS_KEYS if k in d]
    if geometry and lumped:
        raise ScenarioError(
            f"{name}.{geometry[0]}",
            d[geometry[0]],
            "either mass, polar_inertia, diametral_inertia or the geometry outer_diameter, "
            "width, material, bore_diameter, not both (width may go with either)",
        )
    if not geometry:
        if "mass" not in d:
            raise ScenarioError(f"{name}.mass", None, "a value (or the disk geometry)")
        return Disk(
            d["position"],
            d["mass"],
            d.get("polar_inertia", 0.0),
            d.get("diametral_inertia", 0.0),
            width=d.get("width", 0.0),
            name=d.get("name", ""),
        )
    for key in ("outer_diameter", "width", "material"):
        if key not in d:
            raise ScenarioError(f"{name}.{key}", None, "a value (disk given by its geometry)")
    return Disk.from_geometry(
        d["position"],
        d["outer_diameter"],
        d["width"],
        _material(materials, f"{name}.material", d["material"]),
        d.get("bore_diameter", 0.0),
        name=d.get("name", ""),
    )


def _bearing(b: dict):
    """The support term of a ``[[bearing]]`` table, by its ``type`` (a :class:`Bearing` of
    coefficients by default; :data:`rubrotor.forces.supports.SUPPORT_TYPES`)."""
    return support_term(b)


def build_rotor(spec: dict) -> Rotor:
    """The :class:`Rotor` of normalised tables (see :func:`normalise_rotor_tables`).

    Raises
    ------
    ScenarioError
        Naming the key (``section[2].diameter``, ``bearing``, ``disk[1].position`` ...).
    """
    try:
        materials = _materials(spec)
    except InputError as exc:
        raise ScenarioError(exc.field, exc.value, exc.allowed) from None
    parts: dict = {"section": [], "disk": [], "bearing": [], "point_mass": []}
    for table in parts:
        for i, item in enumerate(spec.get(table, [])):
            name = f"{table}[{i + 1}]"
            try:
                if table == "section":
                    mat = _material(materials, f"{name}.material", item["material"])
                    kw = {k: v for k, v in item.items() if k != "material"}
                    parts[table].append(Section(material=mat, **kw))
                elif table == "disk":
                    parts[table].append(_disk(item, name, materials))
                elif table == "point_mass":
                    parts[table].append(PointMass(**item))
                else:
                    parts[table].append(_bearing(item))
            except InputError as exc:
                raise _renamed(exc, name) from None
    try:
        return Rotor(parts["section"], parts["disk"], parts["bearing"],
                     point_masses=parts["point_mass"], **spec.get("rotor", {}))  # fmt: skip
    except InputError as exc:
        raise ScenarioError(exc.field, exc.value, exc.allowed) from None


def rotor_to_dict(rotor: Rotor) -> dict:
    """Tables that :func:`build_rotor` turns back into ``rotor`` (disks as mass, SI values)."""
    materials = {}
    sections = []
    for s in rotor.sections:
        m = s.material
        mat = {"youngs_modulus": m.youngs_modulus, "density": m.density}
        if m.shear_modulus is not None:
            mat["shear_modulus"] = m.shear_modulus
        else:
            mat["poisson_ratio"] = m.poisson_ratio
        materials[m.name] = mat
        sec = {"length": s.length, "diameter": s.diameter, "bore_diameter": s.bore_diameter}
        sec["material"] = m.name
        if s.elements is not None:
            sec["elements"] = s.elements
        for key in ("position", "mass_damping", "stiffness_damping"):
            if getattr(s, key):  # None or 0: the default
                sec[key] = getattr(s, key)
        sections.append(sec)
    disks = [
        {
            "position": d.position,
            "mass": d.mass,
            "polar_inertia": d.polar_inertia,
            "diametral_inertia": d.diametral_inertia,
            "width": d.width,
            "name": d.name,
        }
        for d in rotor.disks
    ]
    bearings = []
    for b in rotor.bearings:
        if hasattr(b, "table_entry"):  # a support term that writes its own table
            bearings.append(b.table_entry())
            continue
        item = {"position": b.position, "kind": b.kind, "name": b.name}
        for c in COEFFICIENTS if b.kind != "pinned" else ():
            v = getattr(b, c)
            item[c] = list(v) if not isinstance(v, int | float) else v
        if b.speeds is not None:
            item["speeds"] = list(b.speeds)
        if b.frequencies is not None:
            item["frequencies"] = list(b.frequencies)
        for key, default in (("interpolation", "linear"), ("extrapolation", "hold"),
                             ("myy", 0.0), ("myz", 0.0), ("mzz", 0.0), ("link", None),
                             ("on", None), ("fail_time", None)):  # fmt: skip
            if getattr(b, key) != default:
                item[key] = getattr(b, key)
        bearings.append(item)
    out = {"materials": materials, "section": sections, "bearing": bearings}
    if disks:
        out["disk"] = disks
    if rotor.point_masses:
        out["point_mass"] = [
            {"name": p.name, "position": p.position, "mass_y": p.mass_y, "mass_z": p.mass_z}
            for p in rotor.point_masses
        ]
    out["rotor"] = {
        "theory": rotor.theory,
        "gyroscopic": rotor.gyroscopic,
        "shear_coefficient": rotor.shear_coefficient,
    }
    if rotor.max_element_length is not None:
        out["rotor"]["max_element_length"] = rotor.max_element_length
    for key in ("mass_damping", "stiffness_damping"):
        if getattr(rotor, key):
            out["rotor"][key] = getattr(rotor, key)
    return out
