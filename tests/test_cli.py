"""Command line: output shapes, exit codes, error messages without tracebacks."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from importlib import resources
from pathlib import Path

import pytest

import rubrotor
from rubrotor.cli import COMMANDS, main, parse_speeds
from rubrotor.errors import InputError

SEED = str(resources.files("rubrotor") / "scenarios" / "seed_rotor.toml")
SRC = str(Path(rubrotor.__file__).resolve().parent.parent)


@pytest.fixture
def bad_scenario(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("[shaft]\nlenght = 0.4\n[speed]\nrpm = 1000\n")
    return str(p)


def test_registry():
    assert [c.name for c in COMMANDS][:3] == ["modes", "critical", "campbell"]


def test_modes_json(capsys):
    assert main(["modes", SEED, "--json", "--speed", "0"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"speed_rad_s", "modes", "modal_masses", "modal_mass_normalisation"}
    assert out["speed_rad_s"] == 0.0
    assert len(out["modes"]) == 12
    first = out["modes"][0]
    assert set(first) == {"n", "branch", "whirl", "frequency_hz"}
    assert (first["n"], first["branch"], first["whirl"]) == (1, "bending", "backward")
    assert first["frequency_hz"] == pytest.approx(1193.2, abs=0.05)
    assert all(m["frequency_hz"] > 0 for m in out["modes"])


def test_modes_default_speed_and_table(capsys):
    assert main(["modes", SEED, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["speed_rad_s"] == pytest.approx(1.5 * 7742.494, rel=1e-6)
    assert main(["modes", SEED]) == 0
    text, masses = capsys.readouterr().out.split("modal masses", 1)  # masses: modes at rest
    assert "frequency (Hz)" in text and "shear" in text and "1193" not in text
    assert "1193.19" in masses


def test_critical_json_and_table(capsys):
    assert main(["critical", SEED, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    first = [c for c in out["critical_speeds"] if c["whirl"] == "forward"][0]
    assert first == {
        "n": 1,
        "branch": "bending",
        "whirl": "forward",
        "speed_rad_s": pytest.approx(7742.5, abs=0.05),
    }
    assert main(["critical", SEED]) == 0
    text = capsys.readouterr().out
    assert "speed (rpm)" in text and "1232.26" in text and "73935" in text


def test_campbell_writes_png_and_json(tmp_path, capsys):
    out = tmp_path / "campbell.png"
    assert main(["campbell", SEED, "--speeds", "0:60000:50", "--out", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out.stat().st_size > 10_000
    assert len(data["speed_rad_s"]) == 50
    assert len(data["modes"]) == 12
    assert len(data["modes"][0]["frequency_hz"]) == 50
    assert sorted(os.listdir(tmp_path)) == ["campbell.png"]  # no temporary file left


@pytest.mark.parametrize("speeds", ["0:60000", "a:b:c", "100:0:10", "0:1000:1", "0:1e3:2.5"])
def test_campbell_bad_speeds(speeds, tmp_path, capsys):
    out = tmp_path / "c.png"
    assert main(["campbell", SEED, "--speeds", speeds, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("rubrotor: error: --speeds") and "START:STOP:COUNT" in err
    assert not out.exists()


def test_parse_speeds():
    assert parse_speeds("10:20:11")[1] == pytest.approx(11.0)
    with pytest.raises(InputError):
        parse_speeds("-1:5:3")


def test_bad_scenario_in_process(bad_scenario, capsys):
    assert main(["modes", bad_scenario]) == 2
    err = capsys.readouterr().err
    assert err.startswith("rubrotor: error: ") and "shaft.lenght" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_missing_file(tmp_path, capsys):
    assert main(["critical", str(tmp_path / "nope.toml")]) == 2
    assert "cannot read" in capsys.readouterr().err


def test_usage_error(capsys):
    assert main(["frobnicate"]) == 2
    assert "invalid choice" in capsys.readouterr().err


def _run(*args):
    env = dict(os.environ, PYTHONPATH=SRC)
    return subprocess.run(
        [sys.executable, "-m", "rubrotor", *args],
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )


def test_subprocess_modes_json_and_error(bad_scenario):
    ok = _run("modes", SEED, "--json")
    assert ok.returncode == 0, ok.stderr
    out = json.loads(ok.stdout)
    assert set(out) >= {"speed_rad_s", "modes", "modal_masses"} and len(out["modes"]) == 12
    bad = _run("modes", bad_scenario)
    assert bad.returncode == 2
    assert bad.stderr.startswith("rubrotor: error: ") and "shaft.lenght" in bad.stderr
    assert "Traceback" not in bad.stderr and bad.stdout == ""
