r"""Machinery-diagnostics views of a record with a known spin angle: cascade, shaft centreline,
order-filtered orbits and keyphasor marks.

All take a :class:`rubrotor.analysis.orders.SpinAngle` (from the run, a speed column or a
keyphasor) and signals sampled at its times; speeds and frequencies are in rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.analysis.orders import _TWO_PI, OrderTrack, SpinAngle, _per_rev, _rev_sums
from rubrotor.errors import InputError

__all__ = [
    "Cascade",
    "cascade",
    "Centreline",
    "shaft_centreline",
    "filtered_orbit",
    "keyphasor_marks",
]


@dataclass(frozen=True)
class Cascade:
    """Spectra of consecutive blocks against speed (a waterfall).

    Attributes
    ----------
    speed_rad_s : numpy.ndarray, shape (n_blocks,)
        Mean spin speed of each block (rad/s).
    frequency_rad_s : numpy.ndarray, shape (n_freq,)
        Frequencies (rad/s): ``0 .. pi fs`` for one channel, ``-pi fs .. pi fs`` for a full
        spectrum (negative = backward whirl).
    amplitude : numpy.ndarray, shape (n_blocks, n_freq)
        Hann-window amplitude-corrected spectrum of each block (unit of the signal): a tone of
        amplitude ``A`` reads ``A`` (one channel); a circular orbit of radius ``R`` reads ``R``.
    full : bool
        Whether this is a full-spectrum cascade of ``y + i w``.
    """

    speed_rad_s: np.ndarray
    frequency_rad_s: np.ndarray
    amplitude: np.ndarray
    full: bool


def _uniform_fs(t: np.ndarray) -> float:
    dt = np.diff(t)
    if np.ptp(dt) > 1e-6 * np.mean(dt):
        raise InputError("time", "non-uniform sampling", "a uniform time grid for a cascade")
    return 1.0 / float(np.mean(dt))


def _mark_times(spin: SpinAngle) -> np.ndarray:
    """Times (s) of the keyphasor marks (``theta = 2 pi j``) inside the record."""
    sl = spin.valid
    t, a = spin.time[sl], spin.angle[sl]
    j = np.arange(math.ceil(a[0] / _TWO_PI - 1e-12), math.floor(a[-1] / _TWO_PI + 1e-12) + 1)
    return np.interp(_TWO_PI * j, a, t)


def cascade(spin: SpinAngle, y, w=None, *, revolutions: int = 8, max_spectra: int = 120) -> Cascade:
    """Cascade (waterfall) of spectra against spin speed; full-spectrum cascade with ``w``.

    The record is cut at keyphasor marks into blocks of ``revolutions`` revolutions (consecutive,
    not overlapping; every few blocks are skipped to keep at most ``max_spectra``), each Hann
    windowed and zero-padded to a common length.

    Parameters
    ----------
    spin : SpinAngle
        Spin angle and speed of the record.
    y : array_like, shape (n,)
        Signal (any unit) on a uniform time grid ``spin.time``.
    w : array_like, shape (n,), optional
        Second direction: the cascade is then the full spectrum of ``y + i w``.
    revolutions : int
        Revolutions per spectrum (>= 2).
    max_spectra : int
        Largest number of spectra.

    Returns
    -------
    Cascade
    """
    if not (isinstance(revolutions, int) and revolutions >= 2):
        raise InputError("revolutions", revolutions, "an integer >= 2")
    fs = _uniform_fs(spin.time)
    x = np.asarray(y, dtype=np.float64) + (0j if w is None else 1j * np.asarray(w, float))
    if x.shape != spin.time.shape:
        raise InputError(
            "y", f"array of shape {x.shape}", f"one sample per time ({spin.time.size})"
        )
    marks = _mark_times(spin)
    idx = np.searchsorted(spin.time, marks)
    edges = idx[::revolutions]
    if edges.size < 2:
        raise InputError(
            "record", f"{marks.size - 1} revolutions", f"at least {revolutions} revolutions"
        )
    keep = np.arange(edges.size - 1)[:: max(1, math.ceil((edges.size - 1) / max_spectra))]
    nfft = 2 ** math.ceil(math.log2(int(np.max(np.diff(edges))) * 2))
    from scipy.signal import get_window

    rows, speeds = [], []
    for k in keep:
        a, b = int(edges[k]), int(edges[k + 1])
        win = get_window("hann", b - a, fftbins=True)
        spec = np.abs(np.fft.fft(x[a:b] * win, nfft)) / np.sum(win)
        rows.append(spec)
        speeds.append((spin.angle[b] - spin.angle[a]) / (spin.time[b] - spin.time[a]))
    freq = np.fft.fftfreq(nfft, 1.0 / fs) * _TWO_PI
    amp = np.array(rows)
    if w is None:
        half = nfft // 2 + 1
        freq, amp = np.abs(freq[:half]), amp[:, :half] * 2.0
        amp[:, 0] *= 0.5
    else:
        order = np.argsort(freq)
        freq, amp = freq[order], amp[:, order]
    return Cascade(np.array(speeds), freq, amp, w is not None)


@dataclass(frozen=True)
class Centreline:
    """Average shaft position per revolution (the shaft centreline plot).

    Attributes
    ----------
    speed_rad_s : numpy.ndarray
        Mean spin speed of each revolution (rad/s).
    time_s : numpy.ndarray
        Time of each revolution's middle (s).
    y, z : numpy.ndarray
        Mean position over the revolution (m, or the signals' unit).
    """

    speed_rad_s: np.ndarray
    time_s: np.ndarray
    y: np.ndarray
    z: np.ndarray


def shaft_centreline(spin: SpinAngle, y, w, *, samples_per_rev: int | None = None) -> Centreline:
    """Average position per revolution against speed (exact mean over each revolution's angle).

    Parameters
    ----------
    spin : SpinAngle
        Spin angle and speed of the record.
    y, w : array_like, shape (n,)
        Displacements along y and z (m) at ``spin.time``.
    samples_per_rev : int, optional
        Angle samples per revolution (see :func:`rubrotor.analysis.orders.track_orders`).

    Returns
    -------
    Centreline
    """
    m = _per_rev(spin, samples_per_rev)
    chans = [np.asarray(y, float), np.asarray(w, float)]
    r0, (sy, sz), time_at = _rev_sums(spin, chans, m, np.zeros(1))
    edges = time_at(_TWO_PI * (r0 + np.arange(sy.shape[0] + 1)))
    mid = time_at(_TWO_PI * (r0 + 0.5 + np.arange(sy.shape[0])))
    return Centreline(_TWO_PI / np.diff(edges), mid, sy[:, 0].real / m, sz[:, 0].real / m)


def filtered_orbit(spin: SpinAngle, track: OrderTrack, order: float = 1.0):
    """The orbit of one tracked order: ``y_k = Re(Y_k(t) exp(i k theta))``, same for z.

    ``Y_k(t)`` is interpolated linearly in time between the blocks' middle times; outside the
    first and last middle times the samples are NaN.

    Parameters
    ----------
    spin : SpinAngle
        The record's spin angle (at the signal's times).
    track : OrderTrack
        Tracked orders of the probe (with both directions).
    order : float
        The order to keep (one of ``track.orders``).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        ``y_k, z_k`` at ``spin.time`` (unit of the tracked signal).
    """
    if track.w is None:
        raise InputError("track", "one direction", "an order track of y and z (an orbit)")
    i = track.order_index(order)
    t = spin.time
    inside = (t >= track.time_s[0]) & (t <= track.time_s[-1])
    rot = np.exp(1j * order * spin.angle[inside])
    out = []
    for ph in (track.y[i], track.w[i]):
        re = np.interp(t[inside], track.time_s, ph.real)
        im = np.interp(t[inside], track.time_s, ph.imag)
        x = np.full(t.shape, np.nan)
        x[inside] = ((re + 1j * im) * rot).real
        out.append(x)
    return out[0], out[1]


def keyphasor_marks(spin: SpinAngle, y, w) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where the orbit is when the keyphasor fires (``theta = 2 pi j``).

    Parameters
    ----------
    spin : SpinAngle
        Spin angle of the record.
    y, w : array_like, shape (n,)
        Orbit coordinates at ``spin.time`` (m); NaN samples give NaN marks.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        Mark times (s) and the orbit's y, z there (linear interpolation between samples).
    """
    tm = _mark_times(spin)
    return tm, np.interp(tm, spin.time, y), np.interp(tm, spin.time, w)
