"""An unknown scenario key or table gets the nearest valid one (difflib), not the list of all
~30 keys; a key near none of them still gets the list."""

from __future__ import annotations

import copy
import tomllib
from importlib import resources

import pytest

from rubrotor.errors import ScenarioError
from rubrotor.scenario.load import scenario_from_dict
from rubrotor.scenario.schema import unknown_key_text

BASE = tomllib.loads((resources.files("rubrotor") / "scenarios" / "seal_rub.toml").read_text())


def _message(edit) -> str:
    d = copy.deepcopy(BASE)
    edit(d)
    with pytest.raises(ScenarioError) as info:
        scenario_from_dict(d)
    return str(info.value)


def _rename(table: dict, old: str, new: str) -> None:
    table[new] = table.pop(old)


@pytest.mark.parametrize(
    ("edit", "field", "near"),
    [
        (
            lambda d: _rename(d["contact"][0], "clearance", "clerance"),
            "contact[1].clerance",
            "`clearance`",
        ),
        (
            lambda d: _rename(d["contact"][0], "offset_y", "ofset_y"),
            "contact[1].ofset_y",
            "`offset_y`",
        ),
        (lambda d: _rename(d["bearing"][1], "kyy", "Kyy"), "bearing[2].Kyy", "`kyy`"),
        (lambda d: _rename(d["speed"], "rpm", "rmp"), "speed.rmp", "`rpm`"),
        (lambda d: _rename(d["gravity"], "y", "yy"), "gravity.yy", "`y`"),
        (lambda d: _rename(d["initial"], "state", "stat"), "initial.stat", "`state`"),
        (lambda d: _rename(d, "contact", "contcat"), "contcat", "`contact`"),
        (
            lambda d: _rename(d["disk"][0], "outer_diameter", "outer_diamter"),
            "disk[1].outer_diamter",
            "`outer_diameter`",
        ),
    ],
)
def test_a_typo_gets_the_nearest_key(edit, field, near):
    msg = _message(edit)
    assert msg.startswith(field + " = ")
    assert msg.endswith(f"did you mean {near}?")


def test_a_key_near_none_gets_the_list_once():
    msg = _message(lambda d: _rename(d["contact"][0], "offset_y", "xyz"))
    assert "one of the keys law, position" in msg
    listed = msg.split("one of the keys ")[1].split(" of [[contact]]")[0].split(", ")
    assert len(listed) == len(set(listed)) and "offset_y" in listed


def test_ties_are_all_named():
    assert unknown_key_text("kzy_", ("kyz", "kzy", "kzz"), "[bearing]").endswith(
        "did you mean `kzy`?"
    )
    # "kxy" shares two of three letters with both (ratio 2 * 2 / 6)
    assert (
        unknown_key_text("kxy", ("kyy", "kxx"), "[t]")
        == "a key of [t]: did you mean `kyy` or `kxx`?"
    )
