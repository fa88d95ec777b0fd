"""Exact variational propagation on the general engine's map, and its speed family.

References (each independent of the code under test):

* the monodromy of the compiled variational run (:mod:`rubrotor.core.engine_tangent`) against
  central differences of the plain compiled map (``GeneralMap.differences``: ``2 dim`` runs of
  ``rubrotor.core.engine.expo_fixed``, which shares no derivative code with it);
* the plant a speed family gives at a new speed (projection on a fixed basis, Newton on the
  banded quadratic eigenproblem, Woodbury statics, banded particular solution) against the plant
  the engine builds from scratch there (``build_plant``: dense eigen-decomposition of the whole
  first-order matrix, dense inverses), aligned to the same reference modes;
* continuation points computed on the speed family against Newton shooting on the dense
  rebuilt map at each point's key value.
"""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

from rubrotor.orbits import shooting
from rubrotor.orbits.general_map import GeneralMap
from rubrotor.scenario import load_scenario

SEAL = resources.files("rubrotor") / "scenarios" / "seal_rub.toml"
STEPS = 128


@pytest.fixture(scope="module")
def seal():
    return load_scenario(SEAL).with_changes(**{"speed.rad_per_s": 600.0})


@pytest.fixture(scope="module")
def orbit(seal):
    return shooting.shoot(seal, steps=STEPS, transient_revolutions=30)


def _rel(a, b) -> float:
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def test_monodromy_equals_central_differences(seal, orbit):
    """The seal rub orbit at 600 rad/s (annular rub all revolution long: every step solves the
    implicit contact with friction, offset flexible stator, cross-coupled bearings): the
    propagated Jacobian equals central differences to 1e-6 of its largest entry (measured
    4.5e-9; the differences carry ~1e-10 of truncation and rounding), the map itself to 1e-12,
    and the multipliers to 1e-6. Also off the orbit, from a state 5 % away along a mix of modes
    and forces (transient contact), where the map is not at a fixed point."""
    mp = GeneralMap(seal, 1, STEPS)
    x = orbit.state
    rng = np.random.default_rng(1)
    away = x + 0.05 * np.abs(x).max() * rng.standard_normal(x.size) * (
        np.arange(x.size) < 2 * mp.ns
    )
    for state in (x, away):
        px, jac, radius, grazes = mp.tangent(state)
        px_d, jac_d, radius_d = mp.differences(state)
        assert grazes == 0
        assert _rel(px, px_d) < 1e-12 and radius == pytest.approx(radius_d, rel=1e-12)
        assert _rel(jac, jac_d) < 1e-6
    mu = shooting.multipliers_of(mp.tangent(x)[1])[:8]
    mu_d = shooting.multipliers_of(mp.differences(x)[1])[:8]
    np.testing.assert_allclose(np.abs(mu), np.abs(mu_d), rtol=1e-6)
    assert np.all(np.abs(mu) < 1) and abs(mu[0]) > 0.5  # a contracting rub orbit, not trivial


def test_monodromy_through_contact_onset_and_separation(tmp_path, orbit):
    """The same rotor with the clearance opened to 46 um, from the 40 um orbit's state: the
    revolution starts in contact, separates and touches again (101 of 128 steps in contact,
    two events), so the propagated derivative crosses free steps, a separation step and an
    onset step; it equals central differences to 1e-6 of its largest entry (measured 9.5e-10)."""
    path = tmp_path / "wide.toml"
    path.write_text(SEAL.read_text().replace("clearance = 40e-6", "clearance = 46e-6"))
    mp = GeneralMap(load_scenario(path).with_changes(**{"speed.rad_per_s": 600.0}), 1, STEPS)
    _, out, events = mp._kernel(orbit.state)
    fn = out[4 * len(mp.plant.stations) + 6, 1:]
    assert 0 < np.sum(fn > 0) < STEPS and len(events) >= 2
    px, jac, _, grazes = mp.tangent(orbit.state)
    px_d, jac_d, _ = mp.differences(orbit.state)
    assert grazes == 0 and _rel(px, px_d) < 1e-12
    assert _rel(jac, jac_d) < 1e-6


def test_speed_family_plant_equals_dense_rebuild(seal, orbit):
    """Plants at 600 (the anchor), 612 (2 % away, same basis) and 640 rad/s (beyond
    ANCHOR_SPAN: a new anchor) from the speed family equal the engine's dense rebuild there,
    aligned to the same reference: eigenvalues to 1e-10, contact rows and modal inputs to 1e-8,
    unbalance response to 1e-10, residual flexibility to 1e-6 (a small difference of two
    large flexibilities: both routes carry ~2e-8 of rounding, measured 1.4e-8 and 5e-8), and the
    map from the orbit's state to 1e-6 (measured 2e-8)."""
    from rubrotor.orbits import speed_family

    base = GeneralMap(seal, 1, STEPS)
    for speed in (600.0, 612.0, 640.0):
        fam = base.at_speed(speed)
        ref = GeneralMap(seal, 1, STEPS, speed, base)  # dense, aligned to base
        a, b = fam.plant, ref.plant
        assert _rel(a.lam, b.lam) < 1e-10
        assert _rel(a.contacts.Cd, b.contacts.Cd) < 1e-8 and _rel(a.beta, b.beta) < 1e-8
        assert _rel(a.contacts.Pu, b.contacts.Pu) < 1e-10
        assert _rel(a.contacts.d0, b.contacts.d0) < 1e-10
        assert _rel(a.contacts.Rd, b.contacts.Rd) < 1e-6
        assert _rel(a.outputs.ORd, b.outputs.ORd) < 1e-6
        assert _rel(fam.run(orbit.state)[0], ref.run(orbit.state)[0]) < 1e-6
    assert len(base.family.anchors) == 2  # 600 (612 within its span) and 640
    assert abs(640.0 - base.family.anchors[1].speed0) <= speed_family.ANCHOR_SPAN * 640.0


def test_continuation_points_equal_dense_shooting(seal):
    """Continuation in speed from 600 rad/s at 128 steps per revolution on the speed family
    with the propagated monodromy (Newton in the state at each predicted speed): at its last
    two points, Newton shooting on the DENSE rebuilt
    map at that speed (its modes aligned to the first point's, central-difference monodromy)
    from the branch's state lands on the same state to 1e-6 (relative to the state's size;
    measured 1e-9) and the same largest radius to 1e-6; the multipliers agree to 1e-6."""
    from rubrotor.orbits.continuation import continue_orbit

    branch = continue_orbit(seal, "speed.rad_per_s", 600.0, 620.0, points=4, steps=STEPS)
    assert len(branch.points) == 4 and branch.points[-1].value > 602.0
    first = GeneralMap(seal, 1, STEPS)
    for p in branch.points[2:]:
        dense = GeneralMap(seal, 1, STEPS, p.value, first)
        dense.run = lambda x, jacobian=False, m=dense: (
            m.differences(x) if jacobian else GeneralMap.run(m, x)
        )
        x, jac, _, _ = shooting.newton_orbit(dense, p.state, tol=1e-12)
        assert _rel(x, p.state) < 1e-6
        assert dense.run(x)[2] == pytest.approx(p.max_radius_m, rel=1e-6)
        np.testing.assert_allclose(np.abs(shooting.multipliers_of(jac)[:6]),
                                   np.abs(p.multipliers[:6]), rtol=1e-6)  # fmt: skip


def test_band_solve_transposed_equals_dense_solve():
    """The transposed banded solve (one LU serves the right and the left eigenvectors) against
    SciPy's dense solve of ``A^T x = b`` on a random complex band matrix (3 sub-, 2
    super-diagonals, pivoting needed: small diagonal), to 1e-12 relative."""
    import scipy.linalg

    from rubrotor.core.banded import OK, band_factor, band_solve, band_solve_transposed

    rng = np.random.default_rng(3)
    n, kl, ku = 30, 3, 2
    a = np.zeros((n, n), complex)
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            a[i, j] = rng.standard_normal() + 1j * rng.standard_normal()
    a[np.arange(n), np.arange(n)] *= 1e-3
    ab = np.zeros((n, 2 * kl + ku + 1), complex)
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            ab[j, kl + ku + i - j] = a[i, j]
    ipiv = np.zeros(n, np.int64)
    assert band_factor(ab, kl, ku, ipiv) == OK
    b = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    for solve, mat in ((band_solve, a), (band_solve_transposed, a.T)):
        x = b.copy()
        solve(ab, kl, ku, ipiv, x)
        ref = scipy.linalg.solve(mat, b)
        assert np.max(np.abs(x - ref)) < 1e-12 * np.max(np.abs(ref))


def test_pseudo_arclength_chord_with_exact_gx(seal, monkeypatch):
    """Where Newton at the predicted speed is refused (near a fold), the pseudo-arclength
    chord with the exact ``G_x`` at every iterate corrects the point: forced here on every
    point, the branch advances in speed and its points are fixed points of their maps (re-shot
    by Newton to 1e-12 they move by less than 1e-6 of the state, the corrector's tolerance)."""
    from rubrotor.orbits import continuation

    monkeypatch.setattr(continuation, "_fixed_key", lambda *args, **kw: None)
    branch = continuation.continue_orbit(seal, "speed.rad_per_s", 600.0, 620.0, points=3,
                                         steps=STEPS)  # fmt: skip
    first = GeneralMap(seal, 1, STEPS)
    for p in branch.points[1:]:
        x = shooting.newton_orbit(first.at_speed(p.value), p.state, tol=1e-12)[0]
        assert _rel(x, p.state) < 1e-6
    assert branch.points[-1].value > branch.points[1].value > 600.0
