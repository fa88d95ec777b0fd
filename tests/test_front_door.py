"""One front door: what a scenario is is decided once (:class:`rubrotor.scenario.model.Model`),
and ``rubrotor simulate`` runs every rotor (``rubrotor run`` is its alias for the folder
layout)."""

import json
from pathlib import Path

import pytest
import xarray as xr

from rubrotor.cli import main
from rubrotor.cli.studies import shipped_scenarios
from rubrotor.errors import ScenarioError
from rubrotor.scenario.load import load_scenario
from rubrotor.scenario.model import Model

SHIPPED = {s["name"]: Path(s["path"]) for s in shipped_scenarios()}


def test_model_of_shipped_scenarios():
    """The seed's case runs on the shaft's engine; the seal rub is a finite-element rotor on the
    general engine, with the keys that need it listed; a [shaft] with [gravity] is a shaft on the
    general engine."""
    seed = load_scenario(SHIPPED["seed_case1"])
    assert seed.model == Model(rotor="shaft", engine="shaft", formulation="two-field")
    seal = load_scenario(SHIPPED["seal_rub"])
    assert (seal.model.rotor, seal.model.engine, seal.model.formulation) == ("fe", "general", "fe")
    assert {"gravity", "contact.stator"} <= set(seal.model.features)
    heavy = seed.with_changes(**{"gravity.y": -9.81})
    assert (heavy.model.rotor, heavy.model.engine, heavy.model.features) == (
        "shaft",
        "general",
        ("gravity",),
    )


def test_seed_form_with_a_general_engine_key_is_refused_by_name(tmp_path, capsys):
    """``seed-eq1`` runs only on the shaft's engine: with ``[gravity]`` it used to load and
    silently run the two-field model; now the scenario is refused, naming both keys."""
    seed = load_scenario(SHIPPED["seed_case1"]).with_changes(**{"shaft.formulation": "seed-eq1"})
    with pytest.raises(ScenarioError, match="shaft.formulation.*gravity"):
        seed.with_changes(**{"gravity.y": -9.81})
    text = (
        SHIPPED["seed_case1"]
        .read_text()
        .replace('theory = "timoshenko"', 'theory = "timoshenko"\nformulation = "seed-eq1"')
    )
    path = tmp_path / "eq1_gravity.toml"
    path.write_text(text + "\n[gravity]\ny = -9.81\n")
    assert main(["simulate", str(path), "--out", str(tmp_path / "r.nc")]) == 2
    err = capsys.readouterr().err
    assert "shaft.formulation" in err and "gravity" in err and "Traceback" not in err
    assert not (tmp_path / "r.nc").exists()


def test_shaft_engine_verbs_name_the_key_that_needs_the_general_engine(capsys):
    seal = load_scenario(SHIPPED["seal_rub"])
    with pytest.raises(ScenarioError, match="section"):
        seal.model.require_shaft_engine("the convergence study")
    heavy = load_scenario(SHIPPED["seed_case1"]).with_changes(**{"gravity.y": -9.81})
    with pytest.raises(ScenarioError, match="^gravity"):
        heavy.require_seed_engine("the convergence study")


def test_run_is_an_alias_of_simulate_into_a_folder(tmp_path, capsys):
    """``run --out DIR`` and ``simulate --out DIR/`` write the same DIR/results.nc and
    DIR/summary.json; ``run`` says it is an alias."""
    seed = str(SHIPPED["seed_case1"])
    assert main(["run", seed, "--out", str(tmp_path / "a"), "--revolutions", "3"]) in (0, 1)
    assert "alias of `rubrotor simulate" in capsys.readouterr().err
    assert main(["simulate", seed, "--out", str(tmp_path / "b") + "/", "--revolutions", "3"]) in (
        0,
        1,
    )
    a, b = (xr.load_dataset(tmp_path / d / "results.nc") for d in ("a", "b"))
    xr.testing.assert_equal(a[["v", "w", "normal_force"]], b[["v", "w", "normal_force"]])
    sa, sb = (json.loads((tmp_path / d / "summary.json").read_text()) for d in ("a", "b"))
    sa.pop("wall_time_s"), sb.pop("wall_time_s")
    assert sa == sb and sa["samples"] == a.sizes["time"]
    assert main(["simulate", seed, "--out", str(tmp_path / "c.txt")]) == 2
    assert "--out" in capsys.readouterr().err
