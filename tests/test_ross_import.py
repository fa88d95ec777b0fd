"""``rubrotor import-ross`` and ``Scenario.from_ross`` on rotor files saved by ROSS, without ROSS.

The files in tests/data/ross were written by ROSS's own ``Rotor.save``: ROSS 3.1's
``rotor_example`` and ``rotor_example_amb_simple`` (magnetic bearings tabulated against
frequency, element damping), ROSS's ``test_global_index`` rotor (bearings linked to housing
point masses, bearing mass; built as in tests/test_ross_parity.py) and a ``rotor8``-style
rotor saved by ROSS 2.3 (its older file). References: the files' own numbers read with
``tomllib`` here (element masses ``rho pi (od^2 - id^2) L / 4``, disk and point masses, the
bearing tables), independent of the mapping; the equality with ROSS's matrices is in
tests/test_ross_import_ross.py (ROSS venvs).
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rubrotor import load_scenario
from rubrotor.cli.app import main
from rubrotor.errors import InputError
from rubrotor.rotors.ross_model import read_ross_file
from rubrotor.scenario.load import Scenario, scenario_to_dict
from rubrotor.scenario.ross import ross_scenario_dict

DATA = Path(__file__).parent / "data" / "ross"
FILES = sorted(DATA.glob("*.toml"))


def _raw(path: Path) -> dict:
    return tomllib.loads(path.read_text())


def _rigid_mass(system, direction: int) -> float:
    """``r^T M r`` for a unit translation along ``direction`` (0: v, 1: w) of every node and
    point mass: the rotor's total mass (kg)."""
    n_nodes = len(system.basis.nodes)
    r = np.zeros(system.M.shape[0])
    r[direction : 4 * n_nodes : 4] = 1.0
    r[4 * n_nodes + direction :: 2] = 1.0
    return float(r @ system.M @ r)


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_saved_scenario_loads_back_bit_for_bit(path, tmp_path):
    """Scenario.from_ross(file).save() then load_scenario: the same tables and the same linear
    system to the last bit (numbers are written with repr)."""
    sc = Scenario.from_ross(path, speed=300.0)
    out = sc.save(tmp_path / "imported.toml")
    back = load_scenario(out)
    assert scenario_to_dict(back) == scenario_to_dict(sc)
    a, b = sc.rotor.linear_system(), back.rotor.linear_system()
    for w in (0.0, 123.0, 5000.0):
        ma, mb = a.matrices(w), b.matrices(w)
        for nm in "MKCG":
            assert np.array_equal(getattr(ma, nm), getattr(mb, nm))


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_mass_equals_the_files_elements(path):
    """Total mass of the imported rotor along y and z = the file's shaft elements
    (``rho pi (od^2 - id^2) L / 4``, sleeves included), disks and point masses, to 1e-12."""
    raw = _raw(path)
    shaft = sum(
        t["material"]["rho"] * math.pi * (t["odl"] ** 2 - t["idl"] ** 2) / 4 * t["L"]
        for k, t in raw.items() if k.startswith("ShaftElement")
    )  # fmt: skip
    disks = sum(t["m"] for k, t in raw.items() if k.startswith("DiskElement"))
    masses = [t for k, t in raw.items() if k.startswith("PointMass")]
    bearing_m = [
        (np.atleast_1d(t.get("mxx", 0.0))[0], np.atleast_1d(t.get("myy", 0.0))[0])
        for k, t in raw.items() if "Bearing" in k or "Seal" in k
    ]  # fmt: skip
    system = Scenario.from_ross(path).rotor.linear_system()
    for d, key in ((0, "mx"), (1, "my")):
        pm = sum(t.get(key) or t.get("m", 0.0) for t in masses)
        # a bearing's mass to the ground adds to M; linked ones add (+m, -m) blocks summing to 0
        grounded = sum(m[d] for m, (k, t) in zip(bearing_m, _bearings(raw), strict=True)
                       if t.get("n_link") is None)  # fmt: skip
        expect = shaft + disks + pm + grounded
        assert _rigid_mass(system, d) == pytest.approx(expect, rel=1e-12)


def _bearings(raw: dict) -> list:
    return [(k, t) for k, t in raw.items() if "Bearing" in k or "Seal" in k]


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_bearing_tables_are_the_files(path):
    """Each support's table holds the file's coefficients at its table points, in our
    directions (kyy = kxx, kyz = kxy, kzy = kyx, kzz = kyy), on the file's axis."""
    raw = _raw(path)
    ross3 = raw["ross_version"].startswith("3")
    system = Scenario.from_ross(path).rotor.linear_system()
    by_name = {s.name: s for s in system.supports}
    for key, t in _bearings(raw):
        sup = by_name[t.get("tag", key)]
        kxx = np.atleast_1d(np.asarray(t["kxx"], float))
        axis = t.get("speed") if t.get("speed") is not None else t.get("frequency")
        if axis is not None and np.size(axis) > 1:
            assert sup.axis == ("speed" if "speed" in t or not ross3 else "frequency")
            np.testing.assert_array_equal(sup.speeds, axis)
        np.testing.assert_array_equal(sup.k[:, 0, 0], kxx)
        np.testing.assert_array_equal(sup.k[:, 0, 1], np.atleast_1d(t.get("kxy", 0.0)))
        np.testing.assert_array_equal(sup.c[:, 1, 0], np.atleast_1d(t.get("cyx", 0.0)))


def test_housings_and_bearing_mass_mapped():
    """The housings rotor: two point masses after the nodal DOFs, the shaft bearings linked
    to them, the housings' supports on them, the support's bearing mass in M."""
    sc = Scenario.from_ross(DATA / "housings_ross31.toml")
    rotor = sc.rotor
    assert [p.name for p in rotor.point_masses] == ["Point Mass 0", "Point Mass 1"]
    assert [b.link for b in rotor.bearings[:2]] == ["Point Mass 0", "Point Mass 1"]
    assert [b.on for b in rotor.bearings[2:]] == ["Point Mass 0", "Point Mass 1"]
    system = rotor.linear_system()
    n = 4 * len(system.basis.nodes)
    assert system.M.shape[0] == n + 4
    assert system.M[n, n] == pytest.approx(1.5 + 0.4, rel=1e-15)  # point mass + support's mxx
    assert system.M[n + 3, n + 3] == pytest.approx(2.5, rel=1e-15)


def test_cli_import_then_verbs(tmp_path, capsys):
    """import-ross writes a scenario the linear verbs run on."""
    out = tmp_path / "rotor.toml"
    assert main(["import-ross", str(DATA / "rotor_example_ross31.toml"), "--out", str(out),
                 "--rpm", "3000", "--json"]) == 0  # fmt: skip
    assert load_scenario(out).speed == pytest.approx(100 * math.pi, rel=1e-15)
    capsys.readouterr()
    assert main(["modes", str(out), "--json"]) == 0
    assert main(["static", str(out), "--json"]) == 0


def test_bad_files_refused_by_name(tmp_path, capsys):
    """Missing file, not TOML, a tapered element and an unknown element: errors naming them."""
    with pytest.raises(InputError, match="ROTOR_FILE"):
        read_ross_file(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("this is = not toml [")
    with pytest.raises(InputError, match="TOML or JSON"):
        read_ross_file(bad)
    text = (DATA / "rotor_example_ross31.toml").read_text()
    tapered = tmp_path / "tapered.toml"
    tapered.write_text(text.replace("odr = 0.05", "odr = 0.06", 1))
    with pytest.raises(InputError, match="tapered"):
        ross_scenario_dict(read_ross_file(tapered))
    gear = tmp_path / "gear.toml"
    gear.write_text(text + '\n["GearElement_g"]\nn = 1\n')
    with pytest.raises(InputError, match="GearElement"):
        read_ross_file(gear)
    assert main(["import-ross", str(gear), "--out", str(tmp_path / "x.toml")]) == 2
    assert "GearElement" in capsys.readouterr().err


def test_every_shipped_scenario_saves_and_loads_back(tmp_path):
    """Scenario.save writes any scenario (arrays of tables, named tables, dimensionless keys):
    loading the file gives the same tables."""
    from importlib import resources

    for f in sorted((resources.files("rubrotor") / "scenarios").iterdir()):
        if not f.name.endswith(".toml"):
            continue
        sc = load_scenario(f)
        back = load_scenario(sc.save(tmp_path / f.name))
        assert scenario_to_dict(back) == scenario_to_dict(sc), f.name
