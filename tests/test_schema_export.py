"""The JSON Schema of scenario files: generated from the validation's tables, shipped up to date,
accepts every shipped scenario and rejects what :func:`rubrotor.load_scenario` rejects for the
structural reasons it encodes (unknown section or key, wrong kind of value, two alternatives)."""

from __future__ import annotations

import copy
import json
import math
import tomllib
from importlib import resources

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from rubrotor.errors import InputError
from rubrotor.scenario import SCHEMA, scenario_from_dict
from rubrotor.scenario.export import SCHEMA_FILE, scenario_json_schema
from rubrotor.scenario.schema import KEYS, TABLES

jsonschema = pytest.importorskip("jsonschema")

TABLE_NAMES = {t.name for t in TABLES}
SHIPPED = sorted(
    p for p in (resources.files("rubrotor") / "scenarios").iterdir() if p.name.endswith(".toml")
)


@pytest.fixture(scope="module")
def validator():
    schema = scenario_json_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def test_shipped_file_is_the_generated_schema():
    """Regenerate with ``python -m rubrotor.scenario.export`` when the tables change."""
    assert json.loads(SCHEMA_FILE.read_text()) == scenario_json_schema()


def test_table_or_array_form_accepts_both():
    """A table that may be repeated (``[contact]`` or ``[[contact]]``, form ``"table|array"``)
    validates as one table or as an array of them, with the same key rules."""
    from rubrotor.scenario.export import _form
    from rubrotor.scenario.schema import Table

    schema = _form(Table("contact", "table|array", "any", "a test table"))
    check = jsonschema.Draft202012Validator(schema)
    one = {"clearance": 1e-3, "stiffness": 1e9}
    assert check.is_valid(one) and check.is_valid([one, one])
    assert not check.is_valid({"clearance": -1.0}) and not check.is_valid([{"gap": 1.0}])


def test_ranges_of_the_rows_are_in_the_schema(validator):
    """Each numeric key of seed case 1 set one ulp beyond a bound of its row is refused by the
    schema (the same bound the loader applies, checked in tests/test_schema.py)."""
    import math

    from rubrotor.scenario.schema import key_row

    refused = 0
    for section, body in _case1().items():
        for key in body:
            row = key_row(section, key)
            if row.kind != "number":
                continue
            for bound, outward in ((row.minimum, -math.inf), (row.maximum, math.inf)):
                if bound is None or (bound == 0 and row.zero):
                    continue
                d = _case1()
                d[section][key] = math.nextafter(float(bound), outward)
                if d[section][key] == 0 and row.zero:
                    continue
                assert not validator.is_valid(d), (section, key, d[section][key])
                refused += 1
    assert refused >= 10


def test_every_key_of_the_validation_tables_is_in_the_schema():
    props = scenario_json_schema()["properties"]
    for section, keys in SCHEMA.items():
        body = props[section]
        body = body["oneOf"][0] if "oneOf" in body else body  # [t] or [[t]]: the table itself
        assert set(body["properties"]) == set(keys)
    assert "(m)" in props["shaft"]["properties"]["length"]["description"]


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.name)
def test_shipped_scenarios_are_valid(path, validator):
    assert list(validator.iter_errors(tomllib.loads(path.read_text()))) == []


def _case1():
    path = next(p for p in SHIPPED if p.name == "seed_case1.toml")
    return tomllib.loads(path.read_text())


def _mutants():
    out = {}
    d = _case1()
    d["shaft"]["lenght"] = 0.4
    out["unknown key"] = d
    d = _case1()
    d["shafts"] = {}
    out["unknown section"] = d
    d = _case1()
    d["shaft"]["length"] = "long"
    out["string for a number"] = d
    d = _case1()
    d["shaft"]["modes"] = 2.5
    out["float for an int"] = d
    d = _case1()
    d["speed"]["rpm"] = 1000.0
    out["two speeds"] = d
    d = _case1()
    del d["shaft"]["density"]
    out["required key missing"] = d
    d = _case1()
    del d["speed"]
    out["no speed"] = d
    for section, key, value in (
        ("shaft", "diameter", 1e300),
        ("shaft", "length", 0.0),
        ("shaft", "modes", 0),
        ("contact", "friction", -0.1),
        ("contact", "law", "glue"),
        ("contact", "friction_sign", 1.0),
        ("damping", "ratio", [0.01, 1.0]),
        ("simulation", "method", "rk4"),
    ):
        d = _case1()
        d.setdefault(section, {})[key] = value
        out[f"{section}.{key} = {value!r}"] = d
    d = _case1()
    d["disk"] = [{"position": 0.2, "mass": 1.0}]
    out["general-rotor table with [shaft]"] = d
    return out


@pytest.mark.parametrize("name", list(_mutants()))
def test_structural_errors_are_rejected_by_schema_and_loader(name, validator):
    """Both routes refuse the same mangled scenario: the schema (what an editor shows) and the
    loader (what the CLI says)."""
    data = _mutants()[name]
    assert list(validator.iter_errors(copy.deepcopy(data)))
    with pytest.raises(InputError):
        scenario_from_dict(data)


def _slot(doc: dict, table: str):
    """The body of ``table`` in ``doc`` to put a key in (first item of an array, first label)."""
    body = doc[table]
    if isinstance(body, list):
        return body[0]
    if table == "materials":
        return next(iter(body.values()))
    return body


_VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, 0.0, -1.0, 1, 3, 1e-9, 0.5, 1e3, 1e16, 1e300, math.nextafter(0.0, 1.0)]),
    st.integers(min_value=-3, max_value=20_000),
    st.booleans(),
    st.sampled_from(["", "x", "hertz", "seed", "cowper", "rest", "abm", "pinned"]),
    st.lists(st.floats(min_value=-1.0, max_value=1e4), max_size=3),
)


@settings(
    max_examples=300,
    deadline=None,
    derandomize=True,  # the same 300 examples on every run (CI is reproducible)
    suppress_health_check=[HealthCheck.too_slow],
)
@given(data=st.data())
def test_the_schema_never_refuses_what_the_loader_accepts(validator, data):
    """One key of a shipped scenario set to an arbitrary value (or removed): whenever the JSON
    Schema refuses the result, the loader refuses it too (with an :class:`InputError`), so an
    editor never flags a scenario rubrotor would run. (The loader may refuse more: rules across
    keys are not in the schema.)"""
    path = data.draw(st.sampled_from(SHIPPED), label="scenario")
    doc = tomllib.loads(path.read_text())
    table = data.draw(st.sampled_from(sorted(t for t in doc if t in TABLE_NAMES)), label="table")
    body = _slot(doc, table)
    keys = [k.key for k in KEYS if k.table == table]
    key = data.draw(st.sampled_from(keys), label="key")
    if data.draw(st.booleans(), label="remove"):
        body.pop(key, None)
    else:
        body[key] = data.draw(_VALUES, label="value")
    if validator.is_valid(copy.deepcopy(doc)):
        event("accepted by the schema")
        return
    event("refused by the schema")
    with pytest.raises(InputError):
        scenario_from_dict(doc)
