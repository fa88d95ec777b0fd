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
    ax.plot(x, d[:, 1], "C1", lw=2, label="w (along z)")
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
    for b in result.bearings:
        for comp, color, dx in ((b.force_y, "C0", -0.004), (b.force_z, "C1", 0.004)):
            xb = b.position + dx * (x[-1] - x[0])
            ax_f.annotate(
                "", (xb, comp), (xb, 0.0), arrowprops={"arrowstyle": "->", "color": color, "lw": 2}
            )
        ax_f.annotate(
            f"{b.name}\nF_y = {b.force_y:.4g} N\nF_z = {b.force_z:.4g} N",
            (b.position, 0.0),
            textcoords="offset points",
            xytext=(8, -30 if b.force_y > 0 else 10),
            fontsize=8,
        )
    ax_f.plot([], [], "C0", label="F_y on the rotor")
    ax_f.plot([], [], "C1", label="F_z on the rotor")
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
        Top: ``2 S_cc a_major`` (µm pk-pk) per clearance, its 75 % limit (dashed) and ``2 c``
        (dotted), the operating band shaded. Bottom: probe amplitudes (µm pk-pk), ``A_vl``.
    """
    fig = Figure(figsize=(10, 7), layout="constrained")
    ax, ax_p = fig.subplots(2, 1, sharex=True)
    s = check.speeds
    for j, name in enumerate(check.names):
        c = check.clearances[j] * 1e6
        ax.plot(s, check.scaled[j] * 1e6, f"C{j}", lw=2, label=f"{name}: scaled response")
        ax.axhline(0.75 * c, color=f"C{j}", ls="--", lw=1, label=f"{name}: 75 % of {c:g} µm")
        ax.axhline(c, color=f"C{j}", ls=":", lw=1, label=f"{name}: clearance {c:g} µm")
    for a in (ax, ax_p):
        a.axvspan(check.min_speed, check.max_speed, color="0.85", alpha=0.6)
        a.grid(alpha=0.3)
    ax.set(ylabel="µm peak to peak", title=f"{title}: S_cc = {check.scale_factor:.3g}")
    ax.legend(fontsize=8, loc="upper left")
    for p, row in enumerate(check.probe_response):
        ax_p.plot(s, row * 1e6, lw=1.5, label=f"probe {p + 1}")
    ax_p.axhline(check.vibration_limit * 1e6, color="r", lw=1, label="A_vl")
    ax_p.set(xlabel="spin speed (rad/s)", ylabel="probe µm pk-pk (unscaled)", yscale="log")
    ax_p.legend(fontsize=8, loc="upper left")
    return fig


def level1_figure(result: Level1, title: str = "API 684 Level I stability") -> Figure:
    """Log dec of the first forward mode against the added cross-coupled stiffness, with
    ``Q0`` (log dec 0), ``Q_A`` and the 0.1 screening line.

    Parameters
    ----------
    result : Level1
        From :func:`rubrotor.linear.api684.level1`.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(8, 5), layout="constrained")
    ax = fig.subplots()
    ax.semilogx(result.stiffness, result.log_dec, "k-o", ms=3, label="first forward mode")
    ax.axhline(0.0, color="0.4", lw=1)
    ax.axhline(0.1, color="r", ls="--", lw=1, label="log dec 0.1")
    if result.q0 is not None:
        ax.axvline(result.q0, color="C3", lw=1, label=f"Q0 = {result.q0:.3g} N/m")
    if result.qa is not None:
        ax.axvline(result.qa, color="C0", lw=1.5, label=f"Q_A = {result.qa:.3g} N/m")
        ax.plot(result.qa, result.log_dec_at_qa, "D", mfc="gold", mec="k")
    verdict = f" ({result.verdict})" if result.verdict else ""
    ax.set(xlabel="added cross-coupled stiffness Q (N/m)", ylabel="logarithmic decrement",
           title=f"{title} at {result.speed_rad_s:.5g} rad/s, x = {result.position:g} m{verdict}")  # fmt: skip
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    return fig
