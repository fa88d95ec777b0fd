"""Campbell diagram with stability of any :class:`~rubrotor.rotors.linear.LinearSystem`: the
frequencies, logarithmic decrements and whirl of its lowest modes over a sweep of spin speeds.

Starting values from a projection onto the rotor's lowest undamped modes
(:mod:`rubrotor.linear.band`) are refined by Newton's method on the full banded quadratic
eigenproblem (LAPACK banded LU, :mod:`rubrotor.linear.lapack`); a speed where Newton fails takes the dense route of
:func:`rubrotor.linear.modes.damped_modes`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubrotor.core.bandtypes import BandParts, Starts
from rubrotor.errors import InputError
from rubrotor.linear.band import _KRYLOV_SIZE, _band_parts, _projected_lam, _reduced, _sparse_rows
from rubrotor.linear.lapack import refine_eigenpairs, ritz_vectors
from rubrotor.linear.modes import _modes
from rubrotor.linear.roots import (
    OVERDAMPED,
    TWO_PI,
    _circularise,
    _clusters,
    _speed_array,
    _stations,
    _whirl_labels,
)
from rubrotor.rotors.linear import LinearSystem, check_table_axes

__all__ = ["CampbellData", "campbell_data"]


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

    def to_dict(self) -> dict:
        """JSON form printed by ``rubrotor campbell --json`` (without its ``figure`` key)."""
        return {
            "speed_rad_s": self.speeds.tolist(),
            "frequency_hz": self.frequency_hz.tolist(),
            "log_dec": self.log_dec.tolist(),
            "whirl": self.whirl.tolist(),
        }


def campbell_data(system: LinearSystem, speeds, n: int = 8) -> CampbellData:
    """Frequencies, logarithmic decrements and whirl of the ``n`` lowest modes over ``speeds``.

    Each eigenpair is exact (the same eigenvalues as
    :func:`~rubrotor.linear.modes.damped_modes`, to ~1e-12): a projection onto the rotor's lowest
    undamped modes gives starting values at every speed
    (one batched small eigen-solve), which Newton's method on the full quadratic eigenproblem
    refines with LAPACK banded LU solves. A speed where Newton fails falls back
    to the dense route.

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    speeds : array_like
        Increasing spin speeds (rad/s).
    n : int
        Number of modes (the lowest at each speed; branches are sorted by frequency, so two
        crossing branches swap rows at their crossing). Overdamped roots (``Im(lam) <=
        OVERDAMPED |lam|``, log dec >= 628) are not modes and take no row; ``damped_modes``
        lists them, marked.

    Returns
    -------
    CampbellData
    """
    s = _speed_array("speeds", speeds)
    check_table_axes(system, "campbell_data", speed=s, frequency=s)
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise InputError("n", n, "a number of modes >= 1")
    lam, shapes, ok = _refined_modes(system, s, n)
    with np.errstate(invalid="ignore"):  # Newton landed on an overdamped root: redo densely
        ok = ok & (lam.imag > OVERDAMPED * np.abs(lam))
    f = np.full((s.size, n), np.nan)
    ld = np.full((s.size, n), np.nan)
    wh = np.full((s.size, n), "", dtype=object)
    good = ok & np.isfinite(lam)
    f[good] = lam[good].imag / TWO_PI
    ld[good] = -TWO_PI * lam[good].real / lam[good].imag
    wh[good] = _whirl_labels(shapes)[good]
    for i in np.flatnonzero(~ok.all(axis=1)):  # Newton failed somewhere: the dense route
        f[i], ld[i], wh[i] = np.nan, np.nan, ""
        for j, md in enumerate(_dense_modes(system, float(s[i]), n)):
            f[i, j], ld[i, j], wh[i, j] = md.frequency_hz, md.log_dec, md.whirl
    return CampbellData(speeds=s, frequency_hz=f, log_dec=ld, whirl=wh)


def _dense_modes(system: LinearSystem, speed: float, n: int) -> list:
    """The ``n`` lowest modes by frequency at ``speed`` (rad/s), overdamped roots left out
    (``Im <= OVERDAMPED |lam|``: log dec >= 628, nothing oscillates; heavy element damping
    makes them, e.g. ROSS's AMB rotor, whose 183 and 335 rad/s modes they pushed out of the
    rows), by the dense route of :func:`~rubrotor.linear.modes.damped_modes`."""
    count = n
    while True:
        found = _modes(system, speed, count, natural=False).modes
        kept = [m for m in found if not m.overdamped]
        if len(kept) >= n or len(found) < count:
            return kept[:n]
        count += n


def _refined_modes(system: LinearSystem, speeds: np.ndarray, n: int):
    """Eigenvalues (S, n), shapes at the whirl stations (S, n, 2 stations) and a success mask.

    Starting values (:func:`_refine_chunk`) refined by Newton on the full banded quadratic
    eigenproblem (:func:`rubrotor.linear.lapack.refine_eigenpairs`) until a step is below
    ``1e-10 |lam|`` (quadratic convergence: the error after it is at rounding level); clusters of
    equal eigenvalues get the shapes of extreme whirl (as in :func:`~rubrotor.linear.modes.damped_modes`).
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
    solve(key, _projected_lam(red, key, count, OVERDAMPED))
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
            solve(redo, _projected_lam(red, redo, count, OVERDAMPED))
    order = np.argsort(np.where(np.isfinite(lam), lam.imag, np.inf), axis=1)[:, :n]
    return (
        np.take_along_axis(lam, order, 1),
        np.take_along_axis(shapes, order[:, :, None], 1),
        np.take_along_axis(ok, order, 1),
    )
