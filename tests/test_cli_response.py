"""The verbs ``static``, ``response``, ``unbalance``, ``ucs`` and ``shapes`` from the command
line: their JSON equals the library's results (the reference, tested against closed forms and
second routes in test_linear_verbs.py), figures are written, and bad input exits 2 with one
line naming the flag."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rubrotor
from rubrotor.cli import main
from rubrotor.linear.response import scenario_unbalance_response
from rubrotor.linear.static import static_analysis
from rubrotor.linear.ucs import ucs_map
from rubrotor.linear.verbs import linear_system
from rubrotor.scenario.load import load_scenario

SCEN = Path(rubrotor.__file__).parent / "scenarios"
GENERAL = str(SCEN / "general_rotor.toml")
SEAL = str(SCEN / "seal_rub.toml")


def _json(capsys, argv) -> dict:
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_static_json_and_figure(capsys, tmp_path):
    """JSON keys as documented; forces equal static_analysis; the y forces carry the weight."""
    out = _json(capsys, ["static", GENERAL, "--json", "--figure", str(tmp_path / "s.png")])
    ref = static_analysis(load_scenario(GENERAL))
    assert {"x_m", "deflection_y_m", "deflection_z_m", "bearings"} <= set(out)
    np.testing.assert_array_equal(out["deflection_y_m"], ref.deflection[:, 0])
    assert [set(b) for b in out["bearings"]] == [
        {"name", "position_m", "force_y_N", "force_z_N"}
    ] * 2
    assert sum(b["force_y_N"] for b in out["bearings"]) == pytest.approx(-ref.applied[0], rel=1e-12)
    assert (tmp_path / "s.png").read_bytes()[:4] == b"\x89PNG"


def test_unbalance_json_uses_every_plane(capsys, tmp_path):
    """seal_rub.toml's two [[unbalance]] planes: the JSON equals scenario_unbalance_response."""
    argv = ["unbalance", SEAL, "--speeds", "100:1500:8", "--probe", "0.75", "--json"]
    out = _json(capsys, argv + ["--figure", str(tmp_path / "u.png")])
    ref = scenario_unbalance_response(load_scenario(SEAL), np.linspace(100, 1500, 8), [0.75])
    (probe,) = out["probes"]
    assert probe["position_m"] == 0.75
    np.testing.assert_allclose(probe["major_m"], ref.major[:, 0], rtol=1e-12)
    np.testing.assert_allclose(probe["phase_z_rad"], ref.phase[:, 0, 1], rtol=1e-12)
    keys = {"position_m", "speed_rad_s", "amplitude_y_m", "phase_y_rad", "amplitude_z_m",
            "phase_z_rad", "major_m", "amplitude"}  # fmt: skip
    assert set(probe) == keys and probe["amplitude"] == "0-peak"
    assert (tmp_path / "u.png").exists()


def test_response_ucs_shapes_run(capsys, tmp_path):
    """response, ucs and shapes print JSON consistent with the library and write figures."""
    out = _json(capsys, ["response", GENERAL, "--at", "0.45", "--frequencies", "0:2000:5",
                         "--kind", "backward", "--force", "3", "--json"])  # fmt: skip
    assert out["force"]["kind"] == "backward" and len(out["probes"][0]["major_m"]) == 5
    ucs = _json(capsys, ["ucs", GENERAL, "--stiffness", "1e6:1e9:4", "--modes", "2", "--json",
                         "--figure", str(tmp_path / "ucs.png")])  # fmt: skip
    ref = ucs_map(linear_system(load_scenario(GENERAL)), np.logspace(6, 9, 4), 2)
    np.testing.assert_allclose(ucs["critical_speeds_rad_s"], ref.critical_speeds.T, rtol=1e-12)
    shapes = _json(capsys, ["shapes", GENERAL, "--speed", "300", "--modes", "2", "--json",
                            "--figure", str(tmp_path / "sh.png")])  # fmt: skip
    assert len(shapes["modes"]) == 2 and len(shapes["modes"][0]["v_real"]) == len(shapes["x_m"])
    assert (tmp_path / "ucs.png").exists() and (tmp_path / "sh.png").exists()


@pytest.mark.parametrize(
    ("argv", "flag"),
    [
        (["unbalance", SEAL, "--speeds", "10:100:3", "--probe", "3.0"], "--probe"),
        (["static", GENERAL, "--figure", "x.jpg"], "--figure"),
        (["ucs", GENERAL, "--stiffness", "0:1e9:4"], "--stiffness"),
        (["response", GENERAL, "--at", "-1", "--frequencies", "0:10:3"], "--at"),
        (["ucs", str(SCEN / "seed_case1.toml")], "bearing"),
    ],
)
def test_bad_input_exits_2_naming_the_flag(capsys, argv, flag):
    """One line on stderr naming the flag (or field), exit status 2, no traceback."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"rubrotor: error: {flag} = ") and err.count("\n") == 1


def test_clearance_and_level1_verbs(capsys, tmp_path):
    """clearance: one entry per [[contact]], verdict consistent with the margin, and a note on
    stderr where the scaled orbit reaches the clearance; level1: Q_A from a stage equals
    anticipated_cross_coupling, and the JSON equals the library's Level I."""
    from rubrotor.linear.api684 import anticipated_cross_coupling, level1

    argv = [
        "clearance",
        SEAL,
        "--speeds",
        "10:800:80",
        "--json",
        "--figure",
        str(tmp_path / "c.png"),
    ]
    assert main(argv) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    (c,) = out["clearances"]
    assert c["position_m"] == 0.75 and c["diametral_clearance_m"] == pytest.approx(80e-6)
    assert (c["verdict"] == "pass") == (c["margin_m"] >= 0)
    assert bool(c["touching_speeds_rad_s"]) == ("reaches its clearance" in cap.err)
    argv = ["level1", SEAL, "--stiffness", "1e4:1e7:7", "--stage", "2e6,0.3,0.015,1.4", "--json",
            "--figure", str(tmp_path / "l1.png")]  # fmt: skip
    out = _json(capsys, argv)
    sc = load_scenario(SEAL)
    qa = anticipated_cross_coupling(2e6, sc.speed, 0.3, 0.015, 1.4)
    assert out["qa_N_m"] == pytest.approx(qa, rel=1e-12)
    # the default station: mid-span between the bearings at 0.05 and 1.25 m (API 684 for a
    # between-bearing rotor; tests/test_level1_location.py)
    assert out["position_m"] == pytest.approx(0.65) and out["location"] == "mid-span"
    ref = level1(linear_system(sc, (0.65,)), sc.speed, 0.65, np.logspace(4, 7, 7), qa)
    np.testing.assert_allclose(out["log_dec"], ref.log_dec, rtol=1e-9)
    assert out["verdict"] == ref.verdict
    assert (tmp_path / "c.png").exists() and (tmp_path / "l1.png").exists()
    assert main(["clearance", GENERAL]) == 2  # no contact: nothing to check
    assert "contact" in capsys.readouterr().err
