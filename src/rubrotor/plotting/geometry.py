"""The rotor's geometry as a figure: shaft sections, disks, bearings, contacts (seals, rub
stations, touchdown rings), unbalance planes and the finite-element nodes, drawn in an axial
section as ROSS draws a rotor. Readable in grey scale (hatching and marker shapes, not colour).

:func:`draw_rotor` takes a loaded scenario (a general finite-element rotor or the uniform
continuous shaft) and returns a :class:`matplotlib.figure.Figure` not registered with pyplot;
``rubrotor draw SCENARIO --out rotor.png`` writes it.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Polygon, Rectangle

from rubrotor.modelling import model_of

__all__ = ["draw_rotor", "disk_outer_radius"]

_SHAFT = {"facecolor": "0.8", "edgecolor": "k", "lw": 0.8}
_DISK = {"facecolor": "0.55", "edgecolor": "k", "lw": 0.8, "hatch": "///"}
_STATOR = {"facecolor": "0.15", "edgecolor": "k", "lw": 0.8}


def disk_outer_radius(mass: float, polar_inertia: float, fallback: float) -> float:
    """Radius (m) of the uniform solid disk of the same mass (kg) and polar inertia (kg m^2):
    ``sqrt(2 J / m)``; ``fallback`` (m) when either is zero (a disk given by its mass only)."""
    if mass > 0 and polar_inertia > 0:
        return math.sqrt(2.0 * polar_inertia / mass)
    return fallback


def _radius_at(sections, x: float) -> float:
    for x0, length, r, _ in sections:
        if x0 - 1e-12 <= x <= x0 + length + 1e-12:
            return r
    return sections[-1][2]


def _support(ax, x: float, r: float, size: float, label: str, pinned: bool) -> None:
    """A bearing: triangles under and over the shaft (filled for a bearing with coefficients,
    open for a pinned support), with a spring zig-zag to the ground line (none when pinned)."""
    for sign in (-1.0, 1.0):
        tip = sign * r
        base = sign * (r + size)
        tri = Polygon([(x, tip), (x - 0.5 * size, base), (x + 0.5 * size, base)], closed=True,
                      facecolor="white" if pinned else "0.35", edgecolor="k", lw=0.9, zorder=4)  # fmt: skip
        ax.add_patch(tri)
        ground = base
        if not pinned:
            zz = base + sign * np.linspace(0, 1.2 * size, 7)
            ax.plot(x + 0.25 * size * np.array([0, -1, 1, -1, 1, -1, 0]), zz, "k", lw=0.8)
            ground = base + sign * 1.2 * size
        ax.plot([x - 0.6 * size, x + 0.6 * size], [ground, ground], "k", lw=1.6)
    ax.annotate(label, (x, -(r + 2.4 * size)), ha="center", va="top", fontsize=8)


def _contacts(ax, scenario, sections, size: float) -> list[str]:
    """Stator blocks at each contact (gap drawn at a visible size, not to scale); returns the
    legend lines naming each contact's clearance."""
    notes = []
    model = model_of(scenario)
    if model.contact_stations:
        stations = [(st.contact, st.stator is not None, math.hypot(st.offset_y, st.offset_z))
                    for st in model.contact_stations]  # fmt: skip
    elif model.first_contact is not None:
        stations = [(model.first_contact, False, 0.0)]
    else:
        return notes
    for i, (c, flexible, offset) in enumerate(stations, 1):
        r = c.radius if c.radius else _radius_at(sections, c.position)
        gap, w = 0.35 * size, 0.8 * size
        for sign in (-1.0, 1.0):
            y0 = sign * (r + gap) if sign > 0 else -(r + gap + size)
            ax.add_patch(Rectangle((c.position - w / 2, y0), w, size, zorder=5, **_STATOR))
        if c.radius and c.radius > _radius_at(sections, c.position):
            ax.add_patch(Rectangle((c.position - w / 2, -c.radius), w, 2 * c.radius,
                                   facecolor="0.8", edgecolor="k", lw=0.6, zorder=3))  # fmt: skip
        ax.annotate(f"C{i}", (c.position, r + gap + size), xytext=(0, 3),
                    textcoords="offset points", ha="center", va="bottom", fontsize=8)  # fmt: skip
        extra = ", flexible stator" if flexible else ""
        extra += f", stator offset {offset * 1e6:.3g} µm" if offset > 0 else ""
        notes.append(f"C{i}: contact at x = {c.position:g} m, radial clearance "
                     f"{c.clearance * 1e6:.4g} µm{extra}")  # fmt: skip
    return notes


def _disks(ax, geometry, sections, length: float) -> list[str]:
    notes = []
    for d in geometry.disks:
        r = disk_outer_radius(d.mass, d.polar_inertia, 2.0 * _radius_at(sections, d.position))
        w = d.width if d.width > 0 else 0.02 * length
        ax.add_patch(Rectangle((d.position - w / 2, -r), w, 2 * r, zorder=3, **_DISK))
        name = d.name or "disk"
        ax.annotate(name, (d.position, r), xytext=(0, 3), textcoords="offset points",
                    ha="center", va="bottom", fontsize=8)  # fmt: skip
        notes.append(f"{name}: {d.mass:.3g} kg at x = {d.position:g} m")
    return notes


def _supports(ax, geometry, sections, size: float) -> None:
    for x, label, pinned in geometry.supports:
        _support(ax, x, _radius_at(sections, x), size, label, pinned)


def draw_rotor(scenario, *, nodes: bool = True, title: str | None = None) -> Figure:
    """The rotor's geometry in an axial section: sections (bores white), disks (hatched),
    bearings (triangles and springs to ground), contacts (dark stator blocks, labelled C1, C2,
    ...), unbalance planes (U) and, optionally, the finite-element nodes (ticks on the axis).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A loaded scenario (:func:`rubrotor.load_scenario`): a general rotor or the uniform shaft.
    nodes : bool
        Draw the mesh's nodes (finite-element rotor only) as ticks on the axis.
    title : str, optional
        Figure title (default: the scenario's name, its length, mass and speed).

    Returns
    -------
    matplotlib.figure.Figure
        Axial position x (m) across, radius (m) up, to the same scale; a disk given by mass and inertia is drawn
        as the uniform disk of the same mass and polar inertia; contact gaps are enlarged to be
        visible and their clearances (µm) are listed under the drawing.
    """
    geometry = model_of(scenario).geometry()
    sections, length = list(geometry.sections), geometry.length
    rmax = max(s[2] for s in sections)
    size = max(0.35 * rmax, 0.022 * length)
    fig = Figure(figsize=(11, 5.2), layout="constrained")
    ax = fig.subplots()
    for x0, ln, r, bore in sections:
        ax.add_patch(Rectangle((x0, -r), ln, 2 * r, zorder=2, **_SHAFT))
        if bore > 0:
            ax.add_patch(Rectangle((x0, -bore), ln, 2 * bore, facecolor="white", edgecolor="k",
                                   lw=0.6, ls="--", zorder=2))  # fmt: skip
    ax.axhline(0.0, color="k", lw=0.6, ls="-.", zorder=6)
    notes = _disks(ax, geometry, sections, length)
    _supports(ax, geometry, sections, size)
    notes += _contacts(ax, scenario, sections, size)
    for k, u in enumerate(scenario.unbalances or ()):
        ax.plot(u.position, 0.0, "kv", ms=7, mfc="white", zorder=7,
                label="unbalance plane" if k == 0 else None)  # fmt: skip
    if nodes and geometry.nodes:
        xs = np.asarray(geometry.nodes)
        ax.plot(xs, np.zeros_like(xs), "|", color="k", ms=6, zorder=7,
                label=f"finite-element nodes ({len(xs)})")  # fmt: skip
    mass = geometry.mass
    head = title or (f"{scenario.name}: rotor geometry, length {length:g} m"
                     + (f", mass {mass:.4g} kg" if mass else "")
                     + f", speed {scenario.speed:.5g} rad/s ({scenario.speed * 30 / math.pi:.0f} rpm)")  # fmt: skip
    ax.set_title(head, fontsize=11)
    ax.set_xlabel("axial position x (m)")
    ax.set_ylabel("radius (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale_view()
    ax.margins(x=0.04, y=0.12)
    if ax.get_legend_handles_labels()[0]:
        fig.legend(fontsize=8, loc="lower right")
    if notes:
        fig.text(0.01, 0.005, "\n".join(notes), fontsize=8, va="bottom", ha="left")
        fig.get_layout_engine().set(
            rect=(0, 0.018 * (len(notes) + 1), 1, 1 - 0.018 * (len(notes) + 1))
        )
    ax.grid(alpha=0.25)
    return fig
