"""Muszynska's fluid-ring force term (``[[bearing]] type = "muszynska"``).

References, each independent of the code under test:
- the closed forms derived in :mod:`rubrotor.forces.muszynska` (Jeffcott rotor in a fluid ring:
  eigenvalue from the quadratic ``M s^2 + (D + D_f) s + K + K_f - i lambda Omega D_f = 0``,
  threshold ``Omega_th = (1 + D / D_f) sqrt((K + K_f) / M) / lambda``);
- the force written out component by component from the fixed-frame form (the rotating-frame
  spring-damper transformed by hand), against the support coefficients the linear system uses;
- a rotor made a Jeffcott rotor: a nearly rigid steel shaft (E = 2e13 Pa: bending stiffness
  5.8e11 N/m against 1.2e6 N/m of supports) with one disk at midspan between two equal bearings,
  symmetric so that its translation (mass: disk plus shaft) does not couple to its tilt; the
  closed form then holds to ~K/K_shaft = 2e-6 relative with one disk at midspan between two equal bearings, the seal at
  the disk. The time run (exponential engine) and the linear eigen-analysis must both agree
  with the closed form.
"""

import math

import numpy as np
import pytest

import rubrotor
from rubrotor.errors import InputError, ScenarioError
from rubrotor.forces.muszynska import (
    MuszynskaSeal,
    jeffcott_eigenvalue,
    muszynska_force,
    whirl_threshold,
)
from rubrotor.forces.supports import support_term

MD, KB, CB = 20.0, 5e5, 50.0  # disk mass (kg); stiffness (N/m) and damping (N s/m) per bearing
M = MD + 7810.0 * math.pi * 0.1**2 / 4 * 0.2  # the translating mass: disk and rigid shaft (kg)
SEAL = MuszynskaSeal(position=0.1, fluid_stiffness=2e5, fluid_damping=400.0, swirl_ratio=0.5)
K, D = 2 * KB, 2 * CB

TOML = """
[meta]
name = "jeffcott_seal"
[speed]
rad_per_s = {speed!r}
[materials.rigid]
youngs_modulus = 2e13
poisson_ratio = 0.3
density = 7810.0
[[section]]
length = 0.2
diameter = 0.1
material = "rigid"
elements = 2
[[disk]]
position = 0.1
mass = {MD!r}
polar_inertia = 0.1
diametral_inertia = 0.05
[[bearing]]
position = 0.0
kyy = {KB!r}
kzz = {KB!r}
cyy = {CB!r}
czz = {CB!r}
[[bearing]]
position = 0.2
kyy = {KB!r}
kzz = {KB!r}
cyy = {CB!r}
czz = {CB!r}
[[bearing]]
position = 0.1
type = "muszynska"
fluid_stiffness = 2e5
fluid_damping = 400.0
swirl_ratio = 0.5
{extra}
"""


def _scenario(tmp_path, speed, extra=""):
    path = tmp_path / "jeffcott_seal.toml"
    path.write_text(TOML.format(speed=float(speed), MD=MD, KB=KB, CB=CB, extra=extra))
    return rubrotor.load_scenario(path)


def test_force_kernel_is_the_fixed_frame_form_and_the_support_coefficients():
    """The kernel equals the rotating-frame spring-damper seen from the fixed frame, and
    ``-(K q + C q')`` of the coefficients the linear system assembles (two routes)."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        v, w, vd, wd = rng.normal(size=4) * [1e-4, 1e-4, 1e-2, 1e-2]
        om = rng.uniform(0, 2000)
        fy, fz, jac = muszynska_force(v, w, vd, wd, om, SEAL.params)
        # rotating frame at lambda Omega: F_r = -K_f z_r - D_f z_r'; back to the fixed frame
        t = rng.uniform(0, 1)
        rot = np.exp(-1j * SEAL.swirl_ratio * om * t)
        z, zd = complex(v, w), complex(vd, wd)
        zr, zrd = z * rot, (zd - 1j * SEAL.swirl_ratio * om * z) * rot
        f = (-SEAL.fluid_stiffness * zr - SEAL.fluid_damping * zrd) / rot
        assert abs(complex(fy, fz) - f) <= 1e-12 * abs(f)
        sup = SEAL.support(0, "seal")
        k, c = sup.coefficients(om)
        ref = -(k @ [v, w] + c @ [vd, wd])
        np.testing.assert_allclose([fy, fz], ref, rtol=1e-12, atol=1e-12 * abs(f))
        np.testing.assert_allclose(jac, -np.hstack([k, c]), rtol=1e-12, atol=1e-9)


def test_threshold_closed_form_is_the_root_crossing():
    """At ``Omega_th`` the forward root of the quadratic is ``i sqrt((K + K_f)/M)``."""
    om = whirl_threshold(M, K, D, SEAL)
    s = jeffcott_eigenvalue(M, K, D, SEAL, om)
    wn = math.sqrt((K + SEAL.fluid_stiffness) / M)
    assert abs(s.real) <= 1e-12 * wn
    assert s.imag == pytest.approx(wn, rel=1e-12)
    assert jeffcott_eigenvalue(M, K, D, SEAL, 0.99 * om).real < 0
    assert jeffcott_eigenvalue(M, K, D, SEAL, 1.01 * om).real > 0
    no_swirl = MuszynskaSeal(0.0, 2e5, 400.0, 0.0)
    assert whirl_threshold(M, K, D, no_swirl) == math.inf


def test_linear_eigen_analysis_matches_closed_form(tmp_path):
    from rubrotor.linear.modes import damped_modes
    from rubrotor.linear.stability import stability_threshold

    om_th = whirl_threshold(M, K, D, SEAL)
    sc = _scenario(tmp_path, om_th)
    system = sc.rotor.linear_system(sc.stations)
    for speed in (0.5 * om_th, om_th, 1.3 * om_th):
        s_ref = jeffcott_eigenvalue(M, K, D, SEAL, speed)
        lams = [m.eigenvalue for m in damped_modes(system, speed).modes]
        s = min(lams, key=lambda x: abs(x - s_ref))
        assert abs(s - s_ref) <= 1e-5 * abs(s_ref), (speed, s, s_ref)
    found = stability_threshold(system, 2 * om_th, points=40)
    assert found == pytest.approx(om_th, rel=1e-5)


@pytest.mark.parametrize("ratio", [0.97, 1.03])
def test_time_run_growth_rate_is_the_closed_form_eigenvalue(tmp_path, ratio):
    """Started on the forward whirl mode, the orbit radius grows (above ``Omega_th``) or
    decays (below) at exactly ``Re(s)`` of the closed form; its whirl frequency is ``Im(s)``."""
    om_th = whirl_threshold(M, K, D, SEAL)
    speed = ratio * om_th
    s = jeffcott_eigenvalue(M, K, D, SEAL, speed)
    a = 1e-6
    extra = (f"[initial]\nstate = \"given\"\npositions = [0.1]\nv = [{a!r}]\nw = [0.0]\n"
             f"v_dot = [{(s * a).real!r}]\nw_dot = [{(s * a).imag!r}]\n"
             "[simulation]\nduration = 0.1\ndt = 2e-5\nsample_rate = 10000\nprobes = [0.1]\n")  # fmt: skip
    ds = rubrotor.simulate(_scenario(tmp_path, speed, extra))
    assert ds.attrs["status"] == "complete"
    t = ds["time"].values
    z = ds["v"].values[0] + 1j * ds["w"].values[0]
    late = t > 0.02
    rate = np.polyfit(t[late], np.log(np.abs(z[late])), 1)[0]
    assert np.sign(rate) == np.sign(ratio - 1)
    assert rate == pytest.approx(s.real, rel=1e-4, abs=1e-3)
    phase = np.unwrap(np.angle(z[late]))
    assert np.polyfit(t[late], phase, 1)[0] == pytest.approx(s.imag, rel=1e-6)


@pytest.mark.parametrize(
    ("row", "field"),
    [
        ({"fluid_damping": 0.0}, "bearing.fluid_damping"),
        ({"fluid_damping": -1.0}, "bearing.fluid_damping"),
        ({"fluid_stiffness": -5.0}, "bearing.fluid_stiffness"),
        ({"swirl_ratio": 1.0}, "bearing.swirl_ratio"),
        ({"swirl_ratio": "half"}, "bearing.swirl_ratio"),
        ({"kyy": 1e6}, "bearing.kyy"),
        ({"type": "journal"}, "bearing.type"),
    ],
)
def test_bad_values_are_refused_naming_the_key(row, field):
    base = {"position": 0.1, "type": "muszynska", "fluid_stiffness": 1e5, "fluid_damping": 10.0}
    with pytest.raises(InputError) as info:
        support_term({**base, **row})
    assert info.value.field == field


def test_scenario_refuses_out_of_range_key_by_name(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(TOML.format(speed=100.0, MD=MD, KB=KB, CB=CB, extra="").replace(
        "swirl_ratio = 0.5", "swirl_ratio = 1.5"))  # fmt: skip
    with pytest.raises(ScenarioError, match="swirl_ratio"):
        rubrotor.load_scenario(path)


def test_round_trip_through_rotor_tables(tmp_path):
    from rubrotor.scenario.rotor import build_rotor, rotor_to_dict

    sc = _scenario(tmp_path, 100.0)
    again = build_rotor(rotor_to_dict(sc.rotor))
    assert again.bearings[2] == SEAL
