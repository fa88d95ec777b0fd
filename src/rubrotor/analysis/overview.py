r"""One-call analysis of a response: scalogram map, scalogram curves, spectra and rub indicators.

Used by ``rubrotor analyze`` and ``rubrotor reproduce``: it bundles the calls to
:mod:`rubrotor.analysis.wavelet`, :mod:`rubrotor.analysis.spectra` and
:func:`rubrotor.analysis.indicators.rub_indicators` that a figure and an indicator table need,
and turns the results into JSON-able numbers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from rubrotor.analysis.indicators import RubIndicators, rub_indicators
from rubrotor.analysis.spectra import Spectrum, amplitude_spectrum, full_spectrum
from rubrotor.analysis.wavelet import BinnedCWT, cwt_binned, inner_scalogram, log_frequencies
from rubrotor.analysis.wavelet import scalogram as _scalogram
from rubrotor.errors import InputError

__all__ = ["SignalAnalysis", "analyze_signal", "mode_entries", "band_energy", "indicators_dict"]


@dataclass(frozen=True)
class SignalAnalysis:
    """Everything a response analysis figure and table show.

    Attributes
    ----------
    fs : float
        Sampling frequency (Hz).
    unit : str
        Unit of the analysed signal (e.g. ``"m/s^2"``).
    spin_hz : float or None
        Spin frequency (Hz).
    modes : list of (str, float, str)
        ``(label, frequency_hz, whirl)`` natural frequencies marked and used for band energies.
    binned : BinnedCWT
        Time-binned max ``|W|`` map of the first channel (unit of the signal).
    frequencies : numpy.ndarray
        Scalogram frequencies (Hz).
    scalogram : numpy.ndarray
        Scalogram of the first channel (unit * s**0.5), seed eq. 19.
    inner : numpy.ndarray
        Inner scalogram of the first channel (unit * s**0.5), seed eq. 20.
    spectrum : Spectrum
        Full spectrum of ``v + i w`` (two channels, negative frequencies = backward whirl) or the
        one-sided amplitude spectrum of the single channel (unit of the signal).
    two_channel : bool
        Whether ``spectrum`` is a full spectrum.
    indicators : RubIndicators or None
        Rub indicators of the signal (None without a spin frequency).
    details : dict
        Extra numbers (signal RMS, duration).
    """

    fs: float
    unit: str
    spin_hz: float | None
    modes: list
    binned: BinnedCWT
    frequencies: np.ndarray
    scalogram: np.ndarray
    inner: np.ndarray
    spectrum: Spectrum
    two_channel: bool
    indicators: RubIndicators | None
    details: dict = field(default_factory=dict)


def mode_entries(modes) -> list[tuple[str, float, str]]:
    """``(label, frequency_hz, whirl)`` entries from :class:`rubrotor.linear.shaft.Mode` objects.

    Parameters
    ----------
    modes : iterable of Mode
        From :func:`rubrotor.modes`.

    Returns
    -------
    list of (str, float, str)
        Labels like ``"1F bending"`` or ``"1B shear"``; frequency (Hz); whirl.
    """
    return [
        (f"{m.n}{'F' if m.whirl == 'forward' else 'B'} {m.branch}", float(m.frequency_hz), m.whirl)
        for m in modes
    ]


def band_energy(v, fs: float, lo_hz: float, hi_hz: float, w=None) -> float:
    """Mean-square content of a signal between two frequencies, both whirl directions.

    Hann-windowed periodogram normalized so that the sum over all lines is the mean square
    (as in :mod:`rubrotor.analysis.indicators`); with ``w`` the orbit ``v + i w`` is used and
    both ``lo <= |f| <= hi`` sides are summed.

    Parameters
    ----------
    v : array_like
        Signal (any unit).
    fs : float
        Sampling frequency (Hz).
    lo_hz, hi_hz : float
        Band limits (Hz), ``0 <= lo < hi <= fs/2``.
    w : array_like, optional
        Second channel (same unit and length).

    Returns
    -------
    float
        Mean-square content in the band (unit**2).
    """
    from rubrotor.analysis.indicators import _periodogram_full

    if not 0 <= lo_hz < hi_hz <= fs / 2:
        raise InputError("band", (lo_hz, hi_hz), f"0 <= lo < hi <= fs/2 = {fs / 2:g} Hz")
    z = np.asarray(v, dtype=np.float64) + (0j if w is None else 1j * np.asarray(w, float))
    f, p = _periodogram_full(z, fs)
    sel = (np.abs(f) >= lo_hz) & (np.abs(f) <= hi_hz)
    return float(np.sum(p[sel]))


def analyze_signal(
    v,
    fs: float,
    *,
    w=None,
    spin_hz: float | None = None,
    modes: Sequence = (),
    unit: str = "",
    frequency_range: tuple[float, float] | None = None,
    n_frequencies: int = 96,
    n_bins: int = 400,
    baseline=None,
) -> SignalAnalysis:
    """Analyse one response (one or two channels).

    Parameters
    ----------
    v : array_like, shape (n_samples,)
        First channel (any unit).
    fs : float
        Sampling frequency (Hz), > 0.
    w : array_like, optional
        Second channel; with it the spectrum is the full (whirl-resolved) spectrum.
    spin_hz : float, optional
        Spin frequency (Hz); needed for the rub indicators and spin harmonics.
    modes : sequence of (str, float, str), optional
        Natural frequencies ``(label, frequency_hz, whirl)``; those at or above ``0.45 fs`` are
        dropped (they cannot be resolved).
    unit : str
        Unit of the signal, for labels.
    frequency_range : (float, float), optional
        Scalogram range (Hz); default from ``min(spin/4, 20 fs/N)`` (at least ``4 fs/N``) to
        ``0.4 fs``, or to twice the highest natural frequency when that is lower.
    n_frequencies : int
        Number of log-spaced scalogram frequencies.
    n_bins : int
        Time bins of the map (fewer if the record is shorter).
    baseline : array_like or tuple, optional
        Reference response passed to :func:`rub_indicators` (band ratios).

    Returns
    -------
    SignalAnalysis
    """
    from rubrotor.analysis.spectra import _check_fs, _check_signal

    fs = _check_fs(fs)
    v = _check_signal(v, "v")
    if w is not None:
        w = _check_signal(w, "w")
        if w.size != v.size:
            raise InputError("w", f"array of length {w.size}", f"the length of v ({v.size})")
    n = v.size
    if n < 64:
        raise InputError("signal", f"{n} samples", "at least 64 samples")
    if frequency_range is None:
        lo = 20.0 * fs / n
        if spin_hz:
            lo = min(lo, spin_hz / 4)
        lo = max(lo, 4.0 * fs / n)
        hi = 0.4 * fs
        if modes:
            hi = min(hi, 2.0 * max(m[1] for m in modes))
        frequency_range = (lo, hi)
    freqs = log_frequencies(frequency_range[0], frequency_range[1], n_frequencies)
    kept = [m for m in modes if m[1] < 0.45 * fs]
    binned = cwt_binned(v, fs, freqs, int(min(n_bins, n)))
    scal = _scalogram(v, fs, freqs)
    inner = inner_scalogram(v, fs, freqs)
    spectrum = full_spectrum(v, w, fs) if w is not None else amplitude_spectrum(v, fs)
    ind = None
    if spin_hz is not None:
        ind = rub_indicators(
            v,
            fs,
            spin_hz,
            kept,
            w=w,
            baseline=baseline,
            scalogram_range_hz=frequency_range,
            n_frequencies=n_frequencies,
        )
    details = {
        "samples": int(n),
        "duration_s": n / fs,
        "rms": float(np.sqrt(np.mean(v**2))) if w is None else float(np.sqrt(np.mean(v**2 + w**2))),
        "frequency_range_hz": [float(frequency_range[0]), float(frequency_range[1])],
    }
    return SignalAnalysis(
        fs,
        unit,
        spin_hz,
        list(kept),
        binned,
        freqs,
        scal,
        inner,
        spectrum,
        w is not None,
        ind,
        details,
    )


def _num(x):
    x = float(x)
    return x if math.isfinite(x) else None


def indicators_dict(a: SignalAnalysis) -> dict:
    """JSON-able numbers of an analysis (indicators, scalogram peaks, parameters).

    Parameters
    ----------
    a : SignalAnalysis
        The analysis.

    Returns
    -------
    dict
        ``fs_hz``, ``unit``, ``spin_hz``, ``band_energy`` ({label: unit**2}),
        ``band_ratio``, ``harmonic_ratio`` ({order: ratio to 1X}), ``backward_share``,
        ``inner_scalogram_peaks_hz``, ``details``. Infinite ratios are written as null.
    """
    out = {
        "fs_hz": a.fs,
        "unit": a.unit,
        "spin_hz": a.spin_hz,
        **a.details,
        "modes": [{"label": m[0], "frequency_hz": m[1], "whirl": m[2]} for m in a.modes],
    }
    ind = a.indicators
    if ind is None:
        from rubrotor.analysis.indicators import scalogram_peaks

        out["inner_scalogram_peaks_hz"] = scalogram_peaks(a.frequencies, a.inner, 5).tolist()
        return out
    out["band_energy"] = {k: _num(v) for k, v in ind.band_energy.items()}
    out["band_ratio"] = (
        None if ind.band_ratio is None else {k: _num(v) for k, v in ind.band_ratio.items()}
    )
    out["harmonic_ratio"] = {f"{k:.4g}": _num(v) for k, v in ind.harmonic_ratio.items()}
    out["backward_share"] = None if ind.backward_share is None else float(ind.backward_share)
    out["inner_scalogram_peaks_hz"] = [float(f) for f in ind.scalogram_peaks_hz]
    out["band_halfwidth_hz"] = float(ind.details["band_halfwidth_hz"])
    return out


def decimate_to(signals, fs: float, max_rate: float):
    """Low-pass and decimate signals by one integer factor so the rate is at most ``max_rate``.

    Parameters
    ----------
    signals : sequence of array_like
        Channels of equal length.
    fs : float
        Sampling frequency (Hz).
    max_rate : float
        Largest wanted sampling frequency (Hz).

    Returns
    -------
    (list of numpy.ndarray, float)
        The channels (unchanged when ``fs <= max_rate``) and their sampling frequency (Hz).
        The anti-alias filter is an order-8 Chebyshev type I applied forward and backward
        (zero phase), cut at 0.8 of the new Nyquist frequency, applied in stages of at most 10
        (:func:`scipy.signal.decimate`).
    """
    from scipy.signal import decimate

    factor = int(math.ceil(fs / max_rate))
    out = [np.asarray(s, dtype=np.float64) for s in signals]
    if factor <= 1:
        return out, fs
    remaining = factor
    stages = []
    while remaining > 1:
        q = min(10, remaining)
        while remaining % q:
            q -= 1
        if q == 1:  # prime > 10: take it in one stage
            q = remaining
        stages.append(q)
        remaining //= q
    for q in stages:
        out = [decimate(s, q, ftype="iir", zero_phase=True) for s in out]
    return out, fs / factor
