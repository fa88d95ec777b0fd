"""Figures an engineer can hand on (issue 31): units on the axes, the screening band readable,
clearances named for what they are. Checked on the artists; every figure was rendered and looked
at."""

from __future__ import annotations

import numpy as np
import pytest

from rubrotor.linear.api import ClearanceCheck, Level1
from rubrotor.plotting.response import clearance_figure, level1_figure


def _level1() -> Level1:
    """A curve shaped like general_rotor's: log dec 0.09 falling to -5.5 over Q = 1e4-1e9 N/m;
    its zero crossing is put in by hand (Q0 = 4.4e5 N/m)."""
    q = np.logspace(4, 9, 41)
    ld = 0.09 - 5.6 * (1 - np.exp(-q / 3e7))
    return Level1(628.3, 0.45, q, ld, np.full_like(q, 75.0), 4.4e5, 2e5)


def test_level1_screening_band_is_not_squashed():
    """The old single panel spread -5.5..0.1 over its height, so the 0-0.1 band took 2 % of
    it; the screening panel's y range is -0.05..0.2 (the 0-0.1 band is 40 % of its height),
    every panel says its units, the title says the speed in rad/s and rpm."""
    fig = level1_figure(_level1(), "API 684 Level I: general_rotor")
    whole, band = fig.axes
    lo, hi = band.get_ylim()
    assert (lo, hi) == pytest.approx((-0.05, 0.2))
    assert 0.1 / (hi - lo) == pytest.approx(0.4)
    for ax in fig.axes:
        assert ax.get_xlabel() == "added cross-coupled stiffness Q (N/m)"
        assert ax.get_ylabel() == "logarithmic decrement (1)"
    title = fig._suptitle.get_text()
    assert "general_rotor" in title and "628.3 rad/s" in title and "6000 rpm" in title
    styles = {line.get_linestyle() for line in band.lines}
    assert {"-", "--", "-.", ":"} <= styles  # grey-scale readable: four line styles


def test_clearance_labels_say_diametral_and_name_the_operating_range():
    """The 80 µm of the check is the diametral clearance 2c (radial 40 µm); the shaded band is
    named with its speeds; every probe is drawn."""
    s = np.linspace(0.0, 800.0, 81)
    check = ClearanceCheck(
        s, 440.0, 628.3, [], np.vstack([1e-6 * np.ones_like(s), 2e-6 * np.ones_like(s)]),
        25.4e-6, 2e-6, 6.0, ["contact 1 at 0.75 m"], np.array([0.75]), np.array([80e-6]),
        np.array([50e-6 * np.ones_like(s)]),
    )  # fmt: skip
    fig = clearance_figure(check, "API 617 clearance check: seal_rub")
    top, bottom = fig.axes
    labels = top.get_legend_handles_labels()[1]
    assert any("diametral clearance 2c = 80 µm (radial 40 µm)" in t for t in labels)
    assert any(t == "operating range 440-628.3 rad/s" for t in labels)
    assert len([t for t in bottom.get_legend_handles_labels()[1] if t.startswith("probe")]) == 2
    assert all("µm" in ax.get_ylabel() for ax in fig.axes)
