"""The scenario schema as one table of data (:mod:`rubrotor.scenario.schema`): every row is consistent,
and the views the validation uses are generated from the rows."""

from __future__ import annotations

import math

import pytest

from rubrotor.scenario.schema import KEYS, KINDS, TABLES, allowed_text, check_value, key_row


@pytest.mark.parametrize("row", KEYS, ids=lambda k: k.dotted)
def test_every_row_is_consistent(row):
    """Kinds are known, tables exist, choices go with strings only, numbers carry a unit,
    strings and flags none, bounds are ordered, and a default passes the row's own check."""
    assert row.kind in KINDS
    assert row.table in {t.name for t in TABLES}
    assert row.description
    assert not row.choices or row.kind in ("str", "number|str", "strlist")
    assert (row.unit == "") == (row.kind in ("str", "bool", "strlist"))
    if row.minimum is not None and row.maximum is not None:
        assert row.minimum < row.maximum
    if row.default is not None:
        assert check_value(row.dotted, row.default, row) == row.default
    assert not (row.required and row.default is not None)


def test_keys_are_unique_and_groups_name_existing_keys():
    names = [k.dotted for k in KEYS]
    assert len(names) == len(set(names))
    for t in TABLES:
        for group, _ in t.groups:
            for key in group:
                assert key_row(t.name, key)


def _check(row, value):
    """``check_value`` of one number; a list row gets a list of that one number."""
    if row.kind == "list":
        return check_value(row.dotted, [value], row)[0]
    return check_value(row.dotted, value, row)


def test_range_bounds_are_enforced_exactly():
    """At and just beyond each finite bound: closed bounds accept the bound, open ones refuse
    it, and one ulp outside is refused (``math.nextafter``), with the key named."""
    for row in KEYS:
        if row.kind not in ("number", "number|list", "list"):
            continue
        for bound, exclusive, outward in (
            (row.minimum, row.exclusive_minimum, -math.inf),
            (row.maximum, row.exclusive_maximum, math.inf),
        ):
            if bound is None:
                continue
            if not (bound == 0 and row.zero):
                if exclusive:
                    with pytest.raises(ValueError):
                        _check(row, float(bound))
                else:
                    assert _check(row, float(bound)) == bound
            beyond = math.nextafter(float(bound), outward)
            if beyond == 0 and row.zero:
                continue
            with pytest.raises(ValueError, match=row.dotted.replace(".", r"\.")):
                _check(row, beyond)
    assert allowed_text(key_row("shaft", "length")) == "a number in [1e-06, 1000] (m)"


def _object_defaults() -> dict[str, dict]:
    """Defaults of the model objects' own fields, the second source the table must agree with."""
    import dataclasses

    from rubrotor.engine.settings import Integrator
    from rubrotor.rotors.fe import Bearing, Disk, Rotor, Section
    from rubrotor.rotors.forces import Contact, RadialLoad, ThermalBow
    from rubrotor.rotors.shaft import Shaft

    classes = {
        "shaft": Shaft,
        "contact": Contact,
        "load": RadialLoad,
        "simulation": Integrator,
        "rotor": Rotor,
        "section": Section,
        "disk": Disk,
        "bearing": Bearing,
        "thermal": ThermalBow,
    }
    return {
        table: {
            f.name: f.default
            for f in dataclasses.fields(cls)
            # None and () (no probes) mean "not given": the table has no default for those
            if f.default is not dataclasses.MISSING and f.default not in (None, ())
        }
        for table, cls in classes.items()
    }


def test_defaults_are_those_of_the_model_objects():
    """A key's default in the table is the default of the field of the same name of the object
    it builds (``Shaft.modes``, ``Integrator.rtol``, ``Bearing.kyy`` ...); every such field that
    is also a key has its default in the table."""
    import inspect

    from rubrotor.rotors.forces import restitution_damping

    objects = _object_defaults()
    compared = 0
    for row in KEYS:
        fields = objects.get(row.table, {})
        if row.key in fields and not row.required:
            assert row.default == fields[row.key], row.dotted
            compared += 1
    assert compared >= 20
    sig = inspect.signature(restitution_damping)
    assert key_row("contact", "restitution_model").default == sig.parameters["model"].default
    assert key_row("unbalance", "phase_deg").default == 0.0


def test_views_are_generated_from_the_rows():
    """SCHEMA, ROTOR_SCHEMA, KEY_UNITS, REQUIRED and ALTERNATIVES of the loader are the rows,
    regrouped; the loader's module re-exports the same objects."""
    import rubrotor.scenario as sc
    import rubrotor.scenario.rotor as sr
    from rubrotor.scenario import schema

    assert sc.SCHEMA is schema.SCHEMA and sr.ROTOR_SCHEMA is schema.ROTOR_SCHEMA
    assert sc.KEY_UNITS is schema.KEY_UNITS and sc.ALTERNATIVES is schema.ALTERNATIVES
    flat = {f"{t}.{k}": kind for tables in (schema.SCHEMA, schema.ROTOR_SCHEMA)
            for t, keys in tables.items() for k, kind in keys.items()}  # fmt: skip
    assert flat == {k.dotted: k.kind for k in KEYS}
    assert {k for k in flat if flat[k] not in ("str", "bool", "strlist")} == set(schema.KEY_UNITS)
    assert schema.key_unit("contact.clearance") == "m" and schema.key_unit("shaft.kappa") == "1"
    assert schema.REQUIRED["shaft"] == ("length", "youngs_modulus", "density")


def test_docs_table_has_one_row_per_key():
    """The docs page's key tables (docs/conf.py writes them at build time) list every row once,
    under a heading of its table, with its unit and its choices or range."""
    from rubrotor.scenario.schema import markdown_table

    table = None
    seen = []
    for line in markdown_table().splitlines():
        if line.startswith("# "):
            table = line.strip("#` []").split(".")[0]
        elif line.startswith("| `"):
            key = line.split("`")[1]
            row = key_row(table, key)
            seen.append(row)
            assert f"| {row.unit or '-'} |" in line
            if row.choices:
                assert all(f'"{c}"' in line for c in row.choices)
            if row.minimum is not None and row.kind != "int":
                assert f"{row.minimum:g}" in line
    assert seen == list(KEYS)


def _objects():
    """Valid keyword sets of the model objects that check the shared ranges themselves."""
    from rubrotor.rotors.fe import Disk, Material, Section
    from rubrotor.rotors.shaft import Shaft

    steel = Material("steel", 211e9, 7810.0, poisson_ratio=0.3)
    return {
        "shaft": (
            Shaft,
            dict(length=0.4, diameter=0.1, youngs_modulus=71e9, density=2660.0, shear_modulus=26e9),
        ),
        "materials": (
            lambda **kw: Material("m", **kw),
            dict(youngs_modulus=211e9, density=7810.0, shear_modulus=81e9),
        ),
        "section": (Section, dict(length=0.5, diameter=0.05, material=steel)),
        "disk": (Disk, dict(position=0.2, mass=10.0, polar_inertia=0.1, diametral_inertia=0.05)),
    }


@pytest.mark.parametrize("table", ["shaft", "materials", "section", "disk"])
def test_model_objects_refuse_what_the_rows_refuse(table):
    """Second route: the model objects' own checks (``Shaft``, ``Material``, ``Section``,
    ``Disk``) refuse a value one ulp beyond each bound of the row of the same key, naming the
    key, as the rows do; the rows and the objects share their ranges."""
    from rubrotor.errors import InputError

    make, good = _objects()[table]
    make(**good)
    checked = 0
    for key in good:
        if (table, key) not in {(k.table, k.key) for k in KEYS}:
            continue
        row = key_row(table, key)
        for bound, outward in ((row.minimum, -math.inf), (row.maximum, math.inf)):
            if bound is None or row.kind != "number" or key == "position":
                continue
            beyond = math.nextafter(float(bound), outward)
            if beyond == 0 and row.zero:
                continue
            with pytest.raises(ValueError):
                _check(row, beyond)
            with pytest.raises(InputError, match=key):
                make(**{**good, key: beyond})
            checked += 1
    assert checked >= 4
