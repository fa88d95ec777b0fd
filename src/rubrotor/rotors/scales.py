"""How far each input of a finite-element rotor sits from the rotor's own scale.

A bearing coefficient of ``-1.5e100`` N/m, a damping of ``5e304`` N s/m or a density of
``0.0078`` kg/m^3 is a valid number, but the eigenproblems of the rotor then lose every digit
(junk modes, or none) or their eigenvectors stop being independent. The error must name the key
that does it, not the speed. Each input is compared with the scale the assembled shaft gives:

* bearing stiffness ``|k|`` (N/m) against ``k_s``, the largest deflection diagonal of the
  shaft's own stiffness matrix (about ``24 E I / h^3`` of its stiffest elements);
* bearing damping ``|c|`` (N s/m) against ``sqrt(k_s m_s)``, ``m_s`` the median deflection
  diagonal of the mass matrix (kg): the critical damping of one node on the shaft;
* a section's node mass ``rho A h`` (kg) against the largest node mass (a disk's), when smaller;
* a disk's mass (kg) against ``m_s``, when larger.

The distance is in decades, ``log10`` of the ratio. :func:`check_scales` refuses a bearing
coefficient more than :data:`HARD_DECADES` off (a value that large is a rigid constraint in
every digit the solvers keep: use a pinned bearing); the ranking is kept on the
:class:`~rubrotor.rotors.linear.LinearSystem` (``scales``), so that an eigenproblem that fails
later names its most likely cause (:func:`explain`) when it is more than :data:`NAME_DECADES` off.
"""

from __future__ import annotations

import math

import numpy as np

from rubrotor.errors import InputError

__all__ = ["HARD_DECADES", "NAME_DECADES", "rotor_scales", "check_scales", "explain"]

HARD_DECADES = 12.0
"""A bearing coefficient this many decades above the shaft's scale is refused outright."""
NAME_DECADES = 3.0
"""An input this many decades off the scale is named as the cause of a failed eigenproblem."""

_PAIRS = {"kyy": (0, 0), "kyz": (0, 1), "kzy": (1, 0), "kzz": (1, 1)}


def _decades(ratio: float) -> float:
    return math.log10(ratio) if ratio > 0 else -math.inf


def rotor_scales(rotor, x: np.ndarray, M: np.ndarray, K: np.ndarray) -> tuple:
    """Inputs of ``rotor`` ranked by their distance from its scale (module docstring).

    Parameters
    ----------
    rotor : rubrotor.rotors.fe.Rotor
        The rotor.
    x : ndarray
        Node positions (m).
    M, K : ndarray
        The shaft's assembled mass and stiffness (disks included, supports not).

    Returns
    -------
    tuple of (float, str, float, str)
        ``(decades, key, value, scale)``, largest distance first; ``scale`` describes the
        reference in words with its value and unit.
    """
    kd, md = np.diag(K)[0::4], np.diag(M)[0::4]
    k_s = float(kd.max())
    m_s = float(np.median(md))
    c_s = math.sqrt(k_s * m_s)
    out = []
    for i, b in enumerate(rotor.bearings):
        if b.kind == "pinned":
            continue
        _, k, c = b._table
        for name, (a, j) in _PAIRS.items():
            for coef, arr, ref, what in (
                (name, k, k_s, f"the shaft's stiffness scale {k_s:.3g} N/m"),
                ("c" + name[1:], c, c_s, f"the shaft's damping scale {c_s:.3g} N s/m"),
            ):
                v = float(np.max(np.abs(arr[:, a, j])))
                value = float(arr[np.argmax(np.abs(arr[:, a, j])), a, j])
                out.append((_decades(v / ref), f"bearing[{i + 1}].{coef}", value, what))
    m_max = float(md.max())
    for s in rotor.sections:
        area = math.pi * (s.diameter**2 - s.bore_diameter**2) / 4
        h = float(np.max(np.diff(x)))
        m_node = s.material.density * area * h
        what = f"the largest node mass {m_max:.3g} kg (the shaft's nodes weigh {m_node:.3g} kg)"
        key = f"materials.{s.material.name}.density"
        out.append((_decades(m_max / m_node), key, s.material.density, what))
    for i, d in enumerate(rotor.disks):
        out.append((_decades(d.mass / m_s), f"disk[{i + 1}].mass", d.mass,
                    f"the shaft's node mass {m_s:.3g} kg"))  # fmt: skip
    best = {}
    for item in out:
        if item[1] not in best or item[0] > best[item[1]][0]:
            best[item[1]] = item
    return tuple(sorted(best.values(), key=lambda t: -t[0]))


def check_scales(scales: tuple) -> None:
    """Refuse a bearing coefficient more than :data:`HARD_DECADES` above the shaft's scale.

    Parameters
    ----------
    scales : tuple
        From :func:`rotor_scales`.

    Raises
    ------
    InputError
        Naming the key, its value and the scale.
    """
    for decades, key, value, what in scales:
        if key.startswith("bearing[") and decades > HARD_DECADES:
            raise InputError(
                key, value, f"a coefficient within 1e{HARD_DECADES:.0f} of {what}: beyond, the "
                "rotor's modes lose every digit (for a rigid support use kind = \"pinned\")"
            )  # fmt: skip


def explain(exc: InputError, scales: tuple) -> InputError:
    """``exc`` (an eigenproblem that failed: modes not independent) naming its likely cause.

    Parameters
    ----------
    exc : InputError
        The eigenproblem's error (its field is not a scenario key), with a ``reason``
        attribute (e.g. ``rubrotor.engine.reduce.IllConditioned``).
    scales : tuple
        From :func:`rotor_scales` (empty for rotors without them).

    Returns
    -------
    InputError
        ``exc`` itself when no input is more than :data:`NAME_DECADES` off the scale, else an
        error naming that input's key and value.
    """
    if not scales or scales[0][0] <= NAME_DECADES:
        return exc
    decades, key, value, what = scales[0]
    return InputError(
        key, value, f"a value nearer {what} ({decades:.1f} decades off): with it {exc.reason}"
    )
