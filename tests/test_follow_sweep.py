"""State-carrying sweeps (rubrotor.sweeps.follow) and starting simulations from a state.

References:

* a run continued from the final state of a shorter run equals one long run (the same
  steps; the Newton start of the first continued step differs, so equal to the solve
  tolerance), also when the split is inside a revolution (the state is turned back to
  unbalance angle 0, exact by the rotational symmetry of the rotor and annular stator);
* the one-mode rotor's steady orbits in closed form, derived here: with modal mass ``m``,
  stiffness ``k``, damping ``c = 2 zeta sqrt(k m)`` (the modal damping definition), mode shape
  1 at midspan where unbalance ``u = m_u e`` and a linear contact ``k_c`` with friction ``mu``
  act, a synchronous circular orbit of radius ``r`` satisfies in the rotating frame
  ``[(k - m W^2) r + k_c (r - g)]^2 + [c W r + mu k_c (r - g)]^2 = (u W^2)^2`` (radial and
  tangential balance; friction opposes the surface speed R W, along the damping force) when
  ``r > g``, and ``r = u W^2 / |k - m W^2 + i c W|`` without contact. The up sweep's jump
  lies at the rub branch's fold (its largest speed), the down sweep's at contact onset of the
  no-contact orbit (``r = g``).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.optimize
from test_lyapunov import LOADED, one_mode

from rubrotor.cli import main
from rubrotor.engine.settings import Integrator
from rubrotor.engine.simulate import RotorState, simulate_scenario
from rubrotor.errors import InputError
from rubrotor.rotors.shaft import modal_matrices
from rubrotor.scenario import load_scenario
from rubrotor.sweeps.follow import follow_sweep
from rubrotor.sweeps.sweep import open_sweep, regime_labels

# hardening full annular rub coexisting with the no-contact orbit: a hysteresis loop
HYST = one_mode(**{"contact.friction": 0.01, "contact.stiffness": 5e8})
HYST_TOML = """
[meta]
name = "one_mode"
[shaft]
length = 0.4
diameter = 0.1
youngs_modulus = 71e9
density = 2660
poisson_ratio = 0.33
theory = "euler-bernoulli"
modes = 1
[speed]
critical_multiple = 1.3
[unbalance]
magnitude = 2e-4
[contact]
law = "linear"
clearance = 1e-4
stiffness = 5e8
damping = 0.0
friction = 0.01
[damping]
ratio = 0.05
"""
VALUES = np.linspace(1.2, 1.8, 13)  # x first forward critical speed
RUNS = dict(transient_revolutions=150, revolutions=180, samples_per_revolution=32)


@pytest.mark.parametrize("kw", [dict(dtau=2 * math.pi / 256), dict(output_dtau=2 * math.pi / 64)])
@pytest.mark.parametrize("split", [10.0, 10.3])
def test_continued_run_equals_one_run(kw, split):
    sc = LOADED.with_changes(**{"load.force_y": 0.0})
    full = simulate_scenario(sc, Integrator(revolutions=20, **kw), progress=False)
    a = simulate_scenario(sc, Integrator(revolutions=split, **kw), progress=False)
    b = simulate_scenario(
        sc, Integrator(revolutions=20 - split, **kw), progress=False, start=a.final_state
    )
    p_full = full.channels[0, -1] + 1j * full.channels[1, -1]
    # b runs in a frame turned by the unbalance angle at the hand-over
    p_b = (b.channels[0, -1] + 1j * b.channels[1, -1]) * np.exp(1j * a.final_state.phase)
    scale = np.max(np.hypot(full.channels[0], full.channels[1]))
    assert abs(p_b - p_full) < 1e-10 * scale
    assert full.stats["contact_events"] > 0  # the runs rub


def test_start_state_errors():
    sc = LOADED  # with a side load the rotational symmetry is broken
    a = simulate_scenario(sc, Integrator(revolutions=1.5, dtau=0.01), progress=False)
    with pytest.raises(InputError, match="start.phase"):
        simulate_scenario(
            sc, Integrator(revolutions=1, dtau=0.01), progress=False, start=a.final_state
        )
    bad = RotorState(q=np.zeros(2, complex), qd=np.zeros(2, complex))
    with pytest.raises(InputError, match="start"):
        simulate_scenario(sc, Integrator(revolutions=1, dtau=0.01), progress=False, start=bad)


def _closed_form(sc):
    mm = modal_matrices(sc.shaft, 1)
    m, k = mm.M[0, 0], mm.K[0, 0]
    c = 2 * sc.damping.ratios[0] * math.sqrt(k * m)
    kc, mu, g = sc.contact.stiffness, sc.contact.friction, sc.contact.clearance
    u = sc.unbalance.magnitude

    def balance(r, w):
        radial = (k - m * w * w) * r + kc * (r - g)
        tangential = c * w * r + mu * kc * (r - g)
        return radial**2 + tangential**2 - (u * w * w) ** 2

    def rub_radii(w):
        grid = g * np.linspace(1.0, 50.0, 5001)
        v = balance(grid, w)
        brackets = zip(grid[:-1], grid[1:], v[:-1], v[1:], strict=True)
        return [
            scipy.optimize.brentq(balance, a, b, args=(w,), xtol=1e-16)
            for a, b, fa, fb in brackets
            if fa * fb < 0
        ]

    def free_radius(w):
        return u * w * w / abs(k - m * w * w + 1j * c * w)

    def omega(r):  # the largest speed with a rub orbit of radius r (0 if none)
        a, b, d = (k + kc) * r - kc * g, m * r, mu * kc * (r - g)
        roots = np.roots(
            [b * b - u * u, 0, c * c * r * r - 2 * a * b, 2 * c * r * d, a * a + d * d]
        )
        real = [x.real for x in roots if abs(x.imag) < 1e-9 * abs(x) and x.real > 0]
        return max(real, default=0.0)

    def fold():  # the rub branch's largest speed, max W(r) over r > g
        grid = g * np.linspace(1.001, 20.0, 2000)
        i = int(np.argmax([omega(r) for r in grid]))
        res = scipy.optimize.minimize_scalar(
            lambda r: -omega(r), bounds=(grid[i - 1], grid[i + 1]), method="bounded",
            options={"xatol": 1e-15},
        )  # fmt: skip
        return -res.fun

    onset = scipy.optimize.brentq(
        lambda w: free_radius(w) - g, 1.0 * sc.speed / 1.3, 3.0 * sc.speed / 1.3
    )
    return rub_radii, free_radius, fold(), onset


def test_up_and_down_sweeps_show_hysteresis_at_the_closed_form_jumps():
    ds = follow_sweep(HYST, "speed.critical_multiple", VALUES, direction="both", workers=2, **RUNS)
    crit = HYST.speed / 1.3
    rub_radii, free_radius, w_fold, w_onset = _closed_form(HYST)
    labels = regime_labels(ds)
    x = ds["speed.critical_multiple"].values
    up, down = labels[0], labels[1]
    # the up sweep stays on the rub branch up to its fold, the down sweep off contact down to
    # contact onset: both jumps within one sweep step of the closed form's speeds
    assert np.all(up[x < w_fold / crit] == "full annular rub")
    assert np.all(up[x > w_fold / crit] == "no contact")
    assert np.all(down[x > w_onset / crit] == "no contact")
    assert np.all(down[x < w_onset / crit] == "full annular rub")
    assert np.any((up == "full annular rub") & (down == "no contact"))  # hysteresis
    # the amplitudes on both branches equal the closed forms
    for d in range(2):
        for i, w in enumerate(x * crit):
            r = ds["max_displacement"].values[d, i]
            if labels[d, i] == "no contact":
                assert r == pytest.approx(free_radius(w), rel=1e-6)
            else:
                assert min(abs(r - rr) / rr for rr in rub_radii(w)) < 1e-6
    # every point but the first of each chain started from its predecessor's state
    assert ds["started_from"].values.sum(axis=1).tolist() == [x.size - 1, x.size - 1]


def test_follow_store_resume_equals_uninterrupted(tmp_path, monkeypatch):
    import rubrotor.sweeps.follow as fo

    vals = VALUES[3:9]
    kw = dict(direction="both", workers=1, chunk_size=2, **RUNS)
    ref = follow_sweep(HYST, "speed.critical_multiple", vals, **kw)
    store = tmp_path / "f.zarr"
    real = fo.run_follow_chunk
    calls = []

    def stop_after_two(task):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(task["chunk"])
        return real(task)

    monkeypatch.setattr(fo, "run_follow_chunk", stop_after_two)
    with pytest.raises(KeyboardInterrupt):
        follow_sweep(HYST, "speed.critical_multiple", vals, store=store, **kw)
    monkeypatch.setattr(fo, "run_follow_chunk", real)
    ds = follow_sweep(HYST, "speed.critical_multiple", vals, store=store, **kw)
    np.testing.assert_array_equal(regime_labels(ds), regime_labels(ref))
    np.testing.assert_allclose(
        ds["max_displacement"].values, ref["max_displacement"].values, rtol=1e-9
    )


def test_cli_follow_figure_and_errors(tmp_path, capsys):
    scen = tmp_path / "hyst.toml"
    scen.write_text(HYST_TOML)
    assert load_scenario(scen) == HYST
    png = tmp_path / "bif.png"
    args = ["sweep", str(scen), "--vary", "speed.critical_multiple=1.3:1.7:5", "--follow", "both"]
    args += ["--out", str(tmp_path / "f.zarr"), "--figure", str(png), "--transient", "150"]
    args += ["--revolutions", "180", "--samples", "32", "--workers", "2", "--lyapunov"]
    assert main(args) == 0
    summary = json.loads(capsys.readouterr().out)
    stored = open_sweep(tmp_path / "f.zarr")
    assert stored["done"].values.all()
    assert np.all(stored["lyapunov_exponent"].values < 0)  # stable orbits on both branches
    assert set(summary["regimes"]) == {"up", "down"}
    assert (
        summary["regimes"]["up"]["full annular rub"]
        > summary["regimes"]["down"]["full annular rub"]
    )
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    bad = [
        "sweep",
        str(scen),
        "--vary",
        "speed.critical_multiple=1:2:3",
        "--vary",
        "unbalance.magnitude=1e-4:2e-4:2",
    ]
    assert main(bad + ["--follow", "up", "--out", str(tmp_path / "g.zarr")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--follow" in err
