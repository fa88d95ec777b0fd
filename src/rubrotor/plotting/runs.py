"""Figures of the continuous shaft's time runs: the six-panel response (seed Figs. 3-5), two
beam theories compared (seed Fig. 6) and the orbit envelopes per revolution, each returning a
:class:`matplotlib.figure.Figure` not registered with pyplot.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

__all__ = ["response_figure", "theory_comparison_figure", "envelope_figure"]


def response_figure(ds, *, title: str | None = None, clearance: float | None = None) -> Figure:
    """Six-panel response figure like seed Figs. 3-5.

    (a) horizontal displacement v and (c) vertical displacement w against time with the
    clearance marked, (b), (d) their phase portraits, (e) the normal contact force against time,
    (f) the orbit with the clearance circle.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`rubrotor.simulate`.
    title : str, optional
        Figure title.
    clearance : float, optional
        Radial clearance (m); default from ``ds.attrs["parameters"]`` (none without contact).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import json

    if clearance is None:
        params = json.loads(ds.attrs.get("parameters", "{}"))
        clearance = (params.get("contact.clearance") or [None])[0]
    t = ds["time"].values * 1e3
    v = ds["v"].values[0] * 1e3  # station 0: the contact station (midspan without contact)
    w = ds["w"].values[0] * 1e3
    vd = ds["v_dot"].values[0]
    wd = ds["w_dot"].values[0]
    fn = ds["normal_force"].values.sum(axis=0) * 1e-3  # no contact: zeros
    fig = Figure(figsize=(12, 11), layout="constrained")
    axes = fig.subplots(3, 2)
    g = None if clearance is None else clearance * 1e3
    for row, (x, xd, name) in enumerate(((v, vd, "v (horizontal)"), (w, wd, "w (vertical)"))):
        ax = axes[row, 0]
        ax.plot(t, x, linewidth=0.5, color="tab:blue")
        if g is not None:
            for s in (1, -1):
                ax.axhline(s * g, color="black", linewidth=1.0)
        ax.set_xlabel("Time (ms)")
        ax.set_ylabel(f"{name} (mm)")
        ax.set_xlim(t[0], t[-1])
        ax = axes[row, 1]
        ax.plot(x, xd, linewidth=0.3, color="tab:blue")
        ax.set_xlabel(f"{name.split()[0]} (mm)")
        ax.set_ylabel(f"d{name.split()[0]}/dt (m/s)")
    axes[2, 0].plot(t, fn, linewidth=0.5, color="tab:red")
    axes[2, 0].set_xlabel("Time (ms)")
    axes[2, 0].set_ylabel("Normal contact force (kN)")
    axes[2, 0].set_xlim(t[0], t[-1])
    if not np.any(fn > 0):
        axes[2, 0].text(
            0.5,
            0.5,
            "no contact",
            transform=axes[2, 0].transAxes,
            ha="center",
            va="center",
            fontsize=12,
            color="0.4",
        )
    ax = axes[2, 1]
    ax.plot(v, w, linewidth=0.3, color="tab:blue")
    if g is not None:
        th = np.linspace(0, 2 * np.pi, 361)
        ax.plot(g * np.cos(th), g * np.sin(th), color="black", linewidth=1.2, label="clearance")
        ax.legend(fontsize=8, loc="upper right")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("v (mm)")
    ax.set_ylabel("w (mm)")
    for ax, letter in zip(axes[:, 0], "ace", strict=True):
        ax.set_title(f"({letter})", loc="left", fontsize=10)
    for ax, letter in zip(axes[:, 1], "bdf", strict=True):
        ax.set_title(f"({letter})", loc="left", fontsize=10)
    for ax in axes.flat:
        ax.grid(True, alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


def theory_comparison_figure(
    ds_a,
    ds_b,
    *,
    labels=("Timoshenko", "Euler-Bernoulli"),
    variable: str = "w",
    title: str | None = None,
) -> Figure:
    """Two responses of the same rotor under two beam theories (seed Fig. 6) and their difference.

    Parameters
    ----------
    ds_a, ds_b : xarray.Dataset
        Results on the same time grid.
    labels : (str, str)
        Legend names.
    variable : {"v", "w"}
        Displacement compared (m, plotted in mm).
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Top: both responses; bottom: their difference (same unit, mm).
    """

    t = ds_a["time"].values * 1e3
    a = ds_a[variable].values[0] * 1e3  # station 0: the contact station (midspan)
    b = ds_b[variable].values[0] * 1e3
    n = min(a.size, b.size)
    fig = Figure(figsize=(11, 6.5), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [1.6, 1]})
    ax1.plot(t[:n], a[:n], color="tab:blue", linewidth=1.4, label=labels[0])
    ax1.plot(t[:n], b[:n], color="tab:orange", linewidth=1.0, linestyle="--", label=labels[1])
    ax1.set_ylabel(f"{variable} at midspan (mm)")
    ax1.legend(fontsize=9, loc="upper right")
    ax2.plot(t[:n], a[:n] - b[:n], color="0.2", linewidth=0.8)
    ax2.set_ylabel(f"difference {variable} (mm)")
    ax2.set_xlabel("Time (ms)")
    rel = float(np.max(np.abs(a[:n] - b[:n])) / np.max(np.abs(a[:n])))
    ax2.set_title(f"max |difference| / max |{variable}| = {rel:.2e}", fontsize=9, loc="left")
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
        ax.set_xlim(t[0], t[n - 1])
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


def envelope_figure(envelopes: dict, *, title: str | None = None) -> Figure:
    """Largest orbit radius per revolution (or block of revolutions) relative to the clearance.

    Parameters
    ----------
    envelopes : dict
        ``{(case, variant): (revolution, max_abs_P_over_g)}``; one colour per case, one
        line style per variant (first variant solid, second dashed).
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Logarithmic |P|/g axis (dimensionless) against revolutions; the clearance (|P|/g = 1)
        is a black line.
    """
    fig = Figure(figsize=(10, 4.8), layout="constrained")
    ax = fig.subplots()
    cases = list(dict.fromkeys(k[0] for k in envelopes))
    variants = list(dict.fromkeys(k[1] for k in envelopes))
    styles = ["-", "--", ":"]
    colors = ["tab:blue", "tab:orange", "tab:green", "tab:purple"]
    for (case, variant), (rev, val) in envelopes.items():
        ax.semilogy(
            rev,
            val,
            color=colors[cases.index(case) % 4],
            linestyle=styles[variants.index(variant) % 3],
            linewidth=1.2,
            label=f"{case}, {variant}",
        )
    ax.axhline(1.0, color="black", linewidth=1.0, label="clearance")
    ax.set_xlabel("Revolution")
    ax.set_ylabel("max |P| / g (-)")
    ax.grid(True, which="both", alpha=0.3)
    fig.legend(fontsize=8, loc="outside right upper")
    if title:
        fig.suptitle(title, fontsize=11)
    return fig
