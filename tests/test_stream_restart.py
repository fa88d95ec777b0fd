"""Streamed runs survive kills and continue exactly; restarts check what they restart.

The streamed runs are ``rubrotor simulate`` of ``seal_rub.toml`` (a general rotor in a full
annular rub against a flexible, offset seal casing) in child processes killed with
``SIGKILL`` or ``SIGTERM`` (the child only drops a marker file after its n-th flushed chunk,
so the kill lands while it computes or writes the next ones). The reference for a continued
run is the same scenario run without interruption: a second route through the same engine
that never writes or reads a restart state, so their agreement measures the restart alone.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import rubrotor
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.general import _problem, simulate_engine
from rubrotor.errors import InputError, ScenarioError
from rubrotor.scenario.load import load_scenario

SEAL = Path(__file__).parents[1] / "src" / "rubrotor" / "scenarios" / "seal_rub.toml"
SRC = str(Path(__file__).parents[1] / "src")
DT = 2e-5  # s, seal_rub's step (one sample per step)
CHUNK = 1 << 14  # samples per chunk of simulate_general (its default)

CHILD = textwrap.dedent(
    """
    import sys
    from pathlib import Path

    import rubrotor.engine.stream as stream

    marker, after = Path(sys.argv[1]), int(sys.argv[2])
    inner = stream.NetcdfSink.checkpoint

    def checkpoint(self, *a, **k):
        inner(self, *a, **k)
        if self.n_checkpoints == after:  # the initial state, then one row per chunk
            marker.write_text("flushed")

    stream.NetcdfSink.checkpoint = checkpoint
    from rubrotor.cli.app import main

    sys.exit(main(sys.argv[3:]))
    """
)


def seal_text(revolutions: float | None = None, initial: str | None = None, **sim) -> str:
    """seal_rub.toml with its revolutions, [initial] table or [simulation] keys changed."""
    text = SEAL.read_text()
    if revolutions is not None:
        text = text.replace("revolutions = 40", f"revolutions = {revolutions}")
    if initial is not None:
        text = text.replace('state = "static"          # start on the static deflection under '
                            "gravity", initial)  # fmt: skip
    if "duration" in sim:
        text = text.replace("revolutions = 40\n", "")
    for key, val in sim.items():
        text = text.replace("[simulation]\n", f"[simulation]\n{key} = {val}\n")
    return text


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def env() -> dict:
    return {**os.environ, "PYTHONPATH": SRC, "OPENBLAS_NUM_THREADS": "1"}


def start_and_signal(tmp_path: Path, sig: int, after: int = 3):
    """Start a streamed ``rubrotor simulate`` of seal_rub over 10,000 revolutions (5e6 samples,
    far longer than the test waits), send ``sig`` once ``after`` restart rows are flushed;
    the results file and the child's return code."""
    scen = write(tmp_path, "long.toml", seal_text(revolutions=10000))
    out = tmp_path / "k.nc"
    marker = tmp_path / "marker"
    cmd = [sys.executable, "-c", CHILD, str(marker), str(after), "simulate", str(scen),
           "--out", str(out), "--no-progress"]  # fmt: skip
    child = subprocess.Popen(cmd, env=env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 300
    while not marker.exists():
        assert child.poll() is None, child.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.005)
    child.send_signal(sig)
    _, err = child.communicate(timeout=300)
    return out, child.returncode, err.decode()


def restart_row(path: Path) -> tuple[float, np.ndarray]:
    """Time (s) and vector of a file's last restart state."""
    with xr.open_dataset(path) as ds:
        return float(ds["restart_time"].values[-1]), ds["restart_vector"].values[-1]


def test_kill_9_leaves_a_readable_partial_file_that_continues_exactly(tmp_path):
    """``kill -9`` of a streamed run: the file under its own name (no hidden temporary file,
    the usual permissions) is readable, marked partial, holds whole chunks (1 + k 16384 samples, k >= 2) and the
    state at the end of the last one; continued from it for 2,500 steps it ends where one
    uninterrupted run of the same total length ends, to 1e-9 (state vector, relative)."""
    out, code, _ = start_and_signal(tmp_path, signal.SIGKILL)
    assert code == -signal.SIGKILL
    # no hidden temporary data file; the output lock of the killed writer may stay behind (it
    # names a dead pid, and the next run on this path takes it over: tests/test_bad_input.py)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert [n for n in names if n != ".k.nc.lock"] == ["k.nc", "long.toml", "marker"]
    umask = os.umask(0o022)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~umask  # as an in-memory run's file (not 0600)
    with xr.open_dataset(out) as ds:
        n = ds.sizes["time"]
        assert ds.attrs["status"] == "partial" and "killed" in ds.attrs["status_message"]
        assert (n - 1) % CHUNK == 0 and (n - 1) // CHUNK >= 2
        assert ds.sizes["checkpoint"] == 1 + (n - 1) // CHUNK
        t_end = float(ds["time"].values[-1])
        assert float(ds["restart_time"].values[-1]) == t_end
        for var in ("v", "w", "v_dot", "v_ddot", "normal_force", "stator_y", "tau"):
            assert np.isfinite(ds[var].values).all(), var
        assert ds["normal_force"].values[0, -CHUNK:].min() > 0  # in the rub, not before it
    extra = 2500
    cont = write(tmp_path, "cont.toml", seal_text(
        initial=f'state = "file"\npath = "{out}"', duration=extra * DT))  # fmt: skip
    continued = simulate_engine(load_scenario(cont), progress=False)
    assert continued.attrs["status"] == "complete"
    assert float(continued["time"].values[0]) == t_end
    steps = round(t_end / DT) + extra
    whole = simulate_engine(load_scenario(write(tmp_path, "whole.toml", seal_text(
        duration=steps * DT))), progress=False)  # fmt: skip
    a = np.array(json.loads(continued.attrs["final_state"]))
    b = np.array(json.loads(whole.attrs["final_state"]))
    assert np.abs(a - b).max() <= 1e-9 * np.abs(b).max()
    fa = continued["normal_force"].values[0, -1]
    fb = whole["normal_force"].values[0, -1]
    assert fa == pytest.approx(fb, rel=1e-9) and fb > 100  # N: pressed into the seal


def test_sigterm_stops_between_chunks_like_sigint(tmp_path):
    """SIGTERM ends the run after its current chunk: exit status 1 with a warning, the file
    complete in its attributes (status partial naming SIGTERM, end time, final state), its
    data up to the last chunk and a restart state there."""
    out, code, err = start_and_signal(tmp_path, signal.SIGTERM)
    assert code == 1 and "SIGTERM" in err
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == "partial" and "SIGTERM" in ds.attrs["status_message"]
        t_end = float(ds["time"].values[-1])
        assert ds.attrs["end_time_s"] == t_end and (ds.sizes["time"] - 1) % CHUNK == 0
        assert float(ds["restart_time"].values[-1]) == t_end
        assert len(json.loads(ds.attrs["final_state"])) > 0


def test_restart_refuses_another_model(tmp_path):
    """A seal_rub result restarted after moving the seal from 0.75 to 0.70 m is refused naming
    ``contact[1].position``; a stiffer bearing (same mesh, other matrices) names the matrix."""
    first = tmp_path / "first.nc"
    rubrotor.save_dataset(simulate_engine(load_scenario(write(tmp_path, "a.toml", seal_text(
        revolutions=1))), progress=False), first)  # fmt: skip
    moved = seal_text(initial=f'state = "file"\npath = "{first}"', revolutions=1)
    moved = moved.replace("position = 0.75           # m", "position = 0.70           # m")
    with pytest.raises(ScenarioError, match=r"contact\[1\]\.position.*0\.7.*0\.75"):
        simulate_engine(load_scenario(write(tmp_path, "b.toml", moved)), progress=False)
    stiff = seal_text(initial=f'state = "file"\npath = "{first}"', revolutions=1)
    stiff = stiff.replace("kyy = 8.0e7", "kyy = 9.0e7")
    with pytest.raises(ScenarioError, match="stiffness matrix differs"):
        simulate_engine(load_scenario(write(tmp_path, "c.toml", stiff)), progress=False)


def test_diverged_run_restarts_from_its_last_good_chunk_or_is_refused(tmp_path):
    """A run stopped by its displacement limit keeps its data up to the failure but its
    restart state at the end of the last completed chunk (finite, inside the limit); a
    continuation starts there. A file whose kept state is not finite is refused by name."""
    diverge = seal_text(revolutions=60, max_displacement=42e-6)  # just above the 40 um gap
    system, run, kw, _, _ = _problem(load_scenario(write(tmp_path, "d.toml", diverge)))
    res = simulate_general(system, run, **kw, chunk_samples=4096, progress=False)
    assert res.status == "partial" and "diverged" in res.message
    t_fail = res.time[-1]
    assert res.restart["time_s"] < t_fail and res.restart["time_s"] % (4096 * DT) < 1e-12
    x = np.asarray(res.final_state)
    assert np.isfinite(x).all()
    path = tmp_path / "d.nc"
    rubrotor.save_dataset(simulate_engine(load_scenario(tmp_path / "d.toml"), progress=False), path)
    t_keep, vec = restart_row(path)
    with xr.open_dataset(path) as ds:
        assert ds.attrs["status"] == "partial" and t_keep < float(ds["time"].values[-1])
        assert "restart state at t" in ds.attrs["status_message"]
    cont = seal_text(initial=f'state = "file"\npath = "{path}"', revolutions=1)
    again = simulate_engine(load_scenario(write(tmp_path, "e.toml", cont)), progress=False)
    assert float(again["time"].values[0]) == t_keep
    with xr.open_dataset(path) as ds:  # the same state: the same deflections at that time
        kept = ds.sel(time=t_keep)
        for var in ("v", "w", "v_dot", "stator_y"):
            scale = np.abs(ds[var].values).max()  # the variable's range over the run
            got = again[var].values[:, 0]
            assert np.abs(got - kept[var].values).max() <= 1e-9 * scale, var
    with xr.open_dataset(path) as ds:
        bad = ds.load()
    bad["restart_vector"].values[-1, 0] = np.nan
    bad_path = tmp_path / "nan.nc"
    bad.to_netcdf(bad_path)
    nan = seal_text(initial=f'state = "file"\npath = "{bad_path}"', revolutions=1)
    with pytest.raises(ScenarioError, match="initial.path.*kept state is finite"):
        simulate_engine(load_scenario(write(tmp_path, "f.toml", nan)), progress=False)


def test_bad_runs_refused_or_stopped(tmp_path):
    """``chunk_samples = 0`` (it looped forever) and a NaN initial state (it returned
    complete) are refused by name; the output of a restart may not be its own input."""
    system, run, kw, _, _ = _problem(load_scenario(SEAL))
    short = dataclasses.replace(run, duration=10 * DT)
    with pytest.raises(InputError, match="chunk_samples"):
        simulate_general(system, short, **kw, chunk_samples=0)
    x = np.zeros(2 * system.n_dof)
    x[3] = math.nan
    nan_run = dataclasses.replace(short, initial=x)
    with pytest.raises(InputError, match=r"initial\.state.*finite"):
        simulate_general(system, nan_run, **kw)
    first = tmp_path / "first.nc"
    rubrotor.save_dataset(simulate_engine(load_scenario(write(tmp_path, "a.toml", seal_text(
        revolutions=1))), progress=False), first)  # fmt: skip
    same = load_scenario(write(tmp_path, "b.toml", seal_text(
        initial=f'state = "file"\npath = "{first}"', revolutions=1)))  # fmt: skip
    with pytest.raises(ScenarioError, match="initial.path.*other than the output"):
        simulate_engine(same, stream=first)


def peak_rss(tmp_path: Path, revolutions: int) -> tuple[int, int]:
    """Peak RSS (bytes, the child's own ``ru_maxrss`` from ``os.wait4``) of a child running a
    streamed ``rubrotor simulate --figure`` of seal_rub over ``revolutions``, and the samples
    it wrote."""
    scen = write(tmp_path, f"r{revolutions}.toml", seal_text(revolutions=revolutions))
    out = tmp_path / f"r{revolutions}.nc"
    code = ("import sys, rubrotor.engine.general as g, rubrotor.cli.simulate as s; "
            "g.STREAM_SAMPLES = 100; s.FIGURE_SAMPLES = 4096; "
            "from rubrotor.cli.app import main; raise SystemExit(main(sys.argv[1:]))")  # fmt: skip
    cmd = [sys.executable, "-c", code, "simulate", str(scen), "--out", str(out), "--figure",
           "--no-progress"]  # fmt: skip
    err = tmp_path / f"r{revolutions}.err"
    with err.open("w") as fh:
        child = subprocess.Popen(cmd, env=env(), stdout=subprocess.DEVNULL, stderr=fh)
        _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)  # reaped here, not by Popen
    assert child.returncode == 0, err.read_text()
    with xr.open_dataset(out) as ds:
        n = ds.sizes["time"]
    return usage.ru_maxrss * 1024, n


def test_streamed_cli_memory_stays_flat(tmp_path):
    """Peak RSS of a streamed ``rubrotor simulate --figure`` (summary and figure read the
    file in pieces; the figure's window cut to 4096 samples here) grows by less than a
    quarter of the extra data when the run is 3x longer; reading the file back whole (as it
    did) grows by all of it."""
    small, n_small = peak_rss(tmp_path, 150)  # both longer than a block of the summary
    large, n_large = peak_rss(tmp_path, 450)
    assert n_large > 2.9 * n_small
    extra = (n_large - n_small) * 8 * 28  # bytes: 28 float channels (3 stations, 1 contact)
    print(
        f"peak RSS {small / 2**20:.1f} MiB ({n_small} samples), {large / 2**20:.1f} MiB "
        f"({n_large} samples); data {extra / 2**20:.1f} MiB more"
    )
    assert large - small < 0.25 * extra, (small, large, extra)


def test_adaptive_run_continues_to_its_tolerance(tmp_path):
    """The adaptive ("collocation", rtol = 1e-6) stepper restarts too: 20 revolutions, then 20
    more from the file, end within 10 rtol of one run of 40 (relative to the largest state
    entry; the step sequence restarts, so agreement is to the tolerance, not to rounding)."""
    adaptive = seal_text().replace(
        "dt = 2e-5                 # s", "rtol = 1e-6\noutput_dtau = 0.02"
    )
    half = adaptive.replace("revolutions = 40", "revolutions = 20")
    first = tmp_path / "first.nc"
    rubrotor.save_dataset(simulate_engine(load_scenario(write(tmp_path, "a.toml", half)),
                                          progress=False), first)  # fmt: skip
    cont = half.replace('state = "static"', f'state = "file"\npath = "{first}"')
    b = simulate_engine(load_scenario(write(tmp_path, "b.toml", cont)), progress=False)
    c = simulate_engine(load_scenario(write(tmp_path, "c.toml", adaptive)), progress=False)
    assert b.attrs["status"] == c.attrs["status"] == "complete"
    assert json.loads(b.attrs["integrator_stats"])["method"] == "collocation"
    assert float(b["time"].values[-1]) == pytest.approx(float(c["time"].values[-1]), rel=1e-12)
    x1 = np.array(json.loads(b.attrs["final_state"]))
    x2 = np.array(json.loads(c.attrs["final_state"]))
    assert np.abs(x1 - x2).max() <= 1e-5 * np.abs(x2).max()
