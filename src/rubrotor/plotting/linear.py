"""Figures of the linear analyses of any rotor: Campbell diagram with stability, unbalance
response (Bode and polar) and mode shapes. One function per figure kind, each returning a
:class:`matplotlib.figure.Figure` that is not registered with pyplot.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from rubrotor.linear.campbell import CampbellData
from rubrotor.linear.critical import CRITICALLY_DAMPED, LinearCritical
from rubrotor.linear.modes import DampedMode
from rubrotor.linear.response import UnbalanceResponse
from rubrotor.linear.shaft import campbell, critical_speeds
from rubrotor.linear.shapes import ModeShapes, node_whirl
from rubrotor.linear.ucs import UCSMap
from rubrotor.rotors.linear import LinearSystem
from rubrotor.rotors.shaft import Shaft

__all__ = [
    "campbell_figure",
    "separation_margin",
    "amplification_factors",
    "margin_band",
    "resonance_speeds",
    "half_power_speeds",
    "campbell_stability_figure",
    "unbalance_response_figure",
    "mode_shape_figure",
    "ucs_figure",
    "mode_shapes_3d_figure",
]

TWO_PI = 2 * np.pi


def _af_text(af: float) -> str:
    """An amplification factor as text: 3 significant digits, whole numbers from 1000 on."""
    return f"{af:.0f}" if af >= 1000 else f"{af:.3g}"


def separation_margin(amplification: float, above: bool) -> float:
    """API 617 / API 684 separation margin (fraction of the speed) a critical speed of
    amplification factor ``amplification`` needs from the run range.

    ``0`` when ``AF < 2.5`` (critically damped); else ``min(0.16, 0.17 (1 - 1/(AF - 1.5)))`` for
    a critical below the minimum operating speed and ``min(0.26, 0.10 + 0.17 (1 - 1/(AF - 1.5)))``
    for one above the maximum continuous speed (``above=True``).

    Parameters
    ----------
    amplification : float
        Amplification factor (1), ``1 / (2 zeta)`` for a damping ratio ``zeta``.
    above : bool
        The critical speed lies above the run range.

    Returns
    -------
    float
        Required margin as a fraction (0.16 = 16 %) of the run range's nearer end.
    """
    if not math.isfinite(amplification) or amplification < 2.5:
        return 0.0
    core = 0.17 * (1.0 - 1.0 / (amplification - 1.5))
    return min(0.26, 0.10 + core) if above else min(0.16, core)


def margin_band(speed: float, damping_ratio: float) -> tuple[float, float]:
    """Run-range ends (rad/s) that would violate the API 684 separation margin of a critical
    speed ``speed`` (rad/s) of damping ratio ``damping_ratio`` (1): the run range's maximum must
    stay below the first value and its minimum above the second."""
    af = 1.0 / (2.0 * damping_ratio) if damping_ratio > 0 else math.inf
    return speed / (1.0 + separation_margin(af, True)), speed / (1.0 - separation_margin(af, False))


def campbell_stability_figure(
    data: CampbellData,
    criticals: list[LinearCritical] = (),
    operating_speed: float | None = None,
    title: str = "Campbell diagram",
    run_range: tuple[float, float] | None = None,
) -> Figure:
    """Damped frequencies against spin speed, coloured by logarithmic decrement, with the run
    range and the API 684 separation margins of the critical speeds.

    Stable modes are coloured by log dec (saturating at 1, well damped; the lightly damped modes
    dark), forward whirl as circles and backward whirl as triangles (readable in grey scale);
    unstable points (log dec < 0) are red crosses; overdamped roots (no frequency) are left out.
    The 1X line is dotted; critical speeds are diamonds labelled, in rows of their own, with
    their amplification factor ``AF = 1 / (2 zeta)`` (critically damped ones, ``zeta > 0.2``, are
    not critical speeds and are left out); around each, a hatched band at the foot
    marks where the run range may not reach (API 684 separation margin).

    Parameters
    ----------
    data : CampbellData
        From :func:`rubrotor.linear.campbell.campbell_data`.
    criticals : list of LinearCritical
        Critical speeds to mark.
    operating_speed : float, optional
        Spin speed (rad/s) drawn as a vertical line.
    title : str
        Figure title (name the scenario).
    run_range : tuple of float, optional
        Minimum operating and maximum continuous speed (rad/s), shaded.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(10, 5.8), layout="constrained")
    ax = fig.subplots()
    s = np.repeat(data.speeds[:, None], data.frequency_hz.shape[1], axis=1)
    f, ld = data.frequency_hz, data.log_dec
    fmax = float(np.nanmax(f)) * 1.05
    real = np.isfinite(f) & (f > 1e-9 * fmax)  # overdamped roots carry no frequency
    from rubrotor.linear.stability import ZETA_ROUNDOFF

    stable = real & (ld >= -2 * math.pi * ZETA_ROUNDOFF)  # round-off damping is undamped
    backward = np.asarray(data.whirl) == "backward"
    sc = None
    for mask, marker, name in (
        (~backward, "o", "forward whirl"),
        (backward, "v", "backward whirl"),
    ):
        m = stable & mask
        # colour saturates at log dec 1 (well damped); lightly damped modes dark
        sc = ax.scatter(s[m], f[m], c=np.minimum(ld[m], 1.0), s=12, marker=marker,
                        cmap=_LOGDEC_CMAP, vmin=0.0, vmax=1.0, label=name)  # fmt: skip
    if (real & ~stable).any():
        u = real & ~stable
        ax.scatter(s[u], f[u], marker="x", c="r", s=18, label="unstable (log dec < 0)")
    ax.plot(data.speeds, data.speeds / TWO_PI, "k:", lw=1, label="1X")
    # a mode damped beyond API 617's critically damped ratio (AF < 2.5) has no resonance: no
    # critical speed to mark or keep a margin from
    criticals = [c for c in criticals if not c.damping_ratio > CRITICALLY_DAMPED]
    _label_criticals(ax, criticals, fmax)
    _margins(ax, criticals, fmax)
    if run_range is not None:
        ax.axvspan(*run_range, color="0.88", zorder=0,
                   label=f"run range {run_range[0]:.4g}-{run_range[1]:.4g} rad/s")  # fmt: skip
    if operating_speed:
        ax.axvline(operating_speed, color="0.4", lw=1, ls="--",
                   label=f"operating speed {operating_speed:.5g} rad/s")  # fmt: skip
    ax.set(
        xlabel="spin speed (rad/s)",
        ylabel="damped natural frequency (Hz)",
        ylim=(0, fmax),
        xlim=(data.speeds[0], data.speeds[-1]),
        title=title,
    )
    fig.colorbar(sc, ax=ax, extend="max", pad=0.01, fraction=0.035, aspect=30,
                 label="logarithmic decrement (1), stable modes")  # fmt: skip
    ax.legend(loc="upper left", fontsize=8, framealpha=0.9)
    ax.grid(alpha=0.3)
    return fig


def _margins(ax, criticals, fmax: float) -> None:
    """Hatched bands at the foot of the axes: where the run range may not reach (API 684)."""
    first = True
    for c in criticals:
        lo, hi = margin_band(c.speed_rad_s, c.damping_ratio)
        if hi - lo <= 0:
            continue
        ax.fill_between([lo, hi], 0, 0.035 * fmax, facecolor="none", edgecolor="k", hatch="////",
                        lw=0.6, zorder=4,
                        label="API 684 separation margin: keep the run range out" if first
                        else None)  # fmt: skip
        first = False


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
        zeta = c.damping_ratio
        af = f", AF {_af_text(1 / (2 * zeta))}" if zeta > 0 else ""
        ax.annotate(
            f"{c.speed_rad_s:.0f} rad/s, {c.speed_rad_s * 60 / TWO_PI:.0f} rpm ({c.whirl}{af})",
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


def amplification_factors(speeds, amplitude, min_prominence: float = 2.0) -> list[tuple]:
    """Peaks of a response against speed and their amplification factors (half-power method,
    API 684): ``AF = N_c / (N_2 - N_1)`` with ``N_1, N_2`` the speeds where the amplitude is
    the peak's ``1/sqrt(2)``, interpolated linearly between samples.

    Parameters
    ----------
    speeds : array_like, shape (S,)
        Spin speeds (rad/s), increasing.
    amplitude : array_like, shape (S,)
        Response amplitude (any unit).
    min_prominence : float
        A peak counts when it is at least this many times the lower of the minima on its two
        sides (1).

    Returns
    -------
    list of tuple
        ``(speed_rad_s, peak_amplitude, af)`` per peak; ``af`` is NaN when a half-power
        point falls outside the speeds.
    """
    w, a = np.asarray(speeds, float), np.asarray(amplitude, float)
    out = []
    peaks = np.flatnonzero((a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:])) + 1
    for i in peaks:
        left, right = a[: i + 1].min(), a[i:].min()
        if a[i] < min_prominence * max(left, right, 1e-300):
            continue
        half = a[i] / math.sqrt(2.0)
        lo = np.flatnonzero(a[:i] < half)
        hi = np.flatnonzero(a[i:] < half)
        if lo.size == 0 or hi.size == 0:
            out.append((float(w[i]), float(a[i]), math.nan))
            continue
        j, k = lo[-1], i + hi[0]
        n1 = np.interp(half, [a[j], a[j + 1]], [w[j], w[j + 1]])
        n2 = np.interp(half, [a[k], a[k - 1]], [w[k], w[k - 1]])
        out.append((float(w[i]), float(a[i]), float(w[i] / (n2 - n1))))
    return out


def unbalance_response_figure(
    resp: UnbalanceResponse, probe: int = 0, clearance: float | None = None,
    title: str | None = None,
) -> Figure:  # fmt: skip
    """Bode (amplitude and phase against speed) and polar plot, with amplification factors.

    The amplitude panel draws every probe's major semi-axis (one line style each) and ``v``,
    ``w`` of ``probe``; each resonance peak of ``probe`` is labelled with its speed and its
    amplification factor (:func:`amplification_factors`). The phase is unwrapped (no jumps at
    +-180 deg). The curves join the computed speeds with straight lines: sample a resonance
    densely (:func:`resonance_speeds`) for a smooth polar circle.

    Parameters
    ----------
    resp : UnbalanceResponse
        From :func:`rubrotor.linear.response.unbalance_response`.
    probe : int
        Index of the probe whose ``v``, ``w``, phase and polar plot are drawn.
    clearance : float, optional
        Radial clearance (m) of a contact at the probe, drawn as a line on the amplitude plot
        and a circle on the polar plot: where the major semi-axis crosses it, the linear
        response reaches the stator.
    title : str, optional
        Title (name the scenario); the probe is added.

    Returns
    -------
    matplotlib.figure.Figure
        Amplitudes in µm 0-peak, phase in degrees, speed in rad/s.
    """
    fig = Figure(figsize=(11, 5.8), layout="constrained")
    grid = fig.add_gridspec(2, 2, width_ratios=[1.6, 1])
    ax_a, ax_p = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[1, 0])
    ax_pol = fig.add_subplot(grid[:, 1], projection="polar")
    for c, name, ls in ((0, "v", "-"), (1, "w", "--")):
        ax_a.semilogy(resp.speeds, resp.amplitude[:, probe, c] * 1e6, ls=ls, lw=1.2,
                      label=f"{name} at x = {resp.probes[probe]:g} m")  # fmt: skip
        ax_p.plot(resp.speeds, np.degrees(np.unwrap(resp.phase[:, probe, c])), ls=ls, label=name)
        z = resp.complex_response[:, probe, c]
        ax_pol.plot(np.angle(z), np.abs(z) * 1e6, ls=ls, label=name)
    styles = ("-", "-.", ":", (0, (5, 1, 1, 1, 1, 1)))
    for k in range(resp.probes.size):
        ax_a.semilogy(resp.speeds, resp.major[:, k] * 1e6, color="k", ls=styles[k % 4],
                      lw=1.6 if k == probe else 0.9,
                      label=f"major semi-axis, x = {resp.probes[k]:g} m")  # fmt: skip
    for w, peak, af in amplification_factors(resp.speeds, resp.major[:, probe]):
        text = f"{w:.0f} rad/s\nAF {_af_text(af)}" if math.isfinite(af) else f"{w:.0f} rad/s"
        ax_a.annotate(text, (w, peak * 1e6), xytext=(6, -2), textcoords="offset points",
                      fontsize=8, va="top",
                      bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "0.7", "lw": 0.5})  # fmt: skip
    if clearance is not None:
        ax_a.axhline(clearance * 1e6, color="r", lw=1.5, ls=(0, (8, 2)),
                     label=f"radial clearance {clearance * 1e6:g} µm")  # fmt: skip
        th = np.linspace(0, TWO_PI, 200)
        ax_pol.plot(th, np.full_like(th, clearance * 1e6), "r", lw=1.5, ls=(0, (8, 2)),
                    label="clearance")  # fmt: skip
        touch = resp.major[:, probe] >= clearance
        if touch.any():
            ax_a.axvspan(resp.speeds[touch][0], resp.speeds[touch][-1], color="r", alpha=0.08)
    head = f"{title}: " if title else ""
    ax_a.set(ylabel="amplitude (µm 0-peak)",
             title=f"{head}unbalance response at x = {resp.probes[probe]:g} m")  # fmt: skip
    ax_p.set(xlabel="spin speed (rad/s)", ylabel="phase, unwrapped (deg)")
    _polar_axes(ax_pol, resp, probe, clearance)
    for ax in (ax_a, ax_p):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
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


def half_power_speeds(peaks, lo: float, hi: float, points: int = 121) -> np.ndarray:
    """Speeds spread evenly in phase through each resonance: ``N_c (1 + tan(theta) / (2 AF))``
    for ``theta`` evenly in (-1.5, 1.5) rad, the spacing of a single mode's phase, so that its
    polar circle is drawn smooth however light the damping.

    Parameters
    ----------
    peaks : list of tuple
        ``(speed_rad_s, amplitude, af)`` from :func:`amplification_factors` (NaN ``af`` skipped).
    lo, hi : float
        Speed range kept (rad/s).
    points : int
        Speeds per peak.

    Returns
    -------
    ndarray
        Sorted speeds (rad/s) in ``[lo, hi]``.
    """
    theta = np.linspace(-1.5, 1.5, points)
    out = [w * (1 + np.tan(theta) / (2 * af)) for w, _, af in peaks if math.isfinite(af)]
    out = np.concatenate(out) if out else np.empty(0)
    return np.sort(out[(out >= lo) & (out <= hi)])


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


_WHIRL_COLOR = {"forward": "tab:blue", "backward": "tab:red"}


_BRANCH_STYLE = {"bending": "-", "shear": "--"}


_THEORY_NAME = {
    "timoshenko": "Timoshenko",
    "rayleigh": "Rayleigh",
    "euler-bernoulli": "Euler-Bernoulli",
}


_WHIRL_LETTER = {"forward": "F", "backward": "B"}


def campbell_figure(shaft: Shaft, speeds, operating_speed: float | None = None) -> Figure:
    """Campbell diagram: whirl frequencies of every mode against spin speed.

    Forward whirl is blue, backward red; the bending branch is solid, the Timoshenko shear
    (second) branch dashed. Each curve is labelled at its right end by mode number and whirl
    (``2F`` = mode 2, forward). The 1X line (whirl frequency = spin) is black, dotted; critical
    speeds inside the speed range (crossings with the 1X line) are marked with a diamond and
    annotated with their speed in rad/s. For Timoshenko shafts the shear branches, an order of
    magnitude above the bending ones, get their own panel above a broken frequency axis.

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    speeds : array_like, shape (S,)
        Spin speeds ``Omega`` (rad/s), ``>= 0``, at least 2.
    operating_speed : float, optional
        Spin speed (rad/s) drawn as a vertical grey line and labelled.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, not shown and not registered with ``pyplot``.

    Examples
    --------
    >>> s = Shaft(length=0.4, diameter=0.1, youngs_modulus=71e9, density=2660,
    ...           shear_modulus=26.2e9, shear_coefficient="seed")
    >>> fig = campbell_figure(s, [0, 30000, 60000], operating_speed=11614.0)
    >>> len(fig.axes)
    2
    """
    data = campbell(shaft, speeds)
    sp = data["speed_rad_s"]
    lo_sp, hi_sp = float(sp.min()), float(sp.max())
    crits = [c for c in critical_speeds(shaft) if lo_sp <= c.speed_rad_s <= hi_sp]
    fig, panels = _campbell_panels(shaft)
    for branch, ax in panels.items():
        _campbell_curves(ax, branch, data)
        ax.set_xlim(lo_sp, hi_sp)
        ax.grid(True, alpha=0.3)
        ax.set_ylabel("Whirl frequency (Hz)")
        _campbell_criticals(ax, [c for c in crits if c.branch == branch])
        if operating_speed is not None:
            ax.axvline(operating_speed, color="0.45", linestyle="-.", linewidth=1.3)
    _campbell_axes(panels, operating_speed)
    _campbell_legend(fig, panels, bool(crits), operating_speed)
    fig.suptitle(
        f"Campbell diagram: {_THEORY_NAME[shaft.theory]} shaft, L = {shaft.length:g} m, "
        f"D = {shaft.diameter * 1e3:g} mm"
        + (f", \u03ba = {shaft.kappa:.4g}" if shaft.theory == "timoshenko" else "")
        + ("" if shaft.gyroscopic else ", no gyroscopic moments"),
        fontsize=11,
    )
    return fig


def _campbell_panels(shaft: Shaft) -> tuple[Figure, dict]:
    """The figure and its panels: bending only, or shear above bending (Timoshenko)."""
    two = shaft.theory == "timoshenko"
    fig = Figure(figsize=(10, 7 if two else 5.5), layout="constrained")
    if two:
        ax_shear, ax_bend = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [1, 1.6]})
        return fig, {"bending": ax_bend, "shear": ax_shear}
    return fig, {"bending": fig.subplots(1, 1)}


def _campbell_curves(ax, branch: str, data: dict) -> None:
    """Whirl frequencies (Hz) of one branch against spin speed (rad/s), labelled, and 1X."""
    sp, freq, labels = data["speed_rad_s"], data["frequency_hz"], data["labels"]
    cols = [j for j, (b, _) in enumerate(labels) if b == branch]
    fb = freq[:, :, cols]
    top = float(fb.max())
    if branch == "bending":
        ymin, ymax = 0.0, 1.1 * top
    else:
        bottom = float(fb.min())
        pad = 0.08 * (top - bottom)
        ymin, ymax = bottom - pad, top + pad
    for j in cols:
        branch_j, whirl = labels[j]
        for i, n in enumerate(data["n"]):
            f = freq[:, i, j]
            ax.plot(
                sp, f, color=_WHIRL_COLOR[whirl], linestyle=_BRANCH_STYLE[branch_j], linewidth=1.6
            )
            ax.annotate(
                f"{n}{_WHIRL_LETTER[whirl]}",
                (sp[-1], f[-1]),
                xytext=(4, 0),
                textcoords="offset points",
                va="center",
                fontsize=8,
                color=_WHIRL_COLOR[whirl],
            )
    ax.plot(sp, sp / (2 * math.pi), color="black", linestyle=":", linewidth=1.4)
    ax.set_ylim(ymin, ymax)


def _campbell_criticals(ax, crits) -> None:
    """Diamonds at the critical speeds (rad/s), annotated."""
    for c in crits:
        y = c.speed_hz
        ax.plot(
            c.speed_rad_s,
            y,
            marker="D",
            markersize=7,
            markerfacecolor=_WHIRL_COLOR[c.whirl],
            markeredgecolor="black",
            linestyle="none",
            zorder=5,
        )
        ax.annotate(
            f"{c.n}{_WHIRL_LETTER[c.whirl]}: {c.speed_rad_s:.0f} rad/s",
            (c.speed_rad_s, y),
            xytext=(-8, -14) if c.whirl == "backward" else (8, -14),
            textcoords="offset points",
            ha="right" if c.whirl == "backward" else "left",
            fontsize=8,
            bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.8},
            zorder=6,
        )


def _campbell_axes(panels: dict, operating_speed: float | None) -> None:
    """Speed axes (rad/s below, rev/min on top), operating-speed label, panel titles."""
    ax_bend = panels["bending"]
    ax_bend.set_xlabel(r"Spin speed $\Omega$ (rad/s)")
    if operating_speed is not None:
        ax_bend.annotate(
            f"operating: {operating_speed:.0f} rad/s = {operating_speed / (2 * math.pi):.0f} Hz",
            (operating_speed, 0.98),
            xycoords=("data", "axes fraction"),
            xytext=(4, 0),
            textcoords="offset points",
            fontsize=8,
            color="0.3",
            va="top",
            bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.8},
        )
    top_ax = panels.get("shear", ax_bend)
    secx = top_ax.secondary_xaxis(
        "top", functions=(lambda x: x * 60 / (2 * math.pi), lambda r: r * 2 * math.pi / 60)
    )
    secx.set_xlabel("Spin speed (rev/min)")
    if "shear" in panels:
        _break_marks(panels["shear"], panels["bending"])
        for branch, text in (("shear", "shear (second) branch"), ("bending", "bending branch")):
            panels[branch].text(
                0.01,
                0.97,
                text,
                transform=panels[branch].transAxes,
                va="top",
                fontsize=9,
                fontweight="bold",
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.8},
            )


def _campbell_legend(fig, panels: dict, crits: bool, operating_speed: float | None) -> None:
    handles = [
        Line2D([], [], color=_WHIRL_COLOR["forward"], label="forward whirl (F)"),
        Line2D([], [], color=_WHIRL_COLOR["backward"], label="backward whirl (B)"),
        Line2D([], [], color="0.3", linestyle="-", label="bending branch"),
    ]
    if "shear" in panels:
        handles.append(Line2D([], [], color="0.3", linestyle="--", label="shear branch"))
    handles.append(Line2D([], [], color="black", linestyle=":", label=r"1X (whirl = spin)"))
    if crits:
        handles.append(
            Line2D(
                [],
                [],
                marker="D",
                color="0.6",
                markeredgecolor="black",
                linestyle="none",
                label="critical speed",
            )
        )
    if operating_speed is not None:
        handles.append(Line2D([], [], color="0.45", linestyle="-.", label="operating speed"))
    fig.legend(handles=handles, loc="outside right upper", fontsize=9)


def _break_marks(ax_top, ax_bottom) -> None:
    """Draw a broken-axis gap between two stacked panels."""
    ax_top.spines["bottom"].set_visible(False)
    ax_bottom.spines["top"].set_visible(False)
    ax_top.tick_params(axis="x", which="both", bottom=False, labelbottom=False)
    kw = {
        "marker": [(-1, -0.5), (1, 0.5)],
        "markersize": 10,
        "linestyle": "none",
        "color": "k",
        "mec": "k",
        "mew": 1,
        "clip_on": False,
    }
    ax_top.plot([0, 1], [0, 0], transform=ax_top.transAxes, **kw)
    ax_bottom.plot([0, 1], [1, 1], transform=ax_bottom.transAxes, **kw)
