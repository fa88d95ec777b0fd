"""Constant load terms: point loads and gravity, the static part of the engine's forces.

Both are constant forces, so the engine carries them as the static deflection ``K^-1 f_s`` about
which it integrates; they have no state and no output variable of their own.
"""

from __future__ import annotations

import math

import numpy as np

from rubrotor.errors import InputError

__all__ = ["static_load"]


def _num(field: str, value, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise InputError(field, value, f"a number ({unit})")
    v = float(value)
    if not math.isfinite(v):
        raise InputError(field, value, f"a finite number ({unit})")
    return v


def static_load(system, loads=(), gravity=(0.0, 0.0)) -> np.ndarray:
    """Constant generalised force (N) on the free DOFs: point loads plus gravity.

    Gravity ``(g_y, g_z)`` (m/s^2) is ``M r`` with ``r`` the rigid translation along ``g``:
    the consistent load of the distributed shaft mass and the disk masses. It needs DOF labels
    ``"v@..."``/``"w@..."`` (as the finite-element builder makes them). ``loads`` are
    :class:`rubrotor.rotors.forces.RadialLoad` (N at a position in m).
    """
    f = np.zeros(system.M.shape[0])
    gy, gz = (_num("gravity.y", gravity[0], "m/s^2"), _num("gravity.z", gravity[1], "m/s^2"))
    if gy or gz:
        labels = system.dof_labels
        if len(labels) != len(f):
            raise InputError("gravity", gravity, "a rotor with labelled DOFs (v@x, w@x)")
        r = np.array(
            [gy if s.startswith("v@") else gz if s.startswith("w@") else 0.0 for s in labels]
        )
        f += system.M @ r
    f = f[system.free]
    for ld in loads:
        if ld.position is None:
            raise InputError("load.position", None, "an axial position (m)")
        f += system.force_map(ld.position) @ np.array([ld.force_y, ld.force_z])
    return f
