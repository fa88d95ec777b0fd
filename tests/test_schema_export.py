"""The JSON Schema of scenario files: generated from the validation's tables, shipped up to date,
accepts every shipped scenario and rejects what :func:`rubrotor.load_scenario` rejects for the
structural reasons it encodes (unknown section or key, wrong kind of value, two alternatives)."""

from __future__ import annotations

import copy
import json
import tomllib
from importlib import resources

import pytest

from rubrotor.errors import InputError
from rubrotor.scenario import SCHEMA, scenario_from_dict
from rubrotor.schema_export import SCHEMA_FILE, scenario_json_schema

jsonschema = pytest.importorskip("jsonschema")

SHIPPED = sorted(
    p for p in (resources.files("rubrotor") / "scenarios").iterdir() if p.name.endswith(".toml")
)


@pytest.fixture(scope="module")
def validator():
    schema = scenario_json_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def test_shipped_file_is_the_generated_schema():
    """Regenerate with ``python -m rubrotor.schema_export`` when the tables change."""
    assert json.loads(SCHEMA_FILE.read_text()) == scenario_json_schema()


def test_every_key_of_the_validation_tables_is_in_the_schema():
    props = scenario_json_schema()["properties"]
    from rubrotor.scenario_engine import ENGINE_KEYS

    for section, keys in SCHEMA.items():
        new = {k.split(".")[1] for k in ENGINE_KEYS if k.startswith(section + ".")}
        assert set(props[section]["properties"]) == set(keys) | new
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
    return out


@pytest.mark.parametrize("name", list(_mutants()))
def test_structural_errors_are_rejected_by_schema_and_loader(name, validator):
    """Both routes refuse the same mangled scenario: the schema (what an editor shows) and the
    loader (what the CLI says)."""
    data = _mutants()[name]
    assert list(validator.iter_errors(copy.deepcopy(data)))
    with pytest.raises(InputError):
        scenario_from_dict(data)
