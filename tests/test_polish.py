"""Rough edges a new user hits: sweep messages and stores, licence and citation files, the wheel."""

from __future__ import annotations

import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest
import xarray as xr
import yaml

import rubrotor
from rubrotor.cli import main

ROOT = Path(__file__).resolve().parents[1]
SCEN = Path(rubrotor.__file__).parent / "scenarios"


def test_sweep_too_few_revolutions_names_the_transient_option(tmp_path, capsys):
    assert main(["sweep", str(SCEN / "seed_case1.toml"), "--vary",
                 "speed.critical_multiple=1:2:2", "--revolutions", "50",
                 "--out", str(tmp_path / "s.zarr")]) == 2  # fmt: skip
    err = capsys.readouterr().err
    assert "--transient" in err and "100" in err and "--revolutions" in err


def test_sweep_store_is_consolidated(tmp_path):
    """The store opens with xarray's defaults without a warning (warnings are errors here)."""
    out = tmp_path / "s.zarr"
    assert main(["sweep", str(SCEN / "seed_case1.toml"), "--vary",
                 "speed.critical_multiple=1.4:1.5:2", "--transient", "2",
                 "--revolutions", "5", "--workers", "1", "--out", str(out)]) == 0  # fmt: skip
    with xr.open_zarr(out) as ds:
        assert bool(ds["done"].all())
    assert (out / "zarr.json").exists() or (out / ".zmetadata").exists()


def test_license_and_citation():
    """LICENSE is the BSD-3-Clause text pyproject declares; CITATION.cff is valid CFF 1.2.0."""
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert meta["license"]["text"] == "BSD-3-Clause"
    text = (ROOT / "LICENSE").read_text()
    assert "BSD 3-Clause License" in text and "Neither the name of the copyright holder" in text
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0"
    assert cff["version"] == rubrotor.__version__ == meta["version"]
    assert cff["license"] == "BSD-3-Clause"
    assert cff["title"] and cff["message"] and cff["authors"][0]["name"]


@pytest.mark.skipif(not (ROOT / "pyproject.toml").exists(), reason="needs the source tree")
def test_wheel_carries_scenarios_templates_and_license(tmp_path):
    """A built wheel holds every shipped scenario, the report template and the licence."""
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", str(ROOT), "--no-deps",
         "-q", "-w", str(tmp_path)],
        check=True,
    )  # fmt: skip
    (wheel,) = tmp_path.glob("rubrotor-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    for toml in SCEN.glob("*.toml"):
        assert f"rubrotor/scenarios/{toml.name}" in names
    assert any(n.startswith("rubrotor/templates/") for n in names)
    assert any(n.endswith("LICENSE") for n in names)


def test_follow_sweep_too_few_revolutions_names_the_transient_option():
    """Follow sweeps share the sweep's run-length check (same message)."""
    from rubrotor.errors import InputError
    from rubrotor.sweeps.follow import follow_sweep

    sc = rubrotor.load_scenario(SCEN / "seed_case1.toml")
    with pytest.raises(InputError, match="--transient"):
        follow_sweep(sc, "speed.critical_multiple", [1.0, 1.1], revolutions=50)
