"""`rubrotor analyze`: signal files and results files, indicators, figure, input errors."""

from __future__ import annotations

import json
from importlib import resources

import numpy as np
import pytest

from rubrotor import load_scenario, save_dataset, simulate
from rubrotor.analysis.overview import analyze_signal, band_energy, decimate_to
from rubrotor.cli import main
from rubrotor.engine.settings import Integrator

FS = 20000.0
SPIN = 100.0


def _orbit(n=8000):
    t = np.arange(n) / FS
    # forward 1X circle plus a weaker backward 2 kHz whirl
    v = np.cos(2 * np.pi * SPIN * t) + 0.1 * np.cos(2 * np.pi * 2000 * t)
    w = np.sin(2 * np.pi * SPIN * t) - 0.1 * np.sin(2 * np.pi * 2000 * t)
    return v, w


@pytest.fixture
def csv_file(tmp_path):
    v, w = _orbit()
    p = tmp_path / "sig.csv"
    np.savetxt(p, np.column_stack([v, w]), delimiter=",", header="v,w", comments="")
    return p


def test_csv_two_columns(csv_file, tmp_path, capsys):
    out = tmp_path / "out"
    code = main(
        [
            "analyze",
            str(csv_file),
            "--fs",
            str(FS),
            "--columns",
            "v,w",
            "--spin-hz",
            str(SPIN),
            "--out",
            str(out),
            "--json",
        ]
    )
    assert code == 0
    d = json.loads(capsys.readouterr().out)
    assert (out / "analysis.png").stat().st_size > 10000
    assert json.loads((out / "indicators.json").read_text()) == d
    # backward energy: 0.1^2 of the 1 + 0.1^2 total
    assert d["backward_share"] == pytest.approx(0.01 / 1.01, rel=0.05)
    peaks = d["inner_scalogram_peaks_hz"]
    assert any(abs(f - SPIN) / SPIN < 0.05 for f in peaks[:2])
    assert any(abs(f - 2000) / 2000 < 0.05 for f in peaks[:2])


def test_single_column_npy_and_wav(tmp_path, capsys):
    from scipy.io import wavfile

    v, _ = _orbit()
    np.save(tmp_path / "x.npy", v)
    assert (
        main(
            [
                "analyze",
                str(tmp_path / "x.npy"),
                "--fs",
                str(FS),
                "--out",
                str(tmp_path / "a"),
                "--spin-hz",
                str(SPIN),
                "--json",
            ]
        )
        == 0
    )
    d = json.loads(capsys.readouterr().out)
    assert d["backward_share"] is None and d["channels"] == ["0"]
    wavfile.write(tmp_path / "x.wav", int(FS), (v * 1000).astype(np.int16))
    assert main(["analyze", str(tmp_path / "x.wav"), "--out", str(tmp_path / "b")]) == 0
    assert "inner-scalogram peak" in capsys.readouterr().out
    assert (tmp_path / "b" / "analysis.png").is_file()


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["missing.csv", "--fs", "1000"], "an existing file"),
        (["{d}/sig.txt", "--fs", "1000"], "a file ending in"),
        (["{csv}", "--fs", "0"], "--fs"),
        (["{csv}", "--fs", "-5"], "--fs"),
        (["{csv}"], "--fs"),
        (["{csv}", "--fs", "1000", "--columns", "q"], "one of the columns v, w"),
        (["{nan}", "--fs", "1000"], "finite data"),
    ],
)
def test_bad_input(args, needle, csv_file, tmp_path, capsys):
    (tmp_path / "sig.txt").write_text("1\n2\n")
    x = np.ones(100)
    x[5] = np.nan
    np.save(tmp_path / "nan.npy", x)
    args = [a.format(d=tmp_path, csv=csv_file, nan=tmp_path / "nan.npy") for a in args]
    assert main(["analyze", *args, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("rubrotor: error:") and needle in err
    assert len(err.strip().splitlines()) == 1


def test_results_file(tmp_path, capsys):
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")
    ds = simulate(
        sc, integrator=Integrator(revolutions=30, dtau=1e-3, save_every=32), progress=False
    )
    save_dataset(ds, tmp_path / "results.nc")
    assert main(["analyze", str(tmp_path / "results.nc")]) == 0
    out = capsys.readouterr().out
    assert "band energy 1F shear" in out and "backward-whirl share" in out
    d = json.loads((tmp_path / "indicators.json").read_text())
    labels = {m["label"] for m in d["modes"]}
    # both whirl directions and both branches of every mode, at the operating speed
    assert {"1F bending", "1B bending", "1F shear", "1B shear", "3F shear"} <= labels
    assert d["unit"] == "m/s^2" and d["spin_hz"] == pytest.approx(1848.38, rel=1e-4)
    assert (tmp_path / "analysis.png").is_file()
    # a constant-speed run: one speed per tracked order (the run's), and a rub verdict from its
    # contact data
    speed = float(ds.attrs["speed_rad_s"])
    assert {r["order"] for r in d["orders"]} == {0.5, 1.0, 2.0}
    for r in d["orders"]:
        assert r["speed_rad_s"] == pytest.approx([speed], rel=1e-9) and len(r["phase_z_rad"]) == 1
    one = next(r for r in d["orders"] if r["order"] == 1.0)
    assert (
        0.1 * np.abs(ds["v"].values).max() < one["amplitude_y_m"][0] <= np.abs(ds["v"].values).max()
    )
    ev = d["rub"]["evidence"]
    assert (
        d["rub"]["rub"] == "yes" and ev["contact_time_s"] > 0 and ev["impacts_per_revolution"] > 0
    )
    assert "rub: yes: rotor and stator touch" in out


def test_band_energy_and_decimate():
    v, w = _orbit()
    assert band_energy(v, FS, 1500, 2500, w=w) == pytest.approx(0.01, rel=0.02)
    assert band_energy(v, FS, 1500, 2500) == pytest.approx(0.005, rel=0.02)
    (d,), fs = decimate_to([v], FS, 5000.0)
    assert fs == 5000.0 and d.size == v.size // 4
    a = analyze_signal(d, fs, spin_hz=SPIN)
    assert a.indicators is not None and not a.two_channel
