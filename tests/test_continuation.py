"""Pseudo-arclength continuation (rubrotor.continuation) and ``rubrotor continue``.

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

import numpy as np
import pytest
from test_follow_sweep import HYST, HYST_TOML, RUNS, _closed_form

from rubrotor.cli import main
from rubrotor.continuation import continue_orbit
from rubrotor.follow import follow_sweep
from rubrotor.sweep import regime_labels

KEY = "speed.critical_multiple"


@pytest.fixture(scope="module")
def branches():
    return {
        n: continue_orbit(HYST, KEY, 1.8, 1.3, steps=n, points=120, ds=0.05, ds_max=0.5)
        for n in (512, 1024)
    }


def _turns(branch):
    folds = sorted(b.value for b in branch.bifurcations if b.type == "fold")
    assert len(folds) == 2
    return np.array(folds)


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
    assert not any(bb.type != "fold" for bb in b.bifurcations)


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
    assert set(summary) == {"points", "bifurcations"}
    p = summary["points"][0]
    assert set(p) == {"value", "max_radius_m", "stable", "multipliers_abs_max"}
    assert p["value"] == 1.8 and p["stable"] is True and p["multipliers_abs_max"] < 1
    assert out.exists()
    for bad in (f"{KEY}=1.8", f"{KEY}=1:1", "nokey=1:2"):
        assert main(["continue", str(scen), "--vary", bad, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("rubrotor: error:")
