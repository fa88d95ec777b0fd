"""The finite plain journal bearing (rubrotor.forces.reynolds): grid order and both asymptotic limits.

References: Ocvirk's short bearing (L/D -> 0, half-Sommerfeld: ``F_r = (L/R)^2 eps^2/(1-eps^2)^2``,
``F_t = (L/R)^2 pi eps / (4 (1-eps^2)^1.5)`` per ``mu omega R L (R/c)^2``, the model error falling as
``(L/D)^2``), Sommerfeld's long bearing (L/D -> infinity, full film:
``F_t = 12 pi eps / ((2 + eps^2) sqrt(1 - eps^2))``, ``F_r = 0``, the model error falling as ``D/L``),
and for the Reynolds (Swift-Stieber) condition the complementarity conditions of the discrete problem
checked directly and a projected SOR solve of the same discrete operator (a second solver).
"""

import math

import numpy as np
import pytest

from rubrotor.errors import InputError
from rubrotor.forces import reynolds
from rubrotor.forces.reynolds import finite_film

EPS = 0.5


def _slopes(x, err):
    return np.diff(np.log(err)) / np.diff(np.log(x))


def test_grid_convergence_is_second_order():
    """Full film at L/D = 1: successive differences fall by 4 per halving of the cells."""
    t = [finite_film(EPS, 1.0, n_theta=4 * n, n_z=n, cavitation="full_film").tangential
         for n in (18, 36, 72, 144)]  # fmt: skip
    d = np.abs(np.diff(t))
    order = np.log2(d[:-1] / d[1:])
    assert np.all(np.abs(order - 2.0) < 0.1), order


def test_short_limit_is_ocvirk_with_error_of_order_two():
    lds = np.array([0.2, 0.1, 0.05])
    err = []
    for ld in lds:
        f = finite_film(EPS, ld, n_theta=288, n_z=64, cavitation="half_sommerfeld")
        lr = 2 * ld
        fr = -(lr**2) * EPS**2 / (1 - EPS**2) ** 2
        ft = lr**2 * math.pi * EPS / (4 * (1 - EPS**2) ** 1.5)
        err.append((abs(f.radial / fr - 1), abs(f.tangential / ft - 1)))
    err = np.array(err)
    assert err[-1].max() < 5e-3
    for k in range(2):
        s = _slopes(lds, err[:, k])
        assert np.all((s > 1.8) & (s < 2.4)), s


def test_long_limit_is_sommerfeld_with_error_of_order_one():
    lds = np.array([2.5, 5.0, 10.0])
    ft = 12 * math.pi * EPS / ((2 + EPS**2) * math.sqrt(1 - EPS**2))
    err, radial = [], []
    for ld in lds:
        f = finite_film(EPS, ld, n_theta=144, n_z=int(24 * ld), cavitation="full_film")
        err.append(abs(f.tangential / ft - 1))
        radial.append(abs(f.radial))
    s = _slopes(lds, np.array(err))
    assert np.all(np.abs(s + 1.0) < 0.05), s
    assert max(radial) < 1e-10 * ft  # the full film's symmetric pressure has no radial force


def _psor(a, b, sweeps=4000, omega=1.8):
    """Projected SOR on the same discrete operator: an independent solver of the complementarity."""
    a = a.tocsr()
    d = a.diagonal()
    q = np.zeros_like(b)
    for _ in range(sweeps):
        old = q.copy()
        for i in range(b.size):
            lo, hi = a.indptr[i], a.indptr[i + 1]
            gs = q[i] + (b[i] - a.data[lo:hi] @ q[a.indices[lo:hi]]) / d[i]
            q[i] = max(0.0, q[i] + omega * (gs - q[i]))
        if np.abs(q - old).max() < 1e-14:
            break
    return q


def test_reynolds_condition_is_the_complementarity_solution():
    a, b, _, _ = reynolds._operator(0.6, 24, 6, 0.5)
    p, _ = reynolds._active_set(a, b)
    lam = b - a @ p
    open_ = p > 0
    assert p.min() >= 0.0
    assert np.abs(lam[open_]).max() < 1e-12 * np.abs(b).max()
    assert lam[~open_].min() >= -1e-12 * np.abs(b).max()
    assert np.abs(_psor(a, b) - p).max() < 1e-9 * p.max()


def test_reynolds_condition_carries_more_than_half_sommerfeld_at_l_over_d_one():
    """Swift-Stieber closes the film later than the pi-film: more load, smaller attitude angle."""
    rey = finite_film(0.6, 1.0, cavitation="reynolds")
    half = finite_film(0.6, 1.0, cavitation="half_sommerfeld")
    assert rey.load > half.load
    assert rey.attitude_angle_rad < half.attitude_angle_rad


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"eps": 1.0}, "eccentricity_ratio = 1.0"), ({"l_over_d": 0.0}, "length / diameter = 0.0"),
     ({"cavitation": "elrod"}, "cavitation = 'elrod'"), ({"n_z": 2}, "n_z = 2")],
)  # fmt: skip
def test_bad_input_names_the_argument(kwargs, match):
    args = {"eps": 0.5, "l_over_d": 1.0}
    args.update(kwargs)
    eps, ld = args.pop("eps"), args.pop("l_over_d")
    with pytest.raises(InputError, match=match):
        finite_film(eps, ld, **args)
