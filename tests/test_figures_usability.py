"""Issue 23, "figures that hold up": what a reader needs from each figure, checked on the drawn
artists (the figures themselves were rendered to PNG and looked at)."""

from __future__ import annotations

import ast
import itertools
import math
from pathlib import Path

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.text import Text

import rubrotor
from rubrotor.linear.campbell import CampbellData
from rubrotor.linear.critical import LinearCritical
from rubrotor.plotting.linear import _LOGDEC_CMAP, campbell_stability_figure
from rubrotor.plotting.rub import per_revolution

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _luminance(rgba) -> float:
    """Relative luminance (ITU-R BT.709 weights on the sRGB components)."""
    r, g, b = rgba[:3]
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def test_campbell_labels_never_overlap_and_light_damping_is_dark():
    """Four critical speeds within 3 % of each other (general_rotor's 368, 379, 468, 478
    rad/s came out on top of each other): their label boxes, measured on the rendered canvas,
    are pairwise disjoint. The colour of log dec 0 is dark (luminance < 0.2) and that of the
    well-damped end is not pale on white (< 0.75; viridis_r's yellow was 0.87)."""
    speeds = np.linspace(0.0, 1500.0, 31)
    freq = np.stack([np.full(31, 60.0), np.full(31, 62.0), np.full(31, 75.0)], axis=1)
    data = CampbellData(speeds, freq, np.full((31, 3), 0.05), np.full((31, 3), "forward"))
    crit = [LinearCritical(i + 1, "forward", 1.0, w) for i, w in enumerate((368, 372, 376, 380))]
    fig = campbell_stability_figure(data, crit, operating_speed=628.0)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    boxes = [Text.get_window_extent(t, renderer) for t in fig.axes[0].texts]  # text, no arrow
    assert len(boxes) == 4
    for a, b in itertools.combinations(boxes, 2):
        assert not a.overlaps(b)
    assert _luminance(_LOGDEC_CMAP(0.0)) < 0.2
    assert _luminance(_LOGDEC_CMAP(1.0)) < 0.75


def test_per_revolution_envelope():
    """Closed form: ``sin(tau + 0.3) + k`` in revolution ``k`` has maximum ``k + 1`` and minimum
    ``k - 1``; sampled 1000 times per revolution the sampled extremes miss them by at most
    ``(2 pi / 1000)^2 / 2 = 2e-5``; the incomplete last revolution is left out."""
    tau = np.linspace(0.0, 2 * math.pi * 7.5, 7501)
    x = np.sin(tau + 0.3) + np.floor(tau / (2 * math.pi))
    starts, vmax, vmin = per_revolution(tau, x)
    assert starts.size == 7
    np.testing.assert_allclose(vmax, np.arange(7) + 1.0, atol=3e-5)
    np.testing.assert_allclose(vmin, np.arange(7) - 1.0, atol=3e-5)


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("plot_*.py")), ids=lambda p: p.name)
def test_gallery_blocks_end_without_a_repr(path):
    """sphinx-gallery prints the value of an expression closing a code block: a bare
    ``ax.legend()`` put ``<matplotlib.legend.Legend object at 0x...>`` on the run-up page.
    Only ``print(...)`` may close a block."""
    for block in path.read_text().split("\n# %%"):
        body = ast.parse(block).body
        if body and isinstance(body[-1], ast.Expr):
            call = body[-1].value
            assert isinstance(call, ast.Call) and getattr(call.func, "id", "") == "print", (
                ast.unparse(body[-1])
            )


def _seal_like_branch():
    from rubrotor.orbits.continuation import Branch, BranchPoint

    values = np.linspace(600.0, 800.0, 11)
    pts = tuple(BranchPoint(float(v), None, 60e-6 + 1e-7 * (v - 600.0), np.zeros(2), True)
                for v in values)  # fmt: skip
    return Branch("speed.rad_per_s", 1, pts, ())


def test_branch_figure_draws_the_clearance_and_says_why_the_radius_exceeds_it():
    """seal_rub's no-contact orbit lies at 60-65 um about the bearing axis against a 40 um
    clearance: the figure draws the clearance, the band of radii where an orbit can first touch
    a stator offset by 25 um (15 .. 65 um), and names the offset, gravity sag and the flexible
    stator, read from the scenario (:func:`rubrotor.plotting.orbits.contact_geometry`)."""
    from matplotlib.patches import Rectangle

    from rubrotor.plotting.orbits import branch_figure, contact_geometry

    geometry = contact_geometry(rubrotor.load_scenario("seal_rub.toml"))
    assert geometry["clearance"] == 40e-6 and geometry["offset"] == pytest.approx(25e-6)
    assert geometry["why"] == ["stator centre offset 25 µm", "gravity sag", "flexible stator"]
    fig = branch_figure(_seal_like_branch(), geometry=geometry)
    ax = fig.axes[0]
    assert any(np.allclose(line.get_ydata(), 40.0) for line in ax.lines)
    band = [p for p in ax.patches if isinstance(p, Rectangle)]
    assert len(band) == 1
    y0, y1 = band[0].get_bbox().y0, band[0].get_bbox().y1
    assert (y0, y1) == pytest.approx((15.0, 65.0))
    assert "gravity sag" in ax.get_title(loc="left")


def test_resonance_speeds_make_the_polar_circle_smooth():
    """Closed form: a one-degree-of-freedom receptance ``1 / (k - m w^2 + i c w)`` (zeta 1 %)
    turns its phase by 180 degrees within about 2 zeta of its natural frequency. On 100 uniform
    speeds the polar curve jumps by tens of degrees near the peak; on the grid refined by
    :func:`rubrotor.plotting.linear.resonance_speeds` no step exceeds 5 degrees."""
    from rubrotor.plotting.linear import resonance_speeds

    m, k, zeta = 1.0, 1e4, 0.01
    wn = math.sqrt(k / m)

    def phase_steps(w):
        h = 1 / (k - m * w**2 + 2j * zeta * wn * m * w)
        return np.degrees(np.abs(np.diff(np.unwrap(np.angle(h)))))

    coarse = np.linspace(10.0, 300.0, 100)
    fine = resonance_speeds(coarse, 1 / np.abs(k - m * coarse**2 + 2j * zeta * wn * m * coarse))
    assert phase_steps(coarse).max() > 30.0
    assert phase_steps(fine).max() < 5.0
    assert fine[0] == coarse[0] and fine[-1] == coarse[-1] and np.all(np.diff(fine) > 0)
