"""Results Dataset, netCDF round trip, and the run / converge commands."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import rubrotor
from rubrotor.cli import main
from rubrotor.engine.settings import Integrator

CASE1 = Path(rubrotor.__file__).parent / "scenarios" / "seed_case1.toml"


@pytest.fixture(scope="module")
def case1():
    return rubrotor.load_scenario(CASE1)


@pytest.fixture(scope="module")
def short_run(case1):
    integ = Integrator(revolutions=12, dtau=1e-3, save_every=4, probes=(0.1, 0.3))
    return rubrotor.simulate(case1, integrator=integ, progress=False)


def test_dataset_layout_units_and_provenance(short_run, case1):
    ds = short_run
    assert ds.attrs["status"] == "complete"
    for name, unit in [
        ("v", "m"),
        ("w", "m"),
        ("v_dot", "m/s"),
        ("w_ddot", "m/s^2"),
        ("normal_force", "N"),
        ("friction_force", "N"),
        ("unbalance_force_y", "N"),
    ]:
        assert ds[name].attrs["units"] == unit
    assert ds["time"].attrs["units"] == "s"
    assert ds["tau"].values[-1] == pytest.approx(case1.speed * ds["time"].values[-1])
    # one layout for every rotor: the contact station, then the probes, on ``station`` (m)
    assert ds["v"].dims == ("station", "time")
    assert ds["normal_force"].dims == ("contact", "time") and ds.sizes["contact"] == 1
    np.testing.assert_allclose(ds["station"].values, [0.2, 0.1, 0.3])
    assert ds["station"].attrs["units"] == "m"
    # symmetric shaft, midspan force: probes at 0.1 and 0.3 m see the same deflection
    np.testing.assert_allclose(ds["v"][1], ds["v"][2], atol=1e-12 * float(abs(ds["v"]).max()))
    assert json.loads(ds.attrs["contacts"])[0]["clearance"] == pytest.approx(1.2e-3)
    assert ds.attrs["end_time_s"] == pytest.approx(float(ds["time"][-1]))
    params = json.loads(ds.attrs["parameters"])
    assert params["contact.clearance"][1] == "m"
    assert params["contact.clearance"][0] == pytest.approx(1.2e-3)
    assert "[contact]" in ds.attrs["scenario"]
    stats = json.loads(ds.attrs["integrator_stats"])
    assert stats["method"] == "exponential" and stats["steps"] > 0
    # in_contact flag is consistent with the force and with the clearance
    touching = ds["in_contact"].values[0] == 1
    assert touching.any()
    d = np.hypot(ds["v"].values[0], ds["w"].values[0])
    assert np.all(d[touching] > case1.contact.clearance)
    assert np.all(ds["normal_force"].values[0][~touching] == 0)
    assert np.all(ds["event_contact"].values == 0)
    # events alternate onset / separation
    kinds = ds["event_kind"].values
    assert kinds[0] == 1 and np.all(kinds[1:] != kinds[:-1])


def test_unbalance_force_is_m_e_omega_squared(short_run, case1):
    f = np.hypot(short_run["unbalance_force_y"], short_run["unbalance_force_z"])
    np.testing.assert_allclose(f, case1.unbalance.magnitude * case1.speed**2, rtol=1e-12)


def test_netcdf_round_trip_is_identical(short_run, tmp_path):
    path = rubrotor.save_dataset(short_run, tmp_path / "r.nc")
    back = rubrotor.load_dataset(path)
    xr.testing.assert_identical(short_run, back)
    assert not list(tmp_path.glob(".*.tmp"))  # atomic write leaves no temporary behind


def _old_shaft_layout(ds):
    """The continuous shaft's Dataset as written before the layouts were merged (contact
    station on ``time``, probes as ``probe_*`` on ``probe``), rebuilt by hand from ``ds``."""
    old = xr.Dataset(coords={"time": ds["time"], "tau": ds["tau"]}, attrs=dict(ds.attrs))
    for k in ("engine", "start_time_s", "end_time_s", "contacts"):
        del old.attrs[k]
    names = ("v", "w", "v_dot", "w_dot", "v_ddot", "w_ddot")
    for k in names:
        old[k] = ("time", ds[k].values[0], ds[k].attrs)
        old[f"probe_{k}"] = (("probe", "time"), ds[k].values[1:], ds[k].attrs)
    old = old.assign_coords(probe=("probe", ds["station"].values[1:], {"units": "m"}))
    for k in ("normal_force", "friction_force", "in_contact"):
        old[k] = ("time", ds[k].values[0], ds[k].attrs)
    for k in ("unbalance_force_y", "unbalance_force_z", "event_time", "event_kind"):
        old[k] = ds[k]
    return old


def test_old_shaft_layout_file_loads_in_the_one_layout(short_run, tmp_path):
    """A file in the old shaft layout (built by hand from today's run: the reference is the
    run itself) loads with the same numbers on the station and contact dimensions."""
    path = tmp_path / "old.nc"
    _old_shaft_layout(short_run).to_netcdf(path)
    back = rubrotor.load_dataset(path)
    assert "probe" not in back.dims and not any(k.startswith("probe") for k in back.variables)
    np.testing.assert_array_equal(back["station"].values, short_run["station"].values)
    for k in ("v", "w", "v_dot", "w_dot", "v_ddot", "w_ddot", "normal_force", "in_contact"):
        assert back[k].dims == short_run[k].dims
        np.testing.assert_array_equal(back[k].values, short_run[k].values)
    np.testing.assert_array_equal(back["event_contact"].values, 0)
    assert back.attrs["engine"] == "shaft"
    # the analyses read it as they read a new file
    from rubrotor.analysis.verdict import dataset_verdict

    assert dataset_verdict(back).as_dict() == dataset_verdict(short_run).as_dict()


def test_old_layout_without_contact_converts_to_no_contact_rows():
    """An old-layout Dataset of a run without contact (parameters name no ``contact.`` key):
    the converted one has the contact station's samples on ``station`` and no contact rows.
    The reference is the input arrays themselves."""
    from rubrotor.engine.result import from_shaft_layout

    t = np.linspace(0.0, 1e-2, 11)
    old = xr.Dataset(coords={"time": ("time", t)}, attrs={
        "contact_position_m": 0.2, "parameters": json.dumps({"shaft.length": [0.4, "m"]})})  # fmt: skip
    for k, x in zip(("v", "w", "v_dot", "w_dot", "v_ddot", "w_ddot"), range(6), strict=True):
        old[k] = ("time", np.sin(t * (x + 1)), {"units": "m"})
    for k in ("normal_force", "friction_force", "in_contact"):
        old[k] = ("time", np.zeros(t.size), {})
    new = from_shaft_layout(old)
    assert new.sizes["station"] == 1 and new.sizes["contact"] == 0
    np.testing.assert_array_equal(new["station"].values, [0.2])
    np.testing.assert_array_equal(new["w_ddot"].values[0], np.sin(t * 6))
    assert json.loads(new.attrs["contacts"]) == []
    assert from_shaft_layout(new) is new  # the one layout is left as it is


def test_load_dataset_errors(tmp_path):
    with pytest.raises(rubrotor.InputError, match="results"):
        rubrotor.load_dataset(tmp_path / "missing.nc")
    bad = tmp_path / "bad.nc"
    bad.write_text("not netcdf")
    with pytest.raises(rubrotor.InputError, match="readable"):
        rubrotor.load_dataset(bad)


def test_cli_run_writes_results_and_summary(tmp_path, capsys):
    code = main(
        ["run", str(CASE1), "--out", str(tmp_path / "out"), "--revolutions", "5", "--no-progress"]
    )
    assert code == 0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    ds = rubrotor.load_dataset(tmp_path / "out" / "results.nc")
    assert summary["status"] == "complete"
    assert summary["samples"] == ds.sizes["time"]
    assert summary["max_normal_force_N"] == pytest.approx(float(ds["normal_force"].max()))
    # the run is a whole number of saved samples: within one of them of 5 revolutions
    every = rubrotor.load_scenario(CASE1).simulation.save_every
    assert abs(ds["tau"].values[-1] - 5 * 2 * math.pi) <= every * 1e-3
    assert json.loads(capsys.readouterr().out)["scenario"] == "seed_case1"


def test_cli_run_partial_run_exits_1_and_keeps_data(tmp_path, capsys):
    text = CASE1.read_text().replace("dtau = 0.001", "dtau = 0.001\nmax_displacement = 1e-4")
    scen = tmp_path / "s.toml"
    scen.write_text(text)
    code = main(["run", str(scen), "--out", str(tmp_path / "o"), "--no-progress"])
    assert code == 1
    ds = rubrotor.load_dataset(tmp_path / "o" / "results.nc")
    assert ds.attrs["status"] == "partial"
    assert "diverged" in ds.attrs["status_message"]
    assert ds.sizes["time"] > 10
    assert "diverged" in capsys.readouterr().err


def test_cli_run_bad_scenario_exit_2(tmp_path, capsys):
    scen = tmp_path / "s.toml"
    scen.write_text(CASE1.read_text().replace("friction = 0.02", "friction = -0.02"))
    assert main(["run", str(scen), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "contact.friction" in err and "Traceback" not in err


def test_cli_converge_table(capsys):
    code = main(["converge", str(CASE1), "--revolutions", "3", "--halvings", "2", "--json"])
    assert code == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    steps = [r for r in rows if r["study"] == "step"]
    modes = [r for r in rows if r["study"] == "modes"]
    assert len(steps) == 2 and len(modes) == 2
    # second order: halving the step divides the difference by about 4
    assert steps[0]["max_diff_m"] / steps[1]["max_diff_m"] == pytest.approx(4, rel=0.3)
    # mode 2 is never excited by midspan forces: 1 -> 2 modes changes nothing
    assert modes[0]["rel_diff"] < 1e-10
    assert modes[1]["rel_diff"] > 1e-6
