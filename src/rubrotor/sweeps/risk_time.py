"""The time method of a risk analysis: each sample simulated at each speed, locally or on Dask.

Every (sample, speed) runs as a sweep point (:func:`rubrotor.sweeps.sweep.simulate_point`) of
the scenario with the sample's keys and ``speed.rad_per_s`` set. A chunk of samples is one task
(``run_time_chunk``, a pure function of the task: the same seed gives the same bits wherever it
runs); chunks are written to the store as they complete and a rerun computes only the missing
ones. A run that does not complete (``status`` 0: diverged, or refused by the engine) is kept:
its metrics are NaN, it is counted in ``diverged`` and as a rub.

With ``near`` (a fraction), only the (sample, speed) pairs the linear screen puts near the
boundary, ``|margin| <= near c_min`` (``c_min`` the nominal scenario's smallest clearance, m),
are simulated; the others keep the linear verdict (``status`` -1, metrics NaN).
"""

from __future__ import annotations

import time

import numpy as np

from rubrotor.errors import RubrotorError
from rubrotor.scenario.load import key_unit

__all__ = ["run_time", "run_time_chunk"]

_OUT = ("peak_normal_force", "contact_fraction", "regime", "status", "rub")
SCREENED = -1
"""``status`` of a pair left to the linear verdict (not simulated)."""


def run_time_chunk(task: dict) -> dict:
    """Simulate one chunk of samples at every speed (the unit of work of a worker)."""
    from rubrotor.scenario.load import scenario_from_dict
    from rubrotor.sweeps.metrics import _empty_metrics
    from rubrotor.sweeps.sweep import simulate_point

    base = scenario_from_dict(task["scenario"])
    t_rev, revs = task["transient"], task["revolutions"]
    out = {k: np.full((len(task["values"]), len(task["speeds"])), np.nan) for k in _OUT}
    simulate = task.get("simulate")
    for i, row in enumerate(task["values"]):
        for j, w in enumerate(task["speeds"]):
            if simulate is not None and not simulate[i][j]:
                out["status"][i, j] = SCREENED
                out["rub"][i, j] = float(task["linear_rub"][i][j])
                continue
            changes = dict(zip(task["keys"], row, strict=True))
            changes["speed.rad_per_s"] = float(w)
            try:
                m = simulate_point(base.with_changes(**changes), t_rev, revs, 64)[0]
            except (RubrotorError, FloatingPointError, ValueError):
                m = _empty_metrics(revs - t_rev)
            for k in _OUT[:-1]:
                out[k][i, j] = float(m[k])
            out["rub"][i, j] = float(m["status"] != 1 or m["contact_fraction"] > 0)
    return {"chunk": task["chunk"], **out}


def _stats(rub, status, peak, frac, regime) -> dict:
    from rubrotor.sweeps.regimes import REGIMES

    q = [0.05, 0.5, 0.95]
    out = {"diverged": (status == 0).sum(0).astype(int).tolist(),
           "simulated": (status != SCREENED).sum(0).astype(int).tolist(), "quantiles": q,
           "peak_normal_force_N": [], "contact_fraction": [], "regimes": []}  # fmt: skip
    for j in range(rub.shape[1]):
        for name, v in (("peak_normal_force_N", peak[:, j]), ("contact_fraction", frac[:, j])):
            ok = v[np.isfinite(v)]
            out[name].append(np.quantile(ok, q).tolist() if ok.size else None)
        codes = regime[:, j][np.isfinite(regime[:, j])].astype(int)
        out["regimes"].append({REGIMES[c]: int((codes == c).sum()) for c in np.unique(codes)
                               if 0 <= c < len(REGIMES)})  # fmt: skip
    return out


def _tasks(scenario, refs, dists, definition, todo, lengths):
    from rubrotor.sweeps.risk_inputs import check_values, sample_values, unit_samples

    n, chunk, near = definition["samples"], definition["chunk"], definition.get("near")
    screen = band = None
    if near is not None and todo:
        from rubrotor.sweeps.risk_linear import Screen, nominal_clearance

        screen = Screen(scenario, refs, np.asarray(definition["speeds"], float))
        band = near * nominal_clearance(scenario)
    tasks = []
    for ci in todo:
        a, cnt = ci * chunk, min(chunk, n - ci * chunk)
        u = unit_samples(definition["sampler"], len(dists), definition["seed"], a, cnt, n)
        vals = sample_values(dists, u)
        check_values(refs, vals, a)
        task = {"chunk": ci, "scenario": definition["scenario"], "keys": definition["keys"],
                "values": vals.tolist(), "speeds": definition["speeds"],
                "transient": lengths[0], "revolutions": lengths[1]}  # fmt: skip
        if screen is not None:
            margin = screen.margins(vals)
            task["simulate"] = (np.abs(margin) <= band).tolist()
            task["linear_rub"] = (margin <= 0).tolist()
        tasks.append(task)
    return tasks


def _lengths(scenario, lengths) -> tuple[int, int]:
    from rubrotor.sweeps.sweep import run_lengths

    return run_lengths(scenario, lengths[0], lengths[1])


def _backend(scheduler, workers):
    """``(scheduler address or None, cluster to close or None)``."""
    if scheduler != "local":
        return scheduler, None
    from rubrotor.sweeps.sweep import _check_dask

    _check_dask("local")
    from distributed import LocalCluster

    cluster = LocalCluster(n_workers=workers or 1, threads_per_worker=1, processes=True,
                           dashboard_address=None)  # fmt: skip
    return cluster.scheduler_address, cluster


def run_time(scenario, refs, dists, definition, store, progress, scheduler, workers, lengths,
             confidence):  # fmt: skip
    """The time method of :func:`rubrotor.sweeps.risk.risk` (same arguments, checked there)."""
    from rubrotor.sweeps.risk_result import RiskResult, progress_line, wilson_interval
    from rubrotor.sweeps.sweep import map_tasks

    n, chunk, s = definition["samples"], definition["chunk"], np.asarray(definition["speeds"])
    t_rev, revs = _lengths(scenario, lengths)
    definition = {**definition, "transient": t_rev, "revolutions": revs}
    n_chunks = -(-n // chunk)
    st = None
    if store is not None:
        from rubrotor.sweeps.risk_store import RiskStore

        units = {"peak_normal_force": "N", "contact_fraction": "1", "regime": "1", "status": "1",
                 "rub": "1"}  # fmt: skip
        layout = {k: (("sample", "speed"), "f8", np.nan, {"units": u}) for k, u in units.items()}
        coords = {"speed": (s, {"units": "rad/s", "long_name": "spin speed"})}
        st = RiskStore(store, definition, layout, {"sample": n, "speed": s.size}, chunk, coords)
    done = st.done() if st is not None else np.zeros(n_chunks, bool)
    res = {k: np.full((n, s.size), np.nan) for k in _OUT}
    for ci in (int(i) for i in np.flatnonzero(done)):
        a, cnt = ci * chunk, min(chunk, n - ci * chunk)
        for k in _OUT:
            res[k][a : a + cnt] = st.read(k, ci, cnt)
    todo = [int(i) for i in np.flatnonzero(~done)]
    tasks = _tasks(scenario, refs, dists, definition, todo, (t_rev, revs))
    address, cluster = _backend(scheduler, workers) if tasks else (None, None)
    t0, count = time.perf_counter(), int(done.sum())
    try:
        for r in map_tasks(run_time_chunk, tasks, workers=1 if address else (workers or 1),
                           scheduler=address):  # fmt: skip
            ci = r["chunk"]
            a = ci * chunk
            for k in _OUT:
                res[k][a : a + len(r[k])] = r[k]
            if st is not None:
                st.write(ci, {k: r[k] for k in _OUT})
            count += 1
            progress_line(progress, count, n_chunks, t0)
    finally:
        if cluster is not None:
            cluster.close()
    rub = res["rub"] == 1
    rubs = rub.sum(0)
    lo, hi = wilson_interval(rubs, n, confidence)
    stats = _stats(rub, res["status"], res["peak_normal_force"], res["contact_fraction"],
                   res["regime"])  # fmt: skip
    return RiskResult(
        method="time", speeds=s, samples=n, rubs=rubs, probability=rubs / n, lower=lo, upper=hi,
        confidence=float(confidence), keys=tuple(definition["keys"]),
        distributions=tuple(definition["distributions"]), seed=definition["seed"],
        sampler=definition["sampler"], rub_anywhere=float(rub.any(1).mean()),
        time_stats=stats, store=None if store is None else str(store),
        units={k: key_unit(k) for k in definition["keys"]},
    )  # fmt: skip
