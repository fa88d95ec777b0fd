"""The package laid out by concern keeps what users had.

* Old module paths (``rubrotor.simulation``, ``rubrotor.model``, ...) import the module at its new
  path, warning once, so users' scripts survive the move (:mod:`rubrotor._moved`).
* ``rubrotor reproduce`` gives the summary the code gave before the move: the reference file
  ``tests/data/seed_summary_before_layout.json`` was written by ``rubrotor reproduce`` at default
  settings on commit 3c3069b, the last commit of the flat layout (its ``provenance`` field). The
  claim verdicts must be equal, the natural frequencies and critical speed equal to 1e-9, and
  every case metric equal to 1e-6 (measured: 2e-10 at most, the difference between a freshly
  compiled and a cached kernel's rounding amplified by 300 revolutions of contact).
"""

import importlib
import json
import math
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from rubrotor._moved import MOVED, SPLIT

REFERENCE = Path(__file__).parent / "data" / "seed_summary_before_layout.json"


@pytest.mark.parametrize("old", sorted(MOVED))
def test_old_module_path_imports_new_module_with_one_warning(old):
    """In a fresh interpreter: the old path warns (FutureWarning naming both paths) and is the
    same module object as the new path; a second import does not warn again."""
    code = f"""
import warnings, importlib
warnings.simplefilter("always")
with warnings.catch_warnings(record=True) as first:
    old = importlib.import_module("rubrotor.{old}")
with warnings.catch_warnings(record=True) as second:
    importlib.import_module("rubrotor.{old}")
new = importlib.import_module("rubrotor.{MOVED[old]}")
mine = [w for w in first if "rubrotor.{old} moved" in str(w.message)]
assert len(mine) == 1 and mine[0].category is FutureWarning, [str(w.message) for w in first]
assert "rubrotor.{MOVED[old]}" in str(mine[0].message)
assert not [w for w in second if "moved" in str(w.message)]
assert old is new
"""
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


#: the public names of each split module before the split (its ``__all__`` then)
SPLIT_NAMES = {
    "linear.analysis": [
        "DampedMode", "DampedModes", "CampbellData", "LinearCritical", "UnbalanceResponse",
        "damped_modes", "campbell_data", "linear_critical_speeds", "stability_threshold",
        "unbalance_response", "CRITICALLY_DAMPED", "OSCILLATING", "OVERDAMPED",
    ],
    "linear.api": [
        "FORWARD_WHIRL_RATIO", "residual_unbalance", "vibration_limit", "api617_unbalance",
        "ClearanceCheck", "clearance_check", "anticipated_cross_coupling", "Level1", "level1",
    ],
}  # fmt: skip
SPLIT_NAMES["linear_analysis"] = SPLIT_NAMES["linear.analysis"]


@pytest.mark.parametrize("old", sorted(SPLIT))
def test_split_module_path_keeps_its_names_with_one_warning(old):
    """In a fresh interpreter: a module split by concern still imports under its old path,
    warning once (FutureWarning naming the new modules), and every public name it had is the
    same object as in the module that now holds it."""
    code = f"""
import warnings, importlib
warnings.simplefilter("always")
with warnings.catch_warnings(record=True) as first:
    old = importlib.import_module("rubrotor.{old}")
with warnings.catch_warnings(record=True) as second:
    importlib.import_module("rubrotor.{old}")
mine = [w for w in first if "rubrotor.{old} was split" in str(w.message)]
assert len(mine) == 1 and mine[0].category is FutureWarning, [str(w.message) for w in first]
assert not [w for w in second if "split" in str(w.message)]
news = [importlib.import_module("rubrotor." + n) for n in {SPLIT[old]!r}]
for n in {SPLIT[old]!r}:
    assert "rubrotor." + n in str(mine[0].message)
for name in {SPLIT_NAMES[old]!r}:
    homes = [m for m in news if name in vars(m)]
    assert homes and all(vars(m)[name] is getattr(old, name) for m in homes), name
    assert name in old.__all__ or name.isupper(), name
"""
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


def test_linear_keeps_the_linear_system_names():
    """``rubrotor.linear`` is now the package of linear analyses; the names of the old module
    ``rubrotor.linear`` (the linear system) still resolve there, with a FutureWarning."""
    from rubrotor.rotors.linear import LinearSystem

    linear = importlib.import_module("rubrotor.linear")
    with pytest.warns(FutureWarning, match="rotors.linear.LinearSystem"):
        assert linear.LinearSystem is LinearSystem
    with pytest.raises(AttributeError, match="no_such_name"):
        linear.no_such_name  # noqa: B018


def test_packages_read_their_main_module():
    """``rubrotor.scenario``, ``rubrotor.plotting`` and ``rubrotor.cli`` (once modules, now
    packages) still hand out their old names, without a warning."""
    from rubrotor.cli.app import main
    from rubrotor.plotting.figures import campbell_figure
    from rubrotor.scenario.load import Scenario

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        from rubrotor.cli import main as cli_main
        from rubrotor.plotting import campbell_figure as fig
        from rubrotor.scenario import Scenario as Sc
    assert (cli_main, fig, Sc) == (main, campbell_figure, Scenario)


def _leaves(x, path=""):
    if isinstance(x, dict):
        for k, v in x.items():
            yield from _leaves(v, f"{path}/{k}")
    elif isinstance(x, list):
        for i, v in enumerate(x):
            yield from _leaves(v, f"{path}[{i}]")
    else:
        yield path, x


def test_reproduce_summary_unchanged_by_the_layout(tmp_path):
    from rubrotor.cli.app import main

    assert main(["reproduce", "--out", str(tmp_path), "--quiet"]) == 0
    got = json.loads((tmp_path / "summary.json").read_text())
    ref = json.loads(REFERENCE.read_text())
    assert [(c["claim"], c["holds"]) for c in got["claims"]] == [
        (c["claim"], c["holds"]) for c in ref["claims"]
    ]
    for key in ("first_forward_critical_rad_s", "speed_rad_s"):
        assert got[key] == pytest.approx(ref[key], rel=1e-9)
    assert got["natural_frequencies_hz"].keys() == ref["natural_frequencies_hz"].keys()
    for name, f in ref["natural_frequencies_hz"].items():
        assert got["natural_frequencies_hz"][name] == pytest.approx(f, rel=1e-9), name
    ref_cases = dict(_leaves(ref["cases"]))
    got_cases = dict(_leaves(got["cases"]))
    assert got_cases.keys() == ref_cases.keys()
    compared = 0
    for path, value in ref_cases.items():
        if isinstance(value, float) and math.isnan(value):
            assert math.isnan(got_cases[path]), path
        elif isinstance(value, float):
            assert got_cases[path] == pytest.approx(value, rel=1e-6, abs=1e-300), path
            compared += 1
        else:
            assert got_cases[path] == value, path
    assert compared > 50
