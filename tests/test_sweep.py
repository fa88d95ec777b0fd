"""Parameter sweeps: regime labels, store resume, local pool and Dask equality, CLI, figures."""

from __future__ import annotations

import json
import os
import signal
import threading
from importlib import resources

import numpy as np
import pytest
import xarray as xr

from rubrotor.cli import main
from rubrotor.errors import InputError
from rubrotor.scenario import load_scenario
from rubrotor.sweeps.sweep import (
    APERIODIC,
    CHAOTIC,
    FULL,
    NO_CONTACT,
    PARTIAL,
    QUASI,
    classify,
    find_period,
    open_sweep,
    parse_vary,
    poincare_dimension,
    point_metrics,
    regime_labels,
    sweep,
)

CASE1 = str(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")
# seed case 1 geometry and contact with the unbalance these regime cases were built on (2e-3 kg m)
BASE = load_scenario(CASE1).with_changes(**{"unbalance.magnitude": 2e-3})
# periodic partial rub: seed case 1 with 2 % modal damping and a 1e5 N side load
LOADED = BASE.with_changes(**{"damping.ratio": 0.02, "load.force_y": 1e5})
SHORT = dict(transient_revolutions=30, revolutions=60, samples_per_revolution=64)


# ---- classifier on synthetic inputs ------------------------------------------------------------
def _signal_metrics(p, n=64, revs=200, cf=0.5):
    t = np.arange(revs * n + 1) * (2 * np.pi / n)
    fn = np.where(np.arange(t.size) % n < cf * n, 1.0, 0.0)
    return point_metrics(t, p(t), fn, np.array([]), 1.0, 0, revs, n)


def test_classify_no_contact_and_full_annular():
    z = np.exp(1j * np.arange(100))
    assert classify(0.0, 0.0, z, 1.0) == (NO_CONTACT, 0)
    assert classify(1.0, 0.01, z, 1.0) == (FULL, 0)
    # in contact all the time but |P| varies a lot: not a full annular rub
    assert classify(1.0, 0.5, np.ones(100, complex), 1.0) == (PARTIAL, 1)


@pytest.mark.parametrize("k", [1, 2, 3, 5])
def test_period_k_synthetic(k):
    rng = np.random.default_rng(k)
    centres = rng.normal(size=k) + 1j * rng.normal(size=k)
    z = np.tile(centres, 100)[:100] * (1 + 1e-6 * rng.normal(size=100))
    assert find_period(z, 1e-4) == k
    assert classify(0.3, 0.5, z, 1.0) == (PARTIAL, k)


def test_quasi_periodic_synthetic():
    # two incommensurate tones: 1X forward and 0.5 (sqrt 5 - 1) X backward; a torus
    rho = (np.sqrt(5) - 1) / 2
    m = _signal_metrics(lambda t: 1e-3 * np.exp(1j * t) + 4e-4 * np.exp(-1j * rho * t))
    assert m["regime"] == QUASI
    assert m["line_fraction"] > 0.99
    assert m["poincare_dimension"] < 1.5
    f = m["frequency"]
    assert f[0] == pytest.approx(1.0, abs=2e-3)
    assert f[1] == pytest.approx(-rho, abs=2e-3)  # backward whirl is negative
    assert m["frequency_amplitude"][0] == pytest.approx(1e-3, rel=2e-2)
    assert m["forward_share"] == pytest.approx(1 / (1 + 0.16), abs=1e-2)


def test_chaotic_synthetic():
    # a broadband signal (chaotic logistic map, held for one revolution each)
    x = np.empty(200 * 64 + 1)
    v = 0.3
    for i in range(x.size):
        v = 3.99 * v * (1 - v)
        x[i] = v
    y = np.roll(x, 17)
    m = _signal_metrics(lambda t: 1e-3 * (x + 1j * y))
    assert m["line_fraction"] < 0.9
    assert m["regime"] == APERIODIC  # broadband, no period; chaotic only from an exponent
    # a Poincare set filling an area is chaotic even with a line spectrum
    rng = np.random.default_rng(0)
    cloud = rng.random(200) + 1j * rng.random(200)
    assert poincare_dimension(cloud) > 1.5
    assert classify(0.5, 0.5, cloud, 1.0, poincare_dimension(cloud)) == (APERIODIC, 0)
    assert classify(0.5, 0.5, cloud, 1.0, lyapunov_per_rev=0.3) == (CHAOTIC, 0)


# ---- real simulations ----------------------------------------------------------------------------
@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
def test_real_regimes_no_contact_full_and_periodic_partial():
    long = dict(transient_revolutions=100, revolutions=140, samples_per_revolution=64)
    no = sweep(BASE, {"unbalance.magnitude": [1e-4, 3e-3]}, workers=1, **long)
    labels = regime_labels(no)
    # in contact all the time, but 4.9 mm deep at a 1.2 mm clearance: not a machine's rub
    assert labels.tolist() == ["no contact", "indentation > clearance"]
    assert no["max_displacement"].values[1] > 2 * BASE.contact.clearance
    assert no["contact_fraction"].values[0] == 0
    assert no["peak_normal_force"].values[0] == 0
    assert no["contact_fraction"].values[1] == 1
    assert no["peak_normal_force"].values[1] > 1e5  # N
    assert no["frequency"].values[1, 0] == pytest.approx(1.0, abs=1e-3)  # synchronous whirl
    # periodic partial rub: one impact per revolution, period 1 (needs a longer transient)
    pr = sweep(
        LOADED,
        {"speed.critical_multiple": [1.5]},
        workers=1,
        transient_revolutions=100,
        revolutions=140,
        samples_per_revolution=64,
    )
    assert regime_labels(pr).tolist() == ["partial rub (period-1)"]
    assert 0.1 < pr["contact_fraction"].values[0] < 0.5
    assert pr["impacts_per_revolution"].values[0] == pytest.approx(1.0)
    assert pr["poincare_v"].shape == (1, 40)


def test_poincare_samples_are_once_per_revolution():
    ds = sweep(LOADED, {"speed.critical_multiple": [1.5]}, workers=1, **SHORT)
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate_system

    sc = LOADED
    r = simulate_system(
        sc.shaft, sc.speed, Integrator(revolutions=60, output_dtau=2 * np.pi / 64),
        sc.unbalance, sc.contact, sc.load, sc.damping, progress=False,
    )  # fmt: skip
    k = np.arange(30, 60)
    assert np.allclose(r.time[k * 64] * sc.speed, 2 * np.pi * k, rtol=1e-12)
    assert np.array_equal(ds["poincare_v"].values[0], r.channels[0][k * 64])
    assert np.array_equal(ds["poincare_w"].values[0], r.channels[1][k * 64])


# ---- store, resume, pool ------------------------------------------------------------------------
VARY = {"speed.critical_multiple": [1.2, 1.5, 2.0], "unbalance.magnitude": [1e-3, 2e-3]}


@pytest.fixture(scope="module")
def reference():
    return sweep(LOADED, VARY, workers=1, chunk_size=1, **SHORT)


def test_grid_dims_and_pool_equal_in_process(reference, tmp_path):
    assert reference["done"].dims == ("speed.critical_multiple", "unbalance.magnitude")
    assert reference["poincare_v"].shape == (3, 2, 30)
    assert reference["done"].values.all()
    pooled = sweep(LOADED, VARY, workers=2, chunk_size=1, store=tmp_path / "s.zarr", **SHORT)
    xr.testing.assert_identical(pooled, reference)
    xr.testing.assert_identical(open_sweep(tmp_path / "s.zarr"), reference)


def test_resume_computes_only_missing_and_rejects_other_sweeps(reference, tmp_path, monkeypatch):
    store = tmp_path / "s.zarr"
    import rubrotor.sweeps.sweep as sw

    calls = []
    real = sw.run_chunk

    def stop_after_two(task):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(task["chunk"])
        return real(task)

    monkeypatch.setattr(sw, "run_chunk", stop_after_two)
    with pytest.raises(KeyboardInterrupt):
        sweep(LOADED, VARY, workers=1, chunk_size=1, store=store, **SHORT)
    partial = open_sweep(store)  # a valid store with two chunks done
    assert int(partial["done"].sum()) == 2
    calls.clear()
    monkeypatch.setattr(sw, "run_chunk", lambda t: calls.append(t["chunk"]) or real(t))
    ds = sweep(LOADED, VARY, workers=1, chunk_size=1, store=store, **SHORT)
    assert len(calls) == 4
    xr.testing.assert_identical(ds, reference)
    with pytest.raises(InputError, match="transient_revolutions"):
        sweep(LOADED, VARY, workers=1, store=store, transient_revolutions=20, revolutions=60)


def test_interrupt_during_write_is_deferred():
    import rubrotor.sweeps.sweep as sw

    with pytest.raises(KeyboardInterrupt):
        with sw._deferred_interrupt():
            os.kill(os.getpid(), signal.SIGINT)
            done = True  # the block finishes before the interrupt is raised
    assert done


def test_parse_vary_and_errors():
    key, v = parse_vary("unbalance.magnitude=1e-4:1e-2:3", log=True)
    assert key == "unbalance.magnitude" and np.allclose(v, [1e-4, 1e-3, 1e-2])
    for bad in ("nokey", "unbalance.magnitude=1:2", "x.y=1:2:0", "a=1:b:3"):
        with pytest.raises(InputError):
            parse_vary(bad)
    with pytest.raises(InputError, match="unbalance.magnitud"):
        sweep(BASE, {"unbalance.magnitud": [1.0]}, workers=1, **SHORT)
    with pytest.raises(InputError, match="contact.clearance"):
        sweep(BASE, {"contact.clearance": [-1.0, 1e-3]}, workers=1, **SHORT)


# ---- CLI and figures ---------------------------------------------------------------------------
def test_cli_sweep_netcdf_figure_and_errors(tmp_path, capsys):
    out, nc, png = tmp_path / "s.zarr", tmp_path / "s.nc", tmp_path / "bif.png"
    args = ["sweep", CASE1, "--vary", "unbalance.magnitude=1e-4:3e-3:3", "--out", str(out)]
    args += ["--netcdf", str(nc), "--figure", str(png), "--transient", "30"]
    args += ["--revolutions", "60", "--samples", "64", "--workers", "1"]
    assert main(args) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["points"] == 3
    assert summary["regimes"]["no contact"] >= 1
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with xr.open_dataset(nc) as back:
        assert back["regime"].shape == (3,)
    assert main(["sweep", CASE1, "--vary", "speed.warp=1:2:3", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "speed.warp" in err
    assert main(["sweep", CASE1, "--vary", "unbalance.magnitude=1:2:x", "--out", "o"]) == 2
    assert "unbalance.magnitude" in capsys.readouterr().err
    # the same store with another definition: a clear error
    args[3] = "unbalance.magnitude=1e-4:3e-3:4"
    assert main(args) == 2
    assert "values" in capsys.readouterr().err


def test_regime_map_figure(reference):
    from rubrotor.plotting import bifurcation_figure, regime_map_figure

    fig = regime_map_figure(reference, "unbalance.magnitude", "speed.critical_multiple")
    ax = fig.axes[0]
    assert "kg m" in ax.get_xlabel() and "critical" in ax.get_ylabel()
    assert len(fig.legends[0].get_texts()) == len(set(regime_labels(reference).ravel()))
    fig = bifurcation_figure(
        reference.isel({"unbalance.magnitude": [0]}), "speed.critical_multiple"
    )
    assert "(mm)" in fig.axes[0].get_ylabel()


# ---- Dask ---------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=":0",  # a free port: never collides with another cluster
    ) as c:
        yield c


def assert_same_sweep(ds, ref):
    """Equal to rounding: Dask's nanny starts workers with OMP/OPENBLAS_NUM_THREADS=1, so the
    BLAS calls of the (small) modal assembly may round differently than in this process; the
    labels, masks, coordinates and attributes must be identical."""
    # rtol 1e-10 of each value, atol 1e-14 for quantities near zero (m, N and fractions)
    xr.testing.assert_allclose(ds, ref, rtol=1e-10, atol=1e-14)
    for name in ("regime", "period", "done", "status"):
        if name in ref:
            np.testing.assert_array_equal(ds[name].values, ref[name].values)
    assert ds.attrs == ref.attrs
    for name in ref.coords:
        np.testing.assert_array_equal(ds[name].values, ref[name].values)


def test_dask_equals_local(cluster, reference, tmp_path):
    ds = sweep(LOADED, VARY, scheduler=cluster.scheduler_address, chunk_size=1, **SHORT)
    assert_same_sweep(ds, reference)


def test_dask_worker_killed_mid_sweep(cluster, tmp_path):
    vary = {"speed.critical_multiple": np.linspace(1.2, 2.0, 12)}
    local = sweep(LOADED, vary, workers=1, chunk_size=1, **SHORT)
    store = tmp_path / "k.zarr"
    killed = []

    def kill_one():
        # wait until the workers hold tasks, then kill one worker process outright
        import time

        for _ in range(400):
            info = cluster.scheduler.tasks
            if any(ts.state == "processing" for ts in info.values()):
                break
            time.sleep(0.01)
        proc = next(iter(cluster.workers.values())).process.process
        killed.append(proc.pid)
        os.kill(proc.pid, signal.SIGKILL)

    t = threading.Thread(target=kill_one)
    t.start()
    ds = sweep(
        LOADED, vary, scheduler=cluster.scheduler_address, chunk_size=1, store=store, **SHORT
    )
    t.join()
    assert killed
    assert ds["done"].values.all()
    assert_same_sweep(ds, local)
    assert_same_sweep(open_sweep(store), local)
