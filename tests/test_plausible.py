"""Plausibility checks across keys (rubrotor.scenario.plausible): the six unit slips of issue 38
on the shipped seal_rub rotor, each refused by key with the slip named, and the quantity each
message states checked against a closed form computed here from the file's own numbers."""

from __future__ import annotations

import copy
import math
import re
import tomllib
from importlib import resources

import pytest

from rubrotor.cli import main
from rubrotor.errors import ScenarioError
from rubrotor.scenario import plausible
from rubrotor.scenario.load import load_scenario, scenario_from_dict, shipped_scenarios
from rubrotor.scenario.write import write_scenario

BASE = tomllib.loads((resources.files("rubrotor") / "scenarios" / "seal_rub.toml").read_text())
RHO = 7810.0  # kg/m^3, steel of seal_rub.toml


def _rotor_mass(d: dict) -> float:
    """seal_rub's mass (kg) by hand: hollow steel sections, the impeller as a solid steel
    cylinder, the lumped balance disk."""
    m = 0.0
    for s in d["section"]:
        m += (
            RHO
            * math.pi
            / 4
            * (s["diameter"] ** 2 - s.get("bore_diameter", 0.0) ** 2)
            * s["length"]
        )
    imp = d["disk"][0]
    return m + RHO * math.pi / 4 * imp["outer_diameter"] ** 2 * imp["width"] + d["disk"][1]["mass"]


def _number_after(text: str, before: str) -> float:
    m = re.search(re.escape(before) + r"\s*([-+0-9.eE]+)", text)
    assert m, (before, text)
    return float(m.group(1).rstrip("."))


def _refused(d: dict) -> str:
    with pytest.raises(ScenarioError) as info:
        scenario_from_dict(d)
    return str(info.value)


def test_clearance_in_mm_is_refused_by_key_with_the_ratio():
    d = copy.deepcopy(BASE)
    d["contact"][0]["clearance"] = 0.25  # 0.25 mm written in m
    msg = _refused(d)
    assert msg.startswith("implausible contact[1].clearance = 0.25 m")
    assert "did you mean 0.25 mm = 0.00025 m?" in msg
    # the seal's radius is given (0.045 m): ratio 0.25 / 0.045
    assert _number_after(msg, "a radial clearance of") == pytest.approx(0.25 / 0.045, rel=1e-3)


def test_diameter_in_mm_is_refused_before_any_mesh():
    d = copy.deepcopy(BASE)
    d["section"][2]["diameter"] = 90.0  # 90 mm written in m
    msg = _refused(d)
    assert "section[3].diameter = 90 m" in msg and "did you mean 90 mm = 0.09 m?" in msg
    assert _number_after(msg, "a section") == pytest.approx(90 / 1.3, rel=1e-3)


def test_disk_mass_in_grams_is_refused_with_the_width_it_implies():
    d = copy.deepcopy(BASE)
    d["disk"][1]["mass"] = 15000.0  # 15 kg written in g
    msg = _refused(d)
    assert "disk[2].mass = 15000 kg" in msg and "did you mean 15000 g = 15 kg?" in msg
    # a uniform disk: Ip = m R^2 / 2 and m = rho pi R^2 w, so w = m^2 / (2 pi rho Ip)
    width = 15000.0**2 / (2 * math.pi * 7850.0 * 0.12)
    assert _number_after(msg, "is") == pytest.approx(width, rel=1e-2)


def test_bearing_stiffness_in_n_per_mm_is_refused_with_the_sag():
    d = copy.deepcopy(BASE)
    for b in d["bearing"]:
        for k in ("kyy", "kzz", "kyz", "kzy"):
            v = b[k]
            b[k] = [x / 1000 for x in v] if isinstance(v, list) else v / 1000
    msg = _refused(d)
    assert "bearing[2].kyy = 80000 N/m" in msg and "80000 N/mm = 8e+07 N/m" in msg
    # mean sag W / sum(kyy), with each bearing's stiffest table value (1e5 and 8e4 N/m)
    sag = _rotor_mass(BASE) * 9.81 / (1.0e5 + 8.0e4)
    assert _number_after(msg, "sags") * 1e-3 == pytest.approx(sag, rel=1e-3)


def test_rpm_in_a_rad_per_s_key_is_refused_with_the_rim_speed():
    d = copy.deepcopy(BASE)
    d["speed"] = {"rad_per_s": 6000.0}
    msg = _refused(d)
    assert msg.startswith("implausible speed.rad_per_s = 6000")
    assert "6000 rpm = 628.3 rad/s" in msg
    # the impeller's rim: 0.15 m radius
    assert _number_after(msg, "radius at") == pytest.approx(6000 * 0.15, rel=1e-3)


def test_unbalance_in_g_mm_is_refused_with_the_eccentricity():
    d = copy.deepcopy(BASE)
    d["unbalance"][0]["magnitude"] = 500.0  # 500 g mm written in kg m
    msg = _refused(d)
    assert "unbalance[1].magnitude = 500 kg m" in msg and "500 g mm = 0.0005 kg m" in msg
    e = (500.0 + 1.3e-4) / _rotor_mass(BASE)
    assert _number_after(msg, "U / m =") == pytest.approx(e, rel=1e-3)


def test_unbalance_beyond_the_coarsest_iso_grade_warns_with_the_grade():
    """A coarse but not absurd unbalance (e below the rim): G 14400, beyond G 4000, warned."""
    d = copy.deepcopy(BASE)
    d["unbalance"][0]["magnitude"] = 2.0
    d["unbalance"][1]["magnitude"] = 0.0
    with pytest.warns(plausible.PlausibilityWarning) as record:
        scenario_from_dict(d)
    (w,) = record
    grade = 2.0 / _rotor_mass(BASE) * (6000 * 2 * math.pi / 60) * 1e3
    assert _number_after(str(w.message), "G = e Omega =") == pytest.approx(grade, rel=1e-3)
    assert str(w.message).startswith("unbalance[1].magnitude = 2 kg m")


def test_a_check_is_switched_off_by_name_and_the_name_is_checked():
    d = copy.deepcopy(BASE)
    d["contact"][0]["clearance"] = 0.25
    d["checks"] = {"skip": ["clearance_vs_radius"]}
    sc = scenario_from_dict(d)
    assert sc.contacts[0].clearance == 0.25
    assert plausible.findings(sc) == []
    assert [f.check for f in plausible.findings(sc, skip=())] == []  # the file's skip holds
    d["checks"] = {"skip": ["clearance"]}
    with pytest.raises(ScenarioError, match=r"checks\.skip"):
        scenario_from_dict(d)


def test_an_unusual_clearance_warns_instead():
    """Between 5 % and 20 % of the radius: a warning that names the key and how to skip."""
    d = copy.deepcopy(BASE)
    d["contact"][0]["clearance"] = 0.1 * 0.045
    with pytest.warns(plausible.PlausibilityWarning, match=r"contact\[1\]\.clearance"):
        scenario_from_dict(d)


def test_shipped_scenarios_are_plausible():
    for item in shipped_scenarios():
        assert plausible.findings(load_scenario(item["path"])) == [], item["name"]


def test_cli_refuses_with_exit_2(tmp_path, capsys):
    d = copy.deepcopy(BASE)
    d["speed"] = {"rad_per_s": 6000.0}
    path = write_scenario(d, tmp_path / "rpm.toml")
    assert main(["modes", str(path)]) == 2
    assert "speed.rad_per_s = 6000" in capsys.readouterr().err


def test_mesh_beyond_memory_names_the_diameter(tmp_path, capsys, monkeypatch):
    """With the checks off, the mesh check refuses before allocating and names the diameter
    that drives the default mesh (the memory it compares with is mocked to 1 GiB)."""
    import rubrotor._memory

    d = copy.deepcopy(BASE)
    d["section"][2]["diameter"] = 90.0
    d["checks"] = {"skip": list(plausible.CHECKS)}
    path = write_scenario(d, tmp_path / "mm.toml")
    monkeypatch.setattr(rubrotor._memory, "available_memory", lambda: 2**30)
    assert main(["modes", str(path)]) == 2
    err = capsys.readouterr().err
    assert "a mesh that fits in memory" in err and "section[3].diameter = 90 m" in err


def test_python_api_refuses_bad_arguments_by_name():
    from rubrotor.errors import InputError

    with pytest.raises(InputError, match="scenario"):
        plausible.findings("seal_rub.toml")
    with pytest.raises(InputError, match="skip"):
        plausible.findings(load_scenario("seal_rub"), skip=["clearance"])
