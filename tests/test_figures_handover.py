"""Figures an engineer can hand on (issue 31): units on the axes, the screening band readable,
clearances named for what they are. Checked on the artists; every figure was rendered and looked
at."""

from __future__ import annotations

import numpy as np
import pytest

from rubrotor.linear.api617 import ClearanceCheck
from rubrotor.linear.api684 import Level1
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


def test_separation_margin_api_formula():
    """API 617 / 684 by hand: AF 2 needs none; AF 3.5 below the run range 17 (1 - 1/2) = 8.5 %,
    above it 10 + 8.5 = 18.5 %; AF 100 hits the caps, 16 % below and 26 % above."""
    from rubrotor.plotting.linear import margin_band, separation_margin

    assert separation_margin(2.0, False) == 0.0 and separation_margin(2.0, True) == 0.0
    assert separation_margin(3.5, False) == pytest.approx(0.085, rel=1e-14)
    assert separation_margin(3.5, True) == pytest.approx(0.185, rel=1e-14)
    assert (separation_margin(100.0, False), separation_margin(100.0, True)) == (0.16, 0.26)
    lo, hi = margin_band(380.0, 1 / 7.0)  # zeta = 1 / (2 AF), AF 3.5
    assert (lo, hi) == pytest.approx((380.0 / 1.185, 380.0 / 0.915), rel=1e-14)


@pytest.mark.parametrize("zeta", [0.05, 0.01, 0.0005])
def test_amplification_factor_of_one_mode(zeta):
    """One mode's unbalance response ``r^2 / |1 - r^2 + 2 i zeta r|``: the half-power estimate
    of the sampled curve (a uniform pass, then the phase-spaced grid of ``half_power_speeds``)
    matches the same definition evaluated on a 400,001-point grid through the peak to 0.5 %, and
    the textbook ``AF = 1 / (2 zeta)`` to ``3 zeta`` (relative; they differ at O(zeta))."""
    from rubrotor.plotting.linear import amplification_factors, half_power_speeds

    def amp(r):
        return r**2 / np.abs(1 - r**2 + 2j * zeta * r)

    r = np.linspace(0.2, 2.0, 2001)
    first = amplification_factors(r, amp(r))
    grid = np.unique(np.concatenate([r, half_power_speeds(first, r[0], r[-1], 401)]))
    ((w, _, af),) = amplification_factors(grid, amp(grid))
    peak = amp(np.array([w]))[0]
    fine = np.linspace(w * (1 - 20 * zeta), w * (1 + 20 * zeta), 400001)
    a = amp(fine)
    inside = fine[a >= peak / np.sqrt(2)]
    assert af == pytest.approx(w / (inside[-1] - inside[0]), rel=5e-3)
    assert af == pytest.approx(1 / (2 * zeta), rel=3 * zeta + 1e-3)


def test_interactive_pages_hold_their_data(tmp_path):
    """plotly pages (the 'interactive' extra): self-contained (plotly.js inlined, no script
    from the network), with the axes' units; the Campbell page carries every speed."""
    pytest.importorskip("plotly")
    from rubrotor.linear.campbell import CampbellData
    from rubrotor.linear.critical import LinearCritical
    from rubrotor.plotting.interactive import campbell_html, write_html

    speeds = np.linspace(0.0, 600.0, 13)
    data = CampbellData(speeds, np.full((13, 2), 60.0), np.full((13, 2), 0.05),
                        np.array([["forward", "backward"]] * 13))  # fmt: skip
    crit = [LinearCritical(1, "forward", 1.0, 377.0, 0.01)]
    fig = campbell_html(data, crit, 340.0, "Campbell diagram: test", (300.0, 340.0))
    assert fig.layout.xaxis.title.text == "spin speed (rad/s)"
    assert fig.layout.yaxis.title.text == "damped natural frequency (Hz)"
    out = tmp_path / "c.html"
    write_html(fig, out)
    text = out.read_text()
    assert '<script src="http' not in text and "plotly" in text.lower()
    assert sum(len(t.x) for t in fig.data[:2]) == 26


def test_static_figure_draws_no_arrow_for_a_zero_reaction_and_keeps_labels_inside():
    """general_rotor's z reactions are round-off (2.7e-11 N against 442 N): no arrow, printed
    as 0 N; the right bearing's label is right-aligned (it points inwards, not off the edge)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from rubrotor.linear.static import BearingReaction, StaticResult
    from rubrotor.plotting.response import static_figure

    x = np.linspace(0.0, 1.3, 27)
    sag = -50e-6 * np.sin(np.pi * x / 1.3)
    bearings = (BearingReaction("left bearing", 0.05, 442.0, 2.66e-11),
                BearingReaction("right bearing", 1.25, 413.1, -1.1e-11))  # fmt: skip
    res = StaticResult(0.0, (-9.81, 0.0), x, np.column_stack([sag, 0 * sag]), bearings,
                       np.zeros(4), np.zeros(4))  # fmt: skip
    fig = static_figure(res, "static deflection: general_rotor")
    ax_f = fig.axes[1]
    arrows = [t for t in ax_f.texts if t.get_text() == ""]
    labels = [t for t in ax_f.texts if t.get_text()]
    assert len(arrows) == 2  # the two y reactions only
    assert all("F_z = 0 N" in t.get_text() for t in labels)
    assert [t.get_ha() for t in labels] == ["left", "right"]
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    width = fig.bbox.width
    for t in labels:
        box = t.get_window_extent(canvas.get_renderer())
        assert 0 <= box.x0 and box.x1 <= width


def test_touchdown_contacts_that_move_alike_stay_visible():
    """Two contacts with the same orbit (a symmetric drop): contact 1 is drawn wide and solid
    underneath, contact 2 narrower and dashed on top, so the reader sees both (the old figure
    hid contact 1 and ring 1 under contact 2 and ring 2)."""
    import xarray as xr

    from rubrotor.plotting.touchdown import touchdown_figure

    t = np.linspace(0.0, 0.02, 401)
    orbit = 200e-6 * np.exp(1j * 300.0 * t)
    two = np.vstack([orbit, orbit])
    ds = xr.Dataset(
        {
            "v": (("contact", "time"), two.real), "w": (("contact", "time"), two.imag),
            "clearance": ("contact", [250e-6, 250e-6]),
            "normal_force": (("contact", "time"), np.zeros((2, t.size))),
            "ring_speed": (("contact", "time"), np.full((2, t.size), 50.0)),
            "contact_radius": ("contact", [0.03, 0.03]), "ring_radius": ("contact", [0.04, 0.04]),
            "spin_speed": ("time", np.full(t.size, 1000.0)),
        },
        coords={"time": t, "station": ("contact", [0.05, 0.75])},
        attrs={"scenario_name": "touchdown_drop"},
    )  # fmt: skip
    fig = touchdown_figure(ds)
    for ax in fig.axes:
        one = [ln for ln in ax.lines if ln.get_label().endswith("contact 1 at 0.05 m")
               or ln.get_label() == "ring 1"]  # fmt: skip
        two_ = [ln for ln in ax.lines if ln.get_label().endswith("contact 2 at 0.75 m")
                or ln.get_label() == "ring 2"]  # fmt: skip
        for a, b in zip(one, two_, strict=True):
            assert a.get_linestyle() != b.get_linestyle()
            assert a.get_linewidth() > b.get_linewidth() and a.get_zorder() < b.get_zorder()
