"""Sweeps survive their workers and their own death (issue 21).

* a worker killed mid-sweep (SIGKILL, as the OOM killer does): its tasks are run again in a
  fresh pool; a task whose worker dies twice is reported, not a ``BrokenProcessPool`` traceback;
* ``kill -9`` of the process running a sweep: its workers end too (no orphans);
* a sweep killed while creating its store leaves no half-made store;
* after a plain install without Dask, local sweeps work and ``--scheduler`` says what to install.

The references are the same sweep run in process (``workers=1``), which shares no pool code.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import rubrotor.sweeps.sweep as sw
from rubrotor.cli import main
from rubrotor.scenario import load_scenario
from rubrotor.sweeps.pool import LostTasks, local_pool, run_pool

CASE1 = str(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")
LOADED = load_scenario(CASE1).with_changes(
    **{"unbalance.magnitude": 2e-3, "damping.ratio": 0.02, "load.force_y": 1e5}
)
SHORT = dict(transient_revolutions=10, revolutions=20, samples_per_revolution=32)
VARY = {"speed.critical_multiple": [1.2, 1.5, 2.0]}
SRC = str(Path(sw.__file__).parents[2])


def _square_or_die(task):
    """``task["x"] ** 2``; SIGKILLs its own worker the first time (or every time) it runs."""
    marker = Path(task["marker"])
    if task.get("always") or not marker.exists():
        marker.touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return task["x"] ** 2


def test_killed_worker_is_retried_once_then_reported(tmp_path):
    tasks = [{"x": x, "marker": str(tmp_path / "m")} for x in range(6)]
    pool = local_pool(2, len(tasks))
    try:
        assert sorted(run_pool(_square_or_die, tasks, pool)) == [x * x for x in range(6)]
    finally:
        pool.shutdown()
    tasks[3] = tasks[3] | {"always": True}
    pool, lost = local_pool(2, len(tasks)), []
    try:
        got = sorted(run_pool(_square_or_die, tasks, pool, lost))
    finally:
        pool.shutdown()
    assert [t["x"] for t in lost] == [3] and got == [x * x for x in range(6) if x != 3]
    pool = local_pool(2, len(tasks))
    with pytest.raises(LostTasks, match="1 task"):
        try:
            list(run_pool(_square_or_die, tasks, pool))
        finally:
            pool.shutdown()


def _die_on_chunk_one(task):
    if task["chunk"] == 1:
        os.kill(os.getpid(), signal.SIGKILL)
    return _real_run_chunk(task)


_real_run_chunk = sw.run_chunk


def test_sweep_marks_and_reports_lost_points(tmp_path, monkeypatch, capsys):
    """A chunk whose worker dies twice stays not done, is listed, and a rerun completes it."""
    reference = sw.sweep(LOADED, VARY, workers=1, chunk_size=1, **SHORT)
    monkeypatch.setattr(sw, "run_chunk", _die_on_chunk_one)  # the forked workers inherit it
    store = tmp_path / "s.zarr"
    ds = sw.sweep(LOADED, VARY, workers=2, chunk_size=1, store=store, **SHORT)
    assert ds["done"].values.tolist() == [1, 0, 1]
    assert json.loads(ds.attrs["lost_points"]) == [[1.5]]
    monkeypatch.setattr(sw, "run_chunk", _real_run_chunk)
    again = sw.sweep(LOADED, VARY, workers=2, chunk_size=1, store=store, **SHORT)
    for name in ("poincare_v", "peak_normal_force", "regime"):
        np.testing.assert_array_equal(again[name].values, reference[name].values)


def test_cli_sweep_reports_lost_points_in_one_line(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(sw, "run_chunk", _die_on_chunk_one)
    argv = ["sweep", CASE1, "--vary", "speed.critical_multiple=1.2:2.0:3", "--out"]
    argv += [str(tmp_path / "s.zarr"), "--workers", "2", "--chunk-size", "1"]
    argv += ["--transient", "10", "--revolutions", "20", "--samples", "32"]
    assert main(argv) == 1
    out, err = capsys.readouterr()
    assert json.loads(out)["lost_points"] == [[1.6]]
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "1 point(s) lost" in lines[0] and "[1.6]" in lines[0]


def test_workers_die_with_their_parent(tmp_path):
    """``kill -9`` of the sweeping process: its pool's workers are gone within seconds."""
    script = textwrap.dedent(
        """
        import os, sys, time
        from rubrotor.sweeps.pool import local_pool
        pool = local_pool(2, 4)
        pids = sorted(set(pool.submit(os.getpid).result() for _ in range(8)))
        print(" ".join(map(str, pids)), flush=True)
        time.sleep(600)
        """
    )
    env = dict(os.environ, PYTHONPATH=SRC)
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, env=env)
    with proc:
        pids = [int(p) for p in proc.stdout.readline().split()]
        assert pids and proc.pid not in pids
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        deadline = time.monotonic() + 20
        alive = pids
        while alive and time.monotonic() < deadline:
            time.sleep(0.1)
            alive = [p for p in pids if _alive(p)]
        assert alive == []


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return False
    return state != "Z"  # a zombie has ended (its parent, init, reaps it)


def test_store_creation_killed_leaves_no_store(tmp_path, monkeypatch):
    """A sweep stopped while writing its empty store leaves nothing a rerun would refuse."""
    store = tmp_path / "s.zarr"
    real = xr.Dataset.to_zarr

    def half_then_die(self, path, **kw):
        real(self[["done"]], path, **kw)  # part of the store is on disk...
        raise KeyboardInterrupt  # ... when the run is killed

    monkeypatch.setattr(xr.Dataset, "to_zarr", half_then_die)
    with pytest.raises(KeyboardInterrupt):
        sw.sweep(LOADED, VARY, workers=1, chunk_size=1, store=store, **SHORT)
    assert not store.exists() and list(tmp_path.iterdir()) == []
    monkeypatch.setattr(xr.Dataset, "to_zarr", real)
    ds = sw.sweep(LOADED, VARY, workers=1, chunk_size=1, store=store, **SHORT)
    assert ds["done"].values.all() and sw.open_sweep(store)["done"].values.all()


_NO_DASK = """
import sys
sys.modules.update(dask=None, distributed=None)  # as if not installed: import raises ImportError
from rubrotor.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_sweep_without_dask(tmp_path):
    """Local sweeps need no Dask; ``--scheduler`` without it is one line naming the install."""
    env = dict(os.environ, PYTHONPATH=SRC)
    argv = ["sweep", CASE1, "--vary", "unbalance.magnitude=1e-4:3e-3:2", "--out"]
    argv += [str(tmp_path / "s.zarr"), "--workers", "2", "--chunk-size", "1"]
    argv += ["--transient", "10", "--revolutions", "20", "--samples", "32"]
    run = subprocess.run([sys.executable, "-c", _NO_DASK, *argv], env=env, capture_output=True,
                         text=True, timeout=300)  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout)["points"] == 2
    argv[5] = str(tmp_path / "t.zarr")
    run = subprocess.run([sys.executable, "-c", _NO_DASK, *argv, "--scheduler", "tcp://x:1"],
                         env=env, capture_output=True, text=True, timeout=300)  # fmt: skip
    assert run.returncode == 2
    assert run.stderr.count("\n") == 1 and 'pip install "rubrotor[sweep]"' in run.stderr
