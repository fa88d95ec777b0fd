"""Figures of thermal rub (:mod:`rubrotor.studies.thermal`): the 1X polar spiral over time and
the growth rate and spiral period against speed. Each function returns a
:class:`matplotlib.figure.Figure` that is not registered with pyplot.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

__all__ = ["spiral_figure", "growth_figure"]


def spiral_figure(ds, axis: str = "y") -> Figure:
    """The 1X vector of every probe in a polar plot, over machine time (the operators' plot).

    Parameters
    ----------
    ds : xarray.Dataset
        A slow run (:func:`rubrotor.studies.thermal.slow_run`).
    axis : {"y", "z"}
        Probe direction whose 1X phasor is drawn.

    Returns
    -------
    matplotlib.figure.Figure
        One polar panel per station (contacts, then probes): radius the 1X amplitude (µm),
        angle its phase (rad, rotor-fixed frame, from the unbalance reference), colour the
        machine time (h); the start is a circle, the end a square.
    """
    if axis not in ("y", "z"):
        raise ValueError(f"axis = {axis!r} is not allowed: expected 'y' or 'z'")
    a = 0 if axis == "y" else 1
    vec = ds["one_x_real"].values[:, :, a] + 1j * ds["one_x_imag"].values[:, :, a]
    hours = ds["time"].values / 3600.0
    stations = ds["station"].values
    n = len(stations)
    fig = Figure(figsize=(4.2 * n, 4.6), layout="constrained")
    axes = [fig.add_subplot(1, n, i + 1, projection="polar") for i in range(n)]
    for i, ax in enumerate(axes):
        z = vec[:, i] * 1e6
        ax.plot(np.angle(z), np.abs(z), color="0.6", lw=0.8)
        sc = ax.scatter(np.angle(z), np.abs(z), c=hours, cmap="viridis", s=12, zorder=3)
        ax.plot(np.angle(z[0]), abs(z[0]), "o", mfc="none", mec="k", ms=9)
        ax.plot(np.angle(z[-1]), abs(z[-1]), "s", mfc="none", mec="k", ms=9)
        ax.yaxis.set_major_locator(MaxNLocator(4))
        ax.tick_params(labelsize=8)
        kind = "contact" if i < int(ds.attrs.get("n_contacts", 0)) else "probe"
        ax.set_title(f"{kind} at {stations[i]:.3g} m: 1X {axis} (µm)", fontsize=10)
    fig.colorbar(sc, ax=axes, label="machine time (h)", shrink=0.8)
    status = ds.attrs.get("status", "")
    name = ds.attrs.get("scenario_name", "")
    fig.suptitle(f"{name + ': ' if name else ''}thermal spiral at {ds.attrs['speed_rad_s']:.1f} "
                 f"rad/s ({status})")  # fmt: skip
    if status == "runaway":
        fig.text(0.5, 0.0, "caveat: the run stops when a bow passes its limit (default 50 "
                 "clearances); amplitudes of more than a few clearances lie outside the model "
                 "(an elastic seal that neither wears nor yields)", ha="center", va="bottom",
                 fontsize=8, color="0.25", wrap=True)  # fmt: skip
    return fig


def growth_figure(speeds, growth_rate, spiral_period, criticals=()) -> Figure:
    """Growth rate and spiral period of the thermal bow against spin speed.

    Parameters
    ----------
    speeds : array_like
        Spin speeds (rad/s).
    growth_rate : array_like
        Largest real part of the slow dynamics' eigenvalues (1/s); > 0 the spiral grows.
    spiral_period : array_like
        ``2 pi / |Im lambda|`` (s); inf where the eigenvalue is real (no spiral).
    criticals : sequence of float
        Forward critical speeds (rad/s) to mark.

    Returns
    -------
    matplotlib.figure.Figure
        Top: growth rate (1/h) with the growing side shaded; bottom: spiral period (min, log
        scale); the critical speeds as dashed vertical lines.
    """
    w = np.asarray(speeds, float)
    g = np.asarray(growth_rate, float) * 3600.0
    p = np.asarray(spiral_period, float) / 60.0
    fig = Figure(figsize=(7.5, 6.5), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ax1.plot(w, g, "o-", color="tab:red")
    ax1.axhline(0.0, color="k", lw=0.8)
    top = np.nanmax(np.abs(g)) if np.any(np.isfinite(g)) else 1.0
    ax1.axhspan(0.0, 1.1 * top, color="tab:red", alpha=0.07, label="spiral grows")
    ax1.set_ylabel("growth rate (1/h)")
    finite = np.isfinite(p)
    ax2.semilogy(w[finite], p[finite], "o-", color="tab:blue")
    ax2.set_ylabel("spiral period (min)")
    ax2.set_xlabel("spin speed (rad/s)")
    for ax in (ax1, ax2):
        for k, c in enumerate(criticals):
            ax.axvline(c, color="0.3", ls="--", lw=1.0,
                       label="forward critical speed" if k == 0 and ax is ax1 else None)  # fmt: skip
        ax.grid(alpha=0.3, which="both")
    ax1.legend(loc="best", fontsize=8)
    if not np.all(finite):
        ax2.text(0.01, 0.02, "no point: real eigenvalue (no spiral)", transform=ax2.transAxes,
                 fontsize=8, color="0.4")  # fmt: skip
    fig.suptitle("Thermal bow: linearised slow dynamics against speed")
    if math.isfinite(top):
        ax1.set_ylim(-1.1 * top, 1.1 * top)
    return fig
