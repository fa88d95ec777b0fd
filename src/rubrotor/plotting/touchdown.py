"""Figures of a touchdown-bearing drop (:mod:`rubrotor.engine.spin`): orbits in the clearance
circle, whirl frequency and direction against time, contact forces, rotor and ring speeds.
Returns a :class:`matplotlib.figure.Figure` that is not registered with pyplot.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

__all__ = ["whirl_frequency", "touchdown_figure"]


def whirl_frequency(t, v, w, window: float) -> np.ndarray:
    """Whirl frequency (rad/s) of an orbit: the mean rate of its polar angle over a window.

    ``phi = unwrap(atan2(w, v))`` and the frequency is ``(phi(t + T/2) - phi(t - T/2)) / T``
    (clamped at the ends): positive for forward whirl (turning from +v towards +w, as the spin),
    negative for backward whirl.

    Parameters
    ----------
    t : ndarray
        Times (s), evenly spaced.
    v, w : ndarray
        Displacements (m) from the stator centre.
    window : float
        Averaging window ``T`` (s).

    Returns
    -------
    ndarray
        Whirl frequency (rad/s) per sample.
    """
    t = np.asarray(t, float)
    phi = np.unwrap(np.arctan2(w, v))
    dt = t[1] - t[0]
    h = max(int(round(0.5 * window / dt)), 1)
    i = np.arange(t.size)
    lo, hi = np.clip(i - h, 0, t.size - 1), np.clip(i + h, 0, t.size - 1)
    return (phi[hi] - phi[lo]) / (t[hi] - t[lo])


def touchdown_figure(ds, window: float = 2e-3) -> Figure:
    """Four panels of a free-spin run with contacts (a :func:`rubrotor.engine.spin.simulate_free`
    Dataset).

    Parameters
    ----------
    ds : xarray.Dataset
        Results with ``v, w`` (m) at the contact stations, ``clearance`` (m), ``normal_force``
        (N), ``spin_speed``, ``ring_speed`` (rad/s), ``contact_radius``, ``ring_radius`` (m).
    window : float
        Window (s) of the whirl frequency (:func:`whirl_frequency`).

    Returns
    -------
    matplotlib.figure.Figure
        Orbits (µm) in the clearance circles; whirl frequency (rad/s, > 0 forward, < 0 backward)
        against time with the spin speed for scale; normal force (N) against time; rotor and ring
        speeds (rad/s) against time, with the ring speed of rolling without slip
        ``R Omega / r``.
    """
    fig = Figure(figsize=(11, 8), layout="constrained")
    (a1, a2), (a3, a4) = fig.subplots(2, 2)
    t = ds.time.values
    nc = ds.sizes["contact"]
    cols = ("tab:blue", "tab:red", "tab:green", "tab:purple")
    # contacts of a symmetric rotor often move alike: contact 1 wide and solid underneath, the
    # others narrower and dashed on top, so that none hides another (and grey scale reads them)
    styles = ("-", (0, (5, 2)), (0, (1, 1.5)), "-.")
    th = np.linspace(0, 2 * np.pi, 361)
    for i in range(nc):
        c, ls, lw = cols[i % len(cols)], styles[i % len(styles)], 1.8 if i == 0 else 0.9
        lab = f"contact {i + 1} at {float(ds.station.values[i]):g} m"
        v, w = ds.v.values[i], ds.w.values[i]
        g = float(ds.clearance.values[i])
        a1.plot(1e6 * w, 1e6 * v, color=c, lw=0.5 * lw, ls=ls, label=lab, zorder=2 + i)
        a1.plot(1e6 * g * np.cos(th), 1e6 * g * np.sin(th), color=c, ls=ls, lw=lw,
                label=f"clearance {1e6 * g:.4g} µm, contact {i + 1}", zorder=2 + i)  # fmt: skip
        a2.plot(t, whirl_frequency(t, v, w, window), color=c, lw=lw, ls=ls, label=lab, zorder=2 + i)
        a3.plot(t, ds.normal_force.values[i], color=c, lw=0.8 * lw, ls=ls, label=lab, zorder=2 + i)
        rr = float(ds.ring_radius.values[i])
        if rr > 0:
            a4.plot(t, ds.ring_speed.values[i], color=c, lw=lw, ls=ls, label=f"ring {i + 1}",
                    zorder=2 + i)  # fmt: skip
            roll = float(ds.contact_radius.values[i]) / rr * ds.spin_speed.values
            a4.plot(t, roll, color=c, ls=":", lw=0.8, zorder=2 + i,
                    label=f"rolling R Omega / r, ring {i + 1}")  # fmt: skip
    om = ds.spin_speed.values
    a2.plot(t, om, color="0.4", lw=0.8, ls="--", label="spin speed")
    a2.plot(t, -om, color="0.4", lw=0.8, ls=":", label="minus spin speed")
    a2.axhline(0, color="k", lw=0.5)
    a4.plot(t, om, color="k", lw=1.2, label="rotor")
    a1.set(xlabel="w (µm, horizontal)", ylabel="v (µm, vertical)", title="orbits in the clearance")
    a1.set_aspect("equal", adjustable="datalim")
    a2.set(xlabel="time (s)", ylabel="whirl frequency (rad/s, < 0 backward)",
           title=f"whirl frequency and direction ({window * 1e3:g} ms window)")  # fmt: skip
    a3.set(xlabel="time (s)", ylabel="normal force (N)", title="contact forces")
    a4.set(xlabel="time (s)", ylabel="speed (rad/s)", title="rotor and ring speeds")
    for ax in (a1, a2, a3, a4):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    fig.suptitle(f"{ds.attrs.get('scenario_name', '')}: touchdown drop".strip(": "))
    return fig
