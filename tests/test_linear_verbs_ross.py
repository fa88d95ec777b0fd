"""API 617 clearance check, API 684 Level I, the static analysis and the frequency response
against ROSS 3.1's own ``run_clearance_analysis``, ``run_level1``, ``run_static`` and
``run_freq_response`` on ROSS's example rotors (same unbalance, speeds, probes, cross-coupling,
gravity, force). Skipped without ROSS 3.1
(``api617_unbalance`` and ``run_clearance_analysis`` are new in 3.1)."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

with warnings.catch_warnings():  # ROSS's import warns about REFPROP (its ccp dependency)
    warnings.simplefilter("ignore")
    if os.environ.get("RUBROTOR_REQUIRE_ROSS"):  # CI's ROSS step: a missing ROSS is a failure
        import ross
    else:
        ross = pytest.importorskip("ross")

import dataclasses  # noqa: E402

from rubrotor.linear.api617 import api617_unbalance, clearance_check  # noqa: E402
from rubrotor.linear.api684 import level1  # noqa: E402
from rubrotor.linear.response import frequency_response  # noqa: E402
from rubrotor.linear.static import static_analysis  # noqa: E402
from rubrotor.rotors.ross import from_ross  # noqa: E402

pytestmark = [
    pytest.mark.filterwarnings("ignore"),
    pytest.mark.skipif(not hasattr(ross.Rotor, "run_clearance_analysis"), reason="ROSS < 3.1"),
]
RPM = 2 * np.pi / 60


def _example(kxx, kyy, c, **kwargs):
    """ROSS's rotor_example on two new bearings (ROSS's units: N/m, N s/m)."""
    base = ross.rotor_example()
    bearings = [ross.BearingElement(n=n, kxx=kxx, kyy=kyy, cxx=c, cyy=c, **kwargs) for n in (0, 6)]
    return ross.Rotor(base.shaft_elements, base.disk_elements, bearings)


def test_clearance_check_equals_ross():
    """ROSS's own docstring case: bearings of 1e6 N/m, 1e3 N s/m, 100 µm radial clearance,
    probes at the bearings at 45 deg, 0-10000 rpm, N_ma 7000 rpm, N_mc 9000 rpm, no cap.
    Measured: unbalance and W equal to 1e-14, A_max and S_cc to 1e-14, scaled responses to
    2e-13."""
    q = ross.Q_
    rotor = _example(1e6, 1e6, 1e3, radial_clearance=q(100, "um"))
    speeds = np.linspace(0, 10000, 101) * RPM
    nma, nmc = 7000 * RPM, 9000 * RPM
    probes = [ross.Probe(0, q(45, "deg")), ross.Probe(6, q(45, "deg"))]
    ref = rotor.run_clearance_analysis(speeds, nma, nmc, probes)
    theirs = rotor.api617_unbalance(mode=0, maximum_continuous_speed=nmc)
    system = from_ross(rotor)
    x = system.basis.nodes
    planes, loads, _ = api617_unbalance(system, nmc, 0, max_damping_ratio=None)
    assert [p[0] for p in planes] == [x[n] for n in theirs["node"]]
    np.testing.assert_allclose([p[1] for p in planes], theirs["unbalance_magnitude"], rtol=1e-9)
    np.testing.assert_allclose(loads, theirs["static_load"], rtol=1e-9)
    mine = clearance_check(system, speeds, nma, nmc, [(x[0], np.pi / 4), (x[6], np.pi / 4)],
                           [("b0", x[0], 100e-6), ("b6", x[6], 100e-6)],
                           scale_factor_cap=None, max_damping_ratio=None)  # fmt: skip
    assert mine.vibration_limit == pytest.approx(ref.vibration_limit, rel=1e-12)
    assert mine.max_probe_amplitude == pytest.approx(ref.max_probe_amplitude, rel=1e-9)
    assert mine.scale_factor == pytest.approx(ref.scale_factor, rel=1e-9)
    keep = np.isin(ref.speed_range, mine.speeds)  # rubrotor leaves out 0 rad/s (no unbalance)
    assert keep.sum() == ref.speed_range.size - 1
    for j in range(2):
        got = mine.scaled[j][np.searchsorted(mine.speeds, ref.speed_range[keep])]
        np.testing.assert_allclose(got, np.asarray(ref.clearance_response[j])[keep], rtol=1e-6)
        assert 2 * 100e-6 == pytest.approx(ref.diametral_clearance[j])


def test_level1_equals_ross():
    """ROSS's run_level1 on rotor_example with anisotropic damped bearings, cross-coupling at
    the mid node 3, at 9000 rpm. Measured: log decs equal to 7e-11."""
    rotor = _example(1e6, 0.8e6, 300.0)
    rotor = ross.Rotor(rotor.shaft_elements, rotor.disk_elements, rotor.bearing_elements,
                       rated_w=9000 * RPM)  # fmt: skip
    ref = rotor.run_level1(n=3, stiffness_range=(1e3, 2e5), num=6)
    system = from_ross(rotor)
    mine = level1(system, 9000 * RPM, system.basis.nodes[3], ref.stiffness_range)
    np.testing.assert_allclose(mine.log_dec, ref.log_dec, rtol=1e-6)
    assert ref.log_dec[0] > 0 > ref.log_dec[-1] and mine.q0 is not None


def test_static_equals_ross():
    """ROSS's run_static puts the rotor on rigid supports (1e20 N/m) under g = 9.8065 m/s^2
    along its -y (our -z): the same here with the bearings pinned. Measured: reactions equal to
    3e-14, deflections to 1e-12."""
    rotor = ross.rotor_example()
    ref = rotor.run_static()
    system = from_ross(rotor)
    fixed = tuple(d for s in system.supports for d in s.dofs)
    pinned = dataclasses.replace(system, supports=(), fixed=fixed)
    mine = static_analysis(pinned, gravity=(0.0, -9.8065))
    forces = [rotor.bearing_forces_nodal[f"node_{n}"] for n in (0, 6)]
    np.testing.assert_allclose([b.force_z for b in mine.bearings], forces, rtol=1e-9)
    deformation = np.asarray(ref.deformation, float).ravel()
    np.testing.assert_allclose(mine.deflection[:, 1], deformation, rtol=1e-9,
                               atol=1e-9 * np.abs(deformation).max())  # fmt: skip


def test_frequency_response_equals_ross():
    """ROSS's run_freq_response at a fixed spin (its ``speed=``: a non-synchronous force) on
    rotor_example_with_damping: its transfer matrix column of a force along x (our y) or y
    (our z) at node 2, read at node 4, equals our fixed-direction force response. Measured:
    about 1e-13."""
    rotor = ross.rotor_example_with_damping()
    w = np.linspace(10.0, 1500.0, 12)
    h = np.asarray(rotor.run_freq_response(speed_range=w, speed=500.0).freq_resp)
    system = from_ross(rotor)
    x, dof = system.basis.nodes, int(rotor.number_dof)
    for direction, col in ((0.0, dof * 2), (np.pi / 2, dof * 2 + 1)):
        got = frequency_response(system, w, x[2], [x[4]], "fixed", 1.0, direction, 500.0)
        resp = got.complex_response[:, 0]
        np.testing.assert_allclose(resp[:, 0], h[dof * 4, col], rtol=1e-9)
        np.testing.assert_allclose(resp[:, 1], h[dof * 4 + 1, col], rtol=1e-9)
