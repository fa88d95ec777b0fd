"""``rubrotor thermal`` and the ``[thermal]`` table: output shapes, the shipped scenario's
spiral growing below its first forward critical speed, slow runs to netCDF, errors naming the
field.

The independent reference for the critical speed is the Campbell route of
rubrotor.linear.critical.linear_critical_speeds (damped frequency = spin); the growth-rate
numbers themselves are checked against the closed form in test_thermal_model.py.
"""

from __future__ import annotations

import json
from importlib import resources

import pytest
import xarray as xr

from rubrotor.cli import main
from rubrotor.errors import ScenarioError
from rubrotor.scenario.load import load_scenario, scenario_from_dict, scenario_to_dict

THERMAL = str(resources.files("rubrotor") / "scenarios" / "thermal_rub.toml")
SEED = str(resources.files("rubrotor") / "scenarios" / "seed_rotor.toml")


def test_thermal_json_grows_below_the_first_critical(capsys):
    """Below the first forward critical the spiral grows (finite period); above it, damped."""
    assert main(["thermal", THERMAL, "--speeds", "270:375:2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"first_forward_critical_rad_s", "speeds_rad_s", "growth_rate_per_s",
                        "spiral_period_s"}  # fmt: skip
    crit = out["first_forward_critical_rad_s"]
    assert 270 < crit < 375
    (g_below, g_above), (p_below, _) = out["growth_rate_per_s"], out["spiral_period_s"]
    assert g_below > 0 and p_below is not None and p_below > 0
    assert g_above < -1 / load_scenario(THERMAL).thermal.time_constant


def test_thermal_simulate_writes_the_1x_vectors(tmp_path, capsys):
    out = tmp_path / "spiral.nc"
    args = ["thermal", THERMAL, "--simulate", "0.25", "--out", str(out), "--samples", "4",
            "--steps", "256", "--json"]  # fmt: skip
    assert main(args) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["status"] == "complete"
    ds = xr.open_dataset(out)
    assert ds["one_x_real"].dims == ("time", "station", "axis")
    assert ds.sizes["station"] == 3 and ds["time"].values[-1] == pytest.approx(900.0)
    assert ds["one_x_real"].attrs["units"] == "m"
    # the bow grows from a straight rotor while the rub heats it
    assert abs(complex(ds.bow_real[-1, 0], ds.bow_imag[-1, 0])) > 1e-6
    ds.close()


def test_thermal_errors_are_one_line(capsys):
    assert main(["thermal", SEED]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "thermal" in err
    assert main(["thermal", THERMAL, "--simulate", "1"]) == 2
    assert "--out" in capsys.readouterr().err


@pytest.mark.parametrize(("key", "value"), [("time_constant", -1.0), ("hot_spot_lag", 4.0),
                                            ("bow_shape", "mode"), ("bow_per_heat", "x")])  # fmt: skip
def test_thermal_table_validation_names_the_key(key, value):
    spec = scenario_to_dict(load_scenario(THERMAL))
    spec["thermal"][key] = value
    with pytest.raises(ScenarioError, match=f"thermal.{key}"):
        scenario_from_dict(spec)


def test_thermal_table_round_trips():
    sc = load_scenario(THERMAL)
    again = scenario_from_dict(scenario_to_dict(sc, resolved=True))
    assert again.thermal == sc.thermal
