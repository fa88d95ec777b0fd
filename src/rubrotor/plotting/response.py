"""Figures of the static and forced response of any rotor: the deflected shaft with its bearing
loads, and the frequency response (Bode and polar). One function per figure kind, each
returning a :class:`matplotlib.figure.Figure` that is not registered with pyplot.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from rubrotor.linear.api617 import ClearanceCheck
from rubrotor.linear.api684 import Level1
from rubrotor.linear.response import FrequencyResponse
from rubrotor.linear.static import StaticResult

__all__ = ["static_figure", "frequency_response_figure", "clearance_figure", "level1_figure"]


def static_figure(result: StaticResult, title: str = "static deflection") -> Figure:
    """The deflected rotor in both planes (µm) and the forces of the bearings on it (N).

    Parameters
    ----------
    result : StaticResult
        From :func:`rubrotor.linear.static.static_analysis`.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Top: deflections ``v`` and ``w`` (µm) against ``x`` (m), bearings as triangles. Bottom:
        each bearing's force components (N) as arrows from the axis, labelled.
    """
    fig = Figure(figsize=(10, 6.5), layout="constrained")
    ax, ax_f = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [1.4, 1]})
    x, d = result.x, result.deflection * 1e6
    ax.plot(x, d[:, 0], "C0", lw=2, label="v (along y)")
    ax.plot(x, d[:, 1], "C1", lw=2, ls="--", label="w (along z)")
    ax.axhline(0, color="0.6", lw=0.8)
    for b in result.bearings:
        i = int(np.argmin(np.abs(x - b.position)))
        ax.plot(b.position, d[i, 0], "k^", ms=9)
    ax.set(ylabel="deflection (µm)", title=title)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fmax = max(
        [abs(b.force_y) for b in result.bearings]
        + [abs(b.force_z) for b in result.bearings]
        + [1e-30]
    )
    tiny = 1e-9 * fmax  # round-off of a zero reaction (-1.8e-11 N) gets no arrow
    mid = 0.5 * (x[0] + x[-1])
    for b in result.bearings:
        for comp, color, dx, ls in ((b.force_y, "C0", -0.004, "-"), (b.force_z, "C1", 0.004, "--")):
            if abs(comp) <= tiny:
                continue
            xb = b.position + dx * (x[-1] - x[0])
            ax_f.annotate("", (xb, comp), (xb, 0.0),
                          arrowprops={"arrowstyle": "->", "color": color, "lw": 2, "ls": ls})  # fmt: skip
        fy, fz = (0.0 if abs(f) <= tiny else f for f in (b.force_y, b.force_z))
        right = b.position > mid  # labels point inwards: never off the edge
        ax_f.annotate(
            f"{b.name}\nF_y = {fy:.4g} N\nF_z = {fz:.4g} N",
            (b.position, 0.0),
            textcoords="offset points",
            xytext=(-8 if right else 8, -30 if fy > 0 else 10),
            ha="right" if right else "left",
            fontsize=8,
            annotation_clip=False,
        )
    ax_f.plot([], [], "C0", label="F_y on the rotor")
    ax_f.plot([], [], "C1", ls="--", label="F_z on the rotor")
    ax_f.axhline(0, color="0.6", lw=0.8)
    ax_f.set(
        xlabel="axial position x (m)", ylabel="bearing force (N)", ylim=(-1.3 * fmax, 1.3 * fmax)
    )
    ax_f.legend(fontsize=8, loc="lower right")
    ax_f.grid(alpha=0.3)
    return fig


def frequency_response_figure(
    resp: FrequencyResponse, probe: int = 0, title: str | None = None
) -> Figure:
    """Bode (amplitude and phase of ``v``, ``w`` against excitation frequency) and polar plot.

    Parameters
    ----------
    resp : FrequencyResponse
        From :func:`rubrotor.linear.response.frequency_response`.
    probe : int
        Index of the probe drawn.
    title : str, optional
        Figure title (default: the force and the probe).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(11, 5.5), layout="constrained")
    grid = fig.add_gridspec(2, 2, width_ratios=[1.6, 1])
    ax_a, ax_p = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[1, 0])
    ax_pol = fig.add_subplot(grid[:, 1], projection="polar")
    z = resp.complex_response[:, probe]
    for c, name in ((0, "v"), (1, "w")):
        ax_a.semilogy(resp.frequencies, np.abs(z[:, c]) * 1e6, label=name)
        ax_p.plot(resp.frequencies, np.degrees(np.angle(z[:, c])), label=name)
        ax_pol.plot(np.angle(z[:, c]), np.abs(z[:, c]) * 1e6, label=name)
    ax_a.semilogy(
        resp.frequencies, resp.major[:, probe] * 1e6, "k--", lw=1, label="major semi-axis"
    )
    default = (
        f"{resp.kind} force {resp.magnitude:g} N at x = {resp.position:g} m, probe x = "
        f"{resp.probes[probe]:g} m, spin {resp.speed_rad_s:g} rad/s"
    )
    ax_a.set(ylabel="amplitude (µm)", title=title or default)
    ax_p.set(xlabel="excitation frequency (rad/s)", ylabel="phase (deg)", ylim=(-185, 185))
    ax_pol.set_title("polar plot (radius in µm)", fontsize=10)
    for ax in (ax_a, ax_p):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    return fig


def clearance_figure(check: ClearanceCheck, title: str = "API 617 close-clearance check") -> Figure:
    """Scaled response at each close clearance against speed, with 75 % of the clearance and
    the clearance itself, and the probes' unscaled response with the vibration limit.

    Parameters
    ----------
    check : ClearanceCheck
        From :func:`rubrotor.linear.api617.clearance_check`.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Top: ``2 S_cc a_major`` (µm pk-pk) per clearance, 75 % of its diametral clearance
        (dashed) and the diametral clearance ``2 c`` itself (dotted), the operating range shaded
        and named. Bottom: every probe's unscaled amplitude (µm pk-pk) and ``A_vl``.
    """
    fig = Figure(figsize=(10, 7), layout="constrained")
    ax, ax_p = fig.subplots(2, 1, sharex=True)
    s = check.speeds
    marks = "os^vDx"
    for j, name in enumerate(check.names):
        c = check.clearances[j] * 1e6
        style = {"color": f"C{j}", "marker": marks[j % 6], "markevery": max(1, s.size // 12)}
        ax.plot(s, check.scaled[j] * 1e6, lw=2, ms=5, label=f"{name}: scaled response", **style)
        ax.axhline(0.75 * c, color=f"C{j}", ls="--", lw=1,
                   label=f"{name}: 75 % of the diametral clearance ({0.75 * c:.3g} µm)")  # fmt: skip
        ax.axhline(c, color=f"C{j}", ls=":", lw=1.3,
                   label=f"{name}: diametral clearance 2c = {c:.3g} µm (radial {c / 2:.3g} µm)")  # fmt: skip
    for k, a in enumerate((ax, ax_p)):
        a.axvspan(check.min_speed, check.max_speed, color="0.85", alpha=0.6, zorder=0,
                  label=f"operating range {check.min_speed:.5g}-{check.max_speed:.5g} rad/s"
                  if k == 0 else None)  # fmt: skip
        a.grid(alpha=0.3)
    ax.set(ylabel="major axis, µm peak to peak", title=f"{title}: S_cc = {check.scale_factor:.3g}")
    if np.max(check.scaled) > 20 * np.max(check.clearances):  # a peak far above: log, so the
        ax.set_yscale("log")  # clearance lines stay readable
        ax.set_ylim(bottom=max(1e-3 * np.max(check.clearances) * 1e6, ax.get_ylim()[0]))
    ax.legend(fontsize=8, loc="upper left")
    styles = ("-", "--", "-.", ":")
    for p, row in enumerate(check.probe_response):
        ax_p.plot(s, row * 1e6, lw=1.5, ls=styles[p % 4], label=f"probe {p + 1} (unscaled)")
    ax_p.axhline(check.vibration_limit * 1e6, color="k", lw=1.2, ls=(0, (6, 2, 1, 2)),
                 label=f"vibration limit A_vl = {check.vibration_limit * 1e6:.3g} µm")  # fmt: skip
    ax_p.set(xlabel="spin speed (rad/s)", ylabel="probe, µm peak to peak", yscale="log")
    ax_p.legend(fontsize=8, loc="lower right")
    return fig


def level1_figure(result: Level1, title: str = "API 684 Level I stability") -> Figure:
    """Log dec of the first forward mode against the added cross-coupled stiffness, with
    ``Q0`` (log dec 0), ``Q_A`` and the 0.1 screening line: the whole curve on the left, and on
    the right the band that decides the screening (log dec -0.05 to 0.2 or the data's range
    there) on a linear scale, so that the 0-0.1 band is not squashed by the deep negative tail.

    Parameters
    ----------
    result : Level1
        From :func:`rubrotor.linear.api684.level1`.
    title : str
        Figure title (name the scenario in it; the speed and the station are added).

    Returns
    -------
    matplotlib.figure.Figure
        Two panels: log dec (1) against Q (N/m, log axis), whole range and the screening band.
        Lines differ in style, not only in colour (grey-scale readable).
    """
    fig = Figure(figsize=(11, 4.8), layout="constrained")
    ax, ax_z = fig.subplots(1, 2, width_ratios=[1, 1.15])
    q, ld = np.asarray(result.stiffness), np.asarray(result.log_dec)
    hi = max(0.2, 1.15 * float(np.max(ld))) if ld.size else 0.2
    for a in (ax, ax_z):
        a.semilogx(q, ld, "k-o", ms=3, lw=1.5, label="first forward mode")
        a.axhline(0.0, color="0.4", lw=1)
        a.axhline(0.1, color="k", ls="--", lw=1, label="log dec 0.1 (API 684 screening)")
        if result.q0 is not None:
            a.axvline(result.q0, color="0.3", ls="-.", lw=1.2, label=f"Q0 = {result.q0:.3g} N/m")
        if result.qa is not None:
            a.axvline(result.qa, color="k", ls=":", lw=1.5, label=f"Q_A = {result.qa:.3g} N/m")
            a.plot(result.qa, result.log_dec_at_qa, "D", mfc="0.8", mec="k", ms=7)
        a.grid(alpha=0.3, which="both")
        a.set(xlabel="added cross-coupled stiffness Q (N/m)", ylabel="logarithmic decrement (1)")
    ax_z.set_ylim(-0.05, hi)
    inside = ld >= -0.05
    if np.any(inside) and result.q0 is not None:
        right = q[np.flatnonzero(ld < -0.05)[0]] if np.any(ld < -0.05) else q[-1]
        ax_z.set_xlim(q[0], max(right, 2 * result.q0, result.qa or 0.0) * 1.5)
    ax_z.axhspan(0.0, 0.1, color="0.9", zorder=0, label="0 < log dec < 0.1")
    ax.set_title("whole range", fontsize=10)
    ax_z.set_title("screening band (linear scale)", fontsize=10)
    ax_z.legend(fontsize=8, loc="lower left")
    verdict = f" ({result.verdict})" if result.verdict else ""
    fig.suptitle(f"{title} at {result.speed_rad_s:.5g} rad/s ({result.speed_rad_s * 30 / np.pi:.0f} "
                 f"rpm), cross-coupling at x = {result.position:g} m{verdict}")  # fmt: skip
    return fig
