"""Command-line interface: ``rubrotor VERB SCENARIO [options]``: the verb table and ``main``.

Each verb is a :class:`~rubrotor.cli.common.Command`: a name, a help line, a function adding its
arguments to an :mod:`argparse` subparser and a function running it (``run(args) -> int``). The
verbs live in one module per group (:mod:`rubrotor.cli.linear`, :mod:`rubrotor.cli.simulate`,
:mod:`rubrotor.cli.sweeps`, :mod:`rubrotor.cli.analyze`, :mod:`rubrotor.cli.orbits`,
:mod:`rubrotor.cli.studies`, :mod:`rubrotor.cli.thermal`, :mod:`rubrotor.cli.draw`); to add one, write its two functions
in its group's module and add a row to :data:`COMMANDS`, the one table.

Errors the user can cause (:class:`rubrotor.errors.RubrotorError`, including scenario errors)
print ``rubrotor: error: <message>`` on stderr and give exit status 2, with no traceback.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import warnings

from rubrotor._version import __version__
from rubrotor.cli import (
    analyze,
    api,
    bearings,
    draw,
    linear,
    orbits,
    response,
    risk,
    ross_import,
    simulate,
    studies,
    sweeps,
    thermal,
)
from rubrotor.cli.analyze import load_signals
from rubrotor.cli.common import Command, parse_speeds, shipped_scenarios
from rubrotor.cli.simulate import run_summary
from rubrotor.engine.output import claim_output
from rubrotor.errors import InputError, RubrotorError

__all__ = [
    "main",
    "Command",
    "COMMANDS",
    "parse_speeds",
    "load_signals",
    "run_summary",
    "shipped_scenarios",
]

COMMANDS: list[Command] = [
    Command(
        "modes",
        "whirl frequencies of every mode at one spin speed",
        linear.modes_args,
        linear.modes_run,
    ),
    Command(
        "critical",
        "forward and backward critical speeds",
        linear.critical_args,
        linear.critical_run,
    ),
    Command(
        "campbell",
        "Campbell diagram (figure, optionally JSON)",
        linear.campbell_args,
        linear.campbell_run,
        outputs=("out",),
    ),
    Command(
        "stability",
        "eigenvalues of the rotor pressed into the stator (linearised contact)",
        linear.stability_args,
        linear.stability_run,
    ),
    Command(
        "static",
        "static deflection under gravity and loads, and the bearing reactions",
        response.static_args,
        response.static_run,
        outputs=("figure",),
    ),
    Command(
        "bearings",
        "fluid-film bearings at each speed: static eccentricity and linearised coefficients",
        bearings.bearings_args,
        bearings.bearings_run,
        outputs=("figure",),
    ),
    Command(
        "response",
        "frequency response to a fixed or rotating force at a station (Bode, polar)",
        response.response_args,
        response.response_run,
        outputs=("figure",),
    ),
    Command(
        "unbalance",
        "unbalance response of every unbalance plane at probes, over spin speed",
        response.unbalance_args,
        response.unbalance_run,
        outputs=("figure",),
    ),
    Command(
        "ucs",
        "undamped critical speed map: critical speeds against support stiffness",
        response.ucs_args,
        response.ucs_run,
        outputs=("figure",),
    ),
    Command(
        "shapes",
        "mode shapes along the rotor: whirl orbits, forward and backward",
        response.shapes_args,
        response.shapes_run,
        outputs=("figure",),
    ),
    Command(
        "draw",
        "the rotor's geometry: sections, disks, bearings, contacts (figure)",
        draw.draw_args,
        draw.draw_run,
        outputs=("out",),
    ),
    Command(
        "clearance",
        "API 617 close-clearance check of the unbalance response at every contact",
        api.clearance_args,
        api.clearance_run,
        outputs=("figure",),
    ),
    Command(
        "level1",
        "API 684 Level I stability: log dec against added cross-coupled stiffness",
        api.level1_args,
        api.level1_run,
        outputs=("figure",),
    ),
    Command(
        "run",
        "simulate a scenario: DIR/results.nc and a JSON summary",
        simulate.run_args,
        simulate.run_run,
        outputs=("out/",),
    ),
    Command(
        "simulate",
        "simulate any scenario (seed or general rotor) into one results file",
        simulate.simulate_args,
        simulate.simulate_run,
        outputs=("out",),
    ),
    Command(
        "converge",
        "the seed's step and mode convergence table",
        simulate.converge_args,
        simulate.converge_run,
    ),
    Command(
        "sweep",
        "parameter sweep: Poincare samples, rub metrics and regimes in a zarr store",
        sweeps.sweep_args,
        sweeps.sweep_run,
        outputs=("out", "figure"),
    ),
    Command(
        "risk",
        "probability of rub against speed when scenario keys scatter, with Sobol' indices",
        risk.risk_args,
        risk.risk_run,
        outputs=("out/",),
    ),
    Command(
        "continue",
        "pseudo-arclength continuation of a periodic orbit: branch, stability, bifurcations",
        orbits.continue_args,
        orbits.continue_run,
        outputs=("out", "figure"),
    ),
    Command(
        "thermal",
        "thermal bow (Newkirk spiral): growth rate and period against speed, slow-time runs",
        thermal.thermal_args,
        thermal.thermal_run,
        outputs=("out", "figure"),
    ),
    Command(
        "analyze",
        "rub indicators and CWT/spectrum figure of a results or signal file",
        analyze.analyze_args,
        analyze.analyze_run,
        outputs=("out/",),
    ),
    Command(
        "import-ross",
        "turn a rotor file saved by ROSS (Rotor.save) into a scenario every verb runs on",
        ross_import.import_ross_args,
        ross_import.import_ross_run,
        outputs=("out",),
    ),
    Command(
        "scenarios",
        "list the shipped scenario files",
        studies.scenarios_args,
        studies.scenarios_run,
    ),
    Command(
        "reproduce",
        "reproduce the seed study: figures, report.html, summary.json",
        studies.reproduce_args,
        studies.reproduce_run,
        outputs=("out/",),
    ),
]
"""The verbs, in the order ``rubrotor --help`` lists them (the one table)."""


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="rubrotor",
        description="Rotor-stator rub on real rotors: modes, critical speeds, rub simulation, "
        "periodic orbits, sweeps and rub analysis.",
    )
    parser.add_argument("--version", action="version", version=f"rubrotor {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for cmd in COMMANDS:
        p = sub.add_parser(cmd.name, help=cmd.help, description=cmd.help)
        cmd.add_arguments(p)
        p.set_defaults(_command=cmd)
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
        with warnings.catch_warnings():  # "rubrotor: warning: ..." once each, no source line
            warnings.showwarning = _show_warning({})
            return _run(args._command, args)
    except RubrotorError as exc:
        print(f"rubrotor: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. output piped into `head` (before OSError, its base class)
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
    except (OSError, RuntimeError) as exc:  # a full disk (a streamed file is kept, partial)
        why = _disk_full(exc, args)
        if why is None:
            raise
        print(f"rubrotor: error: {why}", file=sys.stderr)
        return 1
    except MemoryError as exc:  # an allocation the size checks did not foresee
        print(f"rubrotor: error: out of memory ({exc or 'an allocation failed'}): the rotor's "
              "mesh or the run is too large for this machine", file=sys.stderr)
        return 1


def _show_warning(seen: dict):
    """A ``warnings.showwarning`` printing ``rubrotor: warning: MESSAGE`` on stderr, once per
    message."""

    def show(message, category, filename, lineno, file=None, line=None):
        text = str(message)
        if text not in seen:
            seen[text] = True
            print(f"rubrotor: warning: {text}", file=sys.stderr)

    return show


def _disk_full(exc: BaseException, args: argparse.Namespace) -> str | None:
    """The message of a write that failed for want of disk space, or None for another error.

    ``ENOSPC``/``EDQUOT`` say so themselves; netCDF reports a full disk as ``NetCDF: HDF
    error``, taken as one when a disk the verb writes to has less than 16 MiB free.
    """
    import errno
    import shutil
    from pathlib import Path

    if isinstance(exc, BrokenPipeError):
        return None
    if isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, errno.EDQUOT):
        text = exc.strerror or str(exc)
        return text if text.startswith("no space left") else f"no space left on device: {exc}"
    if not isinstance(exc, RuntimeError) or "HDF error" not in str(exc):
        return None
    for spec in getattr(args._command, "outputs", ()):
        value = getattr(args, spec.rstrip("/"), None)
        if value is None:
            continue
        folder = Path(value) if spec.endswith("/") else Path(value).parent
        folder = folder if str(folder) else Path(".")
        free = shutil.disk_usage(folder if folder.exists() else Path(".")).free
        if free < 16 * 2**20:
            return (f"no space left on device at {folder} ({free / 2**20:.3g} MiB free) "
                    f"while writing {value} ({exc}); nothing was kept of what did not fit")
    return None


def _run(cmd: Command, args: argparse.Namespace) -> int:
    """Claim the verb's outputs (writable, not being written by another run), then run it."""
    with contextlib.ExitStack() as stack:
        for spec in cmd.outputs:
            name = spec.rstrip("/")
            value = getattr(args, name, None)
            if value is not None:
                field = f"--{name}"
                try:  # netCDF, HDF5 and zarr name files in UTF-8
                    str(value).encode("utf-8")
                except UnicodeEncodeError:
                    raise InputError(field, value, "a file name that is valid UTF-8 (this one "
                                     "holds bytes that are not text)") from None  # fmt: skip
                stack.enter_context(claim_output(value, field, folder=spec.endswith("/")))
        return cmd.run(args)
