"""Every verb on every shipped scenario, mangled as a user could (issue 32).

One mutation of a shipped scenario (a key removed, a value scaled by 1e-12 .. 1e12 or negated,
or set to 0, nan, inf, +-1e300, 1e-300; free-speed, thermal and general-rotor files included)
runs through one verb in-process with short settings. The promise checked on every run:

* exit 0 with finite output (no NaN/inf in the JSON printed, nor in a results file it wrote);
* exit 2 with exactly one line ``rubrotor: error: ...`` on stderr;
* exit 1 (a partial run) with a reason on stderr;
* never a traceback (an exception out of ``main``), never a hang past ``HANG_S`` (an alarm).

CI runs the fixed examples (:data:`FIXED`, the findings of the issue among them) and a few
random ones; ``RUBROTOR_FUZZ=N`` runs ``N`` random examples with a fixed seed and prints the
counts of each outcome (the longer run of the issue's closing note).
"""

from __future__ import annotations

import json
import math
import os
import random
import signal
import tomllib
import warnings
from collections import Counter
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from test_mangled_scenarios import _dump, _leaves, _table

from rubrotor.cli import main

SCENARIOS = sorted(Path(str(resources.files("rubrotor") / "scenarios")).glob("*.toml"))
FACTORS = [1e-12, 1e-6, 1e6, 1e12, -1.0]
VALUES = [0, math.nan, math.inf, 1e300, -1e300, 1e-300]
HANG_S = 300
"""A run longer than this (s) is a hang (the alarm fails it)."""


def _short(doc: dict) -> None:
    """Short runs: one revolution, or at most 0.02 s (a free-speed file: 0.01 s)."""
    sim = doc.setdefault("simulation", {})
    if "duration" in sim:
        sim["duration"] = min(float(sim["duration"]), 0.02)
    else:
        sim["revolutions"] = 1


def _argv(verb: str, scen: Path, tmp: Path, doc: dict) -> list[str]:
    """The verb's command line with short settings (outputs into ``tmp``)."""
    s, out = str(scen), str(tmp / "o.nc")
    contacts = doc.get("contact", [])
    contacts = contacts if isinstance(contacts, list) else [contacts]
    at = next((c.get("position") for c in contacts if isinstance(c, dict)), None)
    at = str(at) if isinstance(at, int | float) and math.isfinite(at) else "0.1"
    return {
        "modes": ["modes", s, "--json"],
        "critical": ["critical", s, "--json"],
        "static": ["static", s, "--json"],
        "shapes": ["shapes", s, "--json"],
        "ucs": ["ucs", s, "--json", "--stiffness", "1e6:1e9:3"],
        "unbalance": ["unbalance", s, "--json", "--speeds", "10:600:4", "--probe", at],
        "clearance": ["clearance", s, "--json", "--speeds", "50:700:8"],
        "level1": ["level1", s, "--json", "--stiffness", "1e4:1e8:3"],
        "campbell": ["campbell", s, "--json", "--speeds", "0:600:4", "--out", str(tmp / "c.png")],
        "simulate": ["simulate", s, "--out", out, "--no-progress"],
        "thermal": ["thermal", s, "--json", "--speeds", "200:300:2", "--steps", "32"],
        "continue": ["continue", s, "--vary", "speed.rad_per_s=300:303", "--points", "3",
                     "--steps", "64", "--out", str(tmp / "b.nc"), "--json"],
    }[verb]  # fmt: skip


VERBS = ["modes", "critical", "static", "shapes", "ucs", "unbalance", "clearance", "level1",
         "campbell", "simulate", "simulate", "thermal", "continue"]  # fmt: skip


def _mutate(doc: dict, leaf, how) -> str:
    """Apply ``how`` to ``leaf`` of ``doc`` in place; the key it names (``table.key``)."""
    table = _table(doc, leaf)
    value = table[leaf[2]]
    if how == "remove":
        del table[leaf[2]]
    else:
        kind, x = how
        if kind == "set" or isinstance(value, bool) or not isinstance(value, int | float | list):
            table[leaf[2]] = x * 1.0 if kind != "set" else x
        elif isinstance(value, list):
            table[leaf[2]] = [v * x if isinstance(v, int | float) else v for v in value]
        else:
            table[leaf[2]] = value * x
    return f"{leaf[0]}.{leaf[2]}" if leaf[0] else str(leaf[2])


def _no_nan(text: str) -> bool:
    return not any(w in text for w in ("NaN", "Infinity"))


def _finite_file(path: Path) -> bool:
    if not path.exists():
        return True
    with xr.open_dataset(path) as ds:
        if ds.attrs.get("status", "complete") != "complete":
            return True
        return all(np.all(np.isfinite(ds[v].values)) for v in ds.data_vars
                   if np.issubdtype(ds[v].dtype, np.floating))  # fmt: skip


def _hang(signum, frame):
    raise TimeoutError(f"no answer within {HANG_S} s")


def run_case(name: str, verb: str, leaf, how, tmp: Path, capsys) -> str:
    """Run one case; its outcome (``"ok"``, ``"refused"``, ``"partial"``, ``"named"`` counted
    among the refusals that name the mutated key), or an AssertionError."""
    doc = tomllib.loads((Path(str(resources.files("rubrotor") / "scenarios")) / f"{name}.toml")
                        .read_text())  # fmt: skip
    _short(doc)
    key = _mutate(doc, leaf, how) if leaf is not None else ""
    scen = tmp / f"{name}.toml"
    scen.write_text(_dump(doc))
    argv = _argv(verb, scen, tmp, doc)
    old = signal.signal(signal.SIGALRM, _hang)
    signal.alarm(HANG_S)
    try:
        with warnings.catch_warnings():  # a warning is printed to the user, not a traceback
            warnings.simplefilter("ignore")
            code = main(argv)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    io = capsys.readouterr()
    case = f"{name} {verb} {key} {how}: exit {code}\n{io.err}"
    lines = [ln for ln in io.err.splitlines() if ln.strip() and not ln.startswith("\r")]
    if code == 0:
        assert _no_nan(io.out), case
        for out in (tmp / "o.nc", tmp / "b.nc"):
            assert _finite_file(out), case
        return "ok"
    if code == 2:
        assert len(lines) == 1 and lines[0].startswith("rubrotor: error:"), case
        leafname = key.rsplit(".", 1)[-1]
        return "named" if leafname and leafname in lines[0] else "refused"
    assert code == 1, case
    assert any("warning" in ln or "error" in ln for ln in lines), case
    return "partial"


# Fixed examples: the findings and one plain run of each verb family.
FIXED = [
    ("touchdown_drop", "simulate", ("contact", 0, "friction"), ("set", 1e300)),
    ("touchdown_drop", "simulate", ("speed", None, "drag"), ("set", 1e9)),
    ("touchdown_drop", "simulate", ("simulation", None, "sample_rate"), ("set", 1e300)),
    ("touchdown_drop", "simulate", ("unbalance", None, "magnitude"), ("set", 1e300)),
    ("seal_rub", "unbalance", ("unbalance", 0, "magnitude"), ("set", 1e300)),
    ("seal_rub", "level1", None, None),
    ("seal_rub", "modes", ("materials", "steel", "density"), ("scale", 1e-12)),
    ("thermal_rub", "thermal", ("contact", 0, "stiffness"), ("set", 1e7)),
    ("seal_rub", "static", ("gravity", None, "y"), ("set", math.nan)),
    ("seed_case1", "critical", None, None),
    ("runup_rub", "simulate", ("speed", None, "to"), ("set", -1e300)),
    # found by the 250-case run: the start run of a continuation failed (AttributeError)
    ("one_mode_chaotic_rub", "continue", ("unbalance", None, "magnitude"), ("set", 0)),
]


def _leaf(doc: dict, table: str, index, key: str):
    """The ``_leaves`` entry of ``table[index].key`` (the mutation helpers' address)."""
    for leaf in _leaves(doc):
        if leaf[0] == table and leaf[2] == key and (index is None or leaf[1] == index):
            return leaf
    return None


@pytest.mark.parametrize("name, verb, where, how", FIXED,
                         ids=[f"{f[0]}-{f[1]}-{f[2][2] if f[2] else 'plain'}" for f in FIXED])  # fmt: skip
def test_fixed_examples(name, verb, where, how, tmp_path, capsys):
    leaf = None
    if where is not None:
        doc = tomllib.loads((Path(str(resources.files("rubrotor") / "scenarios")) /
                             f"{name}.toml").read_text())  # fmt: skip
        leaf = _leaf(doc, *where)
        if leaf is None:
            pytest.skip(f"{name} has no {where}")
    outcome = run_case(name, verb, leaf, how, tmp_path, capsys)
    if name == "touchdown_drop" or verb == "unbalance":
        assert outcome == "named", outcome  # the findings name their key


def random_cases(n: int, seed: int = 32):
    """``n`` random (scenario, verb, leaf, mutation) cases, reproducible from ``seed``."""
    rng = random.Random(seed)
    for _ in range(n):
        path = rng.choice(SCENARIOS)
        doc = tomllib.loads(path.read_text())
        leaf = rng.choice(sorted(_leaves(doc), key=str))
        kind = rng.choice(["remove", "scale", "set"])
        how = "remove" if kind == "remove" else (
            (kind, rng.choice(FACTORS if kind == "scale" else VALUES)))  # fmt: skip
        yield path.stem, rng.choice(VERBS), leaf, how


CI_RANDOM = 4
"""Random examples in CI (``RUBROTOR_FUZZ`` overrides)."""


def test_random_examples(tmp_path_factory, capsys):
    n = int(os.environ.get("RUBROTOR_FUZZ", CI_RANDOM))
    counts, failures = Counter(), []
    for i, (name, verb, leaf, how) in enumerate(random_cases(n)):
        tmp = tmp_path_factory.mktemp(f"fuzz{i}")
        try:
            outcome = run_case(name, verb, leaf, how, tmp, capsys)
        except AssertionError as exc:
            outcome = "FAILED"
            failures.append(str(exc)[:600])
        except Exception as exc:  # a traceback out of main, or the hang alarm
            outcome = "FAILED"
            failures.append(f"{name} {verb} {leaf} {how}: {exc!r}"[:600])
        counts[outcome] += 1
        counts[f"verb:{verb}"] += 1
        if n > CI_RANDOM:
            with capsys.disabled():
                print(f"fuzz case {i}: {name} {verb} {leaf} {how} -> {outcome}", flush=True)
    report = json.dumps({"cases": n, **dict(sorted(counts.items()))}, indent=1)
    with capsys.disabled():
        print(f"\nfuzz counts: {report}")
        for f in failures:
            print("FAILED:", f)
    assert not failures, failures[0]
