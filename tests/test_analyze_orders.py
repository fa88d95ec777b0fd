"""`rubrotor analyze` on run-ups and measured probe files: orders, rub verdict, time columns,
scalogram peaks; the simulate summary's speed profile; streamed run-ups' spin angle."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from rubrotor import load_scenario, simulate
from rubrotor.analysis.indicators import scalogram_peaks
from rubrotor.analysis.verdict import rub_evidence, rub_verdict
from rubrotor.cli import main

sys.path.insert(0, str(Path(__file__).parent))
from orders_reference import KNOWN, SLOW_RUNUP, synthetic  # noqa: E402


def _probe_csv(path, column="speed_rad_s", fs=1000.0):
    t = np.arange(int(2.0 * fs)) / fs
    theta = 60.0 * t + 20.0 * t**2
    y, z = synthetic(t, theta)
    aux = {"speed_rad_s": 60.0 + 40.0 * t, "keyphasor": np.sin(theta)}[column]
    np.savetxt(path, np.column_stack([t, aux, y, z]), delimiter=",",
               header=f"time,{column},y,z", comments="")  # fmt: skip
    return path


def test_csv_with_time_and_speed_columns_gives_orders_without_fs(tmp_path, capsys):
    """A measured-style CSV (time, speed, y, z) needs no --fs; its orders in the JSON equal the
    amplitudes and phases the signal was built with to 1e-3 (relative, rad)."""
    path = _probe_csv(tmp_path / "probe.csv")
    code = main(["analyze", str(path), "--columns", "y,z", "--out", str(tmp_path / "o"), "--json"])
    assert code == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    assert "speed varies from 60" in cap.err
    assert d["fs_hz"] == pytest.approx(1000.0, rel=1e-9) and d["spin_hz"] is None
    rows = {r["order"]: r for r in d["orders"]}
    assert set(rows) == {0.5, 1.0, 2.0}
    for k, ((ay, py), (az, pz)) in KNOWN.items():
        r = rows[k]
        assert np.allclose(r["amplitude_y_m"], ay, rtol=1e-3)
        assert np.allclose(r["amplitude_z_m"], az, rtol=1e-3)
        assert np.max(np.abs(np.angle(np.exp(1j * (np.array(r["phase_y_rad"]) - py))))) < 1e-3
        assert np.max(np.abs(np.angle(np.exp(1j * (np.array(r["phase_z_rad"]) - pz))))) < 1e-3
    assert min(rows[1.0]["speed_rad_s"]) < 80 and max(rows[1.0]["speed_rad_s"]) > 130
    # no clearance given, no sub-harmonic, 2X/1X = |(6, 4)| / |(25, 18)| = 0.234 < 0.3: "no"
    assert d["rub"]["rub"] == "no"
    two = d["rub"]["evidence"]["superharmonic"]["2"]["max_ratio"]
    assert two == pytest.approx(np.hypot(6, 4) / np.hypot(25, 18), rel=1e-3)
    assert (tmp_path / "o" / "orders.png").stat().st_size > 10000
    assert (tmp_path / "o" / "cascade.png").stat().st_size > 10000
    # the default column is the first probe signal, not the time or speed column
    assert main(["analyze", str(path), "--out", str(tmp_path / "o2"), "--rpm"]) == 0
    text = capsys.readouterr().out
    assert "rub indicators of y\n" in text and "spin speed range" in text
    assert "spin frequency" not in text and "\nrub: " in text


def test_measured_verdict_reads_its_signs():
    """Rub verdict of measured orbits (no contact data), against signals built to show each sign.

    References: a 1X ellipse at 30 % of the clearance shows no sign ("no"); the same orbit
    reaching 95 % of the clearance shows proximity only ("possible"); a 1X circle of 60 um with
    a 0.5X of 60 % of 1X reaches 96 um: proximity and a sub-harmonic ("yes").
    """
    from rubrotor.analysis.orders import spin_from_speed

    t = np.arange(8000) / 4000.0
    spin = spin_from_speed(t, np.full(t.size, 150.0))
    th = spin.angle
    c = 100e-6
    calm = rub_verdict(rub_evidence(spin, 30e-6 * np.cos(th), 20e-6 * np.sin(th), clearance=c))
    assert calm.verdict == "no"
    near = rub_verdict(rub_evidence(spin, 95e-6 * np.cos(th), 60e-6 * np.sin(th), clearance=c))
    assert near.verdict == "possible" and "95%" in near.reasons[0]
    y = 60e-6 * np.cos(th) + 36e-6 * np.cos(0.5 * th)
    z = 60e-6 * np.sin(th) + 36e-6 * np.sin(0.5 * th)
    rub = rub_verdict(rub_evidence(spin, y, z, clearance=c))
    assert rub.verdict == "yes"
    assert rub.evidence["subharmonic"]["0.5"]["max_ratio"] == pytest.approx(0.6, rel=1e-3)


def test_runup_results_file_tracks_orders_and_warns(tmp_path, capsys):
    """`analyze` on a run-up: no single spin frequency (a warning instead), orders against the
    run's speed for every station, rub "no" for a run without contact; the simulate summary
    gives the speed law. Reference: the scenario's table 120 -> 420 rad/s."""
    scen = tmp_path / "slow.toml"  # a shorter table: 120 rad/s for 0.5 s, then up to 420 in 2 s
    short = SLOW_RUNUP.replace("times = [0.0, 1.0, 11.0]", "times = [0.0, 0.5, 2.5]")
    scen.write_text(
        short.replace("duration = 11.0", "duration = 2.5").replace(
            "save_every = 2", "save_every = 4"
        )
    )
    nc = tmp_path / "slow.nc"
    assert main(["simulate", str(scen), "--out", str(nc)]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["speed_rad_s"] == 120.0
    assert summary["speed_end_rad_s"] == pytest.approx(420.0, rel=1e-9)
    assert summary["speed_profile"] == {"kind": "table", "times_s": [0.0, 0.5, 2.5],
                                        "speeds_rad_s": [120.0, 120.0, 420.0]}  # fmt: skip
    assert main(["analyze", str(nc), "--json", "--orders", "1,2"]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    assert "speed varies from 120 to 420 rad/s" in cap.err
    assert d["spin_hz"] is None and "harmonic_ratio" not in d
    assert d["speed_range_rad_s"] == pytest.approx([120.0, 420.0], rel=1e-9)
    assert {(r["probe_m"], r["order"]) for r in d["orders"]} == {
        (p, k) for p in (0.25, 0.5) for k in (1.0, 2.0)
    }
    one = next(r for r in d["orders"] if r["probe_m"] == 0.5 and r["order"] == 1.0)
    assert len(one["speed_rad_s"]) > 40 and max(one["speed_rad_s"]) > 400
    assert d["rub"]["rub"] == "no" and d["rub"]["evidence"]["contact_time_s"] == 0.0
    assert "no stator to rub" in d["rub"]["reasons"][0]
    assert main(["analyze", str(nc), "--clearance", "1e-4"]) == 2  # a results file has its own
    assert "--clearance" in capsys.readouterr().err


def test_scalogram_peaks_are_interior():
    """The grid's edges are never peaks: a monotonic scalogram has none; a hump has its top."""
    f = np.geomspace(10, 1000, 50)
    assert scalogram_peaks(f, f**2).size == 0
    hump = np.exp(-(np.log(f / 100.0) ** 2)) + f / 1000.0  # rises again at the top edge
    peaks = scalogram_peaks(f, hump)
    assert peaks.size == 1 and peaks[0] == pytest.approx(100.0, rel=0.1)


def test_csv_tone_near_the_top_of_the_grid_is_not_reported_as_an_edge_peak(tmp_path, capsys):
    """A tone above the scalogram's range makes the inner scalogram rise to its top edge; the
    peak list reports the interior maximum at the 1X tone (50 Hz) and never the edge."""
    fs = 2000.0
    t = np.arange(8000) / fs
    x = np.cos(2 * np.pi * 50 * t) + 3 * np.cos(2 * np.pi * 950 * t)
    path = tmp_path / "tone.csv"
    np.savetxt(path, np.column_stack([t, x]), delimiter=",", header="time,x", comments="")
    assert main(["analyze", str(path), "--json", "--out", str(tmp_path)]) == 0
    d = json.loads(capsys.readouterr().out)
    top = d["frequency_range_hz"][1]
    assert all(f < top * (1 - 1e-9) for f in d["inner_scalogram_peaks_hz"])
    assert any(abs(f - 50) < 5 for f in d["inner_scalogram_peaks_hz"])
    assert d["rub"]["rub"] == "unknown"  # no speed column and no --spin-hz


def test_streamed_runup_file_has_the_spin_angle_of_the_run(tmp_path):
    """A run-up streamed to disk carries the same spin angle as the in-memory run (it carried
    speed * t before). Reference: the in-memory Dataset's ``tau``, the exact integral of the
    speed table."""
    from rubrotor.engine.general import simulate_engine
    from rubrotor.engine.result import load_dataset

    path = tmp_path / "slow.toml"
    path.write_text(SLOW_RUNUP)
    sc = load_scenario(path)
    mem = simulate(sc)
    streamed = load_dataset(simulate_engine(sc, stream=tmp_path / "s.nc", progress=False))
    assert np.allclose(streamed["tau"].values, mem["tau"].values, rtol=1e-12, atol=1e-9)
    assert streamed["tau"].values[-1] == pytest.approx(120.0 + 0.5 * (120 + 420) * 10, rel=1e-12)
    from rubrotor.cli.simulate import streamed_summary

    summary = streamed_summary(tmp_path / "s.nc")  # read chunk by chunk, as the CLI does
    assert summary["speed_profile"]["speeds_rad_s"] == [120.0, 120.0, 420.0]
    assert summary["speed_end_rad_s"] == pytest.approx(420.0, rel=1e-12)


@pytest.mark.parametrize(
    ("option", "needle"),
    [(["--orders", "abc"], "--orders"), (["--orders", "0"], "--orders"),
     (["--orders", "0.123456"], "--orders"), (["--clearance", "-1"], "--clearance")],
)  # fmt: skip
def test_bad_order_options_fail_first_naming_the_option(tmp_path, capsys, option, needle):
    """Bad --orders / --clearance values exit 2 with one line naming the option and the value."""
    path = _probe_csv(tmp_path / "probe.csv")
    assert main(["analyze", str(path), *option, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("rubrotor: error:") and needle in err and option[1] in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o" / "analysis.png").exists()  # refused before any analysis
