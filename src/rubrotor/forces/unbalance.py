"""Unbalance force term: mass unbalance planes rotating with the spin.

The force of a plane ``m e`` (kg m) at angle ``phase`` (rad) is ``Re``/``Im`` of
``m e Omega^2 e^{i (Omega t + phase)}`` (N); at a constant speed the engine carries it as a
particular solution, at a varying speed as an input (``rubrotor.engine.structs.Drive``). It has
no state and no output variable of its own (the spin angle is the run's).
"""

from __future__ import annotations

import math

import numpy as np

from rubrotor.errors import InputError

__all__ = ["unbalance_phasor", "unbalance_load"]


def unbalance_phasor(u, speed: float) -> complex:
    """``m e Omega^2 e^{i phase}`` (N): the force is ``Re`` / ``Im`` of it times ``e^{i Omega t}``."""
    return u.magnitude * speed**2 * complex(math.cos(u.phase), math.sin(u.phase))


def unbalance_load(system, unbalances, speed: float) -> np.ndarray:
    """Complex load vector ``b_u`` (N) on the free DOFs at ``speed`` (rad/s): the force is
    ``Re(b_u e^{i Omega t})``."""
    b_u = np.zeros(len(system.free), complex)
    for u in unbalances:
        if u.position is None:
            raise InputError("unbalance.position", None, "an axial position (m)")
        b_u += unbalance_phasor(u, speed) * (system.force_map(u.position) @ np.array([1, -1j]))
    return b_u
