"""What every verb module of the command line shares: the :class:`Command` record, JSON and
table printing, speed ranges and atomic figure writing."""

from __future__ import annotations

import argparse
import json
import math
import sys
import threading
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from rubrotor.errors import InputError, RubrotorError

if TYPE_CHECKING:  # annotations only: numpy is imported when a verb runs, not at --help
    import numpy as np

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
    outputs : tuple of str
        Options naming what the verb writes (``"out"``, ``"figure"``; ``"out/"`` for a folder).
        Before the verb runs, each given one is checked writable and locked against other runs
        (:func:`rubrotor.engine.output.claim_output`), so a read-only folder or a target another
        run is writing is refused before any computation.
    """

    name: str
    help: str
    add_arguments: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], int]
    outputs: tuple[str, ...] = ()


def load_scenario(path):
    """:func:`rubrotor.scenario.load.load_scenario`, imported when a verb runs (not at ``--help``)."""
    from rubrotor.scenario.load import load_scenario as load

    return load(path)


def shipped_scenarios():
    """:func:`rubrotor.scenario.load.shipped_scenarios`, imported when called."""
    from rubrotor.scenario.load import shipped_scenarios as shipped

    return shipped()


def print_json(obj) -> None:
    """Print ``obj`` as JSON; a non-finite number in it (never valid JSON, never a result) is
    refused with the path where it sits (:class:`RubrotorError`, exit status 2)."""
    where = _non_finite(obj, "")
    if where is not None:
        raise RubrotorError(f"the result is not finite at {where or 'the top'}: an input is "
                            "beyond the range the computation represents (check the values "
                            "of the scenario's keys and the options)")  # fmt: skip
    print(json.dumps(obj, indent=2))


def _non_finite(obj, path: str):
    """The JSON path of the first non-finite float in ``obj``, or None."""
    if isinstance(obj, float):
        return None if math.isfinite(obj) else path
    if isinstance(obj, dict):
        items = ((f"{path}.{k}" if path else str(k), v) for k, v in obj.items())
    elif isinstance(obj, list | tuple):
        items = ((f"{path}[{i}]", v) for i, v in enumerate(obj))
    else:
        return None
    return next((w for p, v in items if (w := _non_finite(v, p)) is not None), None)


def add_scenario(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scenario", metavar="SCENARIO", help="scenario TOML file")


def table(headers: list[str], rows: list[list[str]]) -> str:
    widths = [
        max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(headers)
    ]
    lines = ["  ".join(h.rjust(w) for h, w in zip(headers, widths, strict=True))]
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows]
    return "\n".join(lines)


def parse_speeds(text: str, field: str = "--speeds") -> np.ndarray:
    """Parse ``START:STOP:COUNT`` into ``COUNT`` evenly spaced spin speeds (rad/s).

    Parameters
    ----------
    text : str
        E.g. ``"0:60000:200"`` (rad/s) or ``"0:12000rpm:61"`` (a unit after a number: rad/s,
        rpm or Hz; see :func:`rubrotor.units.parse_range`).
    field : str
        The option named in an error.

    Returns
    -------
    ndarray, shape (COUNT,)
        Speeds (rad/s).

    Examples
    --------
    >>> parse_speeds("0:100:3")
    array([  0.,  50., 100.])
    """
    from rubrotor.units import parse_range

    return parse_range(text, field)


def save_atomic(fig, out: Path) -> None:
    """Write the figure atomically (see :func:`rubrotor.engine.result.atomic_write`)."""
    from rubrotor.engine.result import atomic_write

    directory = out.parent if str(out.parent) else Path(".")
    if not directory.is_dir():
        raise InputError("--out", str(out), "a file in an existing directory")
    fmt = out.suffix.lstrip(".").lower() or "png"
    atomic_write(out, lambda tmp: fig.savefig(tmp, format=fmt, dpi=150))


COMPILE_NOTICE_AFTER = 3.0
"""Seconds numba may spend compiling before :func:`compile_notice` says so (cache loads are
shorter)."""


@contextmanager
def compile_notice(what: str = "the rub engine", after: float = COMPILE_NOTICE_AFTER):
    """Print one line on stderr when numba compiles for longer than ``after`` seconds inside the
    block ("compiling the rub engine: first run only ..."), at most once.

    numba's ``numba:compile`` events mark each compilation (and each load from its cache,
    which is quick); a timer started at the first outermost event prints the line if that event
    is still running when it fires.
    """
    from numba.core import event as ev

    state = {"said": False, "depth": 0, "timer": None}

    def say():
        if state["depth"] > 0 and not state["said"]:
            state["said"] = True
            print(f"compiling {what}: first run only (the compiled code is cached for the next "
                  "runs)", file=sys.stderr, flush=True)  # fmt: skip

    class Notice(ev.Listener):
        def on_start(self, event):
            state["depth"] += 1
            if state["depth"] == 1 and not state["said"] and state["timer"] is None:
                state["timer"] = threading.Timer(after, say)
                state["timer"].daemon = True
                state["timer"].start()

        def on_end(self, event):
            state["depth"] -= 1
            if state["depth"] == 0 and state["timer"] is not None:
                state["timer"].cancel()
                state["timer"] = None

    listener = Notice()
    ev.register("numba:compile", listener)
    try:
        yield
    finally:
        ev.unregister("numba:compile", listener)
        if state["timer"] is not None:
            state["timer"].cancel()
