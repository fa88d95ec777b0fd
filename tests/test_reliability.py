"""Nothing silently wrong under faults and bad input (issue 32), one section per numbered item.

Each test reproduces one finding of the issue (it failed before the fix: a traceback, a NaN with
exit 0, a hang, a wrong key) and checks the promise instead: exit 0 with finite output, exit 2
with one line naming the key, or exit 1 with the data kept and marked partial with a reason.
References: the compiled free-spin kernel called once over the whole run (the chunked driver
must take exactly its steps); the stability limit of the Dormand-Prince pair (3.3 / rate, Hairer
and Wanner vol. 1, IV.2) for the step counts a run needs.
"""

from __future__ import annotations

import math
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from test_mangled_scenarios import _dump

from rubrotor.cli import main

SCENARIOS = Path(str(resources.files("rubrotor") / "scenarios"))


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("rubrotor: error:"), err
    return lines[0]


def _scenario(tmp_path, name, edit=None, file="x.toml") -> Path:
    doc = tomllib.loads((SCENARIOS / f"{name}.toml").read_text())
    if edit is not None:
        edit(doc)
    path = tmp_path / file
    path.write_text(_dump(doc))
    return path


# ---- 1. free-speed runs -----------------------------------------------------------------------
def _drop(tmp_path, table, key, value, duration=0.05):
    """touchdown_drop.toml, ``duration`` s, with ``table.key = value`` (every contact's)."""

    def edit(doc):
        doc["simulation"]["duration"] = duration
        rows = doc[table] if isinstance(doc[table], list) else [doc[table]]
        for row in rows:
            row[key] = value

    return _scenario(tmp_path, "touchdown_drop", edit)


UNRESOLVABLE = [
    ("contact", "friction", 1e300, "contact[2].friction"),
    ("contact", "stiffness", 1e300, "contact[2].stiffness"),
    ("contact", "damping", 1e300, "contact[2].damping"),
    ("unbalance", "magnitude", 1e300, "unbalance.magnitude"),
    ("speed", "drag", 1e9, "speed.drag"),
    ("contact", "ring_drag", 1e9, "contact[1].ring_drag"),
    ("contact", "ring_radius", 1000.0, "contact[2].ring_radius"),
    ("contact", "radius", 1000.0, "radius"),
    ("contact", "friction", 1e6, "contact[2].friction"),
    ("unbalance", "magnitude", 1e3, "unbalance.magnitude"),
    ("simulation", "duration", 1e300, "simulation.duration"),
    ("simulation", "sample_rate", 1e300, "simulation.sample_rate"),
    ("simulation", "sample_rate", 1e9, "simulation.sample_rate"),
]


@pytest.mark.parametrize("table, key, value, named", UNRESOLVABLE)
def test_free_speed_run_beyond_resolution_is_refused_by_key(table, key, value, named, tmp_path,
                                                            capsys):  # fmt: skip
    """Before: exit 0 with NaN, a ValueError/MemoryError traceback, or minutes at full CPU."""
    path = _drop(tmp_path, table, key, value)
    assert main(["simulate", str(path), "--out", str(tmp_path / "o.nc")]) == 2
    line = _one_error_line(capsys)
    assert named in line and ("steps" in line or "memory" in line), line
    assert not (tmp_path / "o.nc").exists()


def _spin_problem(tmp_path, edit=None):
    from rubrotor.engine.spin import free_problem
    from rubrotor.scenario.load import load_scenario

    def short(doc):
        doc["simulation"]["duration"] = 0.03
        if edit:
            edit(doc)

    return free_problem(load_scenario(_scenario(tmp_path, "touchdown_drop", short)))


def test_chunked_free_spin_takes_the_steps_of_one_kernel_call(tmp_path, monkeypatch):
    """The driver calls the kernel a chunk at a time (progress, Ctrl-C, finite checks between
    chunks); the kernel hands back its next step, so the run is the single call's to the bit."""
    import rubrotor.core.spin as kernel
    import rubrotor.engine.spin as spin
    from rubrotor.core.spin import spin_dopri

    system, kw, _ = _spin_problem(tmp_path)
    calls = []

    def single(x0, t_out, *args):
        calls.append(t_out.size)
        return spin_dopri(x0, t_out, *args)

    monkeypatch.setattr(kernel, "spin_dopri", single)
    chunked = spin.simulate_spin(system, **kw)
    assert len(calls) > 3 and chunked.status == "complete"
    # reference: one call over every output time
    res = {}

    def run_chunks(kernel, x0, t_out, args, ctrl, rows, show, diagnose):
        out = np.zeros((rows, t_out.size))
        ist = np.zeros(4, np.int64)
        spin_dopri(np.ascontiguousarray(x0), t_out, *args, ctrl.copy(), out, ist)
        res["ist"] = ist
        return out[:, : ist[3]], (int(ist[1]), int(ist[2])), ""

    monkeypatch.setattr(spin, "run_chunks", run_chunks)
    whole = spin.simulate_spin(system, **kw)
    assert np.array_equal(chunked.state, whole.state)
    assert np.array_equal(chunked.contact, whole.contact)
    assert chunked.stats["accepted"] == whole.stats["accepted"] == res["ist"][1]


def test_non_finite_state_is_never_complete(tmp_path, monkeypatch):
    """An overflowing run (stiffness 1e300, the a-priori refusal lifted) stops partial, naming
    the stiffest term, with only finite samples kept. Before: "complete" with NaN outputs."""
    import rubrotor.engine.spin as spin

    monkeypatch.setattr(spin, "refuse_unresolvable", lambda *a: None)
    system, kw, _ = _spin_problem(tmp_path, lambda d: [c.update(stiffness=1e300)
                                                        for c in d["contact"]])  # fmt: skip
    res = spin.simulate_spin(system, **kw)
    assert res.status == "partial"
    assert "contact[" in res.message and ".stiffness" in res.message, res.message
    assert np.all(np.isfinite(res.state)) and np.all(np.isfinite(res.contact))
    assert res.time.size >= 1


def test_run_that_becomes_too_stiff_stops_partial_naming_the_key(tmp_path):
    """A budget of steps below what the drop needs: the run projects its steps from the last
    chunk and stops partial before exceeding them, naming the stiffest term at that time."""
    from rubrotor.engine.spin import simulate_spin

    system, kw, _ = _spin_problem(tmp_path)
    res = simulate_spin(system, **kw, max_steps=800)
    assert res.status == "partial" and "too many steps" in res.message
    assert "contact[" in res.message and res.stats["accepted"] + res.stats["rejected"] <= 801  # the kernel stops at the first step past it
    assert 1 < res.time.size < 601 and np.all(np.isfinite(res.state))


def test_ctrl_c_keeps_a_partial_free_spin_run(tmp_path, monkeypatch, capsys):
    """Ctrl-C between chunks: the data so far saved, marked partial, exit 1. Before: the kernel
    ran to the end in one call and Ctrl-C did nothing."""
    import rubrotor.core.spin as kernel
    from rubrotor.core.spin import spin_dopri

    calls = []

    def interrupted(*args):
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return spin_dopri(*args)

    monkeypatch.setattr(kernel, "spin_dopri", interrupted)
    path = _drop(tmp_path, "speed", "drag", 0.0, duration=0.03)
    out = tmp_path / "o.nc"
    assert main(["simulate", str(path), "--out", str(out)]) == 1
    assert "interrupted by the user" in capsys.readouterr().err
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == "partial" and 1 < ds.sizes["time"] < 601
        assert np.all(np.isfinite(ds["v"].values))


def test_dopri_stability_limit_is_the_one_the_guard_uses():
    """The guard's 3.3 / rate: the Dormand-Prince pair's stability function |R(z)| = 1 on the
    negative real axis near z = -3.31 (computed here from its tableau)."""
    from rubrotor.core.spin import _A, _B
    from rubrotor.engine.spin_guard import STABILITY

    def R(z):
        k = np.zeros(7, complex)
        for s in range(7):
            k[s] = z * (1 + _A[s, :s] @ k[:s]) if s else z
        return 1 + _B @ k

    zs = np.linspace(-2.5, -4.0, 15001)
    edge = zs[np.argmax(np.abs([R(z) for z in zs]) > 1.0)]
    assert math.isclose(-edge, STABILITY, rel_tol=0.01), edge


# ---- 3. level1 ---------------------------------------------------------------------------------
def _level1_rotor():
    """A 1.2 m shaft, two 20 kg disks, two damped bearings (36 DOF): its first forward mode's
    log dec at 900 rad/s crosses zero near 5.8e4 N/m and the next mode runs close to it."""
    from test_api_checks import STEEL

    from rubrotor.rotors.fe import Bearing, Disk, Rotor, Section

    bearings = [Bearing(x, kyy=5e7, kzz=4e7, cyy=2e4, czz=2e4) for x in (0.05, 1.15)]
    rotor = Rotor([Section(1.2, 0.06, STEEL, elements=6)], bearings=bearings,
                  disks=[Disk(0.4, 20.0, 0.2, 0.1), Disk(0.8, 20.0, 0.2, 0.1)])  # fmt: skip
    return rotor.linear_system((0.6,))


def test_level1_q0_does_not_depend_on_the_grid():
    """Before: 2 points gave a log dec of +0.27 at 1e8 N/m (another mode) and no Q0, 5 points
    Q0 = 3.4e4, 50 points 5.80e4. The mode is followed through its own Q values and Q0 located
    by root finding: the same Q0 (to 1e-6) and the same log dec at 1e8 on 2, 5 and 50 points;
    the log dec at Q0 is zero and the mode at Q0 is the one followed on the finest grid."""
    from rubrotor.linear.api684 import level1

    system = _level1_rotor()
    runs = [level1(system, 900.0, 0.6, np.logspace(4, 8, n)) for n in (2, 5, 50)]
    q0 = runs[-1].q0
    assert q0 is not None and all(r.q0 == pytest.approx(q0, rel=1e-6) for r in runs)
    assert all(r.log_dec[-1] == pytest.approx(runs[-1].log_dec[-1], rel=1e-9) for r in runs)
    near = level1(system, 900.0, 0.6, [q0 * (1 - 1e-6), q0 * (1 + 1e-6)])
    assert near.log_dec[0] > 0 >= near.log_dec[1] and abs(near.log_dec).max() < 1e-5


def test_level1_jeffcott_q0_by_root_finding_on_two_points():
    """Reference: Q0 = c sqrt(k / m) (the closed form of test_api_checks) from 2 points."""
    from test_api_checks import _jeffcott

    from rubrotor.linear.api684 import level1

    m, k, c = 2.0, 8e4, 20.0
    res = level1(_jeffcott(m, k, c), 100.0, 0.0, [1e2, 1e4])
    assert res.q0 == pytest.approx(c * math.sqrt(k / m), rel=1e-9)


def test_level1_refuses_stiffness_past_the_followed_range(capsys):
    """Before: --stiffness 1e300:1e301:3 ran and gave a constant log dec."""
    from rubrotor.errors import InputError
    from rubrotor.linear.api684 import level1

    with pytest.raises(InputError, match="followed"):
        level1(_level1_rotor(), 900.0, 0.6, [1e4, 1e300])
    seal = str(SCENARIOS / "seal_rub.toml")
    assert main(["level1", seal, "--stiffness", "1e300:1e301:3"]) == 2
    assert "--stiffness" in _one_error_line(capsys)


# ---- 2. thermal --------------------------------------------------------------------------------
THERMAL = SCENARIOS / "thermal_rub.toml"


def _thermal(tmp_path, **contact):
    return _scenario(tmp_path, "thermal_rub", lambda d: d["contact"][0].update(contact))


def test_thermal_without_a_growth_rate_says_why_and_exits_1(tmp_path, capsys):
    """Before: contact stiffness 1e7 N/m gave growth null with exit 0 and no message. At
    300 rad/s the rub has no bounded steady orbit (the run from the no-contact orbit diverges):
    the value stays null, the JSON and stderr say why, exit 1."""
    import json

    path = _thermal(tmp_path, stiffness=1e7)
    assert main(["thermal", str(path), "--speeds", "300:310:2", "--steps", "64", "--json"]) == 1
    io = capsys.readouterr()
    out = json.loads(io.out)
    assert out["growth_rate_per_s"][0] is None and "300 rad/s" in out["reasons"][0]
    assert "contact.stiffness" in io.err and "no growth rate at 300 rad/s" in io.err


def test_thermal_runaway_reports_the_time_it_ran_away(tmp_path, capsys):
    """Before: a 1000 h slow run reported "runaway" at end_time_s 0.0 (the last output sample
    before the event). The last sample is now the runaway itself: the bow there is the limit
    (50 clearances, slow_run's max_bow), the time inside (0, duration), exit 1 with a reason."""
    import json

    out = tmp_path / "s.nc"
    args = ["thermal", str(THERMAL), "--simulate", "1000", "--out", str(out), "--samples", "3",
            "--steps", "64", "--json"]  # fmt: skip
    assert main(args) == 1
    io = capsys.readouterr()
    summary = json.loads(io.out)
    assert summary["status"] == "runaway" and 0 < summary["end_time_s"] < 1000 * 3600
    assert "runaway" in io.err and "data kept" in io.err
    with xr.open_dataset(out) as ds:
        bow = np.hypot(ds.bow_real.values[-1], ds.bow_imag.values[-1]).max()
        assert bow == pytest.approx(50 * 30e-6, rel=1e-6)
        assert ds["time"].values[-1] == pytest.approx(summary["end_time_s"])


# ---- 4. unbalance and modes --------------------------------------------------------------------
def test_unbalance_overflowing_magnitude_is_named(tmp_path, capsys):
    """Before: ``unbalance --json`` with a magnitude of 1e300 printed NaN with exit 0."""
    path = _scenario(tmp_path, "seal_rub", lambda d: d["unbalance"][0].update(magnitude=1e300))
    assert main(["unbalance", str(path), "--json", "--speeds", "10:600:5", "--probe", "0.45"]) == 2
    assert "unbalance.magnitude = 1e+300" in _one_error_line(capsys)
    assert capsys.readouterr().out == ""


def test_json_never_holds_a_non_finite_number(capsys):
    from rubrotor.cli.common import print_json
    from rubrotor.errors import RubrotorError

    with pytest.raises(RubrotorError, match=r"not finite at a\.b\[1\]"):
        print_json({"a": {"b": [1.0, math.nan]}})
    print_json({"a": [1.0, None]})
    assert capsys.readouterr().out.count("1.0") == 1


def test_modes_survive_an_arpack_failure(monkeypatch):
    """Before: ``modes`` with a density of 1e-9 raised ArpackError in 2 of 4 runs (its random
    start vector). When ARPACK fails the dense route answers; reference: the dense eigenvalues
    of the same first-order matrix (scipy.linalg.eig)."""
    import scipy.linalg
    import scipy.sparse.linalg

    import rubrotor.linear.modes as modes
    from rubrotor.linear.verbs import linear_system
    from rubrotor.scenario.load import load_scenario

    def fails(*a, **k):
        raise scipy.sparse.linalg.ArpackNoConvergence("no convergence", [], [])

    monkeypatch.setattr(modes, "_newton_eig", lambda *a: None)
    monkeypatch.setattr(scipy.sparse.linalg, "eigs", fails)
    system = linear_system(load_scenario(SCENARIOS / "touchdown_drop.toml"))
    got = modes.damped_modes(system, 500.0, n=4)
    lam = scipy.linalg.eigvals(system.matrices(500.0).first_order()[0])
    lam = lam[lam.imag > 0]
    ref = np.sort(np.abs(lam))[:4]
    np.testing.assert_allclose(np.sort([abs(m.eigenvalue) for m in got.modes]), ref, rtol=1e-9)
