"""The array-level entry (PreparedRun) and the zero-copy results Dataset (issue 14).

References:

* a fresh ``simulate_system`` call for every run: one PreparedRun run many times, from rest,
  from the steady orbit and from other start states, in any order, must give the same arrays
  bit for bit (nothing of one run may leak into the next through the re-used plan and stepper);
* the unbalance force in closed form, ``m e Omega^2 e^{i (Omega t + phase)}`` (N), computed here
  from the scenario, for the Dataset's lazily computed ``unbalance_force_y/z``;
* the result's own arrays for the Dataset's variables (the same memory: no copy).
"""

from __future__ import annotations

import dataclasses
import math
from importlib import resources

import numpy as np
import pytest
import xarray as xr

from rubrotor.engine.result import to_dataset
from rubrotor.engine.settings import Integrator
from rubrotor.engine.simulate import PreparedRun, RotorState, simulate_system
from rubrotor.errors import InputError
from rubrotor.scenario import load_scenario

CASE1 = load_scenario(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")
INTEGRATORS = {
    "adaptive": Integrator(revolutions=6, output_dtau=2 * math.pi / 64),
    "fixed": Integrator(revolutions=6, dtau=2e-3, save_every=8, probes=(0.1, 0.3)),
    "abm": Integrator(revolutions=6, method="abm", dtau=1e-3, save_every=16),
}


def _fresh(integ, **kw):
    sc = CASE1
    return simulate_system(sc.shaft, sc.speed, integ, sc.unbalance, sc.contact, sc.load,
                           sc.damping, progress=False, **kw)  # fmt: skip


def _same(a, b) -> None:
    assert a.status == b.status and a.message == b.message
    assert np.array_equal(a.time, b.time)
    assert np.array_equal(a.channels, b.channels)
    assert np.array_equal(a.events, b.events)
    for x, y in ((a.final_state.q, b.final_state.q), (a.final_state.qd, b.final_state.qd)):
        assert np.array_equal(x, y)
    a_stats = {k: v for k, v in a.stats.items() if k != "wall_s"}
    assert a_stats == {k: v for k, v in b.stats.items() if k != "wall_s"}


@pytest.mark.parametrize("kind", list(INTEGRATORS))
def test_prepared_run_reused_equals_fresh_calls(kind):
    integ = INTEGRATORS[kind]
    prepared = PreparedRun.from_scenario(CASE1, integ)
    rest = _fresh(integ)
    start = RotorState(q=0.5 * rest.final_state.q, qd=-rest.final_state.qd, phase=0.3)
    steady = _fresh(integ, initial="steady")
    from_state = _fresh(integ, start=start)
    # interleaved and repeated: each run must equal its fresh counterpart
    for _ in range(2):
        _same(prepared.run(initial="steady"), steady)
        _same(prepared.run(start=start), from_state)
        _same(prepared.run(), rest)
    assert rest.events.size > 0  # the runs rub: contact state is carried and reset


def test_prepared_run_energy_tracking_and_errors():
    integ = Integrator(revolutions=4, dtau=2e-3, save_every=8)
    prepared = PreparedRun.from_scenario(CASE1, integ, track_energy=True)
    a, b = prepared.run(), prepared.run()
    fresh = _fresh(integ, track_energy=True)
    assert a.work == fresh.work == b.work and a.work["mechanical_energy_start_J"] == 0.0
    with pytest.raises(InputError, match="initial.state"):
        prepared.run(initial="moving")
    with pytest.raises(InputError, match="speed"):
        PreparedRun(CASE1.shaft, -1.0, integ)


def test_result_is_frozen_and_dataset_views_its_arrays():
    integ = INTEGRATORS["fixed"]
    res = PreparedRun.from_scenario(CASE1, integ).run()
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.status = "partial"
    ds = to_dataset(res)
    nst = len(res.stations)
    assert nst == 3
    np.testing.assert_array_equal(ds["station"].values, res.stations)
    for i, name in enumerate(("v", "w", "v_dot", "w_dot", "v_ddot", "w_ddot")):
        assert ds[name].dims == ("station", "time")
        assert np.shares_memory(ds[name].values, res.channels)
        for s in range(nst):
            assert np.array_equal(ds[name].values[s], res.channels[6 * s + i])
    assert np.shares_memory(ds["normal_force"].values, res.channels)
    assert np.array_equal(ds["normal_force"].values[0], res.channels[6 * nst])
    assert np.array_equal(ds["in_contact"].values[0], (res.channels[6 * nst] > 0).astype(np.int8))
    assert ds["in_contact"].dtype == np.int8


def test_lazy_unbalance_force_is_the_closed_form(tmp_path):
    sc = CASE1.with_changes(**{"unbalance.phase_deg": 30.0})
    integ = INTEGRATORS["adaptive"]
    res = PreparedRun.from_scenario(sc, integ).run()
    ds = to_dataset(res)
    t = res.time
    u = sc.unbalance
    f = u.magnitude * sc.speed**2 * np.exp(1j * (sc.speed * t + math.radians(30.0)))
    scale = u.magnitude * sc.speed**2
    sub = ds.isel(time=slice(5, 40, 3))  # lazy indexing first, then the whole variable
    np.testing.assert_allclose(sub["unbalance_force_z"].values, f.imag[5:40:3], atol=1e-12 * scale)
    np.testing.assert_allclose(ds["unbalance_force_y"].values, f.real, atol=1e-12 * scale)
    np.testing.assert_allclose(ds["unbalance_force_z"].values, f.imag, atol=1e-12 * scale)
    # a lazy variable survives a netCDF round trip and equals its loaded self
    ds.to_netcdf(tmp_path / "r.nc")
    xr.testing.assert_identical(xr.load_dataset(tmp_path / "r.nc"), ds.load())


def test_engine_dataset_views_the_result_channels():
    """Reference: the engine's channel layout (rows ``4 s + k`` per station, ``4 S + 8 i + k``
    per contact, :mod:`rubrotor.core.engine`)."""
    from rubrotor.engine.driver import simulate_general
    from rubrotor.engine.parts import RubStation, Run
    from rubrotor.engine.stream import CONTACT_VARS, STATION_VARS
    from rubrotor.rotors.shaft_system import continuous_system

    sc, integ = CASE1, Integrator(revolutions=3)
    run = Run(speed=sc.speed, duration=integ.total_time(sc.speed), probes=(0.1, 0.3),
              step=integ.output_spacing(sc.speed), rtol=integ.rtol, atol=integ.atol)  # fmt: skip
    stn = [RubStation(dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2))]
    res = simulate_general(continuous_system(sc.shaft), run, stn, [sc.unbalance], progress=False)
    ds = res.to_dataset()
    S = len(res.stations)
    assert S == 3 and res.events.size > 0
    for k, (name, _) in enumerate(STATION_VARS):
        assert np.shares_memory(ds[name].values, res.channels)
        for s in range(S):
            assert np.array_equal(ds[name].values[s], res.channels[4 * s + k])
    for k, (name, _) in enumerate(CONTACT_VARS):
        assert np.shares_memory(ds[name].values, res.channels)
        assert np.array_equal(ds[name].values[0], res.channels[4 * S + k])
    fn = res.channels[4 * S + 6]
    assert np.array_equal(ds["in_contact"].values[0], (fn > 0).astype(np.int8))
