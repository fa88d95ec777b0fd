"""``thermal``: the thermal bow of a rubbing rotor (the Newkirk spiral).

``rubrotor thermal SCENARIO [--speeds A:B:N]`` linearises the slow (thermal) dynamics about the
steady bow at each speed (growth rate, spiral period) and gives the first forward critical
speed; ``--simulate HOURS --out F.nc`` integrates the slow dynamics at the scenario's speed and
writes the 1X vector of every contact and probe against machine time.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from rubrotor.cli.common import (
    add_scenario,
    load_scenario,
    parse_speeds,
    print_json,
    save_atomic,
    table,
)
from rubrotor.errors import InputError


def thermal_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument("--speeds", metavar="A:B:N",
                        help="spin speeds (rad/s) of the linearisation (default: 0.4 to 1.4 "
                        "times the first forward critical, 11 speeds)")  # fmt: skip
    parser.add_argument("--json", action="store_true", help="print JSON")
    parser.add_argument("--figure", metavar="F.png",
                        help="growth rate and period against speed, or with --simulate the 1X "
                        "polar spiral")  # fmt: skip
    parser.add_argument("--simulate", type=float, metavar="HOURS",
                        help="integrate the slow dynamics over HOURS of machine time at the "
                        "scenario's speed (from a straight rotor)")  # fmt: skip
    parser.add_argument("--out", metavar="F.nc", help="results of --simulate (netCDF)")
    parser.add_argument("--samples", type=int, default=200, help="output samples of --simulate")
    parser.add_argument("--steps", type=int, default=1024,
                        help="fixed steps per revolution of the orbit map (>= 16)")  # fmt: skip


def _first_forward_critical(scenario, top: float):
    """First forward critical speed (rad/s, None if none below ``top``) and all criticals."""
    from rubrotor.linear.critical import linear_critical_speeds
    from rubrotor.linear.verbs import linear_system

    crit = linear_critical_speeds(linear_system(scenario), top, n=6)
    return next((c.speed_rad_s for c in crit if c.whirl == "forward"), None), crit


def _finite(x: float):
    return float(x) if math.isfinite(x) else None


def thermal_run(args: argparse.Namespace) -> int:
    import numpy as np

    scenario = load_scenario(args.scenario)
    if args.steps < 16:
        raise InputError("--steps", args.steps, "an integer >= 16")
    if args.simulate is not None:
        return _simulate(scenario, args)
    from rubrotor.studies.thermal import growth_against_speed

    top = 3.0 * scenario.speed
    if args.speeds is not None:
        speeds = parse_speeds(args.speeds)
        top = max(top, 1.2 * float(speeds[-1]))
    first, crit = _first_forward_critical(scenario, top)
    if args.speeds is None:
        if first is None:
            raise InputError("--speeds", None, "A:B:N (no forward critical below "
                             f"{top:g} rad/s to centre the default range on)")  # fmt: skip
        speeds = np.linspace(0.4 * first, 1.4 * first, 11)
    res = growth_against_speed(scenario, speeds, steps=args.steps)
    out = {
        "first_forward_critical_rad_s": first,
        "speeds_rad_s": [float(w) for w in speeds],
        "growth_rate_per_s": [_finite(r.growth_rate) for r in res],
        "spiral_period_s": [_finite(r.spiral_period) for r in res],
    }
    if args.figure:
        from rubrotor.plotting.thermal import growth_figure

        cr = [
            c.speed_rad_s
            for c in crit
            if c.whirl == "forward" and speeds[0] <= c.speed_rad_s <= speeds[-1]
        ]
        save_atomic(growth_figure(speeds, [r.growth_rate for r in res],
                                  [r.spiral_period for r in res], cr), Path(args.figure))  # fmt: skip
    reasons = [r.reason for r in res if r.reason]
    if reasons:
        out["reasons"] = [r.reason or None for r in res]
    if args.json:
        print_json(out)
    else:
        print(f"{scenario.name}: thermal bow, first forward critical "
              f"{first if first is None else round(first, 2)} rad/s")  # fmt: skip
        rows = [[f"{w:.2f}", f"{r.growth_rate * 3600:.4g}" if not r.reason else "-",
                 "-" if not math.isfinite(r.spiral_period) else f"{r.spiral_period / 60:.4g}"]
                for w, r in zip(speeds, res, strict=True)]  # fmt: skip
        print(table(["speed (rad/s)", "growth (1/h)", "period (min)"], rows))
    for reason in reasons:  # values missing at some speeds: say why, exit 1 (partial)
        print(f"rubrotor: warning: {reason}", file=sys.stderr)
    return 1 if reasons else 0


def _simulate(scenario, args: argparse.Namespace) -> int:
    from rubrotor.engine.result import save_dataset
    from rubrotor.studies.thermal import ThermalModel, slow_run

    if not args.out:
        raise InputError("--out", None, "a results file F.nc for --simulate")
    if not (math.isfinite(args.simulate) and args.simulate > 0):
        raise InputError("--simulate", args.simulate, "a machine time > 0 (hours)")
    model = ThermalModel(scenario, steps=args.steps)
    ds = slow_run(model, args.simulate * 3600.0, samples=args.samples)
    save_dataset(ds, args.out)
    if args.figure:
        from rubrotor.plotting.thermal import spiral_figure

        save_atomic(spiral_figure(ds), Path(args.figure))
    vec = ds["one_x_real"].values[:, :, 0] + 1j * ds["one_x_imag"].values[:, :, 0]
    summary = {
        "status": ds.attrs["status"],
        "speed_rad_s": model.speed,
        "end_time_s": float(ds["time"].values[-1]),
        "stations_m": [float(x) for x in ds["station"].values],
        "one_x_y_start_m": [float(abs(v)) for v in vec[0]],
        "one_x_y_end_m": [float(abs(v)) for v in vec[-1]],
        "out": str(args.out),
    }
    if args.json:
        print_json(summary)
    else:
        print(f"{scenario.name}: slow run {summary['status']} at "
              f"{summary['end_time_s'] / 3600:.3g} h -> {args.out}")  # fmt: skip
    if summary["status"] != "complete":
        print(f"rubrotor: warning: runaway: a bow reached 50 clearances at t = "
              f"{summary['end_time_s']:.6g} s of {args.simulate * 3600:.6g} s; the run stopped "
              f"there (data kept)", file=sys.stderr)  # fmt: skip
        return 1
    return 0
