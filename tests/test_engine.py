"""The general engine (rubrotor.engine) against independent references.

* A full-DOF SciPy reference (tests/engine_reference.py: solve_ivp DOP853 on ``M q'' + D q' +
  K q = f`` with the same contact law, no modal reduction, rtol 1e-10) on a finite-element rotor
  with two disks, anisotropic cross-coupled bearings, gravity, two unbalance planes and rub at a
  disk against a flexible, offset, anisotropic stator with friction.
* The old compiled engine (rubrotor.engine.simulate) on the seed's case 1 through the continuous
  shaft written as a LinearSystem.
* The closed-form static deflection ``5 w L^4 / (384 E I)`` of a pinned-pinned uniform shaft.
"""

import dataclasses
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from rubrotor.core.engine import STATUS_NAMES
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.parts import RubStation, Run, Stator
from rubrotor.errors import InputError
from rubrotor.rotors.fe import Bearing, Disk, Rotor, Section
from rubrotor.rotors.forces import Contact, Unbalance
from rubrotor.rotors.shaft_system import continuous_system

sys.path.insert(0, str(Path(__file__).parent))
from engine_reference import STEEL, reference_run, two_disk_rotor  # noqa: E402

GRAVITY = (-9.81, 0.0)
SPEED = 300.0  # rad/s


def general_case():
    """Two-disk FE rotor on anisotropic cross-coupled bearings, rub at disk 1."""
    rotor = two_disk_rotor()
    contact = Contact(clearance=1e-4, stiffness=2e7, damping=200, friction=0.2, position=0.33,
                      law="linear", radius=0.1)  # fmt: skip
    station = RubStation(contact, offset_y=-1e-4, offset_z=5e-5,
                         stator=Stator(20, 25, 5e6, 6e6, 500, 500))  # fmt: skip
    unb = [Unbalance(2e-4, 0.33, 0.0), Unbalance(1e-4, 0.67, 1.0)]
    return rotor.linear_system(), [station], unb


@pytest.fixture(scope="module")
def reference():
    system, stations, unb = general_case()
    run = Run(speed=SPEED, duration=0.06, step=2e-5, save_every=5, initial="rest")
    t, rot, sta, _ = reference_run(system, run, stations, unb, gravity=GRAVITY)
    return t, rot, sta


def _error(res, ref):
    t, rot, sta = ref
    n = min(len(t), res.channels.shape[1])
    ch = res.channels
    return max(
        np.max(np.abs(ch[0, :n] - rot[0, 0, :n])),
        np.max(np.abs(ch[1, :n] - rot[0, 1, :n])),
    ) / np.max(np.abs(rot[0, :, :n]))


def _run(step, **kw):
    system, stations, unb = general_case()
    run = Run(speed=SPEED, duration=0.06, step=step, save_every=round(1e-4 / step),
              initial="rest", **kw)  # fmt: skip
    return simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False)


def test_full_model_matches_scipy_with_second_order(reference):
    """All modes kept: the error against DOP853 (rtol 1e-10) falls with the step, with
    contact, friction, the flexible offset stator and gravity all active. The linear law's
    dashpot makes the force jump at every onset, so the measured global order is about 1 (the
    first-order hold is second order only for a continuous force); the slope is fitted."""
    steps = [2e-5, 1e-5, 5e-6]
    runs = [_run(h) for h in steps]
    for r in runs:
        assert r.status == "complete", r.message
        assert r.stats["contact_events"] >= 10  # the rub is really there
    errs = [_error(r, reference) for r in runs]
    slope = np.polyfit(np.log(steps), np.log(errs), 1)[0]
    print("errors", errs, "slope", slope)
    assert slope > 0.8
    assert errs[-1] < 5e-4
    t, rot, sta = reference
    ch = runs[-1].channels
    n = min(len(t), ch.shape[1])
    s_err = np.max(np.abs(ch[4, :n] - sta[0, 0, :n])) / np.max(np.abs(sta[0, 0, :n]))
    assert s_err < 1e-3  # stator displacement (channel 4 = s_y) follows the reference too


def test_residual_correction_gain(reference):
    """Truncation error as the retained modes grow, with and without the static correction of
    the dropped modes. Measured against the all-modes run at the same step (which agrees with
    the SciPy full-DOF reference, test above), so that the step error cancels: the error falls
    with the mode count and the correction divides it at every count (gains printed)."""
    counts = [8, 10, 12, 16]
    full = _run(2e-5)
    scale = np.max(np.abs(full.channels[:2]))

    def trunc(r):
        return np.max(np.abs(r.channels[:2] - full.channels[:2])) / scale

    with_r = [trunc(_run(2e-5, modes=k)) for k in counts]
    without = [trunc(_run(2e-5, modes=k, residual=False)) for k in counts]
    gains = [b / a for a, b in zip(with_r, without, strict=True)]
    print("modes", counts, "with", with_r, "without", without, "gain", gains)
    print(
        "vs SciPy: all modes",
        _error(full, reference),
        "with",
        _error(_run(2e-5, modes=10), reference),
    )
    assert with_r[0] > with_r[-1]
    assert min(gains) > 1.5


def test_seed_case1_same_as_old_engine():
    """Seed case 1 (20 revolutions, dtau 1e-3) through the continuous shaft as a LinearSystem
    agrees with the old complex-coordinate engine to rounding (same scheme, same model)."""
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate_system
    from rubrotor.scenario import load_scenario

    path = Path(__file__).parents[1] / "src/rubrotor/scenarios/seed_case1.toml"
    sc = load_scenario(path)
    integ = Integrator(revolutions=20, dtau=1e-3, save_every=32)
    old = simulate_system(sc.shaft, sc.speed, integ, sc.unbalance, sc.contact, None,
                          sc.damping, progress=False)  # fmt: skip
    contact = dataclasses.replace(sc.contact, radius=sc.shaft.diameter / 2)
    run = Run(speed=sc.speed, duration=integ.total_time(sc.speed), step=1e-3 / sc.speed,
              save_every=32, initial="rest")  # fmt: skip
    new = simulate_general(continuous_system(sc.shaft), run, [RubStation(contact)],
                           [sc.unbalance], progress=False)  # fmt: skip
    n = min(old.channels.shape[1], new.channels.shape[1])
    scale = np.max(np.abs(old.channels[0, :n]))
    assert old.stats["contact_events"] == new.stats["contact_events"] > 0
    for k in range(4):  # v, w, v', w'
        ko = k if k < 2 else k  # the old layout has v, w, v', w' first as well
        d = np.max(np.abs(old.channels[ko, :n] - new.channels[k, :n]))
        ref = np.max(np.abs(old.channels[ko, :n]))
        assert d <= 1e-9 * ref, (k, d / ref)
    assert scale > sc.contact.clearance


def test_static_deflection_under_gravity():
    """Euler-Bernoulli uniform pinned-pinned shaft under gravity, started at static
    equilibrium: the midspan deflection is 5 w L^4 / (384 E I), w = rho A g, and stays."""
    L, d = 1.2, 0.05
    rotor = Rotor([Section(L, d, STEEL, elements=8)], theory="euler-bernoulli",
                  bearings=[Bearing(0.0, kind="pinned"), Bearing(L, kind="pinned")])  # fmt: skip
    g = 9.81
    run = Run(speed=100.0, duration=0.01, step=1e-5, save_every=10, initial="static",
              probes=(L / 2,))  # fmt: skip
    res = simulate_general(rotor.linear_system(), run, gravity=(-g, 0.0), progress=False)
    area, inertia = math.pi * d**2 / 4, math.pi * d**4 / 64
    exact = -5 * STEEL.density * area * g * L**4 / (384 * STEEL.youngs_modulus * inertia)
    v = res.channels[0]
    assert np.max(np.abs(v - exact)) < 1e-9 * abs(exact)
    assert np.max(np.abs(res.channels[1])) < 1e-12 * abs(exact)


def test_bad_input_names_the_field():
    """Errors name the field and what is allowed."""
    with pytest.raises(InputError, match="initial.state"):
        Run(speed=1.0, duration=1.0, step=0.1, initial="moving")
    with pytest.raises(InputError, match="contact.position"):
        RubStation(Contact(clearance=1e-4, stiffness=1e6, law="linear", radius=0.1))
    with pytest.raises(InputError, match="stator_mass_y"):
        Stator.isotropic(0.0, 1e6)
    assert set(STATUS_NAMES.values()) >= {"complete", "diverged", "event buffer full"}


def _energy_residual(step):
    """``(E(T) - E(0) - W) / W_scale`` for the general case with all modes kept (see below)."""
    from rubrotor.engine.driver import build_plant
    from rubrotor.engine.parts import static_load_vector, unbalance_phasor

    system, stations, unb = general_case()
    run = Run(speed=SPEED, duration=0.03, step=step, initial="rest", save_state=True)
    res = simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False)
    assert res.status == "complete" and res.stats["contact_events"] > 0
    plant = build_plant(system, run, stations, unb, gravity=GRAVITY)
    sm = system.matrices(SPEED)
    nr = plant.n_rotor
    z = np.exp(1j * SPEED * res.time)
    Y = res.states[:, :nr]
    q = (Y @ plant.rotor.Vq.T).real + plant.q_static + np.real(np.outer(z, plant.q_unbalance))
    qd = (Y * plant.rotor.lam) @ plant.rotor.Vq.T
    qd = qd.real + np.real(np.outer(1j * SPEED * z, plant.q_unbalance))
    f_s = static_load_vector(system, (), GRAVITY)
    b_u = sum(unbalance_phasor(u, SPEED) * (system.force_map(u.position) @ np.array([1, -1j]))
              for u in unb)  # fmt: skip
    ksym, kskew = 0.5 * (sm.K + sm.K.T), 0.5 * (sm.K - sm.K.T)
    dsym = 0.5 * (sm.damping + sm.damping.T)
    ch = res.channels
    S = len(res.stations)
    s, sd = ch[4 * S : 4 * S + 2], ch[4 * S + 2 : 4 * S + 4]
    F = ch[4 * S + 4 : 4 * S + 6]
    ms, cs, ks = stations[0].stator.matrices()
    energy = (
        0.5 * np.einsum("ti,ij,tj->t", qd, sm.M, qd)
        + 0.5 * np.einsum("ti,ij,tj->t", q, ksym, q)
        - q @ f_s
        + 0.5 * np.einsum("it,ij,jt->t", sd, ms, sd)
        + 0.5 * np.einsum("it,ij,jt->t", s, ks, s)
    )
    power_u = np.einsum("ti,ti->t", qd, np.real(np.outer(z, b_u)))
    power_c = np.sum(F * (ch[2:4] - sd), axis=0)  # contact force on the relative velocity
    power_d = -np.einsum("ti,ij,tj->t", qd, dsym, qd) - np.einsum("it,ij,jt->t", sd, cs, sd)
    power_k = -np.einsum("ti,ij,tj->t", qd, kskew, q)  # circulatory bearing forces
    power = power_u + power_c + power_d + power_k
    work = np.trapezoid(power, res.time)
    scale = np.trapezoid(np.abs(power_c) + np.abs(power_d) + np.abs(power_u), res.time)
    return (energy[-1] - energy[0] - work) / scale


def test_energy_balance_closes_with_flexible_stator():
    """Mechanical energy of rotor and stator (kinetic, strain, gravity potential) changes by
    the work of unbalance, contact (on the relative velocity), damping and the circulatory
    bearing forces, integrated by the trapezoidal rule from the saved state. The imbalance
    falls with the step (the scheme's and the quadrature's error) and is small."""
    steps = [4e-6, 2e-6, 1e-6]
    res = [abs(_energy_residual(h)) for h in steps]
    slope = np.polyfit(np.log(steps), np.log(res), 1)[0]
    print("energy residuals", res, "slope", slope)
    assert res[-1] < 1e-3
    assert slope > 0.8


def test_event_buffer_grows_or_says_full(monkeypatch):
    """A full event buffer is grown between chunks (same events as a large buffer); at its cap
    the run stops partial with the named status instead of dropping events silently."""
    import rubrotor.engine.driver as drv

    base = _run(2e-5)
    monkeypatch.setattr(drv, "EVENT_BUFFER", 140)
    monkeypatch.setattr(drv, "EVENT_BUFFER_MAX", 1 << 20)
    grown = _run(2e-5)
    assert grown.status == "complete"
    np.testing.assert_array_equal(grown.events, base.events)
    monkeypatch.setattr(drv, "EVENT_BUFFER_MAX", 140)
    capped = _run(2e-5)
    assert capped.status == "partial" and "event buffer full" in capped.message
    assert len(capped.events) < len(base.events)


def test_divergence_is_reported():
    """A displacement above ``max_displacement`` stops the run partial, named, data kept."""
    system, stations, unb = general_case()
    run = Run(speed=SPEED, duration=0.06, step=2e-5, initial="rest", max_displacement=1.2e-4)
    res = simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False)
    assert res.status == "partial" and res.message.startswith("diverged")
    assert 1 < len(res.time) < 3000


def _runup_rotor():
    rotor = Rotor(
        [Section(1.0, 0.04, STEEL, elements=6)],
        disks=[Disk(0.5, 10.0, 0.05, 0.025)],
        bearings=[
            Bearing(0.0, kyy=1e6, kzz=1.2e6, cyy=200, czz=200),
            Bearing(1.0, kyy=1e6, kzz=1.2e6, cyy=200, czz=200),
        ],
    )
    return rotor.linear_system(), [Unbalance(1e-4, 0.5, 0.0)]


def _steady_peak_speed(system, unb, speeds):
    """Speed (rad/s) of the largest steady unbalance response at midspan (full model)."""
    amp = []
    for w in speeds:
        sm = system.matrices(w)
        b = unb[0].magnitude * w**2 * (system.force_map(0.5) @ np.array([1, -1j]))
        q = np.linalg.solve(sm.K - w**2 * sm.M + 1j * w * sm.damping, b)
        amp.append(np.max(np.abs(system.output_rows(0.5) @ q)))
    return speeds[int(np.argmax(amp))]


def test_runup_matches_scipy():
    """Run-up (speed linear in time, unbalance with its angular-acceleration term, gyroscopic
    matrix at the current speed) against DOP853 on the full model with Omega(t) in every
    evaluation: the engine re-diagonalises every 1/200 of the speed range."""
    system, unb = _runup_rotor()
    wc = _steady_peak_speed(system, unb, np.linspace(100, 600, 501))
    run = Run(speed=0.6 * wc, speed_end=1.4 * wc, duration=0.3, step=5e-5, save_every=2,
              initial="static", probes=(0.5,))  # fmt: skip
    t, rot, _, _ = reference_run(system, run, [], unb, rtol=1e-9, atol=1e-13)
    errs = []
    span = 0.8 * wc
    for segments in (10, 20, 40, 200):
        r = dataclasses.replace(run, speed_step=span / segments)
        res = simulate_general(system, r, unbalances=unb, progress=False)
        errs.append(np.max(np.abs(rot[0] - res.channels[:2])) / np.max(np.abs(rot[0])))
        print("segments", res.stats["segments"], "error", errs[-1], "wall", res.stats["wall_s"])
    slope = np.polyfit(np.log([10, 20, 40]), np.log(errs[:3]), 1)[0]
    print("error slope against segments", slope)
    assert slope < -0.8  # frozen speed within a segment: error ~ speed change per segment
    assert errs[-1] < 1e-5


def test_runup_ritz_reduction_equals_full_rediagonalisation():
    """Run-up with 2 retained modes: re-diagonalising the system projected on one Ritz basis
    (``runup_reduction="ritz"``) gives the samples of re-diagonalising the full model at every
    segment, and both have the same error against the full-DOF SciPy reference (DOP853 with
    Omega(t) in every evaluation; the error is the truncation to 2 modes)."""
    system, unb = _runup_rotor()
    wc = _steady_peak_speed(system, unb, np.linspace(100, 600, 501))
    base = Run(speed=0.6 * wc, speed_end=1.4 * wc, duration=0.15, step=5e-5, save_every=2,
               initial="static", probes=(0.5,), modes=2, speed_step=0.8 * wc / 100)  # fmt: skip
    t, rot, _, _ = reference_run(system, base, [], unb, rtol=1e-9, atol=1e-13)
    out = {}
    for red in ("full", "ritz"):
        res = simulate_general(system, dataclasses.replace(base, runup_reduction=red),
                               unbalances=unb, progress=False)  # fmt: skip
        assert res.stats["runup_reduction"] == red
        out[red] = res.channels[:2]
    scale = np.max(np.abs(rot[0]))
    errs = {k: np.max(np.abs(rot[0] - v)) / scale for k, v in out.items()}
    dev = np.max(np.abs(out["full"] - out["ritz"])) / scale
    print("errors", errs, "ritz - full", dev)
    assert errs["full"] < 2e-3 and abs(errs["ritz"] - errs["full"]) < 1e-6
    assert dev < 1e-6


def test_speed_table_profile_matches_scipy():
    """A speed table (run-up through the critical, hold, coast-down, rows on the sample grid):
    against DOP853 on the full model with the same piecewise-linear Omega(t), its exact spin
    angle and the angular-acceleration term in every evaluation (tests/engine_reference.py),
    the error falls with the speed step like the linear profile's (frozen speed per segment).
    A two-row table is the linear profile: same samples to rounding."""
    system, unb = _runup_rotor()
    wc = _steady_peak_speed(system, unb, np.linspace(100, 600, 501))
    table = ((0.0, 0.6 * wc), (0.12, 1.3 * wc), (0.16, 1.3 * wc), (0.3, 0.9 * wc))
    run = Run(speed=1.0, duration=0.3, step=5e-5, save_every=2, initial="static",
              probes=(0.5,), speed_table=table)  # fmt: skip
    assert run.speed == 0.6 * wc and run.speed_end == 0.9 * wc
    t, rot, _, _ = reference_run(system, run, [], unb, rtol=1e-9, atol=1e-13)
    scale = np.max(np.abs(rot[0]))
    errs = []
    for step in (0.05 * wc, 0.025 * wc, 0.0125 * wc, 0.0025 * wc):
        res = simulate_general(system, dataclasses.replace(run, speed_step=step),
                               unbalances=unb, progress=False)  # fmt: skip
        errs.append(np.max(np.abs(rot[0] - res.channels[:2])) / scale)
        print("segments", res.stats["segments"], "error", errs[-1])
    slope = np.polyfit(np.log([1, 2, 4]), np.log(errs[:3]), 1)[0]
    print("error slope against segments", slope)
    assert slope < -0.8 and errs[-1] < 1e-5
    lin = Run(speed=0.6 * wc, speed_end=1.4 * wc, duration=0.1, step=5e-5, save_every=2,
              initial="static", probes=(0.5,))  # fmt: skip
    tab = dataclasses.replace(lin, speed_end=None,
                              speed_table=((0.0, 0.6 * wc), (0.1, 1.4 * wc)))  # fmt: skip
    a, b = (simulate_general(system, r, unbalances=unb, progress=False) for r in (lin, tab))
    assert a.stats["segments"] == b.stats["segments"]
    np.testing.assert_allclose(
        b.channels, a.channels, rtol=0, atol=1e-12 * np.abs(a.channels).max()
    )


def test_runup_peak_above_critical_coastdown_below():
    """Passing the critical speed at a finite rate shifts the response peak: above the steady
    peak speed (full-model steady response, closed form) when accelerating, below it when
    decelerating."""
    system, unb = _runup_rotor()
    wc = _steady_peak_speed(system, unb, np.linspace(100, 600, 2001))
    peaks = []
    for w0, w1 in ((0.6 * wc, 1.4 * wc), (1.4 * wc, 0.6 * wc)):
        run = Run(speed=w0, speed_end=w1, duration=1.0, step=5e-5, save_every=4,
                  initial="static", probes=(0.5,))  # fmt: skip
        res = simulate_general(system, run, unbalances=unb, progress=False)
        late = res.time > 0.2  # past the start transient
        env = np.hypot(res.channels[0], res.channels[1])[late]
        peaks.append(w0 + (w1 - w0) * res.time[late][np.argmax(env)])
    print("steady peak", wc, "run-up peak", peaks[0], "coast-down peak", peaks[1])
    assert peaks[0] > wc > peaks[1]


def test_restart_from_final_state_continues_the_run():
    """A run split in two, the second started from the first's ``final_state``, equals the
    run done in one go (rigid offset stator, gravity, no unbalance so that the time origin
    does not matter). Only the force hold of the first step after the restart differs."""
    system, stations, _ = general_case()
    stations = [dataclasses.replace(stations[0], stator=None)]
    whole = Run(speed=SPEED, duration=0.04, step=2e-5, save_every=5, initial="rest")
    one = simulate_general(system, whole, stations, gravity=GRAVITY, progress=False)
    half = dataclasses.replace(whole, duration=0.02)
    a = simulate_general(system, half, stations, gravity=GRAVITY, progress=False)
    b = simulate_general(system, dataclasses.replace(half, initial=a.final_state), stations,
                         gravity=GRAVITY, progress=False)  # fmt: skip
    assert one.stats["contact_events"] > 0
    n = len(a.time)
    joined = np.concatenate([a.channels[:2], b.channels[:2, 1:]], axis=1)
    err = np.max(np.abs(joined - one.channels[:2])) / np.max(np.abs(one.channels[:2]))
    print("restart difference", err)
    assert np.allclose(b.channels[:2, 0], a.channels[:2, -1], rtol=0, atol=1e-12)
    assert err < 1e-3 and joined.shape[1] == 2 * n - 1


def test_streamed_run_equals_in_memory_run(tmp_path):
    """Streaming to netCDF in chunks of 300 samples writes the same samples, events and
    status as the in-memory run, and the result itself keeps no samples."""
    import xarray as xr

    system, stations, unb = general_case()
    run = Run(speed=SPEED, duration=0.06, step=2e-5, save_every=2, initial="rest")
    mem = simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False)
    path = tmp_path / "run.nc"
    st = simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False,
                          stream=str(path), chunk_samples=300)  # fmt: skip
    assert st.channels.shape[1] == 0 and st.status == "complete"
    ref = mem.to_dataset()
    with xr.open_dataset(path) as ds:
        for name in ("v", "w", "v_dot", "stator_y", "force_z", "normal_force"):
            np.testing.assert_array_equal(ds[name].values, ref[name].values)
        np.testing.assert_allclose(ds.time.values, ref.time.values, rtol=1e-15)
        np.testing.assert_array_equal(ds.event_time.values, ref.event_time.values)
        assert ds.attrs["status"] == "complete"


def test_streamed_events_are_flushed_per_chunk(tmp_path, monkeypatch):
    """A streamed run hands its events to the file chunk by chunk (chunks of 100 samples; a
    2-event buffer, below the kernel's margin, grows to it) and the file holds exactly the
    in-memory run's events, in order, with their contact index and kind (reference: the
    in-memory run)."""
    import xarray as xr

    from rubrotor.engine import driver

    system, stations, unb = general_case()
    run = Run(speed=SPEED, duration=0.06, step=2e-5, save_every=2, initial="rest")
    mem = simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False)
    assert len(mem.events) > 3
    monkeypatch.setattr(driver, "EVENT_BUFFER", 2)  # below the kernel's margin: grows once
    path = tmp_path / "run.nc"
    st = simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False,
                          stream=str(path), chunk_samples=100)  # fmt: skip
    assert st.status == "complete"
    assert st.stats["contact_events"] == mem.stats["contact_events"]
    ref = mem.to_dataset()
    with xr.open_dataset(path) as ds:
        for name in ("event_time", "event_contact", "event_kind"):
            np.testing.assert_array_equal(ds[name].values, ref[name].values)


def test_run_too_large_is_refused_before_it_starts():
    """A run whose samples cannot fit in memory is refused, naming the keys to change."""
    system, stations, unb = general_case()
    run = Run(speed=SPEED, duration=1e7, step=1e-5, initial="rest")
    with pytest.raises(InputError, match="simulation.save_every"):
        simulate_general(system, run, stations, unb, progress=False)


def test_adaptive_steps_meet_tolerance(reference):
    """Adaptive steps (output spacing 1e-4 s): the error against the SciPy full-DOF reference
    falls with rtol, and at rtol 1e-6 beats the fixed step 1e-5 s with fewer steps."""
    system, stations, unb = general_case()
    errs, steps = [], []
    for rtol in (1e-3, 1e-5, 1e-6):
        run = Run(speed=SPEED, duration=0.06, step=1e-4, initial="rest", rtol=rtol)
        r = simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False)
        assert r.status == "complete"
        errs.append(_error(r, reference))
        steps.append(r.stats["accepted_steps"] + r.stats["rejected_steps"])
    fixed = _run(1e-5)
    print("adaptive errors", errs, "steps", steps, "fixed 1e-5:", _error(fixed, reference), 6000)
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < _error(fixed, reference) and steps[2] < fixed.stats["steps"]


def test_adaptive_onsets_located():
    """Contact onsets of an adaptive run lie where the fine fixed-step run (step 1e-7 s, gap
    crossing interpolated within the step) finds them, to within a small fraction of the
    output spacing."""
    system, stations, unb = general_case()
    run = Run(speed=SPEED, duration=0.03, step=1e-4, initial="rest", rtol=1e-6)
    ad = simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False)
    fine = simulate_general(system, Run(speed=SPEED, duration=0.03, step=1e-7, save_every=1000,
                            initial="rest"), stations, unb, gravity=GRAVITY, progress=False)  # fmt: skip
    on_a = ad.events[ad.events[:, 1] > 0, 0]
    on_f = fine.events[fine.events[:, 1] > 0, 0]
    assert len(on_a) == len(on_f) > 0
    print("onset differences (s)", np.abs(on_a - on_f).max())
    assert np.abs(on_a - on_f).max() < 0.01 * 1e-4  # 1 % of the output spacing


def test_seed_case1_high_friction_fixed_step_goes_on_into_backward_whirl():
    """Seed case 1 with friction 0.3 at d(tau) = 0.001: the old fixed-step run stops partial at
    41 ms (Newton failed); the new one sub-steps (full Newton Jacobian including the friction
    sign) and runs on into backward whirl: the full spectrum of v + i w at the contact peaks at
    a negative frequency, the same one the adaptive run finds."""
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate_system
    from rubrotor.scenario import load_scenario

    sc = load_scenario(Path(__file__).parents[1] / "src/rubrotor/scenarios/seed_case1.toml")
    con = dataclasses.replace(sc.contact, friction=0.3)
    old = simulate_system(sc.shaft, sc.speed, Integrator(duration=0.08, dtau=1e-3, save_every=32),
                          sc.unbalance, con, None, sc.damping, progress=False)  # fmt: skip
    system = continuous_system(sc.shaft)
    stn = [RubStation(dataclasses.replace(con, radius=sc.shaft.diameter / 2))]
    fixed = Run(speed=sc.speed, duration=0.08, step=1e-3 / sc.speed, save_every=32)
    H = Integrator(revolutions=1).output_spacing(sc.speed)
    adaptive = Run(speed=sc.speed, duration=0.08, step=H, rtol=1e-6)
    peaks = []
    for run in (fixed, adaptive):
        r = simulate_general(system, run, stn, [sc.unbalance], progress=False)
        assert r.status == "complete", r.message
        late = r.time > 0.05
        p = (r.channels[0] + 1j * r.channels[1])[late]
        spec = np.abs(np.fft.fft(p * np.hanning(p.size)))
        f = np.fft.fftfreq(p.size, r.time[1] - r.time[0])
        peaks.append(f[np.argmax(spec)])
    print("old:", old.status, old.message, "whirl peaks (Hz)", peaks, "spin", sc.speed / 2 / np.pi)
    assert old.status == "partial"
    assert peaks[0] < 0 and peaks[1] < 0
    assert abs(peaks[0] - peaks[1]) <= 2 / 0.03  # within two frequency bins
