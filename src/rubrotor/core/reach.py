"""Largest distance of elliptic orbits from a point: the linear rub screen's kernel.

For each orbit ``p(theta) = d + a cos(theta) + b sin(theta)`` (2-vectors, m),
``f = |p|^2 = c0 + c1 cos + s1 sin + c2 cos 2theta + s2 sin 2theta`` is a trigonometric
polynomial of degree 2, with at most two maxima. It is sampled at ``GRID`` angles and refined
by Newton's method from the two best sampled local maxima (error at round-off level).
Compiled on first call (cached), never at import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["GRID", "reach_kernel"]

GRID = 32


@njit(cache=True, inline="always")
def _refine(c0, c1, s1, c2, s2, t):
    cs, sn = math.cos(t), math.sin(t)
    for _ in range(4):
        c2t, s2t = cs * cs - sn * sn, 2 * sn * cs
        d1 = -c1 * sn + s1 * cs - 2 * c2 * s2t + 2 * s2 * c2t
        d2 = -c1 * cs - s1 * sn - 4 * c2 * c2t - 4 * s2 * s2t
        if d2 >= 0:
            break
        t += min(0.2, max(-0.2, -d1 / d2))
        cs, sn = math.cos(t), math.sin(t)
    c2t, s2t = cs * cs - sn * sn, 2 * sn * cs
    return c0 + c1 * cs + s1 * sn + c2 * c2t + s2 * s2t


@njit(cache=True)
def reach_kernel(d, ure, uim, out):  # pragma: no cover - compiled
    """``out[k] = max_theta |d[k] + ure[k] cos - uim[k] sin|`` (m) for orbits ``k``.

    Parameters
    ----------
    d, ure, uim : ndarray, shape (K, 2)
        Orbit centres, real and imaginary parts of ``[V, W]`` (m).
    out : ndarray, shape (K,)
        Receives the largest distances (m).
    """
    h = 2 * math.pi / GRID
    f = np.empty(GRID)
    cg = np.cos(np.arange(GRID) * h)
    sg = np.sin(np.arange(GRID) * h)
    c2g = np.cos(2 * np.arange(GRID) * h)
    s2g = np.sin(2 * np.arange(GRID) * h)
    for k in range(d.shape[0]):
        a0, a1 = ure[k, 0], ure[k, 1]
        b0, b1 = -uim[k, 0], -uim[k, 1]
        aa, bb, ab = a0 * a0 + a1 * a1, b0 * b0 + b1 * b1, a0 * b0 + a1 * b1
        c0 = d[k, 0] * d[k, 0] + d[k, 1] * d[k, 1] + 0.5 * (aa + bb)
        c1 = 2 * (d[k, 0] * a0 + d[k, 1] * a1)
        s1 = 2 * (d[k, 0] * b0 + d[k, 1] * b1)
        c2, s2 = 0.5 * (aa - bb), ab
        i1, i2 = 0, -1
        for j in range(GRID):
            f[j] = c0 + c1 * cg[j] + s1 * sg[j] + c2 * c2g[j] + s2 * s2g[j]
            if f[j] > f[i1]:
                i1 = j
        for j in range(GRID):
            if j != i1 and f[j] >= f[j - 1] and f[j] >= f[(j + 1) % GRID]:
                if i2 < 0 or f[j] > f[i2]:
                    i2 = j
        best = max(f[i1], _refine(c0, c1, s1, c2, s2, i1 * h))
        if i2 >= 0:
            best = max(best, _refine(c0, c1, s1, c2, s2, i2 * h))
        out[k] = math.sqrt(max(best, 0.0))
