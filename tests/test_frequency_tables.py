"""Bearing tables read on the axis they are tabulated on (issue 30): a table against whirl
frequency (a magnetic bearing, a squeeze-film damper) is read at the excitation frequency by
the frequency response, a table against speed at the spin.

Reference: a dense solve written here, ``(K_total - w^2 M + i w (C_total + Omega G)) Q = F``
with the bearing's coefficients interpolated by ``numpy.interp`` at the excitation frequency
and placed by hand on the bearing's DOFs (independent of :class:`Support`'s interpolation and
of the banded solver).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from rubrotor.linear.response import frequency_response, unbalance_response
from rubrotor.rotors.fe import Bearing, Material, Rotor, Section
from rubrotor.rotors.linear import TableExtrapolationWarning

STEEL = Material("steel", 211e9, 7810, poisson_ratio=0.3)
TABLE_W = np.array([0.0, 500.0, 1000.0, 1500.0, 2000.0])  # rad/s
KYY = 2e7 * np.array([1.0, 1.05, 1.10, 1.15, 1.20])  # varies 20 % over the band
CYY = 3e3 * np.array([1.0, 0.95, 0.9, 0.85, 0.8])


def _rotor(axis: str, extrapolation: str = "hold") -> Rotor:
    key = "frequencies" if axis == "frequency" else "speeds"
    amb = Bearing(0.0, kyy=tuple(KYY), kzz=tuple(0.9 * KYY), kyz=tuple(0.1 * KYY),
                  cyy=tuple(CYY), czz=tuple(CYY), name="amb", extrapolation=extrapolation,
                  **{key: tuple(TABLE_W)})  # fmt: skip
    other = Bearing(1.0, kyy=3e7, kzz=3e7, cyy=2e3, czz=2e3, name="journal")
    return Rotor([Section(1.0, 0.06, STEEL, elements=8)], bearings=[amb, other])


def _dense(system, speed: float, w: np.ndarray, at: np.ndarray, position: float, probe: float):
    """Fixed force along y at ``position``; response at ``probe`` by a dense solve with the
    "amb" table read (numpy.interp) at ``at`` (rad/s, one per frequency)."""
    mx = system.matrices(0.0)  # supports at 0 rad/s, removed below
    sup = {s.name: s for s in system.supports}
    out = np.zeros((w.size, 2), complex)
    for j, (wj, aj) in enumerate(zip(w, at, strict=True)):
        K, C = system.K.copy(), system.C.copy()
        for s in system.supports:
            if s.name == "amb":
                k = np.array([[np.interp(aj, TABLE_W, KYY), np.interp(aj, TABLE_W, 0.1 * KYY)],
                              [0.0, np.interp(aj, TABLE_W, 0.9 * KYY)]])  # fmt: skip
                c = np.diag([np.interp(aj, TABLE_W, CYY)] * 2)
            else:
                k, c = s.k[0], s.c[0]
            ix = np.ix_(s.dofs, s.dofs)
            K[ix] += k
            C[ix] += c
        f = np.ix_(system.free, system.free)
        a = K[f] - wj**2 * mx.M + 1j * wj * (C[f] + speed * mx.G)
        q = np.linalg.solve(a, system.force_map(position) @ np.array([1.0, 0.0]))
        out[j] = system.output_rows(probe) @ q
    assert "amb" in sup
    return out


def test_frequency_table_read_at_the_excitation_frequency():
    """Spin 300 rad/s, excitation 50 ... 1950 rad/s: the response with the "amb" table against
    frequency equals the dense solve with the table read at each excitation frequency, to
    1e-10 relative; read at the spin (a speed table) it differs by far more."""
    system = _rotor("frequency").linear_system(stations=[0.5])
    w = np.linspace(50.0, 1950.0, 39)
    speed = 300.0
    got = frequency_response(system, w, 0.5, [0.5], speed=speed).complex_response[:, 0, :]
    ref = _dense(system, speed, w, w, 0.5, 0.5)
    err = np.abs(got - ref).max() / np.abs(ref).max()
    assert err <= 1e-10
    at_spin = _dense(system, speed, w, np.full(w.size, speed), 0.5, 0.5)
    assert np.abs(at_spin - ref).max() / np.abs(ref).max() > 1e-3


def test_speed_table_read_at_the_spin():
    """The same table against speed: read at the spin for every excitation frequency."""
    system = _rotor("speed").linear_system(stations=[0.5])
    w = np.linspace(50.0, 1950.0, 39)
    speed = 1250.0
    got = frequency_response(system, w, 0.5, [0.5], speed=speed).complex_response[:, 0, :]
    ref = _dense(system, speed, w, np.full(w.size, speed), 0.5, 0.5)
    assert np.abs(got - ref).max() / np.abs(ref).max() <= 1e-10


def test_unbalance_reads_frequency_tables_synchronously():
    """Unbalance response: whirl frequency = spin, so a frequency table and the same table
    against speed give the same response (to rounding)."""
    speeds = np.linspace(100.0, 1900.0, 19)
    a = unbalance_response(_rotor("frequency").linear_system([0.5]), speeds, [(0.5, 1e-4, 0.0)],
                           [0.5])  # fmt: skip
    b = unbalance_response(_rotor("speed").linear_system([0.5]), speeds, [(0.5, 1e-4, 0.0)],
                           [0.5])  # fmt: skip
    np.testing.assert_allclose(a.complex_response, b.complex_response, rtol=1e-12)


def test_extrapolation_warns_naming_element_and_axis():
    """Beyond the table with ROSS's linear extrapolation: a warning naming the element and the
    axis; inside the table, none."""
    system = _rotor("frequency", extrapolation="linear").linear_system(stations=[0.5])
    with pytest.warns(TableExtrapolationWarning, match=r"'amb'.*frequency axis"):
        frequency_response(system, [100.0, 2500.0], 0.5, [0.5], speed=300.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        frequency_response(system, [100.0, 1900.0], 0.5, [0.5], speed=3000.0)
