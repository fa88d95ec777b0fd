"""Figures of the linear analyses of any rotor: Campbell diagram with stability, unbalance
response (Bode and polar) and mode shapes. One function per figure kind, each returning a
:class:`matplotlib.figure.Figure` that is not registered with pyplot.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from rubrotor.linear.campbell import CampbellData
from rubrotor.linear.critical import LinearCritical
from rubrotor.linear.modes import DampedMode
from rubrotor.linear.response import UnbalanceResponse
from rubrotor.linear.shapes import ModeShapes, node_whirl
from rubrotor.linear.ucs import UCSMap
from rubrotor.rotors.linear import LinearSystem

__all__ = [
    "resonance_speeds",
    "campbell_stability_figure",
    "unbalance_response_figure",
    "mode_shape_figure",
    "ucs_figure",
    "mode_shapes_3d_figure",
]

TWO_PI = 2 * np.pi


def campbell_stability_figure(
    data: CampbellData,
    criticals: list[LinearCritical] = (),
    operating_speed: float | None = None,
    title: str = "Campbell diagram",
) -> Figure:
    """Damped frequencies against spin speed, coloured by logarithmic decrement.

    Stable modes are dots coloured by log dec (saturating at 1, well damped; the lightly damped
    modes dark); unstable points (log dec < 0) are red crosses. The 1X line is dotted, critical
    speeds are diamonds labelled in rows of their own above the highest one.

    Parameters
    ----------
    data : CampbellData
        From :func:`rubrotor.linear.campbell.campbell_data`.
    criticals : list of LinearCritical
        Critical speeds to mark.
    operating_speed : float, optional
        Spin speed (rad/s) drawn as a vertical line.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(9, 5.5), layout="constrained")
    ax = fig.subplots()
    s = np.repeat(data.speeds[:, None], data.frequency_hz.shape[1], axis=1)
    f, ld = data.frequency_hz, data.log_dec
    stable = ld >= 0
    # colour saturates at log dec 1 (well damped); lightly damped modes, the ones that matter,
    # are dark and saturated, well damped ones light orange (never pale on white)
    sc = ax.scatter(s[stable], f[stable], c=np.minimum(ld[stable], 1.0), s=9, cmap=_LOGDEC_CMAP,
                    vmin=0.0, vmax=1.0)  # fmt: skip
    if (~stable).any():
        ax.scatter(s[~stable], f[~stable], marker="x", c="r", s=18, label="unstable (log dec < 0)")
    fmax = float(np.nanmax(f)) * 1.05
    ax.plot(data.speeds, data.speeds / TWO_PI, "k:", lw=1, label="1X")
    _label_criticals(ax, criticals, fmax)
    if operating_speed:
        ax.axvline(operating_speed, color="0.5", lw=1, ls="--", label="operating speed")
    ax.set(
        xlabel="spin speed (rad/s)",
        ylabel="damped natural frequency (Hz)",
        ylim=(0, fmax),
        xlim=(data.speeds[0], data.speeds[-1]),
        title=title,
    )
    fig.colorbar(sc, ax=ax, extend="max", label="logarithmic decrement (1), stable modes")
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def _logdec_cmap():
    """Log dec 0 (lightly damped) dark blue-violet, 1 (well damped) orange: ``plasma`` cut
    before its pale yellow end, so that every point stands out on white."""
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap

    return ListedColormap(colormaps["plasma"](np.linspace(0.0, 0.8, 256)), name="logdec")


_LOGDEC_CMAP = _logdec_cmap()


def _label_criticals(ax, criticals, fmax: float) -> None:
    """Critical speeds as diamonds, labelled in a column of their own rows (never overlapping,
    however close the speeds), each joined to its diamond by a thin leader line."""
    crit = sorted(criticals, key=lambda c: c.speed_rad_s)
    if not crit:
        return
    ys = [c.harmonic * c.speed_rad_s / TWO_PI for c in crit]
    ax.plot([c.speed_rad_s for c in crit], ys, "D", mfc="gold", mec="k", ms=6, zorder=5,
            label="critical speed (1X crossing)")  # fmt: skip
    row = 0.055 * fmax  # one text row, well above an 8 pt line on a 5.5 in tall figure
    base = max(ys) + 2.0 * row
    for i, (c, y) in enumerate(zip(crit, ys, strict=True)):
        ax.annotate(
            f"{c.speed_rad_s:.0f} rad/s, {c.speed_rad_s * 60 / TWO_PI:.0f} rpm ({c.whirl})",
            (c.speed_rad_s, y),
            xytext=(c.speed_rad_s, base + i * row),
            textcoords="data",
            fontsize=8,
            ha="left",
            va="center",
            bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "0.7", "lw": 0.5},
            arrowprops={"arrowstyle": "-", "color": "0.4", "lw": 0.6},
            zorder=6,
        )


def unbalance_response_figure(
    resp: UnbalanceResponse, probe: int = 0, clearance: float | None = None
) -> Figure:
    """Bode (amplitude and phase of ``v`` and ``w`` against speed) and polar plot at one probe.

    The curves join the computed speeds with straight lines: sample a resonance densely (a few
    hundred speeds within 10 % of a critical speed) for a smooth polar circle.

    Parameters
    ----------
    resp : UnbalanceResponse
        From :func:`rubrotor.linear.response.unbalance_response`.
    probe : int
        Index of the probe drawn.
    clearance : float, optional
        Radial clearance (m) of a contact at the probe, drawn as a red line on the amplitude
        plot and a red circle on the polar plot: where the major semi-axis crosses it, the
        linear response reaches the stator.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(11, 5.5), layout="constrained")
    grid = fig.add_gridspec(2, 2, width_ratios=[1.6, 1])
    ax_a, ax_p = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[1, 0])
    ax_pol = fig.add_subplot(grid[:, 1], projection="polar")
    for c, name in ((0, "v"), (1, "w")):
        ax_a.semilogy(resp.speeds, resp.amplitude[:, probe, c] * 1e6, label=name)
        ax_p.plot(resp.speeds, np.degrees(resp.phase[:, probe, c]), label=name)
        z = resp.complex_response[:, probe, c]
        ax_pol.plot(np.angle(z), np.abs(z) * 1e6, label=name)
    ax_a.semilogy(resp.speeds, resp.major[:, probe] * 1e6, "k--", lw=1, label="major semi-axis")
    if clearance is not None:
        ax_a.axhline(clearance * 1e6, color="r", lw=1.5, label=f"clearance {clearance * 1e6:g} µm")
        th = np.linspace(0, TWO_PI, 200)
        ax_pol.plot(th, np.full_like(th, clearance * 1e6), "r", lw=1.5, label="clearance")
        touch = resp.major[:, probe] >= clearance
        if touch.any():
            ax_a.axvspan(resp.speeds[touch][0], resp.speeds[touch][-1], color="r", alpha=0.08)
    ax_a.set(ylabel="amplitude (µm)", title=f"unbalance response at x = {resp.probes[probe]:g} m")
    ax_p.set(xlabel="spin speed (rad/s)", ylabel="phase (deg)")
    _polar_axes(ax_pol, resp, probe, clearance)
    for ax in (ax_a, ax_p):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    return fig


def resonance_speeds(speeds, amplitude, points: int = 200, width: float = 0.05) -> np.ndarray:
    """A speed grid refined around each peak of a response, for smooth Bode and polar plots.

    A resonance sampled on a uniform grid shows as a coarse polygon in the polar plot (its
    circle spans about twice the damping ratio times the critical speed). This adds ``points``
    speeds within ``+-width`` (relative) of every interior local maximum of ``amplitude``.

    Parameters
    ----------
    speeds : array_like
        Spin speeds (rad/s), increasing.
    amplitude : array_like
        Response amplitude at those speeds (any unit), e.g. the major semi-axis.
    points : int
        Speeds added around each peak.
    width : float
        Half-width of the refined band, relative to the peak's speed.

    Returns
    -------
    ndarray
        The sorted union of ``speeds`` and the added speeds (rad/s), within the original range.
    """
    w, a = np.asarray(speeds, float), np.asarray(amplitude, float)
    peaks = [i for i in range(1, w.size - 1) if a[i] >= a[i - 1] and a[i] >= a[i + 1]]
    extra = [np.linspace(w[i] * (1 - width), w[i] * (1 + width), points) for i in peaks]
    out = np.unique(np.concatenate([w, *extra]))
    return out[(out >= w[0]) & (out <= w[-1])]


def _polar_axes(ax, resp: UnbalanceResponse, probe: int, clearance: float | None = None) -> None:
    """Polar plot furniture: four clean radial ticks on a clear ray, speed marks along the
    curves (dots every tenth of the speed range, labelled on ``v`` where its radius exceeds a
    quarter of the largest)."""
    from matplotlib.ticker import MaxNLocator

    rmax = float(np.max(np.abs(resp.complex_response[:, probe, :]))) * 1e6
    ax.set_rlim(0, max(rmax, (clearance or 0.0) * 1e6) * 1.08)
    ax.yaxis.set_major_locator(MaxNLocator(4))
    ax.set_rlabel_position(112.5)
    ax.tick_params(axis="y", labelsize=7)
    marks = np.linspace(resp.speeds[0], resp.speeds[-1], 11)
    for c, color in ((0, "C0"), (1, "C1")):
        z = np.array([np.interp(marks, resp.speeds, f(resp.complex_response[:, probe, c]))
                      for f in (np.real, np.imag)])  # fmt: skip
        zz = z[0] + 1j * z[1]
        ax.plot(np.angle(zz), np.abs(zz) * 1e6, ".", color=color, ms=4)
        if c == 0:  # labels only off the crowded centre
            for w, p in zip(marks, zz, strict=True):
                if abs(p) * 1e6 < 0.25 * rmax:
                    continue
                ax.annotate(f"{w:.0f}", (np.angle(p), abs(p) * 1e6), fontsize=6, color="0.3",
                            xytext=(3, 3), textcoords="offset points")  # fmt: skip
    ax.set_title("polar plot (radius µm; dots: speeds in rad/s)", fontsize=10)


def mode_shape_figure(system: LinearSystem, mode: DampedMode, phases: int = 8) -> Figure:
    """A mode's deflected shape along the rotor in both planes and its whirl orbits.

    Parameters
    ----------
    system : LinearSystem
        The rotor the mode belongs to.
    mode : DampedMode
        From :func:`rubrotor.linear.modes.damped_modes`.
    phases : int
        Snapshots of the deflection over one period.

    Returns
    -------
    matplotlib.figure.Figure
    """
    xs = np.linspace(0.0, system.basis.length, 201)
    d = np.array([system.basis.rows(float(x)) @ mode.shape for x in xs])  # (X, 2) complex
    fig = Figure(figsize=(11, 4.8), layout="constrained")
    ax_v, ax_w, ax_o = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1.3, 1.3, 1]})
    for t in np.linspace(0, TWO_PI, phases, endpoint=False):
        e = np.exp(1j * t)
        ax_v.plot(xs, np.real(d[:, 0] * e), color="C0", alpha=0.5)
        ax_w.plot(xs, np.real(d[:, 1] * e), color="C1", alpha=0.5)
    nodes = getattr(system.basis, "nodes", np.linspace(0, system.basis.length, 11))
    th = np.linspace(0, TWO_PI, 100)
    for x in nodes[:: max(1, len(nodes) // 8)]:
        v, w = system.basis.rows(float(x)) @ mode.shape
        ax_o.plot(np.real(v * np.exp(1j * th)), np.real(w * np.exp(1j * th)), lw=1)
        ax_o.plot(np.real(v), np.real(w), "k.", ms=3)
    for ax, name in ((ax_v, "v"), (ax_w, "w")):
        ax.set(xlabel="axial position x (m)", ylabel=f"{name} (normalised)")
        ax.grid(alpha=0.3)
    ax_v.set_title(
        f"mode {mode.index}: {mode.frequency_hz:.2f} Hz, zeta {mode.damping_ratio:.3g}, {mode.whirl}"
    )
    ax_o.set(xlabel="v", ylabel="w", aspect="equal", title="orbits at nodes (dot: t = 0)")
    return fig


def ucs_figure(data: UCSMap, title: str = "undamped critical speed map") -> Figure:
    """Critical speeds against support stiffness (log-log), with the bearings' ``kyy`` and
    ``kzz`` against spin speed over them; a crossing (gold diamond) is a critical speed on that
    bearing.

    Parameters
    ----------
    data : UCSMap
        From :func:`rubrotor.linear.ucs.ucs_map`.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(9, 6), layout="constrained")
    ax = fig.subplots()
    for j in range(data.critical_speeds.shape[1]):
        ax.loglog(data.stiffness, data.critical_speeds[:, j], "k", lw=1.5)
        ax.annotate(f"mode {j + 1}", (data.stiffness[0], data.critical_speeds[0, j]),
                    textcoords="offset points", xytext=(4, 4), fontsize=8)  # fmt: skip
    top = float(data.critical_speeds.max()) * 1.5
    low = float(data.critical_speeds.min()) / 1.5
    for i, b in enumerate(data.bearings):
        speeds = b.speeds if b.speeds.size > 1 else np.array([low, top])
        ky = b.kyy if b.speeds.size > 1 else np.repeat(b.kyy, 2)
        kz = b.kzz if b.speeds.size > 1 else np.repeat(b.kzz, 2)
        ax.loglog(ky, np.maximum(speeds, low), f"C{i}-", marker="o", ms=3, label=f"{b.name} kyy")
        ax.loglog(kz, np.maximum(speeds, low), f"C{i}--", marker="s", ms=3, label=f"{b.name} kzz")
    cross = data.crossings()
    if cross:
        ax.plot([c["stiffness_N_m"] for c in cross], [c["speed_rad_s"] for c in cross], "D",
                mfc="gold", mec="k", ms=6, label="critical speed on a bearing")  # fmt: skip
    ax.set(xlabel="support stiffness (N/m)", ylabel="critical speed (rad/s)", title=title,
           xlim=(data.stiffness[0], data.stiffness[-1]), ylim=(low, top))  # fmt: skip
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="upper left")
    return fig


def mode_shapes_3d_figure(shapes: ModeShapes, columns: int = 2, stations: int = 25) -> Figure:
    """Each mode's whirl orbits along the rotor in 3-D: red forward, blue backward stations.

    Parameters
    ----------
    shapes : ModeShapes
        From :func:`rubrotor.linear.shapes.mode_shapes`.
    columns : int
        Subplots per row.
    stations : int
        Orbits drawn (evenly chosen stations; the counts in the titles are over all).

    Returns
    -------
    matplotlib.figure.Figure
        One 3-D axes per mode: axial position, ``z`` and ``y`` deflection (normalised); the
        orbit at the chosen stations, a dot at ``t = 0`` and the shape at ``t = 0`` in black.
    """
    n = len(shapes.modes.modes)
    rows = (n + columns - 1) // columns
    fig = Figure(figsize=(6 * columns, 4.6 * rows), layout="constrained")
    th = np.linspace(0, TWO_PI, 60)
    colors = {"forward": "tab:red", "backward": "tab:blue", "none": "0.6"}
    for k, m in enumerate(shapes.modes.modes):
        ax = fig.add_subplot(rows, columns, k + 1, projection="3d")
        v, w = shapes.v[k], shapes.w[k]
        direction = node_whirl(v, w)
        every = np.unique(np.linspace(0, shapes.x.size - 1, min(shapes.x.size, stations)).round())
        for i in every.astype(int):
            x, e = shapes.x[i], np.exp(1j * th)
            ax.plot(np.full(th.size, x), np.real(w[i] * e), np.real(v[i] * e),
                    color=colors[direction[i]], lw=0.9)  # fmt: skip
        ax.plot(shapes.x, w.real, v.real, "k-", lw=1.2)
        ax.plot(shapes.x, w.real, v.real, "k.", ms=3)
        ax.plot(shapes.x, 0 * shapes.x, 0 * shapes.x, color="0.5", lw=0.8, ls=":")
        counts = {d: int(np.sum(direction == d)) for d in ("forward", "backward")}
        ax.set_title(
            f"mode {m.index}: {m.frequency_hz:.2f} Hz, log dec {m.log_dec:.3g}, {m.whirl}\n"
            f"stations forward {counts['forward']} (red), backward {counts['backward']} (blue)",
            fontsize=9,
        )
        ax.set(xlabel="x (m)", ylabel="w", zlabel="v")
        ax.tick_params(labelsize=7)
    return fig
