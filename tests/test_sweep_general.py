"""Plain sweeps of a general (finite-element) rotor in the resumable zarr store.

Each point runs the general engine's fixed-step map (:mod:`rubrotor.sweeps.general_point`) from
the steady no-contact response and is reduced by the metrics every sweep uses.

References:

* Without contact (``seal_rub.toml`` with its clearance opened to 5 mm, gravity removed), the
  kept window is the steady unbalance response, which
  :func:`rubrotor.linear.response.unbalance_response` solves in the frequency domain on the full
  finite-element model (an exact LU solve per speed, no modal reduction): the sweep's
  ``max_displacement`` equals the largest ``|v + i w|`` of that response sampled at the same spin
  phases ``2 pi k / N``. Measured: 9e-13 relative at 600 and 700 rad/s (the engine's steady
  forced response is solved on the full model, so the 16-mode reduction does not enter);
  asserted 1e-9.
* A sweep interrupted after its first chunk and run again gives the store of an uninterrupted
  sweep, point for point (identical Datasets).
"""

import tomllib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import rubrotor
from rubrotor.cli import main
from rubrotor.errors import InputError
from rubrotor.linear.response import unbalance_response
from rubrotor.scenario.load import scenario_from_dict
from rubrotor.sweeps.sweep import open_sweep, sweep

SEAL = Path(rubrotor.__file__).parent / "scenarios" / "seal_rub.toml"
SPEEDS = np.array([600.0, 700.0])
SHORT = dict(transient_revolutions=2, revolutions=6, samples_per_revolution=64, workers=1)


@pytest.fixture(scope="module")
def free():
    d = tomllib.loads(SEAL.read_text())
    d.pop("gravity")
    d["contact"][0]["clearance"] = 5e-3
    d["initial"]["state"] = "rest"
    return scenario_from_dict(d)


@pytest.fixture(scope="module")
def reference(free):
    return sweep(free, {"speed.rad_per_s": SPEEDS}, chunk_size=1, **SHORT)


def test_no_contact_points_equal_the_steady_unbalance_response(free, reference):
    assert reference["done"].values.all() and (reference["status"].values == 1).all()
    assert (reference["contact_fraction"].values == 0).all()
    pos = free.engine.stations[0].contact.position
    planes = [(u.position, u.magnitude, u.phase) for u in free.engine.unbalances]
    resp = unbalance_response(rubrotor.linear_system(free), SPEEDS, planes, [pos])
    theta = 2 * np.pi * np.arange(SHORT["samples_per_revolution"]) / SHORT["samples_per_revolution"]
    for i in range(SPEEDS.size):
        V, W = resp.complex_response[i, 0]
        p = (V * np.exp(1j * theta)).real + 1j * (W * np.exp(1j * theta)).real
        expected = np.abs(p).max()
        got = float(reference["max_displacement"].values[i])
        assert got == pytest.approx(expected, rel=1e-9)


def test_interrupted_general_sweep_resumes_to_the_same_store(
    free, reference, tmp_path, monkeypatch
):
    import rubrotor.sweeps.sweep as sw

    store = tmp_path / "g.zarr"
    real = sw.run_chunk
    calls = []

    def stop_after_one(task):
        if calls:
            raise KeyboardInterrupt
        calls.append(task["chunk"])
        return real(task)

    monkeypatch.setattr(sw, "run_chunk", stop_after_one)
    with pytest.raises(KeyboardInterrupt):
        sweep(free, {"speed.rad_per_s": SPEEDS}, chunk_size=1, store=store, **SHORT)
    assert int(open_sweep(store)["done"].sum()) == 1
    calls.clear()
    monkeypatch.setattr(sw, "run_chunk", lambda t: calls.append(t["chunk"]) or real(t))
    resumed = sweep(free, {"speed.rad_per_s": SPEEDS}, chunk_size=1, store=store, **SHORT)
    assert len(calls) == 1  # only the missing point ran
    xr.testing.assert_identical(resumed, reference)


def test_general_sweep_refusals_and_cli(free, tmp_path, capsys):
    with pytest.raises(InputError, match="samples_per_revolution"):
        sweep(free, {"speed.rad_per_s": SPEEDS}, **{**SHORT, "samples_per_revolution": 48})
    out = tmp_path / "cli.zarr"
    code = main(["sweep", str(SEAL), "--vary", "speed.rad_per_s=600:600:1", "--transient", "1",
                 "--revolutions", "5", "--samples", "32", "--workers", "1", "--out", str(out)])  # fmt: skip
    assert code == 0, capsys.readouterr().err
    ds = open_sweep(out)
    assert ds["done"].values.all() and ds["peak_normal_force"].values[0] > 0  # the seal rubs


def test_general_follow_sweep_resumes_to_the_same_store(free, tmp_path, monkeypatch):
    """A general rotor's state-carrying sweep is written to the zarr store chunk by chunk (it
    was held in memory); killed after two chunks and run again it gives the uninterrupted
    sweep's store, the resumed chains starting from the stored end vectors."""
    import rubrotor.sweeps.follow as fo
    from rubrotor.sweeps.follow import follow_sweep

    values = [600.0, 650.0, 700.0]
    kw = dict(direction="both", transient_revolutions=2, revolutions=6, samples_per_revolution=64,
              workers=1, chunk_size=1)  # fmt: skip
    reference = follow_sweep(free, "speed.rad_per_s", values, store=tmp_path / "ref.zarr", **kw)
    assert reference["done"].values.all()
    # the carried state is the map's vector: a finite end state at every point
    assert np.isfinite(reference["final_state"].values).all()
    real, calls = fo.run_follow_chunk, []

    def stop_after_two(task):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(task["chunk"])
        return real(task)

    store = tmp_path / "f.zarr"
    monkeypatch.setattr(fo, "run_follow_chunk", stop_after_two)
    with pytest.raises(KeyboardInterrupt):
        follow_sweep(free, "speed.rad_per_s", values, store=store, **kw)
    assert int(open_sweep(store)["done"].sum()) == 2
    calls.clear()
    monkeypatch.setattr(fo, "run_follow_chunk", lambda t: calls.append(t["chunk"]) or real(t))
    resumed = follow_sweep(free, "speed.rad_per_s", values, store=store, **kw)
    assert len(calls) == 4
    xr.testing.assert_identical(resumed, reference)
