"""Figures of periodic orbits: a continuation branch (amplitude against the parameter, stability,
folds and bifurcations) over a follow sweep and the clearance, each returning a
:class:`matplotlib.figure.Figure` not registered with pyplot.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from rubrotor.plotting.sweeps import _axis_label, _key_label

__all__ = ["branch_figure", "contact_geometry"]


def _with_corners(branch, x, r, st):
    """Branch points (key values, radii µm, stability) with the bifurcations inserted.

    Contact onset (the corner at a grazing value, radius the clearance) goes where the radius
    crosses it; a bifurcation whose value lies between two points of different stability goes
    between them. Each corner takes the stability of the point it leads into, so the line
    changes style at the bifurcation, not at the next computed point.
    """
    used = set()
    for b in branch.bifurcations:
        rc = b.max_radius_m * 1e6
        if b.type == "contact-onset":
            i = next((j for j in range(x.size - 1) if (r[j] > rc) != (r[j + 1] > rc)), None)
        else:
            i = next((j for j in range(x.size - 1) if st[j] != st[j + 1]
                      and min(x[j], x[j + 1]) <= b.value <= max(x[j], x[j + 1])), None)  # fmt: skip
        if i is None or (i, b.value) in used or not np.isfinite(rc):
            continue
        used.add((i, b.value))
        x, r, st = (np.insert(a, i + 1, v) for a, v in ((x, b.value), (r, rc), (st, st[i + 1])))
    return x, r, st


def _draw_branch(ax, branch, color, handles, suffix: bool) -> None:
    """One branch: runs of equal stability, solid (stable) or dashed (unstable)."""
    x = np.array([p.value for p in branch.points])
    r = np.array([p.max_radius_m for p in branch.points]) * 1e6
    st = np.array([p.stable for p in branch.points])
    x, r, st = _with_corners(branch, x, r, st)
    edges = [0, *(np.flatnonzero(st[1:] != st[:-1]) + 1), x.size]
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        stop = min(b + 1, x.size)
        ax.plot(x[a:stop], r[a:stop], "-" if st[a] else "--", color=color, lw=1.6)
    name = f"continuation, period-{branch.k}" if suffix else "continuation"
    handles += [
        Line2D([], [], color=color, ls="-", label=f"{name}, stable"),
        Line2D([], [], color=color, ls="--", label=f"{name}, unstable"),
    ]


def _draw_follow(ax, sweep, key, handles) -> None:
    """Up (triangles) and down (circles) sweep points; chaotic ones filled."""
    from rubrotor.sweeps.regimes import CHAOTIC

    for d, marker, color in (("up", "^", "C2"), ("down", "o", "C3")):
        if d not in list(sweep["direction"].values):
            continue
        y = sweep["max_displacement"].sel(direction=d).values * 1e6
        chaos = sweep["regime"].sel(direction=d).values == CHAOTIC
        x = sweep[key].values
        ax.plot(x[~chaos], y[~chaos], marker, color=color, mfc="none", ms=7)
        ax.plot(x[chaos], y[chaos], marker, color=color, ms=7)
        handles.append(Line2D([], [], ls="", marker=marker, color=color, mfc="none",
                              label=f"follow sweep {d}"))  # fmt: skip
        if chaos.any():
            handles.append(Line2D([], [], ls="", marker=marker, color=color,
                                  label=f"follow sweep {d}, chaotic"))  # fmt: skip


def contact_geometry(scenario) -> dict | None:
    """The first contact's clearance and stator offset (m) and what moves the orbit's centre.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A scenario with a contact (seed ``[contact]`` or general ``[[contact]]``).

    Returns
    -------
    dict or None
        ``{"clearance", "offset"}`` (m) and ``"why"``: the reasons the radius about the
        bearing axis differs from the radius about the stator centre (offset stator, gravity
        sag, side load, flexible stator); None without a contact.
    """
    from rubrotor.modelling import model_of

    spec = scenario.engine
    if model_of(scenario).contact_stations:
        st = spec.stations[0]
        g, off, flexible = st.contact.clearance, math.hypot(st.offset_y, st.offset_z), st.stator
        why = [f"stator centre offset {off * 1e6:.3g} µm"] if off > 0 else []
        why += ["gravity sag"] if any(spec.gravity) else []
        why += ["side load"] if spec.loads else []
        why += ["flexible stator"] if flexible is not None else []
        return {"clearance": g, "offset": off, "why": why}
    if scenario.contact is None:
        return None
    why = ["side load"] if scenario.load is not None else []
    return {"clearance": scenario.contact.clearance, "offset": 0.0, "why": why}


def _draw_clearance(ax, geometry: dict, handles) -> None:
    """The clearance line and, for an offset stator, the band ``g -+ |offset|`` of radii about
    the bearing axis at which the orbit can first touch."""
    g, off = geometry["clearance"] * 1e6, geometry["offset"] * 1e6
    ax.axhline(g, color="k", lw=0.9, ls=":")
    handles.append(Line2D([], [], color="k", lw=0.9, ls=":", label=f"clearance {g:.3g} µm"))
    if off > 0:
        ax.axhspan(g - off, g + off, color="0.85", zorder=0)
        handles.append(Patch(color="0.85", label="first touch possible (clearance ± offset)"))
    if geometry["why"]:
        ax.set_title("radius about the bearing axis; the stator centre differs by: "
                     + ", ".join(geometry["why"]), fontsize=8, loc="left", color="0.3")  # fmt: skip


def branch_figure(branch, sweep=None, others=(), geometry: dict | None = None) -> Figure:
    """A continued branch (stable solid, unstable dashed, bifurcations marked) over a sweep.

    Parameters
    ----------
    branch : rubrotor.orbits.continuation.Branch
        The branch; largest orbit radius (m) against the continued key.
    sweep : xarray.Dataset, optional
        A state-carrying sweep (:func:`rubrotor.sweeps.follow.follow_sweep`) of the same key: its
        ``max_displacement`` (m) per direction, up as triangles, down as circles; points
        labelled chaotic (by a positive largest Lyapunov exponent when the sweep computed it)
        are filled.
    others : sequence of rubrotor.orbits.continuation.Branch
        More branches of the same key (e.g. from
        :func:`rubrotor.orbits.continuation.switch_period_doubling`), one colour each, labelled by
        their period in revolutions.
    geometry : dict, optional
        :func:`rubrotor.plotting.orbits.contact_geometry` of the scenario: draws the clearance (and, for an offset
        stator, the band of radii where the orbit can first touch) and says why the radius
        about the bearing axis differs from the one about the stator centre.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(7.5, 4.8))
    ax = fig.add_subplot()
    handles = []
    for i, br in enumerate((branch, *others)):
        _draw_branch(ax, br, f"C{[0, 1, 4, 5, 6][i % 5]}", handles, suffix=bool(others))
    if sweep is not None:
        _draw_follow(ax, sweep, branch.key, handles)
    if geometry is not None:
        _draw_clearance(ax, geometry, handles)
    marks = {"fold": "s", "period-doubling": "D", "neimark-sacker": "*", "branch-point": "X",
             "contact-onset": "v"}  # fmt: skip
    bifs = [b for br in (branch, *others) for b in br.bifurcations]
    for b in bifs:
        ax.plot(b.value, b.max_radius_m * 1e6, marks[b.type], color="k", ms=8)
    for t in sorted({b.type for b in bifs}):
        handles.append(Line2D([], [], ls="", marker=marks[t], color="k", label=t))
    ax.set_xlabel(_key_label(branch.key) if sweep is None else _axis_label(sweep, branch.key))
    ax.set_ylabel("largest orbit radius at contact station (µm)")
    ax.grid(alpha=0.3)
    ax.legend(handles=handles, fontsize=8)
    fig.tight_layout()
    return fig
