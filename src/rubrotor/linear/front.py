"""One function per linear verb, for any rotor: what ``rubrotor VERB`` prints, from Python.

Each takes a :class:`~rubrotor.scenario.Scenario` (or a scenario file's path), and where it makes
sense a :class:`~rubrotor.rotors.fe.Rotor`, a :class:`~rubrotor.rotors.shaft.Shaft` or a
:class:`~rubrotor.rotors.linear.LinearSystem`, with the command's defaults, and returns the object
the command prints (``to_dict()`` is its ``--json``). Speed and frequency ranges are arrays in
rad/s or range strings with a unit (``"0:12000rpm:61"``, ``rubrotor.units.parse_range``).
``modes`` and ``critical_speeds`` live in :mod:`rubrotor.linear.verbs`; all are in
``rubrotor.__all__``.
"""

from __future__ import annotations

import dataclasses
import math

from rubrotor.errors import InputError
from rubrotor.linear.verbs import _loaded, _model, _shaft_and_speed, _speed
from rubrotor.scenario.load import Scenario

__all__ = [
    "campbell",
    "static",
    "unbalance_response",
    "frequency_response",
    "clearance_check",
    "level1",
    "ucs",
    "mode_shapes",
]


def campbell(scenario_or_shaft, speeds, n: int = 8):
    """Campbell diagram data of any rotor over a range of spin speeds.

    Parameters
    ----------
    scenario_or_shaft : Scenario, Shaft, Rotor, LinearSystem or path-like
        The rotor.
    speeds : array_like or str
        Spin speeds (rad/s), or a range ``"START:STOP:COUNT"`` with an optional unit after a
        number (``"0:12000rpm:61"``, ``rubrotor.units.parse_range``).
    n : int
        Modes followed on any other rotor than the continuous shaft (default 8).

    Returns
    -------
    dict or CampbellData
        The continuous shaft: the dict of ``rubrotor.linear.shaft.campbell`` (closed-form
        whirl frequencies, Hz). Any other rotor: ``rubrotor.linear.campbell.CampbellData``
        (frequencies, log decs and whirl of its ``n`` lowest modes).
    """
    from rubrotor.units import as_speeds

    sp = as_speeds(speeds)
    model = _model(scenario_or_shaft, "scenario_or_shaft")
    if model.linear == "closed-form":
        from rubrotor.linear.shaft import campbell as shaft_campbell

        return shaft_campbell(_shaft_and_speed(model)[0], sp)
    from rubrotor.linear.campbell import campbell_data

    return campbell_data(model.linear_system(), sp, n=n)


def static(obj, speed: float | None = None, gravity=None, loads=None):
    """Static deflection under gravity and loads and the bearing reactions of any rotor
    (``rubrotor static``); see :func:`rubrotor.linear.static.static_analysis`.

    Parameters
    ----------
    obj : Scenario, Rotor, Shaft, LinearSystem or path-like
    speed : float, optional
        Spin speed for speed-dependent bearings (rad/s); default the scenario's.
    gravity, loads
        See :func:`~rubrotor.linear.static.static_analysis`.

    Returns
    -------
    StaticResult
    """
    from rubrotor.linear.static import static_analysis

    return static_analysis(_loaded(obj), speed, gravity, loads)


def bearings(obj, speeds):
    """Each fluid-film support's static position and linearised coefficients at each speed
    (``rubrotor bearings``); see ``rubrotor.linear.bearings.bearing_coefficients``.

    Parameters
    ----------
    obj : Scenario or path-like
    speeds : array_like or str
        Spin speeds (rad/s), or ``"START:STOP:COUNT"`` (rad/s, rpm or Hz).

    Returns
    -------
    BearingsResult
        With ``to_dict()``.
    """
    from rubrotor.linear.bearings import bearing_coefficients
    from rubrotor.units import parse_range

    sp = parse_range(speeds, "speeds") if isinstance(speeds, str) else speeds
    return bearing_coefficients(_model(_loaded(obj)), sp)


def unbalance_response(scenario, speeds, probes=None):
    """Unbalance response of a scenario's every unbalance plane at probes, over spin speed
    (``rubrotor unbalance``).

    Parameters
    ----------
    scenario : Scenario or path-like
    speeds : array_like or str
        Increasing spin speeds (rad/s, ``> 0``) or a range (``"10:15000rpm:300"``).
    probes : sequence of float, optional
        Probe positions (m); default the scenario's ``[simulation] probes``, else the planes'.

    Returns
    -------
    UnbalanceResponse
        Orbit semi-axes (0-peak, m) and phases (rad) at every probe and speed.
    """
    from rubrotor.linear.response import scenario_unbalance_response
    from rubrotor.scenario.load import as_scenario
    from rubrotor.units import as_speeds

    return scenario_unbalance_response(as_scenario(scenario), as_speeds(speeds), probes)


def frequency_response(obj, frequencies, at: float, probes=None, kind: str = "fixed",
                       force: float = 1.0, direction: float = 0.0, speed: float | None = None):  # fmt: skip
    """Forced response of any rotor to a fixed or rotating force at a station
    (``rubrotor response``); see :func:`rubrotor.linear.response.frequency_response`.

    Parameters
    ----------
    obj : Scenario, Rotor, Shaft, LinearSystem or path-like
    frequencies : array_like or str
        Excitation frequencies (rad/s) or a range (``"0:50hz:200"``).
    at : float
        Force station (m).
    probes : sequence of float, optional
        Probe positions (m); default the force station.
    kind : {"fixed", "forward", "backward"}
    force : float
        Amplitude (N, 0-peak).
    direction : float
        Force angle at ``t = 0`` (rad, from ``+y`` towards ``+z``).
    speed : float, optional
        Spin speed (rad/s); default the scenario's, or 0.

    Returns
    -------
    FrequencyResponse
    """
    from rubrotor.linear.response import frequency_response as response
    from rubrotor.units import as_speeds

    model = _model(obj)
    probes = [at] if probes is None else list(probes)
    system = model.linear_system((at, *probes))
    return response(system, as_speeds(frequencies, "frequencies"), at, probes, kind, force,
                    direction, _speed(model, speed))  # fmt: skip


def _gaps(scenario) -> list:
    """``(name, position m, radial clearance m)`` of every contact of a scenario."""
    from rubrotor.errors import ScenarioError

    if not isinstance(scenario, Scenario) or not scenario.contacts:
        raise ScenarioError("contact", None, "a [contact] or [[contact]] table: the clearances")
    return [(f"contact {i + 1} at {c.position:g} m", c.position, c.clearance)
            for i, c in enumerate(scenario.contacts)]  # fmt: skip


def clearance_check(scenario, max_speed: float | None = None, min_speed: float | None = None,
                    speeds=None, probes=None, mode: int = 0, cap: bool = True,
                    trip_speed: float | None = None, criticals: bool = True):  # fmt: skip
    """API 617 close-clearance check of the unbalance response at every contact
    (``rubrotor clearance``); see :func:`rubrotor.linear.api617.clearance_check`.

    Parameters
    ----------
    scenario : Scenario or path-like
        The rotor and its contacts (their radial clearances).
    max_speed : float, optional
        Maximum continuous speed ``N_mc`` (rad/s); default the scenario's speed.
    min_speed : float, optional
        Minimum allowable speed ``N_ma`` (rad/s); default 0.7 ``N_mc``.
    speeds : array_like or str, optional
        Response speeds (rad/s) or a range; default 0 to 1.25 ``N_mc``, 251 speeds.
    probes : sequence of (float, float or None), optional
        ``(position m, angle rad from +y towards +z or None: the major axis)``; default each
        bearing's station, major axis.
    mode : int
        Forward mode placing the unbalance, counted from 0 (0: the first forward mode).
    cap : bool
        Cap the scale factor at 6 (API 617).
    trip_speed : float, optional
        Trip speed (rad/s) of the criticals' clearance check; default 1.05 ``N_mc``.
    criticals : bool
        Also find every critical speed as API 617 defines it (``ClearanceCheck.criticals``).

    Returns
    -------
    ClearanceCheck
        Responses and clearances peak-to-peak (m), as the keys of its ``to_dict`` say.
    """
    import numpy as np

    from rubrotor.linear.api617 import clearance_check as check
    from rubrotor.scenario.load import as_scenario
    from rubrotor.units import as_speeds

    scenario = as_scenario(scenario)
    model = _model(scenario, "scenario")
    nmc = _speed(model, max_speed, "max_speed")
    nma = _speed(model, 0.7 * nmc if min_speed is None else min_speed, "min_speed")
    if not 0 < nmc or nma > nmc:
        raise InputError("min_speed", nma, f"a speed in [0, {nmc:g}] rad/s (maximum > 0)")
    sp = np.linspace(0.0, 1.25 * nmc, 251) if speeds is None else as_speeds(speeds)
    gaps = _gaps(scenario)
    probes = None if probes is None else [(float(p), a) for p, a in probes]
    system = model.linear_system([p for p, _ in probes or []])
    probes = probes or [(sup.position, None) for sup in system.supports]
    res = check(system, sp, nma, nmc, probes, gaps, mode,
                scale_factor_cap=6.0 if cap else None)  # fmt: skip
    if not criticals:
        return res
    return with_criticals(res, system, probes, gaps, trip_speed)


def with_criticals(res, system, probes, gaps, trip_speed=None):
    """``res`` (a ClearanceCheck) with API 617's critical speeds from the response at the
    probes (:func:`rubrotor.linear.api617_criticals.response_criticals`)."""
    from rubrotor.linear.api617_criticals import response_criticals

    trip = 1.05 * res.max_speed if trip_speed is None else float(trip_speed)
    found = response_criticals(system, res.min_speed, res.max_speed, probes, gaps, trip)
    return dataclasses.replace(res, criticals=found, trip_speed=trip)


def level1(scenario, speed: float | None = None, at: float | None = None, stiffness=None,
           qa: float | None = None, stages=None):  # fmt: skip
    """API 684 Level I stability: log dec of the first forward mode against added
    cross-coupled stiffness (``rubrotor level1``); see :func:`rubrotor.linear.api684.level1`.

    Parameters
    ----------
    scenario : Scenario, Rotor or path-like
    speed : float, optional
        Maximum continuous speed (rad/s); default the scenario's.
    at : float, optional
        Station of the cross-coupling (m); default midway between the outermost bearings for a
        between-bearing rotor, the heaviest overhung disk for an overhung one (the result's
        ``location`` says which).
    stiffness : array_like, optional
        Cross-coupled stiffness values (N/m); default 1e4..1e9, 41 log-spaced.
    qa : float, optional
        Anticipated cross-coupling ``Q_A`` (N/m).
    stages : sequence of (float, float, float[, float]), optional
        Compressor stages ``(power W, diameter m, width m[, density ratio])`` giving ``Q_A``
        (API 684 / Wachel), instead of ``qa``.

    Returns
    -------
    Level1
    """
    from rubrotor.linear.api684 import anticipated_cross_coupling
    from rubrotor.linear.api684 import level1 as level_one

    model = _model(scenario, "scenario")
    sp = _speed(model, speed)
    location = "given"
    if at is None:
        at, location = level1_station(model)
    if stages:
        rows = [tuple(st) + (1.0,) * (4 - len(st)) for st in stages]
        p, d, h, r = zip(*rows, strict=True)
        qa = anticipated_cross_coupling(p, sp, d, h, r)
    if qa is not None and not (math.isfinite(qa) and qa > 0):
        raise InputError("qa", qa, "a cross-coupled stiffness > 0 (N/m)")
    res = level_one(model.linear_system((at,)), sp, at, stiffness, qa)
    return dataclasses.replace(res, location=location)


def level1_station(model) -> tuple[float, str]:
    """Level I's default station (m) on a model and why: mid-span between the outermost
    bearings, or the heaviest overhung disk (:func:`rubrotor.linear.api684.default_station`)."""
    from rubrotor.linear.api684 import default_station

    geo = model.geometry()
    disks = [(d.position, d.mass) for d in geo.disks]
    return default_station(list(model.carrying_bearings()), disks, geo.length)


def ucs(obj, stiffness=None, n: int = 4):
    """Undamped critical speed map of any rotor (``rubrotor ucs``); see
    :func:`rubrotor.linear.ucs.ucs_map` (stiffness N/m, speeds rad/s)."""
    from rubrotor.linear.ucs import ucs_map

    return ucs_map(_model(obj).linear_system(), stiffness, n)


def mode_shapes(obj, speed: float | None = None, n: int = 4):
    """Mode shapes along any rotor at a speed (``rubrotor shapes``); see
    :func:`rubrotor.linear.shapes.mode_shapes` (speed rad/s)."""
    from rubrotor.linear.shapes import mode_shapes as shapes

    model = _model(obj)
    return shapes(model.linear_system(), _speed(model, speed), n)
