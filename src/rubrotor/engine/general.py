"""Run a scenario through the general engine (:func:`rubrotor.engine.driver.simulate_general`).

:func:`rubrotor.engine.simulate.simulate` sends here every scenario with ``Scenario.engine`` set (a
general ``[[section]]`` rotor, or a key only the general engine supports, see
:mod:`rubrotor.scenario.dynamics`); the seed's scenarios keep the seed's engine.

The results Dataset has the engine's layout: ``v, w`` (m), ``v_dot, w_dot`` (m/s) and
``v_ddot, w_ddot`` (m/s^2, second-order central differences of the saved velocity) on
dimensions ``(station, time)`` (contact stations first, then probes); ``stator_y ...
friction_force`` (m, m/s, N) on ``(contact, time)``; events; attributes ``status``,
``status_message``, ``speed_rad_s``, ``speed_hz``, ``speed_end_rad_s`` (run-ups),
``scenario``, ``scenario_name``, ``integrator_stats`` and ``final_state`` (JSON: the rotor state
``[q, q']`` at the end, for ``[initial] state = "file"``).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from rubrotor.engine.parts import Run, spin_angle
from rubrotor.engine.stream import check_size
from rubrotor.errors import InputError, ScenarioError

__all__ = ["engine_problem", "simulate_engine", "STREAM_SAMPLES"]

STREAM_SAMPLES = 1 << 21
"""``rubrotor simulate`` streams runs with more saved samples than this to the results file."""


def _system(scenario, probes):
    from rubrotor.rotors.shaft_system import continuous_system

    eng = scenario.engine
    if scenario.model.fe_rotor:
        return scenario.rotor.linear_system(tuple(sorted(set(eng.positions + tuple(probes)))))
    return continuous_system(scenario.shaft, scenario.damping)


def _duration(integ, speed: float, speed_end: float | None) -> float:
    if integ.duration is not None:
        return integ.duration
    mean = speed if speed_end is None else 0.5 * (speed + speed_end)
    return integ.revolutions * 2 * math.pi / mean


def _restart(path: str, scenario, system, speed: float) -> tuple[np.ndarray, float, dict | None]:
    """State, start time (s) and restart state stored in an earlier results file of the engine.

    The file must belong to the scenario's model (:func:`rubrotor.engine.restart.fingerprint`,
    refused naming what differs) and hold a finite state; a file that stopped partial (killed,
    interrupted, diverged) continues from the state at the end of its last completed chunk.
    """
    import xarray as xr

    if not Path(path).is_file():
        raise ScenarioError("initial.path", path, "an existing results file (.nc)")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:  # lazily: read what is used
            return _restart_from(ds, path, scenario, system, speed)
    except (OSError, ValueError) as exc:
        raise ScenarioError("initial.path", path, f"a readable results file ({exc})") from None


def _restart_from(ds, path: str, scenario, system, speed: float):
    """:func:`_restart` on the opened file."""
    from rubrotor.engine.restart import check_fingerprint, fingerprint, finite_state, unflatten

    at = ds.attrs
    if "final_state" not in at and "restart_vector" not in ds:
        raise ScenarioError("initial.path", path, "a results file written by the general engine")
    if "speed_end_rad_s" in at:
        raise ScenarioError("initial.path", path, "a constant-speed results file")
    if not math.isclose(float(at["speed_rad_s"]), speed, rel_tol=1e-12):
        raise ScenarioError("initial.path", path, f"a results file run at {speed:g} rad/s")
    if "model_fingerprint" in at:
        now = fingerprint(system, scenario.engine.stations, speed)
        check_fingerprint(json.loads(at["model_fingerprint"]), now, path)
    snap = None
    if "restart_vector" in ds and ds.sizes["checkpoint"]:
        lay = json.loads(ds["restart_vector"].attrs["layout"])
        t_last = float(ds["restart_time"].values[-1])
        snap = unflatten(ds["restart_vector"].values[-1], lay, t_last)
        x, end = np.array(snap["x"], float), t_last
        if not finite_state(snap):
            raise ScenarioError("initial.path", path, "a results file whose kept state is finite")
    else:  # a file of an earlier version: the rotor state only
        x = np.array(json.loads(at["final_state"]), float)
        end = float(
            at.get("end_time_s", float(at.get("start_time_s", 0.0)) + ds["time"].values[-1])
        )
        if at.get("status") != "complete" or not np.all(np.isfinite(x)):
            raise ScenarioError("initial.path", path,
                                "a complete results file (this one has no restart state)")  # fmt: skip
    n = system.n_dof
    if x.shape != (2 * n,):
        raise ScenarioError("initial.path", path, f"a results file of this rotor ({2 * n} states)")
    return x, end, snap


def engine_problem(scenario, integrator=None):
    """The engine's inputs for a scenario (see :func:`_problem`; without the restart state)."""
    return _problem(scenario, integrator)[:4]


def _problem(scenario, integrator=None):
    """The engine's inputs for a scenario.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A scenario with ``engine`` set.
    integrator : rubrotor.engine.settings.Integrator, optional
        Overrides ``[simulation]``.

    Returns
    -------
    system : rubrotor.rotors.linear.LinearSystem
    run : rubrotor.engine.parts.Run
    kwargs : dict
        ``stations``, ``unbalances``, ``loads``, ``gravity`` of ``simulate_general``.
    t0 : float
        Start time (s): the end time of the file a restart continues, else 0.
    snap : dict or None
        The restart state of that file (``simulate_general(resume=...)``).
    """
    eng = scenario.engine
    integ = integrator or scenario.simulation
    if integ is None:
        raise InputError("simulation", None, "a [simulation] section (revolutions or duration)")
    if integ.method != "exponential":
        raise ScenarioError("simulation.method", integ.method, '"exponential" (general engine)')
    speed, end, table = scenario.speed, eng.speed_end, eng.speed_table
    if speed <= 0:
        raise ScenarioError("speed", speed, "a spin speed > 0 (rad/s) for a time simulation")
    system = _system(scenario, integ.probes)
    step = integ.step_seconds(speed)
    adaptive = step is None
    if adaptive and (end is not None or table):
        raise ScenarioError(
            "simulation.dt", None, 'a fixed step (dt or dtau) with a "linear" or "table" profile'
        )
    if table and integ.duration is None:
        raise ScenarioError("simulation.revolutions", integ.revolutions,
                            'simulation.duration (s) instead, with speed.profile = "table"')  # fmt: skip
    unb, t0, initial, snap = eng.unbalances, 0.0, eng.initial, None
    if initial == "file":
        initial, t0, snap = _restart(eng.initial_path, scenario, system, speed)
        # constant speed: continuing at t0 equals starting at 0 with phases advanced by Omega t0
        unb = tuple(dataclasses.replace(u, phase=u.phase + speed * t0) for u in unb)
    run = Run(
        speed=speed, duration=_duration(integ, speed, end),
        step=integ.output_spacing(speed) if adaptive else step,
        save_every=1 if adaptive else integ.save_every, modes=eng.modes, cutoff=eng.cutoff,
        residual=eng.residual, initial=initial, probes=integ.probes,
        max_displacement=integ.max_displacement, speed_end=end, speed_step=eng.speed_step,
        speed_table=table,
        rtol=integ.rtol if adaptive else None, atol=integ.atol,
    )  # fmt: skip
    kwargs = dict(stations=eng.stations, unbalances=unb, loads=eng.loads, gravity=eng.gravity)
    return system, run, kwargs, t0, snap


def _check_size(scenario, run: Run, stream) -> None:
    """Refuse a run too large for memory (or disk), naming the scenario's keys, before it runs."""
    n = int(math.floor(run.duration / (run.step * run.save_every) + 1e-9)) + 1
    eng = scenario.engine
    nch = 4 * (len(eng.stations) + len(run.probes)) + 8 * len(eng.stations)
    integ = scenario.simulation
    key = "simulation.duration" if integ is None or integ.duration is not None else None
    key = key or "simulation.revolutions"
    spacing = "simulation.save_every" if run.rtol is None else "simulation.output_dtau"
    try:
        check_size(n, nch, 0, stream)
    except InputError as exc:
        value = integ.duration if key.endswith("duration") else integ.revolutions
        why = exc.allowed.split(":")[0]
        raise ScenarioError(
            key, value, f"{why}: change {key} (shorter) or {spacing} (larger)"
        ) from None


def _attrs(scenario, res_stats: dict, run: Run, t0: float) -> dict:
    from rubrotor import __version__

    a = {
        "title": f"rubrotor simulation {scenario.name}".strip(),
        "scenario_name": scenario.name,
        "scenario": scenario.source,
        "speed_hz": run.speed / (2 * math.pi),
        "start_time_s": t0,
        "engine": "general",
        "rubrotor_version": __version__,
        "Conventions": "CF-1.8",
    }
    if run.speed_end is not None:
        a["speed_end_rad_s"] = run.speed_end
    if run.speed_table is not None:
        a["speed_table"] = json.dumps(run.speed_table)  # rows of time (s), speed (rad/s)
    st = scenario.engine.stations
    if st:
        a["contact_position_m"] = float(st[0].contact.position)
    a["contacts"] = json.dumps([
        {"position": s.contact.position, "clearance": s.contact.clearance,
         "radius": s.contact.radius, "offset_y": s.offset_y, "offset_z": s.offset_z,
         "flexible_stator": s.stator is not None} for s in st
    ])  # fmt: skip
    return a


def _dataset(res, scenario, run: Run, t0: float):
    """The results Dataset, built once from views of the run's arrays (see the module doc)."""
    import xarray as xr

    from rubrotor.engine.driver import result_dataset

    time = res.time + t0
    t = time - t0
    coords = {
        "time": xr.Variable("time", time, {"units": "s", "long_name": "time"}),
        "tau": xr.Variable("time", spin_angle(run, t) + run.speed * t0,
                           {"units": "rad", "long_name": "spin angle"}),
    }  # fmt: skip
    attrs = _attrs(scenario, res.stats, run, t0)
    attrs["end_time_s"] = t0 + float(res.time[-1]) if res.time.size else t0
    attrs["final_state"] = json.dumps(res.final_state.tolist())
    data = _accelerations(res, time)
    if res.restart is not None:
        data.update(_restart_vars(res.restart, t0))
    data["event_time"] = xr.Variable("event", res.events[:, 0] + t0, {"units": "s"})
    return result_dataset(res, coords=coords, data=data, attrs=attrs)


def _restart_vars(snap: dict, t0: float) -> dict:
    """``restart_time`` (s) and ``restart_vector`` of one checkpoint (a streamed file's layout,
    :mod:`rubrotor.engine.stream`)."""
    import xarray as xr

    from rubrotor.engine.restart import flatten, layout
    from rubrotor.engine.stream import restart_vector_attrs

    return {
        "restart_time": xr.Variable("checkpoint", [t0 + snap["time_s"]],
                                    {"units": "s", "long_name": "time of the restart state"}),
        "restart_vector": xr.Variable(("checkpoint", "restart_component"), flatten(snap)[None],
                                      restart_vector_attrs(layout(snap))),
    }  # fmt: skip


def _accelerations(res, t: np.ndarray) -> dict:
    """``v_ddot, w_ddot`` (m/s^2): central differences of the saved velocities (order 2; the
    formula of a streamed file, :func:`rubrotor.engine.stream.central_difference`)."""
    import xarray as xr

    from rubrotor.engine.stream import ACCEL_VARS, accel_attrs, central_difference

    S = len(res.stations)
    out = {}
    for k, (name, _, axis) in enumerate(ACCEL_VARS):
        vel = res.channels[2 + k : 4 * S : 4]  # the v_dot / w_dot rows of every station
        out[name] = xr.Variable(("station", "time"), central_difference(vel, t), accel_attrs(axis))
    return out


def simulate_engine(scenario, *, integrator=None, progress=None, stream=None):
    """Simulate a scenario with the general engine.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A scenario with ``engine`` set (general rotor or general-engine keys).
    integrator : rubrotor.engine.settings.Integrator, optional
        Overrides ``[simulation]``.
    progress : bool, optional
        Progress on stderr for long runs (default: when stderr is a terminal).
    stream : str or Path, optional
        Stream the samples chunk by chunk to this netCDF file (bounded memory) and return its
        path; the file then has no ``v_ddot``/``w_ddot`` (``rubrotor analyze`` derives them).

    Returns
    -------
    xarray.Dataset or Path
        The results (see the module docstring), or the streamed file's path.

    Raises
    ------
    ScenarioError
        Bad input, or a run too large for memory or disk (naming the keys to change), before
        it starts.
    """
    from rubrotor.engine.driver import simulate_general
    from rubrotor.engine.restart import fingerprint

    if scenario.engine.free_spin is not None:  # [speed] profile = "free": the spin is a state
        from rubrotor.engine.spin import simulate_free

        if stream is not None:
            raise ScenarioError("speed.profile", "free", "a run without streaming")
        return simulate_free(scenario, integrator=integrator)
    system, run, kwargs, t0, snap = _problem(scenario, integrator)
    src = scenario.engine.initial_path
    if stream is not None and src is not None and Path(src).resolve() == Path(stream).resolve():
        raise ScenarioError("initial.path", src, "a file other than the output, which the run "
                            "rewrites from its start (write the continuation to a new file)")  # fmt: skip
    _check_size(scenario, run, stream)
    fp = json.dumps(fingerprint(system, scenario.engine.stations, run.speed))
    attrs = {**_attrs(scenario, {}, run, t0), "model_fingerprint": fp}
    res = simulate_general(system, run, **kwargs, progress=progress, resume=snap, t0=t0,
                           stream=None if stream is None else str(stream), attrs=attrs)  # fmt: skip
    if stream is not None:
        return Path(stream)
    ds = _dataset(res, scenario, run, t0)
    ds.attrs["model_fingerprint"] = fp
    return ds
