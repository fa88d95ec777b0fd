"""No scenario, however mangled, ends in a traceback.

Property-based: hypothesis takes a shipped scenario, applies one mutation a new user could make
(a key removed, an unknown key added, a value of the wrong type, zero, negative, nan, inf,
1e300) and runs it through the command line in-process. Every run must end with exit status 0,
1 (a partial run) or 2 (an input error, one line on stderr), never an exception.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rubrotor
from rubrotor.cli import main

SCENARIOS = sorted((Path(rubrotor.__file__).parent / "scenarios").glob("*.toml"))
BAD_VALUES = [0, -1.5, math.nan, math.inf, -math.inf, 1e300, -1e300, 1e-300, "x", True, [1, 2], {}]


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def _dump(doc: dict) -> str:
    """TOML text of a scenario dict (top-level tables, arrays of tables, one level of nesting)."""
    lines = []
    for name, body in doc.items():
        if isinstance(body, list) and body and all(isinstance(t, dict) for t in body):
            for t in body:
                lines.append(f"[[{name}]]")
                lines += [f"{k} = {_toml_value(v)}" for k, v in t.items()]
        elif isinstance(body, dict) and body and all(isinstance(t, dict) for t in body.values()):
            for sub, t in body.items():
                lines.append(f"[{name}.{sub}]")
                lines += [f"{k} = {_toml_value(v)}" for k, v in t.items()]
        elif isinstance(body, dict):
            lines.append(f"[{name}]")
            lines += [f"{k} = {_toml_value(v)}" for k, v in body.items()]
        else:
            lines.insert(0, f"{name} = {_toml_value(body)}")
    return "\n".join(lines) + "\n"


def _leaves(doc: dict):
    """Paths ``(table, index or sub-table or None, key)`` of every scalar or list value."""
    for name, body in doc.items():
        if isinstance(body, list) and body and all(isinstance(t, dict) for t in body):
            for i, t in enumerate(body):
                yield from ((name, i, k) for k in t)
        elif isinstance(body, dict):
            for k, v in body.items():
                if isinstance(v, dict):
                    yield from ((name, k, kk) for kk in v)
                else:
                    yield (name, None, k)


def _table(doc: dict, path):
    name, sub, _ = path
    return doc[name] if sub is None else doc[name][sub]


@st.composite
def mangled(draw):
    path = draw(st.sampled_from(SCENARIOS))
    doc = tomllib.loads(path.read_text())
    leaves = sorted(_leaves(doc), key=str)
    leaf = draw(st.sampled_from(leaves))
    kind = draw(st.sampled_from(["remove", "unknown", "value"]))
    table = _table(doc, leaf)
    if kind == "remove":
        del table[leaf[2]]
    elif kind == "unknown":
        table["not_a_key"] = 1.0
    else:
        table[leaf[2]] = draw(st.sampled_from(BAD_VALUES))
    command = draw(st.sampled_from(["modes", "critical", "run"]))
    return path.stem, _dump(doc), command


@settings(
    max_examples=300,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(case=mangled())
def test_mangled_scenario_never_raises(case, tmp_path, capsys):
    name, text, command = case
    f = tmp_path / f"{name}.toml"
    f.write_text(text)
    argv = [command, str(f)]
    if command == "run":
        argv += ["--out", str(tmp_path / "out"), "--revolutions", "2", "--no-progress"]
    status = main(argv)
    err = capsys.readouterr().err
    assert status in (0, 1, 2), (status, err)
    if status == 2:
        lines = [ln for ln in err.splitlines() if ln.strip()]
        assert len(lines) == 1 and lines[0].startswith("rubrotor: error:"), err


@pytest.mark.parametrize("value", [1e300, 1e-300])
def test_absurd_diameter_is_named(value, tmp_path, capsys):
    """``diameter = 1e300`` (once an OverflowError traceback) is refused naming the key."""
    src = Path(rubrotor.__file__).parent / "scenarios" / "seed_rotor.toml"
    doc = tomllib.loads(src.read_text())
    doc["shaft"]["diameter"] = value
    f = tmp_path / "big.toml"
    f.write_text(_dump(doc))
    assert main(["modes", str(f)]) == 2
    assert "shaft.diameter" in capsys.readouterr().err


def test_run_too_large_for_memory_is_refused(tmp_path, capsys):
    """``revolutions = 1e12`` (once a MemoryError traceback) is refused before it starts."""
    src = Path(rubrotor.__file__).parent / "scenarios" / "seed_case1.toml"
    doc = tomllib.loads(src.read_text())
    doc["simulation"]["revolutions"] = 1e12
    f = tmp_path / "huge.toml"
    f.write_text(_dump(doc))
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "simulation.revolutions" in err and "GiB" in err and "save_every" in err
