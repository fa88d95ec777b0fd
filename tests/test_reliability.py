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
    # refused by key: by the plausibility checks at loading (an eccentricity beyond the rotor)
    # or, past them, by the run's resolution or memory checks
    assert named in line and any(w in line for w in ("steps", "memory", "implausible")), line
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
    assert len(calls) > 1 and chunked.status == "complete"  # chunked (the count depends on the machine)
    # reference: one call over every output time
    res = {}

    def run_chunks(kernel, x0, t_out, args, ctrl, rows, show, diagnose):
        out = np.zeros((rows, t_out.size))
        ist = np.zeros(4, np.int64)
        spin_dopri(np.ascontiguousarray(x0), t_out, *args, ctrl.copy(), (out, ist))
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
    line = _one_error_line(capsys)  # the plausibility checks name the table: unbalance[1]
    assert "unbalance.magnitude = 1e+300" in line or "unbalance[1].magnitude = 1e+300" in line
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


# ---- 5. restart files --------------------------------------------------------------------------
@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    """A one-revolution seal_rub results file (in memory, one restart row) and its scenario."""
    from test_stream_restart import seal_text, write

    import rubrotor
    from rubrotor.engine.general import simulate_engine
    from rubrotor.scenario.load import load_scenario

    tmp = tmp_path_factory.mktemp("restart")
    first = tmp / "first.nc"
    scen = load_scenario(write(tmp, "a.toml", seal_text(revolutions=1)))
    rubrotor.save_dataset(simulate_engine(scen, progress=False), first)
    return tmp, first


def _restart_of(tmp, path, edit=lambda t: t, name="b.toml"):
    from test_stream_restart import seal_text, write

    return write(tmp, name, edit(seal_text(initial=f'state = "file"\npath = "{path}"',
                                           revolutions=1)))  # fmt: skip


def _damaged(tmp, first, name, change):
    """A copy of ``first`` with ``change(ds)`` applied (an xarray Dataset, loaded)."""
    with xr.open_dataset(first) as ds:
        ds = ds.load()
    change(ds)
    out = tmp / name
    ds.to_netcdf(out)
    return out


def _refusal(path, capsys) -> str:
    out = path.with_name(path.stem + "_continued.nc")
    assert main(["simulate", str(path), "--out", str(out)]) == 2
    return _one_error_line(capsys)


def _drop_rows(ds):
    """The file of a run killed before its first chunk: restart variables without rows."""
    del ds.attrs["final_state"]
    vec, t = ds["restart_vector"], ds["restart_time"]
    del ds["restart_vector"], ds["restart_time"]
    ds["restart_vector"] = (vec.dims, vec.values[:0], vec.attrs)
    ds["restart_time"] = (t.dims, t.values[:0], t.attrs)


RESTART_DAMAGE = [
    # killed before its first restart row (before: KeyError: 'final_state')
    ("no_rows", _drop_rows, "stopped before its first chunk"),
    ("no_layout", lambda ds: ds["restart_vector"].attrs.pop("layout"), "layout"),  # KeyError
    ("no_speed", lambda ds: ds.attrs.pop("speed_rad_s"), "speed_rad_s"),  # KeyError
    ("negative_time", lambda ds: ds["restart_time"].values.__setitem__(-1, -5.0),
     ">= 0 s"),  # before: started at t = -5 s
    ("nan_time", lambda ds: ds["restart_time"].values.__setitem__(-1, math.nan),
     ">= 0 s"),  # before: NaN named unbalance.phase
    ("flipped_byte", lambda ds: ds["restart_vector"].values.__setitem__(
        (-1, 3), ds["restart_vector"].values[-1, 3] * (1 + 2**-40)), "checksum"),
]  # fmt: skip


@pytest.mark.parametrize("name, change, says", RESTART_DAMAGE, ids=[d[0] for d in RESTART_DAMAGE])
def test_damaged_restart_file_is_refused_naming_initial_path(name, change, says, first_run,
                                                              capsys):  # fmt: skip
    tmp, first = first_run
    bad = _damaged(tmp, first, f"{name}.nc", change)
    line = _refusal(_restart_of(tmp, bad, name=f"{name}.toml"), capsys)
    assert "initial.path" in line and says in line, line


@pytest.mark.parametrize("key, value", [("stiffness", 3e8), ("friction", 0.2)])
def test_restart_with_another_contact_force_is_refused(key, value, first_run, capsys):
    """Before: a changed contact stiffness or friction was not in the fingerprint."""
    import re

    tmp, first = first_run

    def edit(text):
        table = text[text.index("[[contact]]"):]
        changed = re.sub(rf"(?m)^{key} *= *[^\n#]*", f"{key} = {value}", table, count=1)
        assert changed != table
        return text.replace(table, changed)

    line = _refusal(_restart_of(tmp, first, edit, name=f"{key}.toml"), capsys)
    assert f"contact[1].{key} = {value}" in line, line
    assert "readable results file" not in line  # item 8: no longer nested in that refusal


def test_old_layout_file_of_another_model_is_refused(first_run, capsys):
    """A file of the earlier layout (final_state only, no fingerprint) of another rotor with
    the same number of DOF (a bearing's stiffness changed in its stored scenario). Before:
    accepted."""
    tmp, first = first_run

    def old(ds):
        for v in ("restart_time", "restart_vector"):
            del ds[v]
        del ds.attrs["model_fingerprint"]
        ds.attrs["scenario"] = ds.attrs["scenario"].replace("kyy = 8.0e7", "kyy = 9.0e7")

    bad = _damaged(tmp, first, "old.nc", old)
    line = _refusal(_restart_of(tmp, bad, name="old.toml"), capsys)
    assert "initial.path" in line and "[bearing] differs" in line, line


def test_out_equal_to_the_restart_input_is_refused(first_run, capsys):
    """Before: ``--out`` naming the restart input replaced the run with its continuation."""
    tmp, first = first_run
    before = first.read_bytes()
    path = _restart_of(tmp, first, name="same.toml")
    assert main(["simulate", str(path), "--out", str(first)]) == 2
    assert "--out" in _one_error_line(capsys) and first.read_bytes() == before


def test_intact_restart_still_continues(first_run, capsys):
    """The checks pass an intact file: exit 0, the continuation starts at its restart time."""
    tmp, first = first_run
    out = tmp / "cont.nc"
    assert main(["simulate", str(_restart_of(tmp, first, name="ok.toml")), "--out", str(out)]) == 0
    with xr.open_dataset(first) as a, xr.open_dataset(out) as b:
        assert float(b["time"].values[0]) == pytest.approx(float(a["restart_time"].values[-1]))


# ---- 6. tracebacks: encodings, a full disk, Ctrl-C in continue --------------------------------
def test_analyze_of_a_csv_that_is_not_utf8_is_named(tmp_path, capsys):
    """Before: UnicodeDecodeError traceback."""
    bad = tmp_path / "bad.csv"
    bad.write_bytes(b"t,x\n0,1\n\xff\xfe,2\n")
    assert main(["analyze", str(bad), "--out", str(tmp_path / "an") + "/"]) == 2
    line = _one_error_line(capsys)
    assert "input" in line and "UTF-8" in line


def test_out_name_that_is_not_utf8_is_named(tmp_path, capsys):
    """Before: UnicodeEncodeError traceback from netCDF (a file name with a byte 0xff)."""
    import os

    out = os.fsdecode(os.fsencode(str(tmp_path)) + b"/\xff.nc")
    assert main(["simulate", str(SCENARIOS / "seal_rub.toml"), "--revolutions", "1",
                 "--out", out]) == 2  # fmt: skip
    assert "--out" in _one_error_line(capsys)


def _tmpfs(path: Path, size: str):
    """Mount a tmpfs of ``size`` at ``path`` (root only: the test is skipped otherwise)."""
    import os
    import subprocess

    if os.geteuid() != 0:
        pytest.skip("mounting a small tmpfs needs root")
    path.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(path)],
                      capture_output=True).returncode:  # fmt: skip
        pytest.skip("mount -t tmpfs failed")
    return path


@pytest.fixture
def small_disk(tmp_path):
    import subprocess

    disk = _tmpfs(tmp_path / "disk", "24m")
    yield disk
    subprocess.run(["umount", str(disk)], check=False)


def test_full_disk_stops_a_streamed_run_partial_and_says_so(small_disk, monkeypatch, capsys):
    """A real 24 MiB tmpfs. The streamed run's size check is lifted (the disk can fill after the
    start, e.g. by another process); the run streams 6 MiB chunks until the disk cannot take
    the next one. Before: ``RuntimeError: NetCDF: HDF error`` and an unreadable file. Now:
    "no space left on device", exit 1, and the file readable, partial, with its chunks."""
    import rubrotor.engine.driver as driver
    import rubrotor.engine.general as general

    monkeypatch.setattr(general, "STREAM_SAMPLES", 20000)
    monkeypatch.setattr(general, "check_size", lambda *a, **k: None)
    monkeypatch.setattr(driver, "check_size", lambda *a, **k: None)
    out = small_disk / "s.nc"
    argv = ["simulate", str(SCENARIOS / "seal_rub.toml"), "--revolutions", "300", "--out",
            str(out), "--no-progress"]  # fmt: skip
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert "no space left on device" in err and "kept, partial" in err
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == "partial" and "no space left" in ds.attrs["status_message"]
        assert ds.sizes["time"] > 1 and ds.sizes["checkpoint"] >= 1
        assert np.all(np.isfinite(ds["v"].values))


def test_full_disk_for_an_in_memory_result_says_so(tmp_path, capsys):
    """A 1 MiB tmpfs and a 20-revolution seal_rub result (more than 1 MiB). Before: the
    NetCDF HDF error traceback. Now "no space left on device", exit 1, no file left behind."""
    import subprocess

    disk = _tmpfs(tmp_path / "tiny", "1m")
    try:
        out = disk / "a.nc"
        argv = ["simulate", str(SCENARIOS / "seal_rub.toml"), "--revolutions", "20", "--out",
                str(out)]  # fmt: skip
        assert main(argv) == 1
        assert "no space left on device" in capsys.readouterr().err
        assert list(disk.iterdir()) == []
    finally:
        subprocess.run(["umount", str(disk)], check=False)


def test_ctrl_c_in_continue_keeps_the_branch_so_far(tmp_path, monkeypatch, capsys):
    """Before: KeyboardInterrupt traceback. Ctrl-C after the third branch point: the branch so
    far is written, the JSON says why it stopped, exit 1."""
    import json

    from test_continuation import HYST_TOML, KEY

    import rubrotor.orbits.continuation as cont

    real = cont._point
    calls = []

    def point(*a, **k):
        calls.append(1)
        if len(calls) == 4:
            raise KeyboardInterrupt
        return real(*a, **k)

    monkeypatch.setattr(cont, "_point", point)
    scen = tmp_path / "hyst.toml"
    scen.write_text(HYST_TOML)
    out = tmp_path / "b.nc"
    args = ["continue", str(scen), "--vary", f"{KEY}=1.8:1.5", "--out", str(out), "--json",
            "--points", "30"]  # fmt: skip
    assert main(args) == 1
    summary = json.loads(capsys.readouterr().out)
    assert summary["stopped"] == "interrupted" and len(summary["points"]) == 3
    assert out.exists()


# ---- 7. the output lock ------------------------------------------------------------------------
HOLD = """
import sys, time
from rubrotor.errors import InputError
from rubrotor.engine.output import claim_output
start = float(sys.argv[2])
while time.time() < start:
    pass
try:
    with claim_output(sys.argv[1]):
        t0 = time.time()
        time.sleep(3.0)
        t1 = time.time()
    print("held", t0, t1, flush=True)
except InputError:
    print("refused", flush=True)
"""


def test_simultaneous_starts_give_the_lock_to_one_run(tmp_path):
    """Before: 1 of 14 simultaneous starts both got the lock (a lock file created but not yet
    written was read as empty, hence stale). 14 processes released at one instant, each
    holding the lock for 3 s: no two hold it at the same time (a process slowed past the
    first one's release may take it after), the others are refused; twice."""
    import os
    import subprocess
    import sys
    import time

    import rubrotor

    env = dict(os.environ, PYTHONPATH=str(Path(rubrotor.__file__).parents[1]))
    for trial in range(2):
        target = tmp_path / f"r{trial}.nc"
        start = time.time() + 4.0  # every interpreter up and waiting by then, on a calm host
        procs = [subprocess.Popen([sys.executable, "-c", HOLD, str(target), str(start)],
                                  stdout=subprocess.PIPE, env=env) for _ in range(14)]  # fmt: skip
        said = [p.communicate(timeout=120)[0].decode().split() for p in procs]
        held = sorted((float(s[1]), float(s[2])) for s in said if s[0] == "held")
        assert len(held) >= 1 and all(s[0] in ("held", "refused") for s in said), said
        assert all(b[0] >= a[1] for a, b in zip(held, held[1:], strict=False)), held


def test_empty_lock_file_of_a_dead_run_is_taken_and_a_live_one_respected(tmp_path):
    """A lock file left empty (a run killed between creating and writing it) is free; a lock
    held by a live claim is refused even though its file's content is not read."""
    from rubrotor.engine.output import claim_output, lock_path
    from rubrotor.errors import InputError

    target = tmp_path / "r.nc"
    lock_path(target).write_text("")
    with claim_output(target):
        with pytest.raises(InputError, match="no other run is writing"):
            with claim_output(target):
                pass
    assert not lock_path(target).exists()


def test_sweep_on_a_scheduler_without_dask_leaves_no_store(tmp_path, monkeypatch, capsys):
    """Before: ``sweep --scheduler`` without Dask distributed left an empty store behind."""
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "distributed" else real(name, *a))  # fmt: skip
    out = tmp_path / "s.zarr"
    case = str(SCENARIOS / "seed_case1.toml")
    argv = ["sweep", case, "--vary", "unbalance.magnitude=1e-4:3e-3:3", "--out", str(out),
            "--scheduler", "tcp://127.0.0.1:1"]  # fmt: skip
    assert main(argv) == 2
    assert "--scheduler" in _one_error_line(capsys) and not out.exists()


# ---- 9. the Python API names the argument ------------------------------------------------------
def _api_calls(tmp_path):
    import xarray

    import rubrotor
    from rubrotor.linear.static import static_analysis

    seal = rubrotor.load_scenario(SCENARIOS / "seal_rub.toml")
    return [
        (lambda: rubrotor.load_scenario(None), "path"),
        (lambda: rubrotor.load_scenario(3), "path"),
        (lambda: rubrotor.simulate(seal, integrator="abc"), "integrator"),
        (lambda: static_analysis(seal, gravity="down"), "gravity"),
        (lambda: static_analysis(seal, gravity=[1.0, [2.0]]), "gravity"),
        (lambda: rubrotor.save_dataset(xarray.Dataset(), "/proc/nope/x.nc"), "path"),
    ]


def test_bad_python_calls_raise_input_error_naming_the_argument(tmp_path):
    """Before: TypeError, AttributeError, ValueError, FileNotFoundError."""
    from rubrotor.errors import InputError

    for call, field in _api_calls(tmp_path):
        with pytest.raises(InputError) as err:
            call()
        assert err.value.field == field, err.value


def test_free_speed_progress_line(tmp_path, monkeypatch, capsys):
    """``--progress`` on a free-speed run prints a progress line between chunks (before: none,
    the kernel ran the whole run in one call). The clock is advanced so that every chunk
    counts as past the 2 s after which the line starts."""
    import itertools

    import rubrotor.engine.spin_guard as guard

    ticks = itertools.count(0.0, 1.0)
    monkeypatch.setattr(guard.time, "perf_counter", lambda: next(ticks))
    path = _drop(tmp_path, "speed", "drag", 0.0, duration=0.03)
    out = tmp_path / "o.nc"
    assert main(["simulate", str(path), "--out", str(out), "--progress"]) == 0
    err = capsys.readouterr().err
    assert "rubrotor:" in err and "% (t = " in err and "s left" in err
