"""API 617's critical speeds as the standard defines them: response peaks at the probes.

Critical speeds from the unbalance response (API 617, 9th edition, 6.8.2)
-------------------------------------------------------------------------
1. Candidates: every speed up to the top of the analysis range (API 617: 125 % of the maximum
   continuous speed ``N_mc``, and at least the trip speed) where a mode's damped frequency equals
   the spin (:func:`rubrotor.linear.critical.linear_critical_speeds`), of any whirl label:
   forward, backward or mixed (modes damped beyond ``CANDIDATE_DAMPING`` left out).
2. For each, the unbalance that excites that mode's shape at that speed
   (:func:`rubrotor.linear.api617.shape_unbalance`: ``U_a = 2 U_r`` at the antinodes) drives
   the rotor from 0 to the top speed; the peak-to-peak response at the probes (along each
   probe's direction, or the orbit's major axis) peaks near the candidate at ``N_c``.
3. Its amplification factor by the half-power method, ``AF = N_c / (N_2 - N_1)``, with
   ``N_1 < N_c < N_2`` where the amplitude at the probe of the largest peak is the peak over
   ``sqrt(2)``. Only peaks with ``AF >= 2.5`` are critical speeds (below: critically damped).
   Peaks found from several candidates at the same speed (within 1 %) are one critical, that
   of the candidate whose crossing is nearest the peak.
4. Its whirl is read from the response at that probe at ``N_c``: forward when the forward
   circular component ``|V + i W|`` exceeds the backward one ``|V - i W|``; the mode's label is
   kept beside it.
5. The required separation margin (API 617 / API 684): below the minimum operating speed
   ``min(16, 17 (1 - 1/(AF - 1.5)))`` %, above ``N_mc`` ``min(26, 10 + 17 (1 - 1/(AF - 1.5)))``
   %; inside the operating range none suffices. The actual margin is the distance to the nearer
   end of the operating range, relative to it.
6. The amplitude check of that unbalance: the close-clearance check of
   :func:`rubrotor.linear.api617.clearance_check` with these planes, from 0 to the trip speed
   (scaled response against 75 % of each diametral clearance).
7. Verdict: ``"pass"`` when the actual margin reaches the required one and every close
   clearance keeps its margin, else ``"fail"``.

Differences from ROSS 3.1's ``run_clearance_analysis`` (which
:func:`rubrotor.linear.api617.clearance_check` reproduces): ROSS places one unbalance, for the
``n``-th mode labelled forward at ``N_mc``, and reports no critical speed, AF or separation
margin; here every response peak up to the top speed is found, mixed and backward labels
included, each with the unbalance of its own shape.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError
from rubrotor.linear.api617 import _probe_pp, clearance_check, shape_unbalance
from rubrotor.linear.critical import linear_critical_speeds
from rubrotor.linear.response import unbalance_response
from rubrotor.linear.shapes import mode_shapes
from rubrotor.rotors.linear import LinearSystem

__all__ = ["AF_CRITICAL", "required_separation_margin", "half_power", "ResponseCritical",
           "response_criticals"]  # fmt: skip

AF_CRITICAL = 2.5
"""API 617: a response peak with a half-power amplification factor below this is critically
damped, not a critical speed."""
CANDIDATE_DAMPING = 0.4
"""Candidates whose mode is damped beyond this ratio at the crossing (twice API 684's 0.2, so
that no peak of AF near 2.5 is missed) are not followed: near-real roots of overdamped
supports cross 1X without a resonance."""


def required_separation_margin(af: float, above: bool) -> float:
    """API 617 / API 684 separation margin (fraction of the speed) a critical of amplification
    factor ``af`` (1) needs from the operating range: 0 below ``AF = 2.5``; else
    ``min(0.16, 0.17 (1 - 1/(AF - 1.5)))`` below the minimum operating speed and
    ``min(0.26, 0.10 + 0.17 (1 - 1/(AF - 1.5)))`` above the maximum continuous speed.

    Examples
    --------
    >>> round(required_separation_margin(5.0, above=False), 6)
    0.121429
    >>> required_separation_margin(2.0, above=True)
    0.0
    """
    if not math.isfinite(af) or af < AF_CRITICAL:
        return 0.0 if math.isfinite(af) else (0.26 if above else 0.16)
    core = 0.17 * (1.0 - 1.0 / (af - 1.5))
    return min(0.26, 0.10 + core) if above else min(0.16, core)


def half_power(speeds: np.ndarray, amplitude: np.ndarray, i: int):
    """The half-power points around the peak ``i`` of ``amplitude(speeds)``.

    Returns
    -------
    tuple of float or None
        ``(N_1, N_2)`` (rad/s), linearly interpolated where the amplitude falls to
        ``amplitude[i] / sqrt(2)`` on either side; None when it does not on one side, or when
        the amplitude exceeds the peak between them (``i`` is a shoulder of a larger peak,
        not a resonance of its own).
    """
    level = amplitude[i] / math.sqrt(2.0)
    below = np.flatnonzero(amplitude[:i] < level)
    above = np.flatnonzero(amplitude[i + 1 :] < level)
    if not below.size or not above.size:
        return None
    a, b = below[-1], i + 1 + above[0]
    if amplitude[a : b + 1].max() > amplitude[i]:
        return None

    def cross(j0, j1):
        y0, y1 = amplitude[j0] - level, amplitude[j1] - level
        return float(speeds[j0] + (speeds[j1] - speeds[j0]) * y0 / (y0 - y1))

    return cross(a, a + 1), cross(b - 1, b)


@dataclass(frozen=True)
class ResponseCritical:
    """One API 617 critical speed (speeds rad/s, margins as fractions, amplitudes m p-p).

    Attributes
    ----------
    speed_rad_s : float
        ``N_c``: the response peak at the probe.
    mode_speed_rad_s : float
        Where the mode's damped frequency equals the spin (the candidate).
    mode_whirl : str
        The mode's label there (forward, backward, mixed).
    whirl : str
        Whirl of the response at the probe at ``N_c`` (forward or backward).
    probe : int
        Index of the probe whose peak is largest (the one the AF is read at).
    amplification_factor : float
        ``N_c / (N_2 - N_1)`` by the half-power method at that probe.
    half_power_rad_s : tuple of float
        ``(N_1, N_2)``.
    peak_m_pp : float
        Peak-to-peak amplitude at the probe at ``N_c`` for the unbalance ``planes``.
    planes : list of (float, float, float)
        The unbalance exciting the mode: ``(position m, kg m, rad)``.
    required_margin, actual_margin : float
        Separation margins (fraction of the nearer end of the operating range; the actual one
        negative inside the range, by the distance to its nearer end).
    clearance_margins : list of float
        ``0.75 (2 c) - max(scaled)`` (m) at each close clearance, from 0 to trip speed.
    """

    speed_rad_s: float
    mode_speed_rad_s: float
    mode_whirl: str
    whirl: str
    probe: int
    amplification_factor: float
    half_power_rad_s: tuple
    peak_m_pp: float
    planes: list
    required_margin: float
    actual_margin: float
    clearance_margins: list

    @property
    def verdict(self) -> str:
        """``"pass"``: the actual separation margin reaches the required one and every close
        clearance keeps its 75 % margin; else ``"fail"``."""
        ok = self.actual_margin >= self.required_margin and all(m >= 0 for m in
                                                                 self.clearance_margins)  # fmt: skip
        return "pass" if ok else "fail"

    def to_dict(self) -> dict:
        """JSON form (the ``criticals`` of ``rubrotor clearance --json``)."""
        return {
            "speed_rad_s": self.speed_rad_s,
            "mode_speed_rad_s": self.mode_speed_rad_s,
            "mode_whirl": self.mode_whirl,
            "whirl_at_probe": self.whirl,
            "probe": self.probe,
            "amplification_factor": self.amplification_factor,
            "amplification_method": "half-power, response at the probe",
            "half_power_rad_s": list(self.half_power_rad_s),
            "peak_m_pp": self.peak_m_pp,
            "unbalance": [
                {"position_m": p, "magnitude_kg_m": m, "phase_rad": f} for p, m, f in self.planes
            ],  # fmt: skip
            "required_separation_margin": self.required_margin,
            "actual_separation_margin": self.actual_margin,
            "clearance_margins_m": list(self.clearance_margins),
            "verdict": self.verdict,
        }


def _actual_margin(nc: float, min_speed: float, max_speed: float) -> tuple[float, bool]:
    """Separation margin (fraction of the nearer end of the operating range; negative inside
    it, by the distance to the nearer end) and whether the critical is on the upper side."""
    if nc > max_speed:
        return (nc - max_speed) / max_speed, True
    if nc < min_speed:
        return (min_speed - nc) / min_speed, False
    up = (max_speed - nc) / max_speed
    down = (nc - min_speed) / min_speed if min_speed > 0 else math.inf
    return -min(up, down), up <= down


def _grid(top: float, centre: float, points: int) -> np.ndarray:
    """Speeds (rad/s) from 0 to ``top``, dense within 25 % of ``centre``."""
    coarse = np.linspace(0.0, top, points)
    fine = np.linspace(0.75 * centre, min(1.25 * centre, top), points)
    s = np.union1d(coarse, fine)
    return s[s > 0]


def _one(system, c, ctx) -> ResponseCritical | None:
    """The critical the candidate ``c`` (a LinearCritical) leads to, or None (no peak with
    AF >= 2.5 near it)."""
    w0 = c.speed_rad_s
    shapes = mode_shapes(system, w0, ctx["modes"])
    freq = np.array([2 * math.pi * m.frequency_hz for m in shapes.modes.modes])
    k = int(np.argmin(np.abs(freq - w0)))
    planes, _ = shape_unbalance(system, shapes, k, ctx["max_speed"])
    s = _grid(ctx["top"], w0, ctx["points"])
    resp = unbalance_response(system, s, planes, ctx["probes_x"]).complex_response
    pp = _probe_pp(resp, ctx["angles"])
    window = np.flatnonzero((s >= 0.8 * w0) & (s <= 1.2 * w0))
    if not window.size:
        return None
    p, j = np.unravel_index(np.argmax(pp[:, window]), (pp.shape[0], window.size))
    i = int(window[j])
    if i in (0, s.size - 1) or pp[p, i] <= (1 + 1e-9) * max(pp[p, i - 1], pp[p, i + 1]):
        return None  # not a peak: an edge, or a plateau flat to round-off (it flips with it)
    hp = half_power(s, pp[p], i)
    if hp is None:
        return None
    nc = float(s[i])
    af = nc / (hp[1] - hp[0])
    if af < AF_CRITICAL:
        return None
    v, w = resp[i, p, 0], resp[i, p, 1]
    whirl = "forward" if abs(v + 1j * w) >= abs(v - 1j * w) else "backward"
    actual, above = _actual_margin(nc, ctx["min_speed"], ctx["max_speed"])
    required = required_separation_margin(af, above)
    margins = []
    if ctx["clearances"]:
        chk = clearance_check(system, s[s <= ctx["trip"]], ctx["min_speed"], ctx["max_speed"],
                              ctx["probes"], ctx["clearances"], planes=planes)  # fmt: skip
        margins = [float(m) for m in chk.margin]
    return ResponseCritical(nc, w0, c.whirl, whirl, int(p), af, hp, float(pp[p, i]), planes,
                            required, actual, margins)  # fmt: skip


def response_criticals(
    system: LinearSystem,
    min_speed: float,
    max_speed: float,
    probes,
    clearances=(),
    trip_speed: float | None = None,
    modes: int = 12,
    points: int = 400,
) -> list[ResponseCritical]:
    """Every API 617 critical speed up to the analysis range's top (see the module docstring).

    Parameters
    ----------
    system : LinearSystem
        A nodal rotor with bearings.
    min_speed, max_speed : float
        Minimum operating and maximum continuous speed (rad/s).
    probes : sequence of (float, float or None)
        ``(position m, angle rad)``; angle None reads the orbit's major axis.
    clearances : sequence of (str, float, float)
        Close clearances ``(name, position m, radial clearance m)``; empty: no amplitude check.
    trip_speed : float, optional
        Trip speed (rad/s); default 1.05 ``max_speed``. The response runs to
        ``max(trip, 1.25 max_speed)``.
    modes : int
        Modes searched for candidates and shapes.
    points : int
        Speeds of the coarse grid (a second, as dense, covers 25 % around each candidate).

    Returns
    -------
    list of ResponseCritical
        Sorted by speed.
    """
    if not 0 <= min_speed <= max_speed or max_speed <= 0:
        raise InputError("min_speed / max_speed", (min_speed, max_speed),
                         "0 <= minimum operating <= maximum continuous speed, > 0 (rad/s)")  # fmt: skip
    trip = 1.05 * max_speed if trip_speed is None else float(trip_speed)
    if not (math.isfinite(trip) and trip >= max_speed):
        raise InputError("trip_speed", trip_speed, f"a speed >= {max_speed:g} rad/s")
    if not probes:
        raise InputError("probes", probes, "at least one vibration probe (position m, angle)")
    top = max(trip, 1.25 * max_speed)
    ctx = {"modes": modes, "max_speed": float(max_speed), "min_speed": float(min_speed),
           "top": top, "trip": trip, "points": points, "probes": list(probes),
           "probes_x": [p for p, _ in probes], "angles": [a for _, a in probes],
           "clearances": list(clearances)}  # fmt: skip
    found: list[ResponseCritical] = []
    for c in linear_critical_speeds(system, top, n=modes):
        if c.damping_ratio > CANDIDATE_DAMPING:
            continue  # a near-real (overdamped) root crossing 1X: no resonance to find
        crit = _one(system, c, ctx)
        if crit is None:
            continue
        near = 0.01 * crit.speed_rad_s
        same = [f for f in found if abs(f.speed_rad_s - crit.speed_rad_s) <= near]
        if same:  # one peak reached from two candidates: the mode crossing nearer the peak

            def gap(f):
                return abs(f.mode_speed_rad_s - f.speed_rad_s)

            if gap(same[0]) <= gap(crit):
                continue
            found.remove(same[0])
        found.append(crit)
    return sorted(found, key=lambda f: f.speed_rad_s)
