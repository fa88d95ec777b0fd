"""The command line, ``rubrotor VERB SCENARIO [options]`` (:mod:`rubrotor.cli.app`: the verb table and ``main``).

The command runs its BLAS on one thread unless the environment says otherwise
(``OPENBLAS_NUM_THREADS``, ``MKL_NUM_THREADS``; numba's own threads are not touched): rubrotor's linear algebra
is banded or small and dense, where a second BLAS thread gains little on a quiet machine but, on
a busy one, spins against the other processes and made `rubrotor critical general_rotor.toml`
cost 49 s of CPU instead of 4.6 s (measured, 2 cores). Set on first use of the command line,
before NumPy is imported; a program that imported NumPy itself keeps its own setting.
"""

import os
import sys


def _one_blas_thread() -> None:
    if "numpy" in sys.modules:
        return
    for var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")


def __getattr__(name):
    import importlib

    _one_blas_thread()
    module = importlib.import_module("rubrotor.cli.app")

    try:
        return getattr(module, name)
    except AttributeError:
        raise AttributeError(f"module 'rubrotor.cli' has no attribute {name!r}") from None
