"""Command-line interface: ``rubrotor SUBCOMMAND SCENARIO [options]``.

Each subcommand is a :class:`Command`: a name, a help line, a function adding its arguments to
an :mod:`argparse` subparser and a function running it (``run(args) -> int``). To add one, write
those two functions and append a :class:`Command` to :data:`COMMANDS`.

Errors the user can cause (:class:`rubrotor.errors.RubrotorError`, including scenario errors)
print ``rubrotor: error: <message>`` on stderr and give exit status 2, with no traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rubrotor.errors import InputError, RubrotorError
from rubrotor.scenario.load import load_scenario

__all__ = ["main", "Command", "COMMANDS", "parse_speeds"]

TWO_PI = 2 * math.pi


@dataclass(frozen=True)
class Command:
    """One subcommand.

    Attributes
    ----------
    name : str
        Subcommand name.
    help : str
        One-line description shown by ``rubrotor --help``.
    add_arguments : callable
        ``add_arguments(parser)`` adds the subcommand's arguments.
    run : callable
        ``run(args) -> int`` runs it and returns the exit status.
    """

    name: str
    help: str
    add_arguments: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], int]


def _print_json(obj) -> None:
    print(json.dumps(obj, indent=2))


def _add_scenario(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scenario", metavar="SCENARIO", help="scenario TOML file")


def _table(headers: list[str], rows: list[list[str]]) -> str:
    widths = [
        max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(headers)
    ]
    lines = ["  ".join(h.rjust(w) for h, w in zip(headers, widths, strict=True))]
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows]
    return "\n".join(lines)


# ---- modes -------------------------------------------------------------------------------------
def _modes_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
    parser.add_argument(
        "--speed",
        type=float,
        metavar="RAD_PER_S",
        help="spin speed (rad/s); default: the scenario's speed",
    )
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")


def _modes_run(args: argparse.Namespace) -> int:
    from rubrotor.linear.verbs import modes

    scenario = load_scenario(args.scenario)
    speed = scenario.speed if args.speed is None else args.speed
    if not math.isfinite(speed) or speed < 0:
        raise InputError("--speed", args.speed, "a finite spin speed >= 0 (rad/s)")
    if scenario.rotor is not None:
        return _general_modes(scenario, speed, args.json)
    result = modes(scenario, speed)
    if args.json:
        _print_json(
            {
                "speed_rad_s": speed,
                "modes": [
                    {"n": m.n, "branch": m.branch, "whirl": m.whirl, "frequency_hz": m.frequency_hz}
                    for m in result
                ],
            }
        )
        return 0
    print(f"{scenario.name}: whirl frequencies at {speed:.6g} rad/s ({speed / TWO_PI:.6g} Hz)")
    rows = [
        [str(m.n), m.branch, m.whirl, f"{m.frequency_hz:.2f}", f"{m.frequency_rad_s:.2f}"]
        for m in result
    ]
    print(_table(["n", "branch", "whirl", "frequency (Hz)", "frequency (rad/s)"], rows))
    return 0


def _general_modes(scenario, speed: float, as_json: bool) -> int:
    """Damped modes of a general rotor: JSON, or a table."""
    from rubrotor.linear.verbs import damped_modes

    result = damped_modes(scenario, speed)
    if as_json:
        _print_json(result.to_dict())
        return 0
    print(f"{scenario.name}: damped modes at {speed:.6g} rad/s ({speed / TWO_PI:.6g} Hz)")
    rows = [
        [
            str(m.index),
            f"{m.frequency_hz:.3f}",
            f"{m.damping_ratio:.4g}",
            f"{m.log_dec:.4g}",
            m.whirl,
        ]
        for m in result.modes[:20]
    ]
    print(_table(["mode", "frequency (Hz)", "damping ratio", "log dec", "whirl"], rows))
    return 0


def _general_critical(scenario, as_json: bool, max_speed: float | None) -> int:
    """Critical speeds (1X crossings) and the stability threshold of a general rotor."""
    from rubrotor.linear.analysis import linear_critical_speeds, stability_threshold
    from rubrotor.linear.verbs import linear_system

    top = max_speed if max_speed is not None else max(3.0 * scenario.speed, 100.0)
    system = linear_system(scenario)
    crit = linear_critical_speeds(system, top, n=8)
    threshold = stability_threshold(system, top, n=8)
    if as_json:
        _print_json(
            {
                "max_speed_rad_s": top,
                "critical_speeds": [
                    {"index": c.index, "whirl": c.whirl, "speed_rad_s": c.speed_rad_s} for c in crit
                ],
                "stability_threshold_rad_s": threshold,
            }
        )
        return 0
    print(f"{scenario.name}: critical speeds up to {top:.6g} rad/s (damped frequency = spin)")
    rows = [[str(c.index), c.whirl, f"{c.speed_rad_s:.2f}", f"{c.speed_rpm:.0f}"] for c in crit]
    print(_table(["mode", "whirl", "speed (rad/s)", "speed (rpm)"], rows))
    print(
        "stability threshold: "
        + (f"{threshold:.6g} rad/s" if threshold is not None else f"none up to {top:.6g} rad/s")
    )
    return 0


# ---- critical ----------------------------------------------------------------------------------
def _critical_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument(
        "--max-speed",
        type=float,
        metavar="RAD_PER_S",
        help="general rotors: search up to this speed (default 3 x the scenario's speed)",
    )


def _critical_run(args: argparse.Namespace) -> int:
    from rubrotor.linear.verbs import critical_speeds

    scenario = load_scenario(args.scenario)
    if scenario.rotor is not None:
        if args.max_speed is not None and not (
            math.isfinite(args.max_speed) and args.max_speed > 0
        ):
            raise InputError("--max-speed", args.max_speed, "a finite speed > 0 (rad/s)")
        return _general_critical(scenario, args.json, args.max_speed)
    result = critical_speeds(scenario)
    if args.json:
        _print_json(
            {
                "critical_speeds": [
                    {"n": c.n, "branch": c.branch, "whirl": c.whirl, "speed_rad_s": c.speed_rad_s}
                    for c in result
                ]
            }
        )
        return 0
    print(f"{scenario.name}: critical speeds (whirl frequency = spin)")
    rows = [
        [
            str(c.n),
            c.branch,
            c.whirl,
            f"{c.speed_rad_s:.2f}",
            f"{c.speed_hz:.2f}",
            f"{c.speed_hz * 60:.0f}",
        ]
        for c in result
    ]
    print(_table(["n", "branch", "whirl", "speed (rad/s)", "speed (Hz)", "speed (rpm)"], rows))
    return 0


# ---- campbell ----------------------------------------------------------------------------------
def parse_speeds(text: str) -> np.ndarray:
    """Parse ``START:STOP:COUNT`` into ``COUNT`` evenly spaced spin speeds (rad/s).

    Parameters
    ----------
    text : str
        E.g. ``"0:60000:200"``: ``0 <= START < STOP`` (rad/s), integer ``COUNT >= 2``.

    Returns
    -------
    ndarray, shape (COUNT,)
        Speeds (rad/s).

    Examples
    --------
    >>> parse_speeds("0:100:3")
    array([  0.,  50., 100.])
    """
    allowed = "START:STOP:COUNT with 0 <= START < STOP (rad/s) and an integer COUNT >= 2"
    parts = text.split(":")
    if len(parts) != 3:
        raise InputError("--speeds", text, allowed)
    try:
        start, stop = float(parts[0]), float(parts[1])
        count = int(parts[2])
    except ValueError:
        raise InputError("--speeds", text, allowed) from None
    if not (math.isfinite(start) and math.isfinite(stop)) or not 0 <= start < stop:
        raise InputError("--speeds", text, allowed)
    if not 2 <= count <= 1_000_000:
        raise InputError("--speeds", text, allowed.replace(">= 2", "in 2..1000000"))
    return np.linspace(start, stop, count)


def _campbell_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
    parser.add_argument(
        "--speeds",
        required=True,
        metavar="START:STOP:COUNT",
        help="spin speeds (rad/s), e.g. 0:60000:200",
    )
    parser.add_argument("--out", required=True, metavar="FILE.png", help="figure file to write")
    parser.add_argument(
        "--json", action="store_true", help="also print the diagram data as JSON on stdout"
    )


def _save_atomic(fig, out: Path) -> None:
    """Write the figure atomically (see :func:`rubrotor.engine.result.atomic_write`)."""
    from rubrotor.engine.result import atomic_write

    directory = out.parent if str(out.parent) else Path(".")
    if not directory.is_dir():
        raise InputError("--out", str(out), "a file in an existing directory")
    fmt = out.suffix.lstrip(".").lower() or "png"
    atomic_write(out, lambda tmp: fig.savefig(tmp, format=fmt, dpi=150))


def _campbell_run(args: argparse.Namespace) -> int:
    from rubrotor.linear.shaft import campbell
    from rubrotor.plotting.figures import campbell_figure

    speeds = parse_speeds(args.speeds)
    out = Path(args.out)
    fmt = out.suffix.lstrip(".").lower()
    if fmt not in ("png", "pdf", "svg"):
        raise InputError("--out", args.out, "a file name ending in .png, .pdf or .svg")
    scenario = load_scenario(args.scenario)
    if scenario.rotor is not None:
        return _general_campbell(scenario, speeds, out, args.json)
    shaft = scenario.require_shaft("the Campbell diagram")
    fig = campbell_figure(shaft, speeds, operating_speed=scenario.speed)
    _save_atomic(fig, out)
    if args.json:
        data = campbell(shaft, speeds)
        curves = []
        for i, n in enumerate(data["n"]):
            for j, (branch, whirl) in enumerate(data["labels"]):
                curves.append(
                    {
                        "n": int(n),
                        "branch": branch,
                        "whirl": whirl,
                        "frequency_hz": data["frequency_hz"][:, i, j].tolist(),
                    }
                )
        _print_json(
            {
                "speed_rad_s": data["speed_rad_s"].tolist(),
                "operating_speed_rad_s": scenario.speed,
                "modes": curves,
                "figure": str(out),
            }
        )
    else:
        print(f"wrote {out}")
    return 0


def _general_campbell(scenario, speeds, out: Path, as_json: bool) -> int:
    """Campbell diagram with stability (log dec in colour) of a general rotor."""
    from rubrotor.linear.analysis import campbell_data, linear_critical_speeds
    from rubrotor.linear.verbs import linear_system
    from rubrotor.plotting.linear import campbell_stability_figure

    system = linear_system(scenario)
    data = campbell_data(system, speeds, n=8)
    crit = linear_critical_speeds(system, float(speeds[-1]), n=8) if speeds[-1] > 0 else []
    title = f"Campbell diagram: {scenario.name}"
    _save_atomic(campbell_stability_figure(data, crit, scenario.speed, title), out)
    if as_json:
        _print_json(
            {
                "speed_rad_s": data.speeds.tolist(),
                "frequency_hz": data.frequency_hz.tolist(),
                "log_dec": data.log_dec.tolist(),
                "whirl": data.whirl.tolist(),
                "figure": str(out),
            }
        )
    else:
        print(f"wrote {out}")
    return 0


# ---- run ---------------------------------------------------------------------------------------
def _run_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
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
        "max_normal_force_N": float(fn.max()),
        "contact_fraction": float(np.mean(fn > 0)),
        "contact_events": int(stats.get("contact_events", 0)),
        "wall_time_s": float(stats.get("wall_s", float("nan"))),
    }


def _run_run(args: argparse.Namespace) -> int:
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
def _simulate_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
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


def _simulate_run(args: argparse.Namespace) -> int:
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
    _save_atomic(fig, path)


# ---- converge ----------------------------------------------------------------------------------
def _converge_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
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


def _converge_run(args: argparse.Namespace) -> int:
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
        _print_json({"rows": rows})
        return 0
    print(
        _table(
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


# ---- sweep -------------------------------------------------------------------------------------
def _sweep_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
    parser.add_argument(
        "--vary",
        action="append",
        required=True,
        metavar="KEY=START:STOP:COUNT",
        help="scenario key and its values, e.g. speed.critical_multiple=0.5:3:100; "
        "repeat for a grid",
    )
    parser.add_argument(
        "--log", action="append", default=[], metavar="KEY", help="space KEY's values in log"
    )
    parser.add_argument("--out", required=True, metavar="SWEEP.zarr", help="zarr store (resumed)")
    parser.add_argument("--netcdf", metavar="FILE.nc", help="also export the results as netCDF")
    parser.add_argument(
        "--transient", type=int, default=100, metavar="REV", help="revolutions discarded (100)"
    )
    parser.add_argument(
        "--revolutions",
        type=int,
        metavar="REV",
        help="total simulated revolutions, transient included (default: the scenario's, "
        "or transient + 200)",
    )
    parser.add_argument(
        "--samples", type=int, default=128, metavar="N", help="samples per revolution (128)"
    )
    parser.add_argument("--workers", type=int, help="local worker processes (default: all cores)")
    parser.add_argument("--chunk-size", type=int, help="points per chunk")
    parser.add_argument(
        "--scheduler", metavar="tcp://HOST:PORT", help="run on a Dask distributed scheduler"
    )
    parser.add_argument(
        "--follow",
        choices=("up", "down", "both"),
        help="carry the state from point to point (one key): up = increasing values, "
        "down = decreasing, both = up and down sweeps (hysteresis)",
    )
    parser.add_argument(
        "--lyapunov",
        action="store_true",
        help="estimate each point's largest Lyapunov exponent (chaotic = exponent > 0.05/rev)",
    )
    parser.add_argument(
        "--figure",
        metavar="F.png",
        help="bifurcation diagram (one key) or regime map (two keys)",
    )
    parser.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="show progress (default: when stderr is a terminal)",
    )


def _sweep_run(args: argparse.Namespace) -> int:
    from rubrotor.engine.result import atomic_write
    from rubrotor.sweeps.sweep import parse_vary, regime_labels

    vary = {}
    for text in args.vary:
        key = text.partition("=")[0].strip()
        k, values = parse_vary(text, log=key in args.log)
        if k in vary:
            raise InputError(k, text, "each --vary key once")
        vary[k] = values
    for key in args.log:
        if key not in vary:
            raise InputError("--log", key, "a key also given with --vary")
    if args.figure is not None:
        fmt = Path(args.figure).suffix.lstrip(".").lower()
        if fmt not in ("png", "pdf", "svg"):
            raise InputError("--figure", args.figure, "a file name ending in .png, .pdf or .svg")
        if len(vary) > 2:
            raise InputError("--figure", args.figure, "a sweep of one or two keys")
    if args.netcdf is not None and not args.netcdf.endswith(".nc"):
        raise InputError("--netcdf", args.netcdf, "a file name ending in .nc")
    scenario = load_scenario(args.scenario)
    progress = sys.stderr.isatty() if args.progress is None else args.progress
    if args.follow is not None:
        if len(vary) != 1:
            raise InputError("--follow", args.follow, "a sweep of one key (one --vary)")
        if args.scheduler is not None:
            raise InputError("--scheduler", args.scheduler, "no scheduler with --follow")
    try:
        ds = _sweep_or_follow(scenario, vary, args, progress)
    except KeyboardInterrupt:
        print(
            f"rubrotor: interrupted; {args.out} holds every finished chunk: "
            "run the same command again to resume",
            file=sys.stderr,
        )
        return 130
    if args.netcdf is not None:
        atomic_write(args.netcdf, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4"))
    if args.figure is not None:
        from rubrotor.plotting.figures import bifurcation_figure, regime_map_figure

        keys = list(vary)
        if len(keys) == 1:
            fig = bifurcation_figure(ds, keys[0])
        else:
            fig = regime_map_figure(ds, keys[1], keys[0])
        _save_atomic(fig, Path(args.figure))
    summary = {
        "store": args.out,
        "points": int(ds["done"].size),
        "regimes": _regime_counts(ds, regime_labels),
        "incomplete_runs": int((ds["status"].values == 0).sum()),
    }
    if args.netcdf:
        summary["netcdf"] = args.netcdf
    if args.figure:
        summary["figure"] = args.figure
    _print_json(summary)
    return 0


def _regime_counts(ds, regime_labels) -> dict:
    """``{label: count}``; per direction ``{"up": {...}, "down": {...}}`` for a follow sweep."""
    if "direction" in ds.dims:
        return {
            str(d): _regime_counts(ds.sel(direction=d), regime_labels)
            for d in ds["direction"].values
        }
    labels, counts = np.unique(regime_labels(ds), return_counts=True)
    return {str(k): int(c) for k, c in zip(labels, counts, strict=True)}


def _follow_general_store(scenario, key, values, args: argparse.Namespace):
    """A general rotor's state-carrying sweep, computed in memory and written to ``--out`` as
    a zarr store at the end (atomically: a temporary store renamed; not resumable)."""
    import os
    import shutil
    import tempfile

    from rubrotor.sweeps.follow import follow_sweep

    out = Path(args.out)
    if out.exists():
        raise InputError("--out", args.out, "a new store (a general rotor's sweep is not resumed)")
    ds = follow_sweep(scenario, key, values, direction=args.follow,
                      transient_revolutions=args.transient, revolutions=args.revolutions,
                      samples_per_revolution=args.samples, lyapunov=args.lyapunov)  # fmt: skip
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.resolve().parent))
    try:
        ds.to_zarr(tmp / "store.zarr", mode="w", consolidated=True, zarr_format=2)
        os.replace(tmp / "store.zarr", out)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return ds


def _sweep_or_follow(scenario, vary: dict, args: argparse.Namespace, progress: bool):
    from rubrotor.sweeps.follow import follow_sweep
    from rubrotor.sweeps.sweep import sweep

    if args.follow is not None:
        from rubrotor.orbits.general_map import is_general

        ((key, values),) = vary.items()
        if is_general(scenario):
            return _follow_general_store(scenario, key, values, args)
        return follow_sweep(
            scenario,
            key,
            values,
            direction=args.follow,
            transient_revolutions=args.transient,
            revolutions=args.revolutions,
            samples_per_revolution=args.samples,
            workers=args.workers,
            store=args.out,
            chunk_size=args.chunk_size,
            progress=progress,
            lyapunov=args.lyapunov,
        )
    return sweep(
        scenario,
        vary,
        transient_revolutions=args.transient,
        revolutions=args.revolutions,
        samples_per_revolution=args.samples,
        workers=args.workers,
        scheduler=args.scheduler,
        store=args.out,
        chunk_size=args.chunk_size,
        progress=progress,
        lyapunov=args.lyapunov,
    )


COMMANDS: list[Command] = [
    Command("modes", "whirl frequencies of every mode at one spin speed", _modes_args, _modes_run),
    Command("critical", "forward and backward critical speeds", _critical_args, _critical_run),
    Command(
        "campbell", "Campbell diagram (figure, optionally JSON)", _campbell_args, _campbell_run
    ),
    Command("run", "simulate a scenario: DIR/results.nc and a JSON summary", _run_args, _run_run),
    Command(
        "simulate",
        "simulate any scenario (seed or general rotor) into one results file",
        _simulate_args,
        _simulate_run,
    ),
    Command(
        "converge", "the seed's step and mode convergence table", _converge_args, _converge_run
    ),
    Command(
        "sweep",
        "parameter sweep: Poincare samples, rub metrics and regimes in a zarr store",
        _sweep_args,
        _sweep_run,
    ),
]
"""The subcommands, in the order ``--help`` lists them."""


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="rubrotor",
        description="Rotor-stator rub in a continuous Timoshenko rotor.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for cmd in COMMANDS:
        p = sub.add_parser(cmd.name, help=cmd.help, description=cmd.help)
        cmd.add_arguments(p)
        p.set_defaults(_run=cmd.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line.

    Parameters
    ----------
    argv : list of str, optional
        Arguments without the program name; default ``sys.argv[1:]``.

    Returns
    -------
    int
        Exit status: 0 on success, 2 on a usage or input error (message on stderr).
    """
    parser = _parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse already printed its message
        return int(exc.code or 0)
    try:
        return args._run(args)
    except RubrotorError as exc:
        print(f"rubrotor: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. output piped into `head`
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1


# ---- analyze / scenarios / reproduce -----------------------------------------------------------
_SIGNAL_EXTENSIONS = (".nc", ".csv", ".npy", ".wav")
_MAX_ANALYSIS_RATE = 2.0e6  # Hz; longer-rate records are low-passed and decimated first


def _analyze_args(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "input",
        metavar="FILE",
        help="results.nc from `rubrotor run`, or a signal (.csv, .npy, .wav)",
    )
    parser.add_argument(
        "--out", metavar="DIR", help="output directory (default: the input file's directory)"
    )
    parser.add_argument(
        "--fs", type=float, metavar="HZ", help="sampling frequency (Hz); required for .csv and .npy"
    )
    parser.add_argument(
        "--columns",
        metavar="A[,B]",
        help="column names (CSV header) or 0-based indices: one column, or two "
        "(v,w) for the full spectrum; default the first column",
    )
    parser.add_argument(
        "--spin-hz",
        type=float,
        metavar="HZ",
        help="spin frequency (Hz) for signal files (harmonic ratios)",
    )
    parser.add_argument("--json", action="store_true", help="print the indicators as JSON")


def _read_table(path: Path, ext: str, fs):
    """Channels of a signal file as {name: array}, plus the file's own rate (WAV) or None."""
    if ext == ".npy":
        try:
            data = np.load(path, allow_pickle=False)
        except (OSError, ValueError) as exc:
            raise InputError("input", str(path), f"a readable .npy array ({exc})") from None
        data = np.asarray(data)
        if data.ndim == 1:
            data = data[:, None]
        if data.ndim != 2:
            raise InputError("input", f"array of shape {data.shape}", "a 1-D or 2-D array")
        return {str(i): data[:, i] for i in range(data.shape[1])}, None
    if ext == ".wav":
        from scipy.io import wavfile

        try:
            rate, data = wavfile.read(path)
        except (OSError, ValueError) as exc:
            raise InputError("input", str(path), f"a readable WAV file ({exc})") from None
        data = np.asarray(data, dtype=np.float64)
        if data.ndim == 1:
            data = data[:, None]
        return {str(i): data[:, i] for i in range(data.shape[1])}, float(rate)
    text = path.read_text().splitlines()
    if not text:
        raise InputError("input", str(path), "a CSV file with at least one row")
    first = [c.strip() for c in text[0].split(",")]
    try:
        [float(c) for c in first]
        names = [str(i) for i in range(len(first))]
        skip = 0
    except ValueError:
        names = first
        skip = 1
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=skip, ndmin=2)
    except ValueError as exc:
        raise InputError("input", str(path), f"a CSV file of numbers ({exc})") from None
    if data.shape[1] != len(names):
        raise InputError("input", str(path), "a CSV file with the same number of columns per row")
    out = {n: data[:, i] for i, n in enumerate(names)}
    for i in range(len(names)):  # indices work too
        out.setdefault(str(i), data[:, i])
    return out, None


def _pick_columns(table: dict, spec: str | None) -> list[tuple[str, np.ndarray]]:
    names = list(table)
    if spec is None:
        return [(names[0], table[names[0]])]
    wanted = [c.strip() for c in spec.split(",")]
    if not 1 <= len(wanted) <= 2 or any(not c for c in wanted):
        raise InputError("--columns", spec, "one or two column names or indices, e.g. v,w")
    for c in wanted:
        if c not in table:
            raise InputError("--columns", c, "one of the columns " + ", ".join(names))
    return [(c, table[c]) for c in wanted]


def load_signals(path, *, fs=None, columns=None, spin_hz=None) -> dict:
    """Read the signals ``rubrotor analyze`` works on.

    Parameters
    ----------
    path : path-like
        ``.nc`` results file (the accelerations ``v_ddot``, ``w_ddot`` are analysed, the spin
        speed and natural frequencies come from its attributes and scenario text), or a ``.csv``
        (optional header row), ``.npy`` (1-D or 2-D, columns) or ``.wav`` signal file.
    fs : float, optional
        Sampling frequency (Hz); required for CSV and NPY, optional for WAV (default: its rate).
    columns : str, optional
        ``"A"`` or ``"A,B"``: column names or indices of a signal file.
    spin_hz : float, optional
        Spin frequency (Hz) of a signal file.

    Returns
    -------
    dict
        ``v``, ``w`` (or None), ``fs`` (Hz), ``spin_hz``, ``modes`` ((label, Hz, whirl) list),
        ``unit``, ``names`` (channel names), ``source``.
    """
    import tomllib

    p = Path(path)
    ext = p.suffix.lower()
    if ext not in _SIGNAL_EXTENSIONS:
        raise InputError("input", str(path), "a file ending in " + ", ".join(_SIGNAL_EXTENSIONS))
    if not p.is_file():
        raise InputError("input", str(path), "an existing file")
    if fs is not None and not (math.isfinite(fs) and fs > 0):
        raise InputError("--fs", fs, "a finite sampling frequency > 0 (Hz)")
    if spin_hz is not None and not (math.isfinite(spin_hz) and spin_hz > 0):
        raise InputError("--spin-hz", spin_hz, "a finite spin frequency > 0 (Hz)")
    if ext == ".nc":
        from rubrotor.analysis.overview import mode_entries
        from rubrotor.engine.result import load_dataset
        from rubrotor.errors import ScenarioError
        from rubrotor.linear.verbs import modes
        from rubrotor.scenario.load import scenario_from_dict

        ds = load_dataset(p)
        for var in ("v_dot", "w_dot", "time"):
            if var not in ds.variables:
                raise InputError("input", str(path), f"a rubrotor results file (no '{var}')")
        t = ds["time"].values
        dt = np.diff(t)
        if t.size < 64 or not np.all(dt > 0) or np.ptp(dt) > 1e-6 * np.mean(dt):
            raise InputError(
                "input", str(path), "results saved on a uniform time grid (at least 64 samples)"
            )
        rate = 1.0 / float(np.mean(dt))
        text = ds.attrs.get("scenario", "")
        entries: list = []
        if text:
            try:
                sc = scenario_from_dict(tomllib.loads(text))
                entries = mode_entries(modes(sc, float(ds.attrs["speed_rad_s"])))
            except (tomllib.TOMLDecodeError, ScenarioError):
                entries = []
        v, w = _acceleration_channels(ds)
        for name, x in (("v_ddot", v), ("w_ddot", w)):
            if not np.all(np.isfinite(x)):
                raise InputError("input", f"{path}: {name}", "finite data (no NaN or inf)")
        return {
            "v": v,
            "w": w,
            "fs": rate,
            "spin_hz": float(ds.attrs["speed_hz"]),
            "modes": entries,
            "unit": "m/s^2",
            "names": ["v_ddot", "w_ddot"],
            "source": str(p),
            "scenario_name": ds.attrs.get("scenario_name", ""),
        }
    table, rate = _read_table(p, ext, fs)
    if fs is None:
        if rate is None:
            raise InputError("--fs", None, f"a sampling frequency (Hz) for {ext} files")
        fs = rate
    cols = _pick_columns(table, columns)
    for name, x in cols:
        if x.size < 64:
            raise InputError("input", f"column {name}: {x.size} samples", "at least 64 samples")
        if not np.all(np.isfinite(x)):
            raise InputError("input", f"column {name}", "finite data (no NaN or inf)")
    return {
        "v": cols[0][1],
        "w": cols[1][1] if len(cols) == 2 else None,
        "fs": float(fs),
        "spin_hz": spin_hz,
        "modes": [],
        "unit": "signal unit",
        "names": [c[0] for c in cols],
        "source": str(p),
        "scenario_name": "",
    }


def _acceleration_channels(ds) -> tuple[np.ndarray, np.ndarray]:
    """``v_ddot, w_ddot`` (m/s^2) at the contact station: the first station of a general-engine
    file (derived from the velocities by central differences when streamed without them)."""
    if "v_ddot" in ds.variables:
        v, w = ds["v_ddot"].values, ds["w_ddot"].values
    else:
        t = ds["time"].values
        v = np.gradient(ds["v_dot"].values, t, axis=-1)
        w = np.gradient(ds["w_dot"].values, t, axis=-1)
    return (v[0], w[0]) if v.ndim == 2 else (v, w)


def _indicator_rows(d: dict) -> list[list[str]]:
    rows = [["samples", f"{d['samples']}", ""], ["sampling frequency", f"{d['fs_hz']:.6g}", "Hz"]]
    if d.get("spin_hz"):
        rows.append(["spin frequency", f"{d['spin_hz']:.6g}", "Hz"])
    unit = d["unit"]
    freq = {m["label"]: m["frequency_hz"] for m in d.get("modes", [])}
    for label, e in (d.get("band_energy") or {}).items():
        rows.append([f"band energy {label} ({freq[label]:.0f} Hz)", f"{e:.4g}", f"({unit})^2"])
    for order, r in (d.get("harmonic_ratio") or {}).items():
        kind = "sub" if float(order) < 1 else "super"
        rows.append(
            [f"{kind}-harmonic {float(order):.3g}X / 1X", "inf" if r is None else f"{r:.4g}", ""]
        )
    if d.get("backward_share") is not None:
        rows.append(["backward-whirl share", f"{d['backward_share']:.4f}", ""])
    for i, f in enumerate(d.get("inner_scalogram_peaks_hz", []), 1):
        rows.append([f"inner-scalogram peak {i}", f"{f:.5g}", "Hz"])
    return rows


def _analyze_run(args: argparse.Namespace) -> int:
    from rubrotor.analysis.overview import analyze_signal, decimate_to, indicators_dict
    from rubrotor.engine.result import atomic_write
    from rubrotor.plotting.figures import analysis_figure

    sig = load_signals(args.input, fs=args.fs, columns=args.columns, spin_hz=args.spin_hz)
    chans = [sig["v"]] + ([sig["w"]] if sig["w"] is not None else [])
    chans, fs = decimate_to(chans, sig["fs"], _MAX_ANALYSIS_RATE)
    spin = sig["spin_hz"]
    if spin is not None and 3 * spin >= fs / 2:
        raise InputError("--spin-hz", spin, f"a spin frequency with 3X below fs/2 = {fs / 2:g} Hz")
    out = Path(args.out) if args.out else Path(args.input).resolve().parent
    if out.exists() and not out.is_dir():
        raise InputError("--out", args.out, "a directory")
    a = analyze_signal(
        chans[0],
        fs,
        w=chans[1] if len(chans) == 2 else None,
        spin_hz=spin,
        modes=sig["modes"],
        unit=sig["unit"],
    )
    d = indicators_dict(a)
    d["source"] = sig["source"]
    d["channels"] = sig["names"]
    name = sig["scenario_name"] or Path(args.input).name
    fig = analysis_figure(
        a, title=f"{name}: {' + i '.join(sig['names'])} (fs = {fs / 1e3:.4g} kHz)"
    )
    atomic_write(out / "analysis.png", lambda tmp: fig.savefig(tmp, format="png", dpi=110))
    atomic_write(out / "indicators.json", lambda tmp: Path(tmp).write_text(json.dumps(d, indent=2)))
    if args.json:
        _print_json(d)
    else:
        print(f"{name}: rub indicators of {', '.join(sig['names'])}")
        print(_table(["quantity", "value", "unit"], _indicator_rows(d)))
        print(f"wrote {out / 'analysis.png'} and {out / 'indicators.json'}")
    return 0


COMMANDS += [
    Command(
        "analyze",
        "rub indicators and CWT/spectrum figure of a results or signal file",
        _analyze_args,
        _analyze_run,
    ),
]


def _scenarios_args(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")


def shipped_scenarios() -> list[dict]:
    """The scenario files shipped with rubrotor: name, description and path.

    Returns
    -------
    list of dict
        ``{"name", "description", "path"}`` sorted by file name.
    """
    import tomllib
    from importlib import resources

    folder = resources.files("rubrotor") / "scenarios"
    out = []
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        if not entry.name.endswith(".toml"):
            continue
        meta = tomllib.loads(entry.read_text()).get("meta", {})
        out.append(
            {
                "name": meta.get("name", entry.name[:-5]),
                "description": " ".join(meta.get("description", "").split()),
                "path": str(entry),
            }
        )
    return out


def _scenarios_run(args: argparse.Namespace) -> int:
    items = shipped_scenarios()
    if args.json:
        _print_json({"scenarios": items})
        return 0
    width = max(len(i["name"]) for i in items)
    for i in items:
        print(f"{i['name'].ljust(width)}  {i['description']}")
    return 0


def _reproduce_args(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--out", required=True, metavar="DIR", help="output directory")
    parser.add_argument(
        "--quick", action="store_true", help="shortened runs and coarser output (for tests)"
    )
    parser.add_argument(
        "--seed-friction",
        action="store_true",
        help="run cases 1-3 with the seed's literal friction sign",
    )
    parser.add_argument(
        "--full",
        action="store_true",
        help="also the claim-robustness grid and the larger detection grid (minutes)",
    )
    parser.add_argument(
        "--workers", type=int, metavar="N", help="worker processes of --full (default: all cores)"
    )
    parser.add_argument(
        "--scheduler", metavar="ADDRESS", help="Dask scheduler for --full (tcp://host:port)"
    )
    parser.add_argument("--quiet", action="store_true", help="no progress lines")


def _reproduce_run(args: argparse.Namespace) -> int:
    from rubrotor.studies.seed.reproduce import reproduce

    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError("--out", args.out, "a directory")
    if args.workers is not None and args.workers < 1:
        raise InputError("--workers", args.workers, "an integer >= 1")
    summary = reproduce(
        out,
        quick=args.quick,
        seed_friction=args.seed_friction,
        quiet=args.quiet,
        full=args.full,
        workers=args.workers,
        scheduler=args.scheduler,
    )
    print(
        _table(
            ["seed claim", "two-field", "seed eq. (1)", "seed eq. (1), larger unbalance"],
            [
                [
                    c["claim"][:70],
                    *("holds" if x["holds"] else "does not hold" for x in (c, d, e)),
                ]
                for c, d, e in zip(
                    summary["claims"],
                    summary["seed_study"]["seed_form"]["claims"],
                    summary["seed_study"]["seed_form"]["strong"]["claims"],
                    strict=True,
                )
            ],
        )
    )
    print(
        f"wrote {out / 'report.html'}, {out / 'report.md'}, {out / 'summary.json'} "
        f"in {summary['wall_time_s']:.1f} s"
    )
    return 0


COMMANDS += [
    Command("scenarios", "list the shipped scenario files", _scenarios_args, _scenarios_run),
    Command(
        "reproduce",
        "reproduce the seed study: figures, report.html, summary.json",
        _reproduce_args,
        _reproduce_run,
    ),
]


# ---- stability of a pressed contact ----------------------------------------------------------
def _stability_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
    parser.add_argument(
        "--indentation", type=float, required=True, metavar="M", help="static indentation (m)"
    )
    parser.add_argument(
        "--bh-nd", type=float, metavar="BH", help="contact damping b_h' (default: the scenario's)"
    )
    parser.add_argument(
        "--formulation",
        choices=("both", "two-field", "seed-eq1"),
        default="both",
        help="shaft formulation(s) (default both)",
    )
    parser.add_argument("--modes", type=int, metavar="N", help="shaft modes (default: scenario's)")
    parser.add_argument("--no-friction", action="store_true", help="set mu = 0")
    parser.add_argument(
        "--linearisation", choices=("radial", "isotropic"), default="radial", help="contact model"
    )
    parser.add_argument("--top", type=int, default=6, help="eigenvalues listed per formulation")
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")


def _stability_run(args: argparse.Namespace) -> int:
    from rubrotor.linear.stability import contact_stability

    scenario = load_scenario(args.scenario)
    if args.modes is not None and not 1 <= args.modes <= 200:
        raise InputError("--modes", args.modes, "an integer in 1..200")
    forms = ("two-field", "seed-eq1") if args.formulation == "both" else (args.formulation,)
    res = [
        contact_stability(
            scenario,
            args.indentation,
            formulation=f,
            contact_damping_nd=args.bh_nd,
            modes=args.modes,
            friction=not args.no_friction,
            linearisation=args.linearisation,
        )
        for f in forms
    ]
    if args.json:
        _print_json({"speed_rad_s": scenario.speed, "results": [r.as_dict() for r in res]})
        return 0
    r0 = res[0]
    print(
        f"{scenario.name}: pressed contact, indentation {r0.indentation:.4g} m, F_n0 "
        f"{r0.normal_force:.4g} N, radial stiffness {r0.radial_stiffness:.4g} N/m, damping "
        f"{r0.radial_damping:.4g} N s/m (b_h = {r0.contact_damping:.4g} s/m), "
        f"{args.linearisation} linearisation"
    )
    rows = [
        [
            r.formulation,
            f"{e.real:+.4g}",
            f"{e.imag / TWO_PI:+.2f}",
            "unstable" if e.real > 0 else "",
        ]
        for r in res
        for e in r.eigenvalues[: max(args.top, 1)]
    ]
    print(_table(["formulation", "growth rate (1/s)", "whirl frequency (Hz)", ""], rows))
    return 0


COMMANDS += [
    Command(
        "stability",
        "eigenvalues of the rotor pressed into the stator (linearised contact)",
        _stability_args,
        _stability_run,
    )
]


# ---- continuation of periodic orbits ---------------------------------------------------------
SWITCHES = ("period-doubling",)
"""Values of ``rubrotor continue --switch``."""


def _continue_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
    parser.add_argument("--vary", required=True, metavar="KEY=START:STOP", help="continued key")
    parser.add_argument("--out", required=True, metavar="BRANCH.nc", help="branch (netCDF)")
    parser.add_argument("--json", action="store_true", help="print points and bifurcations")
    parser.add_argument("--figure", metavar="F.png", help="branch over a follow sweep")
    parser.add_argument("--points", type=int, default=200, help="largest number of points")
    parser.add_argument("--k", type=int, default=1, help="revolutions per period (default 1)")
    parser.add_argument(
        "--sweep-points", type=int, default=25, help="points of the figure's follow sweep"
    )
    parser.add_argument(
        "--switch",
        metavar="KIND",
        help="after the branch, switch onto the branch born at its first bifurcation of this "
        "kind and continue it to STOP (period-doubling: the 2k-revolution branch); --out, "
        "--json and --figure then hold both branches",
    )
    parser.add_argument(
        "--steps", type=int, default=1024, help="fixed steps per revolution of the map (>= 16)"
    )
    parser.add_argument(
        "--ds-max", type=float, default=0.2, help="largest arclength step (scaled, default 0.2)"
    )
    parser.add_argument(
        "--method",
        default="auto",
        help="auto (default): circular orbits of an axisymmetric rotor without load as exact "
        "rotating-frame equilibria, any other orbit by shooting; shooting; synchronous",
    )
    parser.add_argument(
        "--richardson",
        action="store_true",
        help="shooting: extrapolate points and folds to zero step from --steps and 2 x --steps "
        "(fourth order on orbits in permanent contact or without contact)",
    )


def _parse_range(text: str) -> tuple[str, float, float]:
    key, sep, rng = text.partition("=")
    parts = rng.split(":")
    allowed = "KEY=START:STOP with finite START != STOP, e.g. speed.critical_multiple=1.8:1.2"
    try:
        start, stop = (float(v) for v in parts)
    except ValueError:
        raise InputError("--vary", text, allowed) from None
    if not sep or not key.strip() or not (math.isfinite(start) and math.isfinite(stop)):
        raise InputError("--vary", text, allowed)
    if start == stop:
        raise InputError("--vary", text, allowed)
    return key.strip(), start, stop


def _continue_run(args: argparse.Namespace) -> int:
    from rubrotor.engine.result import save_dataset
    from rubrotor.orbits.continuation import branches_dataset, continue_orbit

    key, start, stop = _check_continue(args)
    scenario = load_scenario(args.scenario)
    scenario.with_changes(**{key: start})  # names a bad key before any work
    branch = continue_orbit(scenario, key, start, stop, k=args.k, points=args.points,
                            steps=args.steps, ds_max=args.ds_max, method=args.method,
                            richardson=args.richardson)  # fmt: skip
    branches = [branch]
    if args.switch is not None:
        branches.append(_switch(scenario, key, branch, stop, args))
    save_dataset(branches_dataset(branches), args.out)
    if args.figure is not None:
        from rubrotor.orbits.general_map import is_general
        from rubrotor.plotting.figures import branch_figure
        from rubrotor.sweeps.follow import follow_sweep

        values = np.linspace(min(start, stop), max(start, stop), max(args.sweep_points, 2))
        if is_general(scenario):
            from rubrotor.sweeps.follow import follow_general

            sweep = follow_general(scenario, key, values, "both", 100, 20, steps=args.steps)
        else:
            sweep = follow_sweep(scenario, key, values, direction="both", workers=2)
        branch_figure(branch, sweep, others=branches[1:]).savefig(args.figure, dpi=130)
    if args.json:
        summary = branch.summary()
        for other in branches[1:]:
            summary["period_doubled"] = {
                "revolutions_per_period": other.k,
                "start": other.points[0].value,
                **other.summary(),
            }
        _print_json(summary)
    return 0


def _check_continue(args: argparse.Namespace) -> tuple[str, float, float]:
    """Validate the options of ``continue`` before any work; returns the parsed ``--vary``."""
    key, start, stop = _parse_range(args.vary)
    if not args.out.endswith(".nc"):
        raise InputError("--out", args.out, "a file name ending in .nc")
    if not Path(args.out).resolve().parent.is_dir():
        raise InputError("--out", args.out, "a file in an existing directory")
    if args.figure is not None and Path(args.figure).suffix.lower() not in (".png", ".pdf", ".svg"):
        raise InputError("--figure", args.figure, "a file name ending in .png, .pdf or .svg")
    if args.points < 2:
        raise InputError("--points", args.points, "an integer >= 2")
    if args.switch is not None and args.switch not in SWITCHES:
        raise InputError("--switch", args.switch, " or ".join(SWITCHES))
    if args.steps < 16:
        raise InputError("--steps", args.steps, "an integer >= 16 (steps per revolution)")
    if not (math.isfinite(args.ds_max) and args.ds_max > 0):
        raise InputError("--ds-max", args.ds_max, "a finite number > 0")
    from rubrotor.orbits.continuation import METHODS

    if args.method not in METHODS:
        raise InputError("--method", args.method, " | ".join(METHODS))
    return key, start, stop


def _switch(scenario, key: str, branch, stop: float, args: argparse.Namespace):
    """The period-doubled branch born at ``branch``'s first period doubling, continued to stop."""
    from rubrotor.orbits.continuation import switch_period_doubling

    if not any(b.type == "period-doubling" for b in branch.bifurcations):
        found = sorted({b.type for b in branch.bifurcations}) or ["no bifurcation"]
        raise InputError(
            "--switch",
            args.switch,
            f"a branch with a period doubling in --vary {args.vary} (found: {', '.join(found)})",
        )
    return switch_period_doubling(scenario, key, branch, stop, steps=args.steps,
                                  points=args.points, ds_max=args.ds_max)  # fmt: skip


COMMANDS += [
    Command(
        "continue",
        "pseudo-arclength continuation of a periodic orbit: branch, stability, bifurcations",
        _continue_args,
        _continue_run,
    )
]
