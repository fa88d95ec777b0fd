"""The command-line reference page, generated from the verb table when the site is built.

Every verb of :data:`rubrotor.cli.app.COMMANDS` gets a section with its help line and the
``--help`` text argparse prints for it, so the page cannot drift from the command line.
"""

from __future__ import annotations

import argparse
import os


def markdown() -> str:
    """MyST markdown: one section per verb, in the order ``rubrotor --help`` lists them."""
    from rubrotor.cli.app import COMMANDS, _parser

    os.environ.setdefault("COLUMNS", "90")  # argparse wraps at the terminal width: fix it
    parser = _parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    out = [
        "# Command line",
        "",
        "`rubrotor VERB SCENARIO [options]`: every verb reads a scenario file (a shipped one is",
        "found by name from any folder: `rubrotor scenarios` lists them). An input error prints",
        "`rubrotor: error: <field> = <value> is not allowed: <what is allowed>` and exits with",
        "status 2; a completed run exits 0, a run stopped partial 1. This page is generated from",
        "the verb table (`rubrotor.cli.app.COMMANDS`) when the site is built.",
        "",
        "| verb | what it does |",
        "|---|---|",
    ]
    out += [f"| [`{c.name}`](#rubrotor-{c.name}) | {c.help} |" for c in COMMANDS]
    out.append("")
    for c in COMMANDS:
        text = sub.choices[c.name].format_help().rstrip()
        out += [
            f"(rubrotor-{c.name})=",
            f"## `rubrotor {c.name}`",
            "",
            c.help[0].upper() + c.help[1:] + ".",
            "",
            "```text",
            text,
            "```",
            "",
        ]
    return "\n".join(out)
