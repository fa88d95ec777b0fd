"""Compiled complex banded LU (partial pivoting) and the frequency sweeps built on it.

Matrices are in LAPACK's band storage, transposed so that a matrix column is contiguous in
memory: an ``n x n`` matrix with ``kl`` sub- and ``ku`` super-diagonals is held in ``ab`` of
shape ``(n, 2 kl + ku + 1)`` with ``ab[j, kl + ku + i - j] = a[i, j]``; the first ``kl``
entries of each column take the fill-in of pivoting (as LAPACK's ``zgbtrf``). The sweep kernels assemble the dynamic stiffness of a linear rotor
at each speed from its real band parts and support coefficients (:class:`BandParts`), so a
whole sweep is one call with no Python work per speed. Units are whatever the caller's
matrices carry (SI in rubrotor).
"""

from collections import namedtuple

import numpy as np
from numba import njit, prange

from rubrotor.core.bandtypes import BandParts, Refined, SparseRows, Starts
from rubrotor.core.status import OK, SINGULAR  # SINGULAR: a zero pivot at this speed

__all__ = [
    "BandParts",
    "OK",
    "SINGULAR",
    "band_factor",
    "band_matmul",
    "band_solve",
    "band_solve_transposed",
    "newton_pairs",
    "Refined",
    "SparseRows",
    "Starts",
    "refine_eigenpairs",
    "ritz_vectors",
    "response_sweep",
    "unbalance_sweep",
    "frequency_sweep",
]


_Work = namedtuple("_Work", "ab ipiv u")


@njit(cache=True, inline="always")
def _abs1(z):
    """``|Re z| + |Im z|``: LAPACK's cheap pivot magnitude (no square root)."""
    return abs(z.real) + abs(z.imag)


@njit(cache=True)
def band_factor(ab, kl, ku, ipiv):
    """LU-factorise ``ab`` in place with partial pivoting (``zgbtf2``); return OK or SINGULAR."""
    n = ab.shape[0]
    kv = kl + ku
    ju = 0
    for j in range(n):
        km = min(kl, n - 1 - j)
        jp = 0
        best = _abs1(ab[j, kv])
        for i in range(1, km + 1):
            a = _abs1(ab[j, kv + i])
            if a > best:
                best, jp = a, i
        ipiv[j] = j + jp
        if best == 0.0:
            return SINGULAR
        ju = max(ju, min(j + ku + jp, n - 1))
        if jp != 0:
            for c in range(j, ju + 1):
                t = ab[c, kv + jp + j - c]
                ab[c, kv + jp + j - c] = ab[c, kv + j - c]
                ab[c, kv + j - c] = t
        piv = ab[j, kv]
        for i in range(1, km + 1):
            ab[j, kv + i] /= piv
        for c in range(j + 1, ju + 1):
            u = ab[c, kv + j - c]
            if u != 0.0:
                for i in range(1, km + 1):
                    ab[c, kv + j + i - c] -= ab[j, kv + i] * u
    return OK


@njit(cache=True)
def band_solve(ab, kl, ku, ipiv, b):
    """Solve ``a x = b`` in place in ``b`` from the factors of :func:`band_factor`."""
    n = ab.shape[0]
    kv = kl + ku
    for j in range(n):
        p = ipiv[j]
        if p != j:
            t = b[p]
            b[p] = b[j]
            b[j] = t
        km = min(kl, n - 1 - j)
        for i in range(1, km + 1):
            b[j + i] -= ab[j, kv + i] * b[j]
    for j in range(n - 1, -1, -1):
        b[j] /= ab[j, kv]
        for i in range(1, min(kv, j) + 1):
            b[j - i] -= ab[j, kv - i] * b[j]


@njit(cache=True)
def _assemble(parts, s, omega, lam, ab):
    """``ab <- lam^2 M + lam (C + omega G + C_s) + K + K_s`` at sweep index ``s``.

    ``omega`` is the spin speed (rad/s), ``lam`` the complex frequency (1/s): ``i omega`` for
    the synchronous response, an eigenvalue for the modal problem.
    """
    kl, ku = parts.kl, parts.ku
    lam2 = lam * lam
    for j in range(ab.shape[0]):
        for r in range(kl):
            ab[j, r] = 0.0
        for r in range(kl + ku + 1):
            ab[j, kl + r] = (
                lam2 * parts.m[j, r] + lam * (parts.c[j, r] + omega * parts.g[j, r]) + parts.k[j, r]
            )
    for p in range(parts.sup_row.size):
        i, j = parts.sup_row[p], parts.sup_col[p]
        ab[j, kl + ku + i - j] += parts.sup_k[s, p] + lam * parts.sup_c[s, p]


@njit(cache=True, parallel=True)
def response_sweep(parts, spins, freqs, power, rhs, out_rows):
    """Forced response at every sweep index: ``out[s] = R Q`` with
    ``(K + K_s - w^2 M + i w (C + C_s + W G)) Q = w^power rhs`` (``W = spins[s]`` the spin,
    ``w = freqs[s]`` the excitation frequency, both rad/s; the supports' entries at index ``s``
    when ``parts`` holds one row per index, else at 0).

    The synchronous unbalance response is ``freqs = spins`` and ``power = 2``; the forced
    response at one spin ``power = 0``. Indices are shared among the numba threads in blocks
    (each with its own work arrays). Returns ``(out, status, index)``: ``out`` of shape
    ``(S, R)``; ``status`` OK, or SINGULAR with the sweep ``index`` of the first singular
    matrix.
    """
    n = parts.m.shape[0]
    kl, ku = parts.kl, parts.ku
    ns = freqs.size
    per_index = parts.sup_k.shape[0] > 1
    out = np.zeros((ns, out_rows.shape[0]), np.complex128)
    bad = np.zeros(ns, np.bool_)
    nblk = min(ns, 64)
    for blk in prange(nblk):
        ab = np.empty((n, 2 * kl + ku + 1), np.complex128)
        ipiv = np.empty(n, np.int64)
        x = np.empty(n, np.complex128)
        for s in range(blk * ns // nblk, (blk + 1) * ns // nblk):
            w = freqs[s]
            _assemble(parts, s if per_index else 0, spins[s], 1j * w, ab)
            if band_factor(ab, kl, ku, ipiv) != OK:
                bad[s] = True
                continue
            for i in range(n):
                xi = rhs[i]
                for _ in range(power):
                    xi = xi * w
                x[i] = xi
            band_solve(ab, kl, ku, ipiv, x)
            for r in range(out_rows.shape[0]):
                acc = 0j
                for i in range(n):
                    acc += out_rows[r, i] * x[i]
                out[s, r] = acc
    for s in range(ns):
        if bad[s]:
            return out, SINGULAR, s
    return out, OK, -1


def unbalance_sweep(parts, speeds, rhs, out_rows):
    """Synchronous response at every speed (:func:`response_sweep` with the spin and frequency
    ``speeds[s]``, rad/s, and the force ``W^2 rhs``)."""
    speeds = np.ascontiguousarray(speeds, dtype=np.float64)
    return response_sweep(parts, speeds, speeds, 2, rhs, out_rows)


def frequency_sweep(parts, spin, freqs, rhs, out_rows):
    """Forced response to ``rhs`` at every excitation frequency ``freqs`` (rad/s) at one
    ``spin`` (rad/s), the supports at sweep index 0 (:func:`response_sweep`)."""
    freqs = np.ascontiguousarray(freqs, dtype=np.float64)
    return response_sweep(parts, np.full(freqs.size, float(spin)), freqs, 0, rhs, out_rows)


@njit(cache=True)
def band_matmul(band, ku, x, out):
    """``out <- a @ x`` for real ``a`` in compact band storage (``a[i, j]`` at ``[j, ku + i - j]``)
    and a real block ``x`` (n, k)."""
    n, k = x.shape
    out[:] = 0.0
    for j in range(n):
        for r in range(max(0, ku - j), min(band.shape[1], ku + n - j)):
            a = band[j, r]
            if a != 0.0:
                i = j + r - ku
                for c in range(k):
                    out[i, c] += a * x[j, c]


@njit(cache=True)
def _derivative_apply(parts, s, omega, lam, x, y):
    """``y <- T'(lam) x = (2 lam M + C + omega G + C_s) x`` at sweep index ``s`` (one pass over
    the bands)."""
    n = parts.m.shape[0]
    ku = parts.ku
    y[:] = 0.0
    two_lam = 2.0 * lam
    for j in range(n):
        xj = x[j]
        for r in range(max(0, ku - j), min(parts.m.shape[1], ku + n - j)):
            coef = two_lam * parts.m[j, r] + (parts.c[j, r] + omega * parts.g[j, r])
            y[j + r - ku] += coef * xj
    for p in range(parts.sup_row.size):
        y[parts.sup_row[p]] += parts.sup_c[s, p] * x[parts.sup_col[p]]


@njit(cache=True, parallel=True)
def refine_eigenpairs(parts, speeds, starts, tol, max_iter, out_rows):
    """Newton's method on ``T(lam) x = 0``, ``c^H x = 1`` for the quadratic eigenproblem
    ``T(lam) = lam^2 M + lam (C + W G + C_s) + K + K_s`` (``W = speeds[s]``, rad/s).

    Each step solves ``T(lam) u = T'(lam) x`` by banded LU and sets ``lam <- lam - 1/(c^H u)``,
    ``x <- u / (c^H u)`` (quadratic convergence; ``c = x0 / |x0|^2``). Starts from
    ``starts.lam[s, j]`` (1/s) and ``starts.vec[s, j]`` (free DOFs); stops when the step, or
    the next error predicted from the last two steps, is below ``tol |lam|``. Speeds are shared
    among the numba threads in blocks.

    Returns :class:`Refined`: eigenvalues ``(S, n)``; ``out_rows`` (:class:`SparseRows`) applied
    to ``x``, of shape ``(S, n, R)``;
    Newton steps taken, negative where ``max_iter`` passed without convergence.
    """
    ns, nm = starts.lam.shape
    shapes = np.zeros((ns, nm, out_rows.idx.shape[0]), np.complex128)
    out = Refined(starts.lam.copy(), shapes, np.zeros((ns, nm), np.int64))
    nblk = min(ns, 64)
    for blk in prange(nblk):
        span = (blk * ns // nblk, (blk + 1) * ns // nblk)
        _refine_block(parts, speeds, starts, (tol, max_iter), out_rows, out, span)
    return out


@njit(cache=True)
def _refine_block(parts, speeds, starts, stop, out_rows, out, span):
    """Newton on the speeds ``s0 <= s < s1`` (``span``) of :func:`refine_eigenpairs` (own work
    arrays); ``stop = (tol, max_iter)``."""
    s0, s1 = span
    n = parts.m.shape[0]
    work = _Work(
        np.empty((n, 2 * parts.kl + parts.ku + 1), np.complex128),
        np.empty(n, np.int64),
        np.empty(n, np.complex128),
    )
    for s in range(s0, s1):
        for j in range(starts.lam.shape[1]):
            x = _newton(parts, s, speeds[s], starts, j, stop, work, out)
            for r in range(out_rows.idx.shape[0]):
                acc = 0j
                for k in range(out_rows.idx.shape[1]):
                    acc += out_rows.val[r, k] * x[out_rows.idx[r, k]]
                out.shapes[s, j, r] = acc


@njit(cache=True)
def _newton(parts, s, w, starts, j, stop, work, out):
    """Newton iterations of :func:`refine_eigenpairs` for mode ``j`` at sweep index ``s`` (spin
    ``w``, rad/s) until a step is below ``tol |lam|`` or ``max_iter`` passed (``stop = (tol,
    max_iter)``); writes ``out.lam``, ``out.steps`` and returns the eigenvector."""
    tol, max_iter = stop
    x = starts.vec[s, j].copy()
    lk = starts.lam[s, j]
    out.steps[s, j] = -max_iter
    norm2 = np.vdot(x, x).real
    if not norm2 > 0.0:  # no start vector: not converged (no division by zero in a thread)
        out.lam[s, j] = lk
        return x
    c = x / norm2
    last = 0.0
    for it in range(max_iter):
        _assemble(parts, s, w, lk, work.ab)
        if band_factor(work.ab, parts.kl, parts.ku, work.ipiv) != OK:
            out.steps[s, j] = it + 1  # lk is an eigenvalue to working precision
            break
        _derivative_apply(parts, s, w, lk, x, work.u)
        band_solve(work.ab, parts.kl, parts.ku, work.ipiv, work.u)
        d = np.vdot(c, work.u)
        if d == 0.0:  # the start has no component along the eigenvector: give up
            break
        step = -1.0 / d
        lk = lk + step
        x = work.u / d
        size = abs(step)
        # quadratic convergence: the next error is ~ size^3 / last^2
        if size <= tol * abs(lk) or (
            it > 0 and size < 1e-3 * last and size**3 <= tol * 1e-3 * abs(lk) * last**2
        ):
            out.steps[s, j] = it + 1
            break
        last = size
    out.lam[s, j] = lk
    return x


@njit(cache=True)
def ritz_vectors(mass, damping, stiffness, lam):
    """Null vectors of small dense quadratic eigenproblems at known eigenvalues.

    For every speed ``s`` and mode ``j`` solves ``T y = r_j`` (a fixed right-hand side that
    differs between modes, so that equal eigenvalues get independent vectors) with
    ``T = lam[s, j]^2 mass + lam[s, j] damping[s] + stiffness[s]`` (``mass`` (m, m),
    ``damping``, ``stiffness`` (S, m, m), consistent units; ``lam`` (S, n) in 1/s, NaN to skip)
    by LU with partial pivoting: ``lam`` being an eigenvalue to rounding, ``T`` is singular to
    rounding and ``y`` is its null vector (one step of inverse iteration). Returns ``y`` (S, n, m)
    normalised to unit length; a pivot below ``1e-16`` of the largest entry is raised to it (an
    exactly singular ``T``: ``y`` is then a null vector exactly)."""
    ns, nm = lam.shape
    m = mass.shape[0]
    out = np.zeros((ns, nm, m), np.complex128)
    t = np.empty((m, m), np.complex128)
    y = np.empty(m, np.complex128)
    for s in range(ns):
        for j in range(nm):
            lk = lam[s, j]
            if not (np.isfinite(lk.real) and np.isfinite(lk.imag)):
                continue
            size = 0.0
            for a in range(m):
                y[a] = np.cos(0.7 * a * (j + 1) + j) + 1j * np.sin(1.3 * a + 0.4 * j)
                for b in range(m):
                    t[a, b] = lk * lk * mass[a, b] + lk * damping[s, a, b] + stiffness[s, a, b]
                    size = max(size, _abs1(t[a, b]))
            _dense_solve(t, y, 1e-16 * size if size > 0.0 else 1.0)
            big = 0.0
            for a in range(m):
                big = max(big, _abs1(y[a]))
            y /= big
            out[s, j] = y / np.sqrt(np.vdot(y, y).real)
    return out


@njit(cache=True)
def _dense_solve(t, y, floor):
    """``y <- t^-1 y`` by Gaussian elimination with partial pivoting (overwrites ``t``); a pivot
    below ``floor`` (an exactly singular ``t``) is replaced by ``floor``."""
    m = t.shape[0]
    for k in range(m):
        p = k
        for i in range(k + 1, m):
            if _abs1(t[i, k]) > _abs1(t[p, k]):
                p = i
        if p != k:
            for c in range(m):
                tmp = t[k, c]
                t[k, c] = t[p, c]
                t[p, c] = tmp
            tmp = y[k]
            y[k] = y[p]
            y[p] = tmp
        if _abs1(t[k, k]) < floor:
            t[k, k] = floor
        inv = 1.0 / t[k, k]
        for i in range(k + 1, m):
            f = t[i, k] * inv
            if f != 0.0:
                for c in range(k + 1, m):
                    t[i, c] -= f * t[k, c]
                y[i] -= f * y[k]
    for k in range(m - 1, -1, -1):
        acc = y[k]
        for c in range(k + 1, m):
            acc -= t[k, c] * y[c]
        y[k] = acc / t[k, k]


@njit(cache=True)
def band_solve_transposed(ab, kl, ku, ipiv, b):
    """Solve ``a^T x = b`` (transpose, not conjugate) in place in ``b`` from the factors of
    :func:`band_factor` (LAPACK ``zgbtrs`` with ``'T'``): ``U^T`` forward, then ``L^T`` backward
    with the row interchanges undone in reverse order."""
    n = ab.shape[0]
    kv = kl + ku
    for j in range(n):
        acc = b[j]
        for i in range(1, min(kv, j) + 1):
            acc -= ab[j, kv - i] * b[j - i]
        b[j] = acc / ab[j, kv]
    for j in range(n - 2, -1, -1):
        acc = b[j]
        for i in range(1, min(kl, n - 1 - j) + 1):
            acc -= ab[j, kv + i] * b[j + i]
        b[j] = acc
        p = ipiv[j]
        if p != j:
            t = b[p]
            b[p] = b[j]
            b[j] = t


@njit(cache=True)
def newton_pairs(parts, parts_t, omega, lam, right, left):
    """One Newton step of :func:`refine_eigenpairs` per mode for its right AND left vectors
    with one banded LU: ``T(lam) u = T'(lam) x`` and ``T(lam)^T v = T'(lam)^T y`` (``parts_t``
    the transposed problem's bands, ``omega`` the speed, rad/s). ``right``, ``left`` (k, n) are
    overwritten by the new vectors (scaled as the Newton iteration scales them); returns the
    new eigenvalues (1/s) of the right problem. A mode whose matrix is singular at ``lam``
    (an eigenvalue to working precision) keeps its start."""
    n = parts.m.shape[0]
    kl, ku = parts.kl, parts.ku
    ab = np.empty((n, 2 * kl + ku + 1), np.complex128)
    ipiv = np.empty(n, np.int64)
    w = np.empty(n, np.complex128)
    out = lam.copy()
    for j in range(lam.size):
        lk = lam[j]
        _assemble(parts, 0, omega, lk, ab)
        if band_factor(ab, kl, ku, ipiv) != OK:
            continue
        x = right[j].copy()
        _derivative_apply(parts, 0, omega, lk, x, w)
        band_solve(ab, kl, ku, ipiv, w)
        d = np.vdot(x, w) / np.vdot(x, x).real
        out[j] = lk - 1.0 / d
        right[j] = w / d
        y = left[j].copy()
        _derivative_apply(parts_t, 0, omega, lk, y, w)
        band_solve_transposed(ab, kl, ku, ipiv, w)
        d = np.vdot(y, w) / np.vdot(y, y).real
        left[j] = w / d
    return out
