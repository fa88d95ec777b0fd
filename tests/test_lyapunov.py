"""Lyapunov exponents from the compiled tangent dynamics (rubrotor.orbits.lyapunov, core.tangent).

References, each independent of the tangent kernel:

* the exact contact Jacobian: central finite differences of the contact force;
* a run without contact: the exponential map is the exact flow of ``x' = A x + f(t)``, so the
  exponents are ``Re(lambda)`` of the first-order system (each twice in the real state space)
  and they sum to ``trace(A)`` of the real system, ``-2 sum_modes tr(M^-1 (C + Omega G))``
  computed here from the modal matrices of :func:`rubrotor.rotors.shaft.modal_matrices` with
  ``tr(M^-1 C) = sum 2 zeta omega`` (no eigen-decomposition of ``A``);
* periodic orbits: ``ln|mu| / T`` with ``mu`` the multipliers of the one-revolution map's
  Jacobian built by central finite differences of ``simulate_system`` runs started from
  perturbed states (a second numerical route through the production integrator).
"""

from __future__ import annotations

import math
from importlib import resources

import numpy as np
import pytest
import scipy.linalg

from rubrotor.core.contact import contact_force, contact_force_jac_exact, pack_contact
from rubrotor.engine.settings import Integrator
from rubrotor.engine.simulate import RotorState, assemble, simulate_scenario
from rubrotor.errors import InputError
from rubrotor.orbits.lyapunov import lyapunov_exponents
from rubrotor.rotors.shaft import modal_matrices
from rubrotor.scenario import load_scenario, scenario_from_dict

CASE1 = str(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")
# periodic partial rub with impacts (Hertz contact): seed case 1, 2 % damping, 1e5 N side load
LOADED = load_scenario(CASE1).with_changes(
    **{"unbalance.magnitude": 2e-3, "damping.ratio": 0.02, "load.force_y": 1e5}
)
SPR = 512  # fixed steps per revolution


def one_mode(**changes):
    """One Euler-Bernoulli mode of the seed rotor, linear contact with friction (tests)."""
    spec = {
        "meta": {"name": "one_mode"},
        "shaft": {
            "length": 0.4, "diameter": 0.1, "youngs_modulus": 71e9, "density": 2660,
            "poisson_ratio": 0.33, "theory": "euler-bernoulli", "modes": 1,
        },
        "speed": {"critical_multiple": 1.3},
        "unbalance": {"magnitude": 2e-4},
        "contact": {
            "law": "linear", "clearance": 1e-4, "stiffness": 2e9, "damping": 0.0,
            "friction": 0.05,
        },
        "damping": {"ratio": 0.05},
    }  # fmt: skip
    return scenario_from_dict(spec).with_changes(**changes)


def test_exact_contact_jacobian_matches_finite_differences():
    """Reference: central differences of contact_force (step 1e-7 relative, error ~1e-10)."""
    x = np.array([1.1e-3, 0.3e-3, 0.02, -0.04])
    for law, k, c in ((0, 8.6e9, 0.02), (1, 2e9, 50.0)):
        # a surface speed comparable to the regularisation speed: the sign derivative matters
        cp = pack_contact(1, law, k, c, 1e-3, 0.3, 0, 0.05, 0.01)
        jac = np.zeros((2, 4))
        contact_force_jac_exact(*x, cp, jac)
        fd = np.zeros((2, 4))
        for j in range(4):
            e = np.zeros(4)
            e[j] = 1e-7 * max(abs(x[j]), 1e-3)
            fd[:, j] = (
                np.array(contact_force(*(x + e), cp)[:2])
                - np.array(contact_force(*(x - e), cp)[:2])
            ) / (2 * e[j])
        assert np.max(np.abs(jac - fd)) < 1e-8 * np.max(np.abs(fd))


def _trace_real_A(shaft, speed, zeta):
    tr = 0.0
    for n in range(1, shaft.modes + 1):
        mm = modal_matrices(shaft, n)
        w2 = scipy.linalg.eigh(mm.K, mm.M, eigvals_only=True)
        tr_c = np.sum(2 * zeta * np.sqrt(w2))  # tr(M^-1 C) for C = M Phi diag(2 zeta w) Phi^T M
        tr_g = np.trace(np.linalg.solve(mm.M, speed * mm.G))
        tr += -2 * np.real(tr_c + tr_g)
    return tr


def test_no_contact_exponents_are_real_parts_and_sum_to_trace():
    """Gyroscopic 2-mode Timoshenko seed rotor, 2 % damping, no contact (clearance 1 m).

    The sum of all 2 ns exponents is log|det| of the product of exact propagators: equal to
    trace(A) t to rounding at every length. Each exponent converges to Re(lambda) like C / t
    (the log of the initial vectors' minors over t): the fitted log-log slope is -1.
    """
    sc = LOADED.with_changes(**{"shaft.modes": 2, "contact.clearance": 1.0, "load.force_y": 0.0,
                                "checks.skip": ["clearance_vs_radius"]})  # a clearance of 20 r
    lam = assemble(sc.shaft, sc.speed, sc.damping).lam
    expected = np.sort(np.repeat(lam.real, 2))[::-1]
    trace = _trace_real_A(sc.shaft, sc.speed, 0.02)
    assert np.sum(expected) == pytest.approx(trace, rel=1e-12)  # the two references agree
    revs = np.array([16, 32, 64, 128])
    errors = []
    for r in revs:
        res = lyapunov_exponents(sc, count=expected.size, revolutions=int(r))
        assert res.status == "complete"
        assert np.sum(res.exponents) == pytest.approx(trace, rel=1e-11)
        errors.append(np.max(np.abs(res.exponents - expected)))
    slope = np.polyfit(np.log(revs), np.log(errors), 1)[0]
    assert slope == pytest.approx(-1.0, abs=0.1)
    assert errors[-1] < 1e-2 * np.max(np.abs(expected))


def _vec(st):
    return np.concatenate([st.q.real, st.q.imag, st.qd.real, st.qd.imag])


def _state(v):
    a, b, c, d = np.split(v, 4)
    return RotorState(q=a + 1j * b, qd=c + 1j * d, phase=0.0)


def _one_rev(sc, v):
    integ = Integrator(revolutions=1, dtau=2 * math.pi / SPR)
    return _vec(simulate_scenario(sc, integ, progress=False, start=_state(v)).final_state)


def _fd_monodromy(sc, v0, rel=1e-6):
    """Jacobian of the one-revolution map by central differences (real state coordinates)."""
    n = v0.size
    half = n // 2
    scale = np.r_[np.full(half, np.abs(v0[:half]).max()), np.full(half, np.abs(v0[half:]).max())]
    M = np.empty((n, n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = rel * scale[j]
        M[:, j] = (_one_rev(sc, v0 + e) - _one_rev(sc, v0 - e)) / (2 * e[j])
    return M


@pytest.mark.parametrize(
    "name, sc",
    [
        ("one-mode full annular rub, linear contact", one_mode()),
        ("seed rotor impacting period-1 partial rub, Hertz", LOADED),
    ],
)
@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
def test_periodic_orbit_exponent_equals_floquet(name, sc):
    """lambda_1 = ln|mu_max| / T on a stable period-1 orbit.

    The orbit is reached by a long run; mu from the finite-difference monodromy (module doc).
    Both orbits have two leading complex pairs of multipliers. After 400 revolutions that align
    the tangent vectors with their leading subspace, the sum of the 4 largest exponents (the
    growth of 4-volumes in the invariant subspace of those multipliers) equals
    ``ln|mu_1 mu_2 mu_3 mu_4| / T`` to the finite-difference error (measured 1e-10 to 1.1e-8
    relative),
    which only the exact derivative of the step achieves; ``lambda_1`` itself carries the
    bounded oscillation of a vector turning in the plane of a complex pair, divided by the
    averaging time (measured 1e-3 relative over 160 revolutions).
    """
    settle = lyapunov_exponents(
        sc, revolutions=10, transient_revolutions=600, steps_per_revolution=SPR
    )
    v0 = _vec(settle.final_state)
    assert np.max(np.abs(_one_rev(sc, v0) - v0)) < 1e-9 * np.max(np.abs(v0))  # periodic
    if "partial" in name:  # it impacts: in contact for part of the revolution only
        r = simulate_scenario(
            sc, Integrator(revolutions=1, dtau=2 * math.pi / SPR), progress=False, start=_state(v0)
        )
        fn = r.channels[6 * len(r.stations)]
        assert 0 < np.mean(fn > 0) < 1
    mu = np.linalg.eigvals(_fd_monodromy(sc, v0))
    T = 2 * math.pi / sc.speed
    ref = np.sort(np.log(np.abs(mu)) / T)[::-1]
    res = lyapunov_exponents(
        sc,
        count=4,
        revolutions=160,
        transient_revolutions=400,
        start=_state(v0),
        steps_per_revolution=SPR,
    )
    # 1e-10 to 1.1e-8 relative measured, depending on the compiled kernel (a freshly compiled
    # cache gives 1.1e-8 on the annular-rub case): the finite-difference reference's own error
    assert np.sum(res.exponents) == pytest.approx(np.sum(ref[:4]), rel=3e-8)
    assert res.exponents[0] == pytest.approx(ref[0], rel=3e-3)
    assert res.per_revolution[0] == pytest.approx(res.exponents[0] * T, rel=1e-14)


def test_input_errors():
    with pytest.raises(InputError, match="count"):
        lyapunov_exponents(one_mode(), count=5)  # one mode: real dimension 4
    with pytest.raises(InputError, match="steps_per_revolution"):
        lyapunov_exponents(one_mode(), steps_per_revolution=4)


@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
def test_exponents_of_the_map_converge_to_the_flow_at_second_order():
    """The step map approximates the flow to second order, so do its exponents.

    One-mode full annular rub; steps per revolution 64 .. 1024; the differences of successive
    estimates (all 4 exponents: their sum, and the leading pair) fall by 4 per halving: fitted
    log-log slope 2 against the step.
    """
    sc = one_mode()
    st = lyapunov_exponents(sc, revolutions=10, transient_revolutions=600).final_state
    spr = np.array([64, 128, 256, 512, 1024])
    est = []
    for n in spr:
        r = lyapunov_exponents(
            sc, count=4, revolutions=100, transient_revolutions=300, start=st,
            steps_per_revolution=int(n),
        )  # fmt: skip
        est.append((r.exponents.sum(), r.exponents[:2].mean()))
    diffs = np.abs(np.diff(np.array(est), axis=0))
    for col in range(2):
        slope = np.polyfit(np.log(1.0 / spr[1:]), np.log(diffs[:, col]), 1)[0]
        assert slope == pytest.approx(2.0, abs=0.1)
