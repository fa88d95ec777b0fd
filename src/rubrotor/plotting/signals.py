"""Figures of signals: wavelet scalogram maps and ridge curves, full spectra, and the analysis
figure of ``rubrotor analyze``, each returning a :class:`matplotlib.figure.Figure` not registered
with pyplot.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

__all__ = [
    "scalogram_map_figure",
    "scalogram_curves_figure",
    "full_spectrum_figure",
    "analysis_figure",
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

    f = np.asarray(spectrum.frequencies)
    a = np.asarray(spectrum.amplitudes)
    if two_channel:
        fwd = f > 0
        bwd = f < 0
        # forward over backward: the forward whirl (1X, rub's harmonics) is what is read first
        ax.loglog(
            f[fwd], a[fwd], color="tab:blue", linewidth=0.9, label="forward (f > 0)", zorder=3
        )
        ax.loglog(-f[bwd], a[bwd], color="tab:red", linewidth=0.8, alpha=0.7,
                  label="backward (f < 0)", zorder=2)  # fmt: skip
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
