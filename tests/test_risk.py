"""Rub risk under uncertainty (``rubrotor.risk``, ``rubrotor risk``) against closed forms.

References, each derived here or computed by a second route:

* the orbit's largest distance from the stator centre: the steady unbalance response of
  ``rubrotor.unbalance_response`` at the contact plus ``static_analysis``'s deflection there,
  sampled at 20 001 phases and refined by SciPy's bounded scalar minimiser (not the screen's
  own basis and kernel);
* clearance normal (mu, sd) alone, one speed: ``P = Phi((A - mu) / sd)``;
* unbalance magnitude uniform on [lo, hi], clearance fixed: ``P = (hi - m*) / (hi - lo)``
  with the critical unbalance ``m*`` found by Brent's method on the reference distance;
* Sobol' indices of the Ishigami function: Sobol' (1990) / Ishigami & Homma (1990) closed forms.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.optimize
import scipy.stats

import rubrotor
from rubrotor.errors import InputError, ScenarioError
from rubrotor.scenario.load import load_scenario
from rubrotor.sweeps.risk import risk, wilson_interval
from rubrotor.sweeps.risk_inputs import parse_distribution, unit_samples
from rubrotor.sweeps.risk_linear import orbit_reach
from rubrotor.sweeps.sobol import sobol_indices

SEAL = "src/rubrotor/scenarios/seal_rub.toml"
SHAFT = "src/rubrotor/scenarios/one_mode_partial_rub.toml"
W = 628.3  # rad/s, seal_rub's running speed (6000 rpm)


def _reach_reference(d, v, w):
    """max over theta of |d + Re([v, w] e^{i theta})| by dense sampling and a bounded refine."""

    def r(t):
        return -math.hypot(d[0] + (v * np.exp(1j * t)).real, d[1] + (w * np.exp(1j * t)).real)

    th = np.linspace(0, 2 * np.pi, 20001)
    y = np.hypot(d[0] + (v * np.exp(1j * th)).real, d[1] + (w * np.exp(1j * th)).real)
    t0 = th[y.argmax()]
    res = scipy.optimize.minimize_scalar(
        r, bounds=(t0 - 1e-3, t0 + 1e-3), method="bounded", options={"xatol": 1e-12}
    )
    return float(max(-res.fun, y.max()))


def _seal_reach(scenario, speed=W):
    """The reference largest distance (m) of seal_rub's contact orbit from the stator centre."""
    from rubrotor.linear.static import static_analysis

    resp = rubrotor.unbalance_response(scenario, [0.5 * speed, speed], probes=[0.75])
    v, w = resp.complex_response[-1, 0]
    st = static_analysis(scenario, speed)
    node = int(np.argmin(abs(st.x - 0.75)))
    assert abs(st.x[node] - 0.75) < 1e-12
    d = st.deflection[node] - np.array([-25e-6, 0.0])  # stator centre (offset_y, offset_z)
    return _reach_reference(d, v, w)


def test_orbit_reach_matches_dense_sampling():
    rng = np.random.default_rng(3)
    d = rng.normal(size=(40, 2))
    u = rng.normal(size=(40, 2)) + 1j * rng.normal(size=(40, 2))
    got = orbit_reach(d, u)
    ref = np.array([_reach_reference(d[i], u[i, 0], u[i, 1]) for i in range(40)])
    np.testing.assert_allclose(got, ref, rtol=1e-10)


def test_clearance_normal_matches_phi():
    sc = load_scenario(SEAL)
    a = _seal_reach(sc)
    sd = 4e-6
    mu = a + 0.4 * sd  # P = Phi(-0.4) = 0.345
    res = risk(sc, {"contact.clearance": f"normal({mu!r},{sd!r})"}, samples=4000, speeds=[W],
               confidence=0.99)  # fmt: skip
    p = scipy.stats.norm.cdf((a - mu) / sd)
    assert res.lower[0] <= p <= res.upper[0]
    assert 0.3 < p < 0.4  # the case reaches the boundary: a quantity far above round-off
    # the largest distance itself, through the screen's basis and kernel
    from rubrotor.sweeps.risk_linear import evaluate, linear_basis

    b = linear_basis(sc, np.array([W]))
    m = evaluate(b, b.magnitude[None], b.phase[None], np.zeros((1, 1)), b.offset[None])
    assert abs(-m[0, 0] - a) < 1e-9 * a


def test_unbalance_uniform_matches_critical_unbalance():
    sc = load_scenario(SEAL)
    clear = 40e-6

    def excess(m):
        return _seal_reach(sc.with_changes(**{"unbalance[1].magnitude": m})) - clear

    lo, hi = 1e-4, 9e-4
    assert excess(lo) < 0 < excess(hi)
    m_star = scipy.optimize.brentq(excess, lo, hi, xtol=1e-12)
    res = risk(sc, {"unbalance[1].magnitude": f"uniform({lo!r},{hi!r})"}, samples=4096,
               speeds=[W], confidence=0.99)  # fmt: skip
    p = (hi - m_star) / (hi - lo)
    assert 0.2 < p < 0.8
    assert res.lower[0] <= p <= res.upper[0]
    # a Sobol' sequence of 4096 points places a fraction within about 1/N of the exact one
    assert abs(res.probability[0] - p) < 5e-3


def _coverage(sampler: str, seeds: int) -> float:
    sc = load_scenario(SHAFT)
    from rubrotor.sweeps.risk_linear import evaluate, linear_basis

    b = linear_basis(sc, np.array([sc.speed]))
    a = float(
        -evaluate(b, b.magnitude[None], b.phase[None], np.zeros((1, 1)), b.offset[None])[0, 0]
    )
    sd = 0.1 * a
    p = scipy.stats.norm.cdf(-0.3)
    hits = 0
    for seed in range(seeds):
        r = risk(sc, {"contact.clearance": f"normal({a + 0.3 * sd!r},{sd!r})"}, samples=4000,
                 seed=seed, sampler=sampler, confidence=0.99)  # fmt: skip
        hits += r.lower[0] <= p <= r.upper[0]
    return hits / seeds


@pytest.mark.slow
def test_wilson_interval_coverage_over_200_seeds():
    # plain Monte Carlo: the 99 % interval covers P in 99 % of seeds (binomial sd 0.7 %: three
    # sd below is 0.97); scrambled Sobol' points err less, so they cover at least as often
    assert _coverage("random", 200) >= 0.97
    assert _coverage("sobol", 200) >= 0.97


def test_wilson_interval_closed_form():
    # k = 0 of n: upper bound z^2 / (n + z^2) (the closed form of the Wilson bound at p = 0)
    z = scipy.stats.norm.ppf(0.975)
    lo, hi = wilson_interval(0, 50)
    assert lo == 0 and abs(hi - z * z / (50 + z * z)) < 1e-15
    lo, hi = wilson_interval(25, 50)
    assert abs(0.5 - lo - (hi - 0.5)) < 1e-15  # symmetric about 1/2


def test_ishigami_sobol_indices_within_intervals():
    a, b, n = 7.0, 0.1, 2**13
    u = unit_samples("sobol", 6, 11, 0, n, n)
    x = -np.pi + 2 * np.pi * u

    def f(z):
        return np.sin(z[:, 0]) + a * np.sin(z[:, 1]) ** 2 + b * z[:, 2] ** 4 * np.sin(z[:, 0])

    xa, xb = x[:, :3], x[:, 3:]
    fab = []
    for i in range(3):
        m = xa.copy()
        m[:, i] = xb[:, i]
        fab.append(f(m))
    s = sobol_indices(f(xa), f(xb), np.array(fab), confidence=0.99)
    pi4, pi8 = np.pi**4, np.pi**8
    v = a * a / 8 + b * pi4 / 5 + b * b * pi8 / 18 + 0.5
    v1, v2 = 0.5 * (1 + b * pi4 / 5) ** 2, a * a / 8
    v13 = b * b * pi8 * (1 / 18 - 1 / 50)
    first = np.array([v1, v2, 0.0]) / v
    total = np.array([v1 + v13, v2, v13]) / v
    for i in range(3):
        assert s.first_interval[i, 0] <= first[i] <= s.first_interval[i, 1]
        assert s.total_interval[i, 0] <= total[i] <= s.total_interval[i, 1]
    assert abs(s.total[2] - total[2]) < 0.05  # x3 acts only with x1: S_3 = 0, S_T3 = 0.244


def test_sample_design_is_chunk_invariant():
    whole = unit_samples("sobol", 3, 5, 0, 100, 100)
    parts = np.vstack([unit_samples("sobol", 3, 5, k, 25, 100) for k in range(0, 100, 25)])
    assert np.array_equal(whole, parts)


def test_store_resumes_to_the_same_bits(tmp_path):
    import zarr

    sc = load_scenario(SHAFT)
    kw = dict(samples=300, speeds=[0.9 * sc.speed, sc.speed], chunk_size=64, sobol=True)
    vary = {"contact.clearance": "uniform(2e-5,3e-4)", "unbalance.magnitude": "normal(2e-4,2e-5)"}
    full = risk(sc, vary, **kw)
    store = tmp_path / "s.zarr"
    risk(sc, vary, store=store, **kw)
    g = zarr.open_group(str(store), mode="r+")
    g["done"][2:] = 0  # as if killed after two chunks
    g["rub"][128:] = 7
    again = risk(sc, vary, store=store, **kw)
    assert again.to_dict() | {"store": None} == full.to_dict()
    assert 0 < full.probability.max() < 1
    assert np.all(np.asarray(g["rub"][:]) <= 1)


def test_cli_json_equals_to_dict(tmp_path, capsys):
    from rubrotor.cli import main

    out = tmp_path / "r"
    args = ["risk", SHAFT, "--samples", "64", "--vary", "contact.clearance=uniform(2e-5,3e-4)",
            "--out", str(out), "--json", "--no-figure"]  # fmt: skip
    assert main(args) == 0
    printed = json.loads(capsys.readouterr().out)
    res = risk(SHAFT, {"contact.clearance": "uniform(2e-5,3e-4)"}, samples=64,
               store=out / "samples.zarr")  # fmt: skip
    assert printed == json.loads(json.dumps(res.to_dict()))
    assert json.loads((out / "risk.json").read_text()) == printed
    ds = res.to_dataset()
    assert ds["probability"].attrs["units"] == "1" and ds["speed"].attrs["units"] == "rad/s"


@pytest.mark.parametrize(
    ("vary", "kw", "field", "text"),
    [
        ({"contact.clearence": "normal(1e-4,1e-5)"}, {}, "contact.clearence", "contact.clearance"),
        ({"contact.clearance": "normal(1e-4,-1e-5)"}, {}, "contact.clearance sd", "> 0"),
        ({"contact.clearance": "uniform(2e-4,1e-4)"}, {}, "contact.clearance range", "lo < hi"),
        ({"contact.clearance": "gauss(1e-4,1e-5)"}, {}, "contact.clearance", "normal(mean,sd)"),
        ({"contact.clearance": "normal(1e-4,1e-5)"}, {"samples": 0}, "samples", ">= 1"),
        ({"contact.clearance": "normal(1e-5,1e-4)"}, {}, "contact.clearance", "truncnormal"),
    ],
)
def test_bad_input_refused_by_name(vary, kw, field, text):
    with pytest.raises((InputError, ScenarioError)) as err:
        risk(SHAFT, vary, **{"samples": 64, **kw})
    assert err.value.field == field
    assert text in str(err.value)


def test_cli_bad_key_exit_2(tmp_path, capsys):
    from rubrotor.cli import main

    code = main(["risk", SHAFT, "--samples", "8", "--vary", "contact.clearence=uniform(1,2)",
                 "--out", str(tmp_path / "r")])  # fmt: skip
    assert code == 2
    assert "contact.clearance" in capsys.readouterr().err


def test_distribution_forms():
    d = parse_distribution("truncnormal(1, 2, 0, 3)")
    v = d.ppf(np.array([1e-9, 0.5, 1 - 1e-9]))
    assert 0 <= v[0] < v[1] < v[2] <= 3
    ln = parse_distribution("lognormal(0.5, 0.2)")
    assert abs(ln.ppf(np.array([0.5]))[0] - math.exp(0.5)) < 1e-12  # median e^mu


def test_time_and_linear_agree_far_from_the_boundary(tmp_path):
    import xarray as xr

    sc = load_scenario(SHAFT)
    vary = {"contact.clearance": "uniform(2e-5,3e-4)"}
    lin = risk(sc, vary, samples=4, store=tmp_path / "l.zarr", sampler="lhs", seed=2)
    tim = risk(sc, vary, samples=4, store=tmp_path / "t.zarr", sampler="lhs", seed=2,
               method="time", transient_revolutions=10, revolutions=30)  # fmt: skip
    with xr.open_zarr(tmp_path / "l.zarr", consolidated=False) as a:
        margin, clear = a["margin"].values[:, 0], a["inputs"].values[:, 0]
    with xr.open_zarr(tmp_path / "t.zarr", consolidated=False) as b:
        frac = b["contact_fraction"].values[:, 0]
    far = np.abs(margin) > 0.3 * clear
    assert far.sum() >= 2
    assert np.array_equal((margin <= 0)[far], (frac > 0)[far])
    assert tim.time_stats["diverged"] == [0]
    assert lin.samples == tim.samples == 4


def _arrays(path) -> dict:
    import zarr

    g = zarr.open_group(str(path), mode="r")
    return {k: np.asarray(g[k][:]) for k in ("peak_normal_force", "contact_fraction", "status")}


TIME_ARGS = dict(samples=12, method="time", chunk_size=2, transient_revolutions=10,
                 revolutions=30, sampler="lhs", seed=4)  # fmt: skip
TIME_VARY = {"contact.clearance": "uniform(2e-5,3e-4)", "unbalance.magnitude": "normal(2e-4,2e-5)"}


@pytest.mark.slow
def test_time_method_same_bits_through_a_scheduler_address(tmp_path):
    from distributed import LocalCluster

    ref = risk(SHAFT, TIME_VARY, store=tmp_path / "here.zarr", **TIME_ARGS)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster:  # fmt: skip
        via = risk(SHAFT, TIME_VARY, store=tmp_path / "dask.zarr",
                   scheduler=cluster.scheduler_address, **TIME_ARGS)  # fmt: skip
    a, b = _arrays(tmp_path / "here.zarr"), _arrays(tmp_path / "dask.zarr")
    for k in a:
        assert np.array_equal(a[k], b[k], equal_nan=True), k
    assert np.all(a["status"] == 1) and np.nanmax(a["peak_normal_force"]) > 0
    assert via.to_dict() | {"store": None} == ref.to_dict() | {"store": None}


@pytest.mark.slow
def test_time_method_killed_then_resumed_to_the_same_bits(tmp_path):
    import os
    import signal
    import subprocess
    import sys
    import time

    import zarr

    out = tmp_path / "cli"
    cmd = [sys.executable, "-m", "rubrotor", "risk", SHAFT, "--samples", "12", "--method", "time",
           "--chunk-size", "2", "--transient", "10", "--revolutions", "30", "--sampler", "lhs",
           "--seed", "4", "--out", str(out), "--no-figure"]  # fmt: skip
    for k, v in TIME_VARY.items():
        cmd += ["--vary", f"{k}={v}"]
    env = {**os.environ, "PYTHONPATH": os.path.abspath("src")}
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    store = out / "samples.zarr"
    t0 = time.time()
    try:
        while time.time() - t0 < 600:
            if (
                store.exists()
                and np.asarray(zarr.open_group(str(store), mode="r")["done"][:]).sum()
            ):
                break
            time.sleep(0.05)
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    done = np.asarray(zarr.open_group(str(store), mode="r")["done"][:])
    assert 0 < done.sum() < done.size  # killed midway
    resumed = risk(SHAFT, TIME_VARY, store=store, **TIME_ARGS)
    fresh = risk(SHAFT, TIME_VARY, store=tmp_path / "fresh.zarr", **TIME_ARGS)
    a, b = _arrays(store), _arrays(tmp_path / "fresh.zarr")
    for k in a:
        assert np.array_equal(a[k], b[k], equal_nan=True), k
    assert resumed.to_dict() | {"store": None} == fresh.to_dict() | {"store": None}


def test_indexed_keys_one_resolution():
    from rubrotor.sweeps.sweep import _check_keys

    sc = load_scenario(SEAL)
    two = sc.with_changes(**{"unbalance[2].magnitude": 2e-4})
    assert [u.magnitude for u in two.unbalances] == [5e-4, 2e-4]
    assert (
        sc.with_changes(**{"contact.clearance": 3e-5}).engine.stations[0].contact.clearance == 3e-5
    )
    with pytest.raises(ScenarioError, match=r"unbalance\[i\]\.magnitude with i in 1\.\.2"):
        sc.with_changes(**{"unbalance.magnitude": 1e-4})
    with pytest.raises(ScenarioError, match="1 \\[\\[contact\\]\\] tables"):
        sc.with_changes(**{"contact[2].clearance": 1e-4})
    keys, _ = _check_keys(sc, {"unbalance[2].magnitude": [1e-4, 2e-4]})
    assert keys == ["unbalance[2].magnitude"]
    assert rubrotor.sweeps.sweep.key_unit("unbalance[2].magnitude") == "kg m"


def test_time_method_near_the_boundary_only(tmp_path):
    # pairs farther than 0.2 c_min from the boundary keep the linear verdict, unsimulated
    import zarr

    sc = load_scenario(SHAFT)
    vary = {"contact.clearance": "uniform(2e-5,3e-4)"}
    risk(sc, vary, samples=8, sampler="lhs", seed=2, store=tmp_path / "l.zarr")
    tim = risk(sc, vary, samples=8, sampler="lhs", seed=2, method="time", near=0.2,
               transient_revolutions=10, revolutions=30, store=tmp_path / "t.zarr")  # fmt: skip
    lin = zarr.open_group(str(tmp_path / "l.zarr"), mode="r")
    t = zarr.open_group(str(tmp_path / "t.zarr"), mode="r")
    margin, status = np.asarray(lin["margin"][:, 0]), np.asarray(t["status"][:, 0])
    far = np.abs(margin) > 0.2 * sc.contact.clearance
    assert 0 < far.sum() < 8
    assert np.array_equal(status == -1, far)
    assert np.array_equal(np.asarray(t["rub"][:, 0])[far], (margin <= 0)[far].astype(float))
    assert np.all(status[~far] == 1)
    assert tim.time_stats["simulated"] == [int((~far).sum())]
    with pytest.raises(InputError, match="near"):
        risk(sc, vary, samples=8, near=0.2)
