r"""Rub indicators computed from a response given as plain arrays.

Band energies are mean-square contents (unit**2) read from a Hann-windowed periodogram
normalized by the window energy, ``P_k = |X_k|**2 / (N * sum(w**2))``: summed over all lines it
is the mean square of the record, and a tone of amplitude ``A`` well inside a band contributes
``A**2/2`` (real signal, one-sided) or ``R**2`` (circular orbit of radius R, full spectrum).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft
from scipy.signal import find_peaks, get_window

from rubrotor.analysis.spectra import order_spectrum
from rubrotor.analysis.wavelet import _check_fs, _check_signal, inner_scalogram, log_frequencies
from rubrotor.errors import InputError

__all__ = [
    "RubIndicators",
    "rub_indicators",
    "band_energies",
    "backward_whirl_share",
    "scalogram_peaks",
]

SUB_ORDERS = (1 / 3, 1 / 2, 2 / 3)
SUPER_ORDERS = (2.0, 3.0)


@dataclass(frozen=True)
class RubIndicators:
    """Rub indicators of one response.

    Attributes
    ----------
    band_energy : dict[str, float]
        Mean-square content (unit**2) in ``f +- band_halfwidth_hz`` around each given natural
        frequency, keyed by its label; forward entries read positive frequencies of the full
        spectrum, backward entries negative ones (one-sided spectrum of v when w is absent).
    band_ratio : dict[str, float] or None
        ``band_energy / baseline band energy`` per label (inf when the baseline band is empty);
        None without a baseline.
    harmonic_ratio : dict[float, float]
        Amplitude at each sub- (1/3, 1/2, 2/3) and super-harmonic (2, 3) order divided by the
        1X amplitude (dimensionless), from the order spectrum of v.
    backward_share : float or None
        Fraction of the orbit's full-spectrum energy at negative frequencies (DC excluded);
        None without w.
    scalogram_peaks_hz : numpy.ndarray
        Frequencies (Hz) of the interior local maxima of the inner scalogram of v, strongest
        first (the grid's edges are never reported, see ``scalogram_peaks``).
    details : dict
        Parameters used (band_halfwidth_hz, window, scalogram frequency range).
    """

    band_energy: dict
    band_ratio: dict | None
    harmonic_ratio: dict
    backward_share: float | None
    scalogram_peaks_hz: np.ndarray
    details: dict = field(default_factory=dict)


def _periodogram_full(z: np.ndarray, fs: float):
    n = z.size
    w = get_window("hann", n, fftbins=True)
    p = np.abs(sfft.fft(z * w)) ** 2 / (n * np.sum(w**2))
    return sfft.fftfreq(n, 1.0 / fs), p


def _periodogram_onesided(x: np.ndarray, fs: float):
    f, p = _periodogram_full(x.astype(np.complex128), fs)
    keep = f >= 0
    pos = p[keep].copy()
    pos[f[keep] > 0] *= 2.0  # fold the negative half onto the positive one
    if x.size % 2 == 0:  # Nyquist line sits at -fs/2 in fftfreq: add it once
        pos = np.append(pos, p[x.size // 2])
        fpos = np.append(f[keep], fs / 2)
    else:
        fpos = f[keep]
    return fpos, pos


def _check_modes(modes) -> list[tuple[str, float, str]]:
    out = []
    try:
        items = list(modes)
    except TypeError:
        raise InputError("modes", modes, "a list of (label, frequency_hz, whirl) entries") from None
    for entry in items:
        try:
            label, freq, whirl = entry
            freq = float(freq)
        except (TypeError, ValueError):
            raise InputError(
                "modes", entry, "(label, frequency_hz, whirl) with whirl 'forward' or 'backward'"
            ) from None
        if whirl not in ("forward", "backward") or not np.isfinite(freq) or freq <= 0:
            raise InputError(
                "modes", entry, "(label, frequency_hz > 0, whirl in {'forward', 'backward'})"
            )
        out.append((str(label), freq, whirl))
    return out


def band_energies(
    v, fs: float, modes: Sequence, *, w=None, band_halfwidth_hz: float | None = None
) -> dict:
    """Mean-square content around each natural frequency.

    Parameters
    ----------
    v : array_like, shape (n_samples,)
        Displacement along the first axis (any unit).
    fs : float
        Sampling frequency (Hz).
    modes : sequence of (str, float, str)
        ``(label, frequency_hz, whirl)`` with whirl ``"forward"`` or ``"backward"``, e.g. both
        branches of each mode from the modal analysis.
    w : array_like, optional
        Displacement along the second axis; with it the bands are read in the full spectrum of
        ``v + i w`` on the side of each entry's whirl, without it in the one-sided spectrum of v.
    band_halfwidth_hz : float, optional
        Half width of each band (Hz); default 4 frequency lines (4 fs / N), which holds a Hann
        main lobe.

    Returns
    -------
    dict[str, float]
        Mean-square content (unit**2) per label.
    """
    fs = _check_fs(fs)
    v = _check_signal(v, "v")
    entries = _check_modes(modes)
    hw = _halfwidth(band_halfwidth_hz, fs, v.size)
    if w is None:
        f, p = _periodogram_onesided(v, fs)
    else:
        w = _check_signal(w, "w")
        if w.size != v.size:
            raise InputError("w", f"array of length {w.size}", f"the length of v ({v.size})")
        f, p = _periodogram_full(v + 1j * w, fs)
    out = {}
    for label, freq, whirl in entries:
        if freq >= fs / 2:
            raise InputError("modes", (label, freq, whirl), f"frequency below fs/2 = {fs / 2:g}")
        centre = -freq if (w is not None and whirl == "backward") else freq
        out[label] = float(np.sum(p[np.abs(f - centre) <= hw]))
    return out


def _halfwidth(band_halfwidth_hz, fs, n) -> float:
    if band_halfwidth_hz is None:
        return 4.0 * fs / n
    hw = float(band_halfwidth_hz)
    if not np.isfinite(hw) or hw <= 0:
        raise InputError("band_halfwidth_hz", band_halfwidth_hz, "a finite width > 0 (Hz)")
    return hw


def backward_whirl_share(v, w, fs: float) -> float:
    """Fraction of the orbit's full-spectrum energy at negative (backward) frequencies.

    Parameters
    ----------
    v, w : array_like, shape (n_samples,)
        Displacements along two orthogonal axes (same unit).
    fs : float
        Sampling frequency (Hz).

    Returns
    -------
    float
        ``sum_{f<0} P / sum_{f!=0} P`` (dimensionless, 0 = pure forward whirl, 1 = pure
        backward); the DC line belongs to neither and is excluded, 0 for an orbit with no
        non-DC content.  The Nyquist line (even N) counts as backward.
    """
    fs = _check_fs(fs)
    v = _check_signal(v, "v")
    w = _check_signal(w, "w")
    if w.size != v.size:
        raise InputError("w", f"array of length {w.size}", f"the length of v ({v.size})")
    f, p = _periodogram_full(v + 1j * w, fs)
    back = float(np.sum(p[f < 0]))
    total = back + float(np.sum(p[f > 0]))
    return back / total if total > 0 else 0.0


def scalogram_peaks(frequencies, inner, n_peaks: int = 5) -> np.ndarray:
    """Frequencies of the interior local maxima of a scalogram, strongest first.

    The first and last frequencies of the grid are never peaks: a scalogram still rising at an
    edge of its range has its maximum outside it, not there.

    Parameters
    ----------
    frequencies : array_like
        Scalogram frequencies (Hz), ascending.
    inner : array_like
        Scalogram values at them (any unit).
    n_peaks : int
        Largest number of peaks returned.

    Returns
    -------
    numpy.ndarray
        Peak frequencies (Hz), at most ``n_peaks``.
    """
    inner = np.asarray(inner, dtype=np.float64)
    idx, _ = find_peaks(inner)  # interior samples higher than both neighbours
    idx = idx[np.argsort(inner[idx])[::-1]][:n_peaks]
    return np.asarray(frequencies, dtype=np.float64)[idx]


def rub_indicators(
    v,
    fs: float,
    spin_hz: float,
    modes: Sequence = (),
    *,
    w=None,
    baseline=None,
    band_halfwidth_hz: float | None = None,
    scalogram_range_hz: tuple[float, float] | None = None,
    n_frequencies: int = 96,
    n_peaks: int = 5,
) -> RubIndicators:
    """Rub indicators of a response.

    Parameters
    ----------
    v : array_like, shape (n_samples,)
        Displacement along the first axis (any unit).
    fs : float
        Sampling frequency (Hz).
    spin_hz : float
        Spin frequency (Hz), > 0; 1X for the harmonic ratios.
    modes : sequence of (str, float, str), optional
        ``(label, frequency_hz, whirl)`` entries (both whirl directions, both branches) whose
        band energies are wanted.
    w : array_like, optional
        Displacement along the second axis (same length as v); needed for whirl-resolved bands
        and the backward share.
    baseline : array_like or tuple of two array_like, optional
        A reference response (no contact, or any user signal): ``v_ref`` or ``(v_ref, w_ref)``,
        analysed the same way; gives ``band_ratio``.
    band_halfwidth_hz : float, optional
        Half width of the bands (Hz); default 4 fs / N.
    scalogram_range_hz : (float, float), optional
        Frequency range of the inner scalogram (Hz); default (spin/4, 0.45 fs).
    n_frequencies : int, optional
        Number of log-spaced scalogram frequencies (default 96).
    n_peaks : int, optional
        Number of inner-scalogram peaks to report (default 5).

    Returns
    -------
    RubIndicators

    Examples
    --------
    >>> import numpy as np
    >>> fs, spin = 1000.0, 20.0
    >>> t = np.arange(10000) / fs
    >>> v = np.cos(2 * np.pi * spin * t) + 0.25 * np.cos(np.pi * spin * t)
    >>> ind = rub_indicators(v, fs, spin, w=np.sin(2 * np.pi * spin * t))
    >>> round(ind.harmonic_ratio[0.5], 6)
    0.25
    """
    fs = _check_fs(fs)
    v = _check_signal(v, "v")
    try:
        spin = float(spin_hz)
    except (TypeError, ValueError):
        raise InputError("spin_hz", spin_hz, "a finite spin frequency > 0 (Hz)") from None
    if not np.isfinite(spin) or spin <= 0 or 3 * spin >= fs / 2:
        raise InputError("spin_hz", spin_hz, f"a spin frequency > 0 with 3X < fs/2 = {fs / 2:g}")
    if w is not None:
        w = _check_signal(w, "w")
        if w.size != v.size:
            raise InputError("w", f"array of length {w.size}", f"the length of v ({v.size})")
    bands = band_energies(v, fs, modes, w=w, band_halfwidth_hz=band_halfwidth_hz)
    ratio = None
    if baseline is not None:
        if isinstance(baseline, tuple):
            if len(baseline) != 2:
                raise InputError("baseline", baseline, "v_ref or a tuple (v_ref, w_ref)")
            v_ref, w_ref = baseline
        else:
            v_ref, w_ref = baseline, None
        if (w is None) != (w_ref is None):
            raise InputError(
                "baseline",
                "signal of another kind",
                "(v_ref, w_ref) when w is given, v_ref alone otherwise",
            )
        ref = band_energies(v_ref, fs, modes, w=w_ref, band_halfwidth_hz=band_halfwidth_hz)
        ratio = {k: (bands[k] / ref[k] if ref[k] > 0 else np.inf) for k in bands}
    ords = SUB_ORDERS + (1.0,) + SUPER_ORDERS
    spec = order_spectrum(v, fs, spin, orders=ords)
    one_x = spec.amplitudes[ords.index(1.0)]
    harm = {
        o: (float(a / one_x) if one_x > 0 else np.inf)
        for o, a in zip(ords, spec.amplitudes, strict=True)
        if o != 1.0
    }
    share = backward_whirl_share(v, w, fs) if w is not None else None
    lo, hi = scalogram_range_hz if scalogram_range_hz is not None else (spin / 4, 0.45 * fs)
    freqs = log_frequencies(lo, hi, n_frequencies)
    inner = inner_scalogram(v, fs, freqs)
    peaks = scalogram_peaks(freqs, inner, n_peaks)
    details = {
        "band_halfwidth_hz": _halfwidth(band_halfwidth_hz, fs, v.size),
        "window": "hann",
        "scalogram_range_hz": (lo, hi),
        "energy_unit": "unit**2 (mean square)",
    }
    return RubIndicators(bands, ratio, harm, share, peaks, details)
