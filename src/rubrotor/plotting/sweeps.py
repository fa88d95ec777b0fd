"""Figures of parameter sweeps: the bifurcation diagram against one key and the regime map over
two, each returning a :class:`matplotlib.figure.Figure` not registered with pyplot.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

__all__ = ["bifurcation_figure", "regime_map_figure"]

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
    from matplotlib.colors import ListedColormap

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
