"""The command line's own cost: each verb imports what it needs and nothing more.

A warm ``rubrotor modes general_rotor.toml`` spent most of its 1.4 s importing numba, SciPy's
optimizers and (through the verb table) the scenario loader before it solved anything
(``python -X importtime``). These tests run the command in a fresh interpreter and check which
heavy packages it loaded, the cause of the cost rather than a wall-clock time (the times are in
``benchmarks/bench_cli_vs_ross.py``).
"""

import json
import subprocess
import sys
from pathlib import Path

import pytest

import rubrotor

SCENARIOS = Path(rubrotor.__file__).parent / "scenarios"
HEAVY = ("numpy", "scipy", "scipy.optimize", "numba", "xarray", "matplotlib", "dask")


def _loaded_after(argv: list[str]) -> dict:
    """Run ``rubrotor.cli.main(argv)`` in a fresh interpreter; its exit status and which of
    :data:`HEAVY` it imported."""
    code = (
        "import json, sys, contextlib, io\n"
        "from rubrotor.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    try:\n        status = main({argv!r})\n"
        "    except SystemExit as exc:\n        status = exc.code\n"
        f"print(json.dumps({{'status': status, 'loaded': [m for m in {HEAVY!r} if m in sys.modules]}}))\n"
    )
    src = str(Path(rubrotor.__file__).parents[1])
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={"PYTHONPATH": src, "PATH": "/usr/bin:/bin"})  # fmt: skip
    return dict(json.loads(out.stdout.strip().splitlines()[-1]), stderr=out.stderr)


def test_help_imports_no_numerical_package():
    run = _loaded_after(["--help"])
    assert run["status"] == 0
    assert run["loaded"] == []


@pytest.mark.parametrize("verb", ["modes", "critical", "campbell"])
def test_linear_verb_on_a_general_rotor_imports_no_numba(verb, tmp_path):
    argv = [verb, str(SCENARIOS / "general_rotor.toml")]
    argv += {"modes": ["--speed", "500"], "critical": [],
             "campbell": ["--speeds", "0:1500:5", "--json"]}[verb]  # fmt: skip
    run = _loaded_after(argv)
    assert run["status"] == 0, run["stderr"]
    assert "numpy" in run["loaded"] and "scipy" in run["loaded"]  # it did solve something
    for heavy in ("numba", "xarray", "matplotlib", "dask"):
        assert heavy not in run["loaded"], f"{verb} imported {heavy}"


def _compile_event(seconds: float) -> None:
    """A numba ``numba:compile`` event lasting ``seconds`` (what a compilation emits)."""
    import time

    from numba.core import event as ev

    with ev.trigger_event("numba:compile", data={"dispatcher": None, "args": None}):
        time.sleep(seconds)


def test_compile_notice_says_once_when_compiling_is_long(capsys):
    from rubrotor.cli.common import compile_notice

    with compile_notice(after=0.05):
        _compile_event(0.5)
        _compile_event(0.5)
    err = capsys.readouterr().err
    assert err.count("compiling the rub engine: first run only") == 1


def test_compile_notice_is_silent_for_cache_loads(capsys):
    from rubrotor.cli.common import compile_notice

    with compile_notice(after=5.0):
        _compile_event(0.01)
    _compile_event(0.01)  # outside the block: no listener left behind
    assert capsys.readouterr().err == ""
