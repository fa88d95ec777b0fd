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
from rubrotor.forces.contact import law_of

__all__ = ["engine_problem", "engine_run", "simulate_engine", "given_state", "default_step", "STREAM_SAMPLES"]

STREAM_SAMPLES = 1 << 21
"""``rubrotor simulate`` streams runs with more saved samples than this to the results file."""


def _system(scenario, probes):
    """The rotor the Model builds, meshed at the engine's stations and the probes."""
    from rubrotor.modelling import model_of

    stations = tuple(sorted(set(scenario.engine.positions + tuple(probes))))
    return model_of(scenario).linear_system(stations, only=True)


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
    except ScenarioError:  # a refusal of the file's content: not nested in this one
        raise
    except (OSError, ValueError) as exc:
        raise ScenarioError("initial.path", path, f"a readable results file ({exc})") from None


def _restart_from(ds, path: str, scenario, system, speed: float):
    """:func:`_restart` on the opened file (:func:`rubrotor.engine.restart.read_restart`)."""
    from rubrotor.engine.restart import read_restart

    return read_restart(ds, path, scenario, system, speed)


POINTS_PER_PERIOD = 20
"""Steps per period of the fastest motion the default step resolves (:func:`default_step`)."""

RESOLVED_BAND = 10.0
"""With every mode kept, the default step resolves the modes up to this multiple of the
fastest contact, stator or spin frequency (higher ones are propagated exactly by the
exponential integrator, but their response to the contact force is not resolved)."""


def default_step(system, eng, top_speed: float) -> float:
    """Fixed step (s) of a run-up whose ``[simulation]`` gives neither ``dt`` nor ``dtau``.

    ``dt = 2 pi / (POINTS_PER_PERIOD omega_ref)``, ``omega_ref`` (rad/s) the largest of: the
    highest retained mode (``simulation.modes`` or ``cutoff``; with every mode kept, the
    highest below ``RESOLVED_BAND`` times the next three), each contact's frequency
    ``sqrt(k / m)`` (``k`` the linear stiffness, or the Hertz law's ``1.5 k_h sqrt(g)`` at an
    indentation of one clearance ``g``; ``m`` the smallest modal mass at the contact,
    :func:`rubrotor.linear.modal_mass.modal_masses`), each flexible stator's
    ``sqrt((k_s + k) / m_s)`` and the top spin speed. Modes are the undamped ones at rest
    (bearings at ``top_speed``). On ``seal_rub.toml`` (16 modes) this gives 2.1e-5 s, the
    step the file sets by hand (2e-5 s).

    Parameters
    ----------
    system : rubrotor.rotors.linear.LinearSystem
        The rotor.
    eng : rubrotor.scenario.dynamics.EngineSpec
        Contacts, stators and the retained modes.
    top_speed : float
        Largest spin speed of the profile (rad/s).

    Returns
    -------
    float
        The step (s).
    """
    import scipy.linalg

    from rubrotor.linear.modal_mass import modal_masses

    mats = system.matrices(top_speed)
    w2 = scipy.linalg.eigh(0.5 * (mats.K + mats.K.T), mats.M, eigvals_only=True)
    omega = np.sqrt(w2[w2 > 1e-9 * w2.max()])
    kept = omega.size if eng.modes is None else min(eng.modes, omega.size)
    fast = [top_speed]
    for st in eng.stations:
        c = st.contact
        k = law_of(c).tangent_stiffness(c.stiffness, c.clearance)
        mm = modal_masses(system, top_speed, c.position, n=kept)
        fast.append(math.sqrt(k / min(m.modal_mass for m in mm)))
        if st.stator is not None:
            s = st.stator
            fast += [math.sqrt((s.stiffness_y + k) / s.mass_y),
                     math.sqrt((s.stiffness_z + k) / s.mass_z)]  # fmt: skip
    if eng.cutoff is not None:
        modes = omega[omega <= eng.cutoff]
    elif eng.modes is not None:
        modes = omega[:kept]
    else:
        modes = omega[omega <= RESOLVED_BAND * max(fast)]
    ref = max(fast + [float(modes[-1]) if modes.size else 0.0])
    return 2 * math.pi / (POINTS_PER_PERIOD * ref)


def given_state(system, speed: float, given: tuple) -> np.ndarray:
    """The state ``[q, q']`` (SI, free DOFs) through given deflections and velocities.

    Of all shapes with the deflections ``d`` at the stations, the one of least strain energy:
    the static shape under point forces at those stations alone, ``q = F (B F)^-1 d`` with
    ``F = K^-1 B^T`` (``B`` the rows giving ``v, w`` at the stations, ``K`` with the bearings
    at ``speed``); the velocities take the same form. So ``B q = d`` and ``B q' = d'``
    exactly, and a single station's deflection gives the static deflection line of a point
    load there.

    Parameters
    ----------
    system : rubrotor.rotors.linear.LinearSystem
        The rotor (a node at each station).
    speed : float
        Spin speed (rad/s) for the bearings' coefficients.
    given : tuple
        ``(positions, v, w, v_dot, w_dot)`` of :class:`rubrotor.scenario.dynamics.EngineSpec`
        (m, m, m, m/s, m/s).

    Returns
    -------
    ndarray, shape (2 n,)
    """
    positions, v, w, vd, wd = (np.asarray(g, float) for g in given)
    b = np.vstack([system.basis.rows(float(x))[:, system.free] for x in positions])  # (2P, n)
    f = np.linalg.solve(system.matrices(speed).K, b.T)
    bf = b @ f
    if np.linalg.cond(bf) > 1e12:
        raise ScenarioError("initial.positions", tuple(positions),
                            "stations far enough apart to be deflected independently")  # fmt: skip
    shape = f @ np.linalg.inv(bf)
    d = np.column_stack([v, w]).ravel()
    dd = np.column_stack([vd, wd]).ravel()
    return np.concatenate([shape @ d, shape @ dd])


def modal_state(system, speed: float, modal: tuple) -> np.ndarray:
    """The state ``[q, q']`` (SI, free DOFs) made of undamped modes.

    Mode ``j`` (1-based, by frequency) of ``K_s phi = omega^2 M phi`` (``K_s`` the symmetric
    part of the stiffness with the bearings at ``speed``, as
    :func:`rubrotor.linear.modal_mass.modal_masses`) scaled so that its largest deflection
    ``max |(v, w)|`` over the nodes is 1 m: ``q = sum a_j phi_j``, ``q' = sum a'_j phi_j``.

    Parameters
    ----------
    system : rubrotor.rotors.linear.LinearSystem
        The rotor.
    speed : float
        Spin speed (rad/s) for the bearings' coefficients.
    modal : tuple
        ``(modes, amplitudes, modal_velocities)`` (1-based; m; m/s).

    Returns
    -------
    ndarray, shape (2 n,)
    """
    import scipy.linalg

    from rubrotor.linear.modal_mass import _grid

    modes, amps, vels = modal
    mats = system.matrices(speed)
    w2, phi = scipy.linalg.eigh(0.5 * (mats.K + mats.K.T), mats.M)
    if max(modes) > phi.shape[1]:
        raise ScenarioError("initial.modes", modes, f"mode numbers 1 .. {phi.shape[1]}")
    rows = np.stack([system.basis.rows(x)[:, system.free] for x in _grid(system)])
    q, qd = np.zeros(phi.shape[0]), np.zeros(phi.shape[0])
    for m, a, ad in zip(modes, amps, vels, strict=True):
        shape = phi[:, m - 1] / np.max(np.hypot(*np.moveaxis(rows @ phi[:, m - 1], -1, 0)))
        q += a * shape
        qd += ad * shape
    return np.concatenate([q, qd])


def engine_problem(scenario, integrator=None):
    """The engine's inputs for a scenario (see :func:`_problem`; without the restart state).

    A free spin speed (``[speed] profile = "free"``) is refused naming the key: the maps,
    orbits and sweeps built on these inputs hold the speed imposed.
    """
    from rubrotor.modelling import model_of

    if model_of(scenario).runner == "free-spin":
        raise ScenarioError("speed.profile", "free", 'a "constant", "linear" or "table" speed '
                            "here (a free spin speed runs in rubrotor simulate)")  # fmt: skip
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
    from rubrotor.modelling import model_of

    model = model_of(scenario)  # it builds the rotor, the force terms and the speed law
    law = model.speed_law()
    speed, end, table = law.speed, law.speed_end, law.table
    if speed <= 0:
        raise ScenarioError("speed", speed, "a spin speed > 0 (rad/s) for a time simulation")
    system = _system(scenario, integ.probes)
    forces = model.forces(speed, system)
    step = integ.step_seconds(speed)
    if step is None and (end is not None or table):  # a profile needs a fixed step
        top = max([speed, end or 0.0, *(w for _, w in table or ())])
        step = default_step(system, eng, top)
    adaptive = step is None
    if table and integ.duration is None:
        raise ScenarioError("simulation.revolutions", integ.revolutions,
                            'simulation.duration (s) instead, with speed.profile = "table"')  # fmt: skip
    unb, t0, initial, snap = forces.unbalances, 0.0, eng.initial, None
    if initial == "file":
        initial, t0, snap = _restart(eng.initial_path, scenario, system, speed)
        # constant speed: continuing at t0 equals starting at 0 with phases advanced by Omega t0
        unb = tuple(dataclasses.replace(u, phase=u.phase + speed * t0) for u in unb)
    elif initial == "given" and eng.initial_modes is not None:
        initial = modal_state(system, speed, eng.initial_modes)
    elif initial == "given":
        initial = given_state(system, speed, eng.initial_given)
    run = Run(
        speed=speed, duration=_duration(integ, speed, end),
        step=integ.output_spacing(speed) if adaptive else step,
        save_every=1 if adaptive else integ.save_every, modes=eng.modes, cutoff=eng.cutoff,
        residual=eng.residual, initial=initial, probes=integ.probes,
        max_displacement=integ.max_displacement, speed_end=end, speed_step=law.step,
        speed_table=table,
        rtol=integ.rtol if adaptive else None, atol=integ.atol,
    )  # fmt: skip
    _check_one_sample(integ, run)
    kwargs = dict(stations=forces.stations, unbalances=unb, loads=forces.loads,
                  gravity=forces.gravity, supports=forces.supports)  # fmt: skip
    return system, run, kwargs, t0, snap


def _check_one_sample(integ, run: Run) -> None:
    """Refuse a run shorter than one saved sample, naming the keys the file sets."""
    sample = run.step * run.save_every
    if run.duration >= sample * (1 - 1e-9):
        return
    given = [(k, getattr(integ, k)) for k in ("dt", "dtau", "output_dtau", "sample_rate")]
    key, value = next(((f"simulation.{k}", v) for k, v in given if v is not None),
                      ("simulation.output_dtau", None))  # fmt: skip
    if run.step <= run.duration:  # the step fits: the saved spacing does not
        key, value = "simulation.save_every", run.save_every
    length = ("simulation.duration", integ.duration) if integ.duration is not None else (
        "simulation.revolutions", integ.revolutions)  # fmt: skip
    raise ScenarioError(
        key, value, f"a sample spacing ({sample:.3g} s) no longer than the run "
        f"({length[0]} = {length[1]!r} lasts {run.duration:.3g} s)"
    )  # fmt: skip


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


def engine_run(scenario, *, integrator=None, progress=None, stream=None):
    """Run a scenario on the general engine: the run and what its Dataset needs.

    Parameters
    ----------
    scenario, integrator, progress, stream
        As in :func:`simulate_engine` (imposed speed only).

    Returns
    -------
    res : rubrotor.engine.result.TimeRun
        The run (empty samples when streamed).
    run : rubrotor.engine.parts.Run
        Its settings.
    t0 : float
        Start time (s) (a restart's).
    fingerprint : str
        The model fingerprint (JSON) a restart checks.
    """
    from rubrotor.engine.driver import simulate_general
    from rubrotor.engine.restart import fingerprint

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
    return res, run, t0, fp


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
    from rubrotor.modelling import model_of

    if model_of(scenario).runner == "free-spin":  # [speed] profile = "free": the spin is a state
        from rubrotor.engine.spin import simulate_free

        if stream is not None:
            raise ScenarioError("speed.profile", "free", "a run without streaming")
        return simulate_free(scenario, integrator=integrator, progress=progress)
    res, run, t0, fp = engine_run(scenario, integrator=integrator, progress=progress,
                                  stream=stream)  # fmt: skip
    if stream is not None:
        return Path(stream)
    ds = _dataset(res, scenario, run, t0)
    ds.attrs["model_fingerprint"] = fp
    return ds
