"""Figure of the fluid-film supports over speed: the journal's static locus in its clearance
circle, and the linearised coefficients against speed. Returns a :class:`matplotlib.figure.Figure`
that is not registered with pyplot."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from rubrotor.linear.bearings import BearingsResult

__all__ = ["bearings_figure"]


def bearings_figure(result: BearingsResult, title: str = "fluid films") -> Figure:
    """The eccentricity locus and the coefficients of every fluid-film support against speed.

    Parameters
    ----------
    result : BearingsResult
        From :func:`rubrotor.linear.bearings.bearing_coefficients`.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Left: each journal's static centre ``(z0, y0) / c`` (1) inside the unit clearance circle,
        the speeds marked at the ends. Middle: stiffness coefficients (N/m) against speed
        (rad/s). Right: damping coefficients (N s/m) against speed (rad/s).
    """
    fig = Figure(figsize=(13, 4.6), layout="constrained")
    ax_l, ax_k, ax_c = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1, 1.2, 1.2]})
    t = np.linspace(0, 2 * np.pi, 361)
    ax_l.plot(np.cos(t), np.sin(t), "k", lw=1)
    names = list(dict.fromkeys(r.name for r in result.rows))
    styles = ("-", "--", ":", "-.")
    for j, name in enumerate(names):
        rows = [r for r in result.rows if r.name == name]
        c = rows[0].term.radial_clearance
        p = np.array([r.p0 for r in rows]) / c
        w = np.array([r.speed_rad_s for r in rows])
        ax_l.plot(p[:, 1], p[:, 0], f"C{j}", ls=styles[j % 4], marker=".", label=name)
        for i in (0, -1):
            ax_l.annotate(f"{w[i]:.4g} rad/s", (p[i, 1], p[i, 0]), fontsize=7,
                          textcoords="offset points", xytext=(4, 4))  # fmt: skip
        k = np.array([r.K0 for r in rows])
        cc = np.array([r.C0 for r in rows])
        for a, (ii, jj, lab) in enumerate(((0, 0, "yy"), (0, 1, "yz"), (1, 0, "zy"), (1, 1, "zz"))):
            kw = {"color": f"C{a}", "ls": styles[j % 4]}
            ax_k.plot(w, k[:, ii, jj], label=f"k{lab} {name}", **kw)
            ax_c.plot(w, cc[:, ii, jj], label=f"c{lab} {name}", **kw)
    ax_l.set(xlabel="z0 / c (1)", ylabel="y0 / c (1)", aspect="equal", xlim=(-1.1, 1.1),
             ylim=(-1.1, 1.1), title="static journal centre in the clearance circle")  # fmt: skip
    ax_k.set(xlabel="speed (rad/s)", ylabel="stiffness (N/m)", title="stiffness K0")
    ax_c.set(xlabel="speed (rad/s)", ylabel="damping (N s/m)", title="damping C0")
    for ax in (ax_l, ax_k, ax_c):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(title)
    return fig
