"""One time-run result for every engine, and a Model that builds.

* :func:`rubrotor.engine.simulate.time_run` returns the one frozen
  :class:`~rubrotor.engine.result.TimeRun` for the seed shaft's engine (``seed_case1``), the
  general engine at constant speed (``seal_rub``) and in a run-up (``runup_rub``), and the
  free-spin engine (``touchdown_drop``), each with a status code of the one enumeration
  (:mod:`rubrotor.core.status`); its one Dataset builder gives the Dataset ``rubrotor.simulate``
  returns (the same numbers through the second route).
* :class:`rubrotor.modelling.Model` is built once per scenario and builds each rotor's linear
  system as the rotor's own builder does (compared matrix by matrix).
"""

import dataclasses

import numpy as np
import pytest
import xarray as xr

import rubrotor
from rubrotor.core.status import MESSAGES, Status
from rubrotor.engine.result import STATUSES, TimeRun
from rubrotor.engine.simulate import time_run
from rubrotor.modelling import Model

SHORT = {  # scenario -> a short [simulation] override (the same physics, fewer samples)
    "seed_case1": {"revolutions": 2},
    "seal_rub": {"revolutions": 1},
    "runup_rub": {"revolutions": 2},
    "touchdown_drop": {"duration": 0.004},
}


def _short(name: str):
    sc = rubrotor.load_scenario(name)
    keys = SHORT[name]
    cleared = {"revolutions": None} if "duration" in keys else {"duration": None}
    return sc, dataclasses.replace(sc.simulation, **{**cleared, **keys})


@pytest.mark.parametrize("name", sorted(SHORT))
def test_every_engine_returns_the_one_result(name):
    """Same type, frozen, a status of ``STATUSES`` and a code of the one enumeration whose
    message is the table's; the TimeRun's Dataset holds the samples ``rubrotor.simulate``
    returns (two routes through the one builder, equal to the last bit: the runs are
    deterministic)."""
    sc, integ = _short(name)
    res = time_run(sc, integrator=integ, progress=False)
    assert type(res) is TimeRun
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.status = "partial"
    assert res.status == "complete" and res.status in STATUSES
    assert isinstance(res.code, Status) and res.code is Status.OK
    assert res.code.message == MESSAGES[res.code] == "complete"
    assert res.engine == Model.for_scenario(sc).runner
    ds = rubrotor.simulate(sc, integrator=integ, progress=False)
    assert isinstance(ds, xr.Dataset) and ds.attrs["status"] == res.status
    mine = res.to_dataset() if res.engine != "free-spin" else None
    if mine is not None:
        for var in ("v", "w", "normal_force"):
            np.testing.assert_array_equal(mine[var].values, ds[var].values)
        assert mine.sizes["station"] == ds.sizes["station"] and mine.attrs["status"] == "complete"


def test_old_result_names_are_the_one_type():
    """``SimulationResult``, ``EngineResult`` and ``SpinResult`` stay importable: each is the
    one :class:`TimeRun`."""
    from rubrotor.engine.driver import EngineResult
    from rubrotor.engine.simulate import SimulationResult
    from rubrotor.engine.spin import SpinResult

    assert SimulationResult is EngineResult is SpinResult is TimeRun


@pytest.mark.parametrize("name", ["seed_case1", "seal_rub"])
def test_a_diverged_run_is_partial_with_the_shared_code(name):
    """A displacement bound far below the orbit stops both engines at once: status
    ``"partial"``, code ``Status.DIVERGED`` (the same code on both engines), the samples so
    far kept."""
    sc, integ = _short(name)
    res = time_run(sc, integrator=dataclasses.replace(integ, max_displacement=1e-12),
                   progress=False)  # fmt: skip
    assert (res.status, res.code) == ("partial", Status.DIVERGED)
    assert res.message and res.time.size >= 1


def test_the_model_is_built_once_and_builds_each_rotor():
    """Built once per scenario (a changed scenario gets its own); its linear system is the
    continuous shaft's exact modal model, the finite-element rotor meshed at the scenario's
    stations, or the given system (the same matrices as each builder's, to the last bit)."""
    from rubrotor.rotors.shaft_system import continuous_system

    seed = rubrotor.load_scenario("seed_case1")
    model = Model.for_scenario(seed)
    assert Model.for_scenario(seed) is model and Model.of(seed) is model
    changed = seed.with_changes(**{"speed.critical_multiple": 0.5})
    assert Model.for_scenario(changed) is not model
    general = rubrotor.load_scenario("general_rotor")
    systems = [
        (model.linear_system(), continuous_system(seed.shaft, seed.damping)),
        (Model.for_scenario(general).linear_system(),
         general.rotor.linear_system(tuple(general.stations))),
    ]  # fmt: skip
    system = systems[1][1]
    systems.append((Model.of(system).linear_system(), system))
    for ours, theirs in systems:
        a, b = ours.matrices(300.0), theirs.matrices(300.0)
        for name in ("M", "K", "C", "G"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert (model.runner, model.maps, model.linear) == ("shaft", "shaft", "closed-form")
    gm = Model.for_scenario(general)
    assert (gm.runner, gm.maps, gm.linear) == ("general", "general", "matrix")
    drop = Model.for_scenario(rubrotor.load_scenario("touchdown_drop"))
    assert drop.runner == "free-spin"


def test_maps_refuse_a_shaft_with_general_engine_keys_by_name():
    """A [shaft] with [gravity] runs in time on the general engine, but no periodic map
    honours it: the Model refuses naming the key."""
    heavy = rubrotor.load_scenario("seed_case1").with_changes(**{"gravity.y": -9.81})
    model = Model.for_scenario(heavy)
    assert model.runner == "general"
    with pytest.raises(rubrotor.ScenarioError, match="^gravity"):
        model.require_maps("periodic orbits")
