"""Periodic orbits of a general (finite-element) rotor by shooting (rubrotor.orbits.general_map).

References:

* without contact, the multipliers of the map are ``exp(lambda T)`` of the engine's reduced
  linear system (its ``plant.lam``: rotor and stator modes), which the map propagates exactly;
* with rub, the engine's own time simulation (``rubrotor.simulate``, the driver's chunked run,
  a route that shares only the kernel) from the static deflection: after 300 revolutions its
  last revolution equals the shot orbit, and its deviation from the orbit shrinks per
  revolution by the largest Floquet multiplier's modulus, which checks the difference
  monodromy by an independent measurement.
"""

from __future__ import annotations

import math
from importlib import resources

import numpy as np
import pytest

from rubrotor.errors import InputError
from rubrotor.orbits import shooting
from rubrotor.orbits.general_map import GeneralMap
from rubrotor.scenario import load_scenario

SEAL = resources.files("rubrotor") / "scenarios" / "seal_rub.toml"
STEPS = 256


@pytest.fixture(scope="module")
def orbit():
    return shooting.shoot(load_scenario(SEAL), steps=STEPS, transient_revolutions=50)


def test_no_contact_multipliers_equal_exp_lambda_t(tmp_path):
    """Clearance opened to 10 mm: the orbit never touches and the map is affine, so its
    difference monodromy has the eigenvalues ``exp(lambda T)`` (and zeros for the contact
    force components) to 1e-10 (measured 2.5e-14)."""
    path = tmp_path / "free.toml"
    path.write_text(SEAL.read_text().replace("clearance = 40e-6", "clearance = 1e-2"))
    sc = load_scenario(path)
    orb = shooting.shoot(sc, steps=STEPS)
    lam = GeneralMap(sc, 1, STEPS).plant.lam
    ref = np.exp(lam * 2 * math.pi / sc.speed)
    for mu in np.concatenate([ref, ref.conj()]):
        assert np.min(np.abs(orb.multipliers - mu)) < 1e-10
    assert orb.stable and orb.residual < 1e-12


def test_rub_orbit_is_the_attractor_of_the_time_simulation(orbit):
    """The seal rub's periodic orbit (contact all revolution long, gravity, offset flexible
    stator, friction, speed-tabulated cross-coupled bearings) against 300 revolutions of the
    engine's time simulation at the same fixed step: its last revolution equals the orbit to
    1e-10 of the orbit's size (measured 8e-14), and the per-revolution contraction of its
    deviation over revolutions 20 to 60 equals the largest multiplier's modulus to 0.5 %
    (measured 0.79141 against 0.79186)."""
    import rubrotor
    from rubrotor.engine.settings import Integrator

    assert orbit.stable and orbit.residual < 1e-10
    sc = load_scenario(SEAL)
    T = 2 * math.pi / sc.speed
    integ = Integrator(revolutions=300.0, dt=T / STEPS, save_every=STEPS // 64)
    ds = rubrotor.simulate(sc, integrator=integ, progress=False)
    ref = orbit.dataset(64)
    v, w = ds["v"].sel(station=0.75).values, ds["w"].sel(station=0.75).values
    size = np.max(np.hypot(ref["v"].values, ref["w"].values))
    last = np.hypot(v[-65:] - ref["v"].values[0], w[-65:] - ref["w"].values[0])
    assert np.max(last) < 1e-10 * size
    # deviation at the start of each revolution, revolutions 20 .. 60 (before rounding)
    dev = np.hypot(v[64 * np.arange(20, 61)] - ref["v"].values[0][0],
                   w[64 * np.arange(20, 61)] - ref["w"].values[0][0])  # fmt: skip
    rate = np.exp(np.polyfit(np.arange(20, 61), np.log(dev), 1)[0])
    assert rate == pytest.approx(abs(orbit.multipliers[0]), rel=0.005)


def test_orbit_dataset_and_refusals(orbit):
    """The orbit as a Dataset like a simulation's (closing on itself); the synchronous route is
    refused by name on a general rotor, and so is a speed profile."""
    from rubrotor.orbits.continuation import continue_orbit

    ds = orbit.dataset(64)
    assert ds.sizes["time"] == 65 and ds.attrs["status"] == "complete"
    assert ds["v"].values[0, 0] == ds["v"].values[0, -1]
    assert orbit.max_radius() == pytest.approx(
        float(np.max(np.hypot(ds["v"].values[0], ds["w"].values[0]))), rel=1e-3
    )
    with pytest.raises(InputError, match="method"):
        continue_orbit(load_scenario(SEAL), "speed.rad_per_s", 600.0, 650.0, points=3,
                       method="synchronous")  # fmt: skip
    runup = resources.files("rubrotor") / "scenarios" / "runup_rub.toml"
    with pytest.raises(InputError, match="speed.profile"):
        shooting.shoot(load_scenario(runup))


def test_continuation_in_speed_equals_shooting_at_each_speed(tmp_path, capsys):
    """A general rotor's branch in speed (maps rebuilt at every speed, their modes aligned with
    the first speed's): at three of its points, shooting from scratch at that speed (its own
    reduction and modal basis) gives the same largest radius and multiplier moduli to 1e-5
    (the continuation's tolerance on a general rotor is 1e-6). Through the CLI: --json and
    --figure (no follow sweep for a general rotor) work."""
    import json

    from rubrotor.cli import main
    from rubrotor.orbits.continuation import continue_orbit

    sc = load_scenario(SEAL)
    branch = continue_orbit(sc, "speed.rad_per_s", 628.3, 700.0, points=6, steps=128)
    assert branch.method == "shooting" and len(branch.points) == 6
    assert branch.points[-1].value > branch.points[0].value
    for p in branch.points[2::2]:
        orb = shooting.shoot(sc.with_changes(**{"speed.rad_per_s": p.value}), steps=128,
                             transient_revolutions=100)  # fmt: skip
        assert orb.max_radius() == pytest.approx(p.max_radius_m, rel=1e-5)
        np.testing.assert_allclose(np.abs(orb.multipliers[:6]), np.abs(p.multipliers[:6]),
                                   rtol=1e-5)  # fmt: skip
    out, fig = tmp_path / "b.nc", tmp_path / "b.png"
    args = ["continue", str(SEAL), "--vary", "speed.rad_per_s=628.3:650", "--points", "3",
            "--steps", "128", "--out", str(out), "--json", "--figure", str(fig)]  # fmt: skip
    assert main(args) == 0
    summary = json.loads(capsys.readouterr().out)
    assert len(summary["points"]) == 3 and out.exists() and fig.exists()


@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
def test_state_carrying_sweep_follows_the_shot_orbits():
    """Up and down state-carrying sweeps of the seal rub in speed (general engine, the state
    carried in aligned modal coordinates): the up chain stays on the rub orbit and the down
    chain, started from the steady no-contact response at 700 rad/s, on the no-contact orbit
    down to 650 rad/s (hysteresis; at 600 rad/s only the rub remains). Reference: shooting at each speed from the sweep's regime
    (the rub orbit from 300 transient revolutions of the 600 rad/s rub state; the no-contact
    orbit from the steady response), whose largest radius the sweep's must equal to 1e-7 after its 100
    transient revolutions (largest multiplier ~0.8: 0.8^100 ~ 2e-10)."""
    from rubrotor.sweeps.follow import follow_general
    from rubrotor.sweeps.regimes import regime_labels

    sc = load_scenario(SEAL)
    speeds = [600.0, 650.0, 700.0]
    ds = follow_general(sc, "speed.rad_per_s", speeds, "both", 100, 10, 128, steps=128)
    labels = regime_labels(ds)
    assert all(lab != "no contact" for lab in labels[0]) and all(labels[1, 1:] == "no contact")
    rub = shooting.shoot(
        sc.with_changes(**{"speed.rad_per_s": 600.0}), steps=128, transient_revolutions=100
    )  # the only attractor at 600 rad/s
    for j, w in enumerate(speeds[1:], start=1):
        here = sc.with_changes(**{"speed.rad_per_s": w})
        # the rub orbit: 300 revolutions from the 600 rad/s rub state (read in this map's own
        # modes: a large start in contact), then Newton; the no-contact orbit from the steady
        # response
        on = shooting.shoot(here, rub.state, steps=128, transient_revolutions=300)
        off = shooting.shoot(here, steps=128)
        assert on.max_radius() > 75e-6 > 65e-6 > off.max_radius()
        assert ds["max_displacement"].values[0, j] == pytest.approx(on.max_radius(), rel=1e-7)
        assert ds["max_displacement"].values[1, j] == pytest.approx(off.max_radius(), rel=1e-7)


@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
def test_lyapunov_exponents_of_a_general_rotor(tmp_path, orbit):
    """Benettin on the general map (differences along the tangent vectors, QR each revolution).

    References: without contact, the exponents per revolution are ``Re(lambda) T`` of the
    reduced linear system (each mode twice, its real plane): each to 1e-5 after 100 revolutions
    (the two of a pair share its growth unevenly over a finite run, measured 3e-6 at 128 steps
    per revolution) and each pair's sum to 1e-6 (measured 2e-7); on the seal rub's periodic orbit the two largest (a complex pair of
    multipliers) sum to ``2 ln|mu_max|`` of shooting's difference monodromy (its eigenvalues, a
    separate computation) to 1e-3. A state-carrying sweep with ``lyapunov=True`` labels the
    periodic rub by a negative exponent.
    """
    import rubrotor
    from rubrotor.sweeps.follow import follow_sweep

    path = tmp_path / "free.toml"
    path.write_text(SEAL.read_text().replace("clearance = 40e-6", "clearance = 1e-2"))
    free = load_scenario(path)
    r = rubrotor.lyapunov_exponents(free, count=4, revolutions=100, transient_revolutions=100,
                                    steps_per_revolution=STEPS)  # fmt: skip
    lam = GeneralMap(free, 1, STEPS).plant.lam
    ref = np.sort(np.repeat(lam.real, 2))[::-1][:4] * 2 * math.pi / free.speed
    np.testing.assert_allclose(r.per_revolution, ref, atol=1e-5)  # within a pair: ~1 / N
    pairs = r.per_revolution[0::2] + r.per_revolution[1::2]
    np.testing.assert_allclose(pairs, ref[0::2] + ref[1::2], atol=1e-6)
    rub = rubrotor.lyapunov_exponents(load_scenario(SEAL), count=2, revolutions=100,
                                      transient_revolutions=100, steps_per_revolution=STEPS,
                                      start=orbit.state)  # fmt: skip
    mu = np.log(np.abs(orbit.multipliers[0]))
    assert rub.status == "complete"
    assert np.sum(rub.per_revolution) == pytest.approx(2 * mu, abs=1e-3)
    ds = follow_sweep(load_scenario(SEAL), "speed.rad_per_s", [628.3], direction="up",
                      transient_revolutions=50, revolutions=80, samples_per_revolution=32,
                      lyapunov=True)  # fmt: skip
    assert ds["lyapunov_exponent"].values[0, 0] < 0 and ds["period"].values[0, 0] == 1


def test_cli_follow_sweep_of_a_general_rotor(tmp_path, capsys):
    """``rubrotor sweep --follow`` on a general rotor: written to the zarr store chunk by chunk
    (the same regimes in the printed summary and in the store); running it again resumes the
    finished store (nothing left to compute: the same store)."""
    import json

    import xarray as xr

    from rubrotor.cli import main
    from rubrotor.sweeps.regimes import regime_labels

    out = tmp_path / "f.zarr"
    args = ["sweep", str(SEAL), "--vary", "speed.rad_per_s=600:650:2", "--follow", "up",
            "--transient", "20", "--revolutions", "30", "--samples", "32", "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    summary = json.loads(capsys.readouterr().out)
    ds = xr.open_zarr(out)
    labels = regime_labels(ds)
    assert summary["points"] == 2 and summary["incomplete_runs"] == 0
    assert sum(summary["regimes"]["up"].values()) == 2 and set(labels[0]) <= set(
        summary["regimes"]["up"]
    )
    assert ds.attrs["rotor"] == "fe" and ds.sizes["revolution"] == 10
    first = ds.load()
    assert main(args) == 0
    xr.testing.assert_identical(xr.open_zarr(out).load(), first)
