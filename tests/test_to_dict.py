"""Every result of the linear verbs has ``to_dict()``, and it is what the command's ``--json``
prints (the README's promise): Campbell data, the unbalance response, critical speeds."""

from __future__ import annotations

import json

import numpy as np

import rubrotor
from rubrotor.cli import main
from rubrotor.linear.campbell import campbell_data
from rubrotor.linear.critical import linear_critical_speeds
from rubrotor.linear.verbs import linear_system


def _json(capsys, *argv) -> dict:
    assert main(list(argv)) == 0
    return json.loads(capsys.readouterr().out)


def test_campbell_to_dict_is_the_cli_json(capsys, tmp_path):
    out = _json(capsys, "campbell", "general_rotor", "--speeds", "0:600:4", "--json",
                "--out", str(tmp_path / "c.png"))  # fmt: skip
    sc = rubrotor.load_scenario("general_rotor")
    mine = campbell_data(linear_system(sc), np.linspace(0, 600, 4), n=8).to_dict()
    assert set(out) == {*mine, "figure"}
    np.testing.assert_allclose(out["frequency_hz"], mine["frequency_hz"], rtol=1e-9)
    assert out["whirl"] == mine["whirl"]


def test_unbalance_to_dict_is_the_cli_json(capsys):
    out = _json(capsys, "unbalance", "seal_rub", "--speeds", "100:600:3", "--probe", "0.45",
                "--json")  # fmt: skip
    res = rubrotor.unbalance_response("seal_rub", "100:600:3", [0.45])
    mine = json.loads(json.dumps(res.to_dict()))
    assert mine.keys() == out.keys()
    a, b = mine["probes"][0], out["probes"][0]
    assert a.keys() == b.keys()
    for k in a:
        if isinstance(a[k], list):
            np.testing.assert_allclose(a[k], b[k], rtol=1e-9)


def test_critical_to_dict_is_the_cli_json(capsys):
    out = _json(capsys, "critical", "seal_rub", "--json", "--max-speed", "700")
    mine = [c.to_dict() for c in linear_critical_speeds(
        linear_system(rubrotor.load_scenario("seal_rub")), 700.0, n=8)]  # fmt: skip
    assert [c["index"] for c in out["critical_speeds"]] == [c["index"] for c in mine]
    np.testing.assert_allclose([c["speed_rad_s"] for c in out["critical_speeds"]],
                               [c["speed_rad_s"] for c in mine], rtol=1e-9)  # fmt: skip
