"""Stability decided relative to the eigenvalue's magnitude: an undamped rotor (the docs' ROSS
example: no bearing damping, no cross-coupling) is "undamped", not "stability threshold:
0 rad/s" from damping ratios of +-1e-26.

Reference: its matrices at every speed have C + Omega G with C = 0 and G skew, and K symmetric
positive definite: a conservative gyroscopic system, whose eigenvalues are purely imaginary
(Thomson-Tait); any real part the eigensolver returns is round-off."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from rubrotor.cli import main
from rubrotor.linear.stability import ZETA_ROUNDOFF, is_undamped, stability_threshold
from rubrotor.linear.verbs import linear_system
from rubrotor.scenario.load import Scenario, load_scenario

ROSS_FILE = Path(__file__).parents[1] / "docs" / "howto" / "import-ross" / "ross_rotor.toml"
TOP = 3000 * np.pi / 30 * 3  # rad/s: 3 x 3000 rpm


@pytest.fixture(scope="module")
def system():
    return linear_system(Scenario.from_ross(ROSS_FILE, speed=3000 * np.pi / 30))


def test_the_reference_is_conservative(system):
    for w in (0.0, TOP):
        m = system.matrices(w)
        assert not np.any(m.C) and np.allclose(m.G, -m.G.T)
        np.testing.assert_allclose(m.K, m.K.T, rtol=0, atol=1e-12 * np.abs(m.K).max())
        assert np.linalg.eigvalsh(0.5 * (m.K + m.K.T)).min() > 0


def test_undamped_rotor_has_no_threshold(system):
    assert stability_threshold(system, TOP, n=8) is None
    assert is_undamped(system, (0.0, TOP), n=8)


def test_damped_rotor_is_not_undamped():
    assert not is_undamped(linear_system(load_scenario("seal_rub")), (0.0,), n=4)


def test_cli_says_undamped(tmp_path, capsys):
    out = tmp_path / "ross.toml"
    assert main(["import-ross", str(ROSS_FILE), "--out", str(out), "--rpm", "3000"]) == 0
    capsys.readouterr()
    assert main(["critical", str(out)]) == 0
    text = capsys.readouterr().out
    assert "the rotor is undamped" in text and "stability threshold: 0 " not in text
    assert f"+-{ZETA_ROUNDOFF:g}" in text
    assert main(["critical", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["undamped"] is True and data["stability_threshold_rad_s"] is None
