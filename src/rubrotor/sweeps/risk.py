"""Rub risk under uncertainty: the probability of rub against speed over scattered tolerances.

:func:`risk` draws ``N`` samples of some scenario keys (:mod:`rubrotor.sweeps.risk_inputs`),
decides for each sample and speed whether it rubs, and returns the probability of rub against
speed with a Wilson score interval and, on request, the Sobol' indices naming which key drives
the risk (:mod:`rubrotor.sweeps.sobol`).

Methods
-------
* ``"linear"``: the 1X orbit plus the static deflection at each contact reaches the clearance
  (:mod:`rubrotor.sweeps.risk_linear`); samples are evaluated in batches.
* ``"time"``: every sample runs as a sweep point does (:func:`rubrotor.sweeps.sweep.simulate_point`:
  the general rotor's fixed-step map from its steady no-contact orbit, the shaft's adaptive
  engine) at each speed, locally or on Dask. A sample rubs when its contact fraction is > 0;
  a run that does not complete (diverged) is kept, counted in ``diverged`` and counted as a rub.

Wilson interval of ``k`` rubs in ``n`` samples at level ``1 - alpha`` (``z`` the normal
quantile ``1 - alpha / 2``, ``p = k / n``):
``(p + z^2/2n +- z sqrt(p (1 - p)/n + z^2/4n^2)) / (1 + z^2/n)``.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Mapping

import numpy as np

from rubrotor.errors import InputError
from rubrotor.scenario.keys import resolve_key
from rubrotor.scenario.load import as_scenario, key_unit, scenario_to_dict
from rubrotor.sweeps.risk_inputs import (
    SAMPLERS,
    Distribution,
    check_values,
    parse_distribution,
    sample_values,
    unit_samples,
)
from rubrotor.sweeps.risk_linear import Screen
from rubrotor.sweeps.risk_result import RiskResult, progress_line, wilson_interval
from rubrotor.sweeps.risk_time import run_time

__all__ = ["RiskResult", "risk", "wilson_interval", "METHODS"]

METHODS = ("linear", "time")


# ---- inputs ------------------------------------------------------------------------------------
def _check_vary(scenario, vary) -> tuple[list, list[Distribution]]:
    if not isinstance(vary, Mapping) or not vary:
        raise InputError("vary", vary, "a mapping of at least one scenario key to a distribution")
    spec = scenario_to_dict(scenario)
    refs, dists = [], []
    for key, dist in vary.items():
        ref = resolve_key(spec, str(key), str(dist))
        if not ref.numeric or not ref.name:
            raise InputError(key, str(dist), "a numeric scenario key 'section.key'")
        if not isinstance(dist, Distribution):
            dist = parse_distribution(str(dist), str(key))
        refs.append(ref)
        dists.append(Distribution(dist.kind, dist.params, str(key)))
    if len({(r.section, r.index, r.name) for r in refs}) != len(refs):
        raise InputError("vary", list(vary), "each key once")
    return refs, dists


def _speeds(scenario, speeds) -> np.ndarray:
    if speeds is None:
        return np.array([float(scenario.speed)])
    s = np.atleast_1d(np.asarray(speeds, float))
    if s.ndim != 1 or s.size < 1 or not np.all(np.isfinite(s)) or np.any(s <= 0) or (
            s.size > 1 and np.any(np.diff(s) <= 0)):  # fmt: skip
        raise InputError("speeds", speeds, "increasing finite spin speeds > 0 (rad/s)")
    return s


# ---- the linear screen of a batch --------------------------------------------------------------
def _linear_chunk(ev: Screen, dists, design: tuple, start: int, count: int) -> dict:
    """Inputs, margins and rub flags of samples ``start .. start + count - 1`` (and, with the
    Saltelli design, the smallest margin at ``A``, ``B`` and every ``A_B^(i)``)."""
    sampler, seed, total, with_sobol = design
    d = len(dists)
    u = unit_samples(sampler, 2 * d if with_sobol else d, seed, start, count, total)
    a = sample_values(dists, u[:, :d])
    check_values(ev.refs, a, start)
    margin = ev.margins(a)
    out = {"inputs": a, "margin": margin, "rub": (margin <= 0).astype(np.int8)}
    if with_sobol:
        b = sample_values(dists, u[:, d:])
        check_values(ev.refs, b, start)
        y = [margin.min(1), ev.margins(b).min(1)]
        for i in range(d):
            ab = a.copy()
            ab[:, i] = b[:, i]
            y.append(ev.margins(ab).min(1))
        out["design_margin"] = np.column_stack(y)
    return out


def _layout(keys, units, with_sobol: bool) -> dict:
    lay = {
        "inputs": (("sample", "key"), "f8", np.nan, {"long_name": "sampled key values",
                   "units_per_key": json.dumps([units[k] for k in keys])}),
        "margin": (("sample", "speed"), "f8", np.nan, {"units": "m", "long_name":
                   "clearance minus the orbit's largest distance from the stator centre"}),
        "rub": (("sample", "speed"), "i1", -1, {"units": "1", "long_name": "1 when the sample rubs"}),
    }  # fmt: skip
    if with_sobol:
        lay["design_margin"] = (("sample", "block"), "f8", np.nan, {"units": "m", "long_name":
                                "smallest margin over the speeds at A, B, A_B^(1..d)"})  # fmt: skip
    return lay


def _sobol_dict(keys, y: np.ndarray, confidence: float, seed: int) -> dict:
    from rubrotor.sweeps.sobol import sobol_indices

    out = {}
    for name, f in (("margin", y), ("rub", (y <= 0).astype(float))):
        s = sobol_indices(f[0], f[1], f[2:], confidence=confidence, seed=seed)
        out[name] = {k: {"first": _num(s.first[i]), "total": _num(s.total[i]),
                         "first_interval": [_num(x) for x in s.first_interval[i]],
                         "total_interval": [_num(x) for x in s.total_interval[i]]}
                     for i, k in enumerate(keys)}  # fmt: skip
    return out


def _num(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def _int(name: str, value, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise InputError(name, value, f"an integer >= {minimum}")
    return int(value)


def risk(scenario, vary, *, samples: int, speeds=None, method: str = "linear", seed: int = 0,
         sampler: str = "sobol", sobol: bool = False, confidence: float = 0.95, store=None,
         chunk_size: int | None = None, progress: bool = False, scheduler: str | None = None,
         workers: int | None = None, revolutions: int | None = None,
         transient_revolutions: int = 20, near: float | None = None) -> RiskResult:  # fmt: skip
    """Probability of rub against speed when scenario keys scatter (module docstring).

    Parameters
    ----------
    scenario : Scenario or path
        The nominal scenario, with a contact and an unbalance.
    vary : mapping of str to str or Distribution
        Scenario keys (``"contact.clearance"``, ``"unbalance[2].magnitude"``, see
        :mod:`rubrotor.scenario.keys`) to distributions (``"normal(40e-6,4e-6)"``, see
        :mod:`rubrotor.sweeps.risk_inputs`), in the keys' SI units.
    samples : int
        ``N`` >= 1.
    speeds : array_like, optional
        Increasing spin speeds (rad/s); default the scenario's speed.
    method : {"linear", "time"}
        The rub criterion (module docstring).
    seed : int
        Seed of the samples (>= 0): the same seed gives the same samples and results.
    sampler : {"sobol", "lhs", "random"}
        Scrambled Sobol', Latin hypercube or plain pseudo-random samples.
    sobol : bool
        Also compute Sobol' indices (linear method; ``N (d + 2)`` evaluations, Saltelli design).
    confidence : float
        Level of the Wilson and bootstrap intervals, in (0, 1).
    store : path-like, optional
        zarr store of every sample's inputs and outputs (resumed when it exists).
    chunk_size : int, optional
        Samples per chunk (default 1024 linear, 2 time).
    progress : bool
        Print a progress line to stderr.
    scheduler : str, optional
        Time method: a Dask scheduler address, or ``"local"`` for a LocalCluster of ``workers``.
    workers : int, optional
        Time method: local worker processes (default 1: in this process).
    revolutions, transient_revolutions : int
        Time method: simulated and discarded revolutions per run (default the scenario's
        ``simulation.revolutions`` and 20).
    near : float, optional
        Time method: simulate only the (sample, speed) pairs whose linear margin lies within
        ``near`` times the nominal smallest clearance of the boundary (> 0); the others keep
        the linear verdict. Default: simulate every pair.

    Returns
    -------
    RiskResult
    """
    scenario = as_scenario(scenario)
    refs, dists = _check_vary(scenario, vary)
    n = _int("samples", samples, 1)
    seed = _int("seed", seed, 0)
    s = _speeds(scenario, speeds)
    if method not in METHODS:
        raise InputError("method", method, " or ".join(METHODS))
    if sampler not in SAMPLERS:
        raise InputError("sampler", sampler, " or ".join(SAMPLERS))
    if not (isinstance(confidence, float | int) and 0 < confidence < 1):
        raise InputError("confidence", confidence, "a level in (0, 1)")
    if sobol and method == "time":
        raise InputError("sobol", True, "Sobol' indices with --method linear")
    if near is not None and not (isinstance(near, float | int) and near > 0 and method == "time"):
        raise InputError("near", near, "a fraction > 0 of the clearance, with the time method")
    chunk = _int("chunk_size", chunk_size or (1024 if method == "linear" else 2), 1)
    keys = tuple(r.text for r in refs)
    units = {k: key_unit(k) for k in keys}
    definition = {"version": 1, "scenario": scenario_to_dict(scenario, resolved=False),
                  "keys": list(keys), "distributions": [d.text() for d in dists], "samples": n,
                  "speeds": s.tolist(), "method": method, "seed": seed, "sampler": sampler,
                  "sobol": bool(sobol), "chunk": chunk}  # fmt: skip
    if near is not None:
        definition["near"] = float(near)
    if method == "time":
        return run_time(scenario, refs, dists, definition, store, progress, scheduler, workers,
                        (transient_revolutions, revolutions), confidence)  # fmt: skip
    ev = Screen(scenario, refs, s)
    n_chunks = -(-n // chunk)
    st = None
    if store is not None:
        from rubrotor.sweeps.risk_store import RiskStore

        sizes = {"sample": n, "speed": s.size, "key": len(keys), "block": len(keys) + 2}
        coords = {"speed": (s, {"units": "rad/s", "long_name": "spin speed"})}
        st = RiskStore(store, definition, _layout(keys, units, sobol), sizes, chunk, coords)
    done = st.done() if st is not None else np.zeros(n_chunks, bool)
    rubs, anywhere = np.zeros(s.size, np.int64), 0
    y = np.empty((len(keys) + 2, n)) if sobol else None
    t0 = time.perf_counter()
    for ci in range(n_chunks):
        a, cnt = ci * chunk, min(chunk, n - ci * chunk)
        if done[ci]:
            part = {"rub": st.read("rub", ci, cnt)}
            if sobol:
                part["design_margin"] = st.read("design_margin", ci, cnt)
        else:
            part = _linear_chunk(ev, dists, (sampler, seed, n, sobol), a, cnt)
            if st is not None:
                st.write(ci, part)
        rubs += part["rub"].sum(0)
        anywhere += int(part["rub"].any(1).sum())
        if sobol:
            y[:, a : a + cnt] = part["design_margin"].T
        progress_line(progress, ci + 1, n_chunks, t0)
    lo, hi = wilson_interval(rubs, n, confidence)
    return RiskResult(
        method=method, speeds=s, samples=n, rubs=rubs, probability=rubs / n, lower=lo, upper=hi,
        confidence=float(confidence), keys=keys, distributions=tuple(d.text() for d in dists),
        seed=seed, sampler=sampler, rub_anywhere=anywhere / n,
        sobol=_sobol_dict(keys, y, confidence, seed) if sobol else None,
        store=None if store is None else str(store), units=units,
    )  # fmt: skip
