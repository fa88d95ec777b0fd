"""A linear rotor in band storage, and its projection onto a few Ritz vectors: what the
Newton and frequency-domain loops of :mod:`rubrotor.linear.lapack` work on.

An FE rotor couples neighbouring nodes only, so its matrices are banded and a banded LU costs
``O(n b^2)``. The lowest undamped modes come from a block shift-invert Krylov space on a large
banded rotor (a dense eigen-solve on a small one); with the static deflections under unit support
forces they span the Ritz basis whose small projected problems give Newton its starting values.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
import scipy.linalg

from rubrotor.core.bandtypes import BandParts, SparseRows
from rubrotor.linear.lapack import band_matmul, ritz_vectors
from rubrotor.linear.roots import OSCILLATING
from rubrotor.rotors.linear import LinearSystem


def _support_values(system: LinearSystem, speeds: np.ndarray, frequencies=None):
    """Support entries on the free DOFs: rows, columns and their ``k`` (N/m), ``c`` (N s/m) at
    every speed (rad/s), as :meth:`Support.tabulate` gives them (linked supports expanded);
    with ``frequencies`` (rad/s, one per speed) a table against whirl frequency is read there
    instead (synchronous, frequency = speed, without)."""
    pos = np.full(len(system.M), -1)
    pos[system.free] = np.arange(system.free.size)
    rows, cols, kv, cv = [], [], [], []
    for sup in system.supports:
        at = frequencies if frequencies is not None and sup.axis == "frequency" else speeds
        ks, cs = (sup.block(a) for a in sup.tabulate(at))
        for i, di in enumerate(sup.all_dofs):
            for j, dj in enumerate(sup.all_dofs):
                if pos[di] < 0 or pos[dj] < 0:
                    continue
                rows.append(pos[di])
                cols.append(pos[dj])
                kv.append(ks[:, i, j])
                cv.append(cs[:, i, j])
    shape = (speeds.size, len(rows))
    k = np.array(kv).T.reshape(shape) if kv else np.zeros(shape)
    c = np.array(cv).T.reshape(shape) if cv else np.zeros(shape)
    return np.array(rows, np.int64), np.array(cols, np.int64), k, c


def _band_parts(system: LinearSystem, speeds: np.ndarray, frequencies=None) -> BandParts:
    """The rotor's matrices on the free DOFs in band storage, and its supports over ``speeds``
    (their frequency tables at ``frequencies``, one per speed, when given).

    An FE rotor couples neighbouring nodes only, so its bandwidth is a few DOFs and a banded
    LU costs ``O(n b^2)``; a dense system (e.g. a modal one) is simply a band as wide as the
    matrix.
    """
    mats = [system.M, system.G, system.K, system.C]
    if system.fixed:
        f = np.ix_(system.free, system.free)
        mats = [a[f] for a in mats]
    rows, cols, k, c = _support_values(system, speeds, frequencies)
    pattern = (mats[0] != 0) | (mats[1] != 0) | (mats[2] != 0) | (mats[3] != 0)
    pattern[rows, cols] = True
    r, cidx = np.nonzero(pattern)
    kl = int(max(0, (r - cidx).max(initial=0)))
    ku = int(max(0, (cidx - r).max(initial=0)))
    m, g, kk, cc = (_to_band(a, kl, ku) for a in mats)
    return BandParts(m, g, kk, cc, kl, ku, rows, cols, k, c)


def _to_band(a: np.ndarray, lower: int, upper: int) -> np.ndarray:
    """Compact band storage of ``a``, a column per row: ``ab[j, upper + i - j] = a[i, j]``."""
    n = a.shape[0]
    ab = np.zeros((lower + upper + 1, n), a.dtype)
    for k in range(-lower, upper + 1):
        j0 = max(k, 0)
        ab[upper - k, j0 : j0 + n - abs(k)] = np.diagonal(a, k)
    return np.ascontiguousarray(ab.T)


def _band_matmul(band: np.ndarray, kl: int, ku: int, x: np.ndarray) -> np.ndarray:
    """``a @ x`` for ``a`` in :func:`_to_band` storage (``a[i, j]`` at ``band[j, ku + i - j]``),
    ``kl`` sub- and ``ku`` super-diagonals (sparse: ``O(N (kl + ku) k)`` for ``k`` columns)."""
    x = np.ascontiguousarray(x, dtype=float)
    out = np.empty_like(x)
    band_matmul(np.ascontiguousarray(band), ku, x, out)
    return out


class _BandLU:
    """Real banded LU (LAPACK ``dgbtrf``) of a matrix in :func:`_to_band` storage."""

    def __init__(self, band: np.ndarray, kl: int, ku: int):
        ab = np.zeros((2 * kl + ku + 1, band.shape[0]))
        ab[kl:] = band.T
        self.kl, self.ku = kl, ku
        self.lu, self.piv, info = scipy.linalg.lapack.dgbtrf(ab, kl, ku)
        if info != 0:
            raise np.linalg.LinAlgError(f"singular banded matrix (dgbtrf info {info})")

    def solve(self, b: np.ndarray) -> np.ndarray:
        x, info = scipy.linalg.lapack.dgbtrs(self.lu, self.kl, self.ku, b, self.piv)
        return x


def _stiffness_band(parts: BandParts, at: int) -> np.ndarray:
    """Band of the symmetric part of ``K + K_s`` at sweep index ``at`` (needs ``kl == ku``)."""
    kb = parts.k.copy()
    np.add.at(kb, (parts.sup_col, parts.ku + parts.sup_row - parts.sup_col), parts.sup_k[at])
    kt = np.zeros_like(kb)  # the transpose: a[j, i] sits at kb[i, ku + j - i]
    n, ku = kb.shape[0], parts.ku
    for r in range(kb.shape[1]):
        d = r - ku  # kt[j, r] = a[j, j + d]... stored at kb[j + d, ku - d]
        j0, j1 = max(0, -d), n - max(0, d)
        kt[j0:j1, r] = kb[j0 + d : j1 + d, ku - d]
    return (kb + kt) / 2


def _sparse_rows(rows: np.ndarray) -> SparseRows:
    """``rows`` (R, N) as a :class:`~rubrotor.core.banded.SparseRows` gather (its nonzeros)."""
    nz = rows != 0
    width = max(1, int(nz.sum(axis=1).max(initial=1)))
    order = np.argsort(~nz, axis=1, kind="stable")[:, :width]
    val = np.take_along_axis(rows, order, 1).astype(complex)
    return SparseRows(np.ascontiguousarray(order, dtype=np.int64), np.ascontiguousarray(val))


_EXTRA = 6
"""Undamped modes in the Ritz basis beyond the ``n`` wanted."""


_KRYLOV_SIZE = 120
"""Above this many free DOFs (and a narrow band) the undamped modes of the Ritz basis come from
a banded block Krylov space, not a dense ``O(N^3)`` eigen-solve."""


def _krylov_modes(lu: _BandLU, bands, count: int, start: np.ndarray) -> np.ndarray:
    """Ritz approximations (N, count) of the ``count`` lowest modes of ``(K, M)``.

    ``bands = (K, M, kl, ku)`` in :func:`_to_band` storage, ``lu`` factorises ``K``. A block
    Krylov space of ``K^-1 M`` three blocks deep from the static deflections ``start`` and a
    seeded random block of ``count // 2 + 2`` columns (so results are reproducible). Measured on
    the 244-DOF benchmark rotor with ``count = 18``: the exact 12 lowest modes lie in it to
    better than 1e-5, the next six to ~1e-4; ample for Newton's starting values (Newton makes
    the eigenpairs exact)."""
    k, m, kl, ku = bands
    rng = np.random.default_rng(12345)
    size = k.shape[0]
    block = np.hstack([start, lu.solve(rng.standard_normal((size, count // 2 + 2)))])
    blocks = []
    for _ in range(2):
        block, _ = np.linalg.qr(block)
        blocks.append(block)
        block = lu.solve(_band_matmul(m, kl, ku, block))
    blocks.append(block)
    q, _ = np.linalg.qr(np.hstack(blocks))
    kq, mq = (q.T @ _band_matmul(band, kl, ku, q) for band in (k, m))
    # all eigenpairs (divide and conquer) then the lowest: faster than LAPACK's subset driver
    # at this size (measured 0.19 vs 0.30 ms for 45 x 45)
    _, z = scipy.linalg.eigh((kq + kq.T) / 2, (mq + mq.T) / 2, check_finite=False, driver="gvd")
    return q @ z[:, :count]


def _ritz_basis(
    system: LinearSystem, parts: BandParts, speed: float, at: int, n: int
) -> np.ndarray:
    """A mass-orthonormal basis (N, m) for starting values: the ``n + 6`` lowest undamped modes
    of ``(K_sym, M)`` at ``speed`` (rad/s; sweep index ``at`` of ``parts``) and the static deflections under unit
    forces at the support DOFs (residual flexibility: supports carry the damping and
    cross-coupling); all DOFs when that is not fewer. On a large banded rotor the undamped modes
    are Ritz vectors of a block shift-invert Krylov space (:func:`_krylov_modes`) and every
    product is banded, instead of a dense ``O(N^3)`` eigen-solve."""
    size = parts.m.shape[0]
    dofs = np.unique(parts.sup_row)
    unit = np.zeros((size, dofs.size))
    unit[dofs, np.arange(dofs.size)] = 1.0
    if (
        n + _EXTRA + dofs.size < size
        and size > _KRYLOV_SIZE
        and parts.kl == parts.ku
        and (2 * parts.kl + parts.ku + 1 < size // 4)
    ):
        bands = (_stiffness_band(parts, at), parts.m, parts.kl, parts.ku)
        lu = _BandLU(bands[0], parts.kl, parts.ku)
        statics = lu.solve(unit)
        span = _independent(np.hstack([_krylov_modes(lu, bands, n + _EXTRA, statics), statics]))
        kr, mr = (span.T @ _band_matmul(band, parts.kl, parts.ku, span) for band in bands[:2])
        _, z = scipy.linalg.eigh((kr + kr.T) / 2, (mr + mr.T) / 2, check_finite=False)
        return span @ z
    mx = system.matrices(speed)
    ks = (mx.K + mx.K.T) / 2
    if n + _EXTRA + dofs.size >= size:
        _, phi = scipy.linalg.eigh(ks, mx.M, check_finite=False)
        return phi
    _, modes = scipy.linalg.eigh(ks, mx.M, subset_by_index=[0, n + _EXTRA - 1], check_finite=False)
    span = _independent(np.hstack([modes, np.linalg.solve(ks, unit)]))
    _, z = scipy.linalg.eigh(span.T @ ks @ span, span.T @ mx.M @ span, check_finite=False)
    return span @ z


def _independent(span: np.ndarray) -> np.ndarray:
    """An orthonormal basis of the columns of ``span`` without the ones that depend on the
    others (pivoted QR; |R_ii| below 1e-10 of the largest): a static correction that a kept mode
    already holds (a rotor stiff against its supports) would make the projected mass singular."""
    q, r, _ = scipy.linalg.qr(span, mode="economic", pivoting=True)
    d = np.abs(np.diag(r))
    return q[:, d > 1e-10 * d[0]]


Reduced = namedtuple("Reduced", "phi mr kr dr")
Reduced.__doc__ = """A projection onto the Ritz basis ``phi`` (N, m): mass ``mr`` (m, m),
stiffness ``kr`` and damping ``dr`` (S, m, m) at every speed of the sweep (supports included)."""


def _reduced(system: LinearSystem, parts: BandParts, speeds: np.ndarray, n: int) -> Reduced:
    """The projection of the rotor at every speed (rad/s) onto :func:`_ritz_basis`."""
    mid = speeds.size // 2
    phi = _ritz_basis(system, parts, float(speeds[mid]), mid, n)
    kr0, cr0, gr, mr = (
        phi.T @ _band_matmul(a, parts.kl, parts.ku, phi)
        for a in (parts.k, parts.c, parts.g, parts.m)
    )
    outer = phi[parts.sup_row][:, :, None] * phi[parts.sup_col][:, None, :]
    kr = kr0 + np.einsum("sp,pij->sij", parts.sup_k, outer)
    dr = cr0 + speeds[:, None, None] * gr + np.einsum("sp,pij->sij", parts.sup_c, outer)
    return Reduced(phi, mr, kr, dr)


def _projected_lam(red: Reduced, idx: np.ndarray, n: int, floor: float = OSCILLATING) -> np.ndarray:
    """The ``n`` lowest oscillating eigenvalues (1/s) of the projected problems at sweep
    indices ``idx`` (one batched ``numpy.linalg.eigvals``); NaN where there are fewer.
    Oscillating: ``Im(lam) > floor |lam|`` (the Campbell diagram passes ``OVERDAMPED``)."""
    m = red.mr.shape[0]
    mr_inv = np.linalg.inv(red.mr)
    a = np.zeros((idx.size, 2 * m, 2 * m))
    a[:, :m, m:] = np.eye(m)
    a[:, m:, :m] = -mr_inv @ red.kr[idx]
    a[:, m:, m:] = -mr_inv @ red.dr[idx]
    lam = np.linalg.eigvals(a)
    lam = np.where(lam.imag > floor * np.abs(lam), lam, np.nan)
    lam = np.take_along_axis(lam, np.argsort(np.where(np.isnan(lam), np.inf, lam.imag)), 1)
    out = np.full((idx.size, n), np.nan + 0j)
    out[:, : min(n, lam.shape[1])] = lam[:, :n]
    return out


def _ritz_starts(
    system: LinearSystem, parts: BandParts, speeds: np.ndarray, n: int, red: Reduced | None = None
):
    """Starting eigenpairs at every speed from a projection onto :func:`_ritz_basis`.

    The projected eigenvalues come from :func:`_projected_lam` and the projected shapes from one
    step of inverse iteration each (:func:`rubrotor.linear.lapack.ritz_vectors`, batched;
    cheaper than batched eigenvectors). Returns ``lam0`` (S, n), NaN where fewer than ``n``
    oscillating modes were found, and ``vec0`` (S, n, N) on the free DOFs.
    """
    red = _reduced(system, parts, speeds, n) if red is None else red
    lam0 = _projected_lam(red, np.arange(speeds.size), n)
    return lam0, ritz_vectors(red.mr, red.dr, red.kr, lam0) @ red.phi.T
