"""The API 617 close-clearance check that decides whether a machine rubs: the unbalance
response placed and scaled as the standard says, against the running clearances.

Close-clearance check (API 617, 9th edition, 6.8.2.7-6.8.2.11, as ROSS 3.1's
``run_clearance_analysis`` applies it)
----------------------------------------------------------------------------------------------
1. The forward mode ``mode`` (counted over the forward modes: amplitude-weighted ratio of minor
   to major orbit axis above 0.25) at the maximum continuous speed ``N_mc`` gives the unbalance
   placement: the shape is projected on the major-axis direction of its largest orbit and cut
   into lobes where that projection changes sign (stations below 2 % of the largest orbit do not
   cut); each lobe's largest orbit is an antinode. Antinodes between the outermost bearings with
   at least 10 % of the largest orbit take an unbalance; one outboard of them when it holds the
   largest orbit or at least half of it.
2. Each unbalance is ``U_a = 2 U_r`` with ``U_r = 6350 W / N_mc`` (g mm; ``W`` in kg, ``N_mc``
   in rpm; ``W / 3.937`` from 25000 rpm), phase 0 or pi as its lobe's sign. ``W`` is the sum of
   the journal static loads for a single antinode between the bearings, the load of the nearest
   journal for several, and the mass outboard of the bearing for an outboard one (as ROSS 3.1:
   the shaft elements wholly outboard plus the disks and point masses beyond the bearing).
   Journal loads are, as ROSS 3.1 defines them, the static reactions under standard gravity
   divided by ``g`` with the journal bearings rigid and the seals (``kind = "seal"``, ROSS's
   ``SealElement``) carrying nothing.
3. The mechanical test vibration limit is ``A_vl = min(25.4, 25.4 sqrt(12000 / N_mc))`` µm
   peak to peak; ``A_max`` the largest peak-to-peak amplitude at the probes (along each probe's
   direction, or the orbit's major axis) between the minimum allowable speed and ``N_mc``; the
   scale factor ``S_cc = A_vl / A_max`` (API 617 caps it at 6).
4. At every close clearance (a contact of the scenario) the scaled major-axis response
   ``2 S_cc a_major`` (peak to peak) is compared with 75 % of the diametral running clearance
   ``2 c``: the margin is ``0.75 (2 c) - max(scaled)`` over the speed range. Beyond the
   standard, it also says where the scaled orbit reaches the clearance itself (``>= 2 c``):
   there the rotor rubs, and the rub simulation at that speed tells how.

API 684's Level I stability analysis is in :mod:`rubrotor.linear.api684`; a mode is critically
damped (not used to place the unbalance) beyond
:data:`rubrotor.linear.critical.CRITICALLY_DAMPED`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError
from rubrotor.linear.critical import CRITICALLY_DAMPED
from rubrotor.linear.response import unbalance_response
from rubrotor.linear.shapes import mode_shapes
from rubrotor.linear.static import STANDARD_GRAVITY, static_analysis
from rubrotor.rotors.linear import LinearSystem

__all__ = [
    "FORWARD_WHIRL_RATIO",
    "residual_unbalance",
    "vibration_limit",
    "api617_unbalance",
    "shape_unbalance",
    "ClearanceCheck",
    "clearance_check",
]

FORWARD_WHIRL_RATIO = 0.25
"""A mode is forward for API 617 when its amplitude-weighted minor/major ratio exceeds this."""
RPM = 60 / (2 * math.pi)  # rpm per rad/s


def residual_unbalance(weight_kg: float, speed_rad_s: float) -> float:
    """API 617's maximum allowable residual unbalance ``U_r`` (kg m).

    Parameters
    ----------
    weight_kg : float
        Journal static load ``W`` (kg).
    speed_rad_s : float
        Maximum continuous speed (rad/s).

    Returns
    -------
    float
        ``6350 W / N`` g mm (``N`` in rpm, capped at 25000 rpm), in kg m.

    Examples
    --------
    >>> round(residual_unbalance(100.0, 10000 / RPM) * 1e6, 6)  # g mm
    63.5
    """
    rpm = speed_rad_s * RPM
    return 6350.0 * weight_kg / min(rpm, 25000.0) * 1e-6


def vibration_limit(speed_rad_s: float) -> float:
    """API 617's mechanical test vibration limit (m peak to peak) at ``speed_rad_s`` (rad/s):
    ``min(25.4, 25.4 sqrt(12000 / N))`` µm with ``N`` in rpm."""
    return min(25.4, 25.4 * math.sqrt(12000.0 / (speed_rad_s * RPM))) * 1e-6


def _major_angle(v: complex, w: complex) -> float:
    """Direction (rad from +y towards +z) of the major axis of ``Re([v, w] e^{i t})``."""
    t = -0.5 * np.angle(v * v + w * w)
    return math.atan2(np.real(w * np.exp(1j * t)), np.real(v * np.exp(1j * t)))


def _forward_mode(system: LinearSystem, speed: float, mode: int, count: int, max_zeta):
    """The mode shapes at ``speed`` and the index of forward mode ``mode`` among them: first as
    ROSS 3.1's ``api617_unbalance`` takes them (its ``run_modal(num_modes=count)``: the
    ``count // 2`` modes in ROSS's selection and order); when those hold too few forward modes
    (ROSS would raise), among the ``count`` modes of least ``|lambda|``."""
    for n, order in ((max(1, count // 2), "ross"), (count, "natural")):
        shapes = mode_shapes(system, speed, n, order=order)
        ratio = shapes.minor.sum(axis=1) / shapes.major.sum(axis=1)
        zeta = np.array([m.damping_ratio for m in shapes.modes.modes])
        ok = (ratio > FORWARD_WHIRL_RATIO) & (zeta <= (np.inf if max_zeta is None else max_zeta))
        forward = np.flatnonzero(ok)
        if forward.size > mode:
            return shapes, int(forward[mode])
    top = f"to {forward.size - 1}" if forward.size else "(none found)"
    raise InputError("mode", mode, f"a forward mode index from 0 (the first forward mode) "
                     f"{top} ({forward.size} forward modes among the {count} lowest at "
                     f"{speed:g} rad/s)")  # fmt: skip


def _lobes(sign: np.ndarray, amplitude: np.ndarray) -> list[list[int]]:
    """Runs of stations with one sign of the projected shape (small stations do not cut)."""
    lobes, current, last = [], [], None
    for i, (s, a) in enumerate(zip(sign, amplitude, strict=True)):
        s = s if a >= 0.02 * amplitude.max() else None
        if last is not None and s is not None and s != last:
            lobes.append(current)
            current = []
        current.append(i)
        last = s if s is not None else last
    return lobes + [current]


def _loads(system: LinearSystem) -> dict[float, float]:
    """Static load (kg) of each journal bearing, by position (m), as ROSS 3.1 defines it: the
    reactions under gravity / g with the journal bearings rigid and the seals (``kind ==
    "seal"``) and housings' supports left out (ROSS's ``run_static``)."""
    import dataclasses

    nodal = 4 * len(system.basis.nodes)
    journals = [s for s in system.supports if s.kind != "seal" and max(s.dofs) < nodal]
    fixed = tuple(sorted(set(system.fixed) | {d for s in journals for d in s.dofs}))
    if not journals:  # pinned supports only: their reactions
        res = static_analysis(system, gravity=(-STANDARD_GRAVITY, 0.0), loads=())
    else:
        rigid = dataclasses.replace(system, supports=(), fixed=fixed)
        res = static_analysis(rigid, gravity=(-STANDARD_GRAVITY, 0.0), loads=())
    return {b.position: math.hypot(b.force_y, b.force_z) / STANDARD_GRAVITY for b in res.bearings}


def _outboard_mass(system: LinearSystem, x: np.ndarray, left: float, right: float, side: int):
    """Mass (kg) of the rotor outboard of the outermost bearing on ``side``: as ROSS computes
    it, the shaft elements wholly outboard and the lumped masses beyond the bearing
    (:attr:`LinearSystem.masses`); without that list, the tributary mass of the nodes outboard."""
    tol = 1e-12
    if system.masses:
        if side < 0:
            picked = [m for a, b, m in system.masses if (b <= left + tol and a < b)
                      or (a == b and a < left - tol)]  # fmt: skip
        else:
            picked = [m for a, b, m in system.masses if (a >= right - tol and a < b)
                      or (a == b and a > right + tol)]  # fmt: skip
        return float(sum(picked))
    ones = np.zeros(len(system.M))
    ones[0 : 4 * len(x) : 4] = 1.0
    tributary = (system.M @ ones)[0 : 4 * len(x) : 4]
    mask = x < left if side < 0 else x > right
    return float(tributary[mask].sum())


def api617_unbalance(
    system: LinearSystem,
    max_speed: float,
    mode: int = 0,
    modes: int = 12,
    max_damping_ratio: float | None = CRITICALLY_DAMPED,
):
    """Unbalance planes of API 617 for a forward mode (see the module docstring).

    Parameters
    ----------
    system : LinearSystem
        A nodal rotor (finite-element or ROSS import) with bearings.
    max_speed : float
        Maximum continuous speed ``N_mc`` (rad/s).
    mode : int
        Forward mode index (0: the first forward mode).
    modes : int
        ROSS's ``num_modes``: the forward mode is counted among the ``modes // 2`` modes
        selected and ordered as ROSS's ``run_modal`` (``damped_modes(order="ross")``), as ROSS
        3.1's ``api617_unbalance`` does; when they hold too few forward modes, among the
        ``modes`` modes of least ``|lambda|``.
    max_damping_ratio : float or None
        Modes damped beyond this ratio are not counted (API 617: amplification factor below
        2.5, ``zeta > 0.2``, is critically damped, no critical speed); None counts every
        forward mode (ROSS 3.1 does).

    Returns
    -------
    planes : list of (float, float, float)
        ``(position m, magnitude kg m, phase rad)``.
    loads : list of float
        The load ``W`` (kg) of each plane.
    frequency : float
        Damped natural frequency of the mode (rad/s).
    """
    shapes, k = _forward_mode(system, max_speed, mode, modes, max_damping_ratio)
    planes, weights = shape_unbalance(system, shapes, k, max_speed)
    return planes, weights, 2 * math.pi * shapes.modes.modes[k].frequency_hz


def shape_unbalance(system: LinearSystem, shapes, k: int, max_speed: float):
    """API 617's unbalance planes for mode ``k`` of ``shapes`` (steps 1 and 2 of the module
    docstring): ``(planes, loads)`` as ``api617_unbalance`` returns them.

    Parameters
    ----------
    system : LinearSystem
        The rotor (its journal loads give ``W``).
    shapes : rubrotor.linear.shapes.ModeShapes
        Mode shapes along the rotor.
    k : int
        Index of the mode among them.
    max_speed : float
        Maximum continuous speed ``N_mc`` (rad/s) of ``U_r``.
    """
    v, w, x = shapes.v[k], shapes.w[k], shapes.x
    amp = shapes.major[k]
    ref = int(np.argmax(amp))
    theta = _major_angle(v[ref], w[ref])
    proj = v * math.cos(theta) + w * math.sin(theta)
    sign = np.sign(np.real(proj * np.conj(proj[ref])))
    sign[sign == 0] = 1.0
    loads = _loads(system)
    journals = sorted(loads)
    left, right = journals[0], journals[-1]
    picked = []
    for lobe in _lobes(sign, amp):
        i = lobe[int(np.argmax(amp[lobe]))]
        inboard = left - 1e-12 <= x[i] <= right + 1e-12
        if (inboard and amp[i] >= 0.1 * amp[ref]) or (
            not inboard and (i == ref or amp[i] >= 0.5 * amp[ref])
        ):
            picked.append((i, inboard))
    n_in = sum(inb for _, inb in picked)
    planes, weights = [], []
    for i, inboard in picked:
        if inboard and n_in == 1:
            weight = sum(loads.values())
        elif inboard:
            weight = loads[min(journals, key=lambda p: abs(p - x[i]))]
        else:
            weight = _outboard_mass(system, x, left, right, -1 if x[i] < left else 1)
        phase = 0.0 if sign[i] == sign[ref] else math.pi
        planes.append((float(x[i]), 2 * residual_unbalance(weight, max_speed), phase))
        weights.append(weight)
    return planes, weights


@dataclass(frozen=True)
class ClearanceCheck:
    """API 617 close-clearance check (amplitudes peak to peak, clearances diametral, in m).

    Attributes
    ----------
    speeds : ndarray, shape (S,)
        Spin speeds (rad/s) of the unbalance response.
    min_speed, max_speed : float
        Minimum allowable and maximum continuous speed (rad/s).
    planes : list of (float, float, float)
        The unbalance ``(position m, magnitude kg m, phase rad)``.
    probe_response : ndarray, shape (P, S)
        Peak-to-peak amplitude at each probe (m).
    vibration_limit, max_probe_amplitude, scale_factor : float
        ``A_vl`` (m), ``A_max`` (m) and ``S_cc``.
    names : list of str
        The close clearances.
    positions, clearances : ndarray, shape (C,)
        Their positions (m) and diametral clearances ``2 c`` (m).
    scaled : ndarray, shape (C, S)
        Scaled peak-to-peak major axis ``2 S_cc a_major`` (m).
    mode : dict or None
        The mode the unbalance was placed for (None when the planes were given):
        ``forward_index`` (counted over the forward modes), ``frequency_rad_s`` (its damped
        natural frequency at ``max_speed``, the estimate of its critical speed),
        ``damping_ratio``, ``amplification_factor`` (``1 / (2 zeta)``, API 684's single-mode
        estimate), ``separation_margin`` (its distance to the operating range
        ``[min_speed, max_speed]``, relative to the nearer end; 0 inside) and ``whirl``.
        This is the mode ROSS 3.1's ``run_clearance_analysis`` places the unbalance for.
    criticals : list of rubrotor.linear.api617_criticals.ResponseCritical or None
        Every critical speed as API 617 defines it (response peaks at the probes with a
        half-power AF >= 2.5 up to the analysis range's top), each with its own unbalance,
        separation margins, clearance margins and verdict; None when not computed.
    trip_speed : float or None
        Trip speed (rad/s) of the criticals' clearance check.
    """

    speeds: np.ndarray
    min_speed: float
    max_speed: float
    planes: list
    probe_response: np.ndarray
    vibration_limit: float
    max_probe_amplitude: float
    scale_factor: float
    names: list
    positions: np.ndarray
    clearances: np.ndarray
    scaled: np.ndarray
    mode: dict | None = None
    criticals: list | None = None
    trip_speed: float | None = None

    @property
    def margin(self) -> np.ndarray:
        """``0.75 (2 c) - max(scaled)`` (m) per close clearance; negative fails."""
        return 0.75 * self.clearances - self.scaled.max(axis=1)

    @property
    def worst_speed(self) -> np.ndarray:
        """Speed (rad/s) of the largest scaled response per close clearance."""
        return self.speeds[np.argmax(self.scaled, axis=1)]

    @property
    def touching(self) -> list:
        """Per close clearance, the speeds (rad/s) where the scaled orbit reaches ``2 c``."""
        return [self.speeds[row >= c] for row, c in zip(self.scaled, self.clearances, strict=True)]

    def to_dict(self) -> dict:
        """JSON form printed by ``rubrotor clearance --json``."""
        return {
            "min_speed_rad_s": self.min_speed,
            "max_speed_rad_s": self.max_speed,
            "unbalance": [
                {"position_m": p, "magnitude_kg_m": m, "phase_rad": f} for p, m, f in self.planes
            ],  # fmt: skip
            "mode": self.mode,
            "trip_speed_rad_s": self.trip_speed,
            "criticals": None if self.criticals is None else [c.to_dict() for c in self.criticals],
            "vibration_limit_m_pp": self.vibration_limit,
            "max_probe_amplitude_m_pp": self.max_probe_amplitude,
            "scale_factor": self.scale_factor,
            "clearances": [
                {
                    "name": n,
                    "position_m": float(x),
                    "diametral_clearance_m": float(c),
                    "max_scaled_response_m_pp": float(r.max()),
                    "worst_speed_rad_s": float(ws),
                    "margin_m": float(mg),
                    "verdict": "pass" if mg >= 0 else "fail",
                    "touching_speeds_rad_s": t.tolist(),
                }
                for n, x, c, r, ws, mg, t in zip(
                    self.names,
                    self.positions,
                    self.clearances,
                    self.scaled,
                    self.worst_speed,
                    self.margin,
                    self.touching,
                    strict=True,
                )  # fmt: skip
            ],
        }


def _probe_pp(resp: np.ndarray, angles) -> np.ndarray:
    """Peak-to-peak amplitude (P, S) along each probe angle (rad), or of the major axis."""
    out = []
    for p, a in enumerate(angles):
        v, w = resp[:, p, 0], resp[:, p, 1]
        if a is None:
            out.append(np.abs(v + 1j * w) + np.abs(v - 1j * w))
        else:
            out.append(2 * np.abs(v * math.cos(a) + w * math.sin(a)))
    return np.array(out)


def clearance_check(
    system: LinearSystem,
    speeds,
    min_speed: float,
    max_speed: float,
    probes,
    clearances,
    mode: int = 0,
    planes=None,
    scale_factor_cap: float | None = 6.0,
    max_damping_ratio: float | None = CRITICALLY_DAMPED,
) -> ClearanceCheck:
    """API 617 close-clearance check of the unbalance response (see the module docstring).

    Parameters
    ----------
    system : LinearSystem
        A nodal rotor (finite-element or ROSS import) with bearings.
    speeds : array_like
        Spin speeds (rad/s); ``min_speed`` and ``max_speed`` are added.
    min_speed, max_speed : float
        Minimum allowable and maximum continuous speed (rad/s), ``0 <= min <= max``.
    probes : sequence of (float, float or None)
        Vibration probes: ``(position m, angle rad from +y towards +z)``; angle None reads the
        orbit's major axis.
    clearances : sequence of (str, float, float)
        Close clearances: ``(name, position m, radial clearance m)``.
    mode : int
        Forward mode placing the unbalance (``api617_unbalance``).
    planes : sequence of (float, float, float), optional
        Explicit unbalance ``(position m, kg m, rad)`` instead of API 617's placement.
    scale_factor_cap : float or None
        Upper limit of ``S_cc`` (API 617: 6); None for none (ROSS's default).
    max_damping_ratio : float or None
        See ``api617_unbalance``.

    Returns
    -------
    ClearanceCheck
    """
    if not 0 <= min_speed <= max_speed or max_speed <= 0:
        raise InputError("min_speed / max_speed", (min_speed, max_speed),
                         "0 <= minimum allowable <= maximum continuous speed, > 0 (rad/s)")  # fmt: skip
    if not clearances:
        raise InputError("contact", 0, "close clearances (a [[contact]] with its clearance)")
    if not probes:
        raise InputError("probes", probes, "at least one vibration probe (position m, angle)")
    s = np.union1d(np.asarray(speeds, float), [min_speed, max_speed])
    s = s[s > 0]
    info = None
    if planes is None:
        planes = api617_unbalance(system, max_speed, mode, 12, max_damping_ratio)[0]
        info = _mode_info(system, min_speed, max_speed, mode, max_damping_ratio)
    points = [p for p, _ in probes] + [c[1] for c in clearances]
    resp = unbalance_response(system, s, list(planes), points).complex_response
    pp = _probe_pp(resp[:, : len(probes)], [a for _, a in probes])
    band = (s >= min_speed) & (s <= max_speed)
    amax = float(pp[:, band].max())
    if not amax > 0:
        raise InputError("probes", probes, "probes that see the unbalance response")
    avl = vibration_limit(max_speed)
    scc = avl / amax if scale_factor_cap is None else min(avl / amax, float(scale_factor_cap))
    major = _probe_pp(resp[:, len(probes) :], [None] * len(clearances))
    return ClearanceCheck(
        speeds=s, min_speed=float(min_speed), max_speed=float(max_speed), planes=list(planes),
        probe_response=pp, vibration_limit=avl, max_probe_amplitude=amax, scale_factor=scc,
        names=[c[0] for c in clearances], positions=np.array([c[1] for c in clearances], float),
        clearances=2 * np.array([c[2] for c in clearances], float), scaled=scc * major,
        mode=info,
    )  # fmt: skip


def _mode_info(system, min_speed: float, max_speed: float, mode: int, max_zeta) -> dict:
    """What :attr:`ClearanceCheck.mode` says of forward mode ``mode`` at ``max_speed``."""
    shapes, k = _forward_mode(system, max_speed, mode, 12, max_zeta)
    m = shapes.modes.modes[k]
    f = 2 * math.pi * m.frequency_hz
    if f < min_speed:
        sm = (min_speed - f) / min_speed
    elif f > max_speed:
        sm = (f - max_speed) / max_speed
    else:
        sm = 0.0
    zeta = m.damping_ratio
    return {
        "forward_index": int(mode),
        "frequency_rad_s": f,
        "damping_ratio": zeta,
        "amplification_factor": 1 / (2 * zeta) if zeta > 0 else None,
        "separation_margin": sm,
        "whirl": m.whirl,
    }
