"""The rotor's geometry figure (``rubrotor draw``, :func:`rubrotor.draw_rotor`): what is drawn is
what the scenario holds, checked on the artists (the figures were rendered and looked at)."""

from __future__ import annotations

import math

import pytest
from matplotlib.patches import Polygon, Rectangle

import rubrotor
from rubrotor.cli import main
from rubrotor.plotting.geometry import disk_outer_radius


def test_disk_radius_is_the_uniform_disks():
    """Closed form: a solid uniform disk of radius R has ``J = m R^2 / 2``, so the radius drawn
    for a disk built from its geometry (:meth:`rubrotor.Disk.from_geometry`, D = 0.3 m) is
    R = 0.15 m back, to rounding."""
    steel = rubrotor.Material("steel", 211e9, 7810, poisson_ratio=0.3)
    d = rubrotor.Disk.from_geometry(0.5, outer_diameter=0.3, width=0.05, material=steel)
    assert disk_outer_radius(d.mass, d.polar_inertia, 1.0) == pytest.approx(0.15, rel=1e-14)
    assert disk_outer_radius(15.0, 0.0, 0.07) == 0.07  # a disk of mass only: the fallback


def test_general_rotor_parts_are_all_drawn():
    """seal_rub: six sections (two hollow: two bore rectangles), two disks, two bearings (two
    triangles each, over and under the shaft), one contact (two stator blocks), two unbalance
    planes, one tick per finite-element node; the axes say their units and the title names the
    scenario and the speed."""
    sc = rubrotor.load_scenario("seal_rub.toml")
    fig = rubrotor.draw_rotor(sc)
    ax = fig.axes[0]
    rects = [p for p in ax.patches if isinstance(p, Rectangle)]
    tris = [p for p in ax.patches if isinstance(p, Polygon) and not isinstance(p, Rectangle)]
    hatched = [p for p in rects if p.get_hatch()]
    stator = [p for p in rects if p.get_facecolor()[:3] == pytest.approx((0.15,) * 3)]
    assert len(hatched) == len(sc.rotor.disks) == 2
    assert len(tris) == 2 * len(sc.rotor.bearings) == 4
    assert len(stator) == 2 * len(sc.engine.stations) == 2
    assert len(rects) == 6 + 2 + 2 + 2  # sections, bores, disks, stator blocks
    lines = {line.get_label(): line for line in ax.lines}
    nodes = [v for k, v in lines.items() if k.startswith("finite-element nodes")]
    assert len(nodes[0].get_xdata()) == len(sc.rotor.nodes(sc.stations))
    assert ax.get_xlabel() == "axial position x (m)" and ax.get_ylabel() == "radius (m)"
    assert "seal_rub" in ax.get_title() and "628.32 rad/s" in ax.get_title()
    assert "radial clearance 40 µm" in fig.texts[0].get_text()


def test_shaft_scenario_drawn_with_pinned_ends(tmp_path, capsys):
    """The uniform shaft (seed_case1): one section, pinned ends (open triangles), the contact
    at 0.2 m; the verb writes the file it is given, and refuses a file type it cannot write."""
    out = tmp_path / "rotor.svg"
    assert main(["draw", "seed_case1.toml", "--out", str(out)]) == 0
    assert out.read_text().lstrip().startswith("<?xml")
    fig = rubrotor.draw_rotor(rubrotor.load_scenario("seed_case1.toml"))
    tris = [p for p in fig.axes[0].patches if isinstance(p, Polygon)
            and not isinstance(p, Rectangle)]  # fmt: skip
    assert len(tris) == 4 and all(p.get_facecolor()[:3] == (1.0, 1.0, 1.0) for p in tris)
    assert main(["draw", "seed_case1.toml", "--out", str(tmp_path / "rotor.txt")]) == 2
    assert "--out" in capsys.readouterr().err
    assert math.isclose(fig.axes[0].get_xlim()[1], 0.4, rel_tol=0.2)
