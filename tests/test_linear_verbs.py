"""The linear verbs a ROSS user expects (static analysis, frequency response, unbalance response
of every plane, undamped critical speed map, mode shapes, critical multiples of general rotors),
each against an independent reference named in its test."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest

import rubrotor
from rubrotor.errors import InputError, ScenarioError
from rubrotor.linear.response import (
    force_vector,
    frequency_response,
    scenario_unbalance_response,
    unbalance_response,
)
from rubrotor.linear.shapes import mode_shapes
from rubrotor.linear.static import STANDARD_GRAVITY, static_analysis
from rubrotor.linear.ucs import ucs_map
from rubrotor.linear.verbs import linear_system
from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section
from rubrotor.rotors.forces import RadialLoad
from rubrotor.rotors.linear import LinearSystem, NodalBasis, Support
from rubrotor.rotors.shaft import Shaft
from rubrotor.scenario.load import load_scenario, scenario_from_dict, scenario_to_dict

SCEN = Path(rubrotor.__file__).parent / "scenarios"
STEEL = Material("steel", 211e9, 7810, poisson_ratio=0.3)


def _uniform(theory: str, elements: int, kind: str = "pinned", k: float = 0.0) -> Rotor:
    """A 1 m, 50 mm steel shaft on two supports at its ends (pinned, or springs ``k`` N/m)."""
    ends = [Bearing(x, kind="pinned") if kind == "pinned" else Bearing(x, kyy=k, kzz=k)
            for x in (0.0, 1.0)]  # fmt: skip
    return Rotor([Section(1.0, 0.05, STEEL, elements=elements)], bearings=ends, theory=theory,
                 gyroscopic=False)  # fmt: skip


# ---- static ------------------------------------------------------------------------------------
def test_static_reactions_equal_the_weight_on_cross_coupled_bearings():
    """Reference: the weight from the geometry (Rotor.mass: section volumes and disk masses
    times g) and the balance of forces and moments of a rigid body. general_rotor.toml's
    bearings are cross-coupled (kyz, kzy != 0): the rotor deflects sideways, yet the bearing
    forces along y must carry the whole weight and those along z sum to zero."""
    sc = load_scenario(SCEN / "general_rotor.toml")
    res = static_analysis(sc)
    weight = sc.rotor.mass * STANDARD_GRAVITY
    fy = sum(b.force_y for b in res.bearings)
    fz = sum(b.force_z for b in res.bearings)
    assert fy == pytest.approx(weight, rel=1e-6)
    assert abs(fz) < 1e-9 * weight
    assert np.abs(res.deflection[:, 1]).max() > 1e-3 * np.abs(res.deflection[:, 0]).max()
    assert [b.name for b in res.bearings] == ["left bearing", "right bearing"]
    # [gravity] of the scenario (9.81, not the standard 9.80665) and a side load at 0.75 m
    seal = load_scenario(SCEN / "seal_rub.toml")
    load = RadialLoad(force_y=120.0, force_z=-80.0, position=0.75)
    res = static_analysis(seal, loads=[load])
    r = np.array([[b.force_y, b.force_z] for b in res.bearings])
    x = np.array([b.position for b in res.bearings])
    applied = np.array([-seal.rotor.mass * 9.81 + 120.0, -80.0])
    np.testing.assert_allclose(r.sum(axis=0), -applied, rtol=1e-6, atol=1e-9 * abs(applied[0]))
    # moments about x = 0: the weight acts at the centre of mass of the geometry
    xm = _centre_of_mass(seal.rotor)
    moment = x @ r + np.array([xm * -seal.rotor.mass * 9.81 + 0.75 * 120.0, 0.75 * -80.0])
    assert np.abs(moment).max() < 1e-6 * abs(applied[0])


def _centre_of_mass(rotor: Rotor) -> float:
    """Axial centre of mass (m) of sections and disks, from their geometry."""
    parts = [(d.mass, d.position) for d in rotor.disks]
    for s, a in zip(rotor.sections, rotor.boundaries[:-1], strict=True):
        m = s.material.density * math.pi * (s.diameter**2 - s.bore_diameter**2) / 4 * s.length
        parts.append((m, a + s.length / 2))
    return sum(m * x for m, x in parts) / sum(m for m, _ in parts)


@pytest.mark.parametrize("theory", ["euler-bernoulli", "timoshenko"])
def test_pinned_uniform_shaft_sag_closed_form(theory):
    """Reference: a simply supported uniform beam under its weight w = rho A g sags
    5 w L^4 / (384 E I) at midspan (Euler-Bernoulli), plus w L^2 / (8 kappa G A) of shear
    (Timoshenko, Cowper's kappa = 6 (1 + nu) / (7 + 6 nu) for a solid section). Hermite
    elements with the consistent load are nodally exact for this load, so the sag is exact on
    every mesh: measured relative errors 2e-16 (2 elements) ... 8e-12 (64 elements), growing
    only with the round-off of the stiffer mesh."""
    length, d, nu = 1.0, 0.05, 0.3
    area, inertia = math.pi * d**2 / 4, math.pi * d**4 / 64
    w = STEEL.density * area * STANDARD_GRAVITY
    sag = 5 * w * length**4 / (384 * STEEL.youngs_modulus * inertia)
    if theory == "timoshenko":
        kappa = 6 * (1 + nu) / (7 + 6 * nu)
        sag += w * length**2 / (8 * kappa * STEEL.G * area)
    for elements in (2, 8, 64):
        res = static_analysis(_uniform(theory, elements))
        mid = int(np.argmin(np.abs(res.x - length / 2)))
        assert res.x[mid] == pytest.approx(length / 2)
        assert -res.deflection[mid, 0] == pytest.approx(sag, rel=1e-9)
        assert res.deflection[mid, 1] == 0.0


def test_continuous_shaft_sag_converges_as_its_sine_series():
    """Reference: 5 w L^4 / (384 E I). The continuous shaft's static deflection is the sine
    series sum_n 4 w L^4 / (E I (n pi)^5) sin(n pi x / L) over odd n up to the shaft's modes; its
    midspan truncation error is below the first omitted term (alternating series), here
    (N + 2)^-5 / sum of the kept terms. Reactions: w L / 2 at each end (statics)."""
    for modes in (3, 9):
        shaft = Shaft(length=1.0, diameter=0.05, youngs_modulus=211e9, density=7810,
                      poisson_ratio=0.3, theory="euler-bernoulli", modes=modes)  # fmt: skip
        res = static_analysis(shaft)
        w = shaft.mass_per_length * STANDARD_GRAVITY
        sag = 5 * w / (384 * shaft.bending_stiffness)
        mid = int(np.argmin(np.abs(res.x - 0.5)))
        last_odd = modes if modes % 2 else modes - 1
        bound = (last_odd + 2) ** -5.0
        err = abs(-res.deflection[mid, 0] / sag - 1)
        assert err < bound
        assert err > 1e-3 * bound  # the truncation is what is measured, not round-off
        for b in res.bearings:
            assert b.force_y == pytest.approx(w / 2, rel=1e-12)


def test_static_refuses_bad_input():
    """Bad gravity and speed name the field."""
    rotor = _uniform("euler-bernoulli", 4)
    with pytest.raises(InputError, match="gravity"):
        static_analysis(rotor, gravity=(1.0,))
    with pytest.raises(InputError, match="speed"):
        static_analysis(rotor, speed=-1.0)


# ---- frequency response ------------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["fixed", "forward", "backward"])
def test_frequency_response_equals_a_dense_solve(kind):
    """Reference: a dense LAPACK solve of (K + i w (C + Omega G) - w^2 M) q = B F at every
    frequency (the system's own dense matrices at the spin speed), against the banded compiled
    sweep; general_rotor.toml at 700 rad/s (cross-coupled, speed-tabulated bearings)."""
    system = linear_system(load_scenario(SCEN / "general_rotor.toml"), (0.75,))
    w = np.linspace(0.0, 3000.0, 41)
    res = frequency_response(system, w, 0.45, [0.45, 0.75], kind=kind, magnitude=10.0,
                             direction=0.3, speed=700.0)  # fmt: skip
    mx = system.matrices(700.0)
    b = system.force_map(0.45) @ force_vector(kind, 10.0, 0.3)
    rows = np.concatenate([system.output_rows(p) for p in (0.45, 0.75)])
    for i, wi in enumerate(w):
        q = np.linalg.solve(mx.K + 1j * wi * mx.damping - wi**2 * mx.M, b)
        ref = (rows @ q).reshape(2, 2)
        np.testing.assert_allclose(
            res.complex_response[i], ref, rtol=1e-8, atol=1e-8 * abs(ref).max()
        )


def _jeffcott(m, ky, kz, c) -> LinearSystem:
    """A rigid disk of mass m (kg) on springs ky, kz (N/m) and dampers c (N s/m); tilts fixed."""
    z = np.zeros((4, 4))
    sup = Support((0, 1), np.array([[[ky, 0.0], [0.0, kz]]]), np.array([[[c, 0.0], [0.0, c]]]))
    return LinearSystem(np.diag([m, m, 1.0, 1.0]), z, z.copy(), z.copy(),
                        NodalBasis(np.array([0.0])), supports=(sup,), fixed=(2, 3))  # fmt: skip


def test_frequency_response_jeffcott_closed_form():
    """Reference: for m x'' + c x' + k x = f e^{i w t} the amplitude is f / (k - m w^2 + i c w).
    Isotropic: a forward force f e^{i w t} (F_y + i F_z) gives V = f H, W = -i V; a backward one
    W = +i V. Anisotropic, a fixed force at angle theta: V = f cos(theta) H_y,
    W = f sin(theta) H_z."""
    m, k, c, f = 3.0, 2e5, 40.0, 5.0
    w = np.linspace(10.0, 600.0, 60)
    h = 1 / (k - m * w**2 + 1j * c * w)
    iso = _jeffcott(m, k, k, c)
    fwd = frequency_response(iso, w, 0.0, [0.0], "forward", f).complex_response[:, 0]
    bwd = frequency_response(iso, w, 0.0, [0.0], "backward", f).complex_response[:, 0]
    np.testing.assert_allclose(fwd[:, 0], f * h, rtol=1e-12)
    np.testing.assert_allclose(fwd[:, 1], -1j * f * h, rtol=1e-12)
    np.testing.assert_allclose(bwd[:, 1], 1j * f * h, rtol=1e-12)
    aniso = _jeffcott(m, k, 1.7 * k, c)
    theta = 0.4
    got = frequency_response(aniso, w, 0.0, [0.0], "fixed", f, theta).complex_response[:, 0]
    np.testing.assert_allclose(got[:, 0], f * math.cos(theta) * h, rtol=1e-12)
    hz = 1 / (1.7 * k - m * w**2 + 1j * c * w)
    np.testing.assert_allclose(got[:, 1], f * math.sin(theta) * hz, rtol=1e-12)
    with pytest.raises(InputError, match="kind"):
        frequency_response(iso, w, 0.0, [0.0], "sideways")


# ---- unbalance of every plane ------------------------------------------------------------------
def test_every_unbalance_plane_is_used():
    """Reference: superposition. seal_rub.toml has two [[unbalance]] planes; the scenario's
    response equals the sum of the two planes' responses computed one at a time, and
    Scenario.unbalances lists both (Scenario.unbalance, the single table, is None)."""
    sc = load_scenario(SCEN / "seal_rub.toml")
    assert sc.unbalance is None and len(sc.unbalances) == 2
    assert 0.75 in sc.stations  # the [[contact]] station is a node
    speeds = np.linspace(50.0, 1500.0, 30)
    got = scenario_unbalance_response(sc, speeds, [0.75])
    system = linear_system(sc, (0.75,))
    parts = [unbalance_response(system, speeds, [(u.position, u.magnitude, u.phase)], [0.75])
             for u in sc.unbalances]  # fmt: skip
    total = sum(p.complex_response for p in parts)
    np.testing.assert_allclose(got.complex_response, total, rtol=1e-9, atol=1e-20)
    assert np.abs(parts[1].complex_response).max() > 0.01 * np.abs(total).max()
    no_unbalance = copy.deepcopy(scenario_to_dict(load_scenario(SCEN / "general_rotor.toml")))
    del no_unbalance["unbalance"]
    with pytest.raises(ScenarioError, match="unbalance"):
        scenario_unbalance_response(scenario_from_dict(no_unbalance), speeds)


# ---- undamped critical speed map ---------------------------------------------------------------
def test_ucs_map_limits_closed_forms():
    """References, Euler-Bernoulli uniform shaft (no rotary inertia) on two end springs k:
    rigid supports (k = 1e14 N/m, 40 elements) give the pinned-pinned frequencies
    (n pi / L)^2 sqrt(E I / (rho A)); soft ones the rigid-body bounce sqrt(2 k / m) and rocking
    sqrt(6 k / m) (rocking stiffness k L^2 / 2 over inertia m L^2 / 12). The shaft's own
    flexibility lowers them by a share proportional to k (measured -1.29e-4 for the bounce at
    k = 1e3 N/m, -1.29e-3 at 1e4), which the test checks too; softer springs sink into the
    eigen-solver's round-off (eps ||K|| / ||M||)."""
    rotor = _uniform("euler-bernoulli", 40, kind="bearing", k=1e7)
    data = ucs_map(rotor.linear_system(), [1e14], n=3)
    area, inertia = math.pi * 0.05**2 / 4, math.pi * 0.05**4 / 64
    pinned = (np.arange(1, 4) * math.pi) ** 2 * math.sqrt(211e9 * inertia / (7810 * area))
    np.testing.assert_allclose(data.critical_speeds[0], pinned, rtol=1e-5)
    assert [b.name for b in data.bearings] == ["bearing 1", "bearing 2"]
    mass = 7810 * area
    soft = ucs_map(_uniform("euler-bernoulli", 10, "bearing", 1e7).linear_system(), [1e3, 1e4], n=2)
    rigid = np.sqrt(np.outer([1e3, 1e4], [2 / mass, 6 / mass]))
    err = soft.critical_speeds / rigid - 1
    assert np.all(err < 0) and np.all(np.abs(err) < 2e-3)
    np.testing.assert_allclose(err[0] / err[1], 0.1, rtol=0.05)


def test_ucs_map_curves_and_bearing_tables():
    """Reference: monotony (stiffer supports never lower an undamped natural frequency,
    Rayleigh's theorem) and the bearing tables of general_rotor.toml as written."""
    sc = load_scenario(SCEN / "general_rotor.toml")
    data = ucs_map(linear_system(sc), np.logspace(5, 11, 13), n=4)
    assert np.all(np.diff(data.critical_speeds, axis=0) >= -1e-9 * data.critical_speeds[1:])
    left = data.bearings[0]
    np.testing.assert_array_equal(left.speeds, [0.0, 500.0, 1000.0, 1500.0])
    np.testing.assert_array_equal(left.kyy, [1.0e8, 8.0e7, 7.0e7, 6.5e7])
    np.testing.assert_array_equal(left.kzz, [6.0e7, 5.0e7, 4.5e7, 4.2e7])
    with pytest.raises(InputError, match="stiffness"):
        ucs_map(linear_system(sc), [-1.0])


def test_ucs_crossings_are_the_critical_speeds_on_the_bearings():
    """Reference: the undamped natural frequencies at rest of the rotor on its own (constant,
    isotropic, undamped-for-this-purpose) bearings, by scipy.linalg.eigh on its matrices: a
    bearing's vertical line crosses each mode's curve there (to the log-interpolation error of
    a 401-point stiffness grid, below 1e-4 here)."""
    import scipy.linalg

    rotor = Rotor([Section(1.0, 0.05, STEEL)], disks=[Disk(0.5, 12.0, 0.05, 0.03)],
                  bearings=[Bearing(0.0, kyy=3e6, kzz=3e6, cyy=100.0, czz=100.0),
                            Bearing(1.0, kyy=3e6, kzz=3e6, cyy=100.0, czz=100.0)])  # fmt: skip
    system = rotor.linear_system()
    data = ucs_map(system, np.logspace(5, 8, 401), n=3)
    mx = system.matrices(0.0)
    even = np.flatnonzero(system.free % 2 == 0)
    p = np.ix_(even, even)
    ref = np.sqrt(scipy.linalg.eigh(mx.K[p], mx.M[p], eigvals_only=True)[:3])
    for c in data.crossings():
        assert c["stiffness_N_m"] == 3e6
        assert c["speed_rad_s"] == pytest.approx(ref[c["mode"] - 1], rel=1e-4)
    assert len(data.crossings()) == 2 * 2 * 3


# ---- mode shapes -------------------------------------------------------------------------------
def test_mode_shapes_circular_whirl_on_an_isotropic_rotor():
    """Reference: on isotropic supports a spinning rotor's modes are circular, W = -i V
    (forward) or W = +i V (backward), so minor / major = +1 or -1 at every station; the
    direction per node agrees with damped_modes' whirl label."""
    rotor = Rotor([Section(1.0, 0.05, STEEL)],
                  disks=[Disk(0.3, 10.0, 0.08, 0.04)],
                  bearings=[Bearing(0.0, kyy=1e7, kzz=1e7, cyy=50.0, czz=50.0),
                            Bearing(1.0, kyy=1e7, kzz=1e7, cyy=50.0, czz=50.0)])  # fmt: skip
    shapes = mode_shapes(rotor.linear_system(), 800.0, n=4)
    d = shapes.to_dict()
    assert len(d["x_m"]) == shapes.x.size and len(d["modes"]) == 4
    for k, m in enumerate(shapes.modes.modes):
        big = shapes.major[k] > 1e-3
        ratio = shapes.minor[k][big] / shapes.major[k][big]
        sign = 1.0 if m.whirl == "forward" else -1.0
        assert m.whirl in ("forward", "backward")
        np.testing.assert_allclose(ratio, sign, atol=1e-9)
        assert set(np.array(d["modes"][k]["node_whirl"])[big]) == {m.whirl}
    assert {m.whirl for m in shapes.modes.modes} == {"forward", "backward"}


# ---- critical multiple of a general rotor ------------------------------------------------------
def test_critical_multiple_of_a_general_rotor():
    """References: damped_modes at the resolved speed (a second eigen route): at
    critical_multiple = 1 a mode's damped frequency equals the spin to 1e-8, and that mode
    whirls predominantly forward (minor/major > 0) with zeta <= 0.2; the unbalance response
    peaks there (within 1 %; general_rotor's heavily damped modes near 370 rad/s, zeta 0.98,
    are no critical speed); 1.5 gives 1.5 times that speed."""
    d = scenario_to_dict(load_scenario(SCEN / "general_rotor.toml"))
    d["speed"] = {"critical_multiple": 1.0}
    sc = scenario_from_dict(d)
    shapes = mode_shapes(linear_system(sc), sc.speed, n=8)
    match = [k for k, m in enumerate(shapes.modes.modes)
             if abs(2 * math.pi * m.frequency_hz / sc.speed - 1) < 1e-8]  # fmt: skip
    assert len(match) == 1
    k = match[0]
    assert shapes.minor[k].sum() > 0 and shapes.modes.modes[k].damping_ratio <= 0.2
    speeds = np.linspace(300.0, 700.0, 401)
    u = sc.unbalance
    resp = unbalance_response(linear_system(sc), speeds, [(u.position, u.magnitude, u.phase)],
                              [u.position])  # fmt: skip
    assert speeds[np.argmax(resp.major[:, 0])] == pytest.approx(sc.speed, rel=0.01)
    d["speed"] = {"critical_multiple": 1.5}
    assert scenario_from_dict(d).speed == pytest.approx(1.5 * sc.speed, rel=1e-12)
    d["speed"] = {"dimensionless": 1.5}
    with pytest.raises(ScenarioError, match="speed.dimensionless"):
        scenario_from_dict(d)
