"""Parameter sweeps: many simulations on a grid of scenario keys, reduced to rub metrics.

:func:`sweep` runs the scenario at every point of a grid of scenario keys (any numeric key that
:meth:`rubrotor.scenario.Scenario.with_changes` accepts, e.g. ``"speed.critical_multiple"`` or
``"unbalance.magnitude"``), discards a transient and reduces each run to a few numbers and a
regime label. A [shaft] scenario's points run the shaft's adaptive engine; a finite-element
rotor's points run the general engine's fixed-step map from the steady no-contact response
(:mod:`rubrotor.sweeps.general_point`, 256 steps per revolution). Points run in parallel in local worker processes, or on a Dask distributed cluster
(``scheduler="tcp://host:port"``). With a zarr ``store`` every finished chunk of points is
written as soon as it arrives and marked in a ``done`` mask, so an interrupted sweep (Ctrl-C, a
crash) leaves a valid store, and running the same sweep again computes only what is missing.

Per point, over the kept window ``t in [T, R) * 2 pi / Omega`` (``T`` transient revolutions,
``R`` total revolutions, ``K = R - T`` kept revolutions, ``N`` samples per revolution, the
integrator's output spacing being ``2 pi / (N Omega)`` so that every ``N``-th sample falls
exactly on ``t = k 2 pi / Omega``), with ``P = v + i w`` (m) the contact-station deflection:

* ``poincare_v``, ``poincare_w`` (m): ``P(k 2 pi / Omega)`` for ``k = T .. R - 1``;
* ``peak_normal_force``, ``rms_normal_force`` (N) (the RMS counts the time out of contact);
* ``contact_fraction``: fraction of the kept samples with normal force > 0
  (:func:`rubrotor.sweeps.regimes.contact_fraction`);
* ``impacts_per_revolution``: contact onsets in the kept window per revolution
  (:func:`rubrotor.sweeps.regimes.impacts_per_revolution`, exact event times);
* ``frequency`` (multiples of spin, signed: negative = backward whirl) and
  ``frequency_amplitude`` (m) of the 3 largest spectral peaks of ``P - mean(P)`` (periodic Hann
  window, the DC bin excluded, peak positions refined by a parabola through the log-magnitudes
  of the peak bin and its neighbours);
* ``forward_share``: power at positive frequencies over the power at all non-zero frequencies
  (``backward share = 1 - forward_share``);
* ``line_fraction``: share of that power within +-2 bins of the 10 largest spectral peaks (1 for
  a sum of a few tones, small for a broadband spectrum);
* ``poincare_dimension``: correlation-dimension estimate of the Poincare points,
  ``log(C(8 d) / C(2 d)) / log 4`` with ``C(r)`` the number of pairs closer than ``r`` and ``d``
  the median nearest-neighbour distance: about 1 for points on a closed curve, about 2 for
  points filling an area (NaN with fewer than 64 points);
* ``amplitude_ripple``: ``(max |P| - min |P|) / max |P|`` over the kept window;
* ``lyapunov_exponent`` (1/s): the largest Lyapunov exponent when the sweep is run with
  ``lyapunov=True`` (:func:`rubrotor.orbits.lyapunov.lyapunov_exponents` over ``K`` revolutions of
  512 fixed exponential steps each, started from the point's final state: the attractor the
  kept window shows), else NaN;
* ``regime`` (code) and ``period``: :func:`rubrotor.sweeps.regimes.classify` (the one definition of
  the regime labels, impacts per revolution and contact fraction, see
  :mod:`rubrotor.sweeps.regimes`); with an exponent, "chaotic" means ``lambda_1 2 pi / Omega > 0.05``;
  ``status`` 1 when the run completed.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import signal
import threading
import time
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path

import numpy as np

from rubrotor.errors import InputError
from rubrotor.forces.contact import law_of
from rubrotor.modelling import model_of
from rubrotor.orbits.points import PointScenarios, _point_scenario
from rubrotor.scenario.load import as_scenario, key_unit
from rubrotor.sweeps.metrics import (
    _SCALARS,
    N_PEAKS,
    _empty_metrics,
    point_metrics,
    window_metrics,
)
from rubrotor.sweeps.pool import local_pool as _local_pool
from rubrotor.sweeps.pool import run_pool as _run_pool
from rubrotor.sweeps.regimes import (
    APERIODIC,
    CHAOTIC,
    DEEP,
    FULL,
    NO_CONTACT,
    PARTIAL,
    QUASI,
    REGIMES,
    UNCLASSIFIED,
    classify,
    find_period,
    poincare_dimension,
    regime_label,
    regime_labels,
)

__all__ = [
    "REGIMES",
    "sweep",
    "parse_vary",
    "log_spaced",
    "classify",
    "find_period",
    "poincare_dimension",
    "regime_label",
    "APERIODIC",
    "CHAOTIC",
    "DEEP",
    "FULL",
    "NO_CONTACT",
    "PARTIAL",
    "QUASI",
    "UNCLASSIFIED",
    "point_metrics",
    "regime_labels",
    "open_sweep",
]

STORE_VERSION = 1


# ---- grids -------------------------------------------------------------------------------------
def log_spaced(start: float, stop: float, count: int) -> np.ndarray:
    """``count`` values from ``start`` to ``stop`` (both > 0), evenly spaced in logarithm.

    Examples
    --------
    >>> log_spaced(1e-4, 1e-2, 3)
    array([0.0001, 0.001 , 0.01  ])
    """
    if not (start > 0 and stop > 0):
        raise InputError("log range", (start, stop), "START and STOP > 0 for log spacing")
    return np.geomspace(start, stop, int(count))


def parse_vary(text: str, log: bool = False) -> tuple[str, np.ndarray]:
    """Parse ``"KEY=START:STOP:COUNT"`` into the key and its values.

    Parameters
    ----------
    text : str
        E.g. ``"speed.critical_multiple=0.5:3:400"``; ``START != STOP`` finite, integer
        ``COUNT >= 1`` (``COUNT = 1`` gives ``START``). A single value ``"KEY=VALUE"`` is also
        accepted.
    log : bool
        Space the values evenly in logarithm (``START``, ``STOP`` > 0).

    Returns
    -------
    key : str
    values : ndarray, shape (COUNT,)

    Examples
    --------
    >>> parse_vary("unbalance.magnitude=1e-3:3e-3:3")
    ('unbalance.magnitude', array([0.001, 0.002, 0.003]))
    """
    key, sep, rng = text.partition("=")
    key = key.strip()
    if not sep or not key:
        raise InputError(
            "--vary", text, "KEY=START:STOP:COUNT, e.g. speed.critical_multiple=1:3:50"
        )
    allowed = f"{key}=START:STOP:COUNT with finite START, STOP and an integer COUNT >= 1"
    parts = rng.split(":")
    try:
        if len(parts) == 1:
            values = np.array([float(parts[0])])
        elif len(parts) == 3:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
            if count < 1 or count > 1_000_000:
                raise ValueError
            if log:
                if not (start > 0 and stop > 0):
                    raise InputError(key, rng, "START and STOP > 0 for --log " + key)
                values = np.geomspace(start, stop, count)
            else:
                values = np.linspace(start, stop, count)
        else:
            raise ValueError
    except ValueError:
        raise InputError(key, rng, allowed) from None
    if not np.all(np.isfinite(values)):
        raise InputError(key, rng, allowed)
    return key, values


# ---- running points ----------------------------------------------------------------------------
def simulate_point(
    scenario,
    transient_revolutions: int,
    revolutions: int,
    samples_per_revolution: int,
    start=None,
    lyapunov: bool = False,
) -> tuple[dict, object]:
    """Simulate one scenario with the adaptive integrator and reduce it with :func:`point_metrics`.

    The scenario's ``[simulation]`` tolerances are kept (when adaptive); the length is
    ``revolutions`` and the output spacing ``2 pi / samples_per_revolution`` (rad of spin).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The point's scenario.
    transient_revolutions, revolutions, samples_per_revolution : int
        ``T``, ``R`` and ``N`` of the module docstring.
    start : rubrotor.engine.simulate.RotorState, optional
        State to start from (default rest).
    lyapunov : bool
        Also estimate the largest Lyapunov exponent (module docstring).

    Returns
    -------
    metrics : dict
        :func:`point_metrics` of the run.
    final_state : rubrotor.engine.simulate.RotorState or None
        The state after ``R`` revolutions (None when the run did not complete).
    """
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import PreparedRun

    if model_of(scenario).maps == "general":  # the general engine's fixed-step map
        from rubrotor.sweeps.general_point import simulate_point_general

        return simulate_point_general(
            scenario, transient_revolutions, revolutions, samples_per_revolution, lyapunov
        )
    base = scenario.simulation
    kw = {}
    if base is not None and not base.fixed_step:
        kw = dict(rtol=base.rtol, atol=base.atol, max_displacement=base.max_displacement)
    integ = Integrator(
        revolutions=revolutions, output_dtau=2 * math.pi / samples_per_revolution, **kw
    )
    # the array-level path: no Dataset, the kernel's buffer read in place
    r = PreparedRun.from_scenario(scenario, integ).run(
        initial=getattr(scenario, "initial", "rest"), start=start
    )
    n_rev = samples_per_revolution
    i0, i1 = transient_revolutions * n_rev, revolutions * n_rev
    if r.status != "complete" or r.time.size < i1 + 1:
        return _empty_metrics(revolutions - transient_revolutions), r.final_state
    lam = np.nan
    if lyapunov:
        from rubrotor.orbits.lyapunov import lyapunov_exponents

        kept = revolutions - transient_revolutions
        lam = float(
            lyapunov_exponents(scenario, revolutions=kept, start=r.final_state).exponents[0]
        )
    ch = r.channels
    pw = ch[0, i0:i1] + 1j * ch[1, i0:i1]
    fn = ch[6 * len(r.stations), i0:i1]
    gap = _rigid_clearance(scenario)
    metrics = window_metrics(pw, fn, r.events, r.speed, transient_revolutions, revolutions,
                             samples_per_revolution, lam, gap)  # fmt: skip
    return metrics, r.final_state


def _rigid_clearance(scenario) -> float | None:
    """Clearance (m) of a Hertz contact on the continuous shaft's path (a rigid stator centred
    on the axis), else None. The Hertz law models the local elastic indentation of two solids:
    an indentation beyond the clearance (millimetres for the seed rotor) lies far outside it,
    so such a run is labelled ``"indentation > clearance"``, not a rub. A linear law stands for
    a compliant seal or stator, whose deflection may exceed the gap: no such label."""
    c = model_of(scenario).seed_contact
    if c is None or not law_of(c).indentation:
        return None
    return c.clearance


def run_chunk(task: dict) -> dict:
    """Compute one chunk of points (the unit of work sent to a worker process or Dask).

    Parameters
    ----------
    task : dict
        ``{"scenario": dict form, "keys": [...], "points": [[v1, v2, ...], ...], "chunk": i,
        "transient": T, "revolutions": R, "samples": N}``.

    Returns
    -------
    dict
        ``{"chunk": i, "metrics": [dict per point]}``.
    """
    from rubrotor.errors import RubrotorError
    from rubrotor.scenario.load import scenario_from_dict

    base = scenario_from_dict(task["scenario"])
    point_scenario = PointScenarios(base, task["keys"])
    metrics = []
    for values in task["points"]:
        try:
            sc = point_scenario(values)
            m = simulate_point(
                sc,
                task["transient"],
                task["revolutions"],
                task["samples"],
                lyapunov=task.get("lyapunov", False),
            )[0]
        except RubrotorError:  # e.g. a speed exactly at an undamped critical: not classified
            m = _empty_metrics(task["revolutions"] - task["transient"])
        metrics.append(m)
    return {"chunk": task["chunk"], "metrics": metrics}


# ---- the grid and its Dataset ------------------------------------------------------------------
def _chunks(shape: tuple[int, ...], chunk_size: int) -> list[tuple[tuple[int, ...], slice]]:
    """Rectangular chunks: one index of every leading dimension x a slice of the last one."""
    last = shape[-1]
    out = []
    for lead in np.ndindex(*shape[:-1]):
        for start in range(0, last, chunk_size):
            out.append((tuple(int(i) for i in lead), slice(start, min(start + chunk_size, last))))
    return out


def _region(dims, lead, sl) -> dict:
    reg = {d: slice(i, i + 1) for d, i in zip(dims[:-1], lead, strict=True)}
    reg[dims[-1]] = sl
    return reg


def _template(keys, grid, kept: int, attrs: dict):
    import xarray as xr

    shape = tuple(len(v) for v in grid)
    dims = tuple(keys)
    coords = {}
    for key, values in zip(keys, grid, strict=True):
        coords[key] = (
            key,
            np.asarray(values, float),
            {"units": key_unit(key), "long_name": f"swept scenario key {key}"},
        )
    coords["revolution"] = (
        "revolution",
        np.arange(attrs["transient_revolutions"], attrs["transient_revolutions"] + kept),
        {"units": "1", "long_name": "revolution index k of the Poincare sample t = k 2 pi / Omega"},
    )
    coords["peak"] = ("peak", np.arange(1, N_PEAKS + 1), {"long_name": "spectral peak rank"})
    data = {}
    for name, (dt, fill, units, long) in _SCALARS.items():
        extra = {}
        if name == "regime":
            extra = {
                "flag_values": list(range(len(REGIMES))),
                "flag_meanings": " ".join(r.replace(" ", "_") for r in REGIMES),
                "comment": "code 1 is 'partial rub (period-k)' with k in 'period'; "
                "-1 = not computed yet",
            }
            fill = -1
        data[name] = (
            dims,
            np.full(shape, fill, dtype=dt),
            {"units": units, "long_name": long, **extra},
        )
    for name, long in (("poincare_v", "v"), ("poincare_w", "w")):
        data[name] = (
            (*dims, "revolution"),
            np.full((*shape, kept), np.nan),
            {
                "units": "m",
                "long_name": f"once-per-revolution sample of {long} at the contact station",
            },
        )
    data["frequency"] = (
        (*dims, "peak"),
        np.full((*shape, N_PEAKS), np.nan),
        {"units": "1", "long_name": "dominant whirl frequency / spin (negative = backward)"},
    )
    data["frequency_amplitude"] = (
        (*dims, "peak"),
        np.full((*shape, N_PEAKS), np.nan),
        {"units": "m", "long_name": "amplitude of the dominant whirl component"},
    )
    data["done"] = (dims, np.zeros(shape, np.int8), {"units": "1", "long_name": "1 when computed"})
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _fill(ds, lead, sl, metrics: list[dict]) -> None:
    """Write the metrics of one chunk into the in-memory Dataset."""
    for j, m in enumerate(metrics):
        idx = (*lead, sl.start + j)
        for name, value in m.items():
            ds[name].values[idx] = value
        ds["done"].values[idx] = 1


def write_chunk(ds, store, lead, sl, metrics: list[dict]) -> None:
    """Fill one chunk of points into ``ds`` and, with a zarr ``store``, write it there.

    The values are written before the ``done`` mask, both with SIGINT held, so that a store
    never marks a point done whose values are not written.
    """
    _fill(ds, lead, sl, metrics)
    if store is None:
        return
    part = _chunk_dataset(ds, lead, sl)
    region = _region(ds["done"].dims, lead, sl)
    with _deferred_interrupt():
        part.drop_vars(["done"]).drop_vars(list(part.coords)).to_zarr(
            store, region=region, consolidated=False
        )
        part[["done"]].drop_vars(list(part[["done"]].coords)).to_zarr(
            store, region=region, consolidated=False
        )


def _chunk_dataset(ds, lead, sl):
    dims = ds["done"].dims
    return ds.isel(_region(dims, lead, sl))


@contextlib.contextmanager
def _deferred_interrupt() -> Iterator[None]:
    """Hold SIGINT while a chunk is written, then raise KeyboardInterrupt if one came."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got = []
    previous = signal.signal(signal.SIGINT, lambda *a: got.append(a))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if got:
        raise KeyboardInterrupt


# ---- the sweep ---------------------------------------------------------------------------------
def _definition(scenario, keys, grid, transient, revolutions, samples) -> dict:
    from rubrotor.scenario.load import scenario_to_dict

    return {
        "version": STORE_VERSION,
        "scenario": scenario_to_dict(scenario, resolved=False),
        "keys": list(keys),
        "values": [np.asarray(v, float).tolist() for v in grid],
        "transient_revolutions": transient,
        "revolutions": revolutions,
        "samples_per_revolution": samples,
    }


def _check_keys(scenario, vary: Mapping) -> tuple[list[str], list[np.ndarray]]:
    from rubrotor.errors import RubrotorError
    from rubrotor.scenario.keys import resolve_key
    from rubrotor.scenario.load import scenario_to_dict

    if not isinstance(vary, Mapping) or not vary:
        raise InputError("vary", vary, "a mapping of at least one scenario key to its values")
    keys, grid = [], []
    spec = scenario_to_dict(scenario)
    for key, values in vary.items():
        ref = resolve_key(spec, str(key), "...")
        if not ref.numeric:
            raise InputError(
                key, "...", "a numeric scenario key 'section.key' (e.g. unbalance.magnitude)"
            )
        arr = np.atleast_1d(np.asarray(values, dtype=float))
        if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)):
            raise InputError(key, values, "a non-empty 1-D sequence of finite numbers")
        if np.unique(arr).size != arr.size:
            raise InputError(key, values, "distinct values")
        for v in (arr[0], arr[-1], arr.min(), arr.max()):
            try:
                _point_scenario(scenario, [key], [v])
            except RubrotorError as exc:
                raise InputError(key, float(v), getattr(exc, "allowed", str(exc))) from None
        keys.append(str(key))
        grid.append(arr)
    if len(set(keys)) != len(keys):
        raise InputError("vary", keys, "each key once")
    return keys, grid


def _open_or_create(store, template, definition: dict):
    """Open an existing store of the same sweep or create it; return the ``done`` mask."""
    import xarray as xr

    path = Path(store)
    text = json.dumps(definition, sort_keys=True)
    if path.exists():
        try:
            old = xr.open_zarr(path, consolidated=False)
            recorded = old.attrs.get("sweep_definition")
            done = old["done"].values.astype(bool)
            old.close()
        except Exception as exc:  # noqa: BLE001 - any unreadable store is a user error here
            raise InputError(
                "store", str(path), f"a sweep store written by rubrotor ({exc})"
            ) from None
        if recorded != text:
            diff = _first_difference(json.loads(recorded) if recorded else {}, definition)
            raise InputError(
                "store",
                str(path),
                f"a store of the same sweep to resume (it records a different {diff}); "
                "use another --out or delete it",
            )
        return done
    template.attrs["sweep_definition"] = text
    _create_atomically(template, path)
    return np.zeros(template["done"].shape, bool)


def _create_atomically(template, path: Path) -> None:
    """Write the empty store in a temporary folder beside ``path`` and rename it onto ``path``:
    a run killed while creating it leaves no half-made store that a rerun would refuse."""
    import shutil
    import tempfile

    path.absolute().parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.absolute().parent))
    try:
        template.to_zarr(tmp / "store", mode="w-", consolidated=True, zarr_format=2)
        try:
            os.rename(tmp / "store", path)
        except OSError:  # another run created it meanwhile
            raise InputError("store", str(path), "a store no other run is creating") from None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _first_difference(old: dict, new: dict) -> str:
    for k in new:
        if old.get(k) != new[k]:
            if k == "scenario":
                return "scenario"
            return k
    return "definition"


def run_lengths(scenario, transient_revolutions, revolutions) -> tuple[int, int]:
    """Checked ``(transient, total)`` revolutions of a sweep point.

    ``revolutions`` defaults to the scenario's ``simulation.revolutions`` or the transient plus
    200; it must exceed the transient by at least 2, and the message says which option to change.
    """
    t_rev = _int_arg("transient_revolutions", transient_revolutions, 0)
    if revolutions is None:
        sim = scenario.simulation
        revolutions = int(sim.revolutions) if sim is not None and sim.revolutions else t_rev + 200
    if (
        isinstance(revolutions, int | np.integer)
        and not isinstance(revolutions, bool)
        and revolutions < t_rev + 2
    ):
        raise InputError(
            "revolutions",
            revolutions,
            f"an integer >= {t_rev + 2}: the transient_revolutions (--transient) = {t_rev} "
            "discarded plus 2 kept; lower --transient or raise --revolutions "
            "(or simulation.revolutions in the scenario)",
        )
    return t_rev, _int_arg("revolutions", revolutions, t_rev + 2)


def sweep(
    scenario,
    vary: Mapping[str, Sequence[float]],
    *,
    transient_revolutions: int = 100,
    revolutions: int | None = None,
    samples_per_revolution: int = 128,
    workers: int | None = None,
    scheduler: str | None = None,
    store: str | os.PathLike | None = None,
    chunk_size: int | None = None,
    progress: bool = False,
    lyapunov: bool = False,
):
    """Simulate a scenario on a grid of scenario keys and reduce every point to rub metrics.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The base scenario; its ``[simulation]`` tolerances are used (adaptive integrator).
    vary : mapping of str to array_like
        Scenario keys (``"section.key"``) to their values; several keys make a grid (the first
        key is the outermost dimension).
    transient_revolutions : int
        Revolutions discarded before the metrics are taken (>= 0).
    revolutions : int, optional
        Total simulated revolutions, transient included (> ``transient_revolutions + 1``);
        default the scenario's ``simulation.revolutions`` or ``transient_revolutions + 200``.
    samples_per_revolution : int
        Output samples per revolution ``N`` (>= 8); every ``N``-th is a Poincare sample.
    workers : int, optional
        Local worker processes; default all cores (``os.cpu_count()``). 1 runs in this process.
        Ignored with ``scheduler``.
    scheduler : str, optional
        Address of a Dask distributed scheduler (``"tcp://host:port"``); chunks are submitted
        there and written here as they complete.
    store : path-like, optional
        A zarr store (directory) written chunk by chunk; an existing store of the same sweep is
        resumed (only points not marked ``done`` are computed).
    chunk_size : int, optional
        Points per chunk (along the last swept key); default about ``points / (8 workers)``,
        between 1 and 32 (small chunks balance uneven points).
    progress : bool
        Print a progress line to stderr after every chunk.
    lyapunov : bool
        Estimate the largest Lyapunov exponent of every point (``lyapunov_exponent``, 1/s;
        "chaotic" is then decided by it).

    Returns
    -------
    xarray.Dataset
        Dimensions: the swept keys, ``revolution`` (kept revolutions) and ``peak`` (3);
        variables as listed in the module docstring, plus ``done``; attributes hold the sweep
        definition (JSON) and the scenario text. Points whose worker process died twice
        (:func:`rubrotor.sweeps.pool.run_pool`) stay not ``done`` and are listed (their key
        values) in ``attrs["lost_points"]`` (JSON).
    """
    scenario = as_scenario(scenario)
    keys, grid = _check_keys(scenario, vary)
    t_rev, revs = run_lengths(scenario, transient_revolutions, revolutions)
    n_rev = _int_arg("samples_per_revolution", samples_per_revolution, 8)
    _check_engine(scenario, n_rev)
    shape = tuple(a.size for a in grid)
    n_points = int(np.prod(shape))
    if workers is None:
        workers = os.cpu_count() or 1
    workers = _int_arg("workers", workers, 1)
    if chunk_size is None:
        chunk_size = max(1, min(32, math.ceil(n_points / (8 * workers))))
    chunk_size = _int_arg("chunk_size", chunk_size, 1)
    chunk_size = min(chunk_size, shape[-1])
    definition = _definition(scenario, keys, grid, t_rev, revs, n_rev)
    if lyapunov:
        definition["lyapunov"] = True
    attrs = {
        "title": f"rubrotor sweep {scenario.name}".strip(),
        "scenario_name": scenario.name,
        "swept_keys": " ".join(keys),
        "transient_revolutions": t_rev,
        "revolutions": revs,
        "samples_per_revolution": n_rev,
        "regime_rules": "see rubrotor.sweeps.regimes module docstring",
        "scenario": getattr(scenario, "source", ""),
        "Conventions": "CF-1.8",
    }
    if scenario.contact is not None:
        attrs["clearance_m"] = float(scenario.contact.clearance)
    ds = _template(keys, grid, revs - t_rev, attrs)
    ds.attrs["sweep_definition"] = json.dumps(definition, sort_keys=True)
    chunks = _chunks(shape, chunk_size)
    pool = None
    if scheduler is None:
        pool = _local_pool(workers, len(chunks))
    else:  # before the store is made: a sweep that cannot run leaves nothing behind
        _check_dask(scheduler)
    try:
        return _run(
            ds, keys, grid, chunks, chunk_size, definition, store, pool, scheduler, progress
        )
    finally:
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)


def _run(ds, keys, grid, chunks, chunk_size, definition, store, pool, scheduler, progress):
    shape = ds["done"].shape
    t_rev = definition["transient_revolutions"]
    revs = definition["revolutions"]
    n_rev = definition["samples_per_revolution"]
    if store is not None:
        for name in list(ds.data_vars):
            ds[name].encoding["chunks"] = (
                (1,) * (len(shape) - 1) + (chunk_size,) + ds[name].shape[len(shape) :]
            )
        done = _open_or_create(store, ds.copy(), definition)
        if done.any():
            import xarray as xr

            with xr.open_zarr(store, consolidated=False) as old:
                ds = old.load()
    else:
        done = np.zeros(shape, bool)
    todo = []
    for i, (lead, sl) in enumerate(chunks):
        if not done[(*lead, sl)].all():
            pts = [
                [float(grid[d][j]) for d, j in enumerate((*lead, p))]
                for p in range(sl.start, sl.stop)
            ]
            todo.append(
                {
                    "chunk": i,
                    "scenario": definition["scenario"],
                    "keys": keys,
                    "points": pts,
                    "transient": t_rev,
                    "revolutions": revs,
                    "samples": n_rev,
                    "lyapunov": bool(definition.get("lyapunov", False)),
                }
            )

    def write(result: dict) -> None:
        lead, sl = chunks[result["chunk"]]
        write_chunk(ds, store, lead, sl, result["metrics"])

    t0 = time.perf_counter()
    n_done = 0

    def report():
        if progress:
            import sys

            el = time.perf_counter() - t0
            print(
                f"\rrubrotor sweep: {n_done}/{len(todo)} chunks, {el:.0f} s",
                end="",
                file=sys.stderr,
            )

    lost: list[dict] = []
    for result in _execute(todo, pool, scheduler, lost):
        write(result)
        n_done += 1
        report()
    if progress:
        import sys

        print(file=sys.stderr)
    if lost:  # not marked done: a rerun on the store computes them
        ds.attrs["lost_points"] = json.dumps([p for t in lost for p in t["points"]])
    return ds


def _check_engine(scenario, samples_per_revolution: int) -> None:
    """Refuse, naming the key, a scenario no sweep point can run: the shaft's engine runs a
    [shaft] scenario; a finite-element rotor runs on its fixed-step map (a contact, constant
    speed, kept samples dividing its steps per revolution)."""
    if model_of(scenario).require_maps("a parameter sweep (time simulations)") == "shaft":
        return
    from rubrotor.orbits.general_map import GeneralMap
    from rubrotor.sweeps.general_point import GENERAL_STEPS

    if GENERAL_STEPS % samples_per_revolution:
        raise InputError(
            "samples_per_revolution",
            samples_per_revolution,
            f"a divisor of the {GENERAL_STEPS} fixed steps per revolution of a general rotor",
        )
    GeneralMap(scenario, 1, GENERAL_STEPS)  # a contact, constant speed (named errors)


def _int_arg(name: str, value, minimum: int) -> int:
    if (
        isinstance(value, bool)
        or not isinstance(value, int | np.integer | float)
        or value != int(value)
    ):
        raise InputError(name, value, f"an integer >= {minimum}")
    if int(value) < minimum:
        raise InputError(name, value, f"an integer >= {minimum}")
    return int(value)


def _execute(todo: list[dict], pool, scheduler: str | None, lost: list) -> Iterator[dict]:
    """Yield chunk results as they complete: in process, in a process pool or on Dask (chunks
    whose worker died twice go to ``lost``)."""
    if not todo:
        return
    if scheduler is not None:
        stamp = f"{os.getpid()}-{time.time_ns()}"
        yield from _run_dask(
            run_chunk, todo, scheduler, key=lambda t: f"rubrotor-sweep-{stamp}-{t['chunk']}"
        )
        return
    yield from _run_pool(run_chunk, todo, pool, lost)


def _check_dask(scheduler: str) -> None:
    """Refuse a cluster sweep where Dask distributed is not installed (the installation decides;
    tested with the import blocked)."""
    import importlib.util

    if importlib.util.find_spec("distributed") is None:
        raise InputError(
            "scheduler",
            scheduler,
            'Dask distributed installed for a cluster sweep: pip install "rubrotor[sweep]" '
            "(without --scheduler, sweeps run on local processes)",
        )


def _run_dask(fn, tasks: Sequence, scheduler: str, key=None) -> Iterator:
    """``fn(task)`` for every task on a Dask cluster, results as they complete."""
    try:
        from distributed import Client, as_completed
    except ImportError:  # depends on the installation (tested with the import blocked)
        raise InputError(
            "scheduler",
            scheduler,
            'Dask distributed installed for a cluster sweep: pip install "rubrotor[sweep]" '
            "(without --scheduler, sweeps run on local processes)",
        ) from None
    try:
        client = Client(scheduler, timeout=20, set_as_default=False)
    except OSError as exc:
        raise InputError("scheduler", scheduler, f"a reachable Dask scheduler ({exc})") from None
    try:
        futures = [
            client.submit(fn, t, retries=2, **({"key": key(t)} if key else {"pure": False}))
            for t in tasks
        ]
        for fut in as_completed(futures, loop=client.loop):
            yield fut.result()
            fut.release()
    finally:
        client.close()


def open_sweep(path: str | os.PathLike):
    """Open a sweep zarr store as an in-memory Dataset (grid form, with its ``done`` mask)."""
    import xarray as xr

    p = Path(path)
    if not p.exists():
        raise InputError("store", str(path), "an existing sweep store (zarr directory)")
    with xr.open_zarr(p, consolidated=False) as ds:
        return ds.load()


def map_tasks(
    fn, tasks: Sequence, *, workers: int | None = None, scheduler: str | None = None
) -> Iterator:
    """Run ``fn(task)`` for every task on the sweep machinery; yield results as they complete.

    The same back ends as :func:`sweep`: in process (``workers=1``), a local process pool
    (default ``os.cpu_count()`` workers) or a Dask distributed cluster (``scheduler``). ``fn``
    must be a module-level function and the tasks picklable; results arrive in completion
    order, so a task should carry its own key.

    Parameters
    ----------
    fn : callable
        Module-level function of one task.
    tasks : sequence
        Tasks (picklable).
    workers : int, optional
        Local worker processes (ignored with ``scheduler``).
    scheduler : str, optional
        Dask scheduler address, ``"tcp://host:port"``.

    Yields
    ------
    object
        ``fn(task)`` per task.
    """
    tasks = list(tasks)
    if not tasks:
        return
    if scheduler is not None:
        yield from _run_dask(fn, tasks, scheduler)
        return
    n = _int_arg("workers", (os.cpu_count() or 1) if workers is None else workers, 1)
    pool = _local_pool(n, len(tasks))
    if pool is None:
        yield from _run_pool(fn, tasks, None)
        return
    with pool:
        yield from _run_pool(fn, tasks, pool)
