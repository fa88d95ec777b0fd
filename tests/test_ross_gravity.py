"""import-ross writes gravity as ROSS's run_static applies it: 9.8065 m/s^2 along ROSS's -y,
which is rubrotor's -z (ROSS's x, y are rubrotor's y, z). On the docs' ROSS file and ROSS's
four example rotors (saved by ROSS 2.3 / 3.1): the scenario's gravity, the static sag along -z
only, and the support reactions summing to the rotor's weight (mass times 9.8065, a second
route to the same number)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rubrotor
from rubrotor.cli import main
from rubrotor.scenario.load import Scenario, load_scenario
from rubrotor.scenario.ross import ROSS_GRAVITY

HERE = Path(__file__).parent
FILES = [HERE.parent / "docs" / "howto" / "import-ross" / "ross_rotor.toml",
         *sorted((HERE / "data" / "ross").glob("*.toml"))]  # fmt: skip


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_gravity_along_ross_minus_y(path):
    sc = Scenario.from_ross(path, speed=300.0)
    assert sc.gravity == (0.0, -ROSS_GRAVITY)
    res = rubrotor.static(sc)
    v, w = res.deflection[:, 0], res.deflection[:, 1]
    # sideways only through cross-coupled bearings (the housings rotor: 7 % of the sag)
    assert np.abs(v).max() <= 0.1 * np.abs(w).max()
    assert w[np.argmax(np.abs(w))] < 0  # down, along -z
    rotor = sc.rotor
    ground = {b.name for b in rotor.bearings if b.link is None}  # not shaft-to-housing
    fy = sum(b.force_y for b in res.bearings if b.name in ground)
    fz = sum(b.force_z for b in res.bearings if b.name in ground)
    assert res.applied[0] == 0 and res.applied[1] < 0
    assert fz == pytest.approx(-res.applied[1], rel=1e-9) and abs(fy) <= 1e-9 * fz
    # the weight by hand: rotor, housings (their vertical mass, ROSS's my) and bearing masses
    mass = rotor.mass + sum(p.mass_z for p in rotor.point_masses)
    mass += sum(b.mzz for b in rotor.bearings)
    assert fz == pytest.approx(mass * ROSS_GRAVITY, rel=1e-9)


def test_cli_import_writes_the_gravity_table(tmp_path, capsys):
    out = tmp_path / "r.toml"
    assert main(["import-ross", str(FILES[0]), "--out", str(out)]) == 0
    assert load_scenario(out).gravity == (0.0, -ROSS_GRAVITY)
    assert "[gravity]" in out.read_text()
