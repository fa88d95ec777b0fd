"""A sweep point is the user's simulation of that point, reduced (issue 14: the array-level path).

References:

* ``rubrotor.simulate`` of the point's scenario (built by ``Scenario.with_changes``, the public
  route, which resolves ``speed.critical_multiple`` from the shaft on its own) with the sweep's
  integrator settings, read from its results Dataset, and reduced by
  :func:`rubrotor.sweeps.sweep.point_metrics` on the Dataset's arrays: the sweep's own path builds no
  Dataset, re-uses the critical speed and reads the kernel's buffer in place, so every stored
  number must still equal this route to 1e-12 (relative);
* :meth:`Scenario.with_changes` for the point scenarios the sweep builds with its cached
  critical speed (equal objects and dict forms).
"""

from __future__ import annotations

import math
from importlib import resources

import numpy as np
import pytest

from rubrotor.engine.settings import Integrator
from rubrotor.engine.simulate import simulate
from rubrotor.orbits.points import PointScenarios, _point_scenario
from rubrotor.scenario import load_scenario, scenario_to_dict
from rubrotor.sweeps.follow import run_follow_chunk
from rubrotor.sweeps.sweep import point_metrics, sweep

CASE1 = load_scenario(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")
T, R, N = 20, 40, 64
VALUES = [0.7, 1.5, 2.6]  # no contact, rub, rub (seed case 1's unbalance)


def _reference(sc) -> dict:
    """The point through ``rubrotor.simulate`` and its Dataset (see the module docstring)."""
    base = sc.simulation
    integ = Integrator(revolutions=R, output_dtau=2 * math.pi / N, rtol=base.rtol,
                       atol=base.atol, max_displacement=base.max_displacement)  # fmt: skip
    ds = simulate(sc, integrator=integ, progress=False)
    assert ds.attrs["status"] == "complete"
    p = ds["v"].values[0] + 1j * ds["w"].values[0]  # the contact station
    events = ds["event_time"].values * ds["event_kind"].values
    return point_metrics(ds["time"].values, p, ds["normal_force"].values[0], events,
                         ds.attrs["speed_rad_s"], T, R, N)  # fmt: skip


def _assert_equal(got: dict, ref: dict) -> None:
    for name, value in ref.items():
        a, b = np.asarray(got[name], float), np.asarray(value, float)
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        ok = ~np.isnan(b)
        scale = max(float(np.max(np.abs(b[ok]), initial=0.0)), 1e-300)
        np.testing.assert_allclose(a[ok], b[ok], rtol=0, atol=1e-12 * scale, err_msg=name)


@pytest.fixture(scope="module")
def swept():
    return sweep(CASE1, {"speed.critical_multiple": VALUES}, workers=1, chunk_size=2,
                 transient_revolutions=T, revolutions=R, samples_per_revolution=N)  # fmt: skip


@pytest.mark.parametrize("i", range(len(VALUES)))
def test_sweep_point_equals_simulate_of_that_point(swept, i):
    sc = CASE1.with_changes(**{"speed.critical_multiple": VALUES[i]})
    ref = _reference(sc)
    got = {name: swept[name].values[i] for name in ref}
    _assert_equal(got, ref)
    assert int(swept["done"].values[i]) == 1
    # the first point flies free, the others rub (force, events and spectrum all compared)
    assert (ref["contact_fraction"] > 0) == (i > 0)


def test_follow_point_equals_simulate_of_that_point():
    """The first point of a follow chain starts from rest: the same run as ``simulate``."""
    task = {"scenario": scenario_to_dict(CASE1), "key": "speed.critical_multiple",
            "values": [2.6], "start": None, "transient": T, "revolutions": R, "samples": N,
            "n": 3, "lyapunov": False, "chunk": 0}  # fmt: skip
    got = run_follow_chunk(task)["metrics"][0]
    ref = _reference(CASE1.with_changes(**{"speed.critical_multiple": 2.6}))
    _assert_equal({k: got[k] for k in ref}, ref)


@pytest.mark.parametrize(
    "keys, values",
    [
        (["speed.critical_multiple"], [1.37]),
        (["unbalance.magnitude"], [2e-3]),  # base speed given as a critical multiple
        (["speed.critical_multiple", "contact.clearance"], [2.1, 3e-4]),
        (["unbalance.magnitude", "speed.critical_multiple"], [1e-3, 0.9]),
        (["shaft.length", "speed.critical_multiple"], [0.5, 1.2]),  # shaft swept: no cache
        (["speed.rpm"], [30000.0]),  # another speed key: no cache
    ],
)
def test_point_scenarios_equal_with_changes(keys, values):
    points = PointScenarios(CASE1, keys)
    got = points(values)
    ref = _point_scenario(CASE1, keys, values)
    assert got == ref
    assert got.speed == ref.speed  # bit for bit
    assert scenario_to_dict(got) == scenario_to_dict(ref)
    cached = "speed.rpm" not in keys and "shaft.length" not in keys
    assert (points.critical is not None) == cached


@pytest.mark.parametrize("seed", range(20))
def test_largest_first_equals_a_full_stable_sort(seed):
    """Reference: ``np.argsort(-mag[idx], kind="stable")`` of all peaks (ties in index order)."""
    from rubrotor.sweeps.metrics import _largest_first

    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 60))
    mag = rng.integers(0, 6, size=200).astype(float)  # many ties
    idx = np.sort(rng.choice(200, size=n, replace=False))
    ref = idx[np.argsort(-mag[idx], kind="stable")][:10]
    assert np.array_equal(_largest_first(idx, mag, 10), ref)
