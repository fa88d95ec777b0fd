"""The one regimes module (rubrotor.sweeps.regimes): metrics, labels, and its users agreeing.

References: impacts per revolution against a second count (rising edges of the normal force
sampled at every fixed step of the same run); the seed reproduction's summary and a sweep point
of the same run give the same label; the exponent of a no-contact point equals ``Re(lambda)``
of the modal system (one Euler-Bernoulli mode without gyroscopic coupling: both whirl
eigenvalues have the real part ``-zeta omega``, so the finite-time estimate is exact to rounding).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_lyapunov import LOADED, one_mode

from rubrotor.engine.settings import Integrator
from rubrotor.engine.simulate import assemble, simulate, simulate_scenario
from rubrotor.studies.seed.reproduce import case_metrics
from rubrotor.sweeps.regimes import (
    CHAOS_MARGIN_PER_REV,
    CHAOTIC,
    FULL,
    NO_CONTACT,
    PARTIAL,
    QUASI,
    case_regime,
    classify,
    contact_fraction,
    impacts_per_revolution,
    regime_label,
)
from rubrotor.sweeps.sweep import point_metrics, regime_labels, sweep

PERIODIC = LOADED.with_changes(**{"speed.critical_multiple": 1.5})


def test_impacts_per_revolution_equals_rising_edges_of_every_step():
    """Fixed step, every step saved: each onset event is one rising edge of fn > 0."""
    spr = 512
    r = simulate_scenario(
        PERIODIC, Integrator(revolutions=40, dtau=2 * math.pi / spr), progress=False
    )
    fn = r.channels[6 * len(r.stations)]
    t0, t1 = 20 * 2 * math.pi / PERIODIC.speed, 40 * 2 * math.pi / PERIODIC.speed
    inc = fn > 0
    i0 = 20 * spr
    edges = np.count_nonzero(inc[i0 + 1 :] & ~inc[i0:-1])
    assert edges > 0
    assert impacts_per_revolution(r.events, t0, t1, PERIODIC.speed) == pytest.approx(edges / 20)
    assert contact_fraction(fn[i0:]) == pytest.approx(np.mean(inc[i0:]))


def test_classify_uses_the_exponent_when_given():
    torus = np.exp(1j * (np.sqrt(5) - 1) / 2 * 2 * np.pi * np.arange(100))  # no period
    assert classify(0.3, 0.5, torus, 1.0) == (QUASI, 0)  # spectral rule: lines, a curve
    assert classify(0.3, 0.5, torus, 1.0, lyapunov_per_rev=0.0) == (QUASI, 0)
    above = 1.5 * CHAOS_MARGIN_PER_REV
    assert classify(0.3, 0.5, torus, 1.0, lyapunov_per_rev=above) == (CHAOTIC, 0)
    # broadband but a negative exponent: not chaotic
    assert classify(0.3, 0.5, torus, 0.1, lyapunov_per_rev=-0.1) == (QUASI, 0)
    # a period wins over an exponent (a periodic attractor has no positive exponent)
    assert classify(0.3, 0.5, np.tile([1, 2], 50), 1.0, lyapunov_per_rev=1.0) == (PARTIAL, 2)
    assert classify(1.0, np.nan, torus, np.nan) == (FULL, 0)  # unknown ripple: fraction alone
    assert classify(0.0, 0.5, torus, 1.0, lyapunov_per_rev=1.0) == (NO_CONTACT, 0)


def test_reproduction_summary_and_sweep_point_agree_on_one_run():
    """One simulation, labelled from the reproduction's case summary and as a sweep point."""
    revs, n = 240, 64
    ds = simulate(
        PERIODIC,
        integrator=Integrator(revolutions=revs, output_dtau=2 * math.pi / n),
        progress=False,
    )
    m = case_metrics(ds, PERIODIC.contact.clearance)
    p = ds["v"].values[0] + 1j * ds["w"].values[0]  # the contact station
    events = ds["event_time"].values * ds["event_kind"].values
    pm = point_metrics(
        ds["time"].values,
        p,
        ds["normal_force"].values[0],
        events,
        PERIODIC.speed,
        revs // 2,
        revs,
        n,
    )
    label = regime_label(pm["regime"], pm["period"])
    assert label == "partial rub (period-1)"
    assert case_regime(m) == label
    assert m["contact_fraction"] == pytest.approx(pm["contact_fraction"], abs=2 / (revs * n))


@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
def test_sweep_points_get_the_exponent():
    sc = one_mode()
    ds = sweep(
        sc,
        {"speed.critical_multiple": [0.5, 1.3]},
        workers=1,
        transient_revolutions=300,
        revolutions=340,
        samples_per_revolution=32,
        lyapunov=True,
    )
    assert regime_labels(ds).tolist() == ["no contact", "full annular rub"]
    lam = ds["lyapunov_exponent"].values
    sc0 = sc.with_changes(**{"speed.critical_multiple": 0.5})
    re = assemble(sc0.shaft, sc0.speed, sc0.damping).lam.real
    assert np.ptp(re) < 1e-9 * abs(re[0])  # both whirl eigenvalues share the real part
    assert lam[0] == pytest.approx(re[0], rel=1e-9)
    assert lam[1] < 0  # a stable full annular rub
    assert ds["lyapunov_exponent"].attrs["units"] == "1/s"
