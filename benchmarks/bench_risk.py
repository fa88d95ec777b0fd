"""``rubrotor.risk`` (linear method) against a loop over ``rubrotor.unbalance_response``.

Run: ``python benchmarks/bench_risk.py [--samples 10000] [--speeds 100] [--loop 40] [--reps 3]``.

Case: ``seal_rub.toml`` (16-element FE rotor, speed-dependent bearings, gravity, one offset
seal), three scattered keys (the seal's clearance, its casing offset, the impeller's
unbalance), ``--speeds`` speeds from 100 to 1500 rad/s, ``--samples`` samples.

* ours: ``rubrotor.risk(..., method="linear")`` in memory (no store) and with its zarr store,
  after a warm-up call (compilation of the reach kernel reported separately); median of
  ``--reps`` runs of wall and CPU time; the basis (two unbalance sweeps and 100 static
  solves) is inside the timed call;
* the loop: per sample, the scenario with the sample's keys (``Scenario.with_changes``),
  ``rubrotor.unbalance_response`` at the seal over the same speeds, and the orbit's largest
  distance from the stator centre (the static deflection computed once and given to the loop
  for free). ``--loop`` samples are timed and scaled to ``--samples``. Both sides decide the
  same rub flags on those samples (checked and printed).

Prints, never asserts. State the machine's load (``uptime``) beside the figures.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

import rubrotor
from rubrotor.sweeps.risk_inputs import parse_distribution, unit_samples
from rubrotor.sweeps.risk_linear import linear_basis, orbit_reach

SCEN = Path(rubrotor.__file__).parent / "scenarios" / "seal_rub.toml"
VARY = {
    "contact.clearance": "normal(40e-6,4e-6)",
    "contact.offset_y": "normal(-25e-6,5e-6)",
    "unbalance[1].magnitude": "uniform(3e-4,7e-4)",
}


def _timed(fn):
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - t0, time.process_time() - c0


def _loop(sc, speeds, n, total):
    """The loop's rub flags of the first ``n`` samples (same design as ours, no Sobol')."""
    dists = [parse_distribution(v, k) for k, v in VARY.items()]
    u = unit_samples("sobol", len(dists), 0, 0, n, total)
    x = np.column_stack([d.ppf(u[:, j]) for j, d in enumerate(dists)])
    static = linear_basis(sc, speeds).static[:, 0]  # given to the loop for free
    rubs = np.empty((n, speeds.size), bool)
    for i, (c, oy, m) in enumerate(x):
        s = sc.with_changes(**{"contact.clearance": c, "contact.offset_y": oy,
                               "unbalance[1].magnitude": m})  # fmt: skip
        r = rubrotor.unbalance_response(s, speeds, probes=[0.75]).complex_response[:, 0]
        d = static - np.array([oy, 0.0])
        rubs[i] = orbit_reach(d, r) >= c
    return rubs


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=10_000)
    ap.add_argument("--speeds", type=int, default=100)
    ap.add_argument("--loop", type=int, default=40)
    ap.add_argument("--reps", type=int, default=3)
    a = ap.parse_args()
    sc = rubrotor.load_scenario(SCEN)
    speeds = np.linspace(100.0, 1500.0, a.speeds)
    print(f"load: {os.getloadavg()}")
    _, t_c, _ = _timed(lambda: orbit_reach(np.zeros((1, 2)), np.ones((1, 2), complex)))
    print(f"compile/load of the reach kernel: {t_c:.2f} s")
    rubrotor.risk(sc, VARY, samples=64, speeds=speeds)  # warm-up
    ours, ours_cpu, store_w = [], [], []
    for rep in range(a.reps):
        res, t, c = _timed(lambda: rubrotor.risk(sc, VARY, samples=a.samples, speeds=speeds))
        ours.append(t)
        ours_cpu.append(c)
        with tempfile.TemporaryDirectory() as tmp:
            _, t2, _ = _timed(lambda tmp=tmp, rep=rep: rubrotor.risk(
                sc, VARY, samples=a.samples, speeds=speeds, store=Path(tmp) / f"s{rep}.zarr"))  # fmt: skip
        store_w.append(t2)
    flags, t_loop, c_loop = _timed(lambda: _loop(sc, speeds, a.loop, a.samples))
    with tempfile.TemporaryDirectory() as tmp:
        rubrotor.risk(sc, VARY, samples=a.samples, speeds=speeds, store=Path(tmp) / "c.zarr")
        import xarray as xr

        with xr.open_zarr(Path(tmp) / "c.zarr", consolidated=False) as ds:
            ours_flags = ds["rub"].values[: a.loop] == 1
    scale = a.samples / a.loop
    med, med_cpu = statistics.median(ours), statistics.median(ours_cpu)
    print(f"case: seal_rub, {a.samples} samples x {a.speeds} speeds, keys {list(VARY)}")
    print(f"ours (in memory): median {med:.2f} s wall, {med_cpu:.2f} s CPU "
          f"({a.samples / med:.0f} samples/s); with the zarr store {statistics.median(store_w):.2f} s")  # fmt: skip
    print(f"loop: {a.loop} samples in {t_loop:.2f} s wall ({c_loop:.2f} s CPU), "
          f"scaled to {a.samples}: {t_loop * scale:.0f} s wall, {c_loop * scale:.0f} s CPU")  # fmt: skip
    print(
        f"ratio loop / ours: {t_loop * scale / med:.0f}x wall, {c_loop * scale / med_cpu:.0f}x CPU"
    )
    print(
        f"same rub flags on the {a.loop} looped samples: {bool(np.array_equal(flags, ours_flags))}"
    )
    print(
        f"P(rub) range over the speeds: {res.probability.min():.3f} .. {res.probability.max():.3f}"
    )


if __name__ == "__main__":
    main()
