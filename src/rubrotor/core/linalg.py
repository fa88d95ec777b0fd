"""Small dense real solves inside the compiled engines (the contact Newton matrices, m x m).

One elimination kernel, :func:`lu_solve`, serves the engine's implicit contact solve
(:mod:`rubrotor.core.engine`) and, column by column, the inverse the variational map needs
(:func:`invert`, :mod:`rubrotor.core.engine_tangent`).
"""

import numpy as np
from numba import njit

__all__ = ["lu_solve", "invert"]


@njit(cache=True, inline="always")
def lu_solve(a, b):
    """Solve ``a x = b`` in place (``b`` gets ``x``, ``a`` is overwritten) by Gaussian
    elimination with partial pivoting (Cramer's rule for ``2 x 2``); False if ``a`` is singular
    (a zero pivot or determinant)."""
    n = b.shape[0]
    if n == 2:
        det = a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]
        if det == 0.0:
            return False
        x0 = (a[1, 1] * b[0] - a[0, 1] * b[1]) / det
        b[1] = (-a[1, 0] * b[0] + a[0, 0] * b[1]) / det
        b[0] = x0
        return True
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(a[i, k]) > abs(a[p, k]):
                p = i
        if a[p, k] == 0.0:
            return False
        if p != k:
            for j in range(n):
                a[k, j], a[p, j] = a[p, j], a[k, j]
            b[k], b[p] = b[p], b[k]
        for i in range(k + 1, n):
            f = a[i, k] / a[k, k]
            for j in range(k, n):
                a[i, j] -= f * a[k, j]
            b[i] -= f * b[k]
    for k in range(n - 1, -1, -1):
        s = b[k]
        for j in range(k + 1, n):
            s -= a[k, j] * b[j]
        b[k] = s / a[k, k]
    return True


@njit(cache=True)
def invert(a, inv):
    """``inv <- a^-1`` (m x m real) by :func:`lu_solve` on the unit columns; False if singular.

    ``a`` is left unchanged. For ``m = 2`` the unit columns go through :func:`lu_solve`'s
    ``2 x 2`` arithmetic written out (the same rounding, no work arrays).
    """
    m = a.shape[0]
    if m == 2:
        det = a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]
        if det == 0.0:
            return False
        for c in range(2):
            b0 = 1.0 if c == 0 else 0.0
            b1 = 1.0 - b0
            inv[0, c] = (a[1, 1] * b0 - a[0, 1] * b1) / det
            inv[1, c] = (-a[1, 0] * b0 + a[0, 0] * b1) / det
        return True
    w = np.empty_like(a)
    col = np.empty(m)
    for c in range(m):
        w[:, :] = a
        col[:] = 0.0
        col[c] = 1.0
        if not lu_solve(w, col):
            return False
        for r in range(m):
            inv[r, c] = col[r]
    return True
