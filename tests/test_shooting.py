"""Shooting: periodic orbits, Floquet multipliers against the exact linear propagator."""

import math
from pathlib import Path

import numpy as np
import pytest

from rubrotor import shooting
from rubrotor.errors import InputError
from rubrotor.scenario import load_scenario
from rubrotor.simulation import assemble

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
