"""The stability threshold from one batched Campbell sweep (``n`` given) against closed forms
and against the per-point modal route (``n=None``, a dense modal analysis at every scan point).

References: the cross-coupled Jeffcott rotor's ``Omega* = c sqrt(k/m) / a`` (derived in
``tests/test_linear_analysis.py``), and Muszynska's fluid ring's closed-form whirl threshold
(``rubrotor.forces.muszynska.whirl_threshold``, checked there against eigenvalues).
"""

import math

import pytest
from test_force_muszynska import SEAL, D, K, M, _scenario
from test_linear_analysis import jeffcott

from rubrotor.forces.muszynska import whirl_threshold
from rubrotor.linear.stability import stability_threshold


def test_jeffcott_threshold_by_the_sweep_equals_the_closed_form():
    m, k, c, a = 2.0, 8e4, 20.0, 0.5
    exact = c * math.sqrt(k / m) / a
    assert stability_threshold(jeffcott(m, k, c, a), 3 * exact, n=2) == pytest.approx(
        exact, rel=1e-8
    )
    assert stability_threshold(jeffcott(m, k, c, 0.0), 3 * exact, n=2) is None


def test_fluid_ring_threshold_by_the_sweep_equals_the_per_point_route(tmp_path):
    om_th = whirl_threshold(M, K, D, SEAL)
    sc = _scenario(tmp_path, om_th)
    system = sc.rotor.linear_system(sc.stations)
    swept = stability_threshold(system, 2 * om_th, n=4, points=40)
    assert swept == pytest.approx(om_th, rel=1e-5)
    # the per-point route's n=None modes come from another eigen-solve than the n=4 ones: their
    # damping ratios differ by rounding, which moves the zero crossing by ~2e-9 of itself
    assert swept == pytest.approx(stability_threshold(system, 2 * om_th, points=40), rel=1e-8)
