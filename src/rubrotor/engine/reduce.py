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

A few modes of a large model without the dense eigen-decomposition
-------------------------------------------------------------------
The dense route diagonalises the whole ``2 n x 2 n`` matrix ``A`` (``O(8 n^3)``, 40 ms for
the 136 DOFs of ROSS's example rotor, 0.5-1 s for 244 DOFs here) to keep a dozen modes.
:func:`reduce_auto` instead finds the kept modes' right AND left vectors with ARPACK on
``A^-1 = [[-K^-1 D, -K^-1 M], [I, 0]]`` and its transpose (largest ``|1/lam|`` = smallest
``|lam|``, one LU of ``K`` and of ``M``), and projects ``M q'' + D q' + K q = f`` Petrov-Galerkin
on ``T`` (span of the right displacement vectors and of ``K^-1 B``) and ``Z`` (span of the left
ones and of ``K^-T B``), ``B`` the force stations. A mode whose right and left vectors lie in
the spans is an exact mode of the projected system with the same left and right vectors, and
``T (Z^T K T)^-1 Z^T B = K^-1 B``, so the kept modes and the residual at the stations are
exactly those of the dense route (tests/test_engine_reduce.py), from eigenproblems of the size
``r`` of the bases. The same projection on one fixed basis serves the run-up's segments
(:func:`reduce_projected`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from rubrotor.errors import InputError

__all__ = [
    "Modes", "RitzBasis", "reduce_matrices", "reduce_auto", "reduce_projected", "ritz_basis",
    "basis_from_modes", "reduce", "COND_LIMIT", "IllConditioned", "SpeedBasis", "speed_basis",
]  # fmt: skip

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
    Kinv : ndarray, shape (n, n), or None
        Full static flexibility ``K^-1`` (``None`` from :func:`reduce_projected` unless given).
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


class IllConditioned(InputError):
    """The eigenvectors of a system are not independent (condition number ``cond``): a
    defective system at this speed, or an input far off the rotor's scale (see
    :func:`rubrotor.rotors.scales.explain`, which names it).

    Parameters
    ----------
    cond : float
        1-norm condition number of the eigenvector basis.
    """

    def __init__(self, cond: float):
        self.cond = cond
        self.reason = f"the rotor's modes are not independent (cond {cond:.3g})"
        super().__init__(
            "speed", "-", f"a speed where the rotor's modes are independent (cond {cond:.3g})"
        )


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
        raise IllConditioned(cond)
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


@dataclass(frozen=True)
class RitzBasis:
    """Real orthonormal trial (``T``) and test (``Z``) bases, both ``(n, r)``, of a Petrov-Galerkin
    projection ``Z^T (M, D, K) T`` (see :func:`ritz_basis`)."""

    T: np.ndarray
    Z: np.ndarray


def _orth(X: np.ndarray, tol: float = 1e-10) -> np.ndarray:
    """Orthonormal basis of the columns of ``X`` (pivoted QR, rank by ``tol``)."""
    X = X / np.maximum(np.linalg.norm(X, axis=0), 1e-300)
    Q, R, _ = scipy.linalg.qr(X, mode="economic", pivoting=True)
    d = np.abs(np.diag(R))
    return Q[:, : int(np.sum(d > tol * d[0]))]


def basis_from_modes(modes, K_list, fmap: np.ndarray) -> RitzBasis:
    """Trial and test bases spanning the kept modes of each :class:`Modes` in ``modes``.

    ``T`` spans the real and imaginary parts of the right displacement eigenvectors ``Vq`` and
    the static responses ``K^-1 fmap`` (m/N) to unit forces at the force stations, ``Z`` the
    left ones (``U^T``) and ``K^-T fmap``, each for every stiffness in ``K_list`` (N/m). A mode
    whose left and right vectors both lie in the spans is reproduced exactly by the projected
    system, and ``T (Z^T K T)^-1 Z^T fmap = K^-1 fmap`` (static exactness at the stations).
    """
    right = [np.real(m.Vq) for m in modes] + [np.imag(m.Vq) for m in modes]
    left = [np.real(m.U.T) for m in modes] + [np.imag(m.U.T) for m in modes]
    for K in K_list:
        lu = scipy.linalg.lu_factor(K)
        right.append(scipy.linalg.lu_solve(lu, fmap))
        left.append(scipy.linalg.lu_solve(lu, fmap, trans=1))
    T, Z = _orth(np.hstack(right)), _orth(np.hstack(left))
    r = min(T.shape[1], Z.shape[1])  # equal unless a conjugate partner fell at the boundary
    return RitzBasis(T[:, :r], Z[:, :r])


def _arpack_modes(M, D, K, keep: int):
    """Right displacement vectors ``Vq`` and left rows ``U`` (as in :class:`Modes`) of at least
    the ``keep`` lowest stored modes, by ARPACK on ``A^-1`` (largest ``|1/lam|``) and on its
    transpose; only ``K`` and ``M`` are factorised (LU), never the ``2n`` eigenproblem."""
    from scipy.sparse.linalg import LinearOperator, eigs

    n = M.shape[0]
    luk, lum = scipy.linalg.lu_factor(K), scipy.linalg.lu_factor(M)

    getrs = scipy.linalg.lapack.dgetrs
    DT, MT = np.ascontiguousarray(D.T), np.ascontiguousarray(M.T)

    def inv_a(x):  # A^-1 [y1; y2] = [-K^-1 (D y1 + M y2); y1]
        return np.concatenate([-getrs(luk[0], luk[1], D @ x[:n] + M @ x[n:])[0], x[:n]])

    def inv_at(z):  # (A^-1)^T [z1; z2] = [-D^T w + z2; -M^T w], w = K^-T z1
        w = getrs(luk[0], luk[1], z[:n], trans=1)[0]
        return np.concatenate([-DT @ w + z[n:], -MT @ w])

    k = min(2 * keep + 4, 2 * n - 2)
    v0 = np.random.default_rng(0).standard_normal(2 * n)  # reproducible start
    ops = [LinearOperator((2 * n, 2 * n), matvec=f, dtype=float) for f in (inv_a, inv_at)]
    mu, V = eigs(ops[0], k=k, which="LM", v0=v0)
    mu_l, W = eigs(ops[1], k=k, which="LM", v0=v0)
    # left eigenvector [a, b] of A: b = u M with u the displacement left vector (U row)
    U = scipy.linalg.lu_solve(lum, W[n:], trans=1).T
    return 1 / mu, V[:n], U


class _Vectors:
    def __init__(self, Vq, U):
        self.Vq, self.U = Vq, U


def ritz_basis(M, D, K, keep: int, fmap: np.ndarray) -> RitzBasis:
    """:func:`basis_from_modes` of the ``keep`` lowest modes found by ARPACK (no dense
    ``2n`` eigen-decomposition) and the static responses at the force stations ``fmap``."""
    _, Vq, U = _arpack_modes(M, D, K, keep)
    return basis_from_modes([_Vectors(Vq, U)], [K], fmap)


def reduce_projected(M, D, K, basis: RitzBasis, keep=None, cutoff=None, kinv=None) -> Modes:
    """:func:`reduce_matrices` of the projected system ``Z^T (M, D, K) T`` (size ``r``), lifted
    back to the full coordinates: ``Vq = T Vq_r``, ``U = U_r Z^T``, ``Rq = T Rq_r Z^T`` (exact
    for forces at the stations the basis was built for), ``psi = [-U K / lam, U M]`` (the left
    eigenvector of the first-order form). ``n_total`` is then the size ``r`` of the projected
    system, ``cond`` its eigenvector condition number and ``Kinv`` is ``kinv`` (m/N, the full
    ``K^-1``, or ``None``: the engine solves with ``K`` instead)."""
    T, Z = basis.T, basis.Z
    red = reduce_matrices(Z.T @ M @ T, Z.T @ D @ T, Z.T @ K @ T, keep, cutoff)
    U = red.U @ Z.T
    lam = red.lam
    psi = np.hstack([-(U @ K) / lam[:, None], U @ M])
    return Modes(lam, T @ red.Vq, U, T @ red.Rq @ Z.T, T @ red.Rv @ Z.T, kinv, red.cond,
                 red.n_total, psi)  # fmt: skip


def partial_route(n: int, keep, cutoff, fmap) -> bool:
    """Whether :func:`reduce_auto` takes the ARPACK route: a mode count (not a cut-off) well
    below the model size, and force stations to build the residual on."""
    return keep is not None and cutoff is None and fmap is not None and 8 * (int(keep) + 2) < n


def reduce_auto(M, D, K, keep=None, cutoff=None, fmap=None) -> Modes:
    """Kept modes by the cheaper exact route (see the module docstring): a few modes of a large
    model by ARPACK and the Petrov-Galerkin projection (:func:`ritz_basis`,
    :func:`reduce_projected`); otherwise (or if ARPACK does not converge or misses a mode) the
    dense :func:`reduce_matrices`. ``fmap`` (n, m): the force stations whose residual must be
    exact (with the partial route, ``Rq``/``Rv`` are exact only on forces ``fmap @ F``)."""
    n = M.shape[0]
    if partial_route(n, keep, cutoff, fmap) and not isinstance(keep, bool):
        from scipy.sparse.linalg import ArpackError

        try:
            lam_a, Vq, U = _arpack_modes(M, D, K, int(keep))
            basis = basis_from_modes([_Vectors(Vq, U)], [K], fmap)
            modes = reduce_projected(M, D, K, basis, int(keep))
            scale = np.abs(lam_a)
            found = lam_a[lam_a.imag >= -1e-12 * scale]
            found = found[np.argsort(np.abs(found), kind="stable")][: int(keep)]
            dist = np.min(np.abs(modes.lam[:, None] - found[None, :]), axis=1, initial=np.inf)
            if modes.size == found.size == int(keep) and np.all(dist <= 1e-7 * np.abs(modes.lam)):
                return modes
        except (ArpackError, np.linalg.LinAlgError, InputError, ValueError):
            pass
    return reduce_matrices(M, D, K, keep, cutoff)


def reduce(system, speed: float, keep: int | None = None, cutoff: float | None = None) -> Modes:
    """:func:`reduce_matrices` of a :class:`rubrotor.rotors.linear.LinearSystem` at ``speed`` (rad/s)."""
    sm = system.matrices(speed)
    return reduce_matrices(sm.M, sm.damping, sm.K, keep, cutoff)


@dataclass(frozen=True)
class SpeedBasis:
    """A fixed real first-order basis on which a rotor's kept modes follow its speed.

    Built by :func:`speed_basis` at an anchor speed ``speed0`` (rad/s); :meth:`modes` gives the
    kept modes at a nearby speed from the projected real ``r x r`` first-order matrix
    ``A_r(Omega) = (L R)^-1 L A(Omega) R``, of which only the speed-dependent parts change:
    ``A_r = A_0 + (Omega - Omega_0) A_G - a_s (dK_s R_q + dC_s R_v)``, the gyroscopic term and the
    supports' tabulated coefficients ``dK_s, dC_s`` (change from ``Omega_0``, N/m and N s/m, on
    the support DOFs ``sdofs``). Nothing of size ``n`` is factorised per speed.

    Attributes
    ----------
    speed0 : float
        Anchor speed (rad/s).
    R : ndarray (2 n, r)
        Right basis (first-order vectors ``[q; q']``).
    A0, AG : ndarray (r, r)
        ``(L R)^-1 L A(Omega_0) R`` (1/s) and its derivative in speed through ``Omega G``
        (dimensionless).
    a_s : ndarray (r, p)
        ``(L R)^-1 L_v M^-1`` on the ``p`` support DOFs (1/kg).
    left : ndarray (r, 2 n)
        ``(L R)^-1 L``: the left vectors of a projected mode are ``W^-1 left``.
    left_u : ndarray (r, n)
        ``(L R)^-1 L_v M^-1``: the rows ``U`` of a projected mode are ``W^-1 left_u``.
    sdofs : ndarray of int
        Free-DOF indices of the support DOFs.
    kept : ndarray, complex (r, keep)
        The anchor's kept modes in basis coordinates (columns), to follow them by overlap.
    """

    speed0: float
    R: np.ndarray
    A0: np.ndarray
    AG: np.ndarray
    a_s: np.ndarray
    left: np.ndarray
    left_u: np.ndarray
    sdofs: np.ndarray
    kept: np.ndarray

    def modes(self, dK: np.ndarray, dC: np.ndarray, speed: float):
        """``(lam, Vq, U, psi, cond)`` of the anchor's kept modes followed to ``speed`` (rad/s),
        in the anchor's order (as :class:`Modes`), from the support coefficient changes
        ``dK, dC`` (p, p) since the anchor.

        Each kept mode is the projected eigenvector (``Im lam >= 0``) that overlaps it most in
        basis coordinates (an assignment); the projection also has eigenvalues of the static
        enrichment, which are no modes of the rotor and are never kept.
        """
        import scipy.optimize

        n = self.R.shape[0] // 2
        rs, rv = self.R[self.sdofs], self.R[n + self.sdofs]
        a = self.A0 + (speed - self.speed0) * self.AG - self.a_s @ (dK @ rs + dC @ rv)
        mu, W = scipy.linalg.eig(a)
        scale = max(float(np.max(np.abs(mu))), 1e-300)
        cand = np.flatnonzero(mu.imag >= -1e-10 * scale)
        Wc = W[:, cand] / np.linalg.norm(W[:, cand], axis=0)
        ov = np.abs(self.kept.conj().T @ Wc) / np.linalg.norm(self.kept, axis=0)[:, None]
        idx = cand[scipy.optimize.linear_sum_assignment(-ov)[1]]
        winv = np.linalg.inv(W)
        cond = float(np.abs(W).sum(axis=0).max() * np.abs(winv).sum(axis=0).max())
        real = np.abs(mu[idx].imag) <= 1e-10 * scale
        w = np.where(real, 1.0, 2.0)
        lam = np.where(real, mu[idx].real + 0j, mu[idx])
        Vq = (self.R[:n] @ W[:, idx]) * w[None, :]
        return lam, Vq, winv[idx] @ self.left_u, winv[idx] @ self.left, cond


def speed_basis(sm, count: int, supports, vectors=None, minv=None) -> SpeedBasis:
    """:class:`SpeedBasis` at ``sm.speed`` (:class:`rubrotor.rotors.linear.SystemMatrices`).

    Basis choice: the right and left first-order eigenvectors (real and imaginary parts) of the
    ``count`` lowest stored modes at the anchor speed (all of them followed), enriched by the
    static responses ``K^-1 e_j`` (as displacement and as velocity) to unit forces at the support
    DOFs ``supports`` (free indices) and the left ones ``K^-T e_j``: a change of the supports'
    coefficients is a force at those DOFs, which modes alone represent only slowly (its static
    response spreads over all of them). Exact at the anchor (its modes are in the span); the
    error of the kept eigenvalues grows with the distance from it (measured on
    ``seal_rub.toml``, ``count = 20``: 7e-8 relative at 3 % from the anchor, 2e-5 without the
    enrichment).

    ``vectors = (lam, phq, psi)``: the modes at the anchor speed when known already (1/s; right
    displacement vectors (n, count) without the pair weight; first-order left vectors
    (count, 2 n) with ``psi [phq; lam phq] = 1``), instead of the dense eigen-decomposition.
    ``minv``: ``M^-1`` (1/kg) when known.
    """
    M, K, D, G = sm.M, sm.K, sm.damping, sm.G
    n = M.shape[0]
    if vectors is None:
        md = reduce_matrices(M, D, K, count)
        scale = max(float(np.max(np.abs(md.lam))), 1e-300)
        lam = md.lam
        phq = md.Vq / np.where(lam.imag > 1e-12 * scale, 2.0, 1.0)[None, :]
        psi = md.psi
    else:
        lam, phq, psi = vectors
        scale = max(float(np.max(np.abs(lam))), 1e-300)
        phq, psi = phq.copy(), psi.copy()
        for j in np.flatnonzero(lam.imag <= 1e-12 * scale):  # a real mode: real vectors
            c = phq[np.argmax(np.abs(phq[:, j])), j]
            phq[:, j] *= abs(c) / c
            psi[j] *= c / abs(c)
    pair = lam.imag > 1e-12 * scale
    right = np.vstack([phq, phq * lam[None, :]])
    sdofs = np.asarray(supports, int)
    E = np.zeros((n, sdofs.size))
    E[sdofs, np.arange(sdofs.size)] = 1.0
    lu = scipy.linalg.lu_factor(K)
    Y, Yt = scipy.linalg.lu_solve(lu, E), scipy.linalg.lu_solve(lu, E, trans=1)
    Y, Yt = Y / np.linalg.norm(Y, axis=0), Yt / np.linalg.norm(Yt, axis=0)  # conditioning
    YtM = Yt.T @ M
    YtM /= np.linalg.norm(YtM, axis=1)[:, None]
    zero = np.zeros_like(Y)
    p = np.flatnonzero(pair)
    R = np.hstack([right.real, right[:, p].imag, np.vstack([Y, zero]), np.vstack([zero, Y])])
    L = np.vstack([psi.real, psi[p].imag, np.hstack([Yt.T, zero.T]),
                   np.hstack([zero.T, YtM])])  # fmt: skip
    # the followed modes in basis coordinates: column j (real part) + i column (imaginary part)
    kept = np.zeros((R.shape[1], lam.size), complex)
    kept[np.arange(lam.size), np.arange(lam.size)] = 1.0
    kept[lam.size + np.arange(p.size), p] = 1j
    lr = np.linalg.inv(L @ R)
    minv = np.linalg.inv(M) if minv is None else minv
    AR = np.vstack([R[n:], -minv @ (K @ R[:n] + D @ R[n:])])
    left = lr @ L
    left_u = left[:, n:] @ minv
    AG = left[:, n:] @ (-minv @ (G @ R[n:]))
    return SpeedBasis(float(sm.speed), R, left @ AR, AG, left_u[:, sdofs], left, left_u, sdofs,
                      kept)  # fmt: skip
