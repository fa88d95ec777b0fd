"""Sobol' sensitivity indices from a Saltelli design: first-order (Saltelli 2010) and total (Jansen).

With ``f_A``, ``f_B`` the model at the rows of the independent matrices ``A`` and ``B``
(``N`` rows each) and ``f_ABi`` at ``A`` with column ``i`` taken from ``B``:

* variance ``V = var([f_A, f_B])``;
* first-order ``S_i = mean(f_B (f_ABi - f_A)) / V`` (Saltelli et al. 2010, Comput. Phys.
  Commun. 181, 259, table 2 (b));
* total ``S_Ti = mean((f_A - f_ABi)^2) / (2 V)`` (Jansen 1999, table 2 (f) of the same paper).

Intervals: percentiles of the estimators over bootstrap resamples of the ``N`` rows (the same
rows for every term), the rows treated as independent: for scrambled Sobol' points, whose
errors are smaller than independent sampling's, the interval is conservative.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError

__all__ = ["SobolIndices", "sobol_indices"]


@dataclass(frozen=True)
class SobolIndices:
    """First-order and total Sobol' indices with their bootstrap intervals.

    Attributes
    ----------
    first, total : ndarray, shape (d,)
        ``S_i`` and ``S_Ti`` (1).
    first_interval, total_interval : ndarray, shape (d, 2)
        Lower and upper bounds at ``confidence`` (1).
    variance : float
        ``V`` (the output's unit squared).
    confidence : float
        Confidence level of the intervals.
    """

    first: np.ndarray
    total: np.ndarray
    first_interval: np.ndarray
    total_interval: np.ndarray
    variance: float
    confidence: float


def _estimate(fa, fb, fab):
    v = np.var(np.concatenate([fa, fb], axis=-1), axis=-1, ddof=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        first = np.mean(fb[..., None, :] * (fab - fa[..., None, :]), axis=-1) / v[..., None]
        total = 0.5 * np.mean((fa[..., None, :] - fab) ** 2, axis=-1) / v[..., None]
    return first, total, v


def sobol_indices(fa, fb, fab, confidence: float = 0.95, resamples: int = 300,
                  seed: int = 0) -> SobolIndices:  # fmt: skip
    """Sobol' indices of one scalar output from the Saltelli design's evaluations.

    Parameters
    ----------
    fa, fb : array_like, shape (N,)
        The output at the rows of ``A`` and of ``B`` (any unit).
    fab : array_like, shape (d, N)
        The output at ``A_B^(i)``, ``i = 1..d``.
    confidence : float
        Level of the bootstrap intervals, in (0, 1).
    resamples : int
        Bootstrap resamples (>= 10).
    seed : int
        Seed of the resampling.

    Returns
    -------
    SobolIndices
        NaN indices and intervals when the output does not vary.
    """
    fa, fb, fab = (np.asarray(x, float) for x in (fa, fb, fab))
    n = fa.size
    if fb.shape != (n,) or fab.ndim != 2 or fab.shape[1] != n or n < 2:
        raise InputError("fab", fab.shape, "(d, N) beside fa, fb of shape (N,), N >= 2")
    if not 0 < confidence < 1:
        raise InputError("confidence", confidence, "a level in (0, 1)")
    first, total, v = _estimate(fa, fb, fab)
    if not v > 0:  # a constant output: no index is defined
        nan = np.full((fab.shape[0], 2), np.nan)
        return SobolIndices(first * np.nan, total * np.nan, nan, nan.copy(), float(v),
                            float(confidence))  # fmt: skip
    rng = np.random.default_rng(seed)
    fs, ts = [], []
    for _ in range(max(10, int(resamples))):
        i = rng.integers(0, n, n)
        f1, t1, _ = _estimate(fa[i], fb[i], fab[:, i])
        fs.append(f1)
        ts.append(t1)
    q = [50 * (1 - confidence), 50 * (1 + confidence)]
    return SobolIndices(first, total, np.nanpercentile(fs, q, axis=0).T,
                        np.nanpercentile(ts, q, axis=0).T, float(v), float(confidence))  # fmt: skip
