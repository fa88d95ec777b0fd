"""Figures of the linear analyses of any rotor: Campbell diagram with stability, unbalance
response (Bode and polar) and mode shapes. One function per figure kind, each returning a
:class:`matplotlib.figure.Figure` that is not registered with pyplot.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from rubrotor.linear.analysis import CampbellData, DampedMode, LinearCritical, UnbalanceResponse
from rubrotor.rotors.linear import LinearSystem

__all__ = ["campbell_stability_figure", "unbalance_response_figure", "mode_shape_figure"]

TWO_PI = 2 * np.pi


def campbell_stability_figure(
    data: CampbellData,
    criticals: list[LinearCritical] = (),
    operating_speed: float | None = None,
    title: str = "Campbell diagram",
) -> Figure:
    """Damped frequencies against spin speed, coloured by logarithmic decrement.

    Stable modes are dots coloured by log dec (saturating at 1, well damped); unstable points
    (log dec < 0) are black crosses. The 1X line is dotted, critical speeds are diamonds.

    Parameters
    ----------
    data : CampbellData
        From :func:`rubrotor.linear.analysis.campbell_data`.
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
    # colour saturates at log dec 1 (well damped); the unstable points are drawn as crosses
    sc = ax.scatter(s[stable], f[stable], c=np.minimum(ld[stable], 1.0), s=9, cmap="viridis_r",
                    vmin=0.0, vmax=1.0)  # fmt: skip
    if (~stable).any():
        ax.scatter(s[~stable], f[~stable], marker="x", c="k", s=18, label="unstable (log dec < 0)")
    fmax = float(np.nanmax(f)) * 1.05
    ax.plot(data.speeds, data.speeds / TWO_PI, "k:", lw=1, label="1X")
    for i, c in enumerate(criticals):
        ax.plot(c.speed_rad_s, c.harmonic * c.speed_rad_s / TWO_PI, "D", mfc="gold", mec="k")
        ax.annotate(
            f"{c.speed_rad_s:.0f} rad/s ({c.whirl})",
            (c.speed_rad_s, c.harmonic * c.speed_rad_s / TWO_PI),
            textcoords="offset points",
            xytext=(8, -12 - 11 * (i % 3)),
            fontsize=8,
        )
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


def unbalance_response_figure(resp: UnbalanceResponse, probe: int = 0) -> Figure:
    """Bode (amplitude and phase of ``v`` and ``w`` against speed) and polar plot at one probe.

    Parameters
    ----------
    resp : UnbalanceResponse
        From :func:`rubrotor.linear.analysis.unbalance_response`.
    probe : int
        Index of the probe drawn.

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
    ax_a.set(ylabel="amplitude (µm)", title=f"unbalance response at x = {resp.probes[probe]:g} m")
    ax_p.set(xlabel="spin speed (rad/s)", ylabel="phase (deg)")
    ax_pol.set_title("polar plot (radius in µm)", fontsize=10)
    for ax in (ax_a, ax_p):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    return fig


def mode_shape_figure(system: LinearSystem, mode: DampedMode, phases: int = 8) -> Figure:
    """A mode's deflected shape along the rotor in both planes and its whirl orbits.

    Parameters
    ----------
    system : LinearSystem
        The rotor the mode belongs to.
    mode : DampedMode
        From :func:`rubrotor.linear.analysis.damped_modes`.
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
