"""``risk``: the probability of rub against speed when scenario keys scatter."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from rubrotor.cli.common import add_scenario, load_scenario, parse_speeds, print_json, save_atomic
from rubrotor.errors import InputError

__all__ = ["risk_args", "risk_run"]


def risk_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument("--samples", type=int, required=True, metavar="N", help="samples (>= 1)")
    parser.add_argument(
        "--vary", action="append", required=True, metavar="KEY=DIST",
        help="scenario key and its distribution: normal(mean,sd), truncnormal(mean,sd,lo,hi), "
        "uniform(lo,hi), lognormal(mu,sigma), in the key's SI unit; KEY as in sweeps, "
        "section[i].key for the i-th [[section]] table (from 1); repeat for several keys",
    )  # fmt: skip
    parser.add_argument("--speeds", metavar="A:B:N", help="spin speeds (rad/s; default the "
                        "scenario's speed), e.g. 100:1500:100 or 1000rpm:9000rpm:50")  # fmt: skip
    parser.add_argument("--method", choices=("linear", "time"), default="linear",
                        help="linear: 1X orbit + static deflection against the clearance; "
                        "time: a simulation per sample and speed")  # fmt: skip
    parser.add_argument("--seed", type=int, default=0, help="seed of the samples (0)")
    parser.add_argument("--sampler", choices=("sobol", "lhs", "random"), default="sobol",
                        help="scrambled Sobol' (default), Latin hypercube or pseudo-random")  # fmt: skip
    parser.add_argument("--sobol", action="store_true",
                        help="also Sobol' indices of each key (linear; N (d + 2) evaluations)")  # fmt: skip
    parser.add_argument("--confidence", type=float, default=0.95, help="interval level (0.95)")
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="folder: samples.zarr (resumed), risk.json, risk.png, sobol.png")  # fmt: skip
    parser.add_argument("--scheduler", metavar="ADDRESS|local",
                        help="time method on a Dask scheduler, or 'local' (a LocalCluster)")  # fmt: skip
    parser.add_argument("--workers", type=int, help="time method: worker processes (1)")
    parser.add_argument("--chunk-size", type=int, help="samples per chunk")
    parser.add_argument("--revolutions", type=int, help="time method: revolutions per run")
    parser.add_argument("--transient", type=int, default=20, help="time method: discarded (20)")
    parser.add_argument("--near", type=float, metavar="FRACTION",
                        help="time method: simulate only samples whose linear margin is within "
                        "FRACTION x the nominal clearance of the boundary")  # fmt: skip
    parser.add_argument("--no-figure", action="store_true", help="skip the figures")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                        help="show progress (default: when stderr is a terminal)")  # fmt: skip


def _vary(texts: list[str]) -> dict:
    from rubrotor.sweeps.risk_inputs import parse_risk_vary

    vary = {}
    for text in texts:
        key, dist = parse_risk_vary(text)
        if key in vary:
            raise InputError(key, text, "each --vary key once")
        vary[key] = dist
    return vary


def risk_run(args: argparse.Namespace) -> int:
    from rubrotor.engine.result import atomic_write
    from rubrotor.sweeps.risk import risk

    vary = _vary(args.vary)
    speeds = None if args.speeds is None else parse_speeds(args.speeds)
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError("--out", args.out, "a folder (created if missing)")
    out.mkdir(parents=True, exist_ok=True)
    progress = sys.stderr.isatty() if args.progress is None else args.progress
    try:
        res = risk(load_scenario(args.scenario), vary, samples=args.samples, speeds=speeds,
                   method=args.method, seed=args.seed, sampler=args.sampler, sobol=args.sobol,
                   confidence=args.confidence, store=out / "samples.zarr",
                   chunk_size=args.chunk_size, progress=progress, scheduler=args.scheduler,
                   workers=args.workers, revolutions=args.revolutions,
                   transient_revolutions=args.transient, near=args.near)  # fmt: skip
    except InputError as exc:  # the library's argument names: the options that set them
        if exc.field in ("samples", "seed", "speeds", "chunk_size", "scheduler", "workers",
                         "confidence", "sobol", "revolutions", "near"):  # fmt: skip
            raise InputError(f"--{exc.field.replace('_', '-')}", exc.value, exc.allowed) from None
        raise
    except KeyboardInterrupt:
        print(f"rubrotor: interrupted; {out / 'samples.zarr'} holds every finished chunk: run the "
              "same command again to resume", file=sys.stderr)  # fmt: skip
        return 130
    data = res.to_dict()
    atomic_write(out / "risk.json", lambda tmp: Path(tmp).write_text(json.dumps(data, indent=2)))
    if not args.no_figure:
        from rubrotor.plotting.risk import risk_figure, sobol_figure

        save_atomic(risk_figure(res), out / "risk.png")
        if res.sobol is not None:
            save_atomic(sobol_figure(res), out / "sobol.png")
    if args.json:
        print_json(data)
    else:
        _print_table(res)
    return 0


def _print_table(res) -> None:
    from rubrotor.cli.common import table

    rows = [[f"{w:.6g}", str(int(k)), f"{p:.4f}", f"[{lo:.4f}, {hi:.4f}]"]
            for w, k, p, lo, hi in zip(res.speeds, res.rubs, res.probability, res.lower,
                                       res.upper, strict=True)]  # fmt: skip
    print(table(["speed (rad/s)", "rubs", "P(rub)", f"{100 * res.confidence:g} % interval"], rows))
    print(f"samples {res.samples}, rub at some speed {res.rub_anywhere:.4f}")
    if res.sobol is not None:
        for k, v in res.sobol["rub"].items():
            print(f"Sobol' (rub at some speed) {k}: first {v['first']}, total {v['total']}")
