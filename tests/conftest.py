"""Test-session setup: one BLAS thread per test process.

The suite runs with ``pytest -n 2`` (two worker processes on a 2-core machine); a threaded
OpenBLAS in each worker oversubscribes the cores and makes small dense eigen-solves 20-30x
slower under load. Set before NumPy is imported (an explicit setting in the environment wins).
"""

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
