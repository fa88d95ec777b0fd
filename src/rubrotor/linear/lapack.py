"""The banded linear algebra of the linear verbs on LAPACK (SciPy), with nothing to compile.

Each function here has the signature and result of its compiled twin in
:mod:`rubrotor.core.banded` (same band storage, same namedtuples, same status codes), and does
the same arithmetic: complex banded LU with partial pivoting (LAPACK ``zgbtrf``/``zgbtrs``,
which pivot on ``|Re| + |Im|`` as the compiled ``zgbtf2`` does), Newton's method on the
quadratic eigenproblem, one step of inverse iteration for Ritz vectors. The linear verbs
(modes, critical speeds, Campbell, unbalance and frequency responses, the API 617/684 checks,
UCS maps and mode shapes) call these, so their first call on a fresh install compiles nothing:
on an empty numba cache the compiled kernels cost each verb's first call 6-21 s of CPU (measured,
``benchmarks/bench_cold_start.py``), while LAPACK does the work within 2x of their warm CPU time
(Newton on a 100-speed Campbell of the 280-DOF ``general_rotor``: 0.23 s against 0.12 s; the
sweeps as fast; the batched Ritz vectors 12 ms against 3.5 ms). The compiled kernels stay for
the loops that run in compiled code (continuation's speed family).

``tests/test_linear_lapack.py`` checks each against its compiled twin on the shipped rotors;
``benchmarks/bench_cold_start.py`` times the verbs' first and second calls.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg.lapack as lapack
import scipy.sparse

from rubrotor.core.bandtypes import Refined
from rubrotor.core.status import OK, SINGULAR

__all__ = [
    "band_matmul",
    "frequency_sweep",
    "refine_eigenpairs",
    "ritz_vectors",
    "unbalance_sweep",
]


def band_matmul(band, ku, x, out):
    """``out <- a @ x`` for real ``a`` in compact band storage (``a[i, j]`` at
    ``band[j, ku + i - j]``) and a real block ``x`` (n, k), as
    :func:`rubrotor.core.banded.band_matmul`."""
    out[:] = _dia(band, ku) @ x


def _dia(band: np.ndarray, ku: int) -> scipy.sparse.csr_matrix:
    """The matrix of compact band ``band`` (n, kl + ku + 1) as CSR: its row ``r`` of the
    transposed band is diagonal ``ku - r`` (SciPy's DIA layout, ``data[r, j] = a[j - off, j]``)."""
    n, width = band.shape
    offsets = ku - np.arange(width)
    return scipy.sparse.dia_matrix((np.ascontiguousarray(band.T), offsets), shape=(n, n)).tocsr()


class _Speed:
    """The band of ``T(lam) = lam^2 M + lam (C + omega G + C_s) + K + K_s`` at one sweep
    index, in LAPACK's band layout (``2 kl + ku + 1`` rows, fill-in rows first), and
    ``T'(lam) = 2 lam M + C + omega G + C_s`` as sparse matrices."""

    def __init__(self, parts, s: int, omega: float, derivative: bool = False):
        kl, ku = parts.kl, parts.ku
        self.kl, self.ku, self.n = kl, ku, parts.m.shape[0]
        self.m = np.ascontiguousarray(parts.m.T)
        damp = parts.c + omega * parts.g  # a new array: the supports are added in place
        stiff = parts.k.copy()
        if parts.sup_row.size:
            at = (parts.sup_col, ku + parts.sup_row - parts.sup_col)
            np.add.at(stiff, at, parts.sup_k[s])
            np.add.at(damp, at, parts.sup_c[s])
        self.d = np.ascontiguousarray(damp.T)
        self.k = np.ascontiguousarray(stiff.T)
        if derivative:
            self.m2 = 2.0 * _dia(parts.m, ku)
            self.dsp = _dia(damp, ku)

    def factor(self, lam: complex):
        """``(lu, piv, status)`` of ``T(lam)`` (``zgbtrf``; status OK or SINGULAR)."""
        ab = np.zeros((2 * self.kl + self.ku + 1, self.n), np.complex128, order="F")
        ab[self.kl :] = (lam * lam) * self.m + lam * self.d + self.k
        lu, piv, info = lapack.zgbtrf(ab, self.kl, self.ku, overwrite_ab=1)
        return lu, piv, (SINGULAR if info > 0 else OK)

    def solve(self, lu, piv, b: np.ndarray) -> np.ndarray:
        x, _ = lapack.zgbtrs(lu, self.kl, self.ku, b, piv)
        return x

    def derivative(self, lam: complex, x: np.ndarray) -> np.ndarray:
        return lam * (self.m2 @ x) + self.dsp @ x


def _gather(out_rows, x: np.ndarray) -> np.ndarray:
    """Output rows (:class:`~rubrotor.core.banded.SparseRows`) applied to ``x``."""
    return np.sum(out_rows.val * x[out_rows.idx], axis=1)


def refine_eigenpairs(parts, speeds, starts, tol, max_iter, out_rows):
    """Newton's method on ``T(lam) x = 0``, ``c^H x = 1``: the twin of
    :func:`rubrotor.core.banded.refine_eigenpairs` (same arguments, same :class:`Refined`:
    eigenvalues (S, n) in 1/s, ``out_rows`` applied to the eigenvectors (S, n, R), Newton steps
    (S, n), negative where ``max_iter`` passed without convergence)."""
    ns, nm = starts.lam.shape
    lam_out = starts.lam.astype(np.complex128, copy=True)
    shapes = np.zeros((ns, nm, out_rows.idx.shape[0]), np.complex128)
    steps = np.zeros((ns, nm), np.int64)
    for s in range(ns):
        band = _Speed(parts, s, float(speeds[s]), derivative=True)
        for j in range(nm):
            x, lam_out[s, j], steps[s, j] = _newton(band, starts.vec[s, j], starts.lam[s, j],
                                                    tol, max_iter)  # fmt: skip
            shapes[s, j] = _gather(out_rows, x)
    return Refined(lam_out, shapes, steps)


def _newton(band: _Speed, x0: np.ndarray, lam0: complex, tol: float, max_iter: int):
    """Newton iterations of one mode from ``(lam0, x0)``: ``(x, lam, steps)`` as the compiled
    ``_newton`` returns them (steps ``-max_iter`` without convergence)."""
    x = np.array(x0, np.complex128)
    lk = complex(lam0)
    steps = -max_iter
    norm2 = np.vdot(x, x).real
    if not norm2 > 0.0:  # no start vector: not converged
        return x, lk, steps
    c = x / norm2
    last = 0.0
    for it in range(max_iter):
        lu, piv, status = band.factor(lk)
        if status != OK:
            steps = it + 1  # lk is an eigenvalue to working precision
            break
        u = band.solve(lu, piv, band.derivative(lk, x))
        d = np.vdot(c, u)
        if d == 0.0:  # the start has no component along the eigenvector: give up
            break
        step = -1.0 / d
        lk = lk + step
        x = u / d
        size = abs(step)
        # quadratic convergence: the next error is ~ size^3 / last^2
        if size <= tol * abs(lk) or (
            it > 0 and size < 1e-3 * last and size**3 <= tol * 1e-3 * abs(lk) * last**2
        ):
            steps = it + 1
            break
        last = size
    return x, lk, steps


def _sweep(parts, omegas, lams, index, rhs_scale, rhs, out_rows):
    """``out[s] = R T(lam_s)^-1 (scale_s rhs)`` at spin ``omegas[s]`` and support index
    ``index[s]``: ``(out, status, first singular index)``."""
    ns = lams.size
    out = np.zeros((ns, out_rows.shape[0]), np.complex128)
    rows = np.asarray(out_rows)
    for s in range(ns):
        band = _Speed(parts, int(index[s]), float(omegas[s]))
        lu, piv, status = band.factor(complex(lams[s]))
        if status != OK:
            return out, SINGULAR, s
        with np.errstate(over="ignore", invalid="ignore"):  # the callers check finiteness
            out[s] = rows @ band.solve(lu, piv, rhs * rhs_scale[s])
    return out, OK, -1


def unbalance_sweep(parts, speeds, rhs, out_rows):
    """Synchronous response at every speed, the twin of
    :func:`rubrotor.core.banded.unbalance_sweep`: ``out[s] = R Q`` with
    ``(K - W^2 M + i W (C + W G)) Q = W^2 rhs`` (``W = speeds[s]``, rad/s); returns
    ``(out, status, index)``."""
    w = np.asarray(speeds, float)
    rhs = np.asarray(rhs, np.complex128)
    return _sweep(parts, w, 1j * w, np.arange(w.size), w * w, rhs, out_rows)


def frequency_sweep(parts, spin, freqs, rhs, out_rows):
    """Forced response at every excitation frequency at one spin, the twin of
    :func:`rubrotor.core.banded.frequency_sweep` (``spin`` and ``freqs`` in rad/s); returns
    ``(out, status, index)``."""
    w = np.asarray(freqs, float)
    rhs = np.asarray(rhs, np.complex128)
    # the supports' entries at each frequency when tabulated there (a frequency table), else at 0
    index = np.arange(w.size) if parts.sup_k.shape[0] == w.size > 1 else np.zeros(w.size, int)
    return _sweep(parts, np.full(w.size, float(spin)), 1j * w, index, np.ones(w.size), rhs,
                  out_rows)  # fmt: skip


def ritz_vectors(mass, damping, stiffness, lam):
    """Null vectors of small dense quadratic eigenproblems at known eigenvalues, the twin of
    :func:`rubrotor.core.banded.ritz_vectors`: for every speed ``s`` and mode ``j`` one step of
    inverse iteration ``T y = r_j`` with ``T = lam^2 mass + lam damping[s] + stiffness[s]``, by
    Gaussian elimination with partial pivoting (on ``|Re| + |Im|``) batched over every
    ``(s, j)``, a pivot below ``1e-16`` of the largest entry raised to it; ``y`` (S, n, m)
    normalised to unit length, zero where ``lam`` is not finite."""
    lam = np.asarray(lam, np.complex128)
    ns, nm = lam.shape
    m = mass.shape[0]
    out = np.zeros((ns, nm, m), np.complex128)
    ok = np.isfinite(lam.real) & np.isfinite(lam.imag)
    si, ji = np.nonzero(ok)
    if si.size == 0:
        return out
    lk = lam[si, ji][:, None, None]
    t = lk * lk * mass[None] + lk * damping[si] + stiffness[si]
    a = np.arange(m)[None, :]
    jj = ji[:, None].astype(float)
    y = np.cos(0.7 * a * (jj + 1) + jj) + 1j * np.sin(1.3 * a + 0.4 * jj)
    size = np.max(np.abs(t.real) + np.abs(t.imag), axis=(1, 2))
    floor = np.where(size > 0.0, 1e-16 * size, 1.0)
    # LAPACK's batched solve (zgesv pivots as the compiled elimination does); where a pivot
    # falls below the floor (or is exactly zero) the elimination below raises it to the floor
    y = _solve_floored(t, y, floor)
    big = np.max(np.abs(y.real) + np.abs(y.imag), axis=1)
    y = y / big[:, None]
    out[si, ji] = y / np.sqrt(np.einsum("bi,bi->b", y.conj(), y).real)[:, None]
    return out


def _solve_floored(t: np.ndarray, y: np.ndarray, floor: np.ndarray) -> np.ndarray:
    """``t[b]^-1 y[b]`` by LAPACK's batched ``zgesv`` (``numpy.linalg.solve``; it pivots on
    ``|Re| + |Im|`` as the compiled elimination does). A pivot below the floor but not zero only
    scales the null vector's dominant part, which the caller normalises away; where ``zgesv``
    meets an exactly zero pivot or the result is not finite, those matrices are redone by
    :func:`_solve_batched`, which raises the pivot to the floor as the compiled kernel does."""
    try:
        x = np.linalg.solve(t, y[..., None])[..., 0]
        redo = ~np.all(np.isfinite(x), axis=1)
    except np.linalg.LinAlgError:  # an exactly singular t in the batch
        x = np.empty_like(y)
        redo = np.ones(t.shape[0], bool)
    if redo.any():
        t2, y2 = t[redo], y[redo].copy()
        _solve_batched(t2, y2, floor[redo])
        x[redo] = y2
    return x


def _solve_batched(t: np.ndarray, y: np.ndarray, floor: np.ndarray) -> None:
    """``y[b] <- t[b]^-1 y[b]`` for a batch (B, m, m), in place, by Gaussian elimination with
    partial pivoting on ``|Re| + |Im|``; a pivot below ``floor[b]`` is replaced by it."""
    nb, m, _ = t.shape
    b = np.arange(nb)
    for k in range(m):
        col = t[:, k:, k]
        p = k + np.argmax(np.abs(col.real) + np.abs(col.imag), axis=1)
        swap = p != k
        if swap.any():
            bs, ps = b[swap], p[swap]
            t[bs, k], t[bs, ps] = t[bs, ps].copy(), t[bs, k].copy()
            y[bs, k], y[bs, ps] = y[bs, ps].copy(), y[bs, k].copy()
        piv = t[:, k, k]
        small = np.abs(piv.real) + np.abs(piv.imag) < floor
        if small.any():
            t[small, k, k] = floor[small]
        inv = 1.0 / t[:, k, k]
        f = t[:, k + 1 :, k] * inv[:, None]
        t[:, k + 1 :, k + 1 :] -= f[:, :, None] * t[:, k, None, k + 1 :]
        y[:, k + 1 :] -= f * y[:, k, None]
    for k in range(m - 1, -1, -1):
        acc = y[:, k] - np.einsum("bc,bc->b", t[:, k, k + 1 :], y[:, k + 1 :])
        y[:, k] = acc / t[:, k, k]
