"""Machinery-diagnostics figures of a run-up, coast-down or measured record: transient Bode and
polar plots of tracked orders, cascade (waterfall) and full-spectrum cascade, shaft centreline,
and orbits unfiltered and order-filtered with keyphasor marks and the clearance circle.

The data come from :mod:`rubrotor.analysis.orders` and :mod:`rubrotor.analysis.diagnostics`.
Speeds are drawn in rad/s (``rpm=True``: rev/min); displacements in µm; orbits with z across
and y up, as ``rubrotor.plotting.rub`` draws them.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

__all__ = [
    "bode_figure",
    "polar_figure",
    "cascade_figure",
    "centreline_figure",
    "orbit_figure",
    "mark_orders",
]

UM = 1e6  # m -> µm
RPM = 60.0 / (2.0 * math.pi)  # rad/s -> rev/min


def _speed(x, rpm: bool) -> tuple[np.ndarray, str]:
    x = np.asarray(x, float)
    return (x * RPM, "speed (rev/min)") if rpm else (x, "speed (rad/s)")


def _direction(track, direction: str) -> list[tuple[str, np.ndarray]]:
    rows = {"y": track.y, "z": track.w, "forward": None, "backward": None}
    if direction not in rows:
        from rubrotor.errors import InputError

        raise InputError("direction", direction, '"y", "z", "forward", "backward" or "both"')
    if direction == "forward":
        return [("forward", track.forward)]
    if direction == "backward":
        return [("backward", track.backward)]
    return [(direction, rows[direction])]


def bode_figure(tracks: dict, *, orders=(1.0,), direction: str = "both", rpm: bool = False,
                phase: str = "arg", title: str = "") -> Figure:  # fmt: skip
    """Transient Bode plot: amplitude and phase of tracked orders against speed.

    Parameters
    ----------
    tracks : dict of float or str to OrderTrack
        Order tracks keyed by probe position (m) or by a label (a measured probe's name).
    orders : sequence of float
        Orders to draw (each tracked).
    direction : {"both", "y", "z", "forward", "backward"}
        Which component: ``"both"`` draws y (solid) and z (dashed).
    rpm : bool
        Speed axis in rev/min instead of rad/s.
    phase : {"arg", "lag"}
        ``"arg"``: ``arg Y`` (deg, unwrapped), the phase of ``Re(Y exp(i k theta))`` relative to
        the keyphasor; ``"lag"``: the Bently-Nevada phase lag ``-arg Y`` (deg, unwrapped, the
        first value in 0-360), the angle from the keyphasor to the next positive peak.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Top: amplitude (µm, zero-to-peak), the first curve's highest peak labelled with its
        half-power amplification factor (API 684); bottom: phase (deg).
    """
    if phase not in ("arg", "lag"):
        from rubrotor.errors import InputError

        raise InputError("phase", phase, '"arg" or "lag"')
    fig = Figure(figsize=(8.0, 6.0), layout="constrained")
    ax_a, ax_p = fig.subplots(2, 1, sharex=True, height_ratios=(3, 2))
    colour = 0
    for probe, track in tracks.items():
        dirs = ("y", "z") if direction == "both" else (direction,)
        dirs = dirs[:1] if track.w is None else dirs
        where = f"x = {probe:g} m" if isinstance(probe, int | float) else str(probe)
        for k in orders:
            i = track.order_index(k)
            for d, style in zip(dirs, ("-", "--"), strict=False):
                ((label, ph),) = _direction(track, d)
                sp, xlabel = _speed(track.speed_rad_s, rpm)
                lab = f"{k:g}X {label}, {where}"
                ax_a.plot(sp, np.abs(ph[i]) * UM, style, color=f"C{colour % 10}", lw=1.2, label=lab)
                deg = np.degrees(np.unwrap(np.angle(ph[i])))
                if phase == "lag":
                    deg = -deg
                    deg -= 360.0 * np.floor(deg[0] / 360.0)
                ax_p.plot(sp, deg, style, color=f"C{colour % 10}", lw=1.2)
                if colour == 0 and d == dirs[0]:
                    _label_peaks(ax_a, sp, np.abs(ph[i]) * UM, track.speed_rad_s)
            colour += 1
    ax_a.set_ylabel("amplitude (µm, 0-peak)")
    top = max((float(np.nanmax(ln.get_ydata())) for ln in ax_a.lines), default=1.0)
    ax_a.set_ylim(0, 1.08 * top if top > 0 else 1.0)
    for ax in (ax_a, ax_p):
        ax.ticklabel_format(axis="y", useOffset=False)
    lo, hi = ax_p.get_ylim()
    if hi - lo < 10:  # a steady phase: show +- 5 deg around it, not its round-off
        mid = 0.5 * (lo + hi)
        ax_p.set_ylim(mid - 5, mid + 5)
    ax_a.grid(alpha=0.3)
    ax_a.legend(fontsize=7, ncols=2)
    ax_p.set_ylabel("phase arg Y (deg)" if phase == "arg" else "phase lag (deg)")
    ax_p.set_xlabel(xlabel)
    ax_p.grid(alpha=0.3)
    fig.suptitle(title or "transient Bode plot (order tracking)")
    return fig


def _label_peaks(ax, speed_axis, amplitude, speed_rad_s) -> None:
    """The highest resonance peak of a tracked amplitude, labelled with its speed and
    amplification factor (the lesser peaks of a rubbing run's jagged response are not)."""
    from rubrotor.plotting.linear import amplification_factors

    peaks = amplification_factors(speed_rad_s, amplitude)
    for w, peak, af in sorted(peaks, key=lambda p: p[1])[-1:]:
        x = np.interp(w, speed_rad_s, speed_axis)
        text = f"peak at {w:.0f} rad/s" + (f"\nAF {af:.3g}" if np.isfinite(af) else "")
        ax.annotate(text, (x, peak), xytext=(6, -4), textcoords="offset points", va="top",
                    fontsize=8, bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "0.7"})  # fmt: skip


def polar_figure(track, *, order: float = 1.0, direction: str = "y", rpm: bool = False,
                 n_labels: int = 6, title: str = "") -> Figure:  # fmt: skip
    """Polar (Nyquist) plot of one tracked order: the phasor's tip against speed.

    Parameters
    ----------
    track : OrderTrack
        Tracked orders of one probe.
    order : float
        The order drawn.
    direction : {"y", "z", "forward", "backward"}
        Which component.
    rpm : bool
        Speed labels in rev/min.
    n_labels : int
        Speed labels along the curve.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        The phasor ``Y`` (µm) in the complex plane, phase counted anticlockwise from the
        keyphasor, coloured by speed, with speed labels and a few radial ticks.
    """
    ((label, ph),) = _direction(track, direction)
    y = ph[track.order_index(order)] * UM
    sp, unit = _speed(track.speed_rad_s, rpm)
    fig = Figure(figsize=(6.4, 5.6), layout="constrained")
    ax = fig.add_subplot(projection="polar")
    pts = ax.scatter(np.angle(y), np.abs(y), c=sp, s=6, cmap="viridis", zorder=3)
    ax.plot(np.angle(y), np.abs(y), color="0.6", lw=0.6, zorder=2)
    arc = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(y)))])  # labels evenly along the curve
    for j in np.unique(np.searchsorted(arc, np.linspace(0, arc[-1], n_labels))):
        j = min(int(j), y.size - 1)
        ax.annotate(f"{sp[j]:.0f}", (np.angle(y[j]), np.abs(y[j])), fontsize=7,
                    xytext=(4, 4), textcoords="offset points")  # fmt: skip
    rmax = float(np.abs(y).max()) * 1.1
    ax.set_rmax(rmax)
    ax.set_rticks(np.round(np.linspace(0, rmax, 4)[1:], 3 - int(math.floor(math.log10(rmax)))))
    ax.set_rlabel_position(22.5)
    ax.tick_params(labelsize=8)
    fig.colorbar(pts, ax=ax, shrink=0.7, pad=0.1, label=unit)
    fig.suptitle(title or f"polar plot: {order:g}X {label} (µm)")
    return fig


def cascade_figure(casc, *, orders=(0.5, 1.0, 2.0, 3.0), rpm: bool = False, max_frequency=None,
                   title: str = "") -> Figure:  # fmt: skip
    """Cascade (waterfall): one spectrum per speed, stacked, with order lines.

    Parameters
    ----------
    casc : Cascade
        From :func:`rubrotor.analysis.diagnostics.cascade` (one channel or full spectrum).
    orders : sequence of float
        Order lines drawn (``frequency = order * speed``; both signs for a full spectrum).
    rpm : bool
        Speed and frequency axes in rev/min instead of rad/s.
    max_frequency : float, optional
        Largest absolute frequency drawn (rad/s); default 4 times the top speed.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Spectra drawn as lines whose baseline is the block's speed, heights scaled so the
        largest amplitude spans three spacings; order lines dashed (through the baselines).
    """
    sp, unit = _speed(casc.speed_rad_s, rpm)
    scale = RPM if rpm else 1.0
    f = casc.frequency_rad_s * scale
    fmax = (4.0 * casc.speed_rad_s.max() if max_frequency is None else max_frequency) * scale
    keep = np.abs(f) <= fmax
    f, amp = f[keep], casc.amplitude[:, keep] * UM
    gap = np.median(np.diff(sp)) if sp.size > 1 else 1.0
    gain = 3.0 * abs(gap) / max(float(amp.max()), 1e-300)
    fig = Figure(figsize=(8.0, 6.4), layout="constrained")
    ax = fig.add_subplot()
    for j in range(sp.size)[::-1]:  # back to front
        ax.fill_between(
            f, sp[j], sp[j] + gain * amp[j], color="white", lw=0, zorder=2 * (sp.size - j)
        )
        ax.plot(f, sp[j] + gain * amp[j], color="C0", lw=0.6, zorder=2 * (sp.size - j) + 1)
    line = np.array([sp.min(), sp.max()])
    for k in orders:
        for sign in (1, -1) if casc.full else (1,):
            ax.plot(sign * k * line, line, "--", color="C3", lw=0.7, zorder=10 * sp.size)
            ax.annotate(f"{sign * k:g}X", (sign * k * line[1], line[1]), color="C3", fontsize=8,
                        xytext=(0, 3), textcoords="offset points", ha="center",
                        zorder=10 * sp.size + 1)  # fmt: skip
    ax.set_xlim(-fmax if casc.full else 0, fmax)
    ax.set_xlabel(("frequency" + (" (negative: backward whirl)" if casc.full else ""))
                  + (" (rev/min)" if rpm else " (rad/s)"))  # fmt: skip
    ax.set_ylabel(unit)
    per = unit.split()[-1][1:-1]
    ax.text(0.01, 0.99, f"each spectrum drawn above its speed:\n1 {per} of height = {1 / gain:.3g} µm",
            transform=ax.transAxes, va="top", fontsize=8, zorder=10 * sp.size + 2,
            bbox={"facecolor": "white", "edgecolor": "0.7"})  # fmt: skip
    kind = "full-spectrum cascade" if casc.full else "cascade"
    fig.suptitle(title or f"{kind} (Hann, amplitude µm)")
    return fig


def _circle(ax, radius: float, centre=(0.0, 0.0)) -> None:
    phi = np.linspace(0, 2 * math.pi, 361)
    ax.plot((centre[1] + radius * np.sin(phi)) * UM, (centre[0] + radius * np.cos(phi)) * UM,
            "k--", lw=1, label="clearance")  # fmt: skip


def centreline_figure(cl, *, clearance=None, centre=(0.0, 0.0), rpm: bool = False,
                      title: str = "") -> Figure:  # fmt: skip
    """Shaft centreline: average position per revolution, coloured by speed, in the clearance.

    Parameters
    ----------
    cl : Centreline
        From :func:`rubrotor.analysis.diagnostics.shaft_centreline`.
    clearance : float, optional
        Radial clearance (m): the circle drawn.
    centre : (float, float)
        Stator centre (y, z) (m).
    rpm : bool
        Colour scale in rev/min.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    sp, unit = _speed(cl.speed_rad_s, rpm)
    fig = Figure(figsize=(6.4, 5.6), layout="constrained")
    ax = fig.add_subplot()
    if clearance is not None:
        _circle(ax, clearance, centre)
    ax.plot(cl.z * UM, cl.y * UM, color="0.6", lw=0.6)
    pts = ax.scatter(cl.z * UM, cl.y * UM, c=sp, s=10, cmap="viridis", zorder=3)
    ax.plot([centre[1] * UM], [centre[0] * UM], "k+", label="stator centre")
    fig.colorbar(pts, ax=ax, label=unit)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("z (µm)")
    ax.set_ylabel("y (µm)")
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(alpha=0.3)
    fig.suptitle(title or "shaft centreline (mean position per revolution)")
    return fig


def orbit_figure(spin, y, w, track, *, at_speed: float, revolutions: int = 4, order: float = 1.0,
                 clearance=None, centre=(0.0, 0.0), title: str = "") -> Figure:  # fmt: skip
    """Orbit unfiltered and order-filtered around one speed, keyphasor marks, clearance circle.

    Parameters
    ----------
    spin : SpinAngle
        Spin angle of the record.
    y, w : array_like
        Orbit (m) at ``spin.time``.
    track : OrderTrack
        Tracked orders of the same probe (both directions).
    at_speed : float
        Speed (rad/s) at which the revolutions drawn start.
    revolutions : int
        Revolutions drawn.
    order : float
        The filtered order (1X by default).
    clearance : float, optional
        Radial clearance (m).
    centre : (float, float)
        Stator centre (y, z) (m).
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Left: unfiltered orbit; right: the ``order``-filtered orbit (centred on the mean
        position); keyphasor marks as dots (blank-dot convention: the mark is where the shaft
        is when the keyphasor fires).
    """
    from rubrotor.analysis.diagnostics import filtered_orbit, keyphasor_marks

    y, w = np.asarray(y, float), np.asarray(w, float)
    sl = spin.valid
    t0 = float(np.interp(at_speed, spin.speed[sl], spin.time[sl]))
    a0 = float(np.interp(t0, spin.time, spin.angle))
    a1 = a0 + 2 * math.pi * revolutions
    sel = (spin.angle >= a0) & (spin.angle <= a1)
    fy, fz = filtered_orbit(spin, track, order)
    fig = Figure(figsize=(10.0, 5.0), layout="constrained")
    axes = fig.subplots(1, 2)
    my, mz = np.nanmean(y[sel]), np.nanmean(w[sel])
    tm, _, _ = keyphasor_marks(spin, y, w)
    tm = tm[(tm >= spin.time[sel][0]) & (tm <= spin.time[sel][-1])]
    for ax, (oy, oz), name in ((axes[0], (y, w), "unfiltered"),
                               (axes[1], (fy + my, fz + mz), f"{order:g}X filtered")):  # fmt: skip
        if clearance is not None:
            _circle(ax, clearance, centre)
        ax.plot(oz[sel] * UM, oy[sel] * UM, color="C0", lw=1.0, label=name)
        ky, kz = np.interp(tm, spin.time, oy), np.interp(tm, spin.time, oz)
        ax.plot(kz * UM, ky * UM, "o", mfc="white", mec="k", ms=6, label="keyphasor")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("z (µm)")
        ax.set_ylabel("y (µm)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
        ax.set_title(f"{name}, {revolutions} rev from {at_speed:.4g} rad/s")
    fig.suptitle(title or "orbit")
    return fig


def mark_orders(ax, time_s, speed_rad_s, orders=(0.5, 1.0, 2.0, 3.0), *, time_scale: float = 1e3):
    """Draw order curves ``k * speed(t) / (2 pi)`` (Hz) on a time-frequency map.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        A map with time across (``time_scale`` units per s, ms by default) and frequency (Hz) up,
        such as the CWT map of ``rubrotor.plotting.signals.analysis_figure``.
    time_s : array_like
        Times (s).
    speed_rad_s : array_like
        Spin speed at those times (rad/s).
    orders : sequence of float
        Orders drawn (dotted white, labelled at the right end).
    time_scale : float
        Map time units per second.
    """
    t = np.asarray(time_s, float) * time_scale
    f = np.asarray(speed_rad_s, float) / (2 * math.pi)
    lo, hi = ax.get_ylim()
    for k in orders:
        ax.plot(t, k * f, ":", color="white", lw=1.0)
        if lo <= k * f[-1] <= hi:
            ax.annotate(f"{k:g}X", (t[-1], k * f[-1]), color="white", fontsize=7,
                        xytext=(-2, 2), textcoords="offset points", ha="right")  # fmt: skip
    ax.set_ylim(lo, hi)
