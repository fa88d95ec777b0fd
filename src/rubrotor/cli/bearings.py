"""The ``bearings`` verb: each fluid-film support's static position and linearised coefficients
over spin speed (the coefficients every linear verb uses at that speed)."""

from __future__ import annotations

import argparse
import math

from rubrotor.cli.common import add_scenario, load_scenario, parse_speeds, print_json, table
from rubrotor.cli.response import figure_path, write_figure


def bearings_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument("--speeds", metavar="START:STOP:COUNT",
                        help="spin speeds (rad/s, or with a unit: rpm, Hz); default the "
                             "scenario's speed alone")  # fmt: skip
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument("--figure", metavar="FILE.png",
                        help="also write the eccentricity locus and the coefficients against "
                             "speed (.png/.pdf/.svg)")  # fmt: skip


def bearings_run(args: argparse.Namespace) -> int:
    from rubrotor.linear.front import bearings

    out = figure_path(args.figure)
    scenario = load_scenario(args.scenario)
    speeds = parse_speeds(args.speeds) if args.speeds else [scenario.speed]
    res = bearings(scenario, speeds)
    if args.json:
        print_json(res.to_dict())
    else:
        print(f"{scenario.name}: fluid films at their static equilibrium (gravity and loads)")
        rows = [[r.name, f"{r.speed_rad_s:.6g}", f"{r.eccentricity_ratio:.5f}",
                 f"{math.degrees(r.attitude_angle_rad):.3f}",
                 *(f"{v:.5g}" for v in (*r.K0.ravel(), *r.C0.ravel()))] for r in res.rows]  # fmt: skip
        print(table(["bearing", "speed (rad/s)", "eps (1)", "attitude (deg)", "kyy (N/m)",
                     "kyz (N/m)", "kzy (N/m)", "kzz (N/m)", "cyy (N s/m)", "cyz (N s/m)",
                     "czy (N s/m)", "czz (N s/m)"], rows))  # fmt: skip
    if out is not None:
        from rubrotor.plotting.bearings import bearings_figure

        write_figure(bearings_figure(res, f"fluid films: {scenario.name}"), out, args.json)
    return 0
