r"""Amplitude, full (orbit) and order spectra.

All spectra are amplitude-corrected for their window: a tone of amplitude ``A`` exactly on a
frequency bin reads ``A`` (a tone between bins reads less, by the window's scalloping loss:
at most 15 % for Hann, 0.01 % for "flattop").  Windows are the periodic ("DFT-even") forms of
:func:`scipy.signal.get_window`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.fft as sfft
from scipy.signal import get_window

from rubrotor.analysis.wavelet import _check_fs, _check_signal
from rubrotor.errors import InputError

__all__ = [
    "Spectrum",
    "amplitude_spectrum",
    "full_spectrum",
    "order_spectrum",
    "DEFAULT_ORDERS",
]

DEFAULT_ORDERS = (1 / 3, 1 / 2, 2 / 3, 1.0, 2.0, 3.0)


class Spectrum(NamedTuple):
    """A spectrum.

    Attributes
    ----------
    frequencies : numpy.ndarray, float64
        Frequency of each line (Hz), or order (multiples of the spin frequency) for
        :func:`order_spectrum`.
    amplitudes : numpy.ndarray, float64
        Amplitude of each line (unit of the signal).
    """

    frequencies: np.ndarray
    amplitudes: np.ndarray


def _window(window, n: int) -> np.ndarray:
    try:
        return np.asarray(get_window(window, n, fftbins=True), dtype=np.float64)
    except (ValueError, TypeError):
        raise InputError(
            "window",
            window,
            "a window name known to scipy.signal.get_window, e.g. 'hann', 'boxcar', 'flattop'",
        ) from None


def amplitude_spectrum(signal, fs: float, *, window="hann") -> Spectrum:
    """One-sided amplitude spectrum of a real signal.

    Parameters
    ----------
    signal : array_like, shape (n_samples,)
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    window : str or tuple, optional
        Window for :func:`scipy.signal.get_window` (default ``"hann"``).

    Returns
    -------
    Spectrum
        ``frequencies`` 0 .. fs/2 (Hz, n_samples//2 + 1 lines) and ``amplitudes``
        ``2 |X_k| / sum(w)`` (``|X_k| / sum(w)`` at DC and Nyquist) in the signal's unit.

    Examples
    --------
    >>> import numpy as np
    >>> fs = 100.0
    >>> x = 3.0 * np.cos(2 * np.pi * 10.0 * np.arange(200) / fs)
    >>> spec = amplitude_spectrum(x, fs)
    >>> float(spec.frequencies[np.argmax(spec.amplitudes)]), round(float(spec.amplitudes.max()), 9)
    (10.0, 3.0)
    """
    fs = _check_fs(fs)
    x = _check_signal(signal, "signal")
    n = x.size
    w = _window(window, n)
    amp = np.abs(sfft.rfft(x * w)) * (2.0 / np.sum(w))
    amp[0] *= 0.5
    if n % 2 == 0:
        amp[-1] *= 0.5
    return Spectrum(sfft.rfftfreq(n, 1.0 / fs), amp)


def _orbit(v, w) -> np.ndarray:
    v = _check_signal(v, "v")
    w = _check_signal(w, "w")
    if v.size != w.size:
        raise InputError("w", f"array of length {w.size}", f"the length of v ({v.size})")
    return v + 1j * w


def full_spectrum(v, w, fs: float, *, window="hann") -> Spectrum:
    """Full spectrum of an orbit: amplitude spectrum of ``z = v + i w``.

    Positive frequencies are forward whirl (orbit turning from the v axis towards the w axis, the
    rotation sense when the spin is positive), negative frequencies backward whirl.  A circular
    orbit ``v + i w = R exp(i 2 pi f t)`` reads ``R`` at ``+f``; a straight-line (unidirectional)
    vibration of amplitude ``A`` splits into ``A/2`` at ``+f`` and ``A/2`` at ``-f``.

    Parameters
    ----------
    v, w : array_like, shape (n_samples,)
        Displacements along two orthogonal axes (same unit, same length).
    fs : float
        Sampling frequency (Hz).
    window : str or tuple, optional
        Window (default ``"hann"``).

    Returns
    -------
    Spectrum
        ``frequencies`` ascending from -fs/2 to below fs/2 (Hz) and ``amplitudes``
        ``|Z_k| / sum(w)`` (unit of v).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(400) / 100.0
    >>> z = 2.0 * np.exp(-2j * np.pi * 5.0 * t)  # backward whirl at 5 Hz
    >>> spec = full_spectrum(z.real, z.imag, 100.0)
    >>> float(spec.frequencies[np.argmax(spec.amplitudes)])
    -5.0
    """
    fs = _check_fs(fs)
    z = _orbit(v, w)
    n = z.size
    win = _window(window, n)
    amp = np.abs(sfft.fftshift(sfft.fft(z * win))) / np.sum(win)
    return Spectrum(sfft.fftshift(sfft.fftfreq(n, 1.0 / fs)), amp)


def order_spectrum(
    signal, fs: float, spin_hz: float, *, orders=DEFAULT_ORDERS, window="hann"
) -> Spectrum:
    """Amplitudes at multiples (orders) of the spin frequency.

    Each amplitude is the windowed discrete-time Fourier transform evaluated exactly at
    ``order * spin_hz`` (not the nearest bin), ``2 |sum_n x[n] w[n] exp(-i 2 pi f n / fs)| /
    sum(w)``, so a tone at that order reads its amplitude without bin alignment.  Other lines
    leak in through the window's side lobes: keep the record longer than about 4 / (the
    smallest spacing between orders, in Hz) for Hann.

    Parameters
    ----------
    signal : array_like, shape (n_samples,)
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    spin_hz : float
        Spin (1X) frequency (Hz), > 0.
    orders : sequence of float, optional
        Orders to evaluate, each > 0 with ``order * spin_hz < fs/2``; default 1/3, 1/2, 2/3, 1,
        2, 3.
    window : str or tuple, optional
        Window (default ``"hann"``).

    Returns
    -------
    Spectrum
        ``frequencies`` holds the orders (dimensionless, multiples of spin) and ``amplitudes``
        the amplitude at each (unit of the signal).
    """
    fs = _check_fs(fs)
    x = _check_signal(signal, "signal")
    try:
        spin = float(spin_hz)
    except (TypeError, ValueError):
        raise InputError("spin_hz", spin_hz, "a finite spin frequency > 0 (Hz)") from None
    if not np.isfinite(spin) or spin <= 0:
        raise InputError("spin_hz", spin_hz, "a finite spin frequency > 0 (Hz)")
    ords = np.atleast_1d(np.asarray(orders, dtype=np.float64))
    if (
        ords.ndim != 1
        or ords.size == 0
        or not np.all(np.isfinite(ords))
        or np.any(ords <= 0)
        or np.any(ords * spin >= fs / 2)
    ):
        raise InputError(
            "orders", orders, f"positive orders with order * spin_hz < fs/2 = {fs / 2:g} Hz"
        )
    n = x.size
    win = _window(window, n)
    xw = x * win
    t = np.arange(n)
    amps = np.empty(ords.size)
    for i, o in enumerate(ords):
        phase = np.exp(-2j * np.pi * o * spin * t / fs)
        amps[i] = 2.0 * np.abs(np.dot(xw, phase)) / np.sum(win)
    return Spectrum(ords, amps)
