"""Forced response of any linear rotor in the frequency domain: the steady response to rotating
unbalance over spin speeds (:func:`unbalance_response`), a force at a station at excitation
frequencies independent of the spin (as ROSS's ``run_freq_response``), and the unbalance
response of a scenario with every one of its unbalance planes.

Equations
---------
A harmonic force at spin ``Omega`` and excitation frequency ``w`` (both rad/s) gives the steady
response ``q = Re(Q e^{i w t})`` with

    ``(K + K_s(Omega, w) - w^2 M + i w (C + C_s(Omega, w) + Omega G)) Q = B(x) F``

(each bearing table read on its own axis, as ROSS 3.x reads them: a table against speed at the
spin ``Omega``, a table against frequency, e.g. a magnetic bearing's, at the excitation ``w``;
one banded LU solve per frequency, by LAPACK: ``rubrotor.linear.lapack``). The force ``F = [F_y, F_z]`` of amplitude ``f`` (N) at angle ``theta``
(rad, from ``+y`` towards ``+z``) is

* ``"fixed"``: ``f [cos theta, sin theta] cos(w t)``, so ``F = f [cos theta, sin theta]``;
* ``"forward"``: ``F_y + i F_z = f e^{i (w t + theta)}`` (turning with the spin),
  ``F = f e^{i theta} [1, -i]``;
* ``"backward"``: ``F_y + i F_z = f e^{-i (w t - theta)}``, ``F = f e^{-i theta} [1, i]``.

At a probe ``v(t) = |V| cos(w t + arg V)`` and likewise ``w(t)``; the orbit's major semi-axis
is ``(|V + i W| + |V - i W|) / 2`` (m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.core.status import OK
from rubrotor.errors import InputError, ScenarioError
from rubrotor.linear.band import _band_parts
from rubrotor.linear.lapack import frequency_sweep, unbalance_sweep
from rubrotor.linear.roots import _speed_array
from rubrotor.rotors.linear import LinearSystem, check_table_axes

__all__ = [
    "FORCE_KINDS",
    "FrequencyResponse",
    "UnbalanceResponse",
    "unbalance_response",
    "force_vector",
    "frequency_response",
    "scenario_unbalance_response",
    "unbalance_to_dict",
]

FORCE_KINDS = ("fixed", "forward", "backward")


@dataclass(frozen=True)
class UnbalanceResponse:
    """Steady synchronous response to unbalance at probe positions.

    Attributes
    ----------
    speeds : ndarray, shape (S,)
        Spin speeds (rad/s).
    probes : ndarray, shape (P,)
        Probe positions (m).
    amplitude : ndarray, shape (S, P, 2)
        Amplitude of ``v`` and ``w`` (m).
    phase : ndarray, shape (S, P, 2)
        Phase of ``v`` and ``w`` (rad): ``v(t) = amplitude cos(Omega t + phase)``.
    major : ndarray, shape (S, P)
        Major semi-axis of the orbit (m).
    complex_response : ndarray, shape (S, P, 2), complex
        ``V``, ``W`` with ``v(t) = Re(V exp(i Omega t))`` (m).
    """

    speeds: np.ndarray
    probes: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    major: np.ndarray
    complex_response: np.ndarray

    def to_dict(self) -> dict:
        """JSON form printed by ``rubrotor unbalance --json`` (``unbalance_to_dict``)."""
        return unbalance_to_dict(self)


def unbalance_response(system: LinearSystem, speeds, unbalances, probes) -> UnbalanceResponse:
    """Steady response to rotating unbalance, solved in the frequency domain.

    Each unbalance ``(position m, magnitude kg m, phase rad)`` is a force
    ``F_y + i F_z = m e Omega^2 exp(i (Omega t + phase))`` turning with the spin. On the real DOFs
    ``f(t) = Re(Fc exp(i Omega t))`` with ``Fc = B(x) [1, -i] m e Omega^2 exp(i phase)``, and the
    response ``q = Re(Q exp(i Omega t))`` solves
    ``(K(Omega) - Omega^2 M + i Omega (C(Omega) + Omega G)) Q = Fc`` at each speed (one exact LU
    solve per speed, LAPACK banded LU for FE rotors: ``rubrotor.linear.lapack``).

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    speeds : array_like
        Increasing spin speeds (rad/s), > 0.
    unbalances : sequence of (float, float, float)
        ``(position m, magnitude kg m, phase rad)`` per plane.
    probes : sequence of float
        Probe positions (m).

    Returns
    -------
    UnbalanceResponse
    """
    s = _speed_array("speeds", speeds)
    if not unbalances:
        raise InputError("unbalances", unbalances, "at least one (position m, kg m, rad) plane")
    b = np.zeros(system.n_dof, complex)
    for pos, me, ph in unbalances:
        if not (math.isfinite(me) and me >= 0 and math.isfinite(ph)):
            raise InputError("unbalance", (pos, me, ph), "magnitude >= 0 (kg m), finite phase")
        b += system.force_map(pos) @ np.array([1.0, -1j]) * me * np.exp(1j * ph)
    if not len(probes):
        raise InputError("probes", probes, "at least one probe position (m)")
    rows = np.concatenate([system.output_rows(p) for p in probes]).astype(complex)
    check_table_axes(system, "unbalance_response", speed=s, frequency=s)
    out, status, at = unbalance_sweep(_band_parts(system, s), s, b, rows)
    if status != OK:
        raise InputError("speeds", float(s[at]), "speeds off the undamped critical speeds (rad/s)")
    resp = out.reshape(s.size, len(probes), 2)
    v, w_ = resp[..., 0], resp[..., 1]
    # orbit semi-axes of v = Re(V e^{it}), w = Re(W e^{it}): |(V + i W)|/2 +- |(V - i W)|/2
    major = 0.5 * (np.abs(v + 1j * w_) + np.abs(v - 1j * w_))
    return UnbalanceResponse(
        speeds=s,
        probes=np.asarray(probes, float),
        amplitude=np.abs(resp),
        phase=np.angle(resp),
        major=major,
        complex_response=resp,
    )


@dataclass(frozen=True)
class FrequencyResponse:
    """Steady response to a harmonic force at probe positions.

    Attributes
    ----------
    frequencies : ndarray, shape (F,)
        Excitation frequencies ``w`` (rad/s).
    speed_rad_s : float
        Spin speed (rad/s).
    position : float
        Station of the force (m).
    kind : str
        ``"fixed"``, ``"forward"`` or ``"backward"``.
    direction : float
        Angle ``theta`` of the force (rad).
    magnitude : float
        Force amplitude ``f`` (N).
    probes : ndarray, shape (P,)
        Probe positions (m).
    complex_response : ndarray, shape (F, P, 2), complex
        ``V``, ``W`` (m) with ``v(t) = Re(V e^{i w t})``.
    """

    frequencies: np.ndarray
    speed_rad_s: float
    position: float
    kind: str
    direction: float
    magnitude: float
    probes: np.ndarray
    complex_response: np.ndarray

    @property
    def amplitude(self) -> np.ndarray:
        """``|V|``, ``|W|`` (m), shape (F, P, 2)."""
        return np.abs(self.complex_response)

    @property
    def phase(self) -> np.ndarray:
        """``arg V``, ``arg W`` (rad), shape (F, P, 2)."""
        return np.angle(self.complex_response)

    @property
    def major(self) -> np.ndarray:
        """Major semi-axis of the orbit (m), shape (F, P)."""
        v, w = self.complex_response[..., 0], self.complex_response[..., 1]
        return 0.5 * (np.abs(v + 1j * w) + np.abs(v - 1j * w))

    def to_dict(self) -> dict:
        """The JSON form printed by ``rubrotor response --json``."""
        return {
            "speed_rad_s": self.speed_rad_s,
            "force": {
                "position_m": self.position,
                "kind": self.kind,
                "direction_rad": self.direction,
                "magnitude_N": self.magnitude,
            },
            "probes": [
                _probe_dict(
                    float(p), "frequency_rad_s", self.frequencies, self.complex_response[:, i]
                )
                for i, p in enumerate(self.probes)
            ],
        }


def _probe_dict(position: float, axis: str, values: np.ndarray, resp: np.ndarray) -> dict:
    """One probe's amplitudes (m, 0-peak), phases (rad) and major semi-axis (m, 0-peak) against
    ``axis``; ``"amplitude": "0-peak"`` says so in the JSON (API 617's check is peak-to-peak,
    its keys end in ``_pp``)."""
    v, w = resp[:, 0], resp[:, 1]
    major = 0.5 * (np.abs(v + 1j * w) + np.abs(v - 1j * w))
    return {
        "position_m": position,
        "amplitude": "0-peak",
        axis: np.asarray(values, float).tolist(),
        "amplitude_y_m": np.abs(v).tolist(),
        "phase_y_rad": np.angle(v).tolist(),
        "amplitude_z_m": np.abs(w).tolist(),
        "phase_z_rad": np.angle(w).tolist(),
        "major_m": major.tolist(),
    }


def unbalance_to_dict(resp: UnbalanceResponse) -> dict:
    """The JSON form printed by ``rubrotor unbalance --json``: per probe, speeds (rad/s),
    amplitudes (m), phases (rad) and the orbit's major semi-axis (m)."""
    return {
        "probes": [
            _probe_dict(float(p), "speed_rad_s", resp.speeds, resp.complex_response[:, i])
            for i, p in enumerate(resp.probes)
        ]
    }


def force_vector(kind: str, magnitude: float = 1.0, direction: float = 0.0) -> np.ndarray:
    """Complex ``[F_y, F_z]`` (N) of a harmonic force (see the module docstring).

    Parameters
    ----------
    kind : {"fixed", "forward", "backward"}
        Fixed in direction, or rotating with or against the spin.
    magnitude : float
        Amplitude ``f`` (N), ``>= 0``.
    direction : float
        Angle ``theta`` (rad) from ``+y`` towards ``+z``.

    Returns
    -------
    ndarray, shape (2,), complex

    Examples
    --------
    >>> force_vector("forward", 2.0)
    array([2.+0.j, 0.-2.j])
    """
    if kind not in FORCE_KINDS:
        raise InputError("kind", kind, " or ".join(f'"{k}"' for k in FORCE_KINDS))
    for name, value in (("magnitude", magnitude), ("direction", direction)):
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise InputError(name, value, "a finite number (N for magnitude, rad for direction)")
    if magnitude < 0:
        raise InputError("magnitude", magnitude, "a force amplitude >= 0 (N)")
    if kind == "fixed":
        return magnitude * np.array([math.cos(direction), math.sin(direction)], complex)
    if kind == "forward":
        return magnitude * np.exp(1j * direction) * np.array([1.0, -1j])
    return magnitude * np.exp(-1j * direction) * np.array([1.0, 1j])


def _frequencies(values) -> np.ndarray:
    w = np.asarray(values, dtype=float)
    if w.ndim != 1 or w.size < 1 or not np.all(np.isfinite(w)) or np.any(w < 0):
        raise InputError("frequencies", values, "finite excitation frequencies >= 0 (rad/s)")
    return w


def frequency_response(
    system: LinearSystem,
    frequencies,
    position: float,
    probes,
    kind: str = "fixed",
    magnitude: float = 1.0,
    direction: float = 0.0,
    speed: float = 0.0,
) -> FrequencyResponse:
    """Steady response to a harmonic force at one station, over excitation frequencies.

    Parameters
    ----------
    system : LinearSystem
        The rotor (:func:`rubrotor.linear_system` makes it from a scenario).
    frequencies : array_like
        Excitation frequencies ``w`` (rad/s), ``>= 0``, independent of the spin.
    position : float
        Station of the force (m).
    probes : sequence of float
        Probe positions (m).
    kind : {"fixed", "forward", "backward"}
        Force fixed in direction, or rotating forward or backward at ``w``.
    magnitude : float
        Force amplitude (N).
    direction : float
        Force angle at ``t = 0`` (rad, from ``+y`` towards ``+z``).
    speed : float
        Spin speed ``Omega`` (rad/s): gyroscopic moments and speed-dependent bearings
        (frequency-dependent ones are read at each excitation frequency).

    Returns
    -------
    FrequencyResponse

    Raises
    ------
    InputError
        A bad argument, or a frequency at which the undamped system is singular.
    """
    w = _frequencies(frequencies)
    if isinstance(speed, bool) or not isinstance(speed, int | float) or not speed >= 0:
        raise InputError("speed", speed, "a finite spin speed >= 0 (rad/s)")
    if not math.isfinite(speed):
        raise InputError("speed", speed, "a finite spin speed >= 0 (rad/s)")
    force = force_vector(kind, magnitude, direction)
    probes = np.atleast_1d(np.asarray(probes, float))
    if probes.size == 0:
        raise InputError("probes", probes, "at least one probe position (m)")
    rhs = system.force_map(position) @ force
    rows = np.concatenate([system.output_rows(float(p)) for p in probes]).astype(complex)
    check_table_axes(system, "frequency_response", speed=speed, frequency=w)
    if any(s.axis == "frequency" and s.tabulated for s in system.supports):
        parts = _band_parts(system, np.full(w.size, float(speed)), w)  # tables at each w
    else:
        parts = _band_parts(system, np.array([float(speed)]))
    out, status, at = frequency_sweep(parts, float(speed), w, rhs, rows)
    if status != OK:
        raise InputError("frequencies", float(w[at]), "frequencies off the undamped resonances")
    return FrequencyResponse(
        frequencies=w,
        speed_rad_s=float(speed),
        position=float(position),
        kind=kind,
        direction=float(direction),
        magnitude=float(magnitude),
        probes=probes,
        complex_response=out.reshape(w.size, probes.size, 2),
    )


def scenario_unbalance_response(scenario, speeds, probes=None) -> UnbalanceResponse:
    """Unbalance response of a scenario with every unbalance plane it has.

    Parameters
    ----------
    scenario : Scenario
        Its ``[unbalance]`` or every ``[[unbalance]]`` plane (``Scenario.unbalances``) excites the rotor.
    speeds : array_like
        Increasing spin speeds (rad/s), ``> 0``.
    probes : sequence of float, optional
        Probe positions (m); default the scenario's ``[simulation] probes``, else the planes'
        positions.

    Returns
    -------
    UnbalanceResponse
        Amplitudes (m) and phases (rad) of ``v``, ``w`` at every probe and speed.

    Raises
    ------
    ScenarioError
        The scenario has no unbalance (field ``"unbalance"``).
    """
    from rubrotor.linear.verbs import linear_system

    planes = scenario.unbalances
    if not planes:
        raise ScenarioError("unbalance", None, "an [unbalance] or [[unbalance]] table (kg m at m)")
    if probes is None:
        sim = scenario.simulation.probes if scenario.simulation is not None else ()
        probes = sim or tuple(dict.fromkeys(u.position for u in planes))
    system = linear_system(scenario, tuple(float(p) for p in probes))
    return unbalance_response(
        system, speeds, [(u.position, u.magnitude, u.phase) for u in planes], list(probes)
    )
