"""Compiled kernels of the band-limited inverse DFT behind :mod:`rubrotor.analysis.wavelet`.

A row of the wavelet transform is ``W[m] = sum_k Z[k] * exp(2j*pi*k*m/M)`` over a short band of
integer bins ``k_lo <= k <= k_hi`` of a long circle ``M``.  Writing ``m = P*q + r`` with
``M = P*L`` (``0 <= q < L``, ``0 <= r < P``)::

    W[P*q + r] = sum_{k'=0}^{L-1} A[k', r] * exp(2j*pi*k'*q/L),
    A[k', r]   = sum_{k in band, k = k' mod L} Z[k] * exp(2j*pi*k*r/M)

so a row is one batch of inverse FFTs of the cache-sized length ``L`` along the first axis of the
(L, P) array ``A`` built by :func:`fold_band`, whose result read in C order is ``W`` itself.
Folding is exact (each ``A[k', r]`` sums the at most ``ceil(B/L)`` band bins congruent to ``k'``).

The twiddle of residue ``r`` is ``exp(2j*pi*k*(mult*r + add)/den)``; the symmetric extension
(period ``2N``) uses ``mult = 2, add = 1, den = 4N`` so that the phase ``exp(1j*pi*k/(2N))`` of
its spectrum is included.  Twiddles come from exact integer phase indices and a two-level table
``exp(2j*pi*i/den) = lo[i % S] * hi[i // S]`` every :data:`RESEED` bins and a complex recurrence
in between (error a few tens of float64 ulps).

Only numpy, numba and math are imported here.
"""

import math

import numpy as np
from numba import njit, prange

__all__ = [
    "twiddle_tables",
    "filter_gain",
    "band_values",
    "fold_band",
    "scatter_abs",
    "scatter_complex",
    "band_energy",
    "strip_energy",
]

TABLE_BITS = 11  # low table of 2**11 entries
RESEED = 16  # twiddle recurrence length between exact table values


def twiddle_tables(den: int) -> tuple[np.ndarray, np.ndarray]:
    """Tables ``lo[i] = exp(2j*pi*i/den)`` (i < 2**TABLE_BITS) and ``hi[i] = lo[1]**(i*2**bits)``."""
    size = 1 << TABLE_BITS
    i = np.arange(size, dtype=np.float64)
    lo = np.exp(2j * np.pi * i / den)
    hi = np.exp(2j * np.pi * (np.arange(den // size + 1, dtype=np.float64) * size) / den)
    return lo, hi


@njit(cache=True, inline="always")
def filter_gain(k, w, omega0, gain, h, m):
    """Truncated Gaussian filter ``gain * exp(-(w*k - omega0)**2/2)`` at integer bin ``k``.

    Zero where ``|w*k - omega0| > h``; halved at the Nyquist bin ``2k = m`` of an even circle.
    """
    arg = w * k - omega0
    if abs(arg) > h:
        return 0.0
    g = gain * math.exp(-0.5 * arg * arg)
    if 2 * k == m:
        g *= 0.5
    return g


@njit(cache=True, parallel=True)
def band_values(spec, k_lo, w, omega0, gain, h, m, z):
    """``z[b] = Y[k] * G(k)`` for ``k = k_lo + b``, ``Y[k] = spec[k]`` (k >= 0) or
    ``conj(spec[-k])`` (k < 0), ``G`` from :func:`filter_gain`."""
    nb = z.size
    chunk = 16384
    for c in prange((nb + chunk - 1) // chunk):
        for b in range(c * chunk, min(nb, (c + 1) * chunk)):
            k = k_lo + b
            g = filter_gain(k, w, omega0, gain, h, m)
            z[b] = spec[k] * g if k >= 0 else spec[-k].conjugate() * g


@njit(cache=True, inline="always")
def _next_twiddle(t, step, idx, jump, den, left, lo, hi):
    """Advance the twiddle ``t`` by ``step``; every ``RESEED`` bins take the exact value from the
    two-level table at phase index ``idx + jump`` (mod ``den``) instead. Returns
    ``(t, idx, left)``."""
    left -= 1
    if left == 0:
        idx += jump
        if idx >= den:
            idx -= den
        return lo[idx & ((1 << TABLE_BITS) - 1)] * hi[idx >> TABLE_BITS], idx, RESEED
    return t * step, idx, left


@njit(cache=True, parallel=True)
def fold_band(z, k_lo, twiddle, tables, work, chunk):
    """Fill ``work[r, k'] = sum_{k = k' mod L} z[k - k_lo] * exp(2j*pi*k*(mult*r + add)/den)``.

    Parameters
    ----------
    z : complex128[B]
        Band values (spectrum times filter) for bins ``k_lo .. k_lo + B - 1``.
    k_lo : int
        First bin of the band (may be negative, ``|k_lo| < den``).
    twiddle : tuple of int ``(mult, add, den)``
        Twiddle of residue r is ``exp(2j*pi*k*(mult*r + add)/den)``.
    tables : tuple ``(lo, hi)`` of complex128 arrays
        Tables from :func:`twiddle_tables` for ``den``.
    work : complex64 or complex128 [R, L]
        Output (overwritten), one row per residue r = 0..R-1.
    chunk : int
        Columns of ``work`` per parallel task.
    """
    mult, add, den = twiddle
    lo, hi = tables
    n_res, length = work.shape
    k_hi = k_lo + z.size - 1
    mask = (1 << TABLE_BITS) - 1
    n_chunks = (length + chunk - 1) // chunk
    for task in prange(n_res * n_chunks):
        r = task // n_chunks
        kp0 = (task % n_chunks) * chunk
        kp1 = min(kp0 + chunk, length)
        row = work[r]
        for kp in range(kp0, kp1):
            row[kp] = 0.0
        cr = (mult * r + add) % den
        step = lo[cr & mask] * hi[cr >> TABLE_BITS]
        jump = (RESEED * cr) % den
        # bins k = kp + u*L of the band for kp0 <= kp < kp1, layer by layer
        u = (k_lo - kp1 + 1) // length
        while kp0 + u * length <= k_hi:
            k0 = max(kp0 + u * length, k_lo)
            k1 = min(kp1 - 1 + u * length, k_hi)
            if k0 <= k1:
                idx = ((k0 % den) * cr) % den
                t = lo[idx & mask] * hi[idx >> TABLE_BITS]
                left = RESEED
                for k in range(k0, k1 + 1):
                    row[k - u * length] += z[k - k_lo] * t
                    t, idx, left = _next_twiddle(t, step, idx, jump, den, left, lo, hi)
            u += 1


@njit(cache=True, parallel=True)
def scatter_abs(res, period, n, mirror, out):
    """``out[P*q + r] = |res[r, q]|`` for ``P*q + r < n`` (``P = period``); with ``mirror`` the
    positions ``n <= m < 2n`` go to ``out[2n - 1 - m]``.  Tiled transpose, 8 columns a tile."""
    n_res, length = res.shape
    tile = 8
    for t in prange((length + tile - 1) // tile):
        for q in range(t * tile, min(length, (t + 1) * tile)):
            base = period * q
            for r in range(n_res):
                v = res[r, q]
                a = math.sqrt(v.real * v.real + v.imag * v.imag)
                m = base + r
                if m < n:
                    out[m] = a
                elif mirror:
                    out[2 * n - 1 - m] = a


@njit(cache=True, parallel=True)
def scatter_complex(res, period, n, mirror, out):
    """As :func:`scatter_abs` with the complex value (its conjugate at mirrored positions)."""
    n_res, length = res.shape
    tile = 8
    for t in prange((length + tile - 1) // tile):
        for q in range(t * tile, min(length, (t + 1) * tile)):
            base = period * q
            for r in range(n_res):
                v = res[r, q]
                m = base + r
                if m < n:
                    out[m] = v
                elif mirror:
                    out[2 * n - 1 - m] = v.conjugate()


@njit(cache=True, parallel=True)
def band_energy(spec, k_lo, k_hi, top, filt):
    """Parseval sum ``sum_k |spec[|k|]|**2 * G(k)**2`` over ``k_lo <= k <= k_hi``, ``|k| <= top``.

    ``G`` from :func:`filter_gain` with ``filt = (w, omega0, gain, h, m)``; ``spec`` is the (real or complex) spectrum. The
    squared Gaussian is advanced by its exact two-term recurrence
    (``G2[k+1] = G2[k] r[k]``, ``r[k+1] = r[k] exp(-2 w^2)``) and re-seeded with ``exp`` at the
    start of every block of 4096 bins, so the rounding stays below 1e-12 relative; blocks run in
    parallel.
    """
    w, omega0, gain, h, m = filt
    # bins where the truncated Gaussian is non-zero: |w k - omega0| <= h
    a = max(k_lo, -top, int(math.ceil((omega0 - h) / w)))
    b = min(k_hi, top, int(math.floor((omega0 + h) / w)))
    if b < a:
        return 0.0
    block = 4096
    nblk = (b - a) // block + 1
    q = math.exp(-2.0 * w * w)
    g2 = gain * gain
    parts = np.zeros(nblk)
    for i in prange(nblk):
        k0 = a + i * block
        k1 = min(b, k0 + block - 1)
        arg = w * k0 - omega0
        e = g2 * math.exp(-arg * arg)
        r = math.exp(-(2.0 * arg * w + w * w))
        acc = 0.0
        for k in range(k0, k1 + 1):
            v = spec[abs(k)]
            acc += (v.real * v.real + v.imag * v.imag) * e
            e *= r
            r *= q
        parts[i] = acc
    total = parts.sum()
    if m % 2 == 0:
        kn = m // 2
        for kk in (kn, -kn):
            if a <= kk <= b:
                arg = w * kk - omega0
                # the Nyquist bin carries half the gain: remove 3/4 of its squared weight
                v = spec[abs(kk)]
                total -= 0.75 * (v.real * v.real + v.imag * v.imag) * g2 * math.exp(-arg * arg)
    return total


@njit(cache=True, parallel=True)
def strip_energy(z, k_lo, mult, add, den, lo, hi, positions):
    """``sum_p |W[p]|**2`` over circle ``positions`` by direct band sums (float64).

    ``W[p] = sum_b z[b] * exp(2j*pi*k*(mult*p + add)/den)``, ``k = k_lo + b``: the definition of
    a row (``z`` from :func:`band_values`, twiddle as in :func:`fold_band`); cost
    O(len(positions) * band) instead of a whole row.
    """
    mask = (1 << TABLE_BITS) - 1
    acc = np.zeros(positions.size)
    for i in prange(positions.size):
        c = (mult * positions[i] + add) % den
        step = lo[c & mask] * hi[c >> TABLE_BITS]
        jump = (RESEED * c) % den
        idx = ((k_lo % den) * c) % den
        t = lo[idx & mask] * hi[idx >> TABLE_BITS]
        left = RESEED
        total = 0j
        for b in range(z.size):
            total += z[b] * t
            t, idx, left = _next_twiddle(t, step, idx, jump, den, left, lo, hi)
        acc[i] = total.real * total.real + total.imag * total.imag
    return acc.sum()
