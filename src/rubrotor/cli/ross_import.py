"""``rubrotor import-ross ROTOR_FILE --out scenario.toml``: a ROSS rotor file as a scenario.

The file is what ROSS's ``Rotor.save`` wrote (``.toml`` or ``.json``, ROSS 2.x or 3.x); it is
read without ROSS (:func:`rubrotor.rotors.ross_model.read_ross_file`) and written as a scenario
every verb runs on (:mod:`rubrotor.scenario.ross` says how each element maps).
"""

from __future__ import annotations

import argparse
import math

from rubrotor.cli.common import print_json

__all__ = ["import_ross_args", "import_ross_run"]


def import_ross_args(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "rotor_file",
        metavar="ROTOR_FILE",
        help="rotor file written by ROSS's Rotor.save (.toml or .json)",
    )
    p.add_argument("--out", required=True, help="scenario TOML file to write")
    speed = p.add_mutually_exclusive_group()
    speed.add_argument(
        "--speed",
        type=float,
        default=0.0,
        help="spin speed of the scenario's [speed] table (rad/s; default 0)",
    )
    speed.add_argument("--rpm", type=float, help="spin speed (rev/min) instead of --speed")
    p.add_argument("--name", help="[meta] name (default: the file's stem)")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")  # fmt: skip


def import_ross_run(args: argparse.Namespace) -> int:
    from rubrotor.scenario.load import Scenario

    speed = args.speed if args.rpm is None else args.rpm * 2 * math.pi / 60
    sc = Scenario.from_ross(args.rotor_file, speed=speed, name=args.name)
    path = sc.save(args.out, header=f"Imported by rubrotor import-ross from {args.rotor_file}")
    rotor = sc.rotor
    summary = {
        "scenario": str(path),
        "nodes": int(len(rotor.nodes())),
        "sections": len(rotor.shaft_sections),
        "sleeves": len(rotor.sleeves),
        "disks": len(rotor.disks),
        "bearings": len(rotor.bearings),
        "point_masses": len(rotor.point_masses),
        "speed_rad_per_s": sc.speed,
    }
    if args.json:
        print_json(summary)
    else:
        print(
            f"wrote {path}: {summary['nodes']} nodes, {summary['sections']} sections "
            f"({summary['sleeves']} sleeves), {summary['disks']} disks, "
            f"{summary['bearings']} bearings/seals, {summary['point_masses']} point masses"
        )
    return 0
