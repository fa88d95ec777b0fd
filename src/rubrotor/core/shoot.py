"""Compiled stroboscopic map of the fixed-step exponential scheme and its exact Jacobian.

One call runs the fixed-step exponential step of :func:`rubrotor.core.integrate.expo_fixed`
(the same step kernel, :func:`rubrotor.core.integrate.fixed_step`, run by
:func:`rubrotor.core.tangent.expo_tangent` without re-orthonormalisation, so the end state is
the one a simulation from the same start gives) over ``n_steps`` steps, from the contact force of the start
state, without saving samples; it returns the largest contact-station radius on the way.

With tangent vectors ``Q`` (rows, complex eigen-coordinates) it also propagates the exact
derivative of the DISCRETE map (the variational equations of the scheme, as
:mod:`rubrotor.core.tangent` derives them): ``dy_{k+1} = E dy_k + G0 dF_k + G1 dF_{k+1}`` with
``dF_k = J_k (dP_k, dV_k)`` (``J_k`` the exact 2 x 4 force Jacobian, friction-sign derivative
included) and ``dF_{k+1}`` from the implicit function theorem on the contact equation,
``(I - J_{k+1} S) dF_{k+1} = J_{k+1} (dpd, dud)``. The linear part is exact, so without contact
the propagated matrix is ``E^n`` to rounding.

Unlike the Lyapunov kernel the vectors are NOT re-orthonormalised: shooting needs the monodromy
matrix itself, not its growth rates. Over the ``k`` revolutions of one shooting period this is
well conditioned: each column is a product of ``n`` step Jacobians applied forward, whose
rounding error is ``~ n eps`` relative to the norm of the product, and that norm is bounded by
``max |mu|`` (the largest Floquet multiplier, order 1 to 10 on the orbits one continues; a
strongly unstable orbit is found with a larger ``k`` only if its multiplier stays far from
overflow, ``|mu| << 1e300``). Columns along decaying directions shrink to ``~ |mu_min|`` and lose
their relative accuracy, but only their absolute error ``~ n eps max |mu|`` matters for the
Newton step and for the multipliers near the unit circle that decide stability and
bifurcations; the collapse of all vectors onto the leading direction that forces Benettin's
re-orthonormalisation only matters over the thousands of revolutions of a Lyapunov run.
"""


import numpy as np
from numba import njit

from rubrotor.core.integrate import SAFE_FASTMATH
from rubrotor.core.tangent import expo_tangent
from rubrotor.core.terms import term_force

__all__ = ["expo_strobe", "phi12"]


@njit(cache=True, fastmath=SAFE_FASTMATH)
def expo_strobe(y, Q, k, cp, out):
    """Run the stroboscopic map from the shifted eigen-coordinates ``y`` (in place).

    Parameters
    ----------
    y : ndarray, complex (ns,)
        Shifted eigen-coordinates at unbalance phase 0; overwritten by the end state.
    Q : ndarray, complex (m, ns)
        Tangent vectors as rows (``m = 0``: the map alone); overwritten by their images.
    k : namedtuple (:class:`rubrotor.engine.shaft_steppers.MapStep`)
        ``E, G0, G1`` (ns,) step coefficients, ``sd, sv`` contact-station displacement (m/N)
        and velocity (m/(s N)) per N of the new force, contact rows ``cdc, cvc`` (ns,),
        ``part_c`` (m) and ``vel_cz`` (m/s) the particular solution at the contact station per
        unit phasor, ``part_lc`` (m) its constant-load part, ``omega`` (rad/s), ``h`` (s),
        ``n_steps``, ``max_disp`` (m).
    cp : ndarray
        Packed contact law (:data:`rubrotor.core.contact.CP_FIELDS`).
    out : ndarray (2,)
        Filled with the largest contact-station radius (m) over the start and every step,
        and the status (a code of :mod:`rubrotor.core.status`).

    Returns
    -------
    complex
        The unbalance phasor ``exp(i omega t)`` at the end.
    """
    cdc, cvc = k.cdc, k.cvc
    P = k.part_c + k.part_lc
    V = k.vel_cz + 0j
    for j in range(y.shape[0]):
        P += cdc[j] * y[j]
        V += cvc[j] * y[j]
    fy, fz, fn, ft = term_force(P.real, P.imag, V.real, V.imag, cp)
    cstate = np.array([complex(fy, fz), 1.0 + 0j, 0j, 0j])
    istate = np.zeros(2, np.int64)
    expo_tangent(y, cstate, istate, Q, np.zeros(Q.shape[0]), k, cp, 0)
    out[0] = cstate[3].real
    out[1] = istate[1]
    return cstate[1]


@njit(cache=True)
def phi12(z, p1, p2):
    """``phi1 = (e^z - 1)/z`` and ``phi2 = (e^z - 1 - z)/z^2`` into ``p1, p2`` (complex arrays).

    The arithmetic of :func:`rubrotor.engine.shaft_modal.phi_functions` (Taylor series of 20 terms
    below ``|z| = 0.25``, the recurrence above), compiled, for maps rebuilt at every key value.
    """
    for i in range(z.shape[0]):
        zi = z[i]
        if abs(zi) < 0.25:
            term = 1.0 + 0j
            a1 = 0j
            a2 = 0j
            fact1 = 1.0  # (j + 1)!
            fact2 = 2.0  # (j + 2)!
            for j in range(20):
                a1 = a1 + term / fact1
                a2 = a2 + term / fact2
                term = term * zi
                fact1 *= j + 2
                fact2 *= j + 3
            p1[i] = a1
            p2[i] = a2
        else:
            e = (np.exp(zi) - 1) / zi
            p1[i] = e
            p2[i] = (e - 1) / zi
