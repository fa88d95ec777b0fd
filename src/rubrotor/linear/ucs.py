"""Undamped critical speed map: the rotor's critical speeds against the stiffness of its
supports, with the bearings' own stiffness over it (API 684's map, ROSS's ``run_ucs``).

Every bearing and seal is replaced by an isotropic spring ``k`` (N/m, no damping, no cross
coupling; pinned supports stay pinned) and the undamped natural frequencies of the rotor at
rest are its critical speeds (rad/s) at that ``k``: the eigenvalues ``omega^2`` of
``K(k) x = omega^2 M x`` in one bending plane (with isotropic springs and no spin the two planes
are equal and uncoupled). Gyroscopic stiffening of forward modes is left out, as on the usual
map. Where a bearing's ``kyy(Omega)`` or ``kzz(Omega)`` curve (its table against spin speed)
crosses a critical-speed curve, the rotor on that bearing runs at its critical speed.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from rubrotor.errors import InputError
from rubrotor.rotors.linear import LinearSystem, Support

__all__ = ["BearingCurve", "UCSMap", "ucs_map", "default_stiffness"]


@dataclass(frozen=True)
class BearingCurve:
    """A support's direct stiffness against spin speed, from its table.

    Attributes
    ----------
    name : str
        Label.
    position : float
        Axial position (m).
    speeds : ndarray, shape (T,)
        Spin speeds (rad/s) of the table (one value for constant coefficients).
    kyy, kzz : ndarray, shape (T,)
        Direct stiffness (N/m) at those speeds.
    """

    name: str
    position: float
    speeds: np.ndarray
    kyy: np.ndarray
    kzz: np.ndarray


@dataclass(frozen=True)
class UCSMap:
    """Critical speeds (rad/s) of the lowest modes against support stiffness (N/m).

    Attributes
    ----------
    stiffness : ndarray, shape (S,)
        Support stiffness ``k`` (N/m), increasing.
    critical_speeds : ndarray, shape (S, n)
        Undamped critical speeds (rad/s) of the ``n`` lowest modes at each ``k``.
    bearings : tuple of BearingCurve
        The supports' ``kyy``, ``kzz`` against speed.
    """

    stiffness: np.ndarray
    critical_speeds: np.ndarray
    bearings: tuple

    def crossings(self) -> list[dict]:
        """Where each bearing's ``kyy`` and ``kzz`` curve crosses each mode's curve: the
        critical speed (rad/s) on that bearing's stiffness, ``Omega = w_j(k_b(Omega))``
        (``w_j`` interpolated linearly in ``log k``; a constant bearing crosses at
        ``w_j(k_b)``); crossings outside the stiffness range are left out.

        Returns
        -------
        list of dict
            ``{"bearing", "direction", "mode", "speed_rad_s", "stiffness_N_m"}``.
        """
        logk = np.log(self.stiffness)
        out = []
        for b in self.bearings:
            for direction, kb in (("kyy", b.kyy), ("kzz", b.kzz)):
                for j in range(self.critical_speeds.shape[1]):
                    hit = _crossing(logk, self.critical_speeds[:, j], b.speeds, kb)
                    if hit is not None:
                        out.append({"bearing": b.name, "direction": direction, "mode": j + 1,
                                    "speed_rad_s": hit[0], "stiffness_N_m": hit[1]})  # fmt: skip
        return out

    def to_dict(self) -> dict:
        """JSON form: stiffness (N/m), critical speeds (rad/s) per mode, bearing curves and
        their crossings."""
        return {
            "stiffness_N_m": self.stiffness.tolist(),
            "critical_speeds_rad_s": self.critical_speeds.T.tolist(),
            "bearings": [
                {
                    "name": b.name,
                    "position_m": b.position,
                    "speed_rad_s": b.speeds.tolist(),
                    "kyy_N_m": b.kyy.tolist(),
                    "kzz_N_m": b.kzz.tolist(),
                }
                for b in self.bearings
            ],
            "crossings": self.crossings(),
        }


def _crossing(logk, crit, speeds, kb):
    """``(speed rad/s, k N/m)`` where ``Omega = crit(k_b(Omega))``, or None."""
    if np.any(kb <= 0):
        return None

    def w_at(k):
        lk = np.log(k)
        return np.where((lk >= logk[0]) & (lk <= logk[-1]), np.interp(lk, logk, crit), np.nan)

    if speeds.size == 1:
        w = float(w_at(kb[0]))
        return None if math.isnan(w) else (w, float(kb[0]))
    grid = np.linspace(speeds[0], speeds[-1], 2001)
    g = w_at(np.interp(grid, speeds, kb)) - grid
    idx = np.flatnonzero(
        np.isfinite(g[:-1]) & np.isfinite(g[1:]) & (np.sign(g[:-1]) != np.sign(g[1:]))
    )
    if not idx.size:
        return None
    i = idx[0]
    t = g[i] / (g[i] - g[i + 1])
    w = float(grid[i] + t * (grid[i + 1] - grid[i]))
    return w, float(np.interp(w, speeds, kb))


def _curve(s: Support, span=(1.0, 1.0)) -> BearingCurve:
    """A support's ``kyy``, ``kzz`` against speed. A fluid film's (``s.law``: coefficients at the
    static equilibrium of each speed, see ``rubrotor bearings``) at 40 speeds spaced
    logarithmically over ``span`` (rad/s: the map's critical speeds), those where its film carries
    the load; zero where none does."""
    if s.law is not None:
        from rubrotor.errors import InputError as _Refused

        rows = []
        for w in np.geomspace(max(span[0], 1e-3), max(span[1], 2e-3), 40):
            try:
                k, _ = s.tabulate([w])
            except _Refused:  # below the speed at which the film carries its load
                continue
            rows.append((w, k[0, 0, 0], k[0, 1, 1]))
        if rows:
            w, kyy, kzz = (np.array(col) for col in zip(*rows, strict=True))
            return BearingCurve(s.name, float(s.position), w, kyy, kzz)
        return BearingCurve(s.name, float(s.position), np.zeros(1), np.zeros(1), np.zeros(1))
    speeds = np.zeros(1) if s.speeds is None else np.asarray(s.speeds, float)
    return BearingCurve(s.name, float(s.position), speeds, s.k[:, 0, 0].copy(), s.k[:, 1, 1].copy())


def default_stiffness(system: LinearSystem, count: int = 41) -> np.ndarray:
    """Log-spaced stiffness (N/m) from 1/300 of the softest to 300 times the stiffest bearing
    coefficient ``kyy``, ``kzz`` (1e5 to 1e11 N/m without bearings)."""
    ks = [v for s in system.supports for v in np.r_[s.k[:, 0, 0], s.k[:, 1, 1]] if v > 0]
    lo, hi = (min(ks) / 300, max(ks) * 300) if ks else (1e5, 1e11)
    return np.logspace(math.log10(lo), math.log10(hi), count)


def _plane(system: LinearSystem) -> np.ndarray:
    """Free-DOF indices of the ``y`` plane (even full indices: ``v``, ``psi_v`` per node)."""
    even = np.flatnonzero(system.free % 2 == 0)
    f = np.ix_(system.free, system.free)
    k, m = system.K[f], system.M[f]  # without the supports (replaced by isotropic springs)
    odd = np.setdiff1d(np.arange(system.n_dof), even)
    scale = max(np.abs(k).max(), np.abs(m).max())
    for a in (k, m):
        if np.abs(a[np.ix_(even, odd)]).max(initial=0.0) > 1e-12 * scale:
            raise InputError("rotor", system.name, "uncoupled bending planes at rest (M, K)")
    return even


def ucs_map(system: LinearSystem, stiffness=None, n: int = 4) -> UCSMap:
    """Undamped critical speeds of the ``n`` lowest modes against support stiffness.

    Parameters
    ----------
    system : LinearSystem
        The rotor with at least one bearing or seal (:class:`~rubrotor.rotors.linear.Support`).
    stiffness : array_like, optional
        Support stiffness values (N/m, ``> 0``, increasing); default ``default_stiffness(system)``.
    n : int
        Number of modes (``>= 1``).

    Returns
    -------
    UCSMap

    Examples
    --------
    A rigid 1 kg mass on two springs: the critical speed is ``sqrt(2 k / m)``.

    >>> import numpy as np
    >>> from rubrotor.rotors.linear import LinearSystem, NodalBasis, Support
    >>> z = np.zeros((4, 4)); m = np.diag([1.0, 1.0, 1.0, 1.0])
    >>> s = Support((0, 1), np.zeros((1, 2, 2)), np.zeros((1, 2, 2)))
    >>> sysm = LinearSystem(m, np.diag([0, 0, 1e6, 1e6]), z, z, NodalBasis(np.array([0.0])),
    ...                     supports=(s, s))
    >>> round(float(ucs_map(sysm, [50.0, 200.0], n=1).critical_speeds[1, 0]), 6)
    20.0
    """
    if not system.supports:
        raise InputError(
            "bearing",
            0,
            "a rotor on bearings or seals (on pinned supports only, such as the continuous "
            "shaft, the map is one point: its natural frequencies)",
        )
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise InputError("n", n, "a number of modes >= 1")
    k = default_stiffness(system) if stiffness is None else np.asarray(stiffness, float)
    if k.ndim != 1 or k.size < 1 or not np.all(np.isfinite(k)) or np.any(k <= 0):
        raise InputError("stiffness", stiffness, "support stiffness values > 0 (N/m)")
    plane = _plane(system)
    count = min(n, plane.size)
    out = np.empty((k.size, count))
    zero = np.zeros((1, 2, 2))
    for i, ki in enumerate(k):
        springs = tuple(
            dataclasses.replace(s, k=ki * np.eye(2)[None], c=zero, speeds=None, law=None)
            for s in system.supports
        )
        mx = dataclasses.replace(system, supports=springs).matrices(0.0)
        p = np.ix_(plane, plane)
        lam = scipy.linalg.eigh(mx.K[p], mx.M[p], eigvals_only=True, subset_by_index=[0, count - 1])
        out[i] = np.sqrt(np.maximum(lam, 0.0))
    positive = out[out > 0]
    span = (float(positive.min()), float(positive.max())) if positive.size else (1.0, 1.0)
    return UCSMap(k, out, tuple(_curve(s, span) for s in system.supports))
