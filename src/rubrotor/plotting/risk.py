"""Figures of a risk analysis: the probability of rub against speed with its interval, and the
Sobol' indices of the varied keys. Each function returns a :class:`matplotlib.figure.Figure`
not registered with pyplot.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from rubrotor.sweeps.risk import RiskResult

__all__ = ["risk_figure", "sobol_figure"]


def risk_figure(result: RiskResult) -> Figure:
    """P(rub) (1) against spin speed (rad/s, and rpm on the top axis) with its Wilson band.

    Parameters
    ----------
    result : RiskResult
        From :func:`rubrotor.risk`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(7, 4), layout="constrained")
    ax = fig.add_subplot()
    s = result.speeds
    level = f"{100 * result.confidence:g} % Wilson interval"
    if s.size > 1:
        ax.fill_between(s, result.lower, result.upper, color="C0", alpha=0.25, label=level)
        ax.plot(s, result.probability, "C0-", label="P(rub)")
    else:
        err = [result.probability - result.lower, result.upper - result.probability]
        ax.errorbar(s, result.probability, yerr=err, fmt="o", capsize=4, label=f"P(rub), {level}")
    ax.set_xlabel("spin speed (rad/s)")
    ax.set_ylabel("probability of rub (1)")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(alpha=0.3)
    top = ax.secondary_xaxis("top", functions=(lambda w: w * 30 / np.pi, lambda n: n * np.pi / 30))
    top.set_xlabel("spin speed (rpm)")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"{result.method} method, N = {result.samples} samples ({result.sampler})",
                 fontsize=9)  # fmt: skip
    return fig


def sobol_figure(result: RiskResult) -> Figure:
    """First-order and total Sobol' indices (1) of each varied key, with their intervals: of
    "rubs at some speed" (left; empty when every sample, or none, rubs somewhere) and of the
    smallest margin over the speeds (right).

    Parameters
    ----------
    result : RiskResult
        From :func:`rubrotor.risk` with ``sobol=True``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from rubrotor.errors import InputError

    if result.sobol is None:
        raise InputError("sobol", None, "a risk result computed with sobol=True (--sobol)")
    keys = list(result.keys)
    fig = Figure(figsize=(max(8, 2.4 * len(keys) + 3), 4), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    x = np.arange(len(keys))
    for ax, output, title in zip(axes, ("rub", "margin"), ("rub at some speed",
                                 "smallest margin over the speeds"), strict=True):  # fmt: skip
        rows = result.sobol[output]
        for off, what, colour in ((-0.18, "first", "C0"), (0.18, "total", "C1")):
            val = np.array([np.nan if rows[k][what] is None else rows[k][what] for k in keys])
            iv = np.array([[np.nan if v is None else v for v in rows[k][f"{what}_interval"]]
                           for k in keys])  # fmt: skip
            err = np.abs(np.vstack([val - iv[:, 0], iv[:, 1] - val]))
            ax.bar(x + off, np.nan_to_num(val), 0.36, yerr=np.nan_to_num(err), capsize=3,
                   color=colour, label="first-order" if what == "first" else "total")  # fmt: skip
        if all(rows[k]["first"] is None for k in keys):
            ax.text(0.5, 0.5, "not defined: the output\ndoes not vary", ha="center",
                    transform=ax.transAxes, fontsize=9)  # fmt: skip
        ax.set_xticks(x, keys, rotation=15, ha="right", fontsize=8)
        ax.axhline(0, color="k", lw=0.6)
        ax.grid(axis="y", alpha=0.3)
        ax.set_title(f"of {title}", fontsize=9)
    axes[0].set_ylabel("Sobol' index (1)")
    axes[1].legend(fontsize=8)
    fig.suptitle(f"Sobol' indices, {100 * result.confidence:g} % bootstrap intervals, "
                 f"N = {result.samples}", fontsize=10)  # fmt: skip
    return fig
