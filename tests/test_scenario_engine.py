"""Scenario keys of the general engine (rubrotor.scenario.dynamics) and their wiring into
rubrotor.simulate and ``rubrotor simulate``.

References: the same run built directly through the API (``simulate_general`` on the objects
the test constructs itself, not through the scenario parser) must give the same samples;
a run restarted from a results file must continue a single long run (the exponential stepper
is exact on the linear part, so without contact the two agree to rounding).
"""

import copy
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import rubrotor
from rubrotor.cli import main, shipped_scenarios
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.parts import RubStation, Run, Stator
from rubrotor.errors import ScenarioError
from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section
from rubrotor.rotors.forces import Contact, RadialLoad, Unbalance
from rubrotor.scenario import scenario_from_dict
from rubrotor.scenario.dynamics import ENGINE_KEYS

SCENARIOS = Path(rubrotor.__file__).parent / "scenarios"

BASE = {
    "materials": {"steel": {"youngs_modulus": 211e9, "poisson_ratio": 0.3, "density": 7810}},
    "section": [{"length": 1.0, "diameter": 0.04, "material": "steel", "elements": 6}],
    "disk": [{"position": 0.5, "mass": 8.0, "polar_inertia": 0.04, "diametral_inertia": 0.02}],
    "bearing": [
        {"position": 0.0, "kyy": 2e6, "kzz": 3e6, "kyz": 4e5, "kzy": -3e5, "cyy": 300, "czz": 400},
        {"position": 1.0, "kyy": 2.5e6, "kzz": 2e6, "cyy": 300, "czz": 300},
    ],
    "speed": {"rad_per_s": 300.0},
    "unbalance": [{"position": 0.5, "magnitude": 2e-4, "phase": 0.3}],
    "contact": [
        {
            "position": 0.5,
            "radius": 0.1,
            "clearance": 1e-4,
            "law": "linear",
            "stiffness": 2e7,
            "damping": 200,
            "friction": 0.2,
            "offset_y": -2e-5,
            "stator_mass": 20,
            "stator_stiffness": 5e6,
            "stator_damping": 500,
        },
    ],  # fmt: skip
    "gravity": {"y": -9.81},
    "simulation": {"duration": 0.02, "dt": 5e-5, "save_every": 2},
}


def spec(**changes):
    """BASE with sections replaced (``None`` removes one)."""
    d = copy.deepcopy(BASE)
    for k, v in changes.items():
        if v is None:
            d.pop(k, None)
        else:
            d[k] = v
    return d


def contact(**kw):
    return [{**BASE["contact"][0], **kw}]


BAD = [
    ({"contact": contact(offset_y="a")}, "contact[1].offset_y"),
    ({"contact": contact(offset_z=5.0)}, "contact[1].offset_z"),
    ({"contact": contact(stator_mass=-1)}, "contact[1].stator_mass"),
    ({"contact": contact(stator_stiffness_y=1e7)}, "contact[1].stator_stiffness"),
    ({"contact": contact(stator_damping=math.inf)}, "contact[1].stator_damping"),
    (
        {"contact": contact(radius=None) and [{**BASE["contact"][0]} | {"radius": "x"}]},
        "contact[1].radius",
    ),  # fmt: skip
    ({"contact": contact(clearance=-1.0)}, "contact[1].clearance"),
    ({"contact": contact(position=2.0)}, "contact[1].position"),
    ({"contact": contact(colour=1)}, "contact[1].colour"),
    (
        {"contact": [BASE["contact"][0], {**BASE["contact"][0], "friction": -0.1}]},
        "contact[2].friction",
    ),  # fmt: skip
    ({"contact": []}, "contact"),
    ({"unbalance": [{"position": 0.5, "magnitude": -1.0}]}, "unbalance[1].magnitude"),
    (
        {"unbalance": [{"position": 0.5, "magnitude": 1e-4, "phase": 1, "phase_deg": 2}]},
        "unbalance[1].phase",
    ),  # fmt: skip
    ({"unbalance": [{"position": 3.0, "magnitude": 1e-4}]}, "unbalance[1].position"),
    ({"load": [{"position": 0.5, "force_y": "up"}]}, "load[1].force_y"),
    ({"load": [{"position": 0.5, "fy": 1.0}]}, "load[1].fy"),
    ({"gravity": {"y": 1e9}}, "gravity.y"),
    ({"gravity": {"x": 1.0}}, "gravity.x"),
    ({"speed": {"profile": "cubic", "from": 1.0, "to": 2.0}}, "speed.profile"),
    ({"speed": {"profile": "linear", "from": 100.0}}, "speed.to"),
    ({"speed": {"profile": "linear", "from": -1.0, "to": 2.0}}, "speed.from"),
    ({"speed": {"profile": "linear", "from": 1.0, "to": 2.0, "step": 0}}, "speed.step"),
    ({"speed": {"profile": "linear", "from": 1.0, "to": 2.0, "rpm": 3}}, "speed.rpm"),
    ({"speed": {"rad_per_s": 300.0, "to": 2.0}}, "speed.to"),
    ({"speed": {"times": [0, 1], "speeds": [1, 2]}}, "speed.times"),
    ({"speed": {"profile": "table", "times": [0, 0.02]}}, "speed.speeds"),
    ({"speed": {"profile": "table", "times": [0, 0.02], "speeds": [300, 310, 320]}}, "speed.times"),
    ({"speed": {"profile": "table", "times": [0, "a"], "speeds": [300, 310]}}, "speed.times"),
    ({"speed": {"profile": "table", "times": [0, 0.02], "speeds": [300, -1]}}, "speed.speeds"),
    ({"speed": {"profile": "table", "times": [0, 0.02], "speeds": [1, 2], "to": 3}}, "speed.to"),
    ({"speed": {"profile": "linear", "from": 1, "to": 2, "times": [0, 1]}}, "speed.times"),
    ({"initial": {"state": "moving"}}, "initial.state"),
    ({"initial": {"state": "file"}}, "initial.path"),
    ({"initial": {"state": "static", "path": "x.nc"}}, "initial.path"),
    ({"simulation": {"duration": 0.1, "modes": 0}}, "simulation.modes"),
    ({"simulation": {"duration": 0.1, "modes": 4, "cutoff": 1e3}}, "simulation.modes"),
    ({"simulation": {"duration": 0.1, "residual": 1}}, "simulation.residual"),
]


@pytest.mark.parametrize(("changes", "field"), BAD)
def test_bad_values_are_named(changes, field):
    """Every bad new key raises ScenarioError naming the key (with the entry's index)."""
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(spec(**changes))
    assert err.value.field.startswith(field), err.value


def test_keys_parse_into_engine_objects():
    """Values land in SI on the engine's objects; a single [contact] without new keys and no
    general rotor keeps the seed's engine (Scenario.engine is None)."""
    s = scenario_from_dict(spec(
        load=[{"position": 0.25, "force_z": 10.0}],
        unbalance=[{"position": 0.5, "magnitude": 1e-4, "phase_deg": 90.0},
                   {"position": 0.25, "magnitude": 2e-4, "phase": 1.0}],
    ))  # fmt: skip
    e = s.engine
    assert e.gravity == (-9.81, 0.0)
    assert e.stations[0].stator == Stator(20, 20, 5e6, 5e6, 500, 500)
    assert e.stations[0].offset_y == -2e-5
    assert e.unbalances[0].phase == pytest.approx(math.pi / 2, rel=1e-15)
    assert e.loads == (RadialLoad(0.0, 10.0, 0.25),)
    seed = rubrotor.load_scenario(SCENARIOS / "seed_case1.toml")
    assert seed.engine is None
    for key, row in ENGINE_KEYS.items():  # every key read is a row of the one schema
        assert row.dotted == key and row.kind in ("number", "int", "str", "bool", "list")
        assert row.minimum is None or row.maximum is None or row.minimum <= row.maximum, key


def _direct(duration=0.02, initial="rest", unb_phase=0.3, table=None):
    """The BASE scenario built by hand through the API."""
    steel = Material("steel", 211e9, 7810, poisson_ratio=0.3)
    rotor = Rotor(
        [Section(1.0, 0.04, steel, elements=6)],
        disks=[Disk(0.5, 8.0, 0.04, 0.02)],
        bearings=[Bearing(0.0, kyy=2e6, kzz=3e6, kyz=4e5, kzy=-3e5, cyy=300, czz=400),
                  Bearing(1.0, kyy=2.5e6, kzz=2e6, cyy=300, czz=300)],
    )  # fmt: skip
    c = Contact(1e-4, 2e7, 200, 0.2, position=0.5, law="linear", radius=0.1)
    st = RubStation(c, -2e-5, 0.0, Stator.isotropic(20, 5e6, 500))
    run = Run(speed=300.0, duration=duration, step=5e-5, save_every=2, initial=initial,
              speed_table=table)  # fmt: skip
    return simulate_general(rotor.linear_system((0.5,)), run, [st],
                            [Unbalance(2e-4, 0.5, unb_phase)], gravity=(-9.81, 0.0),
                            progress=False)  # fmt: skip


def test_scenario_equals_direct_api_run():
    """The scenario path builds exactly the run a user builds with simulate_general."""
    ds = rubrotor.simulate(scenario_from_dict(spec()), progress=False)
    ref = _direct()
    assert ds.attrs["status"] == "complete" and ref.status == "complete"
    assert ds.sizes["time"] == ref.time.size
    assert np.array_equal(ds["v"].values[0], ref.channels[0])
    assert np.array_equal(ds["normal_force"].values[0], ref.channels[4 + 6])
    assert ds["normal_force"].values.max() > 0  # the case rubs
    for name, unit in (("v", "m"), ("w_dot", "m/s"), ("v_ddot", "m/s^2"),
                       ("normal_force", "N"), ("stator_y", "m")):  # fmt: skip
        assert ds[name].attrs["units"] == unit


def test_speed_table_scenario_equals_direct_api_run(tmp_path, capsys):
    """``[speed] profile = "table"`` (up, then down) builds exactly ``Run(speed_table=...)``
    (reference: the run built by hand through the API); its Dataset's spin angle is the exact
    integral of the table; a table that stops before the run's end, or off the sample grid, is
    refused naming its file keys ``speed.times / speed.speeds``; a table with revolutions instead of a duration names
    ``simulation.revolutions``; the CLI exits 2 without a traceback."""
    times, speeds = [0.0, 0.012, 0.02], [300.0, 360.0, 330.0]
    sc = scenario_from_dict(spec(speed={"profile": "table", "times": times, "speeds": speeds}))
    ds = rubrotor.simulate(sc, progress=False)
    ref = _direct(table=tuple(zip(times, speeds, strict=True)))
    assert ds.attrs["status"] == "complete" and ref.stats["segments"] > 1
    assert np.array_equal(ds["v"].values[0], ref.channels[0])
    t = ds["time"].values
    up = 300 * t + 0.5 * 5000 * t**2
    down = 300 * 0.012 + 0.5 * 5000 * 0.012**2 + 360 * (t - 0.012) - 0.5 * 3750 * (t - 0.012) ** 2
    np.testing.assert_allclose(ds["tau"].values, np.where(t <= 0.012, up, down), rtol=1e-12)
    for tab in ({"times": [0, 0.01], "speeds": [300, 310]},
                {"times": [0, 0.01005, 0.03], "speeds": [300, 310, 320]}):  # fmt: skip
        bad = scenario_from_dict(spec(speed={"profile": "table", **tab}))
        with pytest.raises(rubrotor.InputError) as err:
            rubrotor.simulate(bad, progress=False)
        assert err.value.field == "speed.times / speed.speeds"
    revs = spec(speed={"profile": "table", "times": times, "speeds": speeds},
                simulation={"revolutions": 1, "dt": 5e-5, "save_every": 2})  # fmt: skip
    with pytest.raises(rubrotor.InputError) as err:
        rubrotor.simulate(scenario_from_dict(revs), progress=False)
    assert err.value.field == "simulation.revolutions"
    path = tmp_path / "short.toml"
    text = (SCENARIOS / "runup_rub.toml").read_text()
    text = text.replace(
        'profile = "linear"', 'profile = "table"\ntimes = [0.0, 0.5]\nspeeds = [150.0, 450.0]'
    )
    text = text.replace("from = 150.0", "").replace("to = 450.0", "")
    path.write_text(text)
    assert main(["simulate", str(path), "--out", str(tmp_path / "r.nc")]) == 2
    assert "speed.times / speed.speeds" in capsys.readouterr().err


def test_restart_from_file_continues_the_run(tmp_path):
    """T + restart(T) equals one run of 2T (rigid stator, no contact during the restart: the
    exponential stepper is exact on the linear part, so only rounding differs)."""
    free = spec(contact=None, gravity={"y": -9.81}, initial={"state": "static"},
                simulation={"duration": 0.01, "dt": 5e-5, "probes": [0.5]})  # fmt: skip
    first = rubrotor.simulate(scenario_from_dict(free), progress=False)
    path = tmp_path / "first.nc"
    rubrotor.save_dataset(first, path)
    again = {**free, "initial": {"state": "file", "path": str(path)}}
    second = rubrotor.simulate(scenario_from_dict(again), progress=False)
    longer = {**free, "simulation": {**free["simulation"], "duration": 0.02}}
    long = rubrotor.simulate(scenario_from_dict(longer), progress=False)
    n = first.sizes["time"]
    assert second["time"].values[0] == pytest.approx(first["time"].values[-1], rel=1e-12)
    v_long = long["v"].values[0, n - 1 :]
    v_rest = second["v"].values[0]
    scale = np.max(np.abs(v_long))
    assert np.max(np.abs(v_rest - v_long)) < 1e-9 * scale
    with pytest.raises(ScenarioError, match="initial.path"):
        rubrotor.simulate(
            scenario_from_dict(
                spec(**{**again, "section": [{**BASE["section"][0], "elements": 4}]})
            ),
            progress=False,
        )


def test_two_contacts():
    """Two stations (disk against a flexible offset stator, quarter span against a rigid ring):
    both are simulated, the tight one at the disk rubs, the far one at x = 0.25 m does not."""
    two = contact() + [{"position": 0.25, "radius": 0.02, "clearance": 1e-3, "law": "linear",
                        "stiffness": 1e7}]  # fmt: skip
    ds = rubrotor.simulate(scenario_from_dict(spec(contact=two)), progress=False)
    assert ds.sizes["contact"] == 2
    assert list(ds["station"].values[:2]) == [0.5, 0.25]
    assert ds["normal_force"].values[0].max() > 0
    assert ds["normal_force"].values[1].max() == 0
    assert np.all(ds["stator_y"].values[1] == 0)  # rigid


def test_huge_run_refused_before_start(tmp_path, capsys):
    """revolutions = 1e12 is refused (exit 2) naming the keys to change, without running."""
    text = (
        (SCENARIOS / "seal_rub.toml").read_text().replace("revolutions = 40", "revolutions = 1e12")
    )
    f = tmp_path / "huge.toml"
    f.write_text(text)
    assert main(["simulate", str(f), "--out", str(tmp_path / "h.nc")]) == 2
    err = capsys.readouterr().err
    assert "simulation.revolutions" in err and "simulation.save_every" in err
    assert not (tmp_path / "h.nc").exists()


@pytest.mark.parametrize(("name", "shorter"), [
    ("seal_rub", ("revolutions = 40", "revolutions = 4")),
    ("runup_rub", ("duration = 1.0 ", "duration = 0.1 ")),
])  # fmt: skip
def test_shipped_scenarios_through_the_cli(tmp_path, capsys, name, shorter):
    """The shipped files (shortened) run through ``rubrotor simulate`` and are listed."""
    assert name in [s["name"] for s in shipped_scenarios()]
    text = (SCENARIOS / f"{name}.toml").read_text()
    assert shorter[0] in text
    f = tmp_path / f"{name}.toml"
    f.write_text(text.replace(*shorter))
    out = tmp_path / "r.nc"
    assert main(["simulate", str(f), "--out", str(out)]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["status"] == "complete"
    ds = rubrotor.load_dataset(out)
    assert ds.attrs["status"] == "complete" and ds.attrs["engine"] == "general"
    for var in ("v", "w", "v_dot", "w_dot", "v_ddot", "normal_force", "friction_force"):
        assert "units" in ds[var].attrs, var
    assert len(json.loads(ds.attrs["final_state"])) > 0
    assert tomllib.loads(ds.attrs["scenario"])["meta"]["name"] == name


def test_streamed_cli_run_and_analyze(tmp_path, capsys, monkeypatch):
    """A run above the streaming threshold goes to the file chunk by chunk: same variables,
    attributes and samples as the in-memory run (accelerations by the same central differences),
    status and final state stored; ``rubrotor analyze`` reads it and ``--figure`` draws it."""
    import rubrotor.engine.general as se

    text = (SCENARIOS / "seal_rub.toml").read_text().replace("revolutions = 40", "revolutions = 2")
    f = tmp_path / "s.toml"
    f.write_text(text)
    mem = tmp_path / "mem.nc"
    assert main(["simulate", str(f), "--out", str(mem)]) == 0
    monkeypatch.setattr(se, "STREAM_SAMPLES", 100)
    streamed = tmp_path / "stream.nc"
    assert main(["simulate", str(f), "--out", str(streamed), "--figure"]) == 0
    capsys.readouterr()
    a, b = rubrotor.load_dataset(mem), rubrotor.load_dataset(streamed)
    assert b.attrs["status"] == "complete"
    assert set(a.variables) == set(b.variables) and set(a.attrs) == set(b.attrs)
    assert np.array_equal(a["v"].values, b["v"].values)
    # the same formula on chunk windows as on the whole record (one rounding at most)
    scale = np.abs(a["v_ddot"].values).max()
    assert np.abs(a["v_ddot"].values - b["v_ddot"].values).max() <= 1e-12 * scale
    assert np.array_equal(a["normal_force"].values, b["normal_force"].values)
    assert json.loads(a.attrs["final_state"]) == json.loads(b.attrs["final_state"])
    assert streamed.with_suffix(".png").stat().st_size > 0
    assert main(["analyze", str(streamed), "--out", str(tmp_path / "an"), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["spin_hz"] == pytest.approx(100.0)
    # the streamed file has no in_contact: the verdict reads the normal force; two revolutions
    # hold no Hann block of 0.5X (four), so the orders say why they are empty
    assert d["rub"]["rub"] == "yes" and d["rub"]["evidence"]["contact_time_s"] > 0
    assert d["orders"] == [] and "at least 4" in d["orders_note"]


def test_seed_engine_verbs_refuse_engine_scenarios():
    """Verbs that run the seed's engine (sweeps, convergence study) refuse a scenario whose
    contacts or gravity it would ignore; with_changes cannot edit an array of tables."""
    seed = tomllib.loads((SCENARIOS / "seed_case1.toml").read_text())
    seed["contact"] = [seed["contact"], {**seed["contact"], "position": 0.1}]
    sc = scenario_from_dict(seed)
    assert sc.engine is not None and len(sc.engine.stations) == 2
    with pytest.raises(ScenarioError, match="general-engine keys"):
        rubrotor.converge(sc)
    with pytest.raises(ScenarioError, match="contact.clearance"):
        sc.with_changes(**{"contact.clearance": 1e-4})
