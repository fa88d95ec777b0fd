"""Period doubling on a partial-rub rotor: k-revolution shooting and branch switching.

References are stated per test.
"""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest
from test_follow_sweep import HYST

from rubrotor.orbits import shooting
from rubrotor.orbits.continuation import continue_orbit, switch_period_doubling
from rubrotor.orbits.lyapunov import lyapunov_exponents
from rubrotor.scenario import load_scenario
from rubrotor.sweeps.regimes import CHAOS_MARGIN_PER_REV, QUASI
from rubrotor.sweeps.regimes import CHAOTIC as CHAOTIC_CODE
from rubrotor.sweeps.regimes import PARTIAL as PARTIAL_CODE
from rubrotor.sweeps.sweep import simulate_point


def test_period_one_orbit_is_a_period_two_fixed_point_with_squared_multipliers():
    """A period-1 orbit is a fixed point of the twice-iterated map, multipliers squared.

    Reference: the chain rule, ``D(P o P)(x*) = DP(x*)^2``, so the k=2 multipliers are the
    squares of the k=1 ones (a second numerical route: two separate shooting problems).
    """
    one = shooting.shoot(HYST, steps=128, transient_revolutions=50)
    two = shooting.shoot(HYST, guess=one.state, k=2, steps=128)
    x1, x2 = shooting.state_vector(one.state), shooting.state_vector(two.state)
    assert np.linalg.norm(x2 - x1) <= 1e-9 * np.linalg.norm(x1)
    sq = one.multipliers**2
    for mu in two.multipliers:
        assert np.min(np.abs(sq - mu)) < 1e-7


SPR = 256  # fixed steps per revolution of the shooting map
KEY = "speed.critical_multiple"
PARTIAL = load_scenario(resources.files("rubrotor") / "scenarios" / "one_mode_partial_rub.toml")


@pytest.fixture(scope="module")
def branch():
    return continue_orbit(PARTIAL, KEY, 2.03, 2.11, steps=SPR, points=40, ds=0.01, ds_max=0.05,
                          transient_revolutions=400)  # fmt: skip


def _brute_force(value):
    """Adaptive-step run from rest (no shooting, no multipliers): metrics of 200 kept revs."""
    m, _ = simulate_point(PARTIAL.with_changes(**{KEY: value}), 2000, 2200, 32)
    return m, np.asarray(m["poincare_v"]) + 1j * np.asarray(m["poincare_w"])


def test_period_doubling_and_torus_found_by_continuation_confirmed_by_brute_force(branch):
    """Partial rub near twice the critical speed: period doubling, then a Neimark-Sacker torus.

    Reference: brute-force simulation with the adaptive integrator from rest (a second route,
    sharing only the model), classified from its once-per-revolution Poincare samples by
    :func:`rubrotor.sweeps.regimes.classify`: period 1 just below the period doubling, period 2 just
    above it (two clusters far apart, each repeating to 1e-9), period 1 just below the
    Neimark-Sacker point and no period just above it.
    """
    types = [b.type for b in branch.bifurcations]
    assert types == ["period-doubling", "period-doubling", "neimark-sacker"]
    pd, _, ns = (b.value for b in branch.bifurcations)
    st = {p.value: p.stable for p in branch.points}
    assert all(s for v, s in st.items() if v < pd) and not any(
        s for v, s in st.items() if pd < v < branch.bifurcations[1].value
    )
    below, z_below = _brute_force(pd - 0.0075)
    above, z_above = _brute_force(pd + 0.0075)
    assert (below["regime"], below["period"]) == (PARTIAL_CODE, 1)
    assert (above["regime"], above["period"]) == (PARTIAL_CODE, 2)
    scale = np.max(np.abs(z_above))
    assert np.abs(z_above[-1] - z_above[-2]) > 0.1 * scale  # two distinct points ...
    assert np.abs(z_above[-1] - z_above[-3]) < 1e-9 * scale  # ... each repeating
    before, _ = _brute_force(ns - 0.003)
    after, z_after = _brute_force(ns + 0.004)
    assert (before["regime"], before["period"]) == (PARTIAL_CODE, 1)
    assert after["period"] == 0 and after["regime"] == QUASI
    assert 0 < after["contact_fraction"] < 1  # partial rub on the torus


@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
def test_second_period_doubling_and_torus_located_independently_of_the_step(branch):
    """The second period doubling and the Neimark-Sacker point do not depend on the step size.

    Reference: a second continuation of the same range with other first / largest arclength
    steps (0.007 / 0.03 instead of 0.01 / 0.05), so the steps bracket each bifurcation
    differently; each is the root of its test function's value (``det(M + I)``, the
    bialternate product) located to the corrector's tolerance, so the two runs must agree to
    1e-6 relative (measured: <= 1.4e-10). Brute force (adaptive runs, no shooting) confirms the
    regimes on both sides of the second period doubling: started on the period-1 orbit
    perturbed by 1e-3 along the Floquet vector of the multiplier near -1, the run settles on
    period 2 just below it and back on period 1 just above it. (From rest the run above it
    also lands on period 2: the doubled branch folds back past this point, so both coexist.)
    """
    other = continue_orbit(PARTIAL, KEY, 2.03, 2.11, steps=SPR, points=40, ds=0.007,
                           ds_max=0.03, transient_revolutions=400)  # fmt: skip
    a = [(b.type, b.value) for b in branch.bifurcations]
    b = [(b.type, b.value) for b in other.bifurcations]
    assert [t for t, _ in a] == [t for t, _ in b]
    for (_, va), (_, vb) in zip(a, b, strict=True):
        assert va == pytest.approx(vb, rel=1e-6)
    pd2 = a[1][1]
    below, z_below = _perturbed_run(branch, pd2 - 0.003)
    above, _ = _perturbed_run(branch, pd2 + 0.003)
    assert (below["regime"], below["period"]) == (PARTIAL_CODE, 2)
    assert (above["regime"], above["period"]) == (PARTIAL_CODE, 1)
    assert np.abs(z_below[-1] - z_below[-2]) > 1e-3 * np.max(np.abs(z_below))


def _perturbed_run(branch, value):
    """Adaptive run of 1000 + 200 revolutions from the period-1 orbit at ``value``, perturbed."""
    sc = PARTIAL.with_changes(**{KEY: value})
    near = min(branch.points, key=lambda q: abs(q.value - value))
    orbit = shooting.shoot(sc, near.state, steps=SPR)
    x = shooting.state_vector(orbit.state)
    mu, vec = np.linalg.eig(shooting.monodromy(sc, x, 1, SPR)[1])
    v = np.real(vec[:, np.argmin(np.abs(mu + 1))])
    start = shooting.vector_state(x + 1e-3 * np.linalg.norm(x) * v / np.linalg.norm(v))
    m, _ = simulate_point(sc, 1000, 1200, 32, start=start)
    return m, np.asarray(m["poincare_v"]) + 1j * np.asarray(m["poincare_w"])


def _contact_point(scenario, x, steps):
    """Contact-station deflection ``v + i w`` (m) at the state vector ``x`` and one rev later."""
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate_scenario

    integ = Integrator(revolutions=1.0, dtau=2 * np.pi / steps, save_every=steps)
    res = simulate_scenario(scenario, integ, progress=False, start=shooting.vector_state(x))
    return res.channels[0] + 1j * res.channels[1]


def test_switching_onto_the_period_doubled_branch(branch):
    """The branch switched onto at the period doubling is period-2 and emanates from it.

    References: the one-revolution map of the shooting module applied to the new branch's
    states (they must not be fixed points of it, but of its square), the splitting
    ``|P(x) - x|`` that vanishes at the period doubling, and an independent brute-force
    adaptive run from rest at the last branch value whose two Poincare clusters must equal
    the doubled orbit's two once-per-revolution points (to the 256-step scheme's error).
    """
    new = switch_period_doubling(PARTIAL, KEY, branch, 2.07, steps=SPR, points=12, ds=0.1)
    pd = next(b.value for b in branch.bifurcations if b.type == "period-doubling")
    assert new.k == 2 and new.points[0].value == pd
    split = []
    for p in new.points:
        sc, x = PARTIAL.with_changes(**{KEY: p.value}), shooting.state_vector(p.state)
        x2 = shooting.strobe(sc, x, 2, SPR)
        assert np.linalg.norm(x2 - x) < 1e-8 * np.linalg.norm(x)  # a period-2 orbit ...
        split.append(np.linalg.norm(shooting.strobe(sc, x, 1, SPR) - x) / np.linalg.norm(x))
    assert split[0] < 1e-8  # ... equal to the period-1 orbit at the period doubling ...
    assert min(split[1:]) > 1e-4 and split[-1] == max(split)  # ... and split apart beyond it
    last = new.points[-1]
    assert last.value > pd and last.stable
    m, z = _brute_force(last.value)
    assert m["period"] == 2
    orbit = _contact_point(PARTIAL.with_changes(**{KEY: last.value}),
                           shooting.state_vector(last.state), SPR)  # fmt: skip
    for point in orbit:
        assert np.min(np.abs(z[-2:] - point)) < 2e-3 * np.max(np.abs(z))


def test_switched_branch_ends_where_it_meets_the_period_one_branch_again(branch):
    """The period-2 branch born at the first period doubling ends at the second one.

    Reference: the period-1 branch's own located period doublings (test functions on that
    branch, a separate computation): the doubled branch's last bifurcation is a branch point at
    the second one (measured 5e-6 apart, the 256-step maps of period 1 and 2), and it turns
    once at its upper fold (2.0952) instead of retracing the loop (before, the march went round
    it again until its points ran out).
    """
    pds = [b.value for b in branch.bifurcations if b.type == "period-doubling"]
    new = switch_period_doubling(PARTIAL, KEY, branch, 2.11, steps=SPR, points=200, ds=0.02)
    assert new.bifurcations[-1].type == "branch-point"
    assert new.bifurcations[-1].value == pytest.approx(pds[1], rel=1e-4)
    upper = [b for b in new.bifurcations if b.type == "fold" and b.value > 2.09]
    assert len(upper) == 1 and len(new.points) < 200


CHAOTIC = load_scenario(resources.files("rubrotor") / "scenarios" / "one_mode_chaotic_rub.toml")


@pytest.mark.slow  # a long physics check: `pytest -m slow` (CI runs it)
def test_chaotic_partial_rub_has_a_converged_positive_exponent_and_periodic_a_negative():
    """Largest Lyapunov exponent: positive and converged in run length on the chaotic rub,
    negative on the period-1 partial rub, and the sweep labels each by it.

    References: on the periodic orbit, ``ln|mu_max| / T`` with the Floquet multipliers of the
    shooting module (finite-difference monodromy, a route independent of the tangent kernel);
    on the chaotic motion, convergence is shown by doubling the averaging length (the
    estimates of 400, 800 and 1600 revolutions at 1024 steps per revolution agree to
    5 %: measured 0.672, 0.681, 0.678 per revolution; a build whose compiled kernels round
    differently follows another chaotic trajectory and gave 0.676, 0.692, 0.682. At 200
    revolutions the two gave 0.690 and 0.624: that average is too short to converge, so it
    is not used) and no
    Poincare period within 12 revolutions in a brute-force run.
    """
    runs = [
        lyapunov_exponents(CHAOTIC, revolutions=n, transient_revolutions=300,
                           steps_per_revolution=1024)
        for n in (400, 800, 1600)
    ]  # fmt: skip
    # a run that leaves the chaotic set for a blown-up state where a contact solve fails (which
    # rounding decides: one compiled build did so after 928 of 1600 revolutions at 1034 steps
    # per revolution) keeps the average over its completed chunks, marked partial
    revs = [r.averaging_time * CHAOTIC.speed / (2 * np.pi) for r in runs]
    assert min(revs) > 255 and all(r.status == "complete" or r.status.startswith("partial")
                                   for r in runs)  # fmt: skip
    est = [r.per_revolution[0] for r in runs]
    assert min(est) > 0.5 and (max(est) - min(est)) < 0.05 * np.mean(est)
    m, _ = simulate_point(CHAOTIC, 300, 500, 64, lyapunov=True)
    assert m["regime"] == CHAOTIC_CODE and m["period"] == 0 and 0 < m["contact_fraction"] < 1
    lam1 = m["lyapunov_exponent"] * 2 * np.pi / CHAOTIC.speed
    assert lam1 > CHAOS_MARGIN_PER_REV

    periodic = PARTIAL.with_changes(**{KEY: 2.0})
    orbit = shooting.shoot(periodic, steps=512, transient_revolutions=400)
    floquet = np.log(np.abs(orbit.multipliers[0]))  # per revolution, k = 1
    lyap = lyapunov_exponents(periodic, revolutions=400, transient_revolutions=400,
                              steps_per_revolution=512, start=orbit.state).per_revolution[0]  # fmt: skip
    assert floquet < 0 and lyap == pytest.approx(floquet, rel=1e-2)
    m, _ = simulate_point(periodic, 2000, 2200, 32, lyapunov=True)
    assert (m["regime"], m["period"]) == (PARTIAL_CODE, 1)
