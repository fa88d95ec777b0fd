"""Issue 23, "no hand arithmetic, no guessing": each usability item through the library and the
CLI (``rubrotor.cli.main`` in-process)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import rubrotor
from rubrotor.errors import ScenarioError
from rubrotor.linear.modal_mass import modal_masses
from rubrotor.rotors.shaft import Shaft


# ---- shipped scenarios by name -----------------------------------------------------------------
def test_shipped_scenario_by_name_from_any_folder(tmp_path, monkeypatch):
    """``load_scenario("seed_case1.toml")`` from a folder without that file reads the shipped
    one; a local file of that name takes precedence; an unknown name points to the list."""
    monkeypatch.chdir(tmp_path)
    assert rubrotor.load_scenario("seed_case1.toml").name == "seed_case1"
    assert rubrotor.load_scenario("seed_case1").name == "seed_case1"
    (tmp_path / "seed_case1.toml").write_text(
        '[meta]\nname = "mine"\n[shaft]\nlength = 0.4\ndiameter = 0.1\nyoungs_modulus = 71e9\n'
        "density = 2660\npoisson_ratio = 0.33\n[speed]\nrpm = 1000\n"
    )
    assert rubrotor.load_scenario("seed_case1.toml").name == "mine"
    with pytest.raises(ScenarioError, match="rubrotor scenarios"):
        rubrotor.load_scenario("no_such_rotor.toml")


# ---- modal masses ------------------------------------------------------------------------------
def test_modal_mass_of_pinned_shaft_is_half_its_mass():
    """Closed form: the first mode of a uniform pinned-pinned Euler-Bernoulli shaft is
    ``sin(pi x / L)``; with ``phi^T M phi = 1`` its midspan modal mass is ``rho A L / 2`` and its
    modal stiffness ``omega^2 rho A L / 2`` with ``omega = (pi/L)^2 sqrt(E I / (rho A))``."""
    shaft = Shaft(length=0.4, diameter=0.1, youngs_modulus=71e9, density=2660, poisson_ratio=0.33,
                  theory="euler-bernoulli", gyroscopic=False, modes=3)  # fmt: skip
    area, inertia = math.pi * 0.1**2 / 4, math.pi * 0.1**4 / 64
    m_ref = 2660 * area * 0.4 / 2
    w_ref = (math.pi / 0.4) ** 2 * math.sqrt(71e9 * inertia / (2660 * area))
    first = modal_masses(shaft)[0]
    assert first.station == pytest.approx(0.2, abs=1e-3)
    assert first.modal_mass == pytest.approx(m_ref, rel=1e-9)
    assert first.modal_stiffness == pytest.approx(w_ref**2 * m_ref, rel=1e-9)
    at_quarter = modal_masses(shaft, station=0.1)[0]  # sin(pi/4)^2 = 1/2: twice the mass
    assert at_quarter.modal_mass == pytest.approx(2 * m_ref, rel=1e-9)


def test_modal_masses_sum_to_static_flexibility():
    """Second route (modal expansion of the static flexibility): with every mode,
    ``sum_i u_i(x)^2 / omega_i^2 = sum_i 1 / k_i`` at a station equals the static deflection
    per unit force there, ``(K^-1)_xx``, solved directly on the FE rotor at rest."""
    from rubrotor.linear.verbs import linear_system

    scenario = rubrotor.load_scenario("general_rotor.toml")
    system = linear_system(scenario)
    x = 0.45
    mm = modal_masses(scenario, speed=0.0, station=x, n=system.n_dof)
    mats = system.matrices(0.0)
    row = system.basis.rows(x)[:, system.free]
    ks = 0.5 * (mats.K + mats.K.T)
    flex = row @ np.linalg.solve(ks, row.T)
    assert len(mm) == system.n_dof
    assert sum(1 / m.modal_stiffness for m in mm) == pytest.approx(np.trace(flex), rel=1e-8)


# ---- through the CLI ---------------------------------------------------------------------------
def test_cli_finds_shipped_scenarios_and_says_version(tmp_path, monkeypatch, capsys):
    """``rubrotor modes seed_rotor.toml`` from an empty folder; an unknown name exits 2 with one
    line pointing to ``rubrotor scenarios``; ``rubrotor --version`` prints the package's."""
    from rubrotor.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["modes", "seed_rotor.toml", "--json", "--speed", "0"]) == 0
    capsys.readouterr()
    assert main(["modes", "seed_rotr.toml"]) == 2
    err = capsys.readouterr().err
    assert "seed_rotr.toml" in err and "rubrotor scenarios" in err and err.count("\n") == 1
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"rubrotor {rubrotor.__version__}"
    assert main(["scenarios", "--json"]) == 0
    described = json.loads(capsys.readouterr().out)["scenarios"]
    assert all(s["description"] for s in described), [s["name"] for s in described]


def test_cli_modes_prints_modal_masses(capsys):
    """``rubrotor modes`` gives modal masses at a station; for the seed rotor's first mode at
    midspan, the closed form of the two-field model's first mode: ``m = 1 / u^2`` with the mode
    ``[v, psi]`` of the 2x2 pencil ``(K - w^2 M)`` of mode 1 mass-normalised (independent of
    the FE-free eigen-solver: solved here with numpy on rubrotor.rotors.shaft.modal_matrices)."""
    from rubrotor.cli import main
    from rubrotor.rotors.shaft import modal_matrices

    assert main(["modes", "seed_rotor.toml", "--json", "--speed", "0", "--station", "0.2"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert "phi^T M phi = 1" in out["modal_mass_normalisation"]
    first = out["modal_masses"][0]
    shaft = rubrotor.load_scenario("seed_rotor.toml").shaft
    b = modal_matrices(shaft, 1)
    m, k = b.M.real, b.K.real
    w2, vec = np.linalg.eig(np.linalg.solve(m, k))
    j = int(np.argmin(w2.real))
    v = vec[:, j].real
    v = v / math.sqrt(v @ m @ v)  # phi^T M phi = 1; the sine is 1 at midspan
    assert first["station_m"] == 0.2
    assert first["modal_mass_kg"] == pytest.approx(1 / v[0] ** 2, rel=1e-9)
    assert first["modal_stiffness_N_per_m"] == pytest.approx(w2[j].real / v[0] ** 2, rel=1e-9)
    assert main(["modes", "general_rotor.toml"]) == 0
    text = capsys.readouterr().out
    assert "modal mass (kg)" in text and "phi^T M phi = 1" in text


def test_cli_stability_round_off_is_neutral(capsys):
    """Undamped whirls of the pressed seed rotor come out at |growth| ~ 1e-11 1/s (round-off of
    eigenvalues ~1e5 rad/s); they are "neutral", and the friction-driven seed-eq1 whirls (growth
    ~ +1e-2 1/s, 500 times the tolerance of 2e-5 1/s) stay "unstable"."""
    from rubrotor.cli import main

    args = ["stability", "seed_case1.toml", "--indentation", "1e-6", "--no-friction", "--json"]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    for r in out["results"]:
        growth = np.array([e[0] for e in r["eigenvalues"]])
        tol = r["growth_tolerance_per_s"]
        assert 1e-7 < tol < 1e-3
        small = np.abs(growth) < tol
        assert small.any()
        assert all(v == "neutral" for v, s in zip(r["verdicts"], small, strict=True) if s)
        assert r["unstable"] == bool((growth > tol).any())
    eq1 = [r for r in out["results"] if r["formulation"] == "seed-eq1"][0]
    assert eq1["unstable"] and eq1["max_growth_rate_per_s"] > 100 * eq1["growth_tolerance_per_s"]


def _shipped_text(name: str) -> str:
    from importlib import resources

    return (resources.files("rubrotor") / "scenarios" / name).read_text()


def test_cli_run_up_needs_no_dt(tmp_path, capsys):
    """A run-up without ``dt`` runs with the default step of the highest retained mode and the
    contact stiffness. Reference: the steps the shipped files set by hand and were validated
    with (seal_rub 2e-5 s, 16 modes; runup_rub 5e-5 s, every mode): the default lies within
    25 % of each (2.14e-5 and 4.57e-5 s measured), and the run's saved samples are spaced by
    that default times ``save_every``."""
    from rubrotor.cli import main
    from rubrotor.engine.general import _system, default_step
    from rubrotor.engine.result import load_dataset

    for name, hand in (("seal_rub.toml", 2e-5), ("runup_rub.toml", 5e-5)):
        sc = rubrotor.load_scenario(name)
        top = sc.engine.speed_end or sc.speed
        dt = default_step(_system(sc, sc.simulation.probes), sc.engine, top)
        assert 0.8 < dt / hand < 1.25, (name, dt)
    text = _shipped_text("runup_rub.toml").replace("dt = 5e-5", "").replace(
        "duration = 1.0", "duration = 0.02").replace("to = 450.0", "to = 160.0")  # fmt: skip
    f = tmp_path / "runup.toml"
    f.write_text(text)
    assert main(["simulate", str(f), "--out", str(tmp_path / "r.nc")]) == 0
    capsys.readouterr()
    ds = load_dataset(tmp_path / "r.nc")
    sc = rubrotor.load_scenario(f)
    dt = default_step(_system(sc, sc.simulation.probes), sc.engine, 160.0)
    assert ds.attrs["status"] == "complete"
    assert float(ds.time[1] - ds.time[0]) == pytest.approx(2 * dt, rel=1e-9)


DROP = """
[materials.steel]
youngs_modulus = 211e9
poisson_ratio = 0.3
density = 7810
[[section]]
length = 1.0
diameter = 0.05
material = "steel"
[[disk]]
position = 0.5
mass = 10.0
[[bearing]]
position = 0.0
kyy = 1e12
kzz = 1e12
[[bearing]]
position = 1.0
kyy = 1e12
kzz = 1e12
[rotor]
theory = "euler-bernoulli"
[speed]
rad_per_s = 100.0
[initial]
state = "given"
positions = [0.5]
v = [1e-4]
w_dot = [0.02]
[simulation]
duration = 0.001
dt = 1e-5
probes = [0.5, 0.25]
"""


def test_cli_initial_given_state(tmp_path, capsys):
    """``[initial] state = "given"``: the run starts at the given deflection and velocity at the
    station, in the static deflection line of a point load there. Closed form: a pinned-pinned
    Euler-Bernoulli beam loaded at midspan deflects at L/4 by 11/16 of its midspan deflection
    (bearings 1e12 N/m: their compliance moves the ratio by ~1e-7; cubic elements are exact for
    nodal point loads); the velocity shape is the same line."""
    from rubrotor.cli import main
    from rubrotor.engine.result import load_dataset

    f = tmp_path / "drop.toml"
    f.write_text(DROP)
    assert main(["simulate", str(f), "--out", str(tmp_path / "d.nc")]) == 0
    capsys.readouterr()
    ds = load_dataset(tmp_path / "d.nc").isel(time=0)
    mid, quarter = (list(ds.station.values).index(x) for x in (0.5, 0.25))
    assert float(ds.v[mid]) == pytest.approx(1e-4, rel=1e-9)
    assert float(ds.w_dot[mid]) == pytest.approx(0.02, rel=1e-9)
    assert abs(float(ds.w[mid])) < 1e-12 and abs(float(ds.v_dot[mid])) < 1e-9
    assert float(ds.v[quarter]) / 1e-4 == pytest.approx(11 / 16, rel=1e-5)
    assert float(ds.w_dot[quarter]) / 0.02 == pytest.approx(11 / 16, rel=1e-5)
    bad = {"v = [1e-4]": "v = [1e-4, 0.0]", 'state = "given"': 'state = "rest"',
           "positions = [0.5]": "positions = [1.5]"}  # fmt: skip
    for old, new in bad.items():
        f.write_text(DROP.replace(old, new))
        assert main(["simulate", str(f), "--out", str(tmp_path / "x.nc")]) == 2
        err = capsys.readouterr().err
        assert "initial." in err and err.count("\n") == 1, err


def test_cli_errors_say_which_table(tmp_path, capsys):
    """An error in the second ``[[contact]]`` table names it as such, counted from 1."""
    from rubrotor.cli import main

    text = _shipped_text("seal_rub.toml")
    second = text[text.index("[[contact]]"):text.index("[initial]")].replace(
        "friction = 0.1", "friction = -0.1").replace("position = 0.75", "position = 0.5")  # fmt: skip
    f = tmp_path / "two.toml"
    f.write_text(text.replace("[initial]", second + "\n[initial]"))
    assert main(["modes", str(f)]) == 2
    err = capsys.readouterr().err
    assert "contact[2].friction" in err and "the second [[contact]] table, counted from 1" in err


def test_cli_continue_says_where_and_why_it_stops(tmp_path, capsys):
    """``rubrotor continue`` without ``--json`` prints a short summary; with too few points it
    says so in the JSON (``stopped``, ``complete``) and in one warning line on stderr. On the
    one-mode annular rub from 1.3 to 1.45 x critical the default (turning-controlled) step
    reaches the end of the range."""
    from rubrotor.cli import main

    base = ["continue", "one_mode_annular_rub.toml", "--vary", "speed.critical_multiple=1.3:1.45",
            "--out", str(tmp_path / "b.nc")]  # fmt: skip
    assert main(base) == 0
    out, err = capsys.readouterr()
    assert "reached the end of the range" in out and "wrote" in out and "warning" not in err
    assert main(base + ["--points", "4", "--json"]) == 0
    out, err = capsys.readouterr()
    summary = json.loads(out)
    assert summary["stopped"] == "points" and summary["complete"] is False
    assert len(summary["points"]) == 4 and summary["points"][-1]["value"] < 1.45
    assert err.count("\n") == 1 and "warning" in err and "--points 4" in err


def test_cli_stability_reads_contact_tables(tmp_path, capsys):
    """``rubrotor stability`` on a general rotor's ``[[contact]]`` table. Second route: without
    friction and with a rigid stator, a linear contact pressed in by ``eps`` along y is a
    bearing at the station with ``kyy = k``, ``kzz = F_n0 / (g + eps) = k eps / (g + eps)``
    (the normal force turning with the position) and ``cyy = c``: the damped modes of the rotor
    with that ``[[bearing]]`` (assembled by the FE rotor, eigenvalues by
    rubrotor.linear.modes) equal the pressed-contact eigenvalues of the rotor with a bearing
    of zero coefficients there (the same mesh) to 1e-8."""
    from rubrotor.cli import main
    from rubrotor.linear.verbs import damped_modes

    text = _shipped_text("seal_rub.toml")
    rigid = "\n".join(line for line in text.splitlines() if not line.startswith("stator_"))
    eps, k, c, g = 5e-6, 2e8, 500.0, 40e-6

    def bearing(kyy, kzz, cyy):  # at the seal: the same mesh for both routes
        return f"[[bearing]]\nposition = 0.75\nkyy = {kyy}\nkzz = {kzz}\ncyy = {cyy}\n\n[rotor]"

    f = tmp_path / "rigid.toml"
    f.write_text(rigid.replace("[rotor]", bearing(0.0, 0.0, 0.0), 1))
    assert main(["stability", str(f), "--indentation", str(eps), "--no-friction", "--json",
                 "--top", "400"]) == 0  # fmt: skip
    res = json.loads(capsys.readouterr().out)["results"][0]
    assert res["formulation"] == "general" and res["normal_force_N"] == pytest.approx(k * eps)
    (tmp_path / "b.toml").write_text(
        rigid.replace("[rotor]", bearing(k, k * eps / (g + eps), c), 1)
    )
    ref = damped_modes(rubrotor.load_scenario(tmp_path / "b.toml"), n=8).modes
    got = np.array([complex(e[0], 2 * math.pi * abs(e[1])) for e in res["eigenvalues"]])
    for mode in ref:  # each reference eigenvalue (Im >= 0) has its twin
        lam = complex(mode.eigenvalue.real, abs(mode.eigenvalue.imag))
        assert np.min(np.abs(got - lam)) < 1e-8 * abs(lam), mode


def test_cli_sweep_without_exponents_calls_nothing_chaotic(tmp_path, capsys):
    """The one-mode chaotic rub (largest Lyapunov exponent +0.7 per revolution,
    tests/test_bifurcation.py) swept without ``--lyapunov``: no period, a broadband spectrum, and
    no exponent to call it chaotic, so "aperiodic" (the spectral rule used to say "chaotic")."""
    from rubrotor.cli import main

    args = ["sweep", "one_mode_chaotic_rub.toml", "--vary", "speed.critical_multiple=1.5:1.5:1",
            "--transient", "100", "--revolutions", "200", "--workers", "1",
            "--out", str(tmp_path / "c.zarr")]  # fmt: skip
    assert main(args) == 0
    assert json.loads(capsys.readouterr().out)["regimes"] == {"aperiodic": 1}


def test_cli_initial_given_by_modes(tmp_path, capsys):
    """``[initial] state = "given"`` with ``modes`` and ``amplitudes``: the first undamped mode
    of a uniform pinned-pinned Euler-Bernoulli shaft is ``sin(pi x / L)``, so started with
    amplitude ``a`` (its largest deflection) the shaft deflects by ``a`` at midspan and by
    ``a sin(pi / 4)`` at a quarter span (cubic elements: 1e-5 relative on this mesh); a mode
    number beyond the model is refused naming ``initial.modes``."""
    from rubrotor.cli import main
    from rubrotor.engine.result import load_dataset

    text = DROP.replace("[[disk]]\nposition = 0.5\nmass = 10.0\n", "").replace(
        "positions = [0.5]\nv = [1e-4]\nw_dot = [0.02]", "modes = [1]\namplitudes = [1e-4]")  # fmt: skip
    f = tmp_path / "mode.toml"
    f.write_text(text)
    assert main(["simulate", str(f), "--out", str(tmp_path / "m.nc")]) == 0
    capsys.readouterr()
    ds = load_dataset(tmp_path / "m.nc").isel(time=0)
    r = np.hypot(ds.v.values, ds.w.values)
    mid, quarter = (list(ds.station.values).index(x) for x in (0.5, 0.25))
    assert r[mid] == pytest.approx(1e-4, rel=1e-5)
    assert r[quarter] == pytest.approx(1e-4 * math.sin(math.pi / 4), rel=1e-5)
    f.write_text(text.replace("modes = [1]", "modes = [100000]"))
    assert main(["simulate", str(f), "--out", str(tmp_path / "x.nc")]) == 2
    assert "initial.modes" in capsys.readouterr().err
