"""API 617 close-clearance check and API 684 Level I stability, against closed forms and the
standards' formulas (ROSS 3.1's own runs are compared in test_linear_verbs_ross.py)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import rubrotor
from rubrotor.errors import InputError
from rubrotor.linear.api617 import (
    api617_unbalance,
    clearance_check,
    residual_unbalance,
    vibration_limit,
)
from rubrotor.linear.api684 import anticipated_cross_coupling, level1
from rubrotor.linear.response import unbalance_response
from rubrotor.linear.verbs import linear_system
from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section
from rubrotor.rotors.linear import LinearSystem, NodalBasis, Support

SCEN = Path(rubrotor.__file__).parent / "scenarios"
STEEL = Material("steel", 211e9, 7810, poisson_ratio=0.3)


def test_api_formulas():
    """References: API 617's U_r = 6350 W / N g mm (N capped at 25000 rpm), the test vibration
    limit min(25.4, 25.4 sqrt(12000 / N)) µm pk-pk, and Wachel's Q_A = B_c T / (D_c H_c)
    (rho_d / rho_s) with T = P / Omega, equal to the US form 63 HP B_c / (D H N) klbf/in."""
    rpm = 2 * math.pi / 60
    assert residual_unbalance(300.0, 9000 * rpm) == pytest.approx(6350 * 300 / 9000 * 1e-6)
    assert residual_unbalance(30.0, 40000 * rpm) == pytest.approx(30 / 3.937 * 1e-6, rel=1e-4)
    assert vibration_limit(9000 * rpm) == pytest.approx(25.4e-6)
    assert vibration_limit(48000 * rpm) == pytest.approx(12.7e-6)
    hp, d_in, h_in, n_rpm = 6000.0, 16.0, 0.8, 10000.0
    us = 63 * hp * 3 / (d_in * h_in * n_rpm) * 1.3  # klbf/in
    si = anticipated_cross_coupling(hp * 745.69987, n_rpm * rpm, d_in * 0.0254, h_in * 0.0254, 1.3)
    assert si == pytest.approx(us * 4448.2216 / 0.0254, rel=2e-3)  # 63 is 63025 / 1000 rounded
    with pytest.raises(InputError):
        anticipated_cross_coupling(1e6, 100.0, 0.0, 0.02)


def _jeffcott(m=2.0, k=8e4, c=20.0) -> LinearSystem:
    """Rigid disk m (kg) on isotropic springs k (N/m) and dampers c (N s/m), tilts fixed."""
    z = np.zeros((4, 4))
    sup = Support((0, 1), np.array([k * np.eye(2)]), np.array([c * np.eye(2)]))
    return LinearSystem(np.diag([m, m, 1.0, 1.0]), z, z.copy(), z.copy(),
                        NodalBasis(np.array([0.0])), supports=(sup,), fixed=(2, 3))  # fmt: skip


def test_level1_jeffcott_closed_form():
    """Reference: with k_yz = Q, k_zy = -Q the forward whirl z = v + i w obeys
    m z'' + c z' + (k - i Q) z = 0: lambda = (-c + sqrt(c^2 - 4 m (k - i Q))) / (2 m), log dec
    -2 pi Re(lambda) / Im(lambda); it crosses zero at Q0 = c sqrt(k / m)."""
    m, k, c = 2.0, 8e4, 20.0
    q = np.logspace(2, 4, 15)
    res = level1(_jeffcott(m, k, c), 100.0, 0.0, q, qa=500.0)
    lam = (-c + np.sqrt(c**2 - 4 * m * (k - 1j * q) + 0j)) / (2 * m)
    lam = np.where(lam.imag > 0, lam, (-c - np.sqrt(c**2 - 4 * m * (k - 1j * q) + 0j)) / (2 * m))
    np.testing.assert_allclose(res.log_dec, -2 * np.pi * lam.real / lam.imag, rtol=1e-9)
    q0 = c * math.sqrt(k / m)
    assert res.q0 == pytest.approx(q0, rel=0.02)  # interpolated between grid points in log Q
    assert res.log_dec_at_qa > 0.1 and res.q0 / res.qa >= 2 and res.verdict == "pass"
    assert level1(_jeffcott(m, k, c), 100.0, 0.0, q, qa=q0 / 1.5).verdict == "level II required"


def _two_disk_rotor() -> Rotor:
    """A 1.2 m shaft, two disks, two damped bearings (a symmetric first bending mode)."""
    return Rotor([Section(1.2, 0.06, STEEL)],
                 disks=[Disk(0.4, 20.0, 0.2, 0.1), Disk(0.8, 20.0, 0.2, 0.1)],
                 bearings=[Bearing(0.05, kyy=5e7, kzz=4e7, cyy=2e3, czz=2e3),
                           Bearing(1.15, kyy=5e7, kzz=4e7, cyy=2e3, czz=2e3)])  # fmt: skip


def test_api617_unbalance_first_mode_and_scale_invariance():
    """References: API 617's placement of the first mode (one antinode between the bearings,
    W = the sum of the journal loads = the rotor's weight / g, from the geometry), and
    linearity: without the cap of S_cc the scaled clearance response does not depend on the
    unbalance magnitude (a hand-placed unbalance 7 times larger gives the same)."""
    rotor = _two_disk_rotor()
    system = rotor.linear_system((0.6,))
    nmc = 900.0
    planes, weights, _ = api617_unbalance(system, nmc, 0)
    assert len(planes) == 1 and planes[0][0] == pytest.approx(0.6, abs=0.05)
    assert weights[0] == pytest.approx(rotor.mass, rel=1e-6)
    assert planes[0][1] == pytest.approx(2 * 6350 * rotor.mass / (nmc * 60 / (2 * math.pi)) * 1e-6)
    speeds = np.linspace(50.0, 1100.0, 60)
    probes, gaps = [(0.05, None), (1.15, math.pi / 4)], [("seal", 0.6, 150e-6)]
    auto = clearance_check(system, speeds, 600.0, nmc, probes, gaps, scale_factor_cap=None)
    hand = clearance_check(system, speeds, 600.0, nmc, probes, gaps, scale_factor_cap=None,
                           planes=[(planes[0][0], 7 * planes[0][1], 0.0)])  # fmt: skip
    np.testing.assert_allclose(hand.scaled, auto.scaled, rtol=1e-9)
    # the scale factor brings the probes' largest pk-pk amplitude in the band to A_vl
    resp = unbalance_response(system, auto.speeds, planes, [0.05])
    band = (auto.speeds >= 600.0) & (auto.speeds <= nmc)
    raw = (2 * resp.major[band, 0]).max()
    assert auto.max_probe_amplitude >= raw * (1 - 1e-12)
    assert auto.scale_factor == pytest.approx(auto.vibration_limit / auto.max_probe_amplitude)
    capped = clearance_check(system, speeds, 600.0, nmc, probes, gaps)  # API 617's cap of 6
    assert capped.scale_factor == pytest.approx(min(6.0, auto.scale_factor))
    assert auto.margin[0] == pytest.approx(0.75 * 300e-6 - auto.scaled[0].max())


def test_clearance_check_of_a_scenario_contact():
    """seal_rub.toml: the [[contact]] (40 µm radial) is the close clearance; the check runs and
    its dict says pass or fail consistently with the margin."""
    sc = rubrotor.load_scenario(SCEN / "seal_rub.toml")
    system = linear_system(sc)
    (c,) = sc.contacts
    res = clearance_check(system, np.linspace(20, 800, 40), 0.7 * sc.speed, sc.speed,
                          [(0.05, None), (1.25, None)], [("seal", c.position, c.clearance)])  # fmt: skip
    d = res.to_dict()["clearances"][0]
    assert d["diametral_clearance_m"] == pytest.approx(80e-6)
    assert (d["verdict"] == "pass") == (d["margin_m"] >= 0)
    with pytest.raises(InputError, match="min_speed"):
        clearance_check(system, [100.0], 700.0, 600.0, [(0.05, None)], [("s", 0.75, 4e-5)])
