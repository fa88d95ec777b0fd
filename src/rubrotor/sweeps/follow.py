"""State-carrying ("follow") sweeps: up and down sweeps that expose hysteresis and jumps.

A brute-force :func:`rubrotor.sweeps.sweep.sweep` starts every point from rest, so it sees only the
attractor reached from rest. :func:`follow_sweep` runs the values of one scenario key in order
and starts every point from the final state of the previous one, as a slow run-up (``"up"``,
increasing values) or coast-down (``"down"``, decreasing values) would: a motion stays on its
branch until that branch ends (a fold) or loses stability, then jumps. Up and down sweeps of the
same range differ where two attractors coexist (hysteresis).

Rules:

* The first point of a chain starts from rest. Every other point starts from the previous
  point's final state, carried as the physical state ``(q, q')`` (:class:`RotorState`), so a
  change of speed, clearance, unbalance, ... between points changes the eigen-basis and the
  particular solution of the new run but not the motion (see
  :func:`rubrotor.engine.simulate.simulate_system`). Runs last a whole number of revolutions, so the
  unbalance angle at the hand-over is 0 (to rounding) and a constant load is allowed.
* A point whose run does not complete (diverged) is ``"not classified"`` and the next point
  starts from rest again; ``started_from`` records which (1 = previous point, 0 = rest).
* Each point is reduced exactly as in :func:`rubrotor.sweeps.sweep.sweep` (same transient, window,
  metrics and regime labels).
* A chain is sequential; with ``direction="both"`` the up and down chains run in two worker
  processes (``workers >= 2``), or one after the other in this process (``workers=1``).

Store layout (zarr, written chunk by chunk and resumable like :func:`rubrotor.sweeps.sweep.sweep`): the
Dataset of a sweep over the one key with a leading dimension ``direction`` (``"up"``,
``"down"`` or both, in that order); along the key both directions hold the key's values in
increasing order. Extra variables: ``started_from`` and the final state of each point,
``final_state`` (dimension ``state_component``: ``Re q, Im q, Re q', Im q'``, SI units) and
``final_phase`` (rad). A resumed chain continues from the stored state of its last finished
point.
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Iterator, Sequence

import numpy as np

from rubrotor.errors import InputError
from rubrotor.modelling import model_of
from rubrotor.scenario.load import as_scenario
from rubrotor.sweeps.pool import LostTasks, local_pool

__all__ = ["DIRECTIONS", "follow_general", "follow_sweep", "run_follow_chunk"]

DIRECTIONS = {"up": ("up",), "down": ("down",), "both": ("up", "down")}
"""Accepted ``direction`` values and the chains each runs."""


def _n_coordinates(scenario) -> int:
    from rubrotor.engine.simulate import assemble

    return int(assemble(scenario.shaft, scenario.speed, scenario.damping).q_index.size)


def _state_vector(state, n: int) -> tuple[np.ndarray, float]:
    if state is None:
        return np.full(4 * n, np.nan), np.nan
    q, qd = np.asarray(state.q), np.asarray(state.qd)
    return np.concatenate([q.real, q.imag, qd.real, qd.imag]), float(state.phase)


def _state_from(vector: np.ndarray, phase: float):
    """The :class:`RotorState` stored as ``vector`` (None when it is not finite)."""
    from rubrotor.engine.simulate import RotorState

    if not (np.all(np.isfinite(vector)) and math.isfinite(phase)):
        return None
    q_re, q_im, qd_re, qd_im = np.split(np.asarray(vector, float), 4)
    return RotorState(q=q_re + 1j * q_im, qd=qd_re + 1j * qd_im, phase=float(phase))


def run_follow_chunk(task: dict) -> dict:
    """Compute one chunk of a chain in order, each point from the previous point's final state.

    Parameters
    ----------
    task : dict
        ``{"scenario": dict form, "key": str, "values": [...] (chain order), "start":
        RotorState or None, "transient": T, "revolutions": R, "samples": N, "n": coordinates,
        "lyapunov": bool, "chunk": i}``.

    Returns
    -------
    dict
        ``{"chunk": i, "metrics": [dict per point, chain order], "state": final RotorState or
        None}``.
    """
    from rubrotor.errors import RubrotorError
    from rubrotor.orbits.points import PointScenarios
    from rubrotor.scenario.load import scenario_from_dict
    from rubrotor.sweeps.metrics import _empty_metrics
    from rubrotor.sweeps.sweep import simulate_point

    base = scenario_from_dict(task["scenario"])
    point_scenario = PointScenarios(base, [task["key"]])
    if model_of(base).maps == "general":
        return _general_chunk(task, point_scenario)
    state = task["start"]
    metrics = []
    for value in task["values"]:
        started = 0 if state is None else 1
        try:
            sc = point_scenario([value])
            m, state = simulate_point(
                sc,
                task["transient"],
                task["revolutions"],
                task["samples"],
                start=state,
                lyapunov=task["lyapunov"],
            )
        except RubrotorError:  # e.g. a speed exactly at an undamped critical: not classified
            m, state = _empty_metrics(task["revolutions"] - task["transient"]), None
        m["started_from"] = started
        m["final_state"], m["final_phase"] = _state_vector(state, task["n"])
        metrics.append(m)
    return {"chunk": task["chunk"], "metrics": metrics, "state": state}


def _general_chunk(task: dict, point_scenario) -> dict:
    """:func:`run_follow_chunk` for a finite-element rotor: each point runs the general engine's
    fixed-step map from the previous point's end vector (modal coordinates aligned with the map
    at the lowest key value, and contact forces), the first from the steady no-contact response."""
    from rubrotor.orbits.general_map import GeneralMap
    from rubrotor.sweeps.general_point import window
    from rubrotor.sweeps.metrics import _empty_metrics

    steps = task["steps"]
    reference = GeneralMap(point_scenario([task["reference"]]), 1, steps)
    x, metrics = task["start"], []
    kept = task["revolutions"] - task["transient"]
    for value in task["values"]:
        started = 0 if x is None else 1
        one = GeneralMap(point_scenario([value]), 1, steps, reference=reference)
        x = one.start() if x is None else x
        try:
            if task["transient"]:
                x = one.repeat(task["transient"]).run(x)[0]
            x, m = window(one.repeat(kept), x, task["samples"], task["lyapunov"])
        except InputError:  # diverged: not classified, the next point starts afresh
            x, m = None, _empty_metrics(kept)
        m["started_from"] = started
        m["final_state"] = np.full(task["n"], np.nan) if x is None else np.asarray(x, float)
        m["final_phase"] = 0.0 if x is not None else np.nan  # whole revolutions
        metrics.append(m)
    return {"chunk": task["chunk"], "metrics": metrics, "state": x}


def _follow_template(key, values, directions, kept, size, attrs):
    import xarray as xr

    from rubrotor.sweeps.sweep import _template

    base = _template([key], [values], kept, attrs)
    data = {}
    for name, var in base.data_vars.items():
        arr = np.repeat(var.values[None], len(directions), axis=0)
        data[name] = (("direction", *var.dims), arr, dict(var.attrs))
    data["started_from"] = (
        ("direction", key),
        np.zeros((len(directions), len(values)), np.int8),
        {"units": "1", "long_name": "1: started from the previous point's state, 0: from rest"},
    )
    data["final_state"] = (
        ("direction", key, "state_component"),
        np.full((len(directions), len(values), size), np.nan),
        {
            "units": "SI (m, rad, m/s, rad/s; N)",
            "long_name": "final state: Re q, Im q, Re q', Im q' (shaft); the map's vector (FE rotor)",
        },
    )
    data["final_phase"] = (
        ("direction", key),
        np.full((len(directions), len(values)), np.nan),
        {"units": "rad", "long_name": "unbalance angle at the final state"},
    )
    coords = {name: base.coords[name] for name in base.coords}
    coords["direction"] = (
        "direction",
        np.array(directions, dtype=object),  # variable-length strings (zarr v3 specified)
        {"long_name": "sweep direction: up = increasing values, down = decreasing"},
    )
    return xr.Dataset(data, coords=coords, attrs=base.attrs)


def _chains(ds, key, directions, chunk_size, definition, n) -> list[list[dict]]:
    """Per direction, the tasks of its not-finished chunks in chain order (first has a start)."""
    from rubrotor.sweeps.sweep import _chunks

    values = ds[key].values
    chunks = _chunks((len(directions), values.size), chunk_size)
    done = ds["done"].values.astype(bool)
    chains = []
    for d, name in enumerate(directions):
        mine = [(i, sl) for i, (lead, sl) in enumerate(chunks) if lead[0] == d]
        if name == "down":
            mine = mine[::-1]
        tasks, prev = [], None
        for i, sl in mine:
            idx = list(range(sl.start, sl.stop))
            if name == "down":
                idx = idx[::-1]
            if done[d, sl].all():
                prev = idx[-1]
                continue
            start = None
            if prev is not None and ds["status"].values[d, prev] == 1:
                vector = ds["final_state"].values[d, prev]
                start = (
                    np.array(vector, float)
                    if definition.get("steps_per_revolution")
                    else _state_from(vector, ds["final_phase"].values[d, prev])
                )
            tasks.append(
                {
                    "chunk": i,
                    "scenario": definition["scenario"],
                    "key": key,
                    "values": [float(values[j]) for j in idx],
                    "start": start,
                    "transient": definition["transient_revolutions"],
                    "revolutions": definition["revolutions"],
                    "samples": definition["samples_per_revolution"],
                    "n": n,
                    "lyapunov": bool(definition.get("lyapunov", False)),
                    "steps": definition.get("steps_per_revolution"),
                    "reference": float(values[0]),
                }
            )
            prev = None  # later tasks get their start from the task before them
        chains.append(tasks)
    return chains


def _execute_chains(chains: list[list[dict]], pool) -> Iterator[dict]:
    """Run each chain's tasks in order (the chains side by side in ``pool`` when given)."""
    if pool is None:
        for tasks in chains:
            state = tasks[0]["start"] if tasks else None
            for task in tasks:
                result = run_follow_chunk(task | {"start": state})
                state = result["state"]
                yield result
        return
    from concurrent.futures import FIRST_COMPLETED, wait

    pos = [0] * len(chains)
    running = {
        pool.submit(run_follow_chunk, tasks[0]): c for c, tasks in enumerate(chains) if tasks
    }
    from concurrent.futures.process import BrokenProcessPool

    try:
        while running:
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for fut in finished:
                c = running.pop(fut)
                try:
                    result = fut.result()
                except BrokenProcessPool:
                    raise LostTasks([chains[c][pos[c]]]) from None
                pos[c] += 1
                if pos[c] < len(chains[c]):
                    nxt = chains[c][pos[c]] | {"start": result["state"]}
                    running[pool.submit(run_follow_chunk, nxt)] = c
                yield result
    finally:
        for fut in running:
            fut.cancel()


def follow_sweep(
    scenario,
    key: str,
    values: Sequence[float],
    *,
    direction: str = "both",
    transient_revolutions: int = 100,
    revolutions: int | None = None,
    samples_per_revolution: int = 128,
    workers: int | None = None,
    store: str | os.PathLike | None = None,
    chunk_size: int | None = None,
    progress: bool = False,
    lyapunov: bool = False,
    steps_per_revolution: int | None = None,
):
    """State-carrying sweep of one scenario key, up, down or both (see the module docstring).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The base scenario; its ``[simulation]`` tolerances are used (adaptive integrator).
    key : str
        The swept numeric scenario key (``"section.key"``, e.g. ``"speed.critical_multiple"``);
        not one that changes the number of modal coordinates (``shaft.modes``).
    values : array_like
        Its distinct values (any order; they are run in increasing order up, decreasing down).
    direction : {"up", "down", "both"}
        Which chains to run.
    transient_revolutions, revolutions, samples_per_revolution
        As in :func:`rubrotor.sweeps.sweep.sweep` (per point; revolutions of spin).
    workers : int, optional
        Local worker processes; 2 or more run the up and down chains side by side; default all
        cores.
    store : path-like, optional
        A zarr store written chunk by chunk; an existing store of the same sweep is resumed.
    chunk_size : int, optional
        Points per written chunk (default about 1/8 of the values, 1 to 16).
    progress : bool
        Print a progress line to stderr after every chunk.
    lyapunov : bool
        Estimate every point's largest Lyapunov exponent (as :func:`rubrotor.sweeps.sweep.sweep`).
    steps_per_revolution : int, optional
        A finite-element rotor's fixed steps per revolution (default 256; a multiple of
        ``samples_per_revolution``). Its points run the general engine's map, the state carried
        as the map's vector (modal coordinates aligned with the map at the lowest value, and the
        contact forces), the first point of a chain from the steady no-contact response.

    Returns
    -------
    xarray.Dataset
        Dimensions ``direction``, the key, ``revolution``, ``peak`` and ``state_component``;
        the variables of :func:`rubrotor.sweeps.sweep.sweep` plus ``started_from``, ``final_state``,
        ``final_phase``; attribute ``follow`` (the direction). A general rotor's
        ``final_state`` holds its map's vectors.
    """
    from rubrotor.sweeps.sweep import (
        _check_keys,
        _definition,
        _int_arg,
        _open_or_create,
        run_lengths,
    )

    scenario = as_scenario(scenario)
    model_of(scenario).require_maps("a state-carrying sweep")
    if direction not in DIRECTIONS:
        raise InputError("follow", direction, " | ".join(DIRECTIONS))
    directions = DIRECTIONS[direction]
    (key,), (arr,) = _check_keys(scenario, {key: values})
    arr = np.sort(arr)
    t_rev, revs = run_lengths(scenario, transient_revolutions, revolutions)
    n_rev = _int_arg("samples_per_revolution", samples_per_revolution, 8)
    if workers is None:
        workers = os.cpu_count() or 1
    workers = _int_arg("workers", workers, 1)
    if chunk_size is None:
        chunk_size = max(1, min(16, math.ceil(arr.size / 8)))
    chunk_size = min(_int_arg("chunk_size", chunk_size, 1), arr.size)
    steps = _general_steps(scenario, steps_per_revolution, n_rev)
    n = _follow_dimension(scenario, key, arr, steps)
    definition = _definition(scenario, [key], [arr], t_rev, revs, n_rev) | {"follow": direction}
    if steps is not None:
        definition["steps_per_revolution"] = steps
    if lyapunov:
        definition["lyapunov"] = True
    attrs = _follow_attrs(scenario, key, direction, t_rev, revs, n_rev)
    size = n if steps is not None else 4 * n
    ds = _follow_template(key, arr, directions, revs - t_rev, size, attrs)
    ds.attrs["sweep_definition"] = json.dumps(definition, sort_keys=True)
    if store is not None:
        for name in list(ds.data_vars):
            ds[name].encoding["chunks"] = (1, chunk_size) + ds[name].shape[2:]
        done = _open_or_create(store, ds.copy(), definition)
        if done.any():
            import xarray as xr

            with xr.open_zarr(store, consolidated=False) as old:
                ds = old.load()
    chains = _chains(ds, key, directions, chunk_size, definition, n)
    pool = local_pool(workers, sum(1 for c in chains if c))
    try:
        _run_chains(ds, store, chains, chunk_size, pool, progress)
    finally:
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)
    return ds


def _follow_attrs(scenario, key, direction, t_rev, revs, n_rev) -> dict:
    """The attributes of a follow sweep's Dataset (rules, lengths, the scenario text)."""
    attrs = {
        "title": f"rubrotor follow sweep {scenario.name}".strip(),
        "scenario_name": scenario.name,
        "rotor": model_of(scenario).rotor,
        "swept_keys": key,
        "follow": direction,
        "transient_revolutions": t_rev,
        "revolutions": revs,
        "samples_per_revolution": n_rev,
        "regime_rules": "see rubrotor.sweeps.sweep and rubrotor.sweeps.regimes module docstrings",
        "follow_rules": "see rubrotor.sweeps.follow module docstring",
        "scenario": getattr(scenario, "source", ""),
        "Conventions": "CF-1.8",
    }
    if scenario.contact is not None:
        attrs["clearance_m"] = float(scenario.contact.clearance)
    return attrs


def _general_steps(scenario, steps_per_revolution, samples_per_revolution) -> int | None:
    """A finite-element rotor's steps per revolution, checked (None for the shaft's engine)."""
    from rubrotor.sweeps.general_point import GENERAL_STEPS

    if model_of(scenario).maps == "shaft":
        if steps_per_revolution is not None:
            raise InputError("steps_per_revolution", steps_per_revolution,
                             "None for a [shaft] scenario (its engine is adaptive)")  # fmt: skip
        return None
    steps = GENERAL_STEPS if steps_per_revolution is None else steps_per_revolution
    if not isinstance(steps, int | np.integer) or steps < 1 or steps % samples_per_revolution:
        raise InputError("samples_per_revolution", samples_per_revolution,
                         f"a divisor of the {steps} fixed steps per revolution")  # fmt: skip
    return int(steps)


def _follow_dimension(scenario, key, values, steps=None) -> int:
    """Size of the carried state, the same at both ends of the range (else an InputError)."""
    from rubrotor.sweeps.sweep import _point_scenario

    if steps is not None:
        from rubrotor.orbits.general_map import GeneralMap

        def size(sc):
            return GeneralMap(sc, 1, steps).dim
    else:
        size = _n_coordinates
    ends = [size(_point_scenario(scenario, [key], [v])) for v in (values[0], values[-1])]
    if ends[0] != ends[1]:
        raise InputError(key, values.tolist(), "a key that keeps the modal coordinates (follow)")
    return ends[0]


def _run_chains(ds, store, chains, chunk_size, pool, progress) -> None:
    from rubrotor.sweeps.sweep import _chunks, write_chunk

    shape = ds["done"].shape
    chunks = _chunks(shape, chunk_size)
    total = sum(len(c) for c in chains)
    t0 = time.perf_counter()
    for n_done, result in enumerate(_execute_chains(chains, pool), 1):
        lead, sl = chunks[result["chunk"]]
        metrics = result["metrics"]
        if ds["direction"].values[lead[0]] == "down":
            metrics = metrics[::-1]
        write_chunk(ds, store, lead, sl, metrics)
        if progress:
            import sys

            el = time.perf_counter() - t0
            print(
                f"\rrubrotor follow: {n_done}/{total} chunks, {el:.0f} s", end="", file=sys.stderr
            )
    if progress:
        import sys

        print(file=sys.stderr)


def follow_general(scenario, key: str, values, direction: str = "both",
                   transient_revolutions: int = 100, revolutions: int = 50,
                   samples_per_revolution: int = 32, steps: int = 256,
                   lyapunov: bool = False):  # fmt: skip
    """State-carrying sweep of a general rotor in one key, in memory (:func:`follow_sweep`).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A general rotor with at least one contact, at constant speed.
    key : str
        The swept key (``"section.key"``, its units).
    values : sequence of float
        Key values (any order; run ascending up, descending down).
    direction : {"up", "down", "both"}
        Which chains.
    transient_revolutions, revolutions : int
        Revolutions discarded and kept per value.
    samples_per_revolution : int
        Kept samples per revolution (a divisor of ``steps``).
    steps : int
        Fixed steps per revolution.
    lyapunov : bool
        Also the largest Lyapunov exponent of every value's kept revolutions.

    Returns
    -------
    xarray.Dataset
        As :func:`follow_sweep`.
    """
    return follow_sweep(scenario, key, values, direction=direction,
                        transient_revolutions=transient_revolutions,
                        revolutions=transient_revolutions + revolutions,
                        samples_per_revolution=samples_per_revolution, workers=1,
                        lyapunov=lyapunov, steps_per_revolution=steps)  # fmt: skip
