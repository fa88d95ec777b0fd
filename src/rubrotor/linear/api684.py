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

__all__ = ["anticipated_cross_coupling", "Level1", "level1"]


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
    """

    speed_rad_s: float
    position: float
    stiffness: np.ndarray
    log_dec: np.ndarray
    frequency_hz: np.ndarray
    q0: float | None
    qa: float | None

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


def level1(system: LinearSystem, speed: float, position: float, stiffness=None, qa=None,
           n: int = 8) -> Level1:  # fmt: skip
    """Log dec of the first forward mode against a cross-coupled stiffness at one station.

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
        ``Q`` values (N/m, > 0, increasing); default 1e4 ... 1e9 N/m, 41 log-spaced.
    qa : float, optional
        Anticipated cross-coupling (N/m), :func:`anticipated_cross_coupling`.
    n : int
        Modes computed at each ``Q``: the lowest mode not whirling backward everywhere (forward
        or mixed) with ``zeta <= 0.2`` at the first ``Q`` is followed to the others by the
        nearest eigenvalue.

    Returns
    -------
    Level1
    """
    q = np.logspace(4, 9, 41) if stiffness is None else np.asarray(stiffness, float)
    if q.ndim != 1 or q.size < 2 or np.any(q <= 0) or np.any(np.diff(q) <= 0):
        raise InputError("stiffness", stiffness, "increasing cross-coupled stiffness > 0 (N/m)")
    rows = system.output_rows(position)
    dofs = tuple(int(system.free[np.argmax(np.abs(r))]) for r in rows)
    if not np.allclose(np.abs(rows).max(axis=1), 1.0):
        raise InputError("position", position, "a node of the rotor (give it as a station)")
    ld, fr = np.empty(q.size), np.empty(q.size)
    lam = None
    for i, qi in enumerate(q):
        k = np.array([[[0.0, qi], [-qi, 0.0]]])
        extra = Support(dofs, k, np.zeros((1, 2, 2)), None, float(position), "cross-coupling")
        coupled = dataclasses.replace(system, supports=(*system.supports, extra))
        if lam is None:
            lam = _start_mode(coupled, speed, n)
        modes = damped_modes(coupled, speed, n=n).modes
        m = min(modes, key=lambda md: abs(md.eigenvalue - lam))  # follow the mode along Q
        lam = m.eigenvalue
        ld[i], fr[i] = m.log_dec, m.frequency_hz
    q0 = None
    cross = np.flatnonzero((ld[:-1] > 0) & (ld[1:] <= 0))
    if cross.size:
        j = cross[0]
        t = ld[j] / (ld[j] - ld[j + 1])
        q0 = float(math.exp(math.log(q[j]) + t * (math.log(q[j + 1]) - math.log(q[j]))))
    return Level1(float(speed), float(position), q, ld, fr, q0, None if qa is None else float(qa))
