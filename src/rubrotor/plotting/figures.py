"""Figures. One function per figure kind, each returning a :class:`matplotlib.figure.Figure`.

Figures are built on :class:`matplotlib.figure.Figure` directly (no ``pyplot``), so they work
with any backend, including none (Agg, headless), create no global state and change no global
style. Save them with ``fig.savefig(path)``.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from rubrotor.linear.shaft import campbell, critical_speeds
from rubrotor.rotors.shaft import Shaft

__all__ = ["campbell_figure", "bifurcation_figure", "regime_map_figure", "branch_figure"]

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
    lo_sp, hi_sp = float(sp.min()), float(sp.max())
    crits = [c for c in critical_speeds(shaft) if lo_sp <= c.speed_rad_s <= hi_sp]
    fig, panels = _campbell_panels(shaft)
    for branch, ax in panels.items():
        _campbell_curves(ax, branch, data)
        ax.set_xlim(lo_sp, hi_sp)
        ax.grid(True, alpha=0.3)
        ax.set_ylabel("Whirl frequency (Hz)")
        _campbell_criticals(ax, [c for c in crits if c.branch == branch])
        if operating_speed is not None:
            ax.axvline(operating_speed, color="0.45", linestyle="-.", linewidth=1.3)
    _campbell_axes(panels, operating_speed)
    _campbell_legend(fig, panels, bool(crits), operating_speed)
    fig.suptitle(
        f"Campbell diagram: {_THEORY_NAME[shaft.theory]} shaft, L = {shaft.length:g} m, "
        f"D = {shaft.diameter * 1e3:g} mm"
        + (f", \u03ba = {shaft.kappa:.4g}" if shaft.theory == "timoshenko" else "")
        + ("" if shaft.gyroscopic else ", no gyroscopic moments"),
        fontsize=11,
    )
    return fig


def _campbell_panels(shaft: Shaft) -> tuple[Figure, dict]:
    """The figure and its panels: bending only, or shear above bending (Timoshenko)."""
    two = shaft.theory == "timoshenko"
    fig = Figure(figsize=(10, 7 if two else 5.5), layout="constrained")
    if two:
        ax_shear, ax_bend = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [1, 1.6]})
        return fig, {"bending": ax_bend, "shear": ax_shear}
    return fig, {"bending": fig.subplots(1, 1)}


def _campbell_curves(ax, branch: str, data: dict) -> None:
    """Whirl frequencies (Hz) of one branch against spin speed (rad/s), labelled, and 1X."""
    sp, freq, labels = data["speed_rad_s"], data["frequency_hz"], data["labels"]
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
                sp, f, color=_WHIRL_COLOR[whirl], linestyle=_BRANCH_STYLE[branch_j], linewidth=1.6
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
    ax.plot(sp, sp / (2 * math.pi), color="black", linestyle=":", linewidth=1.4)
    ax.set_ylim(ymin, ymax)


def _campbell_criticals(ax, crits) -> None:
    """Diamonds at the critical speeds (rad/s), annotated."""
    for c in crits:
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


def _campbell_axes(panels: dict, operating_speed: float | None) -> None:
    """Speed axes (rad/s below, rev/min on top), operating-speed label, panel titles."""
    ax_bend = panels["bending"]
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


def _campbell_legend(fig, panels: dict, crits: bool, operating_speed: float | None) -> None:
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
    "aperiodic": "darkslategray",
    "indentation > clearance": "gold",
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
    order = ["no contact", "partial rub", "full annular rub", "quasi-periodic", "aperiodic",
             "chaotic", "indentation > clearance"]  # fmt: skip
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


def _key_label(key: str) -> str:
    """``key (unit)`` from the scenario schema (as :func:`_axis_label` does from a sweep)."""
    from rubrotor.scenario.schema import key_unit

    units = key_unit(key)
    if units == "x first forward critical":
        return f"{key}  ($\\Omega$ / first forward critical speed)"
    return f"{key} ({units})" if units and units != "1" else key


def _axis_label(ds, key: str) -> str:
    units = ds[key].attrs.get("units", "")
    if units == "x first forward critical":
        return f"{key}  ($\\Omega$ / first forward critical speed)"
    return f"{key} ({units})" if units and units != "1" else key


_DIRECTION_STYLE = {"up": ("^", 3.5, -1), "down": ("v", 3.5, 1)}
_DIRECTION_TEXT = {"up": "up sweep (filled, left)", "down": "down sweep (hollow, right)"}


def _direction_runs(ds1, x):
    """``[(dataset, x positions, (marker, size)), ...]``: one entry, or one per follow direction.

    Up and down sweeps are drawn side by side, shifted by a fifth of the smallest spacing of
    the values to the left (up) and right (down), with up and down triangles.
    """
    import numpy as np

    if "direction" not in ds1.dims:
        return [(ds1, x, (".", 1.5))]
    step = float(np.min(np.diff(np.sort(x)))) if x.size > 1 else abs(float(x[0])) or 1.0
    if _is_log_spaced(x):
        shift = lambda s: x * np.exp(s * 0.2 * np.min(np.diff(np.log(x))))  # noqa: E731
    else:
        shift = lambda s: x + s * 0.2 * step  # noqa: E731
    runs = []
    for name in ds1["direction"].values:
        marker, size, side = _DIRECTION_STYLE[str(name)]
        runs.append((ds1.sel(direction=name), shift(side), (marker, size)))
    return runs


def bifurcation_figure(ds, key: str) -> Figure:
    """Bifurcation diagram of a sweep: Poincare samples of ``v`` and ``w`` against one key.

    Each kept once-per-revolution sample ``v(k 2 pi / Omega)`` (top) and ``w`` (bottom) at the
    contact station is a dot above the swept value, coloured by the point's regime (legend);
    a periodic orbit shows as ``k`` dots, a quasi-periodic or chaotic one as a vertical band.
    The clearance (when constant) is drawn as dashed lines at ``+-g``. A follow sweep
    (:func:`rubrotor.sweeps.follow.follow_sweep`, dimension ``direction``) is drawn with filled up
    triangles shifted left of each value for the up sweep and hollow down triangles shifted
    right for the down sweep, so the two branches and their jumps are told apart.

    Parameters
    ----------
    ds : xarray.Dataset
        A :func:`rubrotor.sweeps.sweep.sweep` result; other swept keys must have a single value.
    key : str
        The swept key on the horizontal axis.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import numpy as np
    from matplotlib.lines import Line2D

    from rubrotor.sweeps.sweep import regime_labels

    if key not in ds.dims:
        raise ValueError(f"{key!r} is not a swept key of this Dataset ({list(ds['done'].dims)})")
    others = [d for d in ds["done"].dims if d not in (key, "direction")]
    for d in others:
        if ds.sizes[d] != 1:
            raise ValueError(f"select one value of {d!r} first (ds.isel({d}=i))")
    ds1 = ds.isel({d: 0 for d in others})
    x = ds1[key].values
    runs = _direction_runs(ds1, x)
    labels_all = np.concatenate([regime_labels(d).ravel() for d, _, _ in runs])
    fig = Figure(figsize=(10, 7), layout="constrained")
    axes = fig.subplots(2, 1, sharex=True)
    clearance = ds.attrs.get("clearance_m")
    if any(d.startswith(("contact.clearance", "shaft.length")) for d in ds["done"].dims):
        clearance = None
    present = sorted(set(labels_all.tolist()), key=_label_order)
    nrev = ds1.sizes["revolution"]
    for ax, name, comp in ((axes[0], "poincare_v", "v"), (axes[1], "poincare_w", "w")):
        for dsd, xd, (marker, size) in runs:
            labels = regime_labels(dsd)
            y = dsd[name].values * 1e3  # mm
            for lab in present:
                sel = labels == lab
                xs = np.repeat(xd[sel], nrev)
                face = "none" if marker == "v" else _regime_color(lab)
                ax.plot(
                    xs, y[sel].ravel(), color=_regime_color(lab), marker=marker,
                    markersize=size, linestyle="none", alpha=0.8, markerfacecolor=face,
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
    if "direction" in ds1.dims:
        for (_, _, (marker, _)), name in zip(runs, ds1["direction"].values, strict=True):
            text = _DIRECTION_TEXT[str(name)]
            face = "none" if marker == "v" else "0.2"
            handles.append(
                Line2D(
                    [], [], color="0.2", marker=marker, markerfacecolor=face, linestyle="none",
                    label=text,
                )
            )  # fmt: skip
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
        A :func:`rubrotor.sweeps.sweep.sweep` result over (at least) ``key_x`` and ``key_y``; any other
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

    from rubrotor.sweeps.sweep import regime_labels

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


# ---- analysis and seed-reproduction figures ----------------------------------------------------
# Figures of `rubrotor analyze` and `rubrotor reproduce`. Natural frequencies are given as
# (label, frequency_hz, whirl) entries (see rubrotor.analysis.overview.mode_entries); a label
# containing "shear" marks the Timoshenko shear branch.
__all__ += [
    "scalogram_map_figure",
    "scalogram_curves_figure",
    "full_spectrum_figure",
    "analysis_figure",
    "response_figure",
    "theory_comparison_figure",
    "envelope_figure",
]

_MARK_COLOR = {"forward": "#2b9bff", "backward": "#ff3ea5"}
_MARK_COLOR_LIGHT = _MARK_COLOR
_HARMONIC_COLOR = "#2ca02c"


def _mark_style(label: str) -> str:
    return ":" if "shear" in label else "--"


def _harmonics(spin_hz, lo: float, hi: float, max_order: int = 40) -> list[tuple[int, float]]:
    if not spin_hz:
        return []
    return [(k, k * spin_hz) for k in range(1, max_order + 1) if lo <= k * spin_hz <= hi]


def _draw_scalogram_map(ax, binned, modes, spin_hz, unit, norm, cmap="magma"):
    """Draw one time-binned |W| map on ``ax``; returns the QuadMesh."""
    import numpy as np

    t_ms = binned.times * 1e3
    f = binned.frequencies
    mesh = ax.pcolormesh(
        t_ms,
        f,
        np.maximum(binned.values, norm.vmin),
        shading="nearest",
        cmap=cmap,
        norm=norm,
        rasterized=True,
    )
    ax.set_yscale("log")
    ax.set_ylim(f[0], f[-1])
    ax.set_xlabel("Time (ms)")
    ax.set_ylabel("Frequency (Hz)")
    for label, freq, whirl in modes:
        if f[0] <= freq <= f[-1]:
            ax.axhline(
                freq,
                color=_MARK_COLOR[whirl],
                linestyle=_mark_style(label),
                linewidth=1.5 if "shear" in label else 1.1,
            )
    harm = _harmonics(spin_hz, f[0], f[-1], max_order=3)
    for k, fk in harm:
        ax.axhline(fk, color=_HARMONIC_COLOR, linestyle="-", linewidth=0.9)
        ax.annotate(
            f"{k}X",
            (1.0, fk),
            xycoords=("axes fraction", "data"),
            xytext=(2, 0),
            textcoords="offset points",
            va="center",
            fontsize=7,
            color="0.2",
        )
    return mesh


def _mark_handles(modes, spin_hz, on_dark: bool) -> list:
    colors = _MARK_COLOR if on_dark else _MARK_COLOR_LIGHT
    handles = []
    seen = set()
    for label, _freq, whirl in modes:
        branch = "shear" if "shear" in label else "bending"
        key = (branch, whirl)
        if key in seen:
            continue
        seen.add(key)
        handles.append(
            Line2D(
                [],
                [],
                color=colors[whirl],
                linestyle=_mark_style(label),
                label=f"{whirl} whirl, {branch} branch",
            )
        )
    if spin_hz:
        handles.append(
            Line2D(
                [],
                [],
                color=_HARMONIC_COLOR,
                linestyle="-",
                linewidth=0.9,
                label=f"spin harmonics kX ({spin_hz:.0f} Hz)",
            )
        )
    return handles


def _log_norm(values_list, decades: float = 4.0):
    import numpy as np
    from matplotlib.colors import LogNorm

    vmax = max(float(np.max(v)) for v in values_list)
    vmax = vmax if vmax > 0 else 1.0
    return LogNorm(vmin=vmax * 10 ** (-decades), vmax=vmax)


def scalogram_map_figure(
    maps,
    *,
    modes=(),
    spin_hz: float | None = None,
    unit: str = "m/s^2",
    title: str | None = None,
    decades: float = 4.0,
    ncols: int = 2,
) -> Figure:
    """Time-frequency map of time-binned ``|W|`` (seed Fig. 7), one panel per signal.

    Parameters
    ----------
    maps : BinnedCWT or dict of str to BinnedCWT
        Maps from :func:`rubrotor.analysis.wavelet.cwt_binned`; a dict gives one titled panel
        per entry, all on one logarithmic colour scale.
    modes : sequence of (str, float, str), optional
        Natural frequencies ``(label, frequency_hz, whirl)`` drawn as horizontal lines (forward
        cyan, backward magenta; bending dashed, shear dotted).
    spin_hz : float, optional
        Spin frequency (Hz); 1X-3X are drawn as thin green lines and labelled on the right.
    unit : str
        Unit of ``|W|`` (that of the signal).
    title : str, optional
        Figure title.
    decades : float
        Colour range in decades below the largest value.
    ncols : int
        Panels per row.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not isinstance(maps, dict):
        maps = {"": maps}
    n = len(maps)
    ncols = min(ncols, n)
    nrows = -(-n // ncols)
    fig = Figure(figsize=(6.2 * ncols + 1.5, 3.9 * nrows + 1.0), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    norm = _log_norm([m.values for m in maps.values()], decades)
    mesh = None
    for ax, (name, b) in zip(axes.flat, maps.items(), strict=False):
        mesh = _draw_scalogram_map(ax, b, modes, spin_hz, unit, norm)
        if name:
            ax.set_title(name, fontsize=10)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.colorbar(mesh, ax=axes, label=f"max |W| per time bin ({unit})", shrink=0.9)
    handles = _mark_handles(modes, spin_hz, on_dark=False)
    if handles:
        fig.legend(
            handles=handles, loc="outside lower center", ncol=min(len(handles), 3), fontsize=8
        )
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


def _draw_scalogram_curves(ax_s, ax_i, frequencies, curves, modes, spin_hz):
    for name, (scal, inner) in curves.items():
        (line,) = ax_s.loglog(frequencies, scal, label=name, linewidth=1.3)
        ax_i.loglog(frequencies, inner, label=name, linewidth=1.3, color=line.get_color())
    for ax in (ax_s, ax_i):
        for label, freq, whirl in modes:
            if frequencies[0] <= freq <= frequencies[-1]:
                ax.axvline(
                    freq,
                    color=_MARK_COLOR_LIGHT[whirl],
                    linestyle=_mark_style(label),
                    linewidth=0.8,
                    alpha=0.7,
                )
        for _k, fk in _harmonics(spin_hz, frequencies[0], frequencies[-1], max_order=3):
            ax.axvline(fk, color=_HARMONIC_COLOR, linewidth=0.8, alpha=0.8)
        ax.set_xlim(frequencies[0], frequencies[-1])
        ax.grid(True, which="both", alpha=0.25)
        ax.set_xlabel("Frequency (Hz)")


def scalogram_curves_figure(
    frequencies,
    curves: dict,
    *,
    modes=(),
    spin_hz: float | None = None,
    unit: str = "m/s^2",
    title: str | None = None,
) -> Figure:
    """Scalogram (seed eq. 19) and inner scalogram (eq. 20) against frequency.

    Parameters
    ----------
    frequencies : array_like
        Scalogram frequencies (Hz).
    curves : dict of str to (array_like, array_like)
        ``{name: (scalogram, inner_scalogram)}``, one line per name in both panels
        (unit of the signal times s^0.5).
    modes : sequence of (str, float, str), optional
        Natural frequencies drawn as vertical lines (forward blue, backward red; bending dashed,
        shear dotted).
    spin_hz : float, optional
        Spin frequency (Hz); 1X-3X drawn as grey lines.
    unit : str
        Unit of the signal.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(11, 4.4), layout="constrained")
    ax_s, ax_i = fig.subplots(1, 2, sharey=True)
    _draw_scalogram_curves(ax_s, ax_i, frequencies, curves, modes, spin_hz)
    ax_s.set_ylabel(f"Scalogram ({unit} s$^{{1/2}}$)")
    ax_s.set_title("scalogram (whole record)", fontsize=10)
    ax_i.set_title("inner scalogram (outside the cone of influence)", fontsize=10)
    handles = [
        Line2D([], [], color=ln.get_color(), label=ln.get_label())
        for ln in ax_s.get_lines()
        if not ln.get_label().startswith("_")
    ]
    handles += _mark_handles(modes, spin_hz, on_dark=False)
    fig.legend(handles=handles, loc="outside right upper", fontsize=8)
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


def _draw_spectrum(ax, spectrum, two_channel, modes, spin_hz, unit):
    import numpy as np

    f = np.asarray(spectrum.frequencies)
    a = np.asarray(spectrum.amplitudes)
    if two_channel:
        fwd = f > 0
        bwd = f < 0
        ax.loglog(f[fwd], a[fwd], color="tab:blue", linewidth=0.9, label="forward (f > 0)")
        ax.loglog(
            -f[bwd], a[bwd], color="tab:red", linewidth=0.9, alpha=0.8, label="backward (f < 0)"
        )
        ax.set_xlabel("|Whirl frequency| (Hz)")
    else:
        pos = f > 0
        ax.loglog(f[pos], a[pos], color="0.2", linewidth=0.9, label="amplitude spectrum")
        ax.set_xlabel("Frequency (Hz)")
    pos = np.abs(f[f != 0])
    lo, hi = float(pos.min()), float(pos.max())
    for label, freq, whirl in modes:
        ax.axvline(
            freq,
            color=_MARK_COLOR_LIGHT[whirl],
            linestyle=_mark_style(label),
            linewidth=0.8,
            alpha=0.6,
        )
    for _k, fk in _harmonics(spin_hz, lo, hi, max_order=3):
        ax.axvline(fk, color=_HARMONIC_COLOR, linewidth=0.8, alpha=0.8)
    peak = float(a.max()) if a.size else 1.0
    ax.set_ylim(peak * 1e-6, peak * 3)
    ax.set_xlim(lo, hi)
    ax.set_ylabel(f"Amplitude ({unit})")
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8, loc="lower left")


def full_spectrum_figure(
    spectrum,
    *,
    two_channel: bool = True,
    modes=(),
    spin_hz: float | None = None,
    unit: str = "m/s^2",
    title: str | None = None,
) -> Figure:
    """Full spectrum of an orbit, forward and backward whirl against |frequency|.

    Parameters
    ----------
    spectrum : Spectrum
        From :func:`rubrotor.analysis.spectra.full_spectrum` (or
        :func:`~rubrotor.analysis.spectra.amplitude_spectrum` with ``two_channel=False``).
    two_channel : bool
        Whether ``spectrum`` is a full spectrum (negative frequencies = backward whirl).
    modes : sequence of (str, float, str), optional
        Natural frequencies drawn as vertical lines.
    spin_hz : float, optional
        Spin frequency (Hz); 1X-3X drawn as grey lines.
    unit : str
        Unit of the amplitudes.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(9, 4.2), layout="constrained")
    ax = fig.subplots()
    _draw_spectrum(ax, spectrum, two_channel, modes, spin_hz, unit)
    handles = _mark_handles(modes, spin_hz, on_dark=False)
    if handles:
        fig.legend(handles=handles, loc="outside right upper", fontsize=8)
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


def analysis_figure(analysis, *, title: str | None = None) -> Figure:
    """Combined analysis figure: scalogram map, scalogram curves and spectrum.

    Parameters
    ----------
    analysis : rubrotor.analysis.overview.SignalAnalysis
        From :func:`rubrotor.analysis.overview.analyze_signal`.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Top: time-binned ``|W|`` map (log colour, natural frequencies and spin harmonics marked);
        middle: scalogram and inner scalogram; bottom: full (or amplitude) spectrum.
    """
    a = analysis
    fig = Figure(figsize=(12, 12), layout="constrained")
    grid = fig.add_gridspec(3, 2, height_ratios=[1.3, 1, 1])
    ax_map = fig.add_subplot(grid[0, :])
    ax_s = fig.add_subplot(grid[1, 0])
    ax_i = fig.add_subplot(grid[1, 1], sharey=ax_s)
    ax_f = fig.add_subplot(grid[2, :])
    norm = _log_norm([a.binned.values])
    mesh = _draw_scalogram_map(ax_map, a.binned, a.modes, a.spin_hz, a.unit, norm)
    fig.colorbar(mesh, ax=ax_map, label=f"max |W| per bin ({a.unit})")
    ax_map.set_title("CWT map (analytic Morlet, omega0 = 6)", fontsize=10)
    _draw_scalogram_curves(
        ax_s, ax_i, a.frequencies, {"signal": (a.scalogram, a.inner)}, a.modes, a.spin_hz
    )
    ax_s.set_ylabel(f"Scalogram ({a.unit} s$^{{1/2}}$)")
    ax_s.set_title("scalogram", fontsize=10)
    ax_i.set_title("inner scalogram", fontsize=10)
    _draw_spectrum(ax_f, a.spectrum, a.two_channel, a.modes, a.spin_hz, a.unit)
    ax_f.set_title(
        "full spectrum (orbit v + i w)" if a.two_channel else "amplitude spectrum", fontsize=10
    )
    handles = _mark_handles(a.modes, a.spin_hz, on_dark=False)
    if handles:
        fig.legend(
            handles=handles, loc="outside lower center", ncol=min(len(handles), 5), fontsize=8
        )
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


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

    import numpy as np

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
    import numpy as np

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


def _with_corners(branch, x, r, st):
    """Branch points (key values, radii um, stability) with the bifurcations inserted.

    Contact onset (the corner at a grazing value, radius the clearance) goes where the radius
    crosses it; a bifurcation whose value lies between two points of different stability goes
    between them. Each corner takes the stability of the point it leads into, so the line
    changes style at the bifurcation, not at the next computed point.
    """
    used = set()
    for b in branch.bifurcations:
        rc = b.max_radius_m * 1e6
        if b.type == "contact-onset":
            i = next((j for j in range(x.size - 1) if (r[j] > rc) != (r[j + 1] > rc)), None)
        else:
            i = next((j for j in range(x.size - 1) if st[j] != st[j + 1]
                      and min(x[j], x[j + 1]) <= b.value <= max(x[j], x[j + 1])), None)  # fmt: skip
        if i is None or (i, b.value) in used or not np.isfinite(rc):
            continue
        used.add((i, b.value))
        x, r, st = (np.insert(a, i + 1, v) for a, v in ((x, b.value), (r, rc), (st, st[i + 1])))
    return x, r, st


def _draw_branch(ax, branch, color, handles, suffix: bool) -> None:
    """One branch: runs of equal stability, solid (stable) or dashed (unstable)."""
    x = np.array([p.value for p in branch.points])
    r = np.array([p.max_radius_m for p in branch.points]) * 1e6
    st = np.array([p.stable for p in branch.points])
    x, r, st = _with_corners(branch, x, r, st)
    edges = [0, *(np.flatnonzero(st[1:] != st[:-1]) + 1), x.size]
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        stop = min(b + 1, x.size)
        ax.plot(x[a:stop], r[a:stop], "-" if st[a] else "--", color=color, lw=1.6)
    name = f"continuation, period-{branch.k}" if suffix else "continuation"
    handles += [
        Line2D([], [], color=color, ls="-", label=f"{name}, stable"),
        Line2D([], [], color=color, ls="--", label=f"{name}, unstable"),
    ]


def _draw_follow(ax, sweep, key, handles) -> None:
    """Up (triangles) and down (circles) sweep points; chaotic ones filled."""
    from rubrotor.sweeps.regimes import CHAOTIC

    for d, marker, color in (("up", "^", "C2"), ("down", "o", "C3")):
        if d not in list(sweep["direction"].values):
            continue
        y = sweep["max_displacement"].sel(direction=d).values * 1e6
        chaos = sweep["regime"].sel(direction=d).values == CHAOTIC
        x = sweep[key].values
        ax.plot(x[~chaos], y[~chaos], marker, color=color, mfc="none", ms=7)
        ax.plot(x[chaos], y[chaos], marker, color=color, ms=7)
        handles.append(Line2D([], [], ls="", marker=marker, color=color, mfc="none",
                              label=f"follow sweep {d}"))  # fmt: skip
        if chaos.any():
            handles.append(Line2D([], [], ls="", marker=marker, color=color,
                                  label=f"follow sweep {d}, chaotic"))  # fmt: skip


def contact_geometry(scenario) -> dict | None:
    """The first contact's clearance and stator offset (m) and what moves the orbit's centre.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A scenario with a contact (seed ``[contact]`` or general ``[[contact]]``).

    Returns
    -------
    dict or None
        ``{"clearance", "offset"}`` (m) and ``"why"``: the reasons the radius about the
        bearing axis differs from the radius about the stator centre (offset stator, gravity
        sag, side load, flexible stator); None without a contact.
    """
    from rubrotor.modelling import model_of

    spec = scenario.engine
    if model_of(scenario).contact_stations:
        st = spec.stations[0]
        g, off, flexible = st.contact.clearance, math.hypot(st.offset_y, st.offset_z), st.stator
        why = [f"stator centre offset {off * 1e6:.3g} um"] if off > 0 else []
        why += ["gravity sag"] if any(spec.gravity) else []
        why += ["side load"] if spec.loads else []
        why += ["flexible stator"] if flexible is not None else []
        return {"clearance": g, "offset": off, "why": why}
    if scenario.contact is None:
        return None
    why = ["side load"] if scenario.load is not None else []
    return {"clearance": scenario.contact.clearance, "offset": 0.0, "why": why}


def _draw_clearance(ax, geometry: dict, handles) -> None:
    """The clearance line and, for an offset stator, the band ``g -+ |offset|`` of radii about
    the bearing axis at which the orbit can first touch."""
    g, off = geometry["clearance"] * 1e6, geometry["offset"] * 1e6
    ax.axhline(g, color="k", lw=0.9, ls=":")
    handles.append(Line2D([], [], color="k", lw=0.9, ls=":", label=f"clearance {g:.3g} um"))
    if off > 0:
        ax.axhspan(g - off, g + off, color="0.85", zorder=0)
        handles.append(Patch(color="0.85", label="first touch possible (clearance ± offset)"))
    if geometry["why"]:
        ax.set_title("radius about the bearing axis; the stator centre differs by: "
                     + ", ".join(geometry["why"]), fontsize=8, loc="left", color="0.3")  # fmt: skip


def branch_figure(branch, sweep=None, others=(), geometry: dict | None = None) -> Figure:
    """A continued branch (stable solid, unstable dashed, bifurcations marked) over a sweep.

    Parameters
    ----------
    branch : rubrotor.orbits.continuation.Branch
        The branch; largest orbit radius (m) against the continued key.
    sweep : xarray.Dataset, optional
        A state-carrying sweep (:func:`rubrotor.sweeps.follow.follow_sweep`) of the same key: its
        ``max_displacement`` (m) per direction, up as triangles, down as circles; points
        labelled chaotic (by a positive largest Lyapunov exponent when the sweep computed it)
        are filled.
    others : sequence of rubrotor.orbits.continuation.Branch
        More branches of the same key (e.g. from
        :func:`rubrotor.orbits.continuation.switch_period_doubling`), one colour each, labelled by
        their period in revolutions.
    geometry : dict, optional
        :func:`rubrotor.plotting.figures.contact_geometry` of the scenario: draws the clearance (and, for an offset
        stator, the band of radii where the orbit can first touch) and says why the radius
        about the bearing axis differs from the one about the stator centre.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(7.5, 4.8))
    ax = fig.add_subplot()
    handles = []
    for i, br in enumerate((branch, *others)):
        _draw_branch(ax, br, f"C{[0, 1, 4, 5, 6][i % 5]}", handles, suffix=bool(others))
    if sweep is not None:
        _draw_follow(ax, sweep, branch.key, handles)
    if geometry is not None:
        _draw_clearance(ax, geometry, handles)
    marks = {"fold": "s", "period-doubling": "D", "neimark-sacker": "*", "branch-point": "X",
             "contact-onset": "v"}  # fmt: skip
    bifs = [b for br in (branch, *others) for b in br.bifurcations]
    for b in bifs:
        ax.plot(b.value, b.max_radius_m * 1e6, marks[b.type], color="k", ms=8)
    for t in sorted({b.type for b in bifs}):
        handles.append(Line2D([], [], ls="", marker=marks[t], color="k", label=t))
    ax.set_xlabel(_key_label(branch.key) if sweep is None else _axis_label(sweep, branch.key))
    ax.set_ylabel("largest orbit radius at contact station (um)")
    ax.grid(alpha=0.3)
    ax.legend(handles=handles, fontsize=8)
    fig.tight_layout()
    return fig
