"""The API 617 check names the mode its unbalance was placed for (issue 30): forward index,
frequency, damping ratio, amplification factor and separation margin, in the result, its JSON
and the CLI's text. References: the mode's own eigenvalue (``damped_modes`` in ROSS's order,
the forward modes counted as ROSS counts them), API 684's single-mode estimate
``AF = 1 / (2 zeta)`` and the separation margin's definition (distance to the operating range
relative to its nearer end)."""

from __future__ import annotations

import json
import math
from importlib import resources

import pytest

import rubrotor
from rubrotor.cli import main
from rubrotor.linear.api617 import api617_unbalance, clearance_check
from rubrotor.linear.modes import damped_modes
from rubrotor.linear.verbs import linear_system

SCEN = resources.files("rubrotor") / "scenarios"


def test_clearance_names_its_mode(capsys):
    sc = rubrotor.load_scenario(SCEN / "general_rotor.toml")
    system = linear_system(sc, stations=(0.45,))
    nmc, nma = 700.0, 500.0
    res = clearance_check(system, [100.0, 400.0, 600.0, 800.0], nma, nmc, [(0.05, None)],
                          [("impeller", 0.45, 2e-4)])  # fmt: skip
    md = res.mode
    _, _, freq = api617_unbalance(system, nmc, 0)
    assert md["frequency_rad_s"] == pytest.approx(freq, rel=1e-12)
    modes = (
        damped_modes(system, nmc, n=6, order="ross").modes + damped_modes(system, nmc, n=12).modes
    )
    match = min(modes, key=lambda m: abs(2 * math.pi * m.frequency_hz - freq))
    assert 2 * math.pi * match.frequency_hz == pytest.approx(freq, rel=1e-12)
    assert md["damping_ratio"] == pytest.approx(match.damping_ratio, rel=1e-9)
    assert md["amplification_factor"] == pytest.approx(1 / (2 * match.damping_ratio), rel=1e-9)
    f = md["frequency_rad_s"]
    expect = (nma - f) / nma if f < nma else (f - nmc) / nmc if f > nmc else 0.0
    assert md["separation_margin"] == pytest.approx(expect, rel=1e-12, abs=1e-15)
    assert json.loads(json.dumps(res.to_dict()))["mode"]["forward_index"] == 0
    hand = clearance_check(system, [100.0, 600.0], nma, nmc, [(0.05, None)],
                           [("impeller", 0.45, 2e-4)], planes=[(0.45, 1e-4, 0.0)])  # fmt: skip
    assert hand.mode is None
    assert main(["clearance", str(SCEN / "seal_rub.toml"), "--speeds", "100:800:8"]) == 0
    assert "mode: forward mode 0 at" in capsys.readouterr().out
    assert main(["clearance", str(SCEN / "seal_rub.toml"), "--speeds", "100:800:8", "--json"]) == 0
    assert set(json.loads(capsys.readouterr().out)["mode"]) >= {"frequency_rad_s", "whirl"}
