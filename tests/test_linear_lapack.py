"""The linear verbs' banded algebra on LAPACK (:mod:`rubrotor.linear.lapack`), checked against
independent references: dense LAPACK on the full matrices (``numpy.linalg.solve``,
``scipy.linalg.eig`` of the first-order form) and, in the slow set, the compiled twins of
:mod:`rubrotor.core.banded` it replaces on the linear verbs' paths."""

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rubrotor
from rubrotor.core.banded import SparseRows, Starts
from rubrotor.linear import lapack
from rubrotor.linear.band import _band_parts, _projected_lam, _reduced
from rubrotor.linear.verbs import linear_system

SCENARIOS = Path(rubrotor.__file__).parent / "scenarios"


@pytest.fixture(scope="module", params=["general_rotor", "seal_rub"])
def rotor(request):
    system = linear_system(rubrotor.load_scenario(SCENARIOS / f"{request.param}.toml"))
    speeds = np.linspace(50.0, 1500.0, 7)
    return system, speeds, _band_parts(system, speeds)


def _dynamic(system, speed, lam):
    mx = system.matrices(speed)
    return lam * lam * mx.M + lam * mx.damping + mx.K


def test_band_matmul_is_the_dense_product(rotor):
    system, _, parts = rotor
    x = np.random.default_rng(0).standard_normal((parts.m.shape[0], 3))
    out = np.empty_like(x)
    lapack.band_matmul(parts.k, parts.ku, x, out)
    dense = system.K[np.ix_(system.free, system.free)]
    assert np.allclose(out, dense @ x, rtol=0, atol=1e-13 * np.abs(dense @ x).max())


def test_unbalance_and_frequency_sweeps_are_dense_solves(rotor):
    """Each speed's banded solve against ``numpy.linalg.solve`` of the full dynamic stiffness."""
    system, speeds, parts = rotor
    n = parts.m.shape[0]
    rng = np.random.default_rng(1)
    rhs = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    rows = rng.standard_normal((3, n)) + 0j
    out, status, at = lapack.unbalance_sweep(parts, speeds, rhs, rows)
    assert (status, at) == (0, -1)
    for s, w in enumerate(speeds):
        ref = rows @ np.linalg.solve(_dynamic(system, w, 1j * w), w * w * rhs)
        assert np.allclose(out[s], ref, rtol=1e-9, atol=1e-12 * np.abs(ref).max())
    one = parts._replace(sup_k=parts.sup_k[:1], sup_c=parts.sup_c[:1])
    freqs = np.linspace(10.0, 3000.0, 5)
    out, status, _ = lapack.frequency_sweep(one, float(speeds[0]), freqs, rhs, rows)
    assert status == 0
    for s, w in enumerate(freqs):
        mx = system.matrices(float(speeds[0]))
        ref = rows @ np.linalg.solve(-w * w * mx.M + 1j * w * mx.damping + mx.K, rhs)
        assert np.allclose(out[s], ref, rtol=1e-9, atol=1e-12 * np.abs(ref).max())


def test_refined_eigenpairs_are_the_dense_eigenvalues(rotor):
    """Newton from the projected starts lands on eigenvalues of the dense first-order matrix
    (``scipy.linalg.eig``) to 1e-9, with eigenvectors of residual ~ rounding; Ritz vectors are
    null vectors of the projected problems."""
    system, speeds, parts = rotor
    n = 4
    red = _reduced(system, parts, speeds, n)
    lam0 = _projected_lam(red, np.arange(speeds.size), n)
    small = lapack.ritz_vectors(red.mr, red.dr, red.kr, lam0)
    for s in range(speeds.size):
        for j in range(n):
            t = lam0[s, j] ** 2 * red.mr + lam0[s, j] * red.dr[s] + red.kr[s]
            assert np.linalg.norm(t @ small[s, j]) <= 1e-8 * np.linalg.norm(t)
    size = parts.m.shape[0]
    every = SparseRows(np.arange(size)[:, None], np.ones((size, 1), complex))
    ref = lapack.refine_eigenpairs(parts, speeds, Starts(lam0, small @ red.phi.T), 1e-10, 8,
                                   every)  # fmt: skip
    assert np.all(ref.steps > 0)
    for s, w in enumerate(speeds):
        a, _ = system.matrices(float(w)).first_order()
        dense = scipy.linalg.eigvals(a)
        for j in range(n):
            lam = ref.lam[s, j]
            assert np.min(np.abs(dense - lam)) <= 1e-9 * abs(lam)
            x = ref.shapes[s, j]
            t = _dynamic(system, float(w), lam)
            assert np.linalg.norm(t @ x) <= 1e-9 * np.linalg.norm(t, 1) * np.linalg.norm(x)


@pytest.mark.slow
def test_the_compiled_twins_agree(rotor):
    """The compiled kernels of :mod:`rubrotor.core.banded` (still used by continuation) and
    their LAPACK twins give the same numbers (rounding: Newton's tolerance 1e-10)."""
    from rubrotor.core import banded

    system, speeds, parts = rotor
    n = 4
    red = _reduced(system, parts, speeds, n)
    lam0 = _projected_lam(red, np.arange(speeds.size), n)
    v1 = banded.ritz_vectors(red.mr, red.dr, red.kr, lam0)
    v2 = lapack.ritz_vectors(red.mr, red.dr, red.kr, lam0)
    phase = np.exp(-1j * np.angle(np.sum(v1.conj() * v2, axis=2)))[..., None]
    assert np.abs(v1 - v2 * phase).max() < 1e-12
    size = parts.m.shape[0]
    every = SparseRows(np.arange(size)[:, None], np.ones((size, 1), complex))
    start = Starts(lam0, v1 @ red.phi.T)
    r1 = banded.refine_eigenpairs(parts, speeds, start, 1e-10, 8, every)
    r2 = lapack.refine_eigenpairs(parts, speeds, start, 1e-10, 8, every)
    assert np.array_equal(r1.steps, r2.steps)
    assert np.max(np.abs(r1.lam - r2.lam) / np.abs(r1.lam)) < 1e-10
    rhs = np.ones(size, complex)
    rows = np.eye(size)[:4].astype(complex)
    o1, o2 = banded.unbalance_sweep(parts, speeds, rhs, rows), lapack.unbalance_sweep(
        parts, speeds, rhs, rows)  # fmt: skip
    assert o1[1:] == o2[1:]
    assert np.abs(o1[0] - o2[0]).max() <= 1e-9 * np.abs(o1[0]).max()
