"""Robustness grid, detection study and the `rubrotor stability` command."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rubrotor.cli import main
from rubrotor.studies.seed import detection, robustness
from rubrotor.sweeps.sweep import map_tasks


def _square(x):
    return x * x


def test_map_tasks_backends_agree():
    """In-process and process-pool back ends return the same results (order aside)."""
    tasks = list(range(7))
    a = sorted(map_tasks(_square, tasks, workers=1))
    b = sorted(map_tasks(_square, tasks, workers=2))
    assert a == b == [t * t for t in tasks]
    assert list(map_tasks(_square, [], workers=2)) == []


def test_robustness_quick_grid():
    """Two configurations (one per formulation); the summary counts what the rows say and
    the conditions text follows from them (checked against a direct count)."""
    st = robustness.QUICK_GRID
    tasks = robustness.configurations(st)
    assert len(tasks) == 2 and {t["formulation"] for t in tasks} == {"two-field", "seed-eq1"}
    res = robustness.run(st, workers=2)
    rows = res["rows"]
    assert [r["key"] for r in rows] == [0, 1]
    for i, e in enumerate(res["summary"]):
        for form in st.formulations:
            sub = [r for r in rows if r["config"]["formulation"] == form]
            n = sum(r["holds"][i] for r in sub)
            assert e[form]["holds"] == n and e[form]["of"] == len(sub)
            assert e[form]["conditions"] == ("always" if n == len(sub) else "never")
    # conditions names the factor level shared by every holding configuration
    fake = [
        {"holds": [True], "config": {"unbalance_factor": 1.0, "damping": 0.0, "initial": "rest",
                                     "friction_sign": "seed"}},
        {"holds": [False], "config": {"unbalance_factor": 1.0, "damping": 0.0, "initial": "rest",
                                      "friction_sign": "physical"}},
    ]  # fmt: skip
    st2 = robustness.RobustnessSettings(unbalance_factors=(1.0,), damping=(0.0,), initial=("rest",))
    assert robustness.conditions(fake, 0, st2) == "only with friction sign seed"


def test_detection_margin_and_noise():
    """Margin in decades from the class extremes (closed form), SNR of the added noise
    measured on a long record (within 0.1 dB)."""
    m, d = detection._margin(np.array([10.0, 20.0]), np.array([0.5, 1.0]))
    assert m == pytest.approx(1.0) and d == "higher with rub"
    m, d = detection._margin(np.array([0.01, 0.02]), np.array([0.1, 0.3]))
    assert m == pytest.approx(math.log10(0.1 / 0.02)) and d == "lower with rub"
    rng = np.random.default_rng(3)
    x = np.sin(np.linspace(0, 2000, 400_000))
    y = detection._noisy(x, 20.0, rng)
    snr = 10 * np.log10(np.mean(x**2) / np.mean((y - x) ** 2))
    assert snr == pytest.approx(20.0, abs=0.1)


def test_detection_quick_runs():
    res = detection.run(detection.QUICK)
    assert {r["class"] for r in res["runs"]} == {"rub", "no rub"}
    for t in res["table"]:
        assert set(t["snr"]) == {"no noise", "20 dB"}
    # without noise the displacement-harmonic indicator separates the classes
    two_x = next(t for t in res["table"] if t["key"] == "super_2x")
    assert two_x["snr"]["no noise"]["margin_decades"] > 0


def test_stability_cli(capsys, tmp_path):
    """`rubrotor stability` prints both formulations; JSON equals the API; bad input: exit 2."""
    from importlib import resources

    from rubrotor import load_scenario
    from rubrotor.linear.stability import contact_stability

    path = str(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")
    assert main(["stability", path, "--indentation", "1e-4", "--modes", "1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    api = contact_stability(load_scenario(path), 1e-4, modes=1, formulation="seed-eq1")
    seed = next(r for r in data["results"] if r["formulation"] == "seed-eq1")
    assert seed["max_growth_rate_per_s"] == pytest.approx(api.max_growth_rate, rel=1e-12)
    assert main(["stability", path, "--indentation", "1e-4", "--top", "2"]) == 0
    out = capsys.readouterr().out
    assert "two-field" in out and "seed-eq1" in out
    assert main(["stability", path, "--indentation", "0"]) == 2
    assert "indentation" in capsys.readouterr().err
    nc = str(resources.files("rubrotor") / "scenarios" / "seed_no_contact.toml")
    assert main(["stability", nc, "--indentation", "1e-4"]) == 2
