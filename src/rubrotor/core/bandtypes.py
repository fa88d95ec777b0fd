"""The named structures of the banded kernels (:mod:`rubrotor.core.banded`), apart from them.

Importing this module compiles nothing and imports no numba: the linear verbs' LAPACK route
(:mod:`rubrotor.linear.lapack`) and the modes and Campbell front ends use these structures
without loading the compiled kernels, so that ``rubrotor modes`` starts without numba's import.
"""

from collections import namedtuple

__all__ = ["BandParts", "Refined", "SparseRows", "Starts"]

BandParts = namedtuple("BandParts", "m g k c kl ku sup_row sup_col sup_k sup_c")
Starts = namedtuple("Starts", "lam vec")
Starts.__doc__ = """Starting eigenvalues ``lam`` (S, n) (1/s) and eigenvectors ``vec`` (S, n, N)."""

Refined = namedtuple("Refined", "lam shapes steps")
Refined.__doc__ = """Refined eigenvalues (S, n) (1/s), eigenvectors at output rows (S, n, R), and
Newton steps (S, n), negative where the iteration did not converge."""

SparseRows = namedtuple("SparseRows", "idx val")
SparseRows.__doc__ = """Output rows as a gather: row ``r`` of ``R x`` is ``sum_k val[r, k] x[idx[r, k]]``.

``idx`` (R, w) int64 and ``val`` (R, w) complex, padded with zero values; a nodal station picks
one DOF (``w = 1``), so the whirl shapes of a large rotor cost a few operations per station
instead of a dense ``R x N`` product."""

BandParts.__doc__ = """The speed-independent band parts of ``M, G, K, C`` and the support entries.

m, g, k, c : ndarray, shape (n, kl + ku + 1)
    Compact band storage (``a[i, j]`` at ``[j, ku + i - j]``) of mass (kg), gyroscopic per unit
    spin (kg m^2), shaft stiffness (N/m) and shaft damping (N s/m) on the free DOFs.
kl, ku : int
    Numbers of sub- and super-diagonals.
sup_row, sup_col : ndarray of int64, shape (P,)
    Matrix row and column of each support entry.
sup_k, sup_c : ndarray, shape (S, P)
    Support stiffness (N/m) and damping (N s/m) of each entry at each speed of the sweep.
"""
