"""Damped modes of any :class:`~rubrotor.rotors.linear.LinearSystem` at one spin speed:
frequencies, damping ratios, logarithmic decrements, whirl and shapes.

The conventions (which roots are modes, how whirl is judged) are those of
:mod:`rubrotor.linear.roots`. Three routes give the eigenpairs: dense on a small system, Newton
on the banded quadratic eigenproblem from projected starts (:mod:`rubrotor.linear.band`) when a
few modes of a large one are wanted, shift-invert Arnoldi otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
import scipy.sparse.linalg

from rubrotor.core.bandtypes import SparseRows, Starts
from rubrotor.errors import InputError
from rubrotor.linear.band import Reduced, _band_parts, _reduced, _ritz_starts
from rubrotor.linear.lapack import refine_eigenpairs, ritz_vectors
from rubrotor.linear.roots import (
    OSCILLATING,
    OVERDAMPED,
    TWO_PI,
    _check_speed,
    _circularise,
    _real_made_real,
    _select,
    _stations,
    _whirl_labels,
)
from rubrotor.rotors.linear import LinearSystem

__all__ = ["DampedMode", "DampedModes", "damped_modes", "ORDERS"]


@dataclass(frozen=True)
class DampedMode:
    """One damped mode at one speed.

    Attributes
    ----------
    index : int
        1-based rank in the order :func:`damped_modes` was asked for (ROSS's, or by undamped
        natural frequency ``|lambda|``).
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
    shape: np.ndarray = field(repr=False)  # printed as its size only (see __repr__)

    def __repr__(self) -> str:
        return (f"DampedMode(index={self.index}, frequency_hz={self.frequency_hz:.6g}, "
                f"damping_ratio={self.damping_ratio:.4g}, log_dec={self.log_dec:.4g}, "
                f"whirl={self.whirl!r}, eigenvalue={self.eigenvalue:.6g}, "
                f"shape=<{self.shape.size} DOFs>)")  # fmt: skip

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

    def __repr__(self) -> str:
        rows = "".join(f"\n  {m!r}," for m in self.modes[:8])
        more = f"\n  ... {len(self.modes) - 8} more" if len(self.modes) > 8 else ""
        return f"DampedModes(speed_rad_s={self.speed_rad_s:.6g}, modes=({rows}{more}))"

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
            try:
                lam, vec = _eig_nearest_zero(mx, k)
            except scipy.sparse.linalg.ArpackError:  # no convergence from its random start
                lam = None  # (seen with a density of 1e-9): the dense route below
                break
    if lam is None:
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
    iteration at the eigenvalue: :func:`rubrotor.linear.lapack.ritz_vectors`). ``None``
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
    """The ``n`` lowest modes at ``speed`` (rad/s) as
    :func:`~rubrotor.linear.campbell.campbell_data` finds them, with full eigenvectors on the free
    DOFs, by frequency or (``natural``) by ``|lam|``; ``None`` when a check fails (fewer than
    ``n`` projected modes, with ``natural`` a projection that ranks otherwise
    (:func:`_ranks_alike`) or an overdamped result, Newton not converged, a start that moved by
    more than 1e-3 of itself, or two starts that converged to one eigenvalue), so that the
    caller takes another route."""
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
    ref = refine_eigenpairs(parts, speeds, Starts(lam0, vec0), 1e-10, 8, every)
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


ORDERS = ("ross", "natural")
"""How :func:`damped_modes` selects and orders the modes."""
ROSS_SHIFT = 1.0
"""ROSS 3.1's shift ``sigma`` (1/s) of its sparse eigen-solve (``run_modal``)."""


def damped_modes(
    system: LinearSystem, speed: float = 0.0, n: int | None = None, order: str = "natural"
) -> DampedModes:
    """Damped modes of a linear rotor at one spin speed.

    Parameters
    ----------
    system : LinearSystem
        The rotor (see ``rubrotor.rotors.linear``).
    speed : float
        Spin speed ``Omega`` (rad/s), ``>= 0``.
    n : int, optional
        Keep ``n`` modes (default: all).
    order : {"natural", "ross"}
        ``"ross"``: selected and ordered as ROSS 3.1's ``run_modal`` (sparse, its default)
        does, in two steps (``rubrotor modes`` uses it by default). (1) Selection: the ``4 n`` eigenvalues nearest ROSS's
        shift ``sigma = 1`` 1/s (ROSS asks ARPACK for ``2 num_modes`` of them, with
        ``num_modes = 2 n``; all eigenvalues when ``n`` is None), those with ``|lambda| > 0.1``
        1/s. (2) Order (ROSS's ``Rotor._index``): positive damped frequencies first, by damped
        frequency ``Im(lambda)``, then by ``|lambda|``; then the real roots (by ``|lambda|``);
        the first ``n`` are kept (ROSS's negative-frequency conjugates are left out). ROSS's
        candidates also hold its axial and torsional roots, which rubrotor does not model:
        where those are among ROSS's ``4 n`` nearest, ROSS's lateral candidates are fewer, so
        an overdamped root (``Im <= OVERDAMPED |lambda|``, damping ratio >= 0.99995: nothing
        oscillates) that ROSS's shorter list leaves out would here come first by its tiny
        damped frequency; such roots are therefore ordered with the real roots, after the
        oscillating modes (the one place this order departs from ROSS's ``_index``).
        ``"natural"`` (default, what every analysis built on the modes uses): the ``n`` modes of
        least undamped natural frequency ``|lambda|``, in that order, then the real and nearly
        real roots up to the last one's ``|lambda|`` (not ROSS's order: where a heavily damped
        mode has a lower damped frequency but a larger ``|lambda|`` than a lighter one, ROSS
        lists it first).

    Returns
    -------
    DampedModes
        Frequencies (Hz), damping ratios, logarithmic decrements, whirl and shapes in the chosen
        order; real roots and roots with ``Im(lambda) <= OVERDAMPED |lambda|`` are marked
        ``DampedMode.overdamped``.

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
    if order not in ORDERS:
        raise InputError("order", order, " or ".join(f'"{o}"' for o in ORDERS))
    return _modes(system, speed, n, natural=True, ross=order == "ross")


def _ross_eig(system: LinearSystem, speed: float, n: int | None):
    """Eigenvalues and ``q`` eigenvectors selected and ordered as ROSS 3.1 (see
    :func:`damped_modes`, ``order="ross"``): dense on a small system, else shift-invert
    Arnoldi for the ``4 n + 8`` eigenvalues nearest zero, of which the ``4 n`` nearest
    :data:`ROSS_SHIFT` are ROSS's candidates."""
    mx = system.matrices(speed)
    size = 2 * system.n_dof
    if n is not None and size > 16 * n:
        lam, vec = _eig_nearest_zero(mx, min(4 * n + 8, size - 2))
    else:
        lam, vec = scipy.linalg.eig(mx.first_order()[0], check_finite=False)
    if n is not None:
        near = np.argsort(np.abs(lam - ROSS_SHIFT), kind="stable")[: 4 * n]
        lam, vec = lam[near], vec[:, near]
    keep = np.abs(lam) > 0.1
    lam, vec = _real_made_real(lam[keep]), vec[:, keep]
    r = np.round(lam, 10)
    sign = np.where(r.imag > 0, 0, np.where(r.imag == 0, 1, 2))
    sign[(sign == 0) & (r.imag <= OVERDAMPED * np.abs(r))] = 1  # overdamped: with the real roots
    idx = np.lexsort((np.abs(r), r.imag, sign))
    idx = idx[sign[idx] < 2][:n]
    return lam[idx], vec[: system.n_dof, idx]


def _modes(
    system: LinearSystem, speed: float, n: int | None, natural: bool, ross: bool = False
) -> DampedModes:
    """:func:`damped_modes` ranked by ``|lambda|`` (``natural``, real roots kept), as ROSS
    (``ross``) or, for the Campbell rows, by ``Im(lambda)`` (oscillating modes only)."""
    lam, vec = _ross_eig(system, speed, n) if ross else _eig(system, speed, n, natural)
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
