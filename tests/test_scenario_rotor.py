"""Scenario files of general rotors: parsing, validation naming the key, CLI exit status.

References: the Python API objects built by hand (same rotor, same matrices), the closed-form
mass of an annular disk, and the continuous shaft of :mod:`rubrotor.linear.shaft` for a uniform
``[[section]]`` on two pinned bearings (the default mesh must meet its 1e-4 claim).
"""

from __future__ import annotations

import copy
import dataclasses
import math
import subprocess
import sys
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rubrotor
from rubrotor.cli import main, shipped_scenarios
from rubrotor.errors import ScenarioError
from rubrotor.linear.shaft import natural_frequencies
from rubrotor.rotors.fe import Bearing, Material, Rotor, Section
from rubrotor.scenario import load_scenario, scenario_from_dict, scenario_to_dict

GENERAL = str(resources.files("rubrotor") / "scenarios" / "general_rotor.toml")
SRC = str(Path(rubrotor.__file__).resolve().parent.parent)

UNIFORM = {
    "materials": {
        "alu": {"youngs_modulus": 71e9, "shear_modulus": 26.2e9, "density": 2660.0},
    },
    "section": [{"length": 0.4, "diameter": 0.1, "material": "alu"}],
    "bearing": [{"position": 0.0, "kind": "pinned"}, {"position": 0.4, "kind": "pinned"}],
    "rotor": {"theory": "timoshenko", "gyroscopic": True, "shear_coefficient": "cowper"},
    "speed": {"rad_per_s": 3000.0},
}


def general_dict() -> dict:
    return tomllib.loads(Path(GENERAL).read_text())


def test_shipped_general_rotor():
    """The shipped scenario: six sections, the impeller's mass from its geometry
    (``rho pi (D^2 - d^2) b / 4``), the tabulated left bearing, 6000 rpm, listed by
    ``rubrotor scenarios``."""
    sc = load_scenario(GENERAL)
    assert sc.shaft is None and sc.rotor is not None
    r = sc.rotor
    assert len(r.sections) == 6 and r.length == pytest.approx(1.3)
    assert r.disks[0].mass == pytest.approx(7810 * math.pi * 0.3**2 / 4 * 0.05)
    assert sc.speed == pytest.approx(6000 * 2 * math.pi / 60)
    system = r.linear_system(sc.stations)
    k, _ = system.supports[0].coefficients(750.0)
    np.testing.assert_allclose(k, [[7.5e7, 1.25e7], [-1.5e7, 4.75e7]])
    assert system.basis.node_at(0.45) is not None
    assert "general_rotor" in [s["name"] for s in shipped_scenarios()]


def test_uniform_section_scenario_matches_continuous_shaft():
    """One ``[[section]]`` on two pinned bearings with the default mesh: the first five
    whirl frequencies at 3000 rad/s are within 1e-4 of the continuous ``[shaft]`` model."""
    sc = scenario_from_dict(UNIFORM)
    a, _ = sc.rotor.linear_system().matrices(sc.speed).first_order()
    lam = scipy.linalg.eigvals(a)
    fe = np.sort(lam.imag[lam.imag > 0])[:5] / (2 * math.pi)
    shaft_sc = scenario_from_dict(
        {
            "shaft": {
                "length": 0.4,
                "diameter": 0.1,
                "youngs_modulus": 71e9,
                "shear_modulus": 26.2e9,
                "density": 2660.0,
                "modes": 3,
            },
            "speed": {"rad_per_s": 3000.0},
        }
    )
    ref = sorted(m.frequency_hz for m in natural_frequencies(shaft_sc.shaft, 3000.0))[:5]
    np.testing.assert_allclose(fe, ref, rtol=1e-4)


def test_scenario_rotor_equals_api_rotor():
    """The scenario tables build the same Rotor (hence matrices) as the Python API."""
    alu = Material("alu", 71e9, 2660.0, shear_modulus=26.2e9)
    api = Rotor(
        [Section(0.4, 0.1, alu)],
        bearings=[Bearing(0.0, kind="pinned"), Bearing(0.4, kind="pinned")],
    )
    assert scenario_from_dict(UNIFORM).rotor == api


def test_round_trip_and_with_changes():
    """``scenario_to_dict(resolved=True)`` rebuilds the same rotor; ``with_changes`` keeps it."""
    sc = load_scenario(GENERAL)
    again = scenario_from_dict(scenario_to_dict(sc, resolved=True))
    assert again.rotor == sc.rotor
    assert again.speed == pytest.approx(sc.speed) and again.unbalance == sc.unbalance
    faster = sc.with_changes(**{"speed.rad_per_s": 900.0})
    assert faster.speed == 900.0 and faster.rotor == sc.rotor
    eb = sc.with_changes(**{"rotor.theory": "euler-bernoulli"})
    assert eb.rotor.theory == "euler-bernoulli" and eb.rotor.sections == sc.rotor.sections


def _edit(path: str, value):
    """A copy of the shipped scenario with ``path`` (tuple of keys/indices) set or removed."""
    d = general_dict()
    node = d
    for key in path[:-1]:
        node = node[key]
    if value is _DELETE:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return d


_DELETE = object()


@pytest.mark.parametrize(
    "path, value, field",
    [
        (("section", 0, "lenght"), 0.1, "section[1].lenght"),
        (("section", 1, "diameter"), "70 mm", "section[2].diameter"),
        (("section", 2, "length"), _DELETE, "section[3].length"),
        (("section", 0, "material"), "titanium", "section[1].material"),
        (("section", 0, "bore_diameter"), 0.06, "section[1].bore_diameter"),
        (("materials", "steel", "density"), _DELETE, "materials.steel.density"),
        (("materials", "steel", "poisson_ratio"), 0.7, "materials.steel.poisson_ratio"),
        (("disk", 1, "mass"), -15.0, "disk[2].mass"),
        (("disk", 0, "mass"), 5.0, "disk[1].outer_diameter"),
        (("disk", 1, "position"), 0.45, "disk[2].position"),
        (("disk", 1, "position"), 1.4, "disk[2].position"),
        (("bearing", 1, "position"), 1.5, "bearing[2].position"),
        (("bearing", 1, "kyy"), -8e7, "bearing[2].kyy"),
        (("bearing", 0, "kyy"), [1e8, 2e8], "bearing[1].kyy"),
        (("bearing", 0, "kind"), "roller", "bearing[1].kind"),
        (("bearing",), _DELETE, "bearing"),
        (("rotor", "theory"), "bernoulli", "rotor.theory"),
        (("rotor", "mesh"), 3, "rotor.mesh"),
        (("speed",), {"dimensionless": 1.5}, "speed.dimensionless"),
        (("unbalance", "position"), 1.31, "unbalance.position"),
        (("damping",), {"ratio": 0.01}, "damping"),
        (("section",), {"length": 0.1}, "section"),
        (("shaft",), {"length": 0.4}, "shaft / section"),
    ],
)
def test_invalid_general_scenarios_name_the_key(path, value, field):
    """Unknown, missing, mistyped and non-physical keys raise ScenarioError naming the key."""
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(_edit(path, value))
    assert err.value.field == field


def test_one_support_is_no_support():
    """A single holding bearing (or none) leaves rigid-body modes: rejected as 'bearing'."""
    d = copy.deepcopy(UNIFORM)
    d["bearing"] = d["bearing"][:1]
    with pytest.raises(ScenarioError, match="two or more stations") as err:
        scenario_from_dict(d)
    assert err.value.field == "bearing"


def test_shaft_only_verbs_refuse_general_rotor(tmp_path):
    """The convergence study and the seed's dimensionless form need [shaft]; time simulation
    runs through the general engine (here refused only for want of a [simulation] section)."""
    sc = load_scenario(GENERAL)
    with pytest.raises(ScenarioError, match="continuous shaft only") as err:
        rubrotor.converge(sc)
    assert err.value.field == "section"
    with pytest.raises(rubrotor.InputError) as err:
        rubrotor.simulate(sc)
    assert err.value.field == "simulation"
    with pytest.raises(ScenarioError):
        sc.dimensionless()


def test_cli_exit_2_one_line(tmp_path, capsys):
    """A bad general-rotor file and a shaft-only verb give exit 2 and one line on stderr."""
    bad = tmp_path / "bad.toml"
    text = Path(GENERAL).read_text().replace("mass = 15.0", "mass = -15.0")
    bad.write_text(text)
    assert main(["run", str(bad), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "disk[2].mass" in err and "Traceback" not in err
    assert main(["run", GENERAL, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "simulation" in err


def test_cli_subprocess_no_traceback(tmp_path):
    """The installed entry point: both [shaft] and [[section]] -> exit 2, the key named."""
    both = tmp_path / "both.toml"
    both.write_text(Path(GENERAL).read_text() + "\n[shaft]\nlength = 0.4\n")
    proc = subprocess.run(
        [sys.executable, "-m", "rubrotor", "run", str(both), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
        env={"PYTHONPATH": SRC, "PATH": "/usr/bin:/bin"},
        check=False,
    )
    assert proc.returncode == 2
    assert "shaft / section" in proc.stderr and "Traceback" not in proc.stderr


def test_default_mesh_of_shipped_rotor_within_1e4():
    """Default mesh of the shipped stepped rotor at its 6000 rpm: the first five damped
    frequencies differ from a mesh with twice as many elements per section by less than
    1e-4 x 3/4 (Richardson with the ``h^2`` rate of Timoshenko elements, so the error of the
    default mesh itself is below 1e-4)."""
    sc = load_scenario(GENERAL)
    rotor = sc.rotor
    x = rotor.nodes(sc.stations)
    bounds = rotor.boundaries
    counts = [
        int(np.sum((x > a + 1e-9) & (x <= b + 1e-9)))
        for a, b in zip(bounds[:-1], bounds[1:], strict=True)
    ]
    fine = dataclasses.replace(
        rotor,
        sections=[
            dataclasses.replace(s, elements=2 * n)
            for s, n in zip(rotor.sections, counts, strict=True)
        ],
    )

    def first_five(r):
        a, _ = r.linear_system(sc.stations).matrices(sc.speed).first_order()
        lam = scipy.linalg.eigvals(a)
        return np.sort(lam.imag[lam.imag > 0])[:5]

    coarse, ref = first_five(rotor), first_five(fine)
    assert len(fine.nodes(sc.stations)) - 1 >= 2 * (len(x) - 1)
    assert np.max(np.abs(coarse - ref) / ref) * 4 / 3 < 1e-4
