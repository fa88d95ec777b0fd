"""``continue``: pseudo-arclength continuation of periodic orbits and their bifurcations."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from rubrotor.cli.common import (
    add_scenario,
    load_scenario,
    print_json,
)
from rubrotor.errors import InputError

# ---- continuation of periodic orbits ---------------------------------------------------------
SWITCHES = ("period-doubling",)
"""Values of ``rubrotor continue --switch``."""


def continue_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
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
        "--ds-max",
        type=float,
        default=None,
        help="largest arclength step (scaled); default: the step follows the branch's turning",
    )
    parser.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="show progress (default: when stderr is a terminal)",
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


def continue_run(args: argparse.Namespace) -> int:
    import numpy as np

    from rubrotor.engine.result import save_dataset
    from rubrotor.orbits.continuation import STOPS, branches_dataset, continue_orbit

    key, start, stop = _check_continue(args)
    scenario = load_scenario(args.scenario)
    scenario.with_changes(**{key: start})  # names a bad key before any work
    show = sys.stderr.isatty() if args.progress is None else args.progress
    progress = _Progress(key, start, stop) if show else None
    try:
        branch = continue_orbit(scenario, key, start, stop, k=args.k, points=args.points,
                                steps=args.steps, ds_max=args.ds_max, method=args.method,
                                richardson=args.richardson, progress=progress)  # fmt: skip
    except KeyboardInterrupt:  # before the branch's first point: nothing to keep
        print("rubrotor: warning: interrupted by the user before the first branch point; "
              "nothing written", file=sys.stderr)  # fmt: skip
        return 1
    if progress is not None:
        progress.done()
    branches = [branch]
    if args.switch is not None and branch.stopped != "interrupted":
        branches.append(_switch(scenario, key, branch, stop, args))
    save_dataset(branches_dataset(branches), args.out)
    if args.figure is not None:
        from rubrotor.plotting.orbits import branch_figure, contact_geometry
        from rubrotor.sweeps.follow import follow_sweep

        values = np.linspace(min(start, stop), max(start, stop), max(args.sweep_points, 2))
        from rubrotor.modelling import model_of

        if model_of(scenario).maps == "general":
            from rubrotor.sweeps.follow import follow_general

            sweep = follow_general(scenario, key, values, "both", 100, 20, steps=args.steps)
        else:
            sweep = follow_sweep(scenario, key, values, direction="both", workers=2)
        fig = branch_figure(branch, sweep, others=branches[1:],
                            geometry=contact_geometry(scenario))  # fmt: skip
        fig.savefig(args.figure, dpi=130)
    for br in branches:
        if not br.complete:
            print(f"rubrotor: warning: the {br.k}-revolution branch stopped at {key} = "
                  f"{br.points[-1].value:.6g} before {stop:g}: it {STOPS[br.stopped]} "
                  f"(--points {args.points}; raise it or --ds-max)", file=sys.stderr)  # fmt: skip
    if args.json:
        summary = branch.summary()
        for other in branches[1:]:
            summary["period_doubled"] = {
                "revolutions_per_period": other.k,
                "start": other.points[0].value,
                **other.summary(),
            }
        print_json(summary)
    else:
        for line in branch_summary(branches, key, args.out):
            print(line)
    return 1 if any(br.stopped == "interrupted" for br in branches) else 0


def branch_summary(branches, key: str, out: str) -> list[str]:
    """Short text summary of continued branches: range, points, bifurcations, why they ended."""
    from rubrotor.orbits.continuation import STOPS

    lines = []
    for br in branches:
        v = [p.value for p in br.points]
        unstable = sum(not p.stable for p in br.points)
        lines.append(f"{br.k}-revolution branch ({br.method}): {len(v)} points, {key} from "
                     f"{v[0]:.6g} to {v[-1]:.6g}, {unstable} unstable; it {STOPS[br.stopped]}")  # fmt: skip
        for b in br.bifurcations:
            lines.append(f"  {b.type:<16} at {key} = {b.value:.10g}, "
                         f"largest radius {b.max_radius_m * 1e6:.4g} um")  # fmt: skip
    lines.append(f"wrote {out}")
    return lines


class _Progress:
    """One updating stderr line: points so far and the key's value against its range."""

    def __init__(self, key: str, start: float, stop: float):
        self.key, self.start, self.stop = key, start, stop

    def __call__(self, n: int, points: int, value: float) -> None:
        frac = (value - self.start) / (self.stop - self.start)
        print(f"\rcontinue: point {n}/{points}, {self.key} = {value:.6g} "
              f"({100 * min(max(frac, 0.0), 1.0):.0f} % of {self.start:g} -> {self.stop:g})",
              end="", file=sys.stderr, flush=True)  # fmt: skip

    def done(self) -> None:
        print(file=sys.stderr)


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
    if args.ds_max is not None and not (math.isfinite(args.ds_max) and args.ds_max > 0):
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
                                  points=args.points, ds_max=args.ds_max or 0.2)  # fmt: skip
