"""Synchronous orbits as rotating-frame equilibria (rubrotor.orbits.synchronous) and their branches.

References:

* the one-mode rotor's closed form of tests/test_follow_sweep.py (derived there): the full
  annular rub's amplitude equation, its fold (largest speed of the rub branch) and contact
  onset (free radius = clearance);
* the linear system's eigenvalues: the no-contact orbit's multipliers are ``exp(lambda T)``;
* shooting (a second, time-stepping route): its states and multipliers carry the map's
  second-order step error, so they are Richardson-extrapolated from N and 2N steps per
  revolution before comparing, on a three-mode gyroscopic (Timoshenko) rotor as well.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_follow_sweep import HYST, _closed_form

from rubrotor.engine.simulate import assemble
from rubrotor.errors import InputError
from rubrotor.orbits import shooting
from rubrotor.orbits.continuation import continue_orbit
from rubrotor.orbits.synchronous import Field, is_circular, synchronous_orbit
from rubrotor.rotors.shaft import modal_matrices

KEY = "speed.critical_multiple"
CRIT = HYST.speed / 1.3  # HYST runs at 1.3 x its first critical speed (rad/s)


def _modal(sc):
    """Modal mass (kg), stiffness (N/m), damping (N s/m); contact stiffness, friction, gap."""
    mm = modal_matrices(sc.shaft, 1)
    m, k = mm.M[0, 0].real, mm.K[0, 0].real
    c = 2 * sc.damping.ratios[0] * math.sqrt(k * m)
    return m, k, c, sc.contact.stiffness, sc.contact.friction, sc.contact.clearance


def _amplitude_distance(sc, r, w):
    """Relative distance of (r m, w rad/s) to the closed-form rub curve (dimensionless)."""
    m, k, c, kc, mu, g = _modal(sc)
    u = sc.unbalance.magnitude
    rad, tan = (k - m * w * w) * r + kc * (r - g), c * w * r + mu * kc * (r - g)
    f = rad**2 + tan**2 - (u * w * w) ** 2
    fr = 2 * rad * (k - m * w * w + kc) + 2 * tan * (c * w + mu * kc)
    fw = -4 * rad * m * w * r + 2 * tan * c * r - 4 * u**2 * w**3
    return abs(f) / math.hypot(fr * r, fw * w)


def _rub_guess(sc, free, r):
    """A state on the closed-form rub circle of radius ``r`` (m), from the free orbit ``free``.

    The one-mode amplitude equation's phasor: the free response times the ratio of the free
    to the rub dynamic stiffness at ``r`` (contact as a stiffness ``kc (1 - g / r)`` with its
    friction part); exact for one mode, a guess for more.
    """
    m, k, c, kc, mu, g = _modal(sc)
    w = sc.speed
    soft = kc * (1 - g / r)
    ratio = (k - m * w * w + 1j * c * w) / (k - m * w * w + soft + 1j * (c * w + mu * soft))
    q, qd = (np.asarray(v) * ratio for v in (free.state.q, free.state.qd))
    return free.state.__class__(q=q, qd=qd, phase=0.0)


def _radius(orbit):
    field = Field(shooting._Map(orbit.scenario, 1, 64))
    return field.evaluate(shooting.state_vector(orbit.state))[2]


def test_full_annular_rub_is_the_closed_form_to_rounding():
    """Both rub orbits (stable and unstable) and the no-contact orbit at 1.4 x critical.

    The rub orbits lie on the amplitude equation to 1e-13 relative (shooting at 1024 steps per
    revolution: ~1e-6); the no-contact radius equals ``u W^2 / |k - m W^2 + i c W|``.
    """
    sc = HYST.with_changes(**{KEY: 1.4})
    rub_radii, free_radius, _, _ = _closed_form(HYST)
    radii = rub_radii(sc.speed)
    assert len(radii) == 2
    free = synchronous_orbit(sc)
    for r_exact in radii:  # Newton from the closed form's phasor, 2 % off
        orbit = synchronous_orbit(sc, _rub_guess(sc, free, 1.02 * r_exact))
        r = _radius(orbit)
        assert r == pytest.approx(r_exact, rel=1e-12)
        assert _amplitude_distance(sc, r, sc.speed) < 1e-13
        assert orbit.residual < 1e-14 and orbit.steps == 0
    assert _radius(free) == pytest.approx(free_radius(sc.speed), rel=1e-13)


def test_no_contact_multipliers_equal_exp_lambda_t():
    """Without contact the multipliers of ``exp(J T)`` are ``exp(lambda T)`` of the linear system.

    Reference: :attr:`ModalSystem.lam` of the assembled system (each complex multiplier with its
    conjugate in the real state), to 1e-12.
    """
    sc = HYST.with_changes(**{KEY: 1.8})
    orbit = synchronous_orbit(sc)
    lam = assemble(sc.shaft, sc.speed, sc.damping).lam
    ref = np.exp(lam * 2 * math.pi / sc.speed)
    for mu in np.concatenate([ref, ref.conj()]):
        assert np.min(np.abs(orbit.multipliers - mu)) < 1e-12


@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
@pytest.mark.parametrize("modes", [1, 3])
def test_rub_orbit_and_multipliers_equal_extrapolated_shooting(modes):
    """State and multipliers against shooting at 512 and 1024 steps, Richardson-extrapolated.

    Shooting's fixed point and monodromy carry the map's O(h^2) error (measured: state 1.5e-5
    and 3.7e-6, ratio 4.0000; multipliers 6e-6 to 9e-6 off at 1024 steps); ``(4 X_1024 -
    X_512) / 3`` is O(h^4), and must equal the synchronous route to 1e-9 (state, measured 6e-11)
    and 1e-8 (multipliers, measured 1.6e-10 and 1.4e-9). ``modes = 3``: Timoshenko modes with
    their gyroscopic coupling, the modal system rebuilt at the speed.
    """
    sc = HYST.with_changes(**{KEY: 1.4, "shaft.modes": modes, "shaft.theory": "timoshenko"})
    free = shooting.state_vector(synchronous_orbit(sc).state)
    # the stable rub attractor: 200 revolutions from 3 x the free orbit, then shooting
    start = shooting.shoot(sc, shooting.vector_state(3 * free), steps=256,
                           transient_revolutions=200)  # fmt: skip
    sync = synchronous_orbit(sc, start.state)
    assert _radius(sync) > 2 * sc.contact.clearance and sync.stable
    x = shooting.state_vector(sync.state)
    shots = {n: shooting.shoot(sc, sync.state, steps=n) for n in (512, 1024)}
    xs = {n: shooting.state_vector(o.state) for n, o in shots.items()}
    err = {n: np.linalg.norm(xs[n] - x) / np.linalg.norm(x) for n in xs}
    assert 3.5 < err[512] / err[1024] < 4.5
    rich = (4 * xs[1024] - xs[512]) / 3
    assert np.linalg.norm(rich - x) < 1e-9 * np.linalg.norm(x)
    mu = sync.multipliers
    mu_rich = (4 * shots[1024].multipliers - shots[512].multipliers) / 3
    assert np.max(np.abs(np.sort_complex(mu_rich) - np.sort_complex(mu))) < 1e-8


def test_continuation_takes_the_exact_route_and_finds_the_closed_form_turns():
    """``continue_orbit`` (method "auto") continues the circles as rotating-frame equilibria.

    The fold and contact onset equal the closed form's to 1e-12 relative (shooting: 1e-6 only
    after Richardson extrapolation, tests/test_continuation.py); every rub point lies on the
    amplitude equation to 1e-12; stable outside the two turns, unstable between them.
    """
    _, _, w_fold, w_onset = _closed_form(HYST)
    branch = continue_orbit(HYST, KEY, 1.8, 1.3, points=120, ds=0.05, ds_max=0.5)
    assert branch.method == "synchronous"
    folds = [b.value for b in branch.bifurcations if b.type == "fold"]
    onsets = [b.value for b in branch.bifurcations if b.type == "contact-onset"]
    assert folds == pytest.approx([w_fold / CRIT], rel=1e-12)
    assert onsets == pytest.approx([w_onset / CRIT], rel=1e-12)
    assert branch.grazings == pytest.approx([w_onset / CRIT], rel=1e-12)
    g = HYST.contact.clearance
    for p in branch.points:
        if p.max_radius_m > 1.001 * g:
            assert _amplitude_distance(HYST, p.max_radius_m, p.value * CRIT) < 1e-12
    stable = np.array([p.stable for p in branch.points])
    assert stable[0] and stable[-1] and not stable.all()


def test_routes_are_chosen_and_refused_by_name():
    """A side load or ``k = 2`` is not a circle: auto shoots, "synchronous" is refused naming
    ``method``; an unknown method is refused naming it."""
    loaded = HYST.with_changes(**{"load.force_y": 5.0})
    assert not is_circular(HYST.with_changes(**{KEY: 1.8}),
                           np.concatenate([np.ones(2) * 1e-5, np.zeros(2)]))  # fmt: skip
    b = continue_orbit(loaded, KEY, 1.8, 1.7, points=3, steps=128)
    assert b.method == "shooting"
    for kwargs in (dict(scenario=loaded), dict(scenario=HYST, k=2)):
        sc = kwargs.pop("scenario")
        with pytest.raises(InputError, match="method"):
            continue_orbit(sc, KEY, 1.8, 1.7, points=3, steps=128, method="synchronous", **kwargs)
    with pytest.raises(InputError, match="method"):
        continue_orbit(HYST, KEY, 1.8, 1.7, points=3, method="harmonic")
    with pytest.raises(InputError, match="method"):
        synchronous_orbit(loaded)


def test_cli_continue_method_and_richardson(tmp_path, capsys):
    """``rubrotor continue --method``: the exact route's fold in --json equals the closed form
    to 1e-12 and --out records the route; ``synchronous`` on a loaded rotor, an unknown method
    exit 2 with one line naming the option; ``--richardson`` runs the shooting route."""
    import json

    from test_follow_sweep import HYST_TOML

    from rubrotor.cli import main
    from rubrotor.engine.result import load_dataset

    scen = tmp_path / "hyst.toml"
    scen.write_text(HYST_TOML)
    out = tmp_path / "b.nc"
    base = ["continue", str(scen), "--vary", f"{KEY}=1.8:1.3", "--out", str(out)]
    assert main(base + ["--json", "--method", "synchronous", "--points", "120"]) == 0
    summary = json.loads(capsys.readouterr().out)
    turns = sorted(b["value"] for b in summary["bifurcations"]
                   if b["type"] in ("fold", "contact-onset"))  # fmt: skip
    _, _, w_fold, w_onset = _closed_form(HYST)
    assert turns == pytest.approx([w_onset / CRIT, w_fold / CRIT], rel=1e-12)
    assert summary["complete"] and summary["stopped"] == "range"
    assert load_dataset(out).attrs["methods"] == "synchronous"
    loaded = tmp_path / "loaded.toml"
    loaded.write_text(HYST_TOML + "\n[load]\nforce_y = 5.0\n")
    for args in (["--method", "synchronous"], ["--method", "harmonic-balance"]):
        cmd = ["continue", str(loaded), "--vary", f"{KEY}=1.8:1.7", "--out", str(out)]
        assert main(cmd + args + ["--points", "3", "--steps", "64"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "method" in err
    assert main(base + ["--points", "4", "--steps", "64", "--richardson", "--method",
                        "shooting"]) == 0  # fmt: skip
    ds = load_dataset(out)
    assert ds.attrs["methods"] == "shooting" and ds.sizes["point"] == 4


def test_general_rotor_is_refused_by_name_not_a_traceback(tmp_path):
    """The synchronous route and the seed engine's simulate_scenario run on the continuous
    [shaft] rotor (shooting, continuation, sweeps and Lyapunov exponents of general rotors:
    tests/test_shooting_general.py, tests/test_sweep_general.py): a general ([[section]]) rotor
    gets an error naming the field, not a traceback."""
    from importlib import resources

    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate_scenario
    from rubrotor.scenario import load_scenario

    path = resources.files("rubrotor") / "scenarios" / "seal_rub.toml"
    sc = load_scenario(path)
    calls = (
        (lambda: synchronous_orbit(sc), "section"),
        (lambda: simulate_scenario(sc, Integrator(revolutions=1.0)), "section"),
    )  # fmt: skip
    for call, field in calls:
        with pytest.raises(InputError, match=field):
            call()
