"""The thermal bow on a general rotor (rubrotor.studies.thermal.ThermalModel).

References: (1) the closed form (rubrotor.studies.thermal.closed_form, itself tested against a
numerical route in test_thermal_closed_form.py) evaluated with the rotor's receptances at the
contact station computed here by a dense solve of the full finite-element model
(K - Omega^2 M + i Omega C)^-1 at the spin speed: no modal reduction, no time stepping, no
shooting; the model gets its steady orbits by shooting on the engine's reduced exponential map;
(2) the model's own linearised growth rate: the slow-time simulation (solve_ivp) started next to
the steady bow must grow by exp(sigma t) over whole spiral periods.
"""

import math

import numpy as np
import pytest

from rubrotor.rotors.forces import ThermalBow
from rubrotor.scenario.load import scenario_from_dict
from rubrotor.studies.thermal import ThermalModel, arc_shape, closed_form, slow_run

GAP, KC, MU, R, UNB = 20e-6, 1e5, 0.2, 0.05, 5e-4
TH = ThermalBow(time_constant=120.0, bow_per_heat=2e-6, hot_spot_lag=0.3)


def _jeffcott_like(speed: float) -> dict:
    """A light shaft (2 x 2 Euler-Bernoulli-like elements) with a 10 kg disk at midspan on
    stiff isotropic damped bearings, its seal at the disk: first critical near 300 rad/s."""
    sec = {"length": 0.3, "diameter": 0.025, "material": "steel", "elements": 2}
    brg = {"kyy": 1e8, "kzz": 1e8, "cyy": 300.0, "czz": 300.0}
    return {
        "materials": {"steel": {"youngs_modulus": 2.1e11, "density": 7800.0,
                                "poisson_ratio": 0.3}},
        "section": [sec, sec],
        "disk": [{"position": 0.3, "mass": 10.0, "polar_inertia": 0.02,
                  "diametral_inertia": 0.01}],
        "bearing": [{"position": 0.0, **brg}, {"position": 0.6, **brg}],
        "rotor": {"gyroscopic": False},
        "speed": {"rad_per_s": speed},
        "unbalance": [{"position": 0.3, "magnitude": UNB}],
        "contact": [{"position": 0.3, "radius": R, "clearance": GAP, "law": "linear",
                     "stiffness": KC, "friction": MU}],
        "simulation": {"revolutions": 1, "probes": [0.15]},
    }  # fmt: skip


def _reference(model: ThermalModel, speed: float):
    system = model.map.system
    sm = system.matrices(speed)
    dyn = sm.K - speed**2 * sm.M + 1j * speed * sm.damping
    rows = system.output_rows(0.3)

    def forward(f):  # forward 1X of v + i w at the station
        q = np.linalg.solve(dyn, f)
        return (rows[0] @ q + 1j * (rows[1] @ q)) / 2

    b = system.force_map(0.3) @ np.array([1, -1j])
    ks = system.K[np.ix_(system.free, system.free)]
    hb = forward(ks @ arc_shape(system, (0.0, 0.6), 0.3))
    return closed_form(forward(b), hb, forward(UNB * speed**2 * b), speed=speed, clearance=GAP,
                       contact_stiffness=KC, friction=MU, radius=R, thermal=TH)  # fmt: skip


@pytest.mark.parametrize("speed", [240.0, 360.0])
def test_model_matches_the_closed_form(speed):
    """Growth rate, spiral frequency and steady bow match the receptance closed form to 1e-6
    of |lambda| (4096 steps per revolution: the map's error (Omega h)^2/12 is 2e-7)."""
    model = ThermalModel(scenario_from_dict(_jeffcott_like(speed)), TH, steps=4096)
    lin = model.steady()
    ref = _reference(model, speed)
    scale = abs(ref.eigenvalues[0])
    assert abs(lin.growth_rate - ref.growth_rate) < 1e-6 * scale
    assert abs(lin.spiral_frequency - ref.spiral_frequency) < 1e-6 * scale
    assert abs(lin.bow[0] - ref.bow[0]) < 1e-6 * abs(ref.bow[0])
    assert abs(abs(lin.high_spot[0]) - GAP) > 0.1 * GAP  # in contact all round


def test_arc_bow_is_pure_end_moments_on_a_uniform_shaft():
    """A uniform curvature loads a uniform free shaft only by two opposite end moments
    (beam theory): K_s Phi has no translational force and equal and opposite end moments."""
    model = ThermalModel(scenario_from_dict(_jeffcott_like(200.0)), TH)
    system = model.map.system
    f = system.K[np.ix_(system.free, system.free)] @ arc_shape(system, (0.0, 0.6), 0.3)
    full = system.expand(f)
    moments = full[2::4]
    assert np.max(np.abs(full[0::4])) < 1e-9 * np.max(np.abs(moments))
    assert np.max(np.abs(moments[1:-1])) < 1e-9 * abs(moments[0])
    assert abs(moments[0] + moments[-1]) < 1e-9 * abs(moments[0])


def test_slow_run_grows_at_the_linearised_rate():
    """Started 1e-4 off the steady bow, |b - b*| grows by exp(sigma t) over two whole spiral
    periods to 1e-3 (the model's own linearisation; the orbit map the same)."""
    speed = 240.0
    model = ThermalModel(scenario_from_dict(_jeffcott_like(speed)), TH, steps=512)
    lin = model.steady()
    assert lin.growth_rate > 0 and math.isfinite(lin.spiral_period)
    b0 = lin.bow * (1 + 1e-4)
    t_end = 2 * lin.spiral_period
    ds = slow_run(model, t_end, bow=b0, samples=3, rtol=1e-10)
    dev = np.hypot(ds.bow_real.values[:, 0] - lin.bow[0].real,
                   ds.bow_imag.values[:, 0] - lin.bow[0].imag)  # fmt: skip
    sigma = math.log(dev[-1] / dev[0]) / t_end
    assert abs(sigma - lin.growth_rate) < 1e-3 * abs(lin.growth_rate)
    assert ds.attrs["status"] == "complete"


def test_unstable_bow_settles_into_a_limit_cycle():
    """The shipped rotor with a stiff seal and a trailing hot spot: the steady bow is unstable
    (growth > 0, a spiral) while the large-orbit limit (heat proportional to the vibration
    vector, the closed form's s = 1 with the model's own receptances) is damped; the slow run
    from a straight rotor stays bounded near the steady bow over 10 spiral periods and loses
    the rub on part of its cycle (zero heat): a limit cycle, not a runaway."""
    from importlib import resources

    from rubrotor.scenario.load import load_scenario, scenario_to_dict

    spec = scenario_to_dict(load_scenario(resources.files("rubrotor") / "scenarios" /
                                          "thermal_rub.toml"))  # fmt: skip
    spec["contact"][0]["stiffness"] = 2e6
    spec["thermal"].update(hot_spot_lag=1.4, bow_per_heat=1e-6)
    model = ThermalModel(scenario_from_dict(spec), steps=256)
    lin = model.steady()
    assert lin.growth_rate > 0 and math.isfinite(lin.spiral_period)
    th = model.thermal
    gain = th.bow_per_heat * 0.3 * 0.07 * model.speed * 2e6
    system = model.map.system  # forward receptances by a dense solve of the full model
    sm = system.matrices(model.speed)
    dyn = sm.K - model.speed**2 * sm.M + 1j * model.speed * sm.damping
    rows = system.output_rows(0.6)

    def fwd(f):
        q = np.linalg.solve(dyn, f)
        return (rows[0] @ q + 1j * (rows[1] @ q)) / 2

    ks = system.K[np.ix_(system.free, system.free)]
    hb = fwd(ks @ arc_shape(system, (0.05, 1.15), 0.6))
    hc = fwd(system.force_map(0.6) @ np.array([1, -1j]))
    lam_large = -1 + gain * np.exp(-1j * th.hot_spot_lag) * hb / (1 + 2e6 * (1 + 0.3j) * hc)
    assert lam_large.real < 0
    ds = slow_run(model, 10 * lin.spiral_period, samples=40, rtol=1e-6)
    assert ds.attrs["status"] == "complete"
    b = ds.bow_real.values[:, 0] + 1j * ds.bow_imag.values[:, 0]
    late = np.abs(b[20:] - lin.bow[0])
    assert late.max() < 0.6 * abs(lin.bow[0])  # bounded, not running away
    assert late.min() > 1e-3 * abs(lin.bow[0])  # and not settled on the unstable steady bow
    heat = np.hypot(ds.heat_real.values[20:, 0], ds.heat_imag.values[20:, 0])
    assert heat.min() == 0.0 and heat.max() > 0.0  # the rub is lost over part of the cycle


def test_a_seal_that_never_touches_adds_only_its_relaxation():
    """Two seals, the second with a clearance the orbit never reaches: its bow sees no heat, so
    the slow dynamics are the one-seal model's plus the pure relaxation -1/tau (twice), and the
    first seal's steady bow and growth rate are unchanged (equivalence to 1e-8)."""
    speed = 240.0
    one = ThermalModel(scenario_from_dict(_jeffcott_like(speed)), TH, steps=512).steady()
    spec = _jeffcott_like(speed)
    far = {**spec["contact"][0], "position": 0.45, "clearance": 5e-3}
    spec["contact"] = [spec["contact"][0], far]
    two = ThermalModel(scenario_from_dict(spec), TH, steps=512).steady()
    assert two.bow.shape == (2,) and two.heat[1] == 0
    assert abs(two.bow[1]) < 1e-12 * abs(two.bow[0])
    assert abs(two.bow[0] - one.bow[0]) < 1e-8 * abs(one.bow[0])
    assert abs(two.growth_rate - one.growth_rate) < 1e-8 * abs(one.eigenvalues[0])
    relax = np.sort_complex(two.eigenvalues)[:2]
    assert np.allclose(relax, -1 / TH.time_constant, rtol=1e-8)
