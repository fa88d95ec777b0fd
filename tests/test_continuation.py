"""Pseudo-arclength continuation (rubrotor.orbits.continuation) and ``rubrotor continue``.

References: the one-mode rotor's closed form of tests/test_follow_sweep.py (derived there): the
full-annular-rub branch turns at its fold (largest speed of W(r) over r > g) and meets the
no-contact orbit at contact onset (free radius = g), a non-smooth turning point. The
continuation's turning points are those of the second-order discrete scheme: their error is
measured at two steps per revolution (ratio ~4, order 2) and Richardson-extrapolated, which must
equal the closed form to 1e-6 relative. The up / down state-carrying sweeps (a second, brute-force
route) must jump within one sweep step of the continuation's fold / onset.
"""

from __future__ import annotations

import json
from importlib import resources

import numpy as np
import pytest
from test_follow_sweep import HYST, HYST_TOML, RUNS, _closed_form

from rubrotor.cli import main
from rubrotor.orbits.continuation import continue_orbit
from rubrotor.sweeps.follow import follow_sweep
from rubrotor.sweeps.sweep import regime_labels

KEY = "speed.critical_multiple"


@pytest.fixture(scope="module")
def branches():
    return {
        n: continue_orbit(
            HYST, KEY, 1.8, 1.3, steps=n, points=120, ds=0.05, ds_max=0.5, method="shooting"
        )
        for n in (512, 1024)
    }


def _turns(branch):
    """Contact onset (reported as such, not as a fold) and the rub branch's fold."""
    onset = [b.value for b in branch.bifurcations if b.type == "contact-onset"]
    folds = [b.value for b in branch.bifurcations if b.type == "fold"]
    assert len(onset) == 1 and len(folds) == 1
    return np.array(onset + folds)


def test_folds_equal_closed_form_turning_points(branches):
    _, _, w_fold, w_onset = _closed_form(HYST)
    crit = HYST.speed / 1.3
    exact = np.array([w_onset, w_fold]) / crit
    coarse, fine = _turns(branches[512]), _turns(branches[1024])
    # the smooth fold: second order in the step, Richardson-extrapolated to 1e-6
    ratio = abs(coarse[1] - exact[1]) / abs(fine[1] - exact[1])
    assert 3.5 < ratio < 4.5
    assert (4 * fine[1] - coarse[1]) / 3 == pytest.approx(exact[1], rel=1e-6)
    # contact onset: the corner where the branch turns onto the no-contact orbit is located
    # on the grazing condition of the free orbit (exact propagation, Fourier maximum of the
    # radius, Brent root), not on the smeared difference Jacobian: measured 1e-15 relative
    for b in branches.values():
        assert b.grazings == pytest.approx([exact[0]], rel=1e-12)
    np.testing.assert_allclose([coarse[0], fine[0]], exact[0], rtol=1e-12)
    # the branch goes through contact onset and both folds: unstable between them
    b = branches[1024]
    x = np.array([p.value for p in b.points])
    st = np.array([p.stable for p in b.points])
    assert x[0] == 1.8 and st[0] and st[-1] and not st.all()
    assert not any(bb.type not in ("fold", "contact-onset") for bb in b.bifurcations)


def test_follow_sweep_jumps_at_the_continuation_folds(branches):
    onset, fold = _turns(branches[1024])
    values = np.linspace(1.2, 1.8, 13)
    ds = follow_sweep(HYST, KEY, values, direction="both", workers=2, **RUNS)
    labels = regime_labels(ds)
    up, down = labels[0], labels[1]
    step = values[1] - values[0]
    up_jump = values[np.flatnonzero(up == "no contact")[0]]  # first no-contact point going up
    down_jump = values[np.flatnonzero(down == "full annular rub")[-1]]  # last rub going down
    assert up_jump - step < fold < up_jump
    assert down_jump < onset < down_jump + step


def test_cli_continue(tmp_path, capsys):
    scen = tmp_path / "hyst.toml"
    scen.write_text(HYST_TOML)
    out = tmp_path / "b.nc"
    args = ["continue", str(scen), "--vary", f"{KEY}=1.8:1.5", "--out", str(out), "--json"]
    assert main(args + ["--points", "30"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert set(summary) == {"points", "bifurcations", "stopped", "stopped_because", "complete"}
    p = summary["points"][0]
    assert set(p) == {"value", "max_radius_m", "stable", "multipliers_abs_max"}
    assert p["value"] == 1.8 and p["stable"] is True and p["multipliers_abs_max"] < 1
    assert out.exists()
    for bad in (f"{KEY}=1.8", f"{KEY}=1:1", "nokey=1:2"):
        assert main(["continue", str(scen), "--vary", bad, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("rubrotor: error:")


def test_cli_continue_switches_onto_the_period_doubled_branch(tmp_path, capsys):
    """``--switch period-doubling``: both branches in --out and --json; bad input exits 2.

    References: the shooting module's stroboscopic map applied to the stored states of the
    switched branch (each must be a fixed point of the two-revolution map, to the Newton
    tolerance, and not of the one-revolution map away from the start: a period-2 orbit), and
    the continued branch's own period doubling: the switched branch starts at its value, on
    an orbit that is a fixed point of the one-revolution map there (the branches meet).
    """
    import xarray as xr

    from rubrotor.orbits import shooting
    from rubrotor.scenario import load_scenario

    scen = resources.files("rubrotor") / "scenarios" / "one_mode_partial_rub.toml"
    out = tmp_path / "pd.nc"
    common = ["continue", str(scen), "--out", str(out), "--steps", "256", "--ds-max", "0.05"]
    args = common + ["--vary", f"{KEY}=2.03:2.11", "--points", "14", "--switch",
                     "period-doubling", "--json"]  # fmt: skip
    assert main(args) == 0
    summary = json.loads(capsys.readouterr().out)
    pd = [b["value"] for b in summary["bifurcations"] if b["type"] == "period-doubling"]
    doubled = summary["period_doubled"]
    assert doubled["revolutions_per_period"] == 2 and doubled["start"] == pd[0]
    assert doubled["points"][0]["value"] == pd[0] and len(doubled["points"]) == 14
    with xr.open_dataset(out) as ds:
        ds = ds.load()
    assert ds.attrs["branches"] == 2
    assert list(np.unique(ds["revolutions_per_period"].values)) == [1, 2]
    sw = ds.where(ds["branch"] == 1, drop=True)
    np.testing.assert_array_equal(sw["value"].values, [p["value"] for p in doubled["points"]])
    base = load_scenario(scen)
    split = []
    for value, x in zip(sw["value"].values, sw["state"].values, strict=True):
        sc = base.with_changes(**{KEY: float(value)})
        assert np.linalg.norm(shooting.strobe(sc, x, 2, 256) - x) < 1e-8 * np.linalg.norm(x)
        split.append(np.linalg.norm(shooting.strobe(sc, x, 1, 256) - x) / np.linalg.norm(x))
    assert split[0] < 1e-8 and max(split) > 1e-3  # meets the period-1 branch, then splits
    # bad input: an unknown kind (before any work), a range with no period doubling
    assert main(common + ["--vary", f"{KEY}=2.03:2.11", "--switch", "fold"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("rubrotor: error: --switch = 'fold'") and err.count("\n") == 1
    assert main(common + ["--vary", f"{KEY}=2.0:2.04", "--points", "4", "--switch",
                          "period-doubling"]) == 2  # fmt: skip
    err = capsys.readouterr().err
    assert "period doubling" in err and err.count("\n") == 1


def _curve_distance(sc, branch):
    """Relative distance of the branch's rub points ``(r, W)`` to the closed-form curve.

    Reference: the one-mode balance ``[(k - m W^2) r + k_c (r - g)]^2 + [c W r + mu k_c
    (r - g)]^2 = (u W^2)^2`` of tests/test_follow_sweep.py, linearised: ``|f| / |grad f . (r,
    W)|`` (the first-order distance, relative to the point).
    """
    from rubrotor.rotors.shaft import modal_matrices

    mm = modal_matrices(sc.shaft, 1)
    m, k = float(mm.M[0, 0].real), float(mm.K[0, 0].real)
    c = 2 * sc.damping.ratios[0] * np.sqrt(k * m)
    kc, mu, g = sc.contact.stiffness, sc.contact.friction, sc.contact.clearance
    u, crit = sc.unbalance.magnitude, sc.speed / 1.3
    r = np.array([p.max_radius_m for p in branch.points])
    w = np.array([p.value for p in branch.points]) * crit
    r, w = r[r > 1.001 * g], w[r > 1.001 * g]
    rad, tan = (k - m * w * w) * r + kc * (r - g), c * w * r + mu * kc * (r - g)
    f = rad**2 + tan**2 - (u * w * w) ** 2
    fr = 2 * rad * (k - m * w * w + kc) + 2 * tan * (c * w + mu * kc)
    fw = -4 * rad * m * w * r + 2 * tan * c * r - 4 * u**2 * w**3
    return np.abs(f) / np.hypot(fr * r, fw * w)


def test_richardson_branch_is_fourth_order():
    """Richardson extrapolation of the branch points from N and 2N steps per revolution.

    Reference: the closed-form curve (:func:`_curve_distance`). The map's own error is second
    order (ratio ~4 per doubling of N); the extrapolated points, solved on the same hyperplane
    normal to the tangent (regular through the fold), are fourth order (ratio ~16) on this
    orbit in permanent contact, and 100x closer to the curve than either map.
    """
    err = {}
    for n in (64, 128):
        for rich in (False, True):
            b = continue_orbit(HYST, KEY, 1.8, 1.3, steps=n, points=40, ds=0.05, ds_max=0.5,
                               richardson=rich, method="shooting")  # fmt: skip
            assert any(bb.type in ("fold", "contact-onset") for bb in b.bifurcations)
            err[n, rich] = _curve_distance(HYST, b).max()
    assert 3.0 < err[64, False] / err[128, False] < 5.0
    assert 10.0 < err[64, True] / err[128, True] < 25.0
    assert err[128, True] < 1e-2 * err[128, False]


def test_richardson_fold_is_fourth_order():
    """The located fold, extrapolated from its locations with N and 2N steps per revolution.

    Reference: the closed form's fold (largest speed of the rub branch, tests/test_follow_sweep.py)
    and contact onset (grazing of the free orbit). Without extrapolation the fold is the
    second-order map's (2.5e-4 at N = 64, measured); with it the error falls 16x per doubling
    (measured 2.1e-8 at 64, 1.3e-9 at 128); the onset stays exact (1e-15, located on the
    grazing condition).
    """
    _, _, w_fold, w_onset = _closed_form(HYST)
    exact = np.array([w_onset, w_fold]) / (HYST.speed / 1.3)
    err = {}
    for n in (64, 128):
        b = continue_orbit(HYST, KEY, 1.8, 1.3, steps=n, points=120, ds=0.05, ds_max=0.5,
                           richardson=True, method="shooting")  # fmt: skip
        folds = _turns(b)
        assert folds[0] == pytest.approx(exact[0], rel=1e-12)
        err[n] = abs(folds[1] - exact[1]) / exact[1]
    assert err[128] < 1e-8
    assert 10.0 < err[64] / err[128] < 25.0
