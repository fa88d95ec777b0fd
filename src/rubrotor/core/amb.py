"""Compiled active magnetic bearing axis: force from the coil currents and the air gaps (SI).

One axis of a heteropolar bearing is a differential pair of electromagnets across the journal.
The journal sits at ``x`` (m) from the centre, the nominal air gap is ``g0`` (m), the bias current
``i0`` (A) and the control current ``i`` (A) drive the coils with ``i0 + i`` and ``i0 - i``, each
held within ``[0, max_current]`` (the amplifier saturates). With the magnetic circuit's reluctance
in the air gaps only, the pull of one magnet is ``k (current / gap)^2`` with
``k = mu0 N^2 A cos(alpha) / 4`` (N m^2 / A^2: ``N`` turns per magnet, ``A`` one pole face's area,
``alpha`` the pole's half angle), so the axis force on the journal is

    f(x, i) = k [ (i0 + i)^2 / (g0 - x)^2 - (i0 - i)^2 / (g0 + x)^2 ],

linearised at the centre as ``f ~ ks x + ki i`` with ``ki = 4 k i0 / g0^2`` (N/A) and
``ks = 4 k i0^2 / g0^3`` (N/m, the negative stiffness of the bias flux).

Parameters come as one :class:`MagnetAxis` namedtuple: ``k`` (N m^2/A^2), ``gap`` (m), ``bias``
(A), ``max_current`` (A).
"""

from __future__ import annotations

from collections import namedtuple

from numba import njit

__all__ = ["MU0", "MagnetAxis", "magnet_force"]

MU0 = 4e-7 * 3.141592653589793
"""Permeability of free space used for the pole constant (H/m)."""

MagnetAxis = namedtuple("MagnetAxis", "k gap bias max_current")
"""One differential axis in SI (see the module docstring)."""


@njit(cache=True)
def magnet_force(x, i, axis):
    """Axis force on the journal (N) and its derivatives.

    Parameters
    ----------
    x : float
        Journal displacement along the axis (m), ``|x| < gap``.
    i : float
        Control current (A).
    axis : MagnetAxis
        Parameters (SI).

    Returns
    -------
    f : float
        Force (N), positive along ``x``.
    df_dx : float
        ``d f / d x`` (N/m).
    df_di : float
        ``d f / d i`` (N/A), zero where both coils are saturated.
    """
    i_up = min(max(axis.bias + i, 0.0), axis.max_current)
    i_dn = min(max(axis.bias - i, 0.0), axis.max_current)
    d_up = 1.0 if 0.0 < axis.bias + i < axis.max_current else 0.0
    d_dn = 1.0 if 0.0 < axis.bias - i < axis.max_current else 0.0
    gu = axis.gap - x
    gd = axis.gap + x
    f = axis.k * (i_up * i_up / (gu * gu) - i_dn * i_dn / (gd * gd))
    df_dx = 2.0 * axis.k * (i_up * i_up / gu**3 + i_dn * i_dn / gd**3)
    df_di = 2.0 * axis.k * (d_up * i_up / (gu * gu) + d_dn * i_dn / (gd * gd))
    return f, df_dx, df_di
