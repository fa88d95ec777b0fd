"""Shooting: periodic orbits, Floquet multipliers against the exact linear propagator."""

import math
from pathlib import Path

import numpy as np
import pytest

from rubrotor.engine.simulate import assemble
from rubrotor.errors import InputError
from rubrotor.orbits import shooting
from rubrotor.scenario import load_scenario

SCENARIOS = Path(__file__).resolve().parents[1] / "src" / "rubrotor" / "scenarios"


def _one_mode(**changes):
    base = load_scenario(SCENARIOS / "seed_no_contact.toml")
    keys = {"shaft.theory": "euler-bernoulli", "shaft.modes": 1, "damping.ratio": 0.02}
    return base.with_changes(**{**keys, **changes})


@pytest.mark.parametrize("k", [1, 2])
def test_no_contact_multipliers_equal_exp_lambda_t(k):
    """Floquet multipliers of the no-contact orbit are ``exp(lambda T)``, ``T = k 2 pi / Omega``.

    Reference: the eigenvalues ``lambda`` of the assembled linear modal system
    (:attr:`ModalSystem.lam`); the real state ``[Re q, Im q, Re q', Im q']`` carries each
    complex multiplier and its conjugate.
    """
    sc = _one_mode()
    orb = shooting.shoot(sc, k=k, steps=64)
    lam = assemble(sc.shaft, sc.speed, sc.damping).lam
    ref = np.exp(lam * k * 2 * math.pi / sc.speed)
    ref = np.concatenate([ref, ref.conj()])
    for mu in ref:
        assert np.min(np.abs(orb.multipliers - mu)) < 1e-9
    assert orb.stable
    assert orb.residual < 1e-12


def test_no_contact_orbit_is_the_steady_unbalance_response():
    """Without contact the periodic state equals the exact particular solution the engine uses.

    Reference: the steady state that :func:`simulate_scenario` starts from with
    ``initial="steady"`` (the closed-form synchronous response), reached by Newton from rest.
    """
    sc = _one_mode()
    rest = shooting.vector_state(np.zeros(4))
    orb = shooting.shoot(sc, guess=rest, steps=64)
    steady = shooting.shoot(sc, steps=64)
    x, y = shooting.state_vector(orb.state), shooting.state_vector(steady.state)
    assert np.linalg.norm(x - y) <= 1e-9 * np.linalg.norm(y)


def test_bad_k_is_an_input_error():
    """``k`` must be a positive integer."""
    with pytest.raises(InputError):
        shooting.shoot(_one_mode(), k=0)


def _annular(multiple=1.5):
    return load_scenario(SCENARIOS / "one_mode_annular_rub.toml").with_changes(
        **{"speed.critical_multiple": multiple}
    )


@pytest.mark.parametrize("factor", [1.0, 1.6])
def test_compiled_monodromy_equals_central_differences(factor):
    """The kernel's variational Jacobian equals central differences of the map, in and out of
    contact.

    Reference: :func:`shooting.monodromy_fd`, central differences of the map itself (a second
    numerical route, error ~1e-10 at its increment). ``factor`` 1 is the no-contact orbit at
    1.5 x critical (radius 86 um < clearance 100 um), 1.6 scales it into the stator (radius
    137 um, in contact for most of the revolution).
    """
    sc = _annular()
    x = shooting.state_vector(shooting.shoot(sc, steps=256).state) * factor
    px, jac = shooting.monodromy(sc, x, 1, 256)
    px_fd, jac_fd = shooting.monodromy_fd(sc, x, 1, 256)
    assert np.array_equal(px, px_fd)
    assert np.linalg.norm(jac - jac_fd) <= 1e-7 * np.linalg.norm(jac)
    radius = shooting._Map(sc, 1, 256).run(x)[2]
    assert (radius > sc.contact.clearance) == (factor > 1)


def test_prepared_map_equals_the_simulation():
    """The prepared map's end state and largest radius equal a simulation from the same state.

    Reference: :func:`rubrotor.engine.simulate.simulate_scenario` with the fixed-step exponential
    integrator from ``start=`` (the simulation driver, its result objects and its saved
    samples), in contact; and :meth:`_Map.at_speed` equals a map built from the scenario
    re-validated at that speed (``with_changes``).
    """
    from rubrotor.engine.simulate import simulate_scenario

    sc = _annular()
    x = shooting.state_vector(shooting.shoot(sc, steps=128).state) * 1.6
    mp = shooting._Map(sc, 2, 128)
    px, _, radius = mp.run(x)
    res = simulate_scenario(
        sc, shooting._integrator(2, 128, True), progress=False, start=shooting.vector_state(x)
    )
    ref = shooting.state_vector(res.final_state)
    assert np.linalg.norm(px - ref) <= 1e-13 * np.linalg.norm(ref)
    assert radius == pytest.approx(np.max(np.hypot(res.channels[0], res.channels[1])), rel=1e-14)
    other = _annular(1.55)
    moved = mp.at_speed(other.speed).run(x, True)
    fresh = shooting._Map(other, 2, 128).run(x, True)
    assert np.linalg.norm(moved[0] - fresh[0]) <= 1e-13 * np.linalg.norm(fresh[0])
    assert np.linalg.norm(moved[1] - fresh[1]) <= 1e-12 * np.linalg.norm(fresh[1])


def test_at_speed_reassembles_a_gyroscopic_rotor():
    """A Timoshenko rotor's modal system depends on the speed: ``at_speed`` must rebuild it.

    Reference: a map built from the scenario re-validated at the new speed (``with_changes``);
    the seed rotor (Timoshenko, 3 modes, gyroscopic) at 1 % more speed.
    """
    sc = load_scenario(SCENARIOS / "seed_no_contact.toml")
    assert shooting._gyroscopic(sc.shaft)
    x = shooting.state_vector(shooting.shoot(sc, steps=64).state)
    other = sc.with_changes(**{"speed.rad_per_s": 1.01 * sc.speed})
    moved = shooting._Map(sc, 1, 64).at_speed(other.speed).run(x, True)
    fresh = shooting._Map(other, 1, 64).run(x, True)
    assert np.linalg.norm(moved[0] - fresh[0]) <= 1e-14 * np.linalg.norm(fresh[0])
    assert np.linalg.norm(moved[1] - fresh[1]) <= 1e-13 * np.linalg.norm(fresh[1])


def test_map_runs_are_repeatable_on_a_multi_mode_rotor():
    """A prepared map gives the same image and monodromy on every run (three Timoshenko modes).

    Regression: the tangent vectors handed to the kernel were a view of the map's
    state-to-eigen-coordinates matrix whenever that matrix was Fortran-ordered (several modal
    coordinates), so the kernel overwrote it and every later run of the map was wrong (Newton
    then failed). Reference: the no-contact multipliers ``exp(lambda T)`` of the assembled
    linear system, on the first and on the third run.
    """
    sc = _one_mode(**{"shaft.theory": "timoshenko", "shaft.modes": 3})
    orb = shooting.shoot(sc, steps=64)
    x = shooting.state_vector(orb.state)
    mp = shooting._Map(sc, 1, 64)
    runs = [mp.run(x, True) for _ in range(3)]
    for px, jac, _ in runs[1:]:
        np.testing.assert_array_equal(px, runs[0][0])
        np.testing.assert_array_equal(jac, runs[0][1])
    lam = assemble(sc.shaft, sc.speed, sc.damping).lam
    ref = np.exp(lam * 2 * math.pi / sc.speed)
    mu = shooting.multipliers_of(runs[2][1])
    for m in np.concatenate([ref, ref.conj()]):
        assert np.min(np.abs(mu - m)) < 1e-9
    assert orb.residual < 1e-12
