"""The short film's parameter structure and cavitation codes, apart from its kernels.

Importing this module compiles nothing and imports no numba: the film supports' terms
(:mod:`rubrotor.forces.fluid_film`) are built by every scenario that has one, and the linear
verbs start without numba's import (the kernels, :mod:`rubrotor.core.film`, load on first use).
"""

from collections import namedtuple

__all__ = ["Film", "FULL_FILM", "PI_FILM"]

FULL_FILM = 0
"""Cavitation code: the film carries negative pressures (the whole circle, Sommerfeld)."""

PI_FILM = 1
"""Cavitation code: negative pressures set to zero (Gumbel, half-Sommerfeld, pi-film)."""

Film = namedtuple("Film", "radius length clearance viscosity cavitation")
"""Short-film parameters in SI (see :mod:`rubrotor.core.film`)."""
