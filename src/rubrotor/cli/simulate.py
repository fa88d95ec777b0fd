"""Time simulation verbs: ``simulate``, ``run`` (its folder layout) and ``converge``."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from rubrotor.cli.common import (
    add_scenario,
    print_json,
    save_atomic,
    table,
)
from rubrotor.errors import InputError
from rubrotor.scenario.load import load_scenario


# ---- run ---------------------------------------------------------------------------------------
def run_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument("--out", required=True, metavar="DIR", help="output directory")
    parser.add_argument(
        "--revolutions", type=float, help="override the scenario's simulated revolutions"
    )
    parser.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="show progress on long runs (default: when stderr is a terminal)",
    )


def run_summary(ds) -> dict:
    """Short JSON-able summary of a results Dataset (SI units in the key names)."""
    p = np.hypot(ds["v"].values, ds["w"].values)
    fn = ds["normal_force"].values
    stats = json.loads(ds.attrs["integrator_stats"])
    return {
        "scenario": ds.attrs.get("scenario_name", ""),
        "status": ds.attrs["status"],
        "status_message": ds.attrs["status_message"],
        "speed_rad_s": float(ds.attrs["speed_rad_s"]),
        "duration_s": float(ds["time"].values[-1]),
        "samples": int(ds.sizes["time"]),
        "max_displacement_m": float(p.max()),
        "max_normal_force_N": float(fn.max()) if fn.size else 0.0,  # no [[contact]]: none
        "contact_fraction": float(np.mean(fn > 0)) if fn.size else 0.0,
        "contact_events": int(stats.get("contact_events", 0)),
        "wall_time_s": float(stats.get("wall_s", float("nan"))),
    }


def run_run(args: argparse.Namespace) -> int:
    import dataclasses

    from rubrotor.engine.result import atomic_write, save_dataset
    from rubrotor.engine.simulate import simulate

    scenario = load_scenario(args.scenario)
    if scenario.engine is None:
        scenario.require_shaft("time simulation")
    integ = scenario.simulation
    if integ is None:
        raise InputError("simulation", None, "a [simulation] section in the scenario")
    if args.revolutions is not None:
        integ = dataclasses.replace(integ, revolutions=args.revolutions, duration=None)
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError("--out", args.out, "a directory")
    ds = simulate(scenario, integrator=integ, progress=args.progress)
    save_dataset(ds, out / "results.nc")
    summary = run_summary(ds)
    atomic_write(
        out / "summary.json", lambda tmp: Path(tmp).write_text(json.dumps(summary, indent=2))
    )
    print(json.dumps(summary, indent=2))
    if ds.attrs["status"] != "complete":
        print(f"rubrotor: warning: {ds.attrs['status_message']}", file=sys.stderr)
        return 1
    return 0


# ---- simulate ----------------------------------------------------------------------------------
def simulate_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument("--out", required=True, metavar="FILE", help="results file (.nc)")
    parser.add_argument(
        "--figure", action="store_true", help="also write FILE with .png: orbit, force, spectrum"
    )
    parser.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="show progress on long runs (default: when stderr is a terminal)",
    )


def simulate_run(args: argparse.Namespace) -> int:
    """Simulate any scenario into one netCDF file; long general-engine runs stream to it."""
    from rubrotor.engine.result import load_dataset, save_dataset
    from rubrotor.engine.simulate import simulate

    scenario = load_scenario(args.scenario)
    out = Path(args.out)
    if out.suffix != ".nc" or out.is_dir():
        raise InputError("--out", args.out, "a results file name ending in .nc")
    ds = None
    if scenario.engine is not None:
        from rubrotor.engine.general import STREAM_SAMPLES, engine_problem, simulate_engine

        _, run, _, _ = engine_problem(scenario)
        if run.duration / (run.step * run.save_every) > STREAM_SAMPLES:
            simulate_engine(scenario, progress=args.progress, stream=out)
            ds = load_dataset(out)
    if ds is None:
        ds = simulate(scenario, progress=args.progress)
        save_dataset(ds, out)
    if args.figure:
        _simulate_figure(ds, out.with_suffix(".png"))
    summary = run_summary(ds)
    summary["results"] = str(out)
    print(json.dumps(summary, indent=2))
    if ds.attrs["status"] != "complete":
        print(f"rubrotor: warning: {ds.attrs['status_message']}", file=sys.stderr)
        return 1
    return 0


def _simulate_figure(ds, path: Path) -> None:
    from rubrotor.plotting.figures import response_figure

    if ds.attrs.get("engine") == "general":
        from rubrotor.plotting.rub import engine_figure

        fig = engine_figure(ds)
    else:
        fig = response_figure(ds)
    save_atomic(fig, path)


# ---- converge ----------------------------------------------------------------------------------
def converge_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument(
        "--dtau", type=float, help="base step (rad of spin); default the scenario's or 0.001"
    )
    parser.add_argument(
        "--halvings", type=int, default=4, help="step halvings (default 4: dtau/16)"
    )
    parser.add_argument("--max-modes", type=int, help="largest mode count (default the scenario's)")
    parser.add_argument("--revolutions", type=float, help="length of each run (rev)")
    parser.add_argument("--method", choices=["exponential", "abm"], help="integrator")
    parser.add_argument("--json", action="store_true", help="print the table as JSON")


def converge_run(args: argparse.Namespace) -> int:
    from rubrotor.engine.simulate import converge

    scenario = load_scenario(args.scenario)
    if args.halvings < 0 or args.halvings > 8:
        raise InputError("--halvings", args.halvings, "an integer in 0..8")
    if args.max_modes is not None and args.max_modes < 1:
        raise InputError("--max-modes", args.max_modes, "an integer >= 1")
    if args.dtau is not None and not (args.dtau > 0 and math.isfinite(args.dtau)):
        raise InputError("--dtau", args.dtau, "a step > 0 (rad of spin)")
    rows = converge(
        scenario,
        dtau=args.dtau,
        halvings=args.halvings,
        max_modes=args.max_modes,
        revolutions=args.revolutions,
        method=args.method,
    )
    if args.json:
        print_json({"rows": rows})
        return 0
    print(
        table(
            ["study", "from", "to", "max |dP| (m)", "relative", "wall (s)"],
            [
                [
                    r["study"],
                    r["a"],
                    r["b"],
                    f"{r['max_diff_m']:.3e}",
                    f"{r['rel_diff']:.3e}",
                    f"{r['wall_s']:.3f}",
                ]
                for r in rows
            ],
        )
    )
    return 0
