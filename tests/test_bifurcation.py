"""Period doubling on a partial-rub rotor: k-revolution shooting and branch switching.

References are stated per test.
"""

from __future__ import annotations

import numpy as np
from test_follow_sweep import HYST

from rubrotor import shooting


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
