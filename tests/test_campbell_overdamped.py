"""Campbell rows hold modes only: overdamped roots are kept apart (issue 38 item 7, issue 39).

ROSS's ``rotor_example_amb_simple`` (magnetic bearings, heavy element damping; its file saved by
ROSS 3.1 is read without ROSS) has, at every speed above 0, roots with ``Im(lam)`` of 6-160 rad/s
and log dec above 800. Sorted by frequency they took the first rows of the Campbell diagram and
pushed the rotor's modes out of the ``n`` kept. The reference here is independent of the code
under test: SciPy's dense generalized eigensolver on ``[[0, I], [-K, -D]] x = lam [[I, 0],
[0, M]] x`` built from the system's matrices, its roots with ``Im > OVERDAMPED |lam|`` (damping
ratio below 0.99995) sorted by frequency. Dense QZ on these ill-conditioned matrices is good to
about 1e-6 (it tells which roots are the modes); each of our eigenvalues is also checked by its
own backward error ``b(lam)``, the smallest singular value of ``T(lam) = lam^2 M + lam D + K``
relative to ``|lam|^2 |M| + |lam| |D| + |K|``: near a root ``b`` grows linearly with the
distance to it, so ``b(lam) <= 0.2 b(lam (1 + 1e-9 e^(i theta)))`` for four directions
``theta`` holds only where ``lam`` is within about 2e-10 of itself of the root (measured ratios:
0.003-0.03 on both rotors, 38-300 for an eigenvalue 1e-9 off).
"""

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from rubrotor.cli import main
from rubrotor.linear.campbell import campbell_data
from rubrotor.linear.roots import OVERDAMPED
from rubrotor.linear.verbs import linear_system
from rubrotor.scenario.load import load_scenario

DATA = Path(__file__).parent / "data" / "ross"
SCENARIOS = Path(__file__).parents[1] / "src" / "rubrotor" / "scenarios"


def _dense_roots(system, speed: float) -> np.ndarray:
    """Every root at ``speed`` (rad/s), 1/s: SciPy ``eig(A, B)`` without inverting ``M``."""
    mx = system.matrices(speed)
    n = mx.M.shape[0]
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-mx.K, -mx.damping]])
    b = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), mx.M]])
    lam = scipy.linalg.eigvals(a, b)
    return lam[np.isfinite(lam)]


def _backward_error(system, speed: float, lam: complex) -> float:
    """Smallest singular value of ``T(lam)`` (inverse iteration on ``T^H T`` from one LU)
    over ``|lam|^2 |M| + |lam| |D| + |K|`` (Frobenius norms)."""
    mx = system.matrices(speed)
    t = lam * lam * mx.M + lam * mx.damping + mx.K
    lu = scipy.linalg.lu_factor(t)
    x = np.ones(t.shape[0], complex)
    for _ in range(6):  # x <- (T^H T)^-1 x, normalised: converges to the smallest singular pair
        x = scipy.linalg.lu_solve(lu, scipy.linalg.lu_solve(lu, x, trans=2))
        x /= np.linalg.norm(x)
    sigma = np.linalg.norm(t @ x)
    scale = abs(lam) ** 2 * np.linalg.norm(mx.M) + abs(lam) * np.linalg.norm(mx.damping)
    return sigma / (scale + np.linalg.norm(mx.K))


def _check(system, data, freq, ld):
    """Same modes as the dense roots (1e-6), each eigenvalue exact by its backward error."""
    assert np.abs(data.frequency_hz - freq).max() <= 1e-6 * freq.max()
    assert np.abs(data.log_dec - ld).max() <= 1e-6 * max(1.0, np.abs(ld).max())
    for i, s in enumerate(data.speeds):
        for f, d in zip(data.frequency_hz[i], data.log_dec[i], strict=True):
            w = 2 * np.pi * f
            lam = complex(-d * w / (2 * np.pi), w)
            near = min(
                _backward_error(system, float(s), lam * (1 + 1e-9 * 1j**k)) for k in range(4)
            )
            assert _backward_error(system, float(s), lam) <= 0.2 * near


def _reference(system, speeds, n: int):
    freq, ld, over = np.zeros((len(speeds), n)), np.zeros((len(speeds), n)), []
    for i, s in enumerate(speeds):
        lam = _dense_roots(system, float(s))
        modes = lam[lam.imag > OVERDAMPED * np.abs(lam)]
        modes = modes[np.argsort(modes.imag)][:n]
        freq[i] = modes.imag / (2 * np.pi)
        ld[i] = -2 * np.pi * modes.real / modes.imag
        over.append(lam[(lam.imag > 0) & (lam.imag <= OVERDAMPED * np.abs(lam))])
    return freq, ld, over


@pytest.fixture(scope="module")
def amb(tmp_path_factory):
    out = tmp_path_factory.mktemp("amb") / "amb.toml"
    assert main(["import-ross", str(DATA / "amb_simple_ross31.toml"), "--out", str(out)]) == 0
    return linear_system(load_scenario(out))


@pytest.mark.filterwarnings("ignore::UserWarning")  # AMB tables read below their first speed
def test_amb_rotor_campbell_rows_are_its_modes(amb):
    speeds = np.linspace(0.0, 1000.0, 6)
    data = campbell_data(amb, speeds, n=6)
    freq, ld, over = _reference(amb, speeds, 6)
    # the feature is reached: overdamped roots below the first mode's frequency at every
    # speed above 0 (they took rows before)
    for i in range(1, len(speeds)):
        assert over[i].size >= 1 and over[i].imag.min() < 2 * np.pi * freq[i, 0]
    _check(amb, data, freq, ld)
    # ROSS's 183 and 335 rad/s modes are on the rows at every speed
    w = 2 * np.pi * data.frequency_hz
    for target in (183.0, 335.0):
        assert np.all(np.abs(w - target).min(axis=1) < 0.05 * target)


def test_general_rotor_campbell_equals_the_dense_roots():
    system = linear_system(load_scenario(SCENARIOS / "general_rotor.toml"))
    speeds = np.linspace(0.0, 1500.0, 7)
    data = campbell_data(system, speeds, n=6)
    freq, ld, _ = _reference(system, speeds, 6)
    _check(system, data, freq, ld)
