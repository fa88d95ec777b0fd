"""Time simulation verbs: ``simulate``, ``run`` (its folder layout) and ``converge``."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path

from rubrotor.cli.common import (
    add_scenario,
    load_scenario,
    print_json,
    save_atomic,
    table,
)
from rubrotor.errors import InputError


# ---- run (an alias of simulate --out DIR/) ---------------------------------------------------
def run_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument("--out", required=True, metavar="DIR", help="output directory")
    _run_options(parser)


def _run_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--revolutions", type=float, help="override the scenario's simulated revolutions"
    )
    parser.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="show progress on long runs (default: when stderr is a terminal)",
    )


def speed_profile(attrs: dict) -> dict:
    """The speed law in a results file's attributes: ``{"kind": "constant"}``,
    ``{"kind": "linear", "from_rad_s", "to_rad_s"}`` (run-up or coast-down over the run) or
    ``{"kind": "table", "times_s", "speeds_rad_s"}`` (rows linear between them)."""
    if "speed_table" in attrs:
        rows = json.loads(attrs["speed_table"])
        return {"kind": "table", "times_s": [r[0] for r in rows], "speeds_rad_s": [r[1] for r in rows]}  # fmt: skip
    if "speed_end_rad_s" in attrs:
        return {"kind": "linear", "from_rad_s": float(attrs["speed_rad_s"]),
                "to_rad_s": float(attrs["speed_end_rad_s"])}  # fmt: skip
    return {"kind": "constant"}


def _speed_end(attrs: dict, duration_s: float) -> dict:
    """``speed_end_rad_s`` (the law's speed at the last sample) and ``speed_profile`` of a run
    whose speed varies; nothing for a constant speed."""
    import numpy as np

    law = speed_profile(attrs)
    if law["kind"] == "constant":
        return {}
    if law["kind"] == "linear":
        end = law["to_rad_s"]
    else:
        end = float(np.interp(duration_s, law["times_s"], law["speeds_rad_s"]))
    return {"speed_end_rad_s": end, "speed_profile": law}


def run_summary(ds) -> dict:
    """Short JSON-able summary of a results Dataset (SI units in the key names); for a run-up,
    coast-down or speed table ``speed_rad_s`` is the start speed, ``speed_end_rad_s`` the end
    speed and ``speed_profile`` the law (:func:`speed_profile`)."""
    import numpy as np

    p = np.hypot(ds["v"].values, ds["w"].values)
    fn = ds["normal_force"].values
    stats = json.loads(ds.attrs["integrator_stats"])
    return {
        "scenario": ds.attrs.get("scenario_name", ""),
        "status": ds.attrs["status"],
        "status_message": ds.attrs["status_message"],
        "speed_rad_s": float(ds.attrs["speed_rad_s"]),
        **_speed_end(ds.attrs, float(ds["time"].values[-1] - ds["time"].values[0])),
        "duration_s": float(ds["time"].values[-1]),
        "samples": int(ds.sizes["time"]),
        "max_displacement_m": float(p.max()),
        "max_normal_force_N": float(fn.max()) if fn.size else 0.0,  # no contact table: none
        "contact_fraction": float(np.mean(fn > 0)) if fn.size else 0.0,
        "contact_events": int(stats.get("contact_events", 0)),
        "wall_time_s": float(stats.get("wall_s", float("nan"))),
    }


def run_run(args: argparse.Namespace) -> int:
    """``rubrotor run SCENARIO --out DIR``: ``rubrotor simulate SCENARIO --out DIR/``, saying so
    once the run is written (an input error stays one line)."""
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError("--out", args.out, "a directory")
    args.out = str(out) + "/"
    args.figure = False
    status = simulate_run(args)
    print(
        "rubrotor: note: `rubrotor run` is an alias of `rubrotor simulate SCENARIO --out DIR/` "
        "and will be removed in a later release",
        file=sys.stderr,
    )
    return status


# ---- simulate ----------------------------------------------------------------------------------
def simulate_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument(
        "--out",
        required=True,
        metavar="FILE|DIR/",
        help="results file (.nc), or a folder (ending in /, or existing) for "
        "DIR/results.nc and DIR/summary.json",
    )
    parser.add_argument(
        "--figure", action="store_true", help="also write FILE with .png: orbit, force, spectrum"
    )
    parser.add_argument(
        "--rpm", action="store_true", help="speed axis of the figure in rev/min (default rad/s)"
    )
    _run_options(parser)


def _outputs(text: str) -> tuple[Path, Path | None]:
    """The results file and the summary file (None for a plain file) of ``--out``."""
    out = Path(text)
    if text.endswith(("/", os.sep)) or out.is_dir():
        if out.exists() and not out.is_dir():
            raise InputError("--out", text, "a directory")
        return out / "results.nc", out / "summary.json"
    if out.suffix != ".nc":
        raise InputError("--out", text, "a results file name ending in .nc, or a folder DIR/")
    return out, None


def simulate_run(args: argparse.Namespace) -> int:
    """Simulate any scenario into one netCDF file (or DIR/results.nc and DIR/summary.json);
    long general-engine runs stream to it. A first run that compiles for more than a few
    seconds says so on stderr (:func:`~rubrotor.cli.common.compile_notice`)."""
    from rubrotor.cli.common import compile_notice

    with compile_notice():
        return _simulate_run(args)


def _simulate_run(args: argparse.Namespace) -> int:
    import dataclasses

    from rubrotor.engine.result import save_dataset
    from rubrotor.engine.simulate import simulate

    scenario = load_scenario(args.scenario)
    out, summary_file = _outputs(args.out)
    source = getattr(getattr(scenario, "engine", None), "initial_path", None)
    if source is not None and Path(source).resolve() == out.resolve():
        raise InputError("--out", args.out, "a file other than the restart file initial.path "
                         "(the continuation would replace the run it continues)")  # fmt: skip
    integ = scenario.simulation
    if args.revolutions is not None:
        if integ is None:
            raise InputError("simulation", None, "a [simulation] section in the scenario")
        integ = dataclasses.replace(integ, revolutions=args.revolutions, duration=None)
    from rubrotor.modelling import model_of

    if model_of(scenario).runner == "general":
        from rubrotor.engine.general import STREAM_SAMPLES, engine_problem, simulate_engine

        _, run, _, _ = engine_problem(scenario, integ)
        if run.duration / (run.step * run.save_every) > STREAM_SAMPLES:
            simulate_engine(scenario, integrator=integ, progress=args.progress, stream=out)
            return _report(streamed_summary(out), out, summary_file, args.figure)
    ds = simulate(scenario, integrator=integ, progress=args.progress)
    save_dataset(ds, out)
    if args.figure:
        _simulate_figure(ds, out.with_suffix(".png"), getattr(args, "rpm", False))
    return _report(run_summary(ds), out, summary_file, False)


FIGURE_SAMPLES = 1 << 18
"""Samples (from the end) a streamed run's figure draws."""


def streamed_summary(path: Path) -> dict:
    """:func:`run_summary` of a streamed results file, read chunk by chunk (bounded memory)."""
    from rubrotor.engine.stream import file_summary

    fs = file_summary(path)
    at = fs["attrs"]
    stats = json.loads(at.get("integrator_stats", "{}"))
    return {
        "scenario": at.get("scenario_name", ""),
        "status": at["status"],
        "status_message": at["status_message"],
        "speed_rad_s": float(at["speed_rad_s"]),
        **_speed_end(at, fs["duration_s"] - float(at.get("start_time_s", 0.0))),
        "duration_s": fs["duration_s"],
        "samples": fs["samples"],
        "max_displacement_m": fs["max_displacement_m"],
        "max_normal_force_N": fs["max_normal_force_N"],
        "contact_fraction": fs["contact_fraction"],
        "contact_events": int(stats.get("contact_events", 0)),
        "wall_time_s": float(stats.get("wall_s", float("nan"))),
    }


def _report(summary: dict, out: Path, summary_file, figure: bool) -> int:
    """Write the summary (and a streamed run's figure of its last samples); the exit status."""
    from rubrotor.engine.result import atomic_write

    if figure:
        from rubrotor.engine.stream import tail_dataset
        from rubrotor.plotting.rub import engine_figure

        ds = tail_dataset(out, FIGURE_SAMPLES)
        t = ds["time"].values
        title = (f"{summary['scenario']} ({summary['status']}): the last {t[-1] - t[0]:.4g} s "
                 f"of {summary['duration_s']:.4g} s")  # fmt: skip
        save_atomic(engine_figure(ds, title=title), out.with_suffix(".png"))
    if summary_file is not None:
        text = json.dumps(summary, indent=2)
        atomic_write(summary_file, lambda tmp: Path(tmp).write_text(text))
    summary["results"] = str(out)
    print(json.dumps(summary, indent=2))
    if summary["status"] != "complete":
        print(f"rubrotor: warning: {summary['status_message']}", file=sys.stderr)
        return 1
    return 0


def _simulate_figure(ds, path: Path, rpm: bool = False) -> None:
    from rubrotor.plotting.runs import response_figure

    if ds.attrs.get("engine") == "general":
        from rubrotor.plotting.rub import engine_figure

        fig = engine_figure(ds, rpm=rpm)
    elif ds.attrs.get("engine") == "free-spin":  # [speed] profile = "free"
        from rubrotor.plotting.touchdown import touchdown_figure

        fig = touchdown_figure(ds)
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
