"""Modes ranked by ``|lambda|`` with overdamped roots marked, damping of critical speeds, support
interpolation options and supports linked to housings: each against a closed form (derived in
the test's docstring) or a second numerical route."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import rubrotor
from rubrotor.cli import main
from rubrotor.errors import InputError
from rubrotor.linear.critical import CRITICALLY_DAMPED, linear_critical_speeds
from rubrotor.linear.modes import damped_modes
from rubrotor.linear.response import unbalance_response
from rubrotor.rotors.linear import LinearSystem, NodalBasis, Support


def _diagonal(m, c, k) -> LinearSystem:
    """Four uncoupled DOFs ``m_i q'' + c_i q' + k_i q = 0`` on one node (no supports)."""
    return LinearSystem(
        M=np.diag(m), K=np.diag(k), C=np.diag(c), G=np.zeros((4, 4)),
        basis=NodalBasis(np.array([0.0])),
    )  # fmt: skip


def _roots(m, c, k) -> np.ndarray:
    """Closed form of ``m lam^2 + c lam + k = 0``: both roots."""
    d = np.sqrt(complex(c * c - 4 * m * k))
    return np.array([(-c + d) / (2 * m), (-c - d) / (2 * m)])


def test_modes_ranked_by_natural_frequency_overdamped_marked():
    """Reference: the roots of ``m lam^2 + c lam + k`` per DOF. ``v``, ``w``: ``omega_n`` =
    100 rad/s, ``zeta`` = 0.01 (two modes). ``psi_w``: ``omega_n`` = 50 rad/s, ``zeta`` =
    0.99999, so ``Im(lam)`` = 0.22 rad/s (a heavily damped root: by frequency it would be mode 1,
    by ``|lam|`` = 50 rad/s it comes first too but is overdamped, so it is marked and listed after
    the modes). ``psi_v``: ``c^2 > 4 m k``, two real roots, -10.00000001 and about -1e7 1/s."""
    m, c, k = [1.0, 1.0, 1e-4, 1.0], [2.0, 2.0, 1e3, 2 * 0.99999 * 50], [1e4, 1e4, 1e4, 2.5e3]
    system = _diagonal(m, c, k)
    mode = _roots(1.0, 2.0, 1e4)[0]
    heavy = _roots(1.0, c[3], 2.5e3)[0]
    real = np.sort(_roots(1e-4, 1e3, 1e4).real)[::-1]  # -10.00000001, then about -1e7
    few = damped_modes(system, 0.0, n=2).modes
    assert [md.overdamped for md in few] == [False, False, True, True]
    np.testing.assert_allclose([md.eigenvalue for md in few], [mode, mode, real[0], heavy],
                               rtol=1e-10)  # fmt: skip
    assert [md.index for md in few] == [1, 2, 3, 4]
    assert few[0].natural_frequency_hz == pytest.approx(100 / (2 * math.pi), rel=1e-12)
    assert few[2].frequency_hz == 0.0 and few[2].log_dec == math.inf
    assert few[3].damping_ratio == pytest.approx(0.99999, rel=1e-12)
    every = damped_modes(system, 0.0).modes  # all: the far real root as well, last
    np.testing.assert_allclose([md.eigenvalue for md in every], [mode, mode, real[0], heavy,
                                real[1]], rtol=1e-9)  # fmt: skip
    payload = json.loads(json.dumps(damped_modes(system, 0.0, n=2).to_dict()))
    assert [md["overdamped"] for md in payload["modes"]] == [False, False, True, True]
    assert payload["modes"][2]["log_dec"] is None  # no JSON infinity


def _jeffcott(c: float) -> LinearSystem:
    """Rigid-disk Jeffcott rotor, ``m`` = 2 kg, ``k`` = 8e4 N/m, no gyroscopic coupling."""
    z = np.zeros((4, 4))
    return LinearSystem(
        M=np.diag([2.0, 2.0, 1.0, 1.0]), K=z.copy(), C=z.copy(), G=z.copy(),
        basis=NodalBasis(np.array([0.0])),
        supports=(Support(dofs=(0, 1), k=np.array([8e4 * np.eye(2)]),
                          c=np.array([c * np.eye(2)])),),
        fixed=(2, 3),
    )  # fmt: skip


@pytest.mark.parametrize("zeta", [0.05, 0.3])
def test_critical_speed_damping_ratio_and_flag(zeta):
    """Reference: without gyroscopics the damped frequency ``omega_n sqrt(1 - zeta^2)`` does not
    depend on the spin, so both modes cross 1X there, with ``zeta = c / (2 sqrt(k m))``;
    flagged critically damped when ``zeta > 0.2`` (API 684: amplification factor < 2.5)."""
    wn = math.sqrt(8e4 / 2.0)
    crit = linear_critical_speeds(_jeffcott(2 * zeta * math.sqrt(8e4 * 2.0)), 2 * wn, n=2)
    assert len(crit) == 2
    for cr in crit:
        assert cr.speed_rad_s == pytest.approx(wn * math.sqrt(1 - zeta**2), rel=1e-9)
        assert cr.damping_ratio == pytest.approx(zeta, rel=1e-9)
        assert cr.critically_damped is (zeta > CRITICALLY_DAMPED)


def test_critical_cli_prints_damping_and_flag(capsys):
    """``rubrotor critical --json`` on the shipped general rotor up to 500 rad/s: every critical
    speed carries the damping ratio of its mode at the crossing, equal to that of the mode of
    the dense eigen-solve there whose damped frequency is the speed (a second route); the two
    bearing-dominated modes (about 0.98) are flagged, the others not."""
    path = rubrotor.__file__.replace("__init__.py", "scenarios/general_rotor.toml")
    assert main(["critical", path, "--json", "--max-speed", "500"]) == 0
    out = json.loads(capsys.readouterr().out)
    system = rubrotor.linear_system(rubrotor.load_scenario(path))
    assert out["critically_damped_above"] == CRITICALLY_DAMPED
    got = out["critical_speeds"]
    assert len(got) >= 3
    for c in got:
        modes = damped_modes(system, c["speed_rad_s"]).modes
        j = np.argmin([abs(2 * math.pi * md.frequency_hz - c["speed_rad_s"]) for md in modes])
        assert c["damping_ratio"] == pytest.approx(modes[j].damping_ratio, rel=1e-6)
        assert c["critically_damped"] is (c["damping_ratio"] > CRITICALLY_DAMPED)
        assert 0 < c["damping_ratio"] < 1  # 121.6 rad/s, zeta -1: a real root, no longer
    assert any(c["critically_damped"] for c in got) and not all(c["critically_damped"] for c in got)


def _support(values, interpolation="linear", extrapolation="hold") -> Support:
    speeds = np.array([0.0, 100.0, 300.0, 400.0])
    k = np.array([v * np.eye(2) for v in values])
    return Support((0, 1), k, 0.1 * k, speeds, 0.0, "s", interpolation, extrapolation)


def test_support_interpolation_options():
    """Closed forms: on a linear table (k = 1e6 + 2e3 s) PCHIP and linear interpolation are the
    line itself, and linear extrapolation continues it (``hold`` keeps the end values). On a
    convex table both pass through every table value; linear equals ``numpy.interp`` (a second
    route); PCHIP stays between neighbouring values (shape preserving) and differs from it."""
    s = np.array([-50.0, 0.0, 50.0, 100.0, 250.0, 300.0, 350.0, 400.0, 500.0])
    line = 1e6 + 2e3 * np.array([0.0, 100.0, 300.0, 400.0])
    for interp in ("linear", "pchip"):
        k, c = _support(line, interp, "linear").tabulate(s)
        np.testing.assert_allclose(k[:, 0, 0], 1e6 + 2e3 * s, rtol=1e-13)
        np.testing.assert_allclose(c[:, 1, 1], 0.1 * (1e6 + 2e3 * s), rtol=1e-13)
        held = _support(line, interp).tabulate(s)[0][:, 0, 0]
        np.testing.assert_allclose(held, 1e6 + 2e3 * np.clip(s, 0, 400), rtol=1e-13)
    convex = 1e6 + 10.0 * np.array([0.0, 100.0, 300.0, 400.0]) ** 2
    lin = _support(convex).tabulate(s)[0][:, 0, 0]
    pch = _support(convex, "pchip").tabulate(s)[0][:, 0, 0]
    np.testing.assert_allclose(lin, np.interp(s, [0, 100, 300, 400], convex), rtol=1e-13)
    table = np.array([0.0, 100.0, 300.0, 400.0])
    np.testing.assert_allclose(_support(convex, "pchip").tabulate(table)[0][:, 0, 0], convex,
                               rtol=1e-14)  # fmt: skip
    inside = (s > 0) & (s < 400) & ~np.isin(s, table)
    lo = np.interp(s, table, convex, left=np.nan)  # bounds: the neighbouring table values
    j = np.searchsorted(table, s[inside])
    assert np.all(pch[inside] >= convex[j - 1]) and np.all(pch[inside] <= convex[j])
    assert np.max(np.abs(pch[inside] - lo[inside]) / lo[inside]) > 1e-3
    with pytest.raises(InputError, match="s.interpolation"):
        _support(convex, "cubic")
    with pytest.raises(InputError, match="s.extrapolation"):
        _support(convex, "pchip", "nearest")


def test_support_linked_to_a_housing():
    """Reference: a shaft mass ``m1`` = 3 kg on a spring ``k1`` = 2e6 N/m to a housing mass
    ``m2`` = 1.5 kg on ``k2`` = 5e6 N/m to the ground (``Support.link``, the housing on the
    basis' extra DOFs), per plane. Natural frequencies: the roots in ``omega^2`` of
    ``(k1 - m1 w^2)(k1 + k2 - m2 w^2) - k1^2 = 0``; unbalance response (force ``m e Omega^2``
    turning forward): ``V = (k1 + k2 - m2 Omega^2) F / det``, ``W = -i V`` (the banded solver
    with the link's off-diagonal entries)."""
    m1, m2, k1, k2 = 3.0, 1.5, 2e6, 5e6
    z = np.zeros((6, 6))
    system = LinearSystem(
        M=np.diag([m1, m1, 1.0, 1.0, m2, m2]), K=z.copy(), C=z.copy(), G=z.copy(),
        basis=NodalBasis(np.array([0.0]), extra=2),
        supports=(Support((0, 1), np.array([k1 * np.eye(2)]), np.zeros((1, 2, 2)), link=(4, 5)),
                  Support((4, 5), np.array([k2 * np.eye(2)]), np.zeros((1, 2, 2)))),
        fixed=(2, 3),
    )  # fmt: skip
    a, b, c = m1 * m2, -(m1 * (k1 + k2) + m2 * k1), k1 * k2
    w2 = np.sort(np.roots([a, b, c]).real)
    got = [2 * np.pi * md.frequency_hz for md in damped_modes(system, 0.0).modes]
    np.testing.assert_allclose(got, np.repeat(np.sqrt(w2), 2), rtol=1e-10)
    speeds = np.array([200.0, 900.0, 2500.0])
    resp = unbalance_response(system, speeds, [(0.0, 1e-3, 0.0)], [0.0]).complex_response
    f = 1e-3 * speeds**2
    det = (k1 - m1 * speeds**2) * (k1 + k2 - m2 * speeds**2) - k1**2
    v = (k1 + k2 - m2 * speeds**2) * f / det
    np.testing.assert_allclose(resp[:, 0, 0], v, rtol=1e-10)
    np.testing.assert_allclose(resp[:, 0, 1], -1j * v, rtol=1e-10)


@pytest.mark.parametrize("dashpot", [0.0, 2e5])
def test_n_modes_routes_equal_the_dense_route(dashpot):
    """On a 40-element rotor (a speed-tabulated cross-coupled bearing) ``damped_modes(n=6)``
    takes the projection + Newton route when the projection ranks alike, and shift-invert
    ARPACK when a heavy dashpot (2e5 N s/m on a soft 1e5 N/m support at the disk) adds a real
    root below the 6th mode; both equal the dense eigen-solve of all 2N roots ranked by
    ``|lambda|`` (reference: ``scipy.linalg.eigvals`` of the first-order matrix) to 1e-9."""
    import scipy.linalg

    from rubrotor.linear.modes import _newton_eig
    from rubrotor.linear.roots import OSCILLATING, OVERDAMPED

    sec = rubrotor.Section(length=0.6, diameter=0.04, material=rubrotor.Material(
        name="steel", youngs_modulus=211e9, poisson_ratio=0.3, density=7810), elements=40)  # fmt: skip
    bearings = [
        rubrotor.Bearing(position=0.0, speeds=(0.0, 1000.0, 4000.0), kyy=(3e6, 4e6, 6e6),
                         kzz=5e6, kyz=(0.0, 4e5, 9e5), kzy=(0.0, -4e5, -9e5), cyy=400.0,
                         czz=(600.0, 500.0, 450.0)),
        rubrotor.Bearing(position=0.6, kyy=3e6, kzz=5e6, cyy=400.0, czz=600.0),
    ]  # fmt: skip
    if dashpot:
        bearings.append(rubrotor.Bearing(position=0.3, kyy=1e5, kzz=1e5, cyy=dashpot, czz=dashpot))
    disk = rubrotor.Disk(position=0.3, mass=4.0, polar_inertia=0.02, diametral_inertia=0.011)
    system = rubrotor.Rotor(sections=(sec,), disks=(disk,), bearings=tuple(bearings)).linear_system(
        ()
    )
    for speed in (0.0, 2500.0):
        lam = scipy.linalg.eigvals(system.matrices(speed).first_order()[0])
        a = np.abs(lam)
        osc = lam[lam.imag > OVERDAMPED * a]
        osc = osc[np.argsort(np.abs(osc))][:6]
        over = lam[(lam.imag > -OSCILLATING * a) & (lam.imag <= OVERDAMPED * a)]
        over = over[np.abs(over) <= np.abs(osc).max()]
        ref = np.concatenate([osc, np.sort(over.real)[::-1]])
        got = [md.eigenvalue for md in damped_modes(system, speed, n=6).modes]
        np.testing.assert_allclose(got, ref, rtol=1e-9)
        assert (_newton_eig(system, speed, 6, natural=True) is None) is bool(dashpot)
        assert len(over) == (2 if dashpot else 0)
