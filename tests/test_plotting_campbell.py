"""Campbell figure: structure, labels, markers; no global side effects."""

from __future__ import annotations

import io

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure
from seed import seed_shaft as shaft

from rubrotor.linear.shaft import critical_speeds
from rubrotor.plotting import campbell_figure

SPEEDS = np.linspace(0, 60000, 60)


def _markers(fig):
    return [
        line
        for ax in fig.axes
        for line in ax.get_lines()
        if line.get_marker() == "D" and line.get_linestyle() == "None"
    ]


def test_timoshenko_two_panels_and_labels():
    rc_before = dict(matplotlib.rcParams)
    fig = campbell_figure(shaft(), SPEEDS, operating_speed=11614.0)
    assert isinstance(fig, Figure)
    assert dict(matplotlib.rcParams) == rc_before
    main_axes = [ax for ax in fig.axes if ax.get_ylabel()]
    assert len(main_axes) == 2
    shear_ax, bend_ax = main_axes
    assert "(Hz)" in bend_ax.get_ylabel() and "(Hz)" in shear_ax.get_ylabel()
    assert "(rad/s)" in bend_ax.get_xlabel()
    # shear panel sits above the bending panel's range
    assert shear_ax.get_ylim()[0] > bend_ax.get_ylim()[1]
    # one diamond per critical speed inside the range, annotated with its speed
    expected = [c for c in critical_speeds(shaft()) if c.speed_rad_s <= 60000]
    marks = _markers(fig)
    assert len(marks) == len(expected) == 6
    xs = sorted(float(m.get_xdata()[0]) for m in marks)
    assert xs == pytest.approx([c.speed_rad_s for c in expected])
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert "1F: 7742 rad/s" in texts
    assert any(t.startswith("operating: 11614 rad/s") for t in texts)
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    for label in ("forward whirl (F)", "backward whirl (B)", "shear branch", "critical speed"):
        assert label in legend
    # the 1X line: frequency in Hz = spin / 2 pi
    spin = [ln for ln in bend_ax.get_lines() if ln.get_linestyle() == ":"][0]
    np.testing.assert_allclose(spin.get_ydata(), SPEEDS / (2 * np.pi))


def test_curves_match_whirl_frequencies():
    fig = campbell_figure(shaft(), SPEEDS)
    bend_ax = [ax for ax in fig.axes if ax.get_ylabel()][1]
    solid = [ln for ln in bend_ax.get_lines() if ln.get_linestyle() == "-"]
    assert len(solid) == 6  # 3 modes x forward/backward
    at_rest = sorted(float(ln.get_ydata()[0]) for ln in solid)
    assert at_rest == pytest.approx([1193.2, 1193.2, 4153.2, 4153.2, 7970.7, 7970.7], abs=0.05)


@pytest.mark.parametrize("theory", ["rayleigh", "euler-bernoulli"])
def test_single_panel_for_other_theories(theory):
    fig = campbell_figure(shaft(theory=theory), SPEEDS)
    assert len([ax for ax in fig.axes if ax.get_ylabel()]) == 1
    assert "shear branch" not in [t.get_text() for t in fig.legends[0].get_texts()]


def test_renders_headless_png():
    fig = campbell_figure(shaft(), SPEEDS, operating_speed=11614.0)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    assert buf.getvalue()[:4] == b"\x89PNG"
    import matplotlib.pyplot as plt

    assert plt.get_fignums() == []  # not registered with pyplot
