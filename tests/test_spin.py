"""The spin speed as a state (``[speed] profile = "free"``, :mod:`rubrotor.engine.spin`).

References: the angular-momentum and energy balances of the rotor (derived in each test's
docstring, the integrals taken by Simpson's rule over the saved samples, a route independent of
the integrator's states); the closed-form spin-up under constant torque and linear drag; the
general engine's constant-speed run (its exponential integrator, an independent code) for a
rotor whose inertia is so large that its speed stays constant.
"""

import dataclasses
import math
import sys
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import simpson

import rubrotor
from rubrotor.engine.simulate import simulate
from rubrotor.engine.spin import FreeSpin, TouchdownRing, polar_inertia, simulate_spin, spin_dataset
from rubrotor.errors import ScenarioError

ROTOR = """
[meta]
name = "free_coast"
[materials.steel]
youngs_modulus = 2.1e11
density = 7800
poisson_ratio = 0.3
[[section]]
length = 0.5
diameter = 0.04
material = "steel"
elements = 4
[[disk]]
position = 0.25
mass = 5.0
polar_inertia = 0.02
diametral_inertia = 0.01
[[bearing]]
position = 0.0
kyy = 1e6
kzz = 1e6
cyy = 200
czz = 200
[[bearing]]
position = 0.5
kyy = 1e6
kzz = 1e6
cyy = 200
czz = 200
[contact]
position = 0.25
clearance = 2e-5
stiffness = 2e7
law = "linear"
friction = 0.1
radius = 0.1
[simulation]
duration = 0.05
sample_rate = 20000
rtol = 1e-8
atol = 1e-12
"""

FREE = '[speed]\nprofile = "free"\nrad_per_s = 100.0\n[gravity]\ny = 9.81\n'


def _load(tmp_path, text):
    p = tmp_path / "s.toml"
    p.write_text(text)
    return rubrotor.load_scenario(p)


def _pieces(s):
    system = s.rotor.linear_system(s.engine.positions)
    return system, s.engine.stations, polar_inertia(s.rotor)


def test_free_coast_angular_momentum(tmp_path):
    """A coast with rub, no drive and no drag: ``J dOmega/dt = -sum mu N R``, so
    ``J (Omega_0 - Omega_end) = integral of the friction torque dt``. The rotor sags under
    gravity onto the stator (sag 50 um > clearance 20 um) and rubs throughout; the torque
    samples (``friction_torque``, from the contact law's forces) are integrated by Simpson's rule.
    Measured: 1.9e-6 relative at 20 kHz sampling; required 1e-3."""
    ds = simulate(_load(tmp_path, ROTOR + FREE))
    assert ds.attrs["status"] == "complete"
    om = ds.spin_speed.values
    J = ds.attrs["polar_inertia_kg_m2"]
    lost = J * (om[0] - om[-1])
    torque = ds.friction_torque.sum("contact").values
    assert om[0] - om[-1] > 1e-2 * om[0] / 2  # a real loss: > 0.5 % of the speed
    assert ds.normal_force.values[0, -1] > 10.0  # still pressed at the end (N)
    assert lost == pytest.approx(simpson(torque, x=ds.time.values), rel=1e-3)


def test_polar_inertia_is_the_rotor_sum(tmp_path):
    """``J`` = the disk's 0.02 kg m^2 plus the shaft's ``rho pi D^4 / 32 L`` (hand formula)."""
    s = _load(tmp_path, ROTOR + FREE)
    shaft = 7800 * math.pi * 0.04**4 / 32 * 0.5
    assert polar_inertia(s.rotor) == pytest.approx(0.02 + shaft, rel=1e-12)


@pytest.mark.parametrize("ring", [None, TouchdownRing(2e-3, 0.10002, 1e-4)])
def test_free_coast_energy_balance(tmp_path, ring):
    """Energy: ``E = J Omega^2 / 2 + J_r omega_r^2 / 2 + eta'^T eta' / 2 + eta^T K eta / 2
    - f0^T eta + k pen^2 / 2`` (spin, ring, lateral kinetic in mass-normalised coordinates,
    elastic, gravity, linear contact spring) decreases by the damping work
    ``integral eta'^T C eta'``, the friction work ``integral -ft v_s`` (``v_s`` the sliding speed
    on the ring, if any) and the ring drag's ``integral d omega_r^2`` (the gyroscopic force does
    no work). The integrals by Simpson's rule on the saved samples. Measured: 1.9e-6 relative
    (fixed stator) and 4.1e-6 (ring) at rtol 1e-9: the quadrature's error."""
    s = _load(tmp_path, ROTOR + FREE)
    system, st, J = _pieces(s)
    c = st[0].contact
    res = simulate_spin(system, J=J, speed=100.0, duration=0.05, spacing=2e-5, stations=st,
                        gravity=(9.81, 0.0), rings=(ring,), rtol=1e-9, atol=1e-13)  # fmt: skip
    r, x, red, t = res.r, res.state, res.reduced, res.time
    eta, etd = x[:r], x[r : 2 * r]
    p = red["Pc"] @ eta
    pen = np.maximum(np.hypot(p[0], p[1]) - c.clearance, 0.0)
    E = (0.5 * J * res.spin_speed**2 + 0.5 * (etd**2).sum(0)
         + 0.5 * np.einsum("in,ij,jn->n", eta, red["K"], eta) - red["f0"] @ eta
         + 0.5 * c.stiffness * pen**2)  # fmt: skip
    power = np.einsum("in,ij,jn->n", etd, red["C"], etd) - res.contact[0, 1] * res.contact[0, 2]
    if ring is not None:
        wr = res.ring_speed[0]
        E = E + 0.5 * ring.inertia * wr**2
        power = power + ring.drag * wr**2
        assert wr[-1] > 1.0  # rad/s: the ring took energy
    lost = E[0] - E[-1]
    assert lost > 1.0  # J is, N m: the spin lost about 3 J
    assert lost == pytest.approx(simpson(power, x=t), rel=1e-4)


def test_constant_torque_and_drag_closed_form(tmp_path):
    """No contact: ``J Omega' = T - d Omega`` gives
    ``Omega = T/d + (Omega_0 - T/d) exp(-d t / J)`` (closed form); a torque table constant at
    the same value gives the same."""
    s = _load(tmp_path, ROTOR + FREE)
    system, _, J = _pieces(s)
    T, d = 2.0, 1e-3
    for free in (FreeSpin(T, None, d), FreeSpin((T, T), (0.0, 1e4), d)):
        res = simulate_spin(system, J=J, speed=100.0, duration=0.5, spacing=1e-3, free=free,
                            rtol=1e-10)  # fmt: skip
        exact = T / d + (100.0 - T / d) * np.exp(-d * res.time / J)
        assert res.spin_speed[-1] - 100.0 > 40.0
        np.testing.assert_allclose(res.spin_speed, exact, rtol=1e-8)


def test_huge_inertia_matches_constant_speed_engine(tmp_path):
    """With ``J = 1e9 kg m^2`` the speed stays at 100 rad/s, so the free run must reproduce the
    general engine's constant-speed run (exponential integrator, independent code) of the same
    rotor with unbalance and rub: orbits to 1e-4 of their amplitude (measured 3e-6)."""
    unb = "[unbalance]\nmagnitude = 5e-3\nposition = 0.25\nphase_deg = 30\n[speed]\nrad_per_s = 100.0\n"
    s = _load(tmp_path, ROTOR + unb)
    ref = simulate(s)
    system, st, _ = _pieces(s)
    res = simulate_spin(system, J=1e9, speed=100.0, duration=0.05, spacing=5e-5, stations=st,
                        unbalances=s.engine.unbalances, rtol=1e-8, atol=1e-12)  # fmt: skip
    ds = spin_dataset(res, system, (0.25,))
    assert ref.normal_force.values.max() > 100.0  # it rubs (N)
    amp = np.abs(ref.v.values).max()
    for k in ("v", "w"):
        np.testing.assert_allclose(ds[k].values, ref[k].values, atol=1e-4 * amp, rtol=0)


def test_ring_takes_what_the_rotor_loses(tmp_path):
    """A touchdown ring as the stator (friction on ``R Omega - r omega_ring``), no drags: the
    rotor's torque is ``R ft``, the ring's ``-r ft``, so the same friction impulse
    ``-integral ft dt`` gives ``J (Omega_0 - Omega) / R = J_ring omega_ring / r`` (measured
    equal to 6e-13 relative) and equals the integral of the saved friction samples (Simpson)."""
    s = _load(tmp_path, ROTOR + FREE)
    system, st, J = _pieces(s)
    ring = TouchdownRing(inertia=2e-3, radius=0.1 + 2e-5)
    res = simulate_spin(system, J=J, speed=100.0, duration=0.05, spacing=5e-5, stations=st,
                        rings=(ring,), gravity=(9.81, 0.0), rtol=1e-9, atol=1e-13)  # fmt: skip
    rotor = J * (res.spin_speed[0] - res.spin_speed[-1]) / 0.1
    gained = ring.inertia * res.ring_speed[0, -1] / ring.radius
    assert gained > 0.1  # N s of tangential impulse (about 0.3)
    assert gained == pytest.approx(rotor, rel=1e-9)
    impulse = simpson(-res.contact[0, 1], x=res.time)
    assert gained == pytest.approx(impulse, rel=1e-3)


@pytest.mark.parametrize(
    ("speed", "key"),
    [
        ('profile = "free"\nrad_per_s = 100.0\nfrom = 1.0\n', "speed.from"),
        ("rad_per_s = 100.0\ndrag = 1.0\n", "speed.drag"),
        (
            'profile = "free"\nrad_per_s = 100.0\ndrive_torques = [1.0, 2.0]\n',
            "speed.drive_torques / speed.drive_speeds",
        ),
        (
            'profile = "free"\nrad_per_s = 100.0\ndrive_torques = [1.0, 2.0]\n'
            "drive_speeds = [5.0, 1.0]\n",
            "speed.drive_speeds",
        ),
    ],
)
def test_bad_free_speed_keys(tmp_path, speed, key):
    """Bad ``[speed]`` keys of a free profile are refused naming the key."""
    with pytest.raises(ScenarioError) as err:
        _load(tmp_path, ROTOR + "[speed]\n" + speed)
    assert err.value.field == key


DROP = resources.files("rubrotor") / "scenarios" / "touchdown_drop.toml"


def _drop(duration=0.08):
    s = rubrotor.load_scenario(DROP)
    return simulate(s, integrator=dataclasses.replace(s.simulation, duration=duration))


def test_touchdown_drop_rotor_and_rings_balance():
    """The shipped drop: both magnetic bearings fail at 0.02 s, the rotor falls onto two
    touchdown rings (drag ``d``). Per ring ``J_r omega_r = r int(-ft) dt - d int omega_r dt``
    and for the rotor ``J (Omega_0 - Omega) = sum R int(-ft) dt``, so
    ``J (Omega_0 - Omega) = sum (R / r) (J_r omega_r + d int omega_r dt)`` (the ring-speed
    integral by Simpson's rule, a smooth signal). Also: no contact before the failure, contact
    after it. Measured: 7e-11 relative."""
    ds = _drop()
    t = ds.time.values
    assert ds.attrs["status"] == "complete"
    assert ds.normal_force.values[:, t < 0.02].max() == 0.0
    assert ds.normal_force.values[:, t > 0.03].max(axis=1).min() > 100.0  # N, both rings hit
    J = ds.attrs["polar_inertia_kg_m2"]
    lost = J * (ds.spin_speed.values[0] - ds.spin_speed.values[-1])
    R, r, Jr, d = 0.03, 0.03025, 2e-4, 1e-5
    wr = ds.ring_speed.values
    given = sum(R / r * (Jr * wr[i, -1] + d * simpson(wr[i], x=t)) for i in range(2))
    assert wr[:, -1].min() > 100.0  # rad/s: the rings spun up
    assert lost == pytest.approx(given, rel=1e-4)


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (('profile = "free"\n', ""), "bearing.fail_time"),
        (("ring_drag = 1.0e-5        # N m s\n", "ring_drag = -1.0\n"), "contact[1].ring_drag"),
        (("fail_time = 0.02\n", "fail_time = 0.03\n"), "bearing.fail_time"),
    ],
)
def test_bad_touchdown_keys(tmp_path, edit, key):
    """Failing bearings and rings without a free spin speed, a negative ring drag and two
    different failure times are refused naming the key."""
    text = DROP.read_text().replace("drag = 0.0\n", "").replace(*edit, 1)
    with pytest.raises(ScenarioError) as err:
        _load(tmp_path, text)
    assert err.value.field == key


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_whirl_frequency_of_a_circle(sense):
    """A circular orbit ``(a cos wt, a sin(sense w t))`` whirls at ``sense w`` (closed form)."""
    from rubrotor.plotting.touchdown import whirl_frequency

    t = np.linspace(0.0, 0.1, 2001)
    wf = whirl_frequency(t, 1e-4 * np.cos(300 * t), 1e-4 * np.sin(sense * 300 * t), 2e-3)
    np.testing.assert_allclose(wf, sense * 300.0, rtol=1e-9)


def test_cli_simulates_the_drop_with_its_figure(tmp_path, capsys):
    """``rubrotor simulate touchdown_drop.toml --figure`` writes the results (with the spin and
    ring speeds) and the touchdown figure; the summary says complete."""
    import json

    import xarray as xr

    from rubrotor.cli import main

    out = tmp_path / "drop.nc"
    assert main(["simulate", str(DROP), "--out", str(out), "--figure"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["status"] == "complete" and summary["contact_events"] > 0
    assert (tmp_path / "drop.png").stat().st_size > 10_000
    with xr.open_dataset(out) as ds:
        assert ds.spin_speed.attrs["units"] == "rad/s"
        assert ds.ring_speed.values[:, -1].min() > 100.0


def test_drop_against_full_dof_scipy_reference():
    """A small rotor (4 elements, a 5 kg disk) with unbalance at 300 rad/s, both bearings failing
    at 4 ms, falling under gravity onto a touchdown ring at the disk: orbit, spin speed and ring
    speed against the full-DOF SciPy DOP853 run of ``tests/spin_reference.py`` (physical
    coordinates, no modal basis, rtol 1e-10). Measured: orbit 1.3e-10 of its amplitude, spin
    speed 4e-11 rad/s (of a 0.74 rad/s loss), ring speed 4e-10 rad/s (of 7.7 rad/s)."""
    sys.path.insert(0, str(Path(__file__).parent))
    from spin_reference import free_spin_reference

    from rubrotor.engine.parts import RubStation
    from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section
    from rubrotor.rotors.forces import Contact, Unbalance

    steel = Material("steel", 2.1e11, 7800.0, poisson_ratio=0.3)
    brg = dict(kyy=1e6, kzz=1e6, cyy=200, czz=200)
    rot = Rotor([Section(0.5, 0.04, steel, elements=4)], disks=[Disk(0.25, 5.0, 0.02, 0.01)],
                bearings=[Bearing(0.0, **brg), Bearing(0.5, **brg)])  # fmt: skip
    system = rot.linear_system((0.25,))
    c = Contact(clearance=2e-5, stiffness=2e7, friction=0.1, position=0.25, law="linear",
                radius=0.1)  # fmt: skip
    kw = dict(stations=(RubStation(c),), rings=(TouchdownRing(2e-3, 0.10002, 1e-4),),
              unbalances=(Unbalance(1e-3, 0.25, 0.3),), gravity=(-9.81, 0.0), fail_time=0.004,
              failing=(0, 1))  # fmt: skip
    J = polar_inertia(rot)
    res = simulate_spin(system, J=J, speed=300.0, duration=0.012, spacing=2e-5, rtol=1e-10,
                        atol=1e-14, **kw)  # fmt: skip
    q, om, _, wr = free_spin_reference(system, J, 300.0, res.time, **kw)
    rows = system.output_rows(0.25)
    ref, ours = rows @ q, rows @ (res.basis @ res.state[: res.r])
    assert res.contact[0, 0].max() > 100.0 and wr.max() > 5.0  # it drops and rubs (N, rad/s)
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-7 * np.abs(ref).max())
    np.testing.assert_allclose(res.spin_speed, om, rtol=0, atol=1e-7 * (om[0] - om[-1]))
    np.testing.assert_allclose(res.ring_speed, wr, rtol=0, atol=1e-7 * wr.max())


def _jeffcott_roll(x0):
    """The dry-whirl study's Jeffcott rotor (10 kg, 1e6 N/m, 5 % damping) on a stiff rigid
    catcher (1e8 N/m, g = 0.1 mm, R = 10 mm, mu = 0.5), free spin from 6 rad/s, J = 0.1 kg m^2."""
    from rubrotor.engine.parts import RubStation
    from rubrotor.rotors.forces import Contact
    from rubrotor.studies.dry_whirl import Jeffcott

    rotor = Jeffcott(10.0, 1e6, 316.0)
    c = Contact(clearance=1e-4, stiffness=1e8, law="linear", radius=0.01, position=0.5,
                friction=0.5, friction_regularization=1e-5)  # fmt: skip
    res = simulate_spin(rotor.system(), J=0.1, speed=6.0, duration=0.2, spacing=2e-5,
                        stations=(RubStation(c),), initial=x0, rtol=1e-9, atol=1e-13)  # fmt: skip
    return rotor, c, res


def test_backward_whirl_follows_the_rolling_law_and_spins_down():
    """Dry whirl on a stiff catcher with high friction, the spin a state. References: the
    rolling law with contact compliance, ``omega = -Omega R / |D|`` with ``|D|`` from the
    impedance (:func:`rubrotor.studies.dry_whirl.rolling_whirls`, closed form), at the current
    speed; and the spin-down rate in rolling. Rolling ties the whirl to the spin
    (``omega' = -R Omega' / |D|``), so the rotor's tangential equation
    ``m |D| omega' = -c |D| omega + ft`` and ``J Omega' = R ft`` give
    ``Omega' = R c |D| omega / (J + m R^2)`` (the rolling rotor's mass adds ``m R^2``; the
    friction torque is ``R ft``). Kicked to 1.5 g, the rotor locks into backward rolling whirl:
    at 0.18 s its frequency is the rolling law's to 1.4e-4 (measured). Started on the rolling
    orbit: whirl frequency to 2.6e-5 (the regularised friction's slide), spin-down rate to 9e-4
    (measured) of the closed form."""
    from rubrotor.plotting.touchdown import whirl_frequency
    from rubrotor.studies.dry_whirl import DryWhirlCase, _rolling_state, rolling_whirls

    def check(res, k, tol_whirl, tol_rate):
        om, t = res.spin_speed, res.time
        q = res.basis @ res.state[: res.r]
        wf = whirl_frequency(t, q[0], q[1], 0.01)[k]
        roll = rolling_whirls(DryWhirlCase(rotor, c, float(om[k])))[-1]
        assert roll.frequency < -500.0  # backward, |omega| ~ Omega R / g = 600 rad/s
        assert wf == pytest.approx(roll.frequency, rel=tol_whirl)
        if tol_rate is not None:
            rate = c.radius * roll.gap * rotor.damping * roll.frequency / (0.1 + 10 * c.radius**2)
            assert np.gradient(om, t)[k] == pytest.approx(rate, rel=tol_rate)

    rotor, c, kicked = _jeffcott_roll(np.array([1.5e-4, 0.0, 0.0, 0.0]))
    check(kicked, 9000, 1e-3, None)
    _, _, rolling = _jeffcott_roll(_rolling_state(DryWhirlCase(rotor, c, 6.0)))
    for k in (1000, 5000, 9000):
        check(rolling, k, 2e-4, 3e-3)
    assert rolling.spin_speed[-1] < 0.95 * 6.0  # it spun down by more than 5 %


def test_constant_torque_runup_matches_the_engine_runup():
    """A constant drive torque ``T = 1000 J`` without contact or drag is the linear run-up
    100 -> 300 rad/s in 0.2 s, so the free run (gyroscopic term and bearings tabulated against
    speed, cross-coupled, following the current speed; unbalance with its ``Omega'`` term) must
    equal the general engine's run-up (independent code: re-diagonalised at segments of frozen
    speed, ``speed_step``) in the limit of small segments. Measured: the deviation falls from
    2.3e-4 (segments of 2 rad/s) to 5.3e-6 (0.5 rad/s) of the amplitude, faster than the square
    of the segment."""
    from rubrotor.engine.driver import simulate_general
    from rubrotor.engine.parts import Run
    from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section
    from rubrotor.rotors.forces import Unbalance

    steel = Material("steel", 2.1e11, 7800.0, poisson_ratio=0.3)
    tab = dict(speeds=(0.0, 200.0, 400.0), kyy=(1e6, 1.5e6, 2.5e6), kzz=(8e5, 1.2e6, 2e6),
               kyz=(0.0, 1e5, 3e5), kzy=(0.0, -1e5, -3e5), cyy=200.0, czz=200.0)  # fmt: skip
    rot = Rotor([Section(0.5, 0.04, steel, elements=4)], disks=[Disk(0.25, 5.0, 0.2, 0.1)],
                bearings=[Bearing(0.0, **tab), Bearing(0.5, **tab)])  # fmt: skip
    system = rot.linear_system((0.25,))
    J = polar_inertia(rot)
    unb = (Unbalance(1e-3, 0.25, 0.0),)
    res = simulate_spin(system, J=J, speed=100.0, duration=0.2, spacing=5e-5,
                        free=FreeSpin(1000.0 * J), unbalances=unb, rtol=1e-10, atol=1e-14)  # fmt: skip
    assert res.spin_speed[-1] == pytest.approx(300.0, rel=1e-12)
    ours = system.output_rows(0.25) @ (res.basis @ res.state[: res.r])
    dev = []
    for seg in (2.0, 0.5):
        run = Run(speed=100.0, duration=0.2, step=1e-5, save_every=5, speed_end=300.0,
                  speed_step=seg, runup_reduction="full", probes=(0.25,))  # fmt: skip
        ref = simulate_general(system, run, unbalances=unb).channels[0:2]
        dev.append(np.abs(ref - ours).max() / np.abs(ref).max())
    assert dev[1] < 2e-5
    assert dev[0] / dev[1] > 8.0  # converging on ours as the frozen-speed segments shrink


def test_maps_orbits_and_sweeps_refuse_a_free_speed():
    """The general engine's fixed-speed inputs (maps, orbits, sweeps) refuse a free spin speed
    naming ``speed.profile`` instead of silently holding the speed."""
    from rubrotor.engine.general import engine_problem

    with pytest.raises(ScenarioError) as err:
        engine_problem(rubrotor.load_scenario(DROP))
    assert err.value.field == "speed.profile"
