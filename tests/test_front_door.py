"""One front door: what a scenario is is decided once (:class:`rubrotor.modelling.Model`),
and ``rubrotor simulate`` runs every rotor (``rubrotor run`` is its alias for the folder
layout)."""

import json
from pathlib import Path

import pytest
import xarray as xr

from rubrotor.cli import main
from rubrotor.cli.studies import shipped_scenarios
from rubrotor.errors import ScenarioError
from rubrotor.modelling import Model
from rubrotor.scenario.load import load_scenario

SHIPPED = {s["name"]: Path(s["path"]) for s in shipped_scenarios()}


def test_model_of_shipped_scenarios():
    """The seed's case runs on the shaft's engine; the seal rub is a finite-element rotor on the
    general engine, with the keys that need it listed; a [shaft] with [gravity] is a shaft on the
    general engine."""
    seed = load_scenario(SHIPPED["seed_case1"])
    assert Model.for_scenario(seed) == Model(rotor="shaft", engine="shaft", formulation="two-field")
    seal = Model.for_scenario(load_scenario(SHIPPED["seal_rub"]))
    assert (seal.rotor, seal.engine, seal.formulation) == ("fe", "general", "fe")
    assert {"gravity", "contact.stator"} <= set(seal.features)
    heavy = Model.for_scenario(seed.with_changes(**{"gravity.y": -9.81}))
    assert (heavy.rotor, heavy.engine, heavy.features) == (
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


def test_modal_damping_through_the_general_engine():
    """The continuous shaft's modal damping reaches the general engine as the viscous matrix of
    each mode's block (``rubrotor.rotors.shaft_system.continuous_system``; it used to be refused
    there). References: the shaft's own first-order modal system
    (``rubrotor.engine.shaft_modal.assemble_modal``, a second route to the same eigenvalues,
    measured 4e-15 apart) and the shaft engine's run of the same scenario without contact (both
    propagate the linear rotor exactly between output samples: measured 7e-14 apart)."""
    import numpy as np

    import rubrotor
    from rubrotor.engine.shaft_modal import assemble_modal
    from rubrotor.rotors.shaft_system import continuous_system

    sc = load_scenario(SHIPPED["seed_no_contact"]).with_changes(
        **{"damping.ratio": 0.02, "simulation.revolutions": 20}
    )
    lam = assemble_modal(sc.shaft, sc.speed, sc.damping).lam
    system = continuous_system(sc.shaft, sc.damping)
    n = system.M.shape[0]
    a = np.block(
        [
            [np.zeros((n, n)), np.eye(n)],
            [
                -np.linalg.solve(system.M, system.K),
                -np.linalg.solve(system.M, system.C + sc.speed * system.G),
            ],
        ]
    )
    real = np.sort_complex(np.linalg.eigvals(a)[np.linalg.eigvals(a).imag > 0])
    ref = np.sort_complex(np.concatenate([lam[lam.imag > 0], np.conj(lam[lam.imag < 0])]))
    assert real.size == ref.size == 4 * sc.shaft.modes
    np.testing.assert_allclose(real, ref, rtol=1e-12)
    assert np.all(ref.real < -1.0)  # damped: 2 % of every mode

    general = sc.with_changes(**{"initial.state": "static", "simulation.probes": [0.2]})
    assert general.model.general and not sc.model.general
    shaft_run, general_run = rubrotor.simulate(sc), rubrotor.simulate(general)
    t1, t2 = shaft_run.time.values, general_run.time.values
    common, i1, i2 = np.intersect1d(np.round(t1, 12), np.round(t2, 12), return_indices=True)
    assert common.size > 3000
    v1, v2 = shaft_run.v.values[0, i1], general_run.v.values[0, i2]
    assert np.max(np.abs(v1 - v2)) <= 1e-10 * np.max(np.abs(v1))

    # the damping acts: the free vibration around the circular steady orbit decays
    # (exp(-zeta omega_1 t) ~ 0.2 after 20 revolutions; undamped it does not)
    def ripple(ds):
        r = np.hypot(ds.v.values[0, -200:], ds.w.values[0, -200:])
        return np.ptp(r)

    undamped = rubrotor.simulate(general.with_changes(**{"damping.ratio": 0.0}))
    assert ripple(general_run) < 0.5 * ripple(undamped)
