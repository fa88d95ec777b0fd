"""``sweep``: parameter sweeps and state-carrying follow sweeps into a zarr store."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from rubrotor.cli.common import (
    add_scenario,
    load_scenario,
    print_json,
    save_atomic,
)
from rubrotor.errors import InputError


# ---- sweep -------------------------------------------------------------------------------------
def sweep_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
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


def sweep_run(args: argparse.Namespace) -> int:
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
    except InputError as exc:  # the library's argument names: the options that set them
        if exc.field in ("scheduler", "workers", "chunk_size"):
            raise InputError(f"--{exc.field.replace('_', '-')}", exc.value, exc.allowed) from None
        raise
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
        from rubrotor.plotting.sweeps import bifurcation_figure, regime_map_figure

        keys = list(vary)
        if len(keys) == 1:
            fig = bifurcation_figure(ds, keys[0])
        else:
            fig = regime_map_figure(ds, keys[1], keys[0])
        save_atomic(fig, Path(args.figure))
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
    lost = json.loads(ds.attrs.get("lost_points", "[]"))
    if lost:
        summary["lost_points"] = lost
    print_json(summary)
    if lost:
        print(
            f"rubrotor: warning: {len(lost)} point(s) lost with a worker process that died twice "
            f"(killed or out of memory): {', '.join(map(str, lost[:5]))}"
            f"{' ...' if len(lost) > 5 else ''}; not marked done in {args.out}: run the same "
            "command again to compute them",
            file=sys.stderr,
        )
        return 1
    return 0


def _regime_counts(ds, regime_labels) -> dict:
    """``{label: count}``; per direction ``{"up": {...}, "down": {...}}`` for a follow sweep."""
    import numpy as np

    if "direction" in ds.dims:
        return {
            str(d): _regime_counts(ds.sel(direction=d), regime_labels)
            for d in ds["direction"].values
        }
    labels, counts = np.unique(regime_labels(ds), return_counts=True)
    return {str(k): int(c) for k, c in zip(labels, counts, strict=True)}


def _sweep_or_follow(scenario, vary: dict, args: argparse.Namespace, progress: bool):
    from rubrotor.sweeps.follow import follow_sweep
    from rubrotor.sweeps.sweep import sweep

    if args.follow is not None:
        ((key, values),) = vary.items()
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
