"""Figures. One function per figure kind, each returning a :class:`matplotlib.figure.Figure`.

Figures are built on :class:`matplotlib.figure.Figure` directly (no ``pyplot``), so they work
with any backend, including none (Agg, headless), create no global state and change no global
style. Save them with ``fig.savefig(path)``.
"""

from __future__ import annotations

import math

from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from rubrotor.modal import campbell, critical_speeds
from rubrotor.model import Shaft

__all__ = ["campbell_figure", "bifurcation_figure", "regime_map_figure"]

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
    freq = data["frequency_hz"]  # (S, N, B)
    labels = data["labels"]
    spin_hz = sp / (2 * math.pi)
    lo_sp, hi_sp = float(sp.min()), float(sp.max())
    crits = [c for c in critical_speeds(shaft) if lo_sp <= c.speed_rad_s <= hi_sp]

    branches = ["bending", "shear"] if shaft.theory == "timoshenko" else ["bending"]
    fig = Figure(figsize=(10, 7 if len(branches) == 2 else 5.5), layout="constrained")
    if len(branches) == 2:
        ax_shear, ax_bend = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [1, 1.6]})
        panels = {"bending": ax_bend, "shear": ax_shear}
    else:
        ax_bend = fig.subplots(1, 1)
        panels = {"bending": ax_bend}

    for branch, ax in panels.items():
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
                    sp,
                    f,
                    color=_WHIRL_COLOR[whirl],
                    linestyle=_BRANCH_STYLE[branch_j],
                    linewidth=1.6,
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
        ax.plot(sp, spin_hz, color="black", linestyle=":", linewidth=1.4)
        ax.set_ylim(ymin, ymax)
        ax.set_xlim(lo_sp, hi_sp)
        ax.grid(True, alpha=0.3)
        ax.set_ylabel("Whirl frequency (Hz)")
        for c in crits:
            if c.branch != branch:
                continue
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
        if operating_speed is not None:
            ax.axvline(operating_speed, color="0.45", linestyle="-.", linewidth=1.3)

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
    fig.suptitle(
        f"Campbell diagram: {_THEORY_NAME[shaft.theory]} shaft, L = {shaft.length:g} m, "
        f"D = {shaft.diameter * 1e3:g} mm"
        + (f", \u03ba = {shaft.kappa:.4g}" if shaft.theory == "timoshenko" else "")
        + ("" if shaft.gyroscopic else ", no gyroscopic moments"),
        fontsize=11,
    )
    return fig


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


# ---- sweeps ------------------------------------------------------------------------------------
_REGIME_COLORS = {
    "no contact": "0.65",
    "full annular rub": "tab:red",
    "quasi-periodic": "tab:green",
    "chaotic": "black",
    "not classified": "tab:pink",
    "not computed": "white",
}
_PERIOD_COLORS = ["tab:blue", "tab:orange", "tab:purple", "tab:cyan", "tab:olive", "tab:brown"]


def _regime_color(label: str) -> str:
    if label in _REGIME_COLORS:
        return _REGIME_COLORS[label]
    k = int(label.rsplit("-", 1)[1].rstrip(")"))  # "partial rub (period-k)"
    return _PERIOD_COLORS[(k - 1) % len(_PERIOD_COLORS)]


def _label_order(label: str) -> tuple:
    order = ["no contact", "partial rub", "full annular rub", "quasi-periodic", "chaotic"]
    for i, name in enumerate(order):
        if label.startswith(name):
            k = int(label.rsplit("-", 1)[1].rstrip(")")) if name == "partial rub" else 0
            return (i, k)
    return (len(order), 0)


def _is_log_spaced(v) -> bool:
    """True for 3+ positive values evenly spaced in logarithm but not linearly."""
    import numpy as np

    v = np.asarray(v, float)
    if v.size < 3 or not np.all(v > 0):
        return False
    lv = np.diff(np.log(v))
    return bool(np.allclose(lv, lv[0]) and not np.allclose(np.diff(v), v[1] - v[0]))


def _axis_label(ds, key: str) -> str:
    units = ds[key].attrs.get("units", "")
    if units == "x first forward critical":
        return f"{key}  ($\\Omega$ / first forward critical speed)"
    return f"{key} ({units})" if units and units != "1" else key


def bifurcation_figure(ds, key: str) -> Figure:
    """Bifurcation diagram of a sweep: Poincare samples of ``v`` and ``w`` against one key.

    Each kept once-per-revolution sample ``v(k 2 pi / Omega)`` (top) and ``w`` (bottom) at the
    contact station is a dot above the swept value, coloured by the point's regime (legend);
    a periodic orbit shows as ``k`` dots, a quasi-periodic or chaotic one as a vertical band.
    The clearance (when constant) is drawn as dashed lines at ``+-g``.

    Parameters
    ----------
    ds : xarray.Dataset
        A :func:`rubrotor.sweep.sweep` result; other swept keys must have a single value.
    key : str
        The swept key on the horizontal axis.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import numpy as np
    from matplotlib.lines import Line2D

    from rubrotor.sweep import regime_labels

    if key not in ds.dims:
        raise ValueError(f"{key!r} is not a swept key of this Dataset ({list(ds['done'].dims)})")
    others = [d for d in ds["done"].dims if d != key]
    for d in others:
        if ds.sizes[d] != 1:
            raise ValueError(f"select one value of {d!r} first (ds.isel({d}=i))")
    ds1 = ds.isel({d: 0 for d in others})
    x = ds1[key].values
    labels = regime_labels(ds1)
    fig = Figure(figsize=(10, 7), layout="constrained")
    axes = fig.subplots(2, 1, sharex=True)
    clearance = ds.attrs.get("clearance_m")
    if any(d.startswith(("contact.clearance", "shaft.length")) for d in ds["done"].dims):
        clearance = None
    present = sorted(set(labels.tolist()), key=_label_order)
    nrev = ds1.sizes["revolution"]
    for ax, name, comp in ((axes[0], "poincare_v", "v"), (axes[1], "poincare_w", "w")):
        y = ds1[name].values * 1e3  # mm
        for lab in present:
            sel = labels == lab
            xs = np.repeat(x[sel], nrev)
            ax.plot(
                xs, y[sel].ravel(), color=_regime_color(lab), marker=".", markersize=1.5,
                linestyle="none", alpha=0.8,
            )  # fmt: skip
        if clearance is not None:
            for s in (1, -1):
                ax.axhline(s * clearance * 1e3, color="0.3", linestyle="--", linewidth=0.8)
        ax.set_ylabel(f"Poincare samples of {comp} (mm)")
        ax.grid(True, alpha=0.3)
    axes[1].set_xlabel(_axis_label(ds, key))
    if _is_log_spaced(x):
        axes[1].set_xscale("log")
    handles = [
        Line2D([], [], color=_regime_color(lab), marker="o", linestyle="none", label=lab)
        for lab in present
    ]
    if clearance is not None:
        handles.append(
            Line2D([], [], color="0.3", linestyle="--", label=f"clearance {clearance * 1e3:.3g} mm")
        )
    fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 4), fontsize=9)
    fig.suptitle(
        f"Bifurcation diagram: {ds.attrs.get('scenario_name', '')}\n"
        f"once-per-revolution samples at the contact station, {nrev} revolutions kept after "
        f"{ds.attrs.get('transient_revolutions')} discarded",
        fontsize=10,
    )
    return fig


def regime_map_figure(ds, key_x: str, key_y: str) -> Figure:
    """Regime map of a 2-D sweep: one categorical colour per regime label, with a legend.

    Parameters
    ----------
    ds : xarray.Dataset
        A :func:`rubrotor.sweep.sweep` result over (at least) ``key_x`` and ``key_y``; any other
        swept key must have a single value.
    key_x, key_y : str
        Swept keys on the horizontal and vertical axes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import numpy as np
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    from rubrotor.sweep import regime_labels

    for k in (key_x, key_y):
        if k not in ds.dims:
            raise ValueError(f"{k!r} is not a swept key of this Dataset")
    others = [d for d in ds["done"].dims if d not in (key_x, key_y)]
    for d in others:
        if ds.sizes[d] != 1:
            raise ValueError(f"select one value of {d!r} first (ds.isel({d}=i))")
    ds2 = ds.isel({d: 0 for d in others}).transpose(key_y, key_x, ...)
    labels = regime_labels(ds2)
    present = sorted(set(labels.ravel().tolist()), key=_label_order)
    codes = np.vectorize(present.index)(labels)
    cmap = ListedColormap([_regime_color(lab) for lab in present])

    def edges(v):
        v = np.asarray(v, float)
        if v.size == 1:
            return np.array([v[0] * 0.95, v[0] * 1.05]) if v[0] else np.array([-0.5, 0.5])
        if (
            np.all(v > 0)
            and np.allclose(np.diff(np.log(v)), np.log(v[1] / v[0]))
            and (not np.allclose(np.diff(v), v[1] - v[0]))
        ):
            lv = np.log(v)
            mid = (lv[1:] + lv[:-1]) / 2
            return np.exp(np.concatenate([[2 * lv[0] - mid[0]], mid, [2 * lv[-1] - mid[-1]]]))
        mid = (v[1:] + v[:-1]) / 2
        return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])

    fig = Figure(figsize=(9, 6), layout="constrained")
    ax = fig.subplots()
    xe, ye = edges(ds2[key_x].values), edges(ds2[key_y].values)
    ax.pcolormesh(
        xe, ye, codes, cmap=cmap, vmin=-0.5, vmax=len(present) - 0.5, edgecolors="white",
        linewidth=0.3,
    )  # fmt: skip
    if _is_log_spaced(ds2[key_x].values):
        ax.set_xscale("log")
    if _is_log_spaced(ds2[key_y].values):
        ax.set_yscale("log")
    ax.set_xlabel(_axis_label(ds, key_x))
    ax.set_ylabel(_axis_label(ds, key_y))
    handles = [Patch(facecolor=_regime_color(lab), edgecolor="0.3", label=lab) for lab in present]
    fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 4), fontsize=9)
    fig.suptitle(f"Rub regime map: {ds.attrs.get('scenario_name', '')}", fontsize=11)
    return fig
