"""Bad input ends in one named error, never a traceback or a silently wrong result (issue 21).

Each case was a traceback, an empty or junk result with exit 0, or a message naming a key the
user never set. The references are the inputs themselves: the error must name the key the test
changed, with its value; where a result is computed, it is compared with an independent route
(the branch point at STOP with a shot orbit at STOP; file modes with ``0666 & ~umask``, what a
plain ``open()`` gives).
"""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
import textwrap
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from test_mangled_scenarios import _dump

import rubrotor
from rubrotor.cli import main
from rubrotor.engine.output import claim_output, lock_path
from rubrotor.errors import InputError

SCENARIOS = Path(str(resources.files("rubrotor") / "scenarios"))
SRC = str(Path(rubrotor.__file__).parents[1])


def _seal(tmp_path, name="seal.toml", edit=None, revolutions=2) -> Path:
    """seal_rub.toml with ``edit(doc)`` applied and ``revolutions`` revolutions."""
    doc = tomllib.loads((SCENARIOS / "seal_rub.toml").read_text())
    doc["simulation"]["revolutions"] = revolutions
    if edit is not None:
        edit(doc)
    path = tmp_path / name
    path.write_text(_dump(doc))
    return path


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("rubrotor: error:"), err
    return lines[0]


# ---- files and the Python API ------------------------------------------------------------------
def test_scenario_file_not_utf8_is_named(tmp_path, capsys):
    bad = tmp_path / "seal.nc"
    bad.write_bytes(b"CDF\x01\x00\x00\xd0\xff" * 4)
    assert main(["modes", str(bad)]) == 2
    line = _one_error_line(capsys)
    assert "seal.nc" in line and "not UTF-8" in line and "0xd0" in line


def test_api_refuses_none_and_accepts_a_path(tmp_path):
    for call, field in ((lambda: rubrotor.simulate(None), "scenario"),
                        (lambda: rubrotor.lyapunov_exponents(None), "scenario"),
                        (lambda: rubrotor.modes(None), "scenario_or_shaft"),
                        (lambda: rubrotor.damped_modes(None), "rotor")):  # fmt: skip
        with pytest.raises(InputError) as err:
            call()
        assert err.value.field == field and err.value.value is None
    with pytest.raises(InputError) as err:
        rubrotor.save_dataset("abc", tmp_path / "x.nc")
    assert err.value.field == "ds" and err.value.value == "abc"
    path = SCENARIOS / "seed_rotor.toml"
    by_path = rubrotor.modes(str(path))
    assert [m.frequency_hz for m in by_path] == [
        m.frequency_hz for m in rubrotor.modes(rubrotor.load_scenario(path))
    ]
    with pytest.raises(InputError, match="no-such.toml"):
        rubrotor.simulate(tmp_path / "no-such.toml")


# ---- outputs: checked before computing, one writer, usual permissions ---------------------------
def _read_only_folder(tmp_path) -> Path:
    """A folder no file can be created in: chmod 0555 (or, as root, /sys, read-only to all)."""
    if os.geteuid() != 0:
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o555)
        return ro
    ro = Path("/sys")
    try:
        fd = os.open(ro / f".probe{os.getpid()}", os.O_CREAT | os.O_WRONLY, 0o600)
    except OSError:
        return ro
    os.close(fd)
    pytest.skip("no read-only folder on this machine")


@pytest.mark.parametrize(
    "verb, out",
    [("simulate", "x.nc"), ("run", "x"), ("campbell", "x.png"), ("sweep", "x.zarr"),
     ("continue", "x.nc"), ("analyze", "x")],
)  # fmt: skip
def test_read_only_output_refused_before_computing(verb, out, tmp_path, capsys, monkeypatch):
    """Every verb that writes refuses an unwritable --out before any computation (the
    computation is replaced by a failure, so reaching it fails the test)."""
    import rubrotor.engine.simulate as sim

    def never(*a, **k):
        raise AssertionError("computed before checking the output")

    monkeypatch.setattr(sim, "simulate", never)
    target = str(_read_only_folder(tmp_path) / out)
    scen = str(SCENARIOS / "seed_case1.toml")
    argv = {
        "simulate": ["simulate", scen, "--out", target],
        "run": ["run", scen, "--out", target],
        "campbell": ["campbell", scen, "--speeds", "0:100:2", "--out", target],
        "sweep": ["sweep", scen, "--vary", "unbalance.magnitude=1e-4:2e-4:2", "--out", target],
        "continue": ["continue", scen, "--vary", "speed.critical_multiple=1.5:1.6", "--out",
                     target],
        "analyze": ["analyze", scen, "--out", target],
    }[verb]  # fmt: skip
    assert main(argv) == 2
    line = _one_error_line(capsys)
    assert "--out" in line and "writable folder" in line


def test_simulate_without_contact_and_modes_of_files(tmp_path, capsys):
    """A general rotor without [[contact]] simulates (it raised after writing the file), and
    the streamed and in-memory files both get ``0666 & ~umask``, as a plain open() gives."""
    from rubrotor.engine.general import simulate_engine

    path = _seal(tmp_path, edit=lambda d: d.pop("contact"))
    out = tmp_path / "free.nc"
    assert main(["simulate", str(path), "--out", str(out)]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["status"] == "complete" and summary["max_normal_force_N"] in (0.0, None)
    plain = tmp_path / "plain"
    plain.write_text("")
    usual = stat.S_IMODE(plain.stat().st_mode)
    assert stat.S_IMODE(out.stat().st_mode) == usual
    streamed = tmp_path / "streamed.nc"
    simulate_engine(rubrotor.load_scenario(path), progress=False, stream=streamed)
    assert stat.S_IMODE(streamed.stat().st_mode) == usual


def test_a_path_another_run_writes_is_refused(tmp_path, capsys):
    """A live run holding the target's lock: refused naming its pid; once it died (SIGKILL,
    its lock left behind), the lock is stale and the next run takes it and removes it."""
    target = tmp_path / "r.nc"
    holder = textwrap.dedent(
        f"""
        import time
        from rubrotor.engine.output import claim_output
        with claim_output({str(target)!r}):
            print("held", flush=True)
            time.sleep(120)
        """
    )
    env = dict(os.environ, PYTHONPATH=SRC)
    proc = subprocess.Popen([sys.executable, "-c", holder], stdout=subprocess.PIPE, env=env)
    with proc:
        assert proc.stdout.readline().strip() == b"held"
        scen = str(_seal(tmp_path, edit=lambda d: d.pop("contact")))
        assert main(["simulate", scen, "--out", str(target)]) == 2
        line = _one_error_line(capsys)
        assert f"process {proc.pid} is writing it" in line and not target.exists()
        proc.kill()
        proc.wait()
    assert lock_path(target).exists()  # left by the killed run
    assert main(["simulate", scen, "--out", str(target)]) == 0
    assert target.exists() and not lock_path(target).exists()
    with claim_output(target) as p:  # this process may claim it again
        assert p == target


# ---- sizes and scales named by key --------------------------------------------------------------
def test_mesh_too_large_for_memory_is_refused_by_key(tmp_path, capsys):
    fine = _seal(tmp_path, "fine.toml", edit=lambda d: d["rotor"].update(max_element_length=1e-6))
    assert main(["modes", str(fine)]) == 2
    line = _one_error_line(capsys)
    assert "rotor.max_element_length = 1e-06" in line and "GiB" in line
    many = _seal(tmp_path, "many.toml", edit=lambda d: d["section"][1].update(elements=10000))
    assert main(["modes", str(many)]) == 2
    line = _one_error_line(capsys)
    assert "section[2].elements = 10000" in line and "GiB" in line


@pytest.mark.parametrize(
    "key, value", [("kzy", -1.5e307), ("kzy", -1.5e100), ("cyy", 5e304)]
)  # fmt: skip
def test_bearing_coefficient_off_scale_is_refused(key, value, tmp_path, capsys):
    """It printed no mode (or junk ones: 3e-9 Hz, damping ratio -0.58) with exit 0."""
    path = _seal(tmp_path, edit=lambda d: d["bearing"][1].update({key: value}))
    assert main(["modes", str(path)]) == 2
    assert f"bearing[2].{key} = {value!r}" in _one_error_line(capsys)


def test_modes_within_the_scale_limit_are_those_of_the_rigid_limit(tmp_path, capsys):
    """Up to the limit the coefficient acts as a constraint: the modes at kzy = -3e22 and
    -1.5e14 (both far stiffer than the shaft's scale, 3.9e10 N/m) agree to 1e-6."""
    freqs = []
    for v in (-1.5e14, -3e22):
        path = _seal(tmp_path, f"k{v}.toml", edit=lambda d, v=v: d["bearing"][1].update(kzy=v))
        ds = rubrotor.damped_modes(rubrotor.load_scenario(path))
        freqs.append([m.frequency_hz for m in ds.modes[:6]])
    np.testing.assert_allclose(freqs[1], freqs[0], rtol=1e-6)


def test_stiff_bearing_simulates_as_the_rigid_limit(tmp_path, capsys):
    """``bearing[2].kzz = 2e18`` (5e7 times the shaft's stiffness scale) was refused naming the
    speed (``a speed off an undamped critical``: the unscaled dynamic stiffness's rcond); the
    run now equals the one at 1e14 N/m, already rigid, to 1e-6 (measured 8e-8)."""
    peaks = []
    for k in (1e14, 2e18):
        path = _seal(tmp_path, f"k{k:g}.toml", edit=lambda d, k=k: d["bearing"][1].update(kzz=k))
        ds = rubrotor.simulate(path, progress=False)
        assert ds.attrs["status"] == "complete"
        peaks.append(float(ds["normal_force"].max()))
    assert peaks[1] == pytest.approx(peaks[0], rel=1e-6)


def test_ill_conditioned_modes_name_the_density(tmp_path, capsys):
    """``density = 0.0078`` reported ``speed = '-' is not allowed ... (cond 3.54e+10)``."""
    path = _seal(tmp_path, edit=lambda d: d["materials"]["steel"].update(density=0.0078))
    assert main(["simulate", str(path), "--out", str(tmp_path / "d.nc")]) == 2
    line = _one_error_line(capsys)
    assert "materials.steel.density = 0.0078" in line and "cond" in line


# ---- messages naming the keys the file sets ----------------------------------------------------
def test_step_longer_than_the_run_names_dt(tmp_path, capsys):
    path = _seal(tmp_path, edit=lambda d: d["simulation"].update(dt=1))
    assert main(["simulate", str(path), "--out", str(tmp_path / "d.nc")]) == 2
    line = _one_error_line(capsys)
    assert "simulation.dt = 1" in line and "simulation.revolutions = 2" in line
    assert "duration" not in line


def test_change_that_removes_a_needed_key_names_the_change(tmp_path, capsys):
    runup = str(SCENARIOS / "runup_rub.toml")
    argv = ["continue", runup, "--vary", "speed.rad_per_s=300:310", "--out"]
    assert main(argv + [str(tmp_path / "b.nc")]) == 2
    line = _one_error_line(capsys)
    assert "speed.rad_per_s = 300.0" in line and "speed.from = 150.0" in line
    assert "None" not in line


def test_no_station_to_save_names_probes(tmp_path, capsys):
    def edit(d):
        d.pop("contact")
        d["simulation"].pop("probes")

    path = _seal(tmp_path, edit=edit)
    assert main(["simulate", str(path), "--out", str(tmp_path / "d.nc")]) == 2
    line = _one_error_line(capsys)
    assert "simulation.probes is missing" in line and "None" not in line and "()" not in line


def test_continuation_ends_on_stop():
    """``--points 10`` over 300:305 returned 300 and 306; the last point now lies on STOP and
    equals the orbit shot there (an independent Newton on the map at that key value)."""
    from test_follow_sweep import HYST

    from rubrotor.orbits.continuation import continue_orbit
    from rubrotor.orbits.shooting import shoot, state_vector

    key, stop = "speed.critical_multiple", 1.72
    branch = continue_orbit(HYST, key, 1.8, stop, steps=128, points=10, ds=0.2, ds_max=0.5,
                            method="shooting")  # fmt: skip
    values = [p.value for p in branch.points]
    assert values[-1] == pytest.approx(stop, abs=1e-12) and len(values) >= 2
    assert all(stop - 1e-12 <= v <= 1.8 for v in values)
    shot = shoot(HYST.with_changes(**{key: stop}), branch.points[-2].state, steps=128)
    a, b = state_vector(branch.points[-1].state), state_vector(shot.state)
    assert np.linalg.norm(a - b) <= 1e-8 * np.linalg.norm(b)
