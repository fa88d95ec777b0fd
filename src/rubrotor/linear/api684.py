"""API 684's Level I stability analysis (API 617 6.8.5): the log dec of the first forward mode
against an added cross-coupled stiffness, and the anticipated cross-coupling of the stages.

Level I stability (API 684, API 617 6.8.5)
-----------------------------------------
The logarithmic decrement of the first forward mode (the lowest not whirling backward at every
station, not critically damped: ``zeta <= 0.2``; followed along ``Q`` by continuity) at ``N_mc`` against a cross-coupled
stiffness ``Q`` added at one station (``k_yz = Q``, ``k_zy = -Q``: a force ``i Q z`` on
``z = v + i w``, which feeds forward whirl), ``Q0`` where it crosses zero, and the anticipated
cross-coupling of the stages (Wachel's formula in SI)::

    Q_A = B_c T / (D_c H_c) (rho_d / rho_s),   T = P / Omega  (stage torque, N m)

with ``B_c = 3``, ``D_c`` the impeller diameter and ``H_c`` the smallest of diffuser and impeller
discharge widths (m), ``rho_d / rho_s`` the discharge to suction density ratio; in US units this
is ``63 HP B_c rho_d / (D_c H_c N rho_s)`` klbf/in. The screening passes when the log dec at
``Q_A`` is at least 0.1 and ``Q0 / Q_A >= 2``; otherwise a Level II analysis is required.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError
from rubrotor.linear.critical import CRITICALLY_DAMPED
from rubrotor.linear.modes import damped_modes
from rubrotor.rotors.linear import LinearSystem, Support

__all__ = ["anticipated_cross_coupling", "Level1", "level1", "default_station"]


def anticipated_cross_coupling(power, speed_rad_s, diameter, width, density_ratio=1.0, bc=3.0):
    """Anticipated cross-coupled stiffness ``Q_A`` (N/m) of compressor stages (Wachel, API 617).

    Parameters
    ----------
    power : float or sequence of float
        Rated power of each stage (W).
    speed_rad_s : float
        Operating speed (rad/s).
    diameter, width : float or sequence of float
        Impeller diameter ``D_c`` and smallest of diffuser and impeller discharge width ``H_c``
        of each stage (m).
    density_ratio : float or sequence of float
        Discharge to suction gas density ``rho_d / rho_s``.
    bc : float
        ``B_c`` (3 for centrifugal compressors).

    Returns
    -------
    float
        ``sum B_c (P / Omega) / (D_c H_c) (rho_d / rho_s)`` (N/m).

    Examples
    --------
    >>> round(anticipated_cross_coupling(5e6, 1000.0, 0.4, 0.02, 1.5) / 1e6, 6)  # MN/m
    2.8125
    """
    p, d, h, r = np.broadcast_arrays(*(np.asarray(a, float) for a in (power, diameter, width,
                                                                       density_ratio)))  # fmt: skip
    if np.any(p < 0) or np.any(d <= 0) or np.any(h <= 0) or np.any(r <= 0) or not speed_rad_s > 0:
        raise InputError("stages", (power, diameter, width, density_ratio),
                         "power >= 0 (W), diameter, width > 0 (m), density ratio > 0, speed > 0")  # fmt: skip
    return float(np.sum(bc * p / speed_rad_s / (d * h) * r))


def default_station(bearings, disks, length: float) -> tuple[float, str]:
    """Where Level I applies its cross-coupling by default, and why (API 684 2.8.3.1: at
    mid-span for a between-bearing rotor, at the stage, for an overhung one).

    Parameters
    ----------
    bearings : sequence of float
        Stations (m) of the bearings that carry the rotor (no seals); empty: the two ends.
    disks : sequence of (float, float)
        ``(position m, mass kg)`` of each disk.
    length : float
        Rotor length (m).

    Returns
    -------
    position : float
        Station (m): the heaviest disk outside the outermost bearings when there is one (an
        overhung stage), else midway between the outermost bearings.
    location : str
        ``"overhung stage"`` or ``"mid-span"``.

    Examples
    --------
    >>> default_station([0.1, 0.9], [(0.5, 30.0)], 1.0)
    (0.5, 'mid-span')
    >>> default_station([0.1, 0.5], [(0.3, 30.0), (0.9, 20.0)], 1.0)
    (0.9, 'overhung stage')
    """
    xs = [float(x) for x in bearings] or [0.0, float(length)]
    lo, hi, tol = min(xs), max(xs), 1e-9 * max(float(length), 1.0)
    overhung = [(float(m), float(x)) for x, m in disks if x < lo - tol or x > hi + tol]
    if overhung:
        return max(overhung)[1], "overhung stage"
    return 0.5 * (lo + hi), "mid-span"


@dataclass(frozen=True)
class Level1:
    """API 684 Level I stability: log dec of the first forward mode against added ``Q``.

    Attributes
    ----------
    speed_rad_s : float
        Maximum continuous speed (rad/s).
    position : float
        Station of the added cross-coupling (m).
    stiffness : ndarray, shape (Q,)
        Added cross-coupled stiffness ``Q`` (N/m).
    log_dec : ndarray, shape (Q,)
        Logarithmic decrement of the first forward mode.
    frequency_hz : ndarray, shape (Q,)
        Its damped natural frequency (Hz).
    q0 : float or None
        ``Q`` (N/m) where the log dec crosses zero (interpolated in ``log Q``), None if never.
    qa : float or None
        Anticipated cross-coupling ``Q_A`` (N/m), when given.
    location : str
        Why the cross-coupling is at ``position``: ``"mid-span"`` (between-bearing rotor) or
        ``"overhung stage"`` (see :func:`default_station`), ``"given"`` when it was chosen.
    """

    speed_rad_s: float
    position: float
    stiffness: np.ndarray
    log_dec: np.ndarray
    frequency_hz: np.ndarray
    q0: float | None
    qa: float | None
    location: str = "given"

    @property
    def log_dec_at_qa(self) -> float | None:
        """Log dec at ``Q_A`` (interpolated in ``log Q``), or None."""
        if self.qa is None:
            return None
        return float(np.interp(math.log(self.qa), np.log(self.stiffness), self.log_dec))

    @property
    def verdict(self) -> str | None:
        """``"pass"`` (log dec at Q_A >= 0.1 and Q0 / Q_A >= 2), ``"level II required"``, or
        None without ``Q_A``."""
        if self.qa is None:
            return None
        ratio_ok = self.q0 is None or self.q0 / self.qa >= 2.0
        return "pass" if self.log_dec_at_qa >= 0.1 and ratio_ok else "level II required"

    def to_dict(self) -> dict:
        """JSON form printed by ``rubrotor level1 --json``."""
        return {
            "speed_rad_s": self.speed_rad_s,
            "position_m": self.position,
            "location": self.location,
            "cross_coupling_N_m": self.stiffness.tolist(),
            "log_dec": self.log_dec.tolist(),
            "frequency_hz": self.frequency_hz.tolist(),
            "q0_N_m": self.q0,
            "qa_N_m": self.qa,
            "log_dec_at_qa": self.log_dec_at_qa,
            "verdict": self.verdict,
        }


def _start_mode(system: LinearSystem, speed: float, n: int) -> complex:
    """Eigenvalue (1/s) of the lowest mode that does not whirl backward at every station
    (forward or mixed, as ROSS's Level I takes it) and is not critically damped."""
    for m in damped_modes(system, speed, n=n).modes:
        if m.whirl != "backward" and m.damping_ratio <= CRITICALLY_DAMPED:
            return m.eigenvalue
    raise InputError(
        "modes", n, f"a count that reaches a forward mode (zeta <= 0.2) at {speed:g} rad/s"
    )


FOLLOW_STEP = 10 ** 0.25
"""Largest ratio between the ``Q`` values at which the mode is followed (4 per decade); a step
whose eigenvalue moves by more than :data:`FOLLOW_SHARE` of its distance to the next mode is
halved (in ``log Q``) until it does not."""
FOLLOW_SHARE = 0.25
FOLLOW_MIN_STEP = 1e-6
"""Smallest relative step in ``Q``: a mode that needs smaller ones is not followed further."""
COUPLING_LIMIT = 1e6
"""``Q`` is followed up to this multiple of the rotor's direct stiffness at the station."""


class _Follower:
    """The mode of :func:`level1` followed along ``Q``: eigenvalue by continuity from a ``Q``
    small against the rotor's stiffness at the station, so that the mode at a ``Q`` does not
    depend on the other ``Q`` values asked for."""

    def __init__(self, system, speed, position, n):
        rows = system.output_rows(position)
        self.dofs = tuple(int(system.free[np.argmax(np.abs(r))]) for r in rows)
        if not np.allclose(np.abs(rows).max(axis=1), 1.0):
            raise InputError("position", position, "a node of the rotor (give it as a station)")
        self.system, self.speed, self.position, self.n = system, speed, position, n
        k = system.matrices(speed).K
        free = list(system.free)
        self.k_scale = max(abs(k[free.index(d), free.index(d)]) for d in self.dofs)

    def modes(self, q: float):
        k = np.array([[[0.0, q], [-q, 0.0]]])
        extra = Support(self.dofs, k, np.zeros((1, 2, 2)), None, float(self.position),
                        "cross-coupling")  # fmt: skip
        coupled = dataclasses.replace(self.system, supports=(*self.system.supports, extra))
        return damped_modes(coupled, self.speed, n=self.n).modes, coupled

    def start(self, q: float):
        """``(Q, mode)`` of the followed mode at ``Q``, where it is identified."""
        _, coupled = self.modes(q)
        lam = _start_mode(coupled, self.speed, self.n)
        modes, _ = self.modes(q)
        return q, min(modes, key=lambda md: abs(md.eigenvalue - lam))

    def step(self, qa: float, mode, qb: float):
        """The followed mode at ``qb`` from its ``mode`` at ``qa``, or None where it cannot be
        told from the others (the step is halved down to :data:`FOLLOW_MIN_STEP`)."""
        while True:
            modes, _ = self.modes(qb)
            lam = np.array([md.eigenvalue for md in modes])
            d = np.abs(lam - mode.eigenvalue)
            i = int(np.argmin(d))
            others = np.delete(lam, i)
            gap = np.min(np.abs(others - lam[i])) if others.size else np.inf
            if d[i] <= FOLLOW_SHARE * gap:
                return modes[i]
            if qb / qa - 1 < FOLLOW_MIN_STEP:
                return None
            mode = self.step(qa, mode, math.sqrt(qa * qb))
            if mode is None:
                return None
            qa = math.sqrt(qa * qb)


def _refuse_beyond(q: float, followed: float, why: str):
    raise InputError("stiffness", float(q), f"cross-coupled stiffness up to {followed:.4g} N/m, the "
                     f"range where the first forward mode is followed ({why})")  # fmt: skip


def _follow(fol: _Follower, q: np.ndarray) -> tuple[np.ndarray, list]:
    """The ``Q`` values (N/m) the mode is followed through (the asked ones and 4 per decade from
    a ``Q`` of 1e-6 of the rotor's stiffness at the station) and the mode at each."""
    limit = COUPLING_LIMIT * fol.k_scale
    if q[-1] > limit:
        _refuse_beyond(q[-1], limit, f"{COUPLING_LIMIT:g} times the rotor's direct stiffness "
                       f"{fol.k_scale:.4g} N/m at x = {fol.position:g} m")  # fmt: skip
    q_ref = 1e-6 * fol.k_scale
    lo = min(q_ref, q[0])
    k = np.arange(math.floor(math.log(lo / q_ref, FOLLOW_STEP)),
                  math.ceil(math.log(q[-1] / q_ref, FOLLOW_STEP)) + 1)  # fmt: skip
    grid = q_ref * FOLLOW_STEP ** k.astype(float)
    path = np.unique(np.concatenate([grid[(grid > lo) & (grid < q[-1])], q]))
    path = path[path >= lo]
    qa, mode = fol.start(path[0])
    modes = [mode]
    for qb in path[1:]:
        mode = fol.step(qa, mode, qb)
        if mode is None:
            _refuse_beyond(q[-1], qa, "beyond it the mode cannot be told from the others")
        modes.append(mode)
        qa = qb
    return path, modes


def _root(fol: _Follower, path, modes, q_lo, q_hi) -> float | None:
    """``Q0`` (N/m): the first zero of the followed mode's log dec in ``[q_lo, q_hi]``, located
    by Brent's method on ``log Q`` between the followed values that bracket it."""
    from scipy.optimize import brentq

    inside = np.flatnonzero((path >= q_lo) & (path <= q_hi))
    ld = np.array([modes[i].log_dec for i in inside])
    cross = np.flatnonzero((ld[:-1] > 0) & (ld[1:] <= 0))
    if not cross.size:
        return None
    a, b = inside[cross[0]], inside[cross[0] + 1]

    def log_dec(x):
        m = fol.step(path[a], modes[a], math.exp(x)) if math.exp(x) > path[a] else modes[a]
        return m.log_dec if m is not None else math.nan

    x = brentq(log_dec, math.log(path[a]), math.log(path[b]), xtol=1e-13, rtol=1e-13)
    return float(math.exp(x))


def level1(system: LinearSystem, speed: float, position: float, stiffness=None, qa=None,
           n: int = 8) -> Level1:  # fmt: skip
    """Log dec of the first forward mode against a cross-coupled stiffness at one station.

    The mode is the lowest one not whirling backward everywhere (forward or mixed) with
    ``zeta <= 0.2`` at a ``Q`` of 1e-6 of the rotor's direct stiffness at the station (or the
    first ``Q`` if lower), followed by continuity through 4 ``Q`` values per decade and the
    ones asked for (a step is halved while the eigenvalue moves by more than a quarter of its
    distance to the next mode), so the log dec at a ``Q`` and ``Q0`` do not depend on the
    other values asked for. ``Q0`` is the first zero of the log dec in the range, located by
    Brent's method.

    Parameters
    ----------
    system : LinearSystem
        The rotor (a node at ``position`` is best: :func:`rubrotor.linear_system` takes
        stations).
    speed : float
        Maximum continuous speed (rad/s).
    position : float
        Station of the added cross-coupling (m): mid-span, or the impeller.
    stiffness : array_like, optional
        ``Q`` values (N/m, > 0, increasing); default 1e4 ... 1e9 N/m, 41 log-spaced. Values
        beyond 1e6 times the rotor's direct stiffness at the station, or beyond the ``Q``
        where the mode can no longer be told from the others, are refused.
    qa : float, optional
        Anticipated cross-coupling (N/m), :func:`anticipated_cross_coupling`.
    n : int
        Modes computed at each ``Q``.

    Returns
    -------
    Level1
    """
    q = np.logspace(4, 9, 41) if stiffness is None else np.asarray(stiffness, float)
    if (q.ndim != 1 or q.size < 2 or not np.all(np.isfinite(q)) or np.any(q <= 0)
            or np.any(np.diff(q) <= 0)):  # fmt: skip
        raise InputError("stiffness", stiffness, "increasing cross-coupled stiffness > 0 (N/m)")
    fol = _Follower(system, speed, position, n)
    path, modes = _follow(fol, q)
    at = np.searchsorted(path, q)
    ld = np.array([modes[i].log_dec for i in at])
    fr = np.array([modes[i].frequency_hz for i in at])
    q0 = _root(fol, path, modes, q[0], q[-1])
    return Level1(float(speed), float(position), q, ld, fr, q0, None if qa is None else float(qa))
