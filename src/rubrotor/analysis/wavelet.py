r"""Continuous wavelet transform with the analytic Morlet wavelet, scalograms and binned maps.

Definitions
-----------
Mother wavelet (non-corrected complex Morlet, no admissibility term)::

    psi(t) = sqrt(2/pi) * exp(i*omega0*t) * exp(-t**2/2),
    Psi(omega) = 2 * exp(-(omega - omega0)**2 / 2)          (Fourier transform).

``omega0`` (rad per unit of dimensionless time, default 6) is the only shape parameter: the
centre frequency is ``fc = omega0/(2*pi)`` cycles per unit time and the Gaussian envelope has unit
standard deviation in time (``exp(-t**2/2)``) and in angular frequency.  In PyWavelets' notation
this shape is ``cmor2.0-{omega0/(2*pi)}`` (bandwidth parameter B = 2, centre C = fc), only
normalized differently.  At scale ``s`` (in samples) the wavelet is centred on the physical
frequency ``f = fs * omega0 / (2*pi*s)`` (Hz), its envelope has standard deviation ``s`` samples in
time and ``f / omega0`` Hz in frequency (relative bandwidth ``1/omega0``).  The negative-frequency
response is ``2*exp(-(s*omega + omega0)**2/2)``, i.e. ``2*exp(-2*omega0**2)`` (1e-31 for
omega0 = 6) at the mirror of the centre frequency, so the transform is analytic to that level
without an explicit Heaviside step (a step would make the time kernel non-local).

Transform (seed eqs. 17-18, discretized with du = one sample)::

    W[j, u] = sum_n x[n] * (1/s_j) * conj(psi((n - u)/s_j))          ("l1", default)

In the frequency domain each scale multiplies the spectrum of the padded signal by
``G_s(omega) = g * exp(-(s*omega - omega0)**2/2)``, real-valued, with peak gain ``g = 2`` for the L1
normalization, so that a tone ``A*cos(2*pi*f*t)`` gives ``|W| = A`` at the scale of ``f``.
``"l2"`` uses unit-energy wavelets ``(1/sqrt(s)) * pi**(-1/4) * exp(i*omega0*t - t**2/2)``
(``g = sqrt(2*s) * pi**(1/4)``), so ``|W| = A * sqrt(s) * pi**(1/4) / sqrt(2)`` for the same tone:
the L2 modulus grows like ``sqrt(s)``, which shifts the peak of ``|W|`` over scales (and of the L2
scalogram) towards lower frequency: for a tone of frequency ``f1`` the maximum sits at
``f = f1 * 2*omega0 / (omega0 + sqrt(omega0**2 + 2))`` (1.35 % low for omega0 = 6), and for
broadband signals low frequencies are weighted up by ``sqrt(s)``.

The Gaussian is truncated to zero where it falls below ``eps`` of its peak, ``eps`` the machine
epsilon of the output precision: ``|s*omega - omega0| <= h = sqrt(2*ln(1/eps))`` (h = 8.49 in
float64, 5.65 in float32).  Only the bins of that band are multiplied.  On the discrete grid the
filter is sampled at the DFT bins of the padded length ``M``; the Nyquist bin (even ``M``) gets
half the gain (it stands for +pi and -pi).

Padding (the transform is circular on the padded length ``M``)
--------------------------------------------------------------
``"symmetric"`` (default)
    Whole-sample mirror to period ``M = 2N``: ``x[0..N-1], x[N-1..0]``.  No jump at the edges,
    valid for every scale (even scales longer than the record), and because the filter is real in
    frequency the second half of the circle holds the complex conjugate of the first
    (``W[2N-1-m] = conj(W[m])``): the energy over the N original samples is exactly half the
    circle's energy, which is what makes the Parseval scalogram exact.  The spectrum of this
    extension is the DCT-II of ``x``; each scale costs one DCT-III and one DST-III of length N.
``"periodic"``
    No padding, ``M = N`` (circular wrap-around at the edges).
``"zero"``
    Zeros appended up to ``M = next_fast_len(N + 2*L_max)``, ``L_max`` the time half-support
    ``ceil(h * s_max) + 1`` of the largest scale, so that the result is the linear convolution.

Cone of influence: ``coi = ceil(sqrt(2) * s)`` samples (the e-folding time of the Morlet power at
scale s) at each end of the record.  ``cwt`` returns it per frequency, in samples.

Scalogram (seed eq. 19) and inner scalogram (eq. 20), discretized with du = 1/fs::

    scal[j]  = sqrt( sum_{n=0}^{N-1}            |W[j, n]|**2 / fs )     (unit * s**0.5)
    inner[j] = sqrt( sum_{n=coi_j}^{N-1-coi_j}  |W[j, n]|**2 / fs )

where ``W`` is exactly the matrix ``cwt`` returns with the same ``padding``, ``omega0``,
``normalization`` and ``dtype=np.complex128``.  ``scalogram`` does not build that matrix: the
full-record energy comes from the spectrum by Parseval (symmetric: half the energy of the 2N circle;
periodic: the circle's energy; zero: the circle's energy minus the padded region, where W is
non-zero only within ``L`` samples of the record), and the inner one subtracts the two edge strips
of width ``coi``, which (like the padded region) are computed by a short direct convolution with
the time-domain kernel ``(g/(s*sqrt(2*pi))) * exp(i*omega0*t/s - t**2/(2*s**2))``, |t| <= L.  That
kernel is the exact inverse DFT of the truncated filter (Poisson summation) up to the truncation
level ``eps``, provided the band does not reach Nyquist (``(omega0 + h)/s < pi``) and the kernel
fits in the circle.  Where it does not (frequencies above about 0.2 fs in float64) the edge
strips are summed directly from the band, ``W[m] = (1/M) sum_k G(k) Y[k] exp(2j*pi*k*m/M)``, for
each of their ``2*coi`` samples (compiled, :mod:`rubrotor.core.cwtkern`); only rows where
neither applies (scales comparable to the record, or zero padding with a band reaching Nyquist)
are computed as full rows one at a time.  The Parseval band sums are compiled too.  Memory is
O(N + number of frequencies).

Computing rows
--------------
Row ``j`` is ``W[m] = sum_k Z[k] exp(2j*pi*k*m/M)`` over its band of ``B`` bins.  With
``M = P*L`` and ``m = P*q + r`` it is a batch of inverse FFTs of length ``L`` (a divisor of
``M`` of at least ``B/8`` bins, about 2^17 at most so that a row stays in cache) of the band
folded modulo ``L`` with per-residue twiddles, interleaved back into the row; the symmetric mode
computes only the residues ``r < ceil(P/2)`` and fills the rest from ``W[2N-1-m] = conj(W[m])``.
The arithmetic is that of one complex FFT of length N per scale, in cache, without any
N-by-scales complex temporary; :func:`cwt_magnitude` writes ``|W|`` straight into a real output.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from typing import NamedTuple

import numpy as np
import scipy.fft as sfft

from rubrotor.core import cwtkern as _kern
from rubrotor.errors import InputError

__all__ = [
    "CWTResult",
    "BinnedCWT",
    "log_frequencies",
    "scale_from_frequency",
    "cwt",
    "cwt_magnitude",
    "scalogram",
    "scalograms",
    "inner_scalogram",
    "cwt_binned",
    "PADDING_MODES",
]

PADDING_MODES = ("symmetric", "periodic", "zero")
_NORMALIZATIONS = ("l1", "l2")
_BATCH_ELEMENTS = 1 << 22  # rows per batch of rows(): about 4 Mi elements of buffer
_MAX_FOLD = 8  # band bins summed into one FFT input bin, at most
_MIN_LENGTH = 8192  # shortest inverse FFT unless the band is narrower
_FOLD_COST = 2.0  # cost of one folded bin relative to one FFT butterfly pass per point
_STRIP_BUDGET = 1 << 25  # strip samples x band bins summed directly for an edge strip
_CACHE_BYTES = 1 << 20  # FFT rows up to this size run from cache (measured: 2^17 complex64)


class CWTResult(NamedTuple):
    """Result of :func:`cwt`.

    Attributes
    ----------
    coefficients : numpy.ndarray, complex, shape (n_frequencies, n_samples)
        Wavelet coefficients W (unit of the signal for ``"l1"``; see module notes for ``"l2"``).
    frequencies : numpy.ndarray, float64, shape (n_frequencies,)
        Physical frequency of each row (Hz).
    coi : numpy.ndarray, int64, shape (n_frequencies,)
        Cone-of-influence margin ``ceil(sqrt(2) * s)`` at each end of the record (samples).
    metadata : dict
        ``fs`` (Hz), ``omega0`` (rad), ``fc`` (= omega0/2pi, cycles per unit time), ``scales``
        (samples, array), ``bandwidth_hz`` (Gaussian standard deviation of each row's frequency
        response, Hz, array), ``normalization``, ``padding``, ``padded_length`` (samples),
        ``truncation_eps`` and ``truncation_halfwidth`` (h, in units of s*omega), ``coi_unit``.
    """

    coefficients: np.ndarray
    frequencies: np.ndarray
    coi: np.ndarray
    metadata: dict


class BinnedCWT(NamedTuple):
    """Result of :func:`cwt_binned`.

    Attributes
    ----------
    values : numpy.ndarray, float64, shape (n_frequencies, n_bins)
        Maximum or RMS of ``|W|`` in each time bin (unit of the signal for ``"l1"``).
    frequencies : numpy.ndarray, float64, shape (n_frequencies,)
        Frequency of each row (Hz).
    times : numpy.ndarray, float64, shape (n_bins,)
        Centre of each bin (s), with t = 0 at the first sample.
    bin_edges : numpy.ndarray, int64, shape (n_bins + 1,)
        Sample index where each bin starts; the last entry is n_samples.
    coi : numpy.ndarray, int64, shape (n_frequencies,)
        Cone-of-influence margin per row (samples).
    """

    values: np.ndarray
    frequencies: np.ndarray
    times: np.ndarray
    bin_edges: np.ndarray
    coi: np.ndarray


# --------------------------------------------------------------------------- validation


def _check_fs(fs) -> float:
    try:
        value = float(fs)
    except (TypeError, ValueError):
        raise InputError("fs", fs, "a finite sampling frequency > 0 (Hz)") from None
    if not math.isfinite(value) or value <= 0.0:
        raise InputError("fs", fs, "a finite sampling frequency > 0 (Hz)")
    return value


def _check_signal(signal, field: str = "signal") -> np.ndarray:
    try:
        x = np.asarray(signal, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(field, signal, "a 1-D array of finite real numbers") from None
    if x.ndim != 1 or x.size < 2:
        raise InputError(
            field, f"array of shape {x.shape}", "a 1-D array of at least 2 finite real samples"
        )
    if not np.all(np.isfinite(x)):
        raise InputError(field, "array with NaN or inf", "a 1-D array of finite real numbers")
    return x


def _check_frequencies(frequencies, fs: float) -> np.ndarray:
    try:
        f = np.atleast_1d(np.asarray(frequencies, dtype=np.float64))
    except (TypeError, ValueError):
        raise InputError("frequencies", frequencies, "an array of frequencies in Hz") from None
    if f.ndim != 1 or f.size == 0:
        raise InputError("frequencies", frequencies, "a non-empty 1-D array of frequencies (Hz)")
    if not np.all(np.isfinite(f)) or np.any(f <= 0.0) or np.any(f >= fs / 2.0):
        raise InputError(
            "frequencies",
            frequencies,
            f"finite frequencies in the open interval (0, fs/2) = (0, {fs / 2:g}) Hz",
        )
    return f


def _check_omega0(omega0) -> float:
    try:
        value = float(omega0)
    except (TypeError, ValueError):
        raise InputError("omega0", omega0, "a finite number >= 5 (rad)") from None
    if not math.isfinite(value) or value < 5.0:
        raise InputError(
            "omega0", omega0, "a finite number >= 5 (rad), so that the wavelet is analytic to 1e-21"
        )
    return value


def _check_choice(field: str, value, allowed: tuple[str, ...]) -> str:
    if value not in allowed:
        raise InputError(field, value, "one of " + ", ".join(repr(a) for a in allowed))
    return value


def _check_dtype(dtype) -> np.dtype:
    try:
        dt = np.dtype(dtype)
    except TypeError:
        raise InputError("dtype", dtype, "numpy.complex64 or numpy.complex128") from None
    if dt not in (np.dtype(np.complex64), np.dtype(np.complex128)):
        raise InputError("dtype", dtype, "numpy.complex64 or numpy.complex128")
    return dt


def _check_workers(workers) -> int:
    if workers is None:
        return 1
    if not isinstance(workers, int | np.integer) or workers == 0:
        raise InputError("workers", workers, "a non-zero integer (negative counts from cpu_count)")
    return int(workers)


# --------------------------------------------------------------------------- helpers


def log_frequencies(fmin: float, fmax: float, count: int) -> np.ndarray:
    """Log-spaced analysis frequencies.

    Parameters
    ----------
    fmin, fmax : float
        Lowest and highest frequency (Hz), ``0 < fmin <= fmax``.
    count : int
        Number of frequencies (>= 1).

    Returns
    -------
    numpy.ndarray, float64, shape (count,)
        Frequencies (Hz), ascending, geometric progression from ``fmin`` to ``fmax``.

    Examples
    --------
    >>> log_frequencies(1.0, 100.0, 3)
    array([  1.,  10., 100.])
    """
    for name, val in (("fmin", fmin), ("fmax", fmax)):
        if not np.isfinite(val) or val <= 0:
            raise InputError(name, val, "a finite frequency > 0 (Hz)")
    if fmax < fmin:
        raise InputError("fmax", fmax, f"a frequency >= fmin = {fmin} (Hz)")
    if not isinstance(count, int | np.integer) or count < 1:
        raise InputError("count", count, "an integer >= 1")
    if count == 1:
        return np.array([float(fmin)])
    return np.geomspace(float(fmin), float(fmax), int(count))


def scale_from_frequency(frequencies, fs: float, omega0: float = 6.0) -> np.ndarray:
    """Morlet scale of each frequency, ``s = fs * omega0 / (2*pi*f)``.

    Parameters
    ----------
    frequencies : array_like
        Frequencies (Hz).
    fs : float
        Sampling frequency (Hz).
    omega0 : float
        Morlet centre angular frequency (rad per unit dimensionless time).

    Returns
    -------
    numpy.ndarray, float64
        Scales (samples).
    """
    return float(fs) * float(omega0) / (2.0 * np.pi * np.asarray(frequencies, dtype=np.float64))


def _divisors(m: int) -> list[int]:
    small = [d for d in range(1, math.isqrt(m) + 1) if m % d == 0]
    return sorted(set(small + [m // d for d in small]))


def _halfwidth(eps: float) -> float:
    return math.sqrt(2.0 * math.log(1.0 / eps))


class _Plan:
    """Spectrum of the padded signal and per-scale filters; yields rows of W in batches."""

    def __init__(self, x, fs, frequencies, omega0, normalization, padding, real_dtype, workers):
        self.x = x
        self.n = x.size
        self.fs = fs
        self.freqs = frequencies
        self.omega0 = omega0
        self.normalization = normalization
        self.padding = padding
        self.rdt = np.dtype(real_dtype)
        self.cdt = np.result_type(self.rdt, np.complex64)
        self.workers = workers
        self.eps = float(np.finfo(self.rdt).eps)
        self.h = _halfwidth(self.eps)
        self.scales = scale_from_frequency(frequencies, fs, omega0)
        self.coi = np.ceil(np.sqrt(2.0) * self.scales).astype(np.int64)
        self.half_support = np.ceil(self.h * self.scales).astype(np.int64) + 1
        if normalization == "l1":
            self.gain = np.full(self.scales.shape, 2.0)
        else:
            self.gain = np.sqrt(2.0 * self.scales) * np.pi**0.25
        n = self.n
        xs = x.astype(self.rdt, copy=False)
        if padding == "symmetric":
            self.m = 2 * n
            self.spec = sfft.dct(xs, type=2, workers=workers)  # C_k, k = 0..N-1; C_N = 0
        elif padding == "periodic":
            self.m = n
            self.spec = sfft.rfft(xs, workers=workers)
        else:
            self.m = sfft.next_fast_len(int(n + 2 * self.half_support.max()))
            self.spec = sfft.rfft(xs, n=self.m, workers=workers)
        self.divisors = _divisors(self.m)
        self._work: np.ndarray | None = None
        self._tables: tuple | None = None
        self._spec_c: np.ndarray | None = None
        self._layouts: dict[int, tuple[int, int, int]] = {}

    def _complex_spectrum(self, sym: bool) -> np.ndarray:
        """The spectrum as complex128; for the symmetric circle with ``C_N = 0`` appended."""
        if not sym:
            return self.spec.astype(np.complex128)
        out = np.zeros(self.n + 1, np.complex128)
        out[: self.n] = self.spec
        return out

    # filter ------------------------------------------------------------------------------
    def band(self, j: int) -> tuple[int, int]:
        """Integer DFT bins (k_lo may be negative) where the truncated filter may be non-zero."""
        s, m = self.scales[j], self.m
        k_lo = math.floor(m * (self.omega0 - self.h) / (2.0 * np.pi * s)) - 1
        k_hi = math.ceil(m * (self.omega0 + self.h) / (2.0 * np.pi * s)) + 1
        k_lo = max(k_lo, -((m - 1) // 2))
        k_hi = min(k_hi, m // 2)
        return k_lo, k_hi

    def gains(self, j: int, k: np.ndarray) -> np.ndarray:
        """Filter value at integer bins ``k`` (float64), truncated and Nyquist-halved."""
        arg = self.scales[j] * (2.0 * np.pi / self.m) * k.astype(np.float64) - self.omega0
        g = self.gain[j] * np.exp(-0.5 * arg * arg)
        g[np.abs(arg) > self.h] = 0.0
        if self.m % 2 == 0 and k.size and k[-1] == self.m // 2:
            g[k == self.m // 2] *= 0.5
        return g

    def local_ok(self, j: int) -> bool:
        """True when the time kernel is the sampled Gaussian Morlet to truncation precision."""
        s = self.scales[j]
        return bool(
            (self.omega0 + self.h) / s < np.pi * (1.0 - 1e-12)
            and 2 * self.half_support[j] + 1 < self.m
        )

    def kernel(self, j: int) -> np.ndarray:
        """Time kernel g[t], t = -L..L (complex128)."""
        s = self.scales[j]
        big_l = int(self.half_support[j])
        t = np.arange(-big_l, big_l + 1, dtype=np.float64)
        amp = self.gain[j] / (s * math.sqrt(2.0 * np.pi))
        return amp * np.exp(1j * self.omega0 * t / s - 0.5 * (t / s) ** 2)

    # rows --------------------------------------------------------------------------------
    def layout(self, j: int) -> tuple[int, int, int]:
        if j not in self._layouts:
            self._layouts[j] = self._layout(j)
        return self._layouts[j]

    def _layout(self, j: int) -> tuple[int, int, int]:
        """``(L, P, R)``: inverse FFT length, interleave period ``P = M/L`` and rows computed.

        ``L`` is a divisor of ``M`` at least the band width divided by ``_MAX_FOLD`` (each FFT
        input bin then sums at most a few band bins) and preferably FFT-friendly; symmetric rows
        need only the residues ``r < ceil(P/2)`` (the rest by conjugate symmetry) and ``P >= 2``.
        """
        k_lo, k_hi = self.band(j)
        width = k_hi - k_lo + 1
        sym = self.padding == "symmetric"
        longest = self.m // 2 if sym else self.m
        best = None
        for length in self.divisors:
            period = self.m // length
            if period < (2 if sym else 1):
                continue
            if length * _MAX_FOLD < width or length < min(width, _MIN_LENGTH, longest):
                continue
            rows = (period + 1) // 2 if sym else period
            smooth = sfft.next_fast_len(length) == length
            # FFT passes (slower once a row leaves the cache) plus the folding of the band
            spill = 1.0 if length * self.cdt.itemsize <= _CACHE_BYTES else 2.5
            cost = (
                0 if smooth else 1,
                rows * length * math.log2(max(length, 2)) * spill
                + _FOLD_COST * rows * max(width, length),
            )
            if best is None or cost < best[0]:
                best = (cost, length, period, rows)
        assert best is not None  # L = M/2 (symmetric) or M always qualifies
        return best[1], best[2], best[3]

    def row_into(self, j: int, dest: np.ndarray) -> None:
        """Write row ``j`` of W (complex ``dest``) or of |W| (real ``dest``), shape (N,)."""
        length, period, rows = self.layout(j)
        k_lo, k_hi = self.band(j)
        sym = self.padding == "symmetric"
        if self._work is None:
            size = max(int(np.prod(self.layout(i)[0::2])) for i in range(self.freqs.size))
            self._work = np.empty(size, dtype=self.cdt)
            widths = [self.band(i)[1] - self.band(i)[0] + 1 for i in range(self.freqs.size)]
            self._z = np.empty(max(widths), dtype=np.complex128)
            self._twiddle = (2, 1, 2 * self.m) if sym else (1, 0, self.m)
            self._tables = (self._twiddle[2], *_kern.twiddle_tables(self._twiddle[2]))
            self._spec_c = self._complex_spectrum(sym)
        z = self._z[: k_hi - k_lo + 1]
        w = self.scales[j] * (2.0 * np.pi / self.m)
        _kern.band_values(
            self._spec_c, k_lo, w, self.omega0, self.gain[j] / self.m, self.h, self.m, z
        )
        work = self._work[: rows * length].reshape(rows, length)
        chunk = max(1024, -(-rows * length // 64) // rows)
        _kern.fold_band(z, k_lo, self._twiddle, self._tables[1:], work, chunk)
        res = sfft.ifft(work, axis=-1, norm="forward", overwrite_x=True, workers=self.workers)
        if np.iscomplexobj(dest):
            _kern.scatter_complex(res, period, self.n, sym, dest)
        else:
            _kern.scatter_abs(res, period, self.n, sym, dest)

    def rows(self, indices, batch: int | None = None) -> Iterator[tuple[np.ndarray, np.ndarray]]:
        """Yield ``(row_indices, W)`` with ``W`` of shape (len(row_indices), N)."""
        indices = np.asarray(indices, dtype=np.int64)
        if batch is None:
            batch = max(1, min(indices.size, _BATCH_ELEMENTS // self.m))
        buf = np.empty((min(batch, indices.size), self.n), dtype=self.cdt)
        for start in range(0, indices.size, batch):
            idx = indices[start : start + batch]
            for r, j in enumerate(idx):
                self.row_into(int(j), buf[r])
            yield idx, buf[: idx.size]

    # energies ----------------------------------------------------------------------------
    def circle_energy(self, j: int) -> float:
        """sum over the padded circle of |W|^2 (Parseval, compiled band sum), float64."""
        k_lo, k_hi = self.band(j)
        top = self.n - 1 if self.padding == "symmetric" else self.m // 2
        w = self.scales[j] * (2.0 * np.pi / self.m)
        filt = (w, self.omega0, float(self.gain[j]), self.h, self.m)
        e = _kern.band_energy(self.spec, k_lo, k_hi, top, filt)
        return float(e) / self.m

    def strip_energy(self, j: int, start: int, stop: int) -> float | None:
        """sum of |W[m]|^2 for circle indices start <= m < stop, or None if too costly.

        The short time-domain convolution where the kernel is local, else direct band sums (the
        definition of W, valid up to Nyquist) when the strip times the band is small.
        """
        if stop <= start:
            return 0.0
        if self.local_ok(j):
            return self.local_energy(j, start, stop)
        k_lo, k_hi = self.band(j)
        if (stop - start) * (k_hi - k_lo + 1) > _STRIP_BUDGET:
            return None
        sym = self.padding == "symmetric"
        if self._spec_c is None:
            self._spec_c = self._complex_spectrum(sym)
        mult, add, den = (2, 1, 2 * self.m) if sym else (1, 0, self.m)
        if self._tables is None or self._tables[0] != den:
            self._tables = (den, *_kern.twiddle_tables(den))
        z = np.empty(k_hi - k_lo + 1, dtype=np.complex128)
        w = self.scales[j] * (2.0 * np.pi / self.m)
        _kern.band_values(
            self._spec_c, k_lo, w, self.omega0, float(self.gain[j]) / self.m, self.h, self.m, z
        )
        return float(
            _kern.strip_energy(
                z,
                k_lo,
                mult,
                add,
                den,
                self._tables[1],
                self._tables[2],
                np.arange(start, stop, dtype=np.int64),
            )
        )

    def extended(self, idx: np.ndarray) -> np.ndarray:
        """Padded signal at arbitrary (possibly negative) circle indices."""
        n, m = self.n, self.m
        i = np.mod(idx, m)
        if self.padding == "symmetric":
            return self.x[np.where(i < n, i, 2 * n - 1 - i)]
        if self.padding == "periodic":
            return self.x[i]
        vals = np.zeros(i.shape)
        inside = i < n
        vals[inside] = self.x[i[inside]]
        return vals

    def local_energy(self, j: int, start: int, stop: int) -> float:
        """sum of |W[m]|^2 for circle indices start <= m < stop, by direct short convolution."""
        if stop <= start:
            return 0.0
        big_l = int(self.half_support[j])
        seg = self.extended(np.arange(start - big_l, stop + big_l))
        g = self.kernel(j)
        if g.size * (stop - start) < 1 << 16:
            w = np.convolve(seg, g, mode="valid")
        else:
            w = _fftconvolve_valid(seg, g)
        return float(np.sum(w.real**2 + w.imag**2))


def _fftconvolve_valid(seg: np.ndarray, g: np.ndarray) -> np.ndarray:
    n = seg.size + g.size - 1
    nf = sfft.next_fast_len(n)
    out = sfft.ifft(sfft.fft(seg, nf) * sfft.fft(g, nf))
    return out[g.size - 1 : seg.size]


def _make_plan(signal, fs, frequencies, omega0, normalization, padding, real_dtype, workers):
    fs = _check_fs(fs)
    x = _check_signal(signal)
    f = _check_frequencies(frequencies, fs)
    omega0 = _check_omega0(omega0)
    _check_choice("normalization", normalization, _NORMALIZATIONS)
    _check_choice("padding", padding, PADDING_MODES)
    workers = _check_workers(workers)
    return _Plan(x, fs, f, omega0, normalization, padding, real_dtype, workers)


# --------------------------------------------------------------------------- public API


def cwt(
    signal,
    fs: float,
    frequencies,
    *,
    omega0: float = 6.0,
    normalization: str = "l1",
    padding: str = "symmetric",
    dtype=np.complex64,
    workers: int | None = None,
) -> CWTResult:
    r"""Continuous wavelet transform with the analytic Morlet wavelet (FFT based).

    One real transform of the padded signal (DCT-II for ``"symmetric"``, rfft otherwise); each
    scale multiplies only the bins of its Gaussian band (truncated at ``eps`` of the peak, see the
    module notes) and the inverse transforms run in batches into a preallocated output.

    Parameters
    ----------
    signal : array_like, shape (n_samples,)
        Real signal sampled at ``fs`` (any unit; W carries the same unit for ``"l1"``).
    fs : float
        Sampling frequency (Hz), > 0.
    frequencies : array_like, shape (n_frequencies,)
        Analysis frequencies (Hz), each in the open interval (0, fs/2); e.g. from
        :func:`~rubrotor.analysis.wavelet.log_frequencies`.  Row ``j`` uses the scale ``s_j = fs*omega0/(2*pi*f_j)`` samples.
    omega0 : float, optional
        Morlet centre angular frequency (rad per unit dimensionless time), >= 5; default 6.
        Relative bandwidth of every row is ``1/omega0`` (Gaussian standard deviation / f).
    normalization : {"l1", "l2"}, optional
        ``"l1"`` (default, seed eq. 18, ``(1/s) psi(t/s)``): a tone of amplitude A reads
        ``|W| = A`` at its own scale.  ``"l2"``: unit-energy wavelets ``(1/sqrt(s)) psi(t/s)``
        with ``psi`` normalized to unit energy (s in samples); ``|W|`` of a tone grows like
        ``sqrt(s)`` and its peak over scales sits 1.35 % below the tone frequency (omega0 = 6).
    padding : {"symmetric", "periodic", "zero"}, optional
        Edge handling, see the module notes.  Default ``"symmetric"`` (whole-signal mirror of
        period 2N: continuous at the edges, and the one for which the scalogram by Parseval is
        exact).
    dtype : {numpy.complex64, numpy.complex128}, optional
        Output precision (default complex64); the internal transforms use the matching real
        precision and the band truncation uses its machine epsilon.
    workers : int, optional
        Threads for scipy.fft (default 1).

    Returns
    -------
    CWTResult
        ``coefficients`` (n_frequencies, n_samples), ``frequencies`` (Hz), ``coi`` (samples at
        each end, ``ceil(sqrt(2) * s)``) and ``metadata`` (dict: fs, omega0, fc, scales,
        bandwidth_hz, normalization, padding, padded_length, truncation_eps, truncation_halfwidth,
        coi_unit).

    Raises
    ------
    rubrotor.errors.InputError
        Empty or non-finite signal, fs <= 0, a frequency outside (0, fs/2), unknown option.

    Examples
    --------
    A 50 Hz tone of amplitude 2 read at 50 Hz in the interior of the record:

    >>> import numpy as np
    >>> fs = 1000.0
    >>> t = np.arange(2000) / fs
    >>> res = cwt(2.0 * np.cos(2 * np.pi * 50.0 * t), fs, [10.0, 50.0, 250.0],
    ...           dtype=np.complex128)
    >>> res.coefficients.shape, res.coi.tolist()
    ((3, 2000), [136, 28, 6])
    >>> np.round(np.abs(res.coefficients[:, 1000]), 4)
    array([0., 2., 0.])
    """
    dt = _check_dtype(dtype)
    real = np.float32 if dt == np.complex64 else np.float64
    plan = _make_plan(signal, fs, frequencies, omega0, normalization, padding, real, workers)
    out = np.empty((plan.freqs.size, plan.n), dtype=dt)
    for j in range(plan.freqs.size):
        plan.row_into(j, out[j])
    return CWTResult(out, plan.freqs.copy(), plan.coi.copy(), _metadata(plan))


def cwt_magnitude(
    signal,
    fs: float,
    frequencies,
    *,
    omega0: float = 6.0,
    normalization: str = "l1",
    padding: str = "symmetric",
    dtype=np.float32,
    workers: int | None = None,
    out: np.ndarray | None = None,
) -> CWTResult:
    """Modulus ``|W|`` of :func:`cwt`, written row by row into a real array.

    Equal to ``np.abs(cwt(...).coefficients)`` to rounding, but the complex matrix is never
    formed: each row goes from a work buffer of about N complex elements straight into ``out``,
    so the memory is the output plus O(N).

    Parameters
    ----------
    signal, fs, frequencies, omega0, normalization, padding, workers
        As in :func:`cwt`.
    dtype : {numpy.float32, numpy.float64}, optional
        Output precision (default float32, computed from complex64 transforms; float64 uses
        complex128).  Ignored when ``out`` is given (its dtype decides).
    out : numpy.ndarray, optional
        Preallocated C-contiguous float32 or float64 array of shape (n_frequencies, n_samples)
        to fill and return.

    Returns
    -------
    CWTResult
        As :func:`cwt` with ``coefficients`` the real modulus ``|W|`` (``out`` when given).

    Examples
    --------
    >>> import numpy as np
    >>> fs = 1000.0
    >>> x = 2.0 * np.cos(2 * np.pi * 50.0 * np.arange(2000) / fs)
    >>> mag = cwt_magnitude(x, fs, [10.0, 50.0, 250.0]).coefficients
    >>> mag.dtype, np.round(mag[:, 1000], 4).tolist()
    (dtype('float32'), [0.0, 2.0, 0.0])
    """
    if out is not None:
        dtype = out.dtype
    try:
        rdt = np.dtype(dtype)
    except TypeError:
        raise InputError("dtype", dtype, "numpy.float32 or numpy.float64") from None
    if rdt not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise InputError("dtype", dtype, "numpy.float32 or numpy.float64")
    plan = _make_plan(signal, fs, frequencies, omega0, normalization, padding, rdt, workers)
    shape = (plan.freqs.size, plan.n)
    if out is None:
        out = np.empty(shape, dtype=rdt)
    elif out.shape != shape or not out.flags.c_contiguous or not out.flags.writeable:
        raise InputError(
            "out",
            f"array of shape {out.shape}",
            f"a writeable C-contiguous float array of shape {shape}",
        )
    for j in range(plan.freqs.size):
        plan.row_into(j, out[j])
    return CWTResult(out, plan.freqs.copy(), plan.coi.copy(), _metadata(plan))


def _metadata(plan: _Plan) -> dict:
    return {
        "fs": plan.fs,
        "omega0": plan.omega0,
        "fc": plan.omega0 / (2.0 * np.pi),
        "scales": plan.scales.copy(),
        "scale_unit": "samples",
        "bandwidth_hz": plan.freqs / plan.omega0,
        "normalization": plan.normalization,
        "padding": plan.padding,
        "padded_length": int(plan.m),
        "truncation_eps": plan.eps,
        "truncation_halfwidth": plan.h,
        "coi_unit": "samples",
        "wavelet": "analytic Morlet psi(t) = sqrt(2/pi) exp(i omega0 t - t^2/2)",
    }


def _energies(plan: _Plan, inner: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """Energies ``sum |W|^2 / fs`` per row over the record and, when ``inner``, outside the
    cone of influence, computed together (the inner one is the full one minus edge strips)."""
    n, m = plan.n, plan.m
    nf = plan.freqs.size
    full = np.empty(nf)
    inn = np.empty(nf) if inner else None
    full_rows = []
    for j in range(nf):
        c = int(plan.coi[j])
        big_l = int(plan.half_support[j])
        pad_strips = []
        if plan.padding == "zero":
            if not plan.local_ok(j):
                full_rows.append(j)  # W then spreads over the whole padding
                continue
            # W vanishes on the zero padding except within L samples of the record
            pad_strips = [(n, min(n + big_l, m - big_l)), (max(m - big_l, n), m)]
        edge_strips = [(0, c), (n - c, n)] if inner and 2 * c < n else []
        if edge_strips and plan.local_ok(j) and c + 2 * big_l >= n:
            full_rows.append(j)  # the short-convolution fallback would wrap
            continue
        pad_parts = [plan.strip_energy(j, a, b) for a, b in pad_strips]
        edge_parts = [plan.strip_energy(j, a, b) for a, b in edge_strips]
        if any(p is None for p in pad_parts + edge_parts):
            full_rows.append(j)
            continue
        e = plan.circle_energy(j)
        if plan.padding == "symmetric":
            e *= 0.5
        full[j] = max(e - sum(pad_parts), 0.0)
        if inner:
            inn[j] = max(full[j] - sum(edge_parts), 0.0) if 2 * c < n else 0.0
    for idx, rows in plan.rows(full_rows, batch=max(1, (1 << 21) // plan.m)):
        for r, j in enumerate(idx):
            p = rows[r].real ** 2 + rows[r].imag ** 2
            c = int(plan.coi[j])
            full[j] = float(np.sum(p[:n]))
            if inner:
                inn[j] = float(np.sum(p[c : n - c])) if 2 * c < n else 0.0
    return full / plan.fs, (inn / plan.fs if inner else None)


def scalogram(
    signal,
    fs: float,
    frequencies,
    *,
    inner: bool = False,
    omega0: float = 6.0,
    normalization: str = "l1",
    padding: str = "symmetric",
    workers: int | None = None,
) -> np.ndarray:
    r"""Scalogram (seed eq. 19) or inner scalogram (eq. 20) without building the CWT matrix.

    ``scal[j] = sqrt(sum_n |W[j, n]|**2 / fs)`` over the N samples of the record (or, with
    ``inner=True``, over ``coi_j <= n < N - coi_j``), where ``W`` is the matrix that
    :func:`cwt` returns for the same ``omega0``, ``normalization`` and ``padding`` with
    ``dtype=numpy.complex128``; computed from the spectrum by Parseval and short edge
    convolutions (module notes), in float64, memory O(N + n_frequencies).

    Parameters
    ----------
    signal : array_like, shape (n_samples,)
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    frequencies : array_like, shape (n_frequencies,)
        Analysis frequencies (Hz) in (0, fs/2).
    inner : bool, optional
        Restrict the time integral to samples outside the cone of influence (eq. 20).  Rows
        whose cone covers the whole record give 0.
    omega0, normalization, padding, workers
        As in :func:`cwt`.

    Returns
    -------
    numpy.ndarray, float64, shape (n_frequencies,)
        Scalogram (unit of the signal times s**0.5 for ``"l1"``).

    Examples
    --------
    >>> import numpy as np
    >>> fs = 100.0
    >>> x = np.cos(2 * np.pi * 5.0 * np.arange(1000) / fs)
    >>> f = np.array([2.5, 5.0, 10.0])
    >>> int(np.argmax(scalogram(x, fs, f, inner=True)))
    1
    """
    plan = _make_plan(signal, fs, frequencies, omega0, normalization, padding, np.float64, workers)
    full, inn = _energies(plan, bool(inner))
    return np.sqrt(inn if inner else full)


def scalograms(
    signal,
    fs: float,
    frequencies,
    *,
    omega0: float = 6.0,
    normalization: str = "l1",
    padding: str = "symmetric",
    workers: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Scalogram and inner scalogram together, sharing the Parseval sums (see :func:`scalogram`).

    Parameters
    ----------
    signal : array_like, shape (n_samples,)
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    frequencies : array_like, shape (n_frequencies,)
        Analysis frequencies (Hz) in (0, fs/2).
    omega0, normalization, padding, workers
        As in :func:`cwt`.

    Returns
    -------
    full, inner : numpy.ndarray, float64, shape (n_frequencies,)
        Seed eqs. (19) and (20) (unit of the signal times s**0.5 for ``"l1"``).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.cos(2 * np.pi * 5.0 * np.arange(1000) / 100.0)
    >>> full, inner = scalograms(x, 100.0, [2.5, 5.0, 10.0])
    >>> bool(np.all(inner <= full))
    True
    """
    plan = _make_plan(signal, fs, frequencies, omega0, normalization, padding, np.float64, workers)
    full, inn = _energies(plan, True)
    return np.sqrt(full), np.sqrt(inn)


def inner_scalogram(signal, fs: float, frequencies, **kwargs) -> np.ndarray:
    """Inner scalogram (seed eq. 20): ``scalogram(..., inner=True)``.

    Parameters
    ----------
    signal : array_like
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    frequencies : array_like
        Analysis frequencies (Hz) in (0, fs/2).
    **kwargs
        ``omega0``, ``normalization``, ``padding``, ``workers`` as in :func:`scalogram`.

    Returns
    -------
    numpy.ndarray, float64, shape (n_frequencies,)
        Inner scalogram (unit of the signal times s**0.5 for ``"l1"``).
    """
    return scalogram(signal, fs, frequencies, inner=True, **kwargs)


def cwt_binned(
    signal,
    fs: float,
    frequencies,
    n_bins: int,
    *,
    statistic: str = "max",
    omega0: float = 6.0,
    normalization: str = "l1",
    padding: str = "symmetric",
    dtype=np.complex64,
    workers: int | None = None,
) -> BinnedCWT:
    """Time-binned ``|W|`` map of bounded size for plotting long records.

    Rows are computed in batches and reduced at once, so memory is O(batch * N + n_frequencies *
    n_bins) and the full matrix is never held.

    Parameters
    ----------
    signal : array_like, shape (n_samples,)
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    frequencies : array_like, shape (n_frequencies,)
        Analysis frequencies (Hz) in (0, fs/2).
    n_bins : int
        Number of time bins, 1 <= n_bins <= n_samples; bin ``i`` covers samples
        ``floor(i*N/n_bins) <= n < floor((i+1)*N/n_bins)``.
    statistic : {"max", "rms"}, optional
        Maximum of ``|W|`` or root-mean-square of ``|W|`` in each bin.
    omega0, normalization, padding, dtype, workers
        As in :func:`cwt`.

    Returns
    -------
    BinnedCWT
        ``values`` (n_frequencies, n_bins), ``frequencies`` (Hz), ``times`` (bin centres, s),
        ``bin_edges`` (samples), ``coi`` (samples).
    """
    dt = _check_dtype(dtype)
    _check_choice("statistic", statistic, ("max", "rms"))
    real = np.float32 if dt == np.complex64 else np.float64
    plan = _make_plan(signal, fs, frequencies, omega0, normalization, padding, real, workers)
    n = plan.n
    if not isinstance(n_bins, int | np.integer) or not 1 <= n_bins <= n:
        raise InputError("n_bins", n_bins, f"an integer in [1, n_samples = {n}]")
    edges = (np.arange(n_bins + 1, dtype=np.int64) * n) // n_bins
    counts = np.diff(edges).astype(np.float64)
    values = np.empty((plan.freqs.size, n_bins))
    reduce: Callable = np.maximum.reduceat if statistic == "max" else np.add.reduceat
    for idx, rows in plan.rows(np.arange(plan.freqs.size)):
        p = rows.real**2 + rows.imag**2
        red = reduce(p, edges[:-1], axis=1)
        if statistic == "rms":
            red = red / counts
        values[idx] = np.sqrt(red)
    times = 0.5 * (edges[:-1] + edges[1:] - 1) / plan.fs
    return BinnedCWT(values, plan.freqs.copy(), times, edges, plan.coi.copy())
