"""``scenarios`` (the shipped scenario files) and ``reproduce`` (the seed study)."""

from __future__ import annotations

import argparse
from pathlib import Path

from rubrotor.cli.common import (
    print_json,
    shipped_scenarios,
    table,
)
from rubrotor.errors import InputError


def scenarios_args(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")


def scenarios_run(args: argparse.Namespace) -> int:
    items = shipped_scenarios()
    if args.json:
        print_json({"scenarios": items})
        return 0
    width = max(len(i["name"]) for i in items)
    for i in items:
        print(f"{i['name'].ljust(width)}  {i['description']}")
    return 0


def reproduce_args(parser: argparse.ArgumentParser) -> None:
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


def reproduce_run(args: argparse.Namespace) -> int:
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
        table(
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
