"""Linear rotordynamics of any :class:`~rubrotor.rotors.linear.LinearSystem`: damped modes and their whirl,
Campbell diagrams with stability, critical speeds, the stability threshold and the unbalance
response in the frequency domain.

Conventions
-----------
The state ``x = [q, q']`` obeys ``x' = A(Omega) x`` (see :meth:`rubrotor.rotors.linear.SystemMatrices.first_order`).
An eigenvalue ``lambda = -zeta omega_n + i omega_d`` with ``omega_d > 0`` is one physical mode:

* frequency ``f = omega_d / (2 pi)`` (Hz, the damped natural frequency);
* damping ratio ``zeta = -Re(lambda) / |lambda|`` (negative when the mode grows);
* logarithmic decrement ``delta = -2 pi Re(lambda) / Im(lambda)``.

Overdamped (real) eigenvalues are not modes and are left out. Eigenvalues come in conjugate
pairs; only the ``Im > 0`` member is kept, so at zero speed an isotropic rotor's two equal
frequencies (one per plane) are two modes, and stay two modes as the speed splits them.

Whirl: a mode shape gives at each station the complex deflections ``V``, ``W``; the orbit
``v + i w`` turns from ``+v`` towards ``+w`` (forward, the spin direction) when
``Im(conj(V) W) < 0``. A mode is ``"forward"`` or ``"backward"`` when every station with a
significant, non-flat orbit turns that way, ``"mixed"`` otherwise (anisotropic supports). Within a
cluster of equal eigenvalues (isotropic rotor at rest) the shapes are first rotated into the
combinations of extreme whirl (the eigenvectors of the 2x2 Hermitian "whirl" form), so that the
pair is reported as one forward and one backward circular mode, as the limit of a slowly spinning
rotor.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass

import numba
import numpy as np
import scipy.linalg
import scipy.optimize
import scipy.sparse.linalg

from rubrotor.core.banded import (
    OK,
    BandParts,
    SparseRows,
    Starts,
    band_matmul,
    refine_eigenpairs,
    ritz_vectors,
    unbalance_sweep,
)
from rubrotor.errors import InputError
from rubrotor.rotors.linear import LinearSystem, NodalBasis

__all__ = [
    "DampedMode",
    "DampedModes",
    "CampbellData",
    "LinearCritical",
    "UnbalanceResponse",
    "damped_modes",
    "campbell_data",
    "linear_critical_speeds",
    "stability_threshold",
    "unbalance_response",
]

TWO_PI = 2 * math.pi


@dataclass(frozen=True)
class DampedMode:
    """One damped mode at one speed.

    Attributes
    ----------
    index : int
        1-based rank by undamped natural frequency ``|lambda|`` (as ROSS ranks its modes).
    frequency_hz : float
        Damped natural frequency ``Im(lambda) / 2 pi`` (Hz; 0 for a real root).
    damping_ratio : float
        ``zeta`` (dimensionless; < 0 when the mode grows).
    log_dec : float
        Logarithmic decrement (dimensionless; < 0 when the mode grows; ``inf`` for a real root).
    whirl : str
        ``"forward"``, ``"backward"`` or ``"mixed"``.
    eigenvalue : complex
        ``lambda`` (1/s).
    shape : ndarray, complex
        Mode shape on all DOFs of the system (fixed DOFs zero), normalised to unit largest
        deflection (m per unit modal amplitude; a mode without deflection, of rotations or
        housings only, to unit largest DOF).
    """

    index: int
    frequency_hz: float
    damping_ratio: float
    log_dec: float
    whirl: str
    eigenvalue: complex
    shape: np.ndarray

    @property
    def natural_frequency_hz(self) -> float:
        """Undamped natural frequency ``|lambda| / 2 pi`` (Hz), the rank key (ROSS's ``wn``)."""
        return abs(self.eigenvalue) / TWO_PI

    @property
    def overdamped(self) -> bool:
        """True for a root that does not oscillate: ``Im(lambda) <= OVERDAMPED |lambda|``."""
        return self.eigenvalue.imag <= OVERDAMPED * abs(self.eigenvalue)

    @property
    def stable(self) -> bool:
        """True when the mode decays (``Re(lambda) < 0``)."""
        return self.eigenvalue.real < 0


@dataclass(frozen=True)
class DampedModes:
    """The modes of a rotor at one speed (``speed_rad_s``, rad/s), ranked by ``|lambda|``."""

    speed_rad_s: float
    modes: tuple[DampedMode, ...]

    def to_dict(self) -> dict:
        """The JSON form printed by ``rubrotor modes --json`` for a general rotor."""
        return {
            "speed_rad_s": self.speed_rad_s,
            "modes": [
                {
                    "index": m.index,
                    "frequency_hz": m.frequency_hz,
                    "natural_frequency_hz": m.natural_frequency_hz,
                    "damping_ratio": m.damping_ratio,
                    "log_dec": m.log_dec if math.isfinite(m.log_dec) else None,
                    "whirl": m.whirl,
                    "overdamped": m.overdamped,
                }
                for m in self.modes
            ],
        }


OSCILLATING = 1e-4
"""A root is complex (a mode that oscillates) when ``Im(lam) > OSCILLATING |lam|`` (damping ratio
below ``1 - 5e-9``), else real.

A critically damped pair of real eigenvalues (heavily damped bearings make them) splits under
rounding into a complex pair with ``Im(lam) ~ sqrt(eps cond) |lam|`` (about ``1e-6 |lam|`` on
the shipped general rotor): without a margin such a pair would appear, or not, as a spurious
zero-frequency mode and shift the numbering of the others."""

OVERDAMPED = 1e-2
"""A mode is marked overdamped when ``Im(lam) <= OVERDAMPED |lam|``: real roots, and complex
ones with damping ratio ``zeta >= 0.99995`` (log dec >= 628: one would-be period shrinks the
motion by ``e^-628``, so nothing oscillates). Heavy element damping makes such roots (ROSS's
``rotor_example_amb_simple`` at 300 rad/s: ``|lam|`` near 1e4 rad/s with ``Im(lam)`` 1-5 rad/s);
ranked by frequency they would come first, ranked by ``|lam|`` they fall where they belong."""


def _check_speed(name: str, speed) -> float:
    if isinstance(speed, bool) or not isinstance(speed, int | float | np.integer | np.floating):
        raise InputError(name, speed, "a spin speed (rad/s)")
    if not (math.isfinite(speed) and speed >= 0):
        raise InputError(name, speed, "a finite spin speed >= 0 (rad/s)")
    return float(speed)


def _stations(system: LinearSystem) -> np.ndarray:
    """``(2 S, n_full)`` rows giving ``V``, ``W`` at the stations whirl is judged at."""
    basis = system.basis
    if isinstance(basis, NodalBasis):  # at a node: the node's v and w DOFs
        count = len(basis.nodes)
        rows = np.zeros((2 * count, basis.n_dof))
        rows[np.arange(2 * count), 4 * np.repeat(np.arange(count), 2) + np.tile([0, 1], count)] = 1
        return rows
    xs = np.linspace(0.0, basis.length, 23)[1:-1]
    return np.vstack([basis.rows(float(x)) for x in xs])


def _circularise(rows: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """Rotate a cluster of equal-eigenvalue shapes into the combinations of extreme whirl."""
    d = rows @ shapes
    v, w = d[0::2], d[1::2]
    h = (np.conj(v).T @ w - np.conj(w).T @ v) / 2j  # Hermitian whirl form
    _, u = np.linalg.eigh(h)
    return shapes @ u


def _eig_nearest_zero(mx, k: int):
    """The ``k`` eigenvalues of ``A`` nearest zero and their eigenvectors, by shift-invert Arnoldi.

    ``A^-1 [x1; x2] = [-K^-1 (M x2 + D x1); x1]`` (``D = C + Omega G``) needs one sparse LU
    factorisation of ``K`` (half the size of ``A``, banded for an FE rotor) and no inverse of
    ``M``.
    """
    n = mx.M.shape[0]
    lu = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(mx.K))
    m, d = scipy.sparse.csr_matrix(mx.M), scipy.sparse.csr_matrix(mx.damping)

    def inverse(x):
        x1, x2 = x[:n], x[n:]
        return np.concatenate([-lu.solve(m @ x2 + d @ x1), x1])

    op = scipy.sparse.linalg.LinearOperator((2 * n, 2 * n), matvec=inverse, dtype=float)
    mu, vec = scipy.sparse.linalg.eigs(op, k=k, which="LM", tol=1e-13)
    return 1.0 / mu, vec


def _select(lam: np.ndarray, n: int | None, natural: bool) -> np.ndarray:
    """Indices of the modes among the roots ``lam``, in their order.

    By frequency: the roots with ``Im > OSCILLATING |lam|``, by ``Im``, the first ``n``. By
    natural frequency (``natural``): the roots with ``Im > OVERDAMPED |lam|`` by ``|lam|``, the
    first ``n``; then, marked overdamped by the caller, the real roots (``|Im| <= OSCILLATING
    |lam|``, each once) and the nearly real ones, by ``|lam|``, those up to the last mode's
    ``|lam|`` (all when ``n`` is None)."""
    a = np.abs(lam)
    if not natural:
        idx = np.flatnonzero(lam.imag > OSCILLATING * a)
        return idx[np.argsort(lam.imag[idx], kind="stable")][:n]
    osc = np.flatnonzero(lam.imag > OVERDAMPED * a)
    osc = osc[np.argsort(a[osc], kind="stable")][:n]
    over = np.flatnonzero((lam.imag > -OSCILLATING * a) & (lam.imag <= OVERDAMPED * a))
    if n is not None:
        over = over[a[over] <= (a[osc].max() if osc.size else np.inf)]
    return np.concatenate([osc, over[np.argsort(a[over], kind="stable")]])


def _real_made_real(lam: np.ndarray) -> np.ndarray:
    """Roots with ``|Im| <= OSCILLATING |lam|`` as exactly real numbers (a rounding split)."""
    return np.where(np.abs(lam.imag) <= OSCILLATING * np.abs(lam), lam.real + 0j, lam)


def _eig(system: LinearSystem, speed: float, n: int | None = None, natural: bool = False):
    """Eigenvalues of the modes (:func:`_select`) and the ``q`` part of their eigenvectors.

    With ``n`` given on a large system: the Campbell route at one speed (:func:`_newton_eig`:
    projection starts, Newton on the banded quadratic eigenproblem; it finds the oscillating
    modes next to the lowest undamped ones). Ranked by ``|lam|`` it is taken only where the
    projected problem has no root left out below the ``n``-th mode's ``|lam|`` (no overdamped
    root there, the same ``n`` modes by frequency as by ``|lam|``: :func:`_ranks_alike`). Else,
    or if one of its checks fails: shift-invert Arnoldi (ARPACK) finds the ``2 n + 8``
    eigenvalues nearest zero, i.e. of least ``|lam|`` (twice as many while fewer than ``n``
    modes are among them), from one sparse LU of ``K``. Both instead of a dense solve of all
    ``2 N``; the tests check them against the dense route.
    """
    size = 2 * system.n_dof
    if n is not None and size > 16 * n:
        found = _newton_eig(system, speed, n, natural)
        if found is not None:
            return found
    mx = system.matrices(speed)
    lam = None
    floor = OVERDAMPED if natural else OSCILLATING
    if n is not None and size > 16 * n:
        k = 2 * n + 8
        while lam is None or (
            np.count_nonzero(lam.imag > floor * np.abs(lam)) < n and k < size // 2
        ):
            k = k if lam is None else 2 * k
            lam, vec = _eig_nearest_zero(mx, k)
    else:
        a, _ = mx.first_order()
        if n is not None:
            found = _eigvals_then_vectors(mx, a, n, natural)
            if found is not None:
                return found
        lam, vec = scipy.linalg.eig(a, overwrite_a=True, check_finite=False)
    sel = _select(lam, n, natural)
    return _real_made_real(lam[sel]), vec[: system.n_dof, sel]


def _eigvals_then_vectors(mx, a: np.ndarray, n: int, natural: bool = False):
    """The ``n`` lowest modes of a small dense system: all eigenvalues of the first-order matrix
    ``a`` without eigenvectors (LAPACK ``dgeev`` skips the back-transformation: about half the
    cost), then one null vector of ``lam^2 M + lam D + K`` per kept mode (one step of inverse
    iteration at the eigenvalue, compiled: :func:`rubrotor.core.banded.ritz_vectors`). ``None``
    when equal eigenvalues (within 1e-7) reach the kept ones: their shapes must span the
    eigenspace as the dense vectors do before :func:`_circularise`, so the caller takes the
    dense route."""
    lam = scipy.linalg.eigvals(a, check_finite=False)
    head = lam[_select(lam, n + 1, natural)]
    if np.any(np.abs(np.diff(head)) <= 1e-7 * np.abs(head[1:])):
        return None
    lam = _real_made_real(lam[_select(lam, n, natural)])
    vec = ritz_vectors(mx.M, mx.damping[None], mx.K[None], lam[None])[0]
    return lam, vec.T


def _ranks_alike(red: Reduced, n: int) -> bool:
    """True when the projected problem's ``n`` lowest modes by frequency are all its roots of
    ``|lam|`` up to theirs (with a 1e-3 margin), none overdamped: ranked by ``|lam|`` the
    Newton route then finds the same modes."""
    m = red.mr.shape[0]
    a = np.zeros((2 * m, 2 * m))
    a[:m, m:] = np.eye(m)
    a[m:, :m] = -np.linalg.solve(red.mr, red.kr[0])
    a[m:, m:] = -np.linalg.solve(red.mr, red.dr[0])
    lam = np.linalg.eigvals(a)
    size = np.abs(lam)
    osc = lam[lam.imag > OSCILLATING * size]
    if osc.size < n:
        return False
    top = np.abs(osc[np.argsort(osc.imag)][:n]).max() * (1 + 1e-3)
    low = lam[(lam.imag > -OSCILLATING * size) & (size <= top)]
    return low.size == n and bool(np.all(low.imag > OVERDAMPED * np.abs(low)))


def _newton_eig(system: LinearSystem, speed: float, n: int, natural: bool = False):
    """The ``n`` lowest modes at ``speed`` (rad/s) as :func:`campbell_data` finds them, with
    full eigenvectors on the free DOFs, by frequency or (``natural``) by ``|lam|``; ``None``
    when a check fails (fewer than ``n`` projected modes, with ``natural`` a projection that
    ranks otherwise (:func:`_ranks_alike`) or an overdamped result, Newton not converged, a
    start that moved by more than 1e-3 of itself, or two starts that converged to one
    eigenvalue), so that the caller takes another route."""
    speeds = np.array([speed])
    parts = _band_parts(system, speeds)
    try:
        red = _reduced(system, parts, speeds, n)
        if natural and not _ranks_alike(red, n):
            return None
        lam0, vec0 = _ritz_starts(system, parts, speeds, n, red)
    except np.linalg.LinAlgError:
        return None
    if not np.all(np.isfinite(lam0)):
        return None
    size = system.n_dof
    every = SparseRows(np.arange(size)[:, None], np.ones((size, 1), complex))
    threads = numba.get_num_threads()
    numba.set_num_threads(1)  # one speed: waking the pool (OpenMP barriers) costs milliseconds
    try:
        ref = refine_eigenpairs(parts, speeds, Starts(lam0, vec0), 1e-10, 8, every)
    finally:
        numba.set_num_threads(threads)
    lam, start = ref.lam[0], lam0[0]
    same = np.abs(lam[:, None] - lam[None, :]) <= 1e-7 * np.abs(lam)[:, None]
    apart = np.abs(start[:, None] - start[None, :]) > 1e-5 * np.abs(start)[:, None]
    if (
        np.any(ref.steps <= 0)
        or np.any(np.abs(lam - start) > 1e-3 * np.abs(start))
        or np.any(same & apart)
        or not np.all(lam.imag > (OVERDAMPED if natural else OSCILLATING) * np.abs(lam))
    ):
        return None
    order = np.argsort(np.abs(lam) if natural else lam.imag, kind="stable")
    return lam[order], ref.shapes[0].T[:, order]


def damped_modes(system: LinearSystem, speed: float = 0.0, n: int | None = None) -> DampedModes:
    """Damped modes of a linear rotor at one spin speed.

    Parameters
    ----------
    system : LinearSystem
        The rotor (see ``rubrotor.rotors.linear``).
    speed : float
        Spin speed ``Omega`` (rad/s), ``>= 0``.
    n : int, optional
        Keep the ``n`` lowest modes (default: all).

    Returns
    -------
    DampedModes
        Frequencies (Hz), damping ratios, logarithmic decrements, whirl and shapes, ranked by
        undamped natural frequency ``|lambda|`` as ROSS ranks them; real roots and roots with
        ``Im(lambda) <= OVERDAMPED |lambda|`` are kept in that rank and marked
        ``DampedMode.overdamped`` (ranked by ``Im(lambda)`` they would come first).

    Examples
    --------
    A 2-DOF Jeffcott rotor (mass 1 kg, stiffness 1e4 N/m in both directions):

    >>> import numpy as np
    >>> from rubrotor.rotors.linear import LinearSystem, NodalBasis
    >>> m = np.diag([1.0, 1.0, 1e-6, 1e-6])
    >>> k = np.diag([1e4, 1e4, 1.0, 1.0])
    >>> z = np.zeros((4, 4))
    >>> jeff = LinearSystem(M=m, K=k, C=z, G=z, basis=NodalBasis(np.array([0.0])))
    >>> [round(md.frequency_hz, 4) for md in damped_modes(jeff, 0.0, n=2).modes]
    [15.9155, 15.9155]
    """
    speed = _check_speed("speed", speed)
    if n is not None and (isinstance(n, bool) or not isinstance(n, int) or n < 1):
        raise InputError("n", n, "a number of modes >= 1")
    return _modes(system, speed, n, natural=True)


def _modes(system: LinearSystem, speed: float, n: int | None, natural: bool) -> DampedModes:
    """:func:`damped_modes` ranked by ``|lambda|`` (``natural``, real roots kept) or, for the
    Campbell rows, by ``Im(lambda)`` (oscillating modes only)."""
    lam, vec = _eig(system, speed, n, natural)
    full = np.zeros((len(system.M), vec.shape[1]), complex)
    full[system.free] = vec
    rows = _stations(system)
    i = 0
    while i < len(lam):  # clusters of equal eigenvalues: circular combinations
        j = i + 1
        while j < len(lam) and abs(lam[j] - lam[i]) <= 1e-7 * abs(lam[i]):
            j += 1
        if j - i > 1:
            full[:, i:j] = _circularise(rows, full[:, i:j])
        i = j
    count = len(lam)
    defl = rows @ full  # V, W at the stations, (2 S, count)
    whirl = _whirl_labels(defl.T)
    big = np.argmax(np.abs(defl), axis=0)
    scale = defl[big, np.arange(count)]
    flat = scale == 0  # a mode of rotations or housings only: unit largest DOF instead
    scale[flat] = full[np.argmax(np.abs(full[:, flat]), axis=0), np.flatnonzero(flat)]
    full = full / scale  # unit largest deflection
    modes = []
    for k in range(count):
        lk = complex(lam[k])
        modes.append(
            DampedMode(
                index=k + 1,
                frequency_hz=lk.imag / TWO_PI,
                damping_ratio=-lk.real / abs(lk),
                log_dec=-TWO_PI * lk.real / lk.imag
                if lk.imag
                else math.copysign(math.inf, -lk.real),
                whirl=whirl[k],
                eigenvalue=lk,
                shape=full[:, k],
            )
        )
    return DampedModes(speed_rad_s=speed, modes=tuple(modes))


def _speed_array(name: str, speeds) -> np.ndarray:
    s = np.asarray(speeds, dtype=float)
    if s.ndim != 1 or s.size < 2 or not np.all(np.isfinite(s)) or np.any(s < 0):
        raise InputError(name, speeds, "at least 2 finite spin speeds >= 0 (rad/s)")
    if np.any(np.diff(s) <= 0):
        raise InputError(name, speeds, "increasing spin speeds (rad/s)")
    return s


@dataclass(frozen=True)
class CampbellData:
    """Campbell diagram with stability: mode ``j`` (sorted by frequency at each speed).

    Attributes
    ----------
    speeds : ndarray, shape (S,)
        Spin speeds (rad/s).
    frequency_hz, log_dec : ndarray, shape (S, n)
        Damped natural frequency (Hz) and logarithmic decrement of the ``n`` lowest modes.
    whirl : ndarray of str, shape (S, n)
        ``"forward"``, ``"backward"`` or ``"mixed"``.
    """

    speeds: np.ndarray
    frequency_hz: np.ndarray
    log_dec: np.ndarray
    whirl: np.ndarray


def campbell_data(system: LinearSystem, speeds, n: int = 8) -> CampbellData:
    """Frequencies, logarithmic decrements and whirl of the ``n`` lowest modes over ``speeds``.

    Each eigenpair is exact (the same eigenvalues as :func:`damped_modes`, to ~1e-12): a
    projection onto the rotor's lowest undamped modes gives starting values at every speed
    (one batched small eigen-solve), which Newton's method on the full quadratic eigenproblem
    refines with banded LU solves in one compiled loop. A speed where Newton fails falls back
    to the dense route.

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    speeds : array_like
        Increasing spin speeds (rad/s).
    n : int
        Number of modes (the lowest at each speed; branches are sorted by frequency, so two
        crossing branches swap rows at their crossing).

    Returns
    -------
    CampbellData
    """
    s = _speed_array("speeds", speeds)
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise InputError("n", n, "a number of modes >= 1")
    lam, shapes, ok = _refined_modes(system, s, n)
    with np.errstate(invalid="ignore"):  # Newton landed on a real root: not a mode, redo densely
        ok = ok & (lam.imag > OSCILLATING * np.abs(lam))
    f = np.full((s.size, n), np.nan)
    ld = np.full((s.size, n), np.nan)
    wh = np.full((s.size, n), "", dtype=object)
    good = ok & np.isfinite(lam)
    f[good] = lam[good].imag / TWO_PI
    ld[good] = -TWO_PI * lam[good].real / lam[good].imag
    wh[good] = _whirl_labels(shapes)[good]
    for i in np.flatnonzero(~ok.all(axis=1)):  # Newton failed somewhere: the dense route
        f[i], ld[i], wh[i] = np.nan, np.nan, ""
        for j, md in enumerate(_modes(system, float(s[i]), n, natural=False).modes):
            f[i, j], ld[i, j], wh[i, j] = md.frequency_hz, md.log_dec, md.whirl
    return CampbellData(speeds=s, frequency_hz=f, log_dec=ld, whirl=wh)


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
        span = np.hstack([_krylov_modes(lu, bands, n + _EXTRA, statics), statics])
        kr, mr = (span.T @ _band_matmul(band, parts.kl, parts.ku, span) for band in bands[:2])
        _, z = scipy.linalg.eigh((kr + kr.T) / 2, (mr + mr.T) / 2, check_finite=False)
        return span @ z
    mx = system.matrices(speed)
    ks = (mx.K + mx.K.T) / 2
    if n + _EXTRA + dofs.size >= size:
        _, phi = scipy.linalg.eigh(ks, mx.M, check_finite=False)
        return phi
    _, modes = scipy.linalg.eigh(ks, mx.M, subset_by_index=[0, n + _EXTRA - 1], check_finite=False)
    span = np.hstack([modes, np.linalg.solve(ks, unit)])
    _, z = scipy.linalg.eigh(span.T @ ks @ span, span.T @ mx.M @ span, check_finite=False)
    return span @ z


_EXTRA = 6
"""Undamped modes in the Ritz basis beyond the ``n`` wanted."""

_KRYLOV_SIZE = 120
"""Above this many free DOFs (and a narrow band) the undamped modes of the Ritz basis come from
a banded block Krylov space, not a dense ``O(N^3)`` eigen-solve."""


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


def _band_matmul(band: np.ndarray, kl: int, ku: int, x: np.ndarray) -> np.ndarray:
    """``a @ x`` for ``a`` in :func:`_to_band` storage (``a[i, j]`` at ``band[j, ku + i - j]``),
    ``kl`` sub- and ``ku`` super-diagonals (compiled: ``O(N (kl + ku) k)`` for ``k`` columns)."""
    x = np.ascontiguousarray(x, dtype=float)
    out = np.empty_like(x)
    band_matmul(np.ascontiguousarray(band), ku, x, out)
    return out


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


def _projected_lam(red: Reduced, idx: np.ndarray, n: int) -> np.ndarray:
    """The ``n`` lowest oscillating eigenvalues (1/s) of the projected problems at sweep
    indices ``idx`` (one batched ``numpy.linalg.eigvals``); NaN where there are fewer."""
    m = red.mr.shape[0]
    mr_inv = np.linalg.inv(red.mr)
    a = np.zeros((idx.size, 2 * m, 2 * m))
    a[:, :m, m:] = np.eye(m)
    a[:, m:, :m] = -mr_inv @ red.kr[idx]
    a[:, m:, m:] = -mr_inv @ red.dr[idx]
    lam = np.linalg.eigvals(a)
    lam = np.where(lam.imag > OSCILLATING * np.abs(lam), lam, np.nan)
    lam = np.take_along_axis(lam, np.argsort(np.where(np.isnan(lam), np.inf, lam.imag)), 1)
    out = np.full((idx.size, n), np.nan + 0j)
    out[:, : min(n, lam.shape[1])] = lam[:, :n]
    return out


def _ritz_starts(
    system: LinearSystem, parts: BandParts, speeds: np.ndarray, n: int, red: Reduced | None = None
):
    """Starting eigenpairs at every speed from a projection onto :func:`_ritz_basis`.

    The projected eigenvalues come from :func:`_projected_lam` and the projected shapes from one
    step of inverse iteration each (:func:`rubrotor.core.banded.ritz_vectors`, compiled;
    cheaper than batched eigenvectors). Returns ``lam0`` (S, n), NaN where fewer than ``n``
    oscillating modes were found, and ``vec0`` (S, n, N) on the free DOFs.
    """
    red = _reduced(system, parts, speeds, n) if red is None else red
    lam0 = _projected_lam(red, np.arange(speeds.size), n)
    return lam0, ritz_vectors(red.mr, red.dr, red.kr, lam0) @ red.phi.T


def _refined_modes(system: LinearSystem, speeds: np.ndarray, n: int):
    """Eigenvalues (S, n), shapes at the whirl stations (S, n, 2 stations) and a success mask.

    Starting values (:func:`_refine_chunk`) refined by Newton on the full banded quadratic
    eigenproblem (:func:`rubrotor.core.banded.refine_eigenpairs`) until a step is below
    ``1e-10 |lam|`` (quadratic convergence: the error after it is at rounding level); clusters of
    equal eigenvalues get the shapes of extreme whirl (as in :func:`damped_modes`).
    """
    parts = _band_parts(system, speeds)
    rows = _stations(system)[:, system.free]
    gather = _sparse_rows(rows)
    lam = np.full((speeds.size, n), np.nan + 0j)
    ok = np.zeros((speeds.size, n), bool)
    shapes = np.zeros((speeds.size, n, rows.shape[0]), complex)
    for c0 in range(0, speeds.size, 256):  # bounded memory for long sweeps
        sl = slice(c0, min(c0 + 256, speeds.size))
        sub = parts._replace(sup_k=parts.sup_k[sl], sup_c=parts.sup_c[sl])
        lam[sl], shapes[sl], ok[sl] = _refine_chunk(system, sub, speeds[sl], n, gather)
    order = np.argsort(np.where(np.isfinite(lam), lam.imag, np.inf), axis=1)
    lam = np.take_along_axis(lam, order, 1)
    shapes = np.take_along_axis(shapes, order[:, :, None], 1)
    eye = np.eye(rows.shape[0])
    for i, j0, j1 in _clusters(lam):
        shapes[i, j0:j1] = _circularise(eye, shapes[i, j0:j1].T).T
    return lam, shapes, ok


def _refine_chunk(system: LinearSystem, parts: BandParts, speeds: np.ndarray, n: int, gather):
    """The ``n`` lowest modes at every speed of one chunk: ``(lam, shapes, ok)`` unsorted.

    On a small rotor ``n + 1`` branches are followed (so that a branch crossing the ``n``-th from
    above is seen) and at every other speed (and the last) the starts are the projected
    eigenvalues
    (:func:`_projected_lam`); at the speeds in between they are the mean of the two refined
    neighbours (a two-sided interpolation, far closer than the projection), with the projected
    shapes at that value. Such a speed is redone from its projected eigenvalues when a branch
    was not smooth across it (neighbours more than 1e-2 apart), Newton failed, a value moved
    by more than 1e-3 from its start, or two starts met one eigenvalue."""
    red = _reduced(system, parts, speeds, n)
    size = speeds.size
    # small rotors only: there the projected eigenvalues cost more than the Newton steps of the
    # extra branch; on a large one (Newton dominant) every speed gets its projected starts
    between = size >= 5 and system.n_dof <= _KRYLOV_SIZE
    count = n + 1 if between else n
    lam = np.full((size, count), np.nan + 0j)
    shapes = np.zeros((size, count, gather.idx.shape[0]), complex)
    ok = np.zeros((size, count), bool)

    def solve(idx, lam0):
        found = np.isfinite(lam0)
        vec0 = ritz_vectors(red.mr, red.dr[idx], red.kr[idx], lam0) @ red.phi.T
        sub = parts._replace(sup_k=parts.sup_k[idx], sup_c=parts.sup_c[idx])
        start = Starts(np.where(found, lam0, 1j), vec0)
        ref = refine_eigenpairs(sub, speeds[idx], start, 1e-10, 8, gather)
        lam[idx] = np.where(found, ref.lam, np.nan)
        shapes[idx], ok[idx] = ref.shapes, (ref.steps > 0) | ~found

    key = np.unique(np.r_[0:size:2, size - 1]) if between else np.arange(size)
    solve(key, _projected_lam(red, key, count))
    odd = np.setdiff1d(np.arange(size), key)
    if odd.size:
        lo, hi = lam[odd - 1], lam[odd + 1]
        guess = (lo + hi) / 2
        smooth = np.abs(hi - lo) <= 1e-2 * np.abs(lo)  # False where NaN
        solve(odd, np.where(smooth | ~np.isfinite(lo), guess, np.nan + 0j))
        got = lam[odd]
        same = np.abs(got[:, :, None] - got[:, None, :]) <= 1e-7 * np.abs(got)[:, :, None]
        apart = np.abs(guess[:, :, None] - guess[:, None, :]) > 1e-5 * np.abs(guess)[:, :, None]
        moved = np.abs(got - guess) > 1e-3 * np.abs(guess)
        bad = (~smooth & np.isfinite(lo)) | ~ok[odd] | moved
        redo = odd[bad.any(axis=1) | (same & apart).any(axis=(1, 2))]
        if redo.size:
            solve(redo, _projected_lam(red, redo, count))
    order = np.argsort(np.where(np.isfinite(lam), lam.imag, np.inf), axis=1)[:, :n]
    return (
        np.take_along_axis(lam, order, 1),
        np.take_along_axis(shapes, order[:, :, None], 1),
        np.take_along_axis(ok, order, 1),
    )


def _sparse_rows(rows: np.ndarray) -> SparseRows:
    """``rows`` (R, N) as a :class:`~rubrotor.core.banded.SparseRows` gather (its nonzeros)."""
    nz = rows != 0
    width = max(1, int(nz.sum(axis=1).max(initial=1)))
    order = np.argsort(~nz, axis=1, kind="stable")[:, :width]
    val = np.take_along_axis(rows, order, 1).astype(complex)
    return SparseRows(np.ascontiguousarray(order, dtype=np.int64), np.ascontiguousarray(val))


def _clusters(lam: np.ndarray):
    """``(speed index, first, end)`` of each run of equal eigenvalues (within 1e-7) at a speed."""
    close = np.abs(np.diff(lam, axis=1)) <= 1e-7 * np.abs(lam[:, 1:])
    for i in np.flatnonzero(close.any(axis=1)):
        j = 0
        while j < lam.shape[1]:
            k = j + 1
            while k < lam.shape[1] and close[i, k - 1]:
                k += 1
            if k - j > 1:
                yield i, j, k
            j = k


def _whirl_labels(shapes: np.ndarray) -> np.ndarray:
    """The whirl of every shape at once (see the module docstring): ``shapes`` (..., 2 stations)
    holds ``V, W`` pairs. A station counts when its orbit is significant (``|V|^2 + |W|^2`` above
    1e-4 of the largest) and not flat (``|Im(conj(V) W)|`` above 1e-6 of it); ``"forward"`` or
    ``"backward"`` when all such stations turn that way, ``"mixed"`` otherwise or when none
    counts."""
    v, w = shapes[..., 0::2], shapes[..., 1::2]
    spin = np.imag(np.conj(v) * w)
    amp = np.abs(v) ** 2 + np.abs(w) ** 2
    big = amp > 1e-4 * amp.max(axis=-1, keepdims=True)
    turning = big & (np.abs(spin) > 1e-6 * amp)
    fwd = np.all(~turning | (spin < 0), axis=-1)
    bwd = np.all(~turning | (spin > 0), axis=-1)
    out = np.full(shapes.shape[:-1], "mixed", dtype=object)
    any_turn = turning.any(axis=-1)
    out[any_turn & fwd] = "forward"
    out[any_turn & bwd] = "backward"
    return out


CRITICALLY_DAMPED = 0.2
"""Damping ratio above which a critical speed is flagged as critically damped (no resonance to
avoid). API 684 (Tutorial on the API Standard Paragraphs Covering Rotor Dynamics, 2nd ed.) and
API 617 call a mode "critically damped" when its amplification factor ``AF < 2.5``; with the
single-mode estimate ``AF = 1 / (2 zeta)`` that is ``zeta > 0.2``. The estimate is the
half-power one (``AF = N_c / (N_2 - N_1)``) for a lightly damped mode; near 0.2 it is an
approximation, so a value close to the limit deserves the unbalance response's own peak."""


@dataclass(frozen=True)
class LinearCritical:
    """A critical speed: mode ``index`` (by frequency) crosses ``harmonic`` times the spin.

    Attributes
    ----------
    index : int
        Mode rank by frequency at the crossing.
    whirl : str
        Whirl of the mode at the crossing.
    harmonic : float
        The excitation order (1 for unbalance).
    speed_rad_s : float
        Spin speed (rad/s).
    damping_ratio : float
        Damping ratio ``zeta`` of the mode at the crossing (dimensionless).
    """

    index: int
    whirl: str
    harmonic: float
    speed_rad_s: float
    damping_ratio: float = float("nan")

    @property
    def critically_damped(self) -> bool:
        """True when ``damping_ratio > CRITICALLY_DAMPED`` (API 684's ``AF < 2.5``)."""
        return self.damping_ratio > CRITICALLY_DAMPED

    @property
    def speed_rpm(self) -> float:
        """The speed in rev/min."""
        return self.speed_rad_s * 60 / TWO_PI


def linear_critical_speeds(
    system: LinearSystem, max_speed: float, n: int = 6, harmonic: float = 1.0, points: int = 200
) -> list[LinearCritical]:
    """Speeds where a mode's damped frequency equals ``harmonic`` times the spin.

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    max_speed : float
        Upper end of the search (rad/s), > 0.
    n : int
        Modes searched (the lowest ``n``).
    harmonic : float
        Excitation order (> 0).
    points : int
        Scan points before the roots are refined by ``brentq`` (to 1e-10 relative).

    Returns
    -------
    list of LinearCritical
        Sorted by speed, each with the mode's damping ratio there; those above
        ``CRITICALLY_DAMPED`` are flagged by ``LinearCritical.critically_damped``.
    """
    max_speed = _check_speed("max_speed", max_speed)
    if max_speed <= 0 or not harmonic > 0:
        raise InputError("max_speed / harmonic", (max_speed, harmonic), "values > 0")
    grid = np.linspace(0.0, max_speed, points)
    data = campbell_data(system, grid, n=n)
    out = []
    for j in range(n):
        g = TWO_PI * data.frequency_hz[:, j] - harmonic * grid
        for i in np.flatnonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0):

            def h(w, j=j):  # the Campbell route itself, so the bracket's signs are g's
                one = campbell_data(system, [w, w * (1 + 1e-12) + 1e-12], n=n)
                d = one.log_dec[0, j]
                zeta = d / math.sqrt(4 * math.pi**2 + d * d)
                return TWO_PI * one.frequency_hz[0, j] - harmonic * w, one.whirl[0, j], zeta

            lo, hi = float(grid[i]), float(grid[i + 1])
            if not h(lo)[0] * h(hi)[0] < 0:  # a branch that appears or vanishes in between
                continue
            w = scipy.optimize.brentq(lambda x: h(x)[0], lo, hi, xtol=1e-12, rtol=1e-10)
            _, whirl, zeta = h(w)
            out.append(LinearCritical(j + 1, whirl, float(harmonic), float(w), float(zeta)))
    return sorted(out, key=lambda c: c.speed_rad_s)


def stability_threshold(
    system: LinearSystem, max_speed: float, n: int | None = None, points: int = 200
) -> float | None:
    """The lowest speed (rad/s) where a mode's damping ratio crosses zero, or None up to
    ``max_speed``.

    Parameters
    ----------
    system : LinearSystem
        The rotor (cross-coupled bearings or seals make thresholds).
    max_speed : float
        Upper end of the search (rad/s), > 0.
    n : int, optional
        Modes considered (default all).
    points : int
        Scan points; the crossing is refined by ``brentq`` to 1e-10 relative.

    Returns
    -------
    float or None
        The threshold speed (rad/s); 0.0 when the rotor is already unstable at rest.
    """
    max_speed = _check_speed("max_speed", max_speed)
    if n is not None and (isinstance(n, bool) or not isinstance(n, int) or n < 1):
        raise InputError("n", n, "a number of modes >= 1")

    def least(w):
        # the n lowest by frequency (the Campbell route): overdamped roots never set the least
        return min(m.damping_ratio for m in _modes(system, w, n, natural=False).modes)

    if least(0.0) < 0:
        return 0.0
    grid = np.linspace(0.0, max_speed, points)
    prev = grid[0]
    for w in grid[1:]:
        if least(float(w)) < 0:
            return float(scipy.optimize.brentq(least, prev, float(w), xtol=1e-12, rtol=1e-10))
        prev = float(w)
    return None


@dataclass(frozen=True)
class UnbalanceResponse:
    """Steady synchronous response to unbalance at probe positions.

    Attributes
    ----------
    speeds : ndarray, shape (S,)
        Spin speeds (rad/s).
    probes : ndarray, shape (P,)
        Probe positions (m).
    amplitude : ndarray, shape (S, P, 2)
        Amplitude of ``v`` and ``w`` (m).
    phase : ndarray, shape (S, P, 2)
        Phase of ``v`` and ``w`` (rad): ``v(t) = amplitude cos(Omega t + phase)``.
    major : ndarray, shape (S, P)
        Major semi-axis of the orbit (m).
    complex_response : ndarray, shape (S, P, 2), complex
        ``V``, ``W`` with ``v(t) = Re(V exp(i Omega t))`` (m).
    """

    speeds: np.ndarray
    probes: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    major: np.ndarray
    complex_response: np.ndarray


def _support_values(system: LinearSystem, speeds: np.ndarray):
    """Support entries on the free DOFs: rows, columns and their ``k`` (N/m), ``c`` (N s/m) at
    every speed (rad/s), as :meth:`Support.tabulate` gives them (linked supports expanded)."""
    pos = np.full(len(system.M), -1)
    pos[system.free] = np.arange(system.free.size)
    rows, cols, kv, cv = [], [], [], []
    for sup in system.supports:
        ks, cs = (sup.block(a) for a in sup.tabulate(speeds))
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


def _band_parts(system: LinearSystem, speeds: np.ndarray) -> BandParts:
    """The rotor's matrices on the free DOFs in band storage, and its supports over ``speeds``.

    An FE rotor couples neighbouring nodes only, so its bandwidth is a few DOFs and a banded
    LU costs ``O(n b^2)``; a dense system (e.g. a modal one) is simply a band as wide as the
    matrix.
    """
    mats = [system.M, system.G, system.K, system.C]
    if system.fixed:
        f = np.ix_(system.free, system.free)
        mats = [a[f] for a in mats]
    rows, cols, k, c = _support_values(system, speeds)
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


def unbalance_response(system: LinearSystem, speeds, unbalances, probes) -> UnbalanceResponse:
    """Steady response to rotating unbalance, solved in the frequency domain.

    Each unbalance ``(position m, magnitude kg m, phase rad)`` is a force
    ``F_y + i F_z = m e Omega^2 exp(i (Omega t + phase))`` turning with the spin. On the real DOFs
    ``f(t) = Re(Fc exp(i Omega t))`` with ``Fc = B(x) [1, -i] m e Omega^2 exp(i phase)``, and the
    response ``q = Re(Q exp(i Omega t))`` solves
    ``(K(Omega) - Omega^2 M + i Omega (C(Omega) + Omega G)) Q = Fc`` at each speed (one exact LU
    solve per speed, banded for FE rotors, all speeds in one compiled loop).

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    speeds : array_like
        Increasing spin speeds (rad/s), > 0.
    unbalances : sequence of (float, float, float)
        ``(position m, magnitude kg m, phase rad)`` per plane.
    probes : sequence of float
        Probe positions (m).

    Returns
    -------
    UnbalanceResponse
    """
    s = _speed_array("speeds", speeds)
    if not unbalances:
        raise InputError("unbalances", unbalances, "at least one (position m, kg m, rad) plane")
    b = np.zeros(system.n_dof, complex)
    for pos, me, ph in unbalances:
        if not (math.isfinite(me) and me >= 0 and math.isfinite(ph)):
            raise InputError("unbalance", (pos, me, ph), "magnitude >= 0 (kg m), finite phase")
        b += system.force_map(pos) @ np.array([1.0, -1j]) * me * np.exp(1j * ph)
    if not len(probes):
        raise InputError("probes", probes, "at least one probe position (m)")
    rows = np.concatenate([system.output_rows(p) for p in probes]).astype(complex)
    out, status, at = unbalance_sweep(_band_parts(system, s), s, b, rows)
    if status != OK:
        raise InputError("speeds", float(s[at]), "speeds off the undamped critical speeds (rad/s)")
    resp = out.reshape(s.size, len(probes), 2)
    v, w_ = resp[..., 0], resp[..., 1]
    # orbit semi-axes of v = Re(V e^{it}), w = Re(W e^{it}): |(V + i W)|/2 +- |(V - i W)|/2
    major = 0.5 * (np.abs(v + 1j * w_) + np.abs(v - 1j * w_))
    return UnbalanceResponse(
        speeds=s,
        probes=np.asarray(probes, float),
        amplitude=np.abs(resp),
        phase=np.angle(resp),
        major=major,
        complex_response=resp,
    )
