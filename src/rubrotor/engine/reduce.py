"""Modal reduction of a linear rotor with the static correction of the dropped modes.

First-order form
----------------
On the free DOFs at spin ``Omega`` (rad/s), ``M q'' + D q' + K q = f`` with ``D = C + Omega G``
(supports included) is ``x' = A x + B f`` with ``x = [q, q']``::

    A = [[0, I], [-M^-1 K, -M^-1 D]],     B = [[0], [M^-1]].

``A`` is real but not symmetric (gyroscopic, anisotropic and cross-coupled supports), so it is
diagonalised with right eigenvectors ``phi_r`` (columns of ``V``) and left ones ``psi_r`` (rows of
``V^-1``, so ``psi_r phi_s = delta_rs``): ``x = sum_r phi_r y_r``, ``y_r' = lam_r y_r + psi_r B f``.

Kept modes and conjugate pairs
------------------------------
Eigenvalues come as conjugate pairs (and real ones for overdamped motion). For a real state the
coordinate of ``conj(lam_r)`` is ``conj(y_r)``, so only the eigenvalues with ``Im lam > 0`` and the
real ones are stored, and ``x = Re(sum_r w_r phi_r y_r)`` with the weight ``w_r = 2`` for a pair and
1 for a real eigenvalue: half the arithmetic of the full complex state, and exact. A *mode* below
is one stored eigenvalue (a forward or backward whirl, or one real eigenvalue); modes are kept in
order of ``|lam|`` (their undamped natural frequency, rad/s).

Residual flexibility of the dropped modes
-----------------------------------------
A dropped mode (``|lam_r|`` far above the forcing frequencies) answers quasi-statically,
``y_r ~ -psi_r B f / lam_r``. Summed over all modes ``sum_r phi_r psi_r / lam_r = A^-1`` and
``-A^-1 B f = [K^-1 f; 0]``, so the dropped modes add the direct feed-through::

    x_res = -sum_dropped phi_r psi_r B f / lam_r = (-A^-1 + sum_kept phi_r psi_r / lam_r) B f
          = [K^-1 + Re(sum_kept w_r phi_r^q psi_r B / lam_r);  Re(sum_kept w_r phi_r^q psi_r B)] f

(``phi^q`` the displacement half of ``phi``; the velocity half uses ``phi^v = lam phi^q`` and
``sum_all phi^q psi B = [I 0] B = 0``). It is exact for a static force and makes the reduced
model keep the full model's static stiffness at every force and contact station, so that
truncation does not soften the contact. With every mode kept it vanishes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from rubrotor.errors import InputError

__all__ = ["Modes", "reduce_matrices", "reduce", "COND_LIMIT"]

COND_LIMIT = 1e10
"""Largest accepted condition number of the kept eigenvector basis (defective systems)."""


@dataclass(frozen=True)
class Modes:
    """Kept modes of ``M q'' + D q' + K q = f`` with its residual flexibility.

    Attributes
    ----------
    lam : ndarray, shape (ns,)
        Kept eigenvalues (1/s), ``Im >= 0``, increasing ``|lam|``.
    Vq : ndarray, shape (n, ns)
        Displacement half of the right eigenvectors, times the pair weight ``w``: the physical
        displacement is ``q = Re(Vq y)`` (m or rad per unit ``y``).
    U : ndarray, shape (ns, n)
        ``psi B`` per unit generalised force: ``y' = lam y + U f``.
    Rq, Rv : ndarray, shape (n, n)
        Residual feed-through of the dropped modes (see the module docstring): displacement
        (m/N) and velocity (m/(s N)) per unit force.
    Kinv : ndarray, shape (n, n)
        Full static flexibility ``K^-1``.
    cond : float
        Condition number (1-norm) of the full eigenvector matrix.
    n_total : int
        Number of modes of the full model (stored half).
    psi : ndarray, shape (ns, 2 n)
        Left eigenvectors of the kept modes: ``y = psi x``.
    """

    lam: np.ndarray
    Vq: np.ndarray
    U: np.ndarray
    Rq: np.ndarray
    Rv: np.ndarray
    Kinv: np.ndarray
    cond: float
    n_total: int
    psi: np.ndarray

    @property
    def size(self) -> int:
        """Number of kept modes (complex coordinates)."""
        return self.lam.size

    def input(self, fmap: np.ndarray) -> np.ndarray:
        """``(ns, m)`` complex: modal input of forces mapped by ``fmap`` (n x m, per N)."""
        return self.U @ fmap

    def rows(self, out: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rows of ``y`` giving ``out @ q`` and ``out @ q'`` (``out`` is (p, n)); take ``Re``."""
        rd = out @ self.Vq
        return rd, rd * self.lam[None, :]

    def residual(self, out: np.ndarray, fmap: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Real ``(p, m)`` feed-through of the dropped modes: displacement and velocity per N."""
        return out @ self.Rq @ fmap, out @ self.Rv @ fmap

    def project(self, x: np.ndarray) -> np.ndarray:
        """Modal coordinates ``y`` of a physical state ``x = [q, q']`` (kept modes only)."""
        return self.psi @ x


def _select(lam: np.ndarray, keep: int | None, cutoff: float | None) -> np.ndarray:
    """Indices of the stored half (``Im >= 0``) kept, by increasing ``|lam|``."""
    scale = max(float(np.max(np.abs(lam))), 1e-300)
    half = np.flatnonzero(lam.imag > 1e-12 * scale)
    real = np.flatnonzero(np.abs(lam.imag) <= 1e-12 * scale)
    idx = np.concatenate([half, real])
    idx = idx[np.argsort(np.abs(lam[idx]), kind="stable")]
    if keep is not None:
        if isinstance(keep, bool) or not isinstance(keep, int | np.integer) or keep < 1:
            raise InputError("modes", keep, f"an integer from 1 to {idx.size}")
        return idx[: min(int(keep), idx.size)]
    if cutoff is not None:
        if not (cutoff > 0 and np.isfinite(cutoff)):
            raise InputError("cutoff", cutoff, "a frequency > 0 (rad/s)")
        sel = idx[np.abs(lam[idx]) <= cutoff]
        if sel.size == 0:
            raise InputError(
                "cutoff", cutoff, f"at least the lowest mode, {abs(lam[idx[0]]):.6g} rad/s"
            )
        return sel
    return idx


def reduce_matrices(
    M: np.ndarray,
    D: np.ndarray,
    K: np.ndarray,
    keep: int | None = None,
    cutoff: float | None = None,
) -> Modes:
    """Diagonalise ``M q'' + D q' + K q = f`` and keep some modes.

    Parameters
    ----------
    M, D, K : ndarray, shape (n, n)
        Mass (kg), damping including ``Omega G`` (N s/m) and stiffness (N/m), real.
    keep : int, optional
        Number of modes kept (see the module docstring); all by default.
    cutoff : float, optional
        Keep every mode with ``|lam| <= cutoff`` (rad/s) instead.

    Returns
    -------
    Modes

    Raises
    ------
    InputError
        ``K`` singular (an unsupported rotor) or eigenvectors too ill-conditioned (a defective
        system: move the speed slightly).
    """
    n = M.shape[0]
    minv = np.linalg.inv(M)
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -minv @ K
    A[n:, n:] = -minv @ D
    lam, V = scipy.linalg.eig(A)
    V = V / np.linalg.norm(V, axis=0)
    try:
        psi = np.linalg.inv(V)
        kinv = np.linalg.inv(K)
    except np.linalg.LinAlgError:
        psi = kinv = np.full((1, 1), np.inf)
    cond = float(np.abs(V).sum(axis=0).max() * np.abs(psi).sum(axis=0).max())  # 1-norm
    if not cond < COND_LIMIT:
        raise InputError(
            "speed", "-", f"a speed where the rotor's modes are independent (cond {cond:.3g})"
        )
    kcond = np.abs(K).sum(axis=0).max() * np.abs(kinv).sum(axis=0).max()
    if not kcond < 1e15:
        raise InputError("supports", "-", "supports that hold the rotor (K is singular)")
    sel = _select(lam, keep, cutoff)
    scale = max(float(np.max(np.abs(lam))), 1e-300)
    w = np.where(lam[sel].imag > 1e-12 * scale, 2.0, 1.0)
    lk = lam[sel]
    Vq = V[:n, sel] * w[None, :]
    U = psi[sel, n:] @ minv
    Rq = kinv + np.real((Vq / lk[None, :]) @ U)
    Rv = np.real(Vq @ U)
    n_half = int(np.sum(lam.imag > 1e-12 * scale) + np.sum(np.abs(lam.imag) <= 1e-12 * scale))
    return Modes(lk, Vq, U, Rq, Rv, kinv, cond, n_half, psi[sel])


def reduce(system, speed: float, keep: int | None = None, cutoff: float | None = None) -> Modes:
    """:func:`reduce_matrices` of a :class:`rubrotor.linear.LinearSystem` at ``speed`` (rad/s)."""
    sm = system.matrices(speed)
    return reduce_matrices(sm.M, sm.damping, sm.K, keep, cutoff)
