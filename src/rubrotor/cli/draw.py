"""The ``draw`` verb: the rotor's geometry (sections, disks, bearings, contacts) as a figure."""

from __future__ import annotations

import argparse

from rubrotor.cli.common import add_scenario, load_scenario, save_atomic
from rubrotor.cli.response import figure_path


def draw_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument("--out", default="rotor.png", metavar="FILE.png",
                        help="figure file (.png/.pdf/.svg); default rotor.png")  # fmt: skip
    parser.add_argument("--no-nodes", action="store_true",
                        help="leave out the finite-element nodes (ticks on the axis)")  # fmt: skip


def draw_run(args: argparse.Namespace) -> int:
    from rubrotor.plotting.geometry import draw_rotor

    out = figure_path(args.out, "--out")
    scenario = load_scenario(args.scenario)
    save_atomic(draw_rotor(scenario, nodes=not args.no_nodes), out)
    print(f"wrote {out}")
    return 0
