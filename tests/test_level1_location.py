"""API 684 Level I's default station: mid-span between the outermost bearings for a
between-bearing rotor (seal_rub), the heaviest overhung disk (the stage) for an overhung one,
said in the result, its JSON and the command's text."""

from __future__ import annotations

import copy
import json
import tomllib
from importlib import resources

import numpy as np
import pytest

import rubrotor
from rubrotor.cli import main
from rubrotor.linear.api684 import default_station, level1
from rubrotor.linear.verbs import linear_system
from rubrotor.scenario.load import scenario_from_dict
from rubrotor.scenario.write import write_scenario

BASE = tomllib.loads((resources.files("rubrotor") / "scenarios" / "seal_rub.toml").read_text())
Q = np.logspace(4, 8, 9)


def test_between_bearing_rotor_takes_mid_span():
    """seal_rub's bearings at 0.05 and 1.25 m: mid-span 0.65 m, not the impeller at 0.45 m.
    The log decs equal Level I run by hand at that station."""
    res = rubrotor.level1("seal_rub", stiffness=Q)
    assert res.location == "mid-span" and res.position == pytest.approx(0.5 * (0.05 + 1.25))
    sc = rubrotor.load_scenario("seal_rub")
    ref = level1(linear_system(sc, (0.65,)), sc.speed, 0.65, Q)
    np.testing.assert_allclose(res.log_dec, ref.log_dec, rtol=1e-9)
    assert res.to_dict()["location"] == "mid-span"
    # the heaviest disk is a given station now, and says so
    assert rubrotor.level1("seal_rub", at=0.45, stiffness=Q).location == "given"


def _overhung() -> dict:
    """seal_rub with its right bearing moved to 0.70 m: the balance disk (15 kg at 0.90 m)
    hangs outside the bearings, the heavier impeller (27.6 kg at 0.45 m) between them."""
    d = copy.deepcopy(BASE)
    d["bearing"][1]["position"] = 0.70
    d["contact"][0]["position"] = 0.60
    return d


def test_overhung_rotor_takes_its_stage(tmp_path, capsys):
    sc = scenario_from_dict(_overhung())
    res = rubrotor.level1(sc, stiffness=Q)
    assert res.location == "overhung stage" and res.position == pytest.approx(0.90)
    path = write_scenario(_overhung(), tmp_path / "overhung.toml")
    assert main(["level1", str(path), "--stiffness", "1e4:1e8:9", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["location"] == "overhung stage" and out["position_m"] == pytest.approx(0.90)
    np.testing.assert_allclose(out["log_dec"], res.log_dec, rtol=1e-9)
    assert main(["level1", str(path), "--stiffness", "1e4:1e8:9"]) == 0
    assert "cross-coupling at x = 0.9 m (overhung stage)" in capsys.readouterr().out


def test_default_station_rules():
    assert default_station([], [], 2.0) == (1.0, "mid-span")  # no bearings: the two ends
    # two overhung disks: the heavier one; a disk on a bearing is not overhung
    assert default_station([0.2, 1.0], [(0.0, 5.0), (1.2, 9.0), (1.0, 50.0)], 1.2) == (
        1.2,
        "overhung stage",
    )
