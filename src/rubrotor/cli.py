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
from rubrotor.scenario import load_scenario

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
    from rubrotor.api import modes

    scenario = load_scenario(args.scenario)
    speed = scenario.speed if args.speed is None else args.speed
    if not math.isfinite(speed) or speed < 0:
        raise InputError("--speed", args.speed, "a finite spin speed >= 0 (rad/s)")
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


# ---- critical ----------------------------------------------------------------------------------
def _critical_args(parser: argparse.ArgumentParser) -> None:
    _add_scenario(parser)
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")


def _critical_run(args: argparse.Namespace) -> int:
    from rubrotor.api import critical_speeds

    scenario = load_scenario(args.scenario)
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
    """Write the figure atomically (see :func:`rubrotor.results.atomic_write`)."""
    from rubrotor.results import atomic_write

    directory = out.parent if str(out.parent) else Path(".")
    if not directory.is_dir():
        raise InputError("--out", str(out), "a file in an existing directory")
    fmt = out.suffix.lstrip(".").lower() or "png"
    atomic_write(out, lambda tmp: fig.savefig(tmp, format=fmt, dpi=150))


def _campbell_run(args: argparse.Namespace) -> int:
    from rubrotor.modal import campbell
    from rubrotor.plotting import campbell_figure

    speeds = parse_speeds(args.speeds)
    out = Path(args.out)
    fmt = out.suffix.lstrip(".").lower()
    if fmt not in ("png", "pdf", "svg"):
        raise InputError("--out", args.out, "a file name ending in .png, .pdf or .svg")
    scenario = load_scenario(args.scenario)
    fig = campbell_figure(scenario.shaft, speeds, operating_speed=scenario.speed)
    _save_atomic(fig, out)
    if args.json:
        data = campbell(scenario.shaft, speeds)
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

    from rubrotor.results import atomic_write, save_dataset
    from rubrotor.simulation import simulate

    scenario = load_scenario(args.scenario)
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
    from rubrotor.simulation import converge

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
    from rubrotor.results import atomic_write
    from rubrotor.sweep import parse_vary, regime_labels, sweep

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
    try:
        ds = sweep(
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
        )
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
        from rubrotor.plotting import bifurcation_figure, regime_map_figure

        keys = list(vary)
        if len(keys) == 1:
            fig = bifurcation_figure(ds, keys[0])
        else:
            fig = regime_map_figure(ds, keys[1], keys[0])
        _save_atomic(fig, Path(args.figure))
    labels, counts = np.unique(regime_labels(ds), return_counts=True)
    summary = {
        "store": args.out,
        "points": int(ds["done"].size),
        "regimes": {str(k): int(c) for k, c in zip(labels, counts, strict=True)},
        "incomplete_runs": int((ds["status"].values == 0).sum()),
    }
    if args.netcdf:
        summary["netcdf"] = args.netcdf
    if args.figure:
        summary["figure"] = args.figure
    _print_json(summary)
    return 0


COMMANDS: list[Command] = [
    Command("modes", "whirl frequencies of every mode at one spin speed", _modes_args, _modes_run),
    Command("critical", "forward and backward critical speeds", _critical_args, _critical_run),
    Command(
        "campbell", "Campbell diagram (figure, optionally JSON)", _campbell_args, _campbell_run
    ),
    Command("run", "simulate a scenario: DIR/results.nc and a JSON summary", _run_args, _run_run),
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
