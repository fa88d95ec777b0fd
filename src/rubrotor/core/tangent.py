"""Compiled tangent dynamics of the fixed-step exponential integrator (Lyapunov exponents).

The fixed-step exponential step of :mod:`rubrotor.core.integrate` is a map of the shifted
eigen-coordinates ``y`` (complex, ``ns``; real dimension ``2 ns``)::

    y_{k+1} = E y_k + G0 F_k + G1 F_{k+1},
    F_{k+1} = f(pd + sd F_{k+1}, ud + sv F_{k+1}),   pd = cdE . y_k + cdG0 F_k + p(t_{k+1}), ...

with ``F_k = f(P_k, V_k)`` the contact force of the state ``y_k`` (``P_k = cd . y_k + ...``,
``V_k = cv . y_k + ...``). Its exact derivative: ``dF_k = J_k (dP_k, dV_k)`` with ``J_k`` the
2 x 4 real Jacobian of the force at state ``k`` (friction-sign derivative included,
``rubrotor.core.contact.contact_force_jac_exact``), and, by the implicit function theorem
on the contact equation, ``(I - J_{k+1} S) dF_{k+1} = J_{k+1} (dpd, dud)`` where ``S`` maps
``dF`` to ``(sd dF, sv dF)``: the matrix ``I - J S`` is the Newton matrix of the contact
solve. Then ``dy_{k+1} = E dy_k + G0 dF_k + G1 dF_{k+1}``. Tangent vectors are propagated with
this map and re-orthonormalised (modified Gram-Schmidt in the real inner product
``Re(a^H b)``) every ``renorm_every`` steps; the logarithms of the norms are summed (Benettin's
method), so ``logs / t`` tends to the Lyapunov exponents of the discrete map, which tend to the
flow's as the step shrinks (the map is the flow's second-order approximation).
"""

import math

import numpy as np
from numba import njit

from rubrotor.core.contact import contact_force_jac_exact, solve_contact
from rubrotor.core.integrate import SAFE_FASTMATH
from rubrotor.core.status import CONTACT_FAILED, DIVERGED, OK, TANGENTS_DEGENERATE

__all__ = ["expo_tangent", "orthonormalise"]


@njit(cache=True)
def orthonormalise(Q, logs):
    """Modified Gram-Schmidt on the rows of ``Q`` (complex, real inner product); add log norms.

    Row ``i`` is made orthogonal to rows ``0 .. i-1`` and normalised; ``log`` of its norm
    before normalisation is added to ``logs[i]``. A row of zero norm stops with ``False``.
    """
    m, ns = Q.shape
    for i in range(m):
        for j in range(i):
            r = 0.0
            for k in range(ns):
                r += Q[j, k].real * Q[i, k].real + Q[j, k].imag * Q[i, k].imag
            for k in range(ns):
                Q[i, k] -= r * Q[j, k]
        nrm = 0.0
        for k in range(ns):
            nrm += Q[i, k].real * Q[i, k].real + Q[i, k].imag * Q[i, k].imag
        nrm = math.sqrt(nrm)
        if not nrm > 0.0:
            return False
        logs[i] += math.log(nrm)
        for k in range(ns):
            Q[i, k] /= nrm
    return True


@njit(cache=True, inline="always")
def _force_tangent(jac, dP, dV):
    """``J (Re dP, Im dP, Re dV, Im dV)`` as a complex force increment (N)."""
    v0 = dP.real
    v1 = dP.imag
    v2 = dV.real
    v3 = dV.imag
    return complex(
        jac[0, 0] * v0 + jac[0, 1] * v1 + jac[0, 2] * v2 + jac[0, 3] * v3,
        jac[1, 0] * v0 + jac[1, 1] * v1 + jac[1, 2] * v2 + jac[1, 3] * v3,
    )


@njit(cache=True, inline="always")
def newton_matrix(jk, sd, sv):
    """``(a11, a12, a21, a22, det)`` of the contact solve's Newton matrix ``I - J S``.

    ``J`` (2 x 4 real) is the force Jacobian ``jk`` at the solved state and ``S`` maps a complex
    force increment ``dF`` to ``(sd dF, sv dF)`` (m/N, m/(s N)).
    """
    a11 = 1.0 - (jk[0, 0] * sd.real + jk[0, 1] * sd.imag + jk[0, 2] * sv.real + jk[0, 3] * sv.imag)
    a12 = -(-jk[0, 0] * sd.imag + jk[0, 1] * sd.real - jk[0, 2] * sv.imag + jk[0, 3] * sv.real)
    a21 = -(jk[1, 0] * sd.real + jk[1, 1] * sd.imag + jk[1, 2] * sv.real + jk[1, 3] * sv.imag)
    a22 = 1.0 - (-jk[1, 0] * sd.imag + jk[1, 1] * sd.real - jk[1, 2] * sv.imag + jk[1, 3] * sv.real)
    return a11, a12, a21, a22, a11 * a22 - a12 * a21


@njit(cache=True, inline="always")
def implicit_force_tangent(jk, nm, dF, q, cdE, cvE, cdG0, cvG0):
    """The new force's increment ``dF_{k+1}`` (N) of tangent vector ``q`` (implicit function
    theorem on the contact equation): ``(I - J S)^-1 J (dpd, dud)``, ``nm`` from
    :func:`newton_matrix`, ``dF`` the old force's increment."""
    dpd = cdG0 * dF
    dud = cvG0 * dF
    for j in range(q.shape[0]):
        dpd += cdE[j] * q[j]
        dud += cvE[j] * q[j]
    b = _force_tangent(jk, dpd, dud)
    a11, a12, a21, a22, det = nm
    return complex((a22 * b.real - a12 * b.imag) / det, (-a21 * b.real + a11 * b.imag) / det)


@njit(cache=True, fastmath=SAFE_FASTMATH)
def expo_tangent(
    y, cstate, istate, n_steps, renorm_every, Q, logs,
    E, G0, G1, sd, sv, cdc, cvc, cp, part, omega, h, max_disp,
):  # fmt: skip
    """Advance the state ``n_steps`` fixed exponential steps with tangent vectors ``Q``.

    State in/out as :func:`rubrotor.core.integrate.expo_fixed`: ``y`` (shifted eigen-
    coordinates), ``cstate = [F, z, F_prev]``, ``istate = [step, status]`` (a code of
    :mod:`rubrotor.core.status`). ``Q`` (m, ns) complex: tangent vectors as rows, orthonormalised
    every ``renorm_every`` steps and at the end, their log growths added to ``logs`` (m,).
    ``part = (part_c, part_lc, vel_cz)``: the contact station's particular-solution
    displacement per unit phasor (m), constant-load displacement (m) and velocity per unit
    phasor (m/s). Returns the number of steps done.
    """
    ns = y.shape[0]
    m = Q.shape[0]
    jac = np.zeros((2, 4))
    jk = np.zeros((2, 4))  # exact Jacobian at the current state
    part_c, part_lc, vel_cz = part
    cdE = cdc * E
    cvE = cvc * E
    cdG0 = 0j
    cvG0 = 0j
    for j in range(ns):
        cdG0 += cdc[j] * G0[j]
        cvG0 += cvc[j] * G0[j]
    F = cstate[0]
    z = cstate[1]
    Fp = cstate[2]
    step = istate[0]
    maxd2 = max_disp * max_disp
    rot = complex(math.cos(omega * h), math.sin(omega * h))
    # the Jacobian at the start state
    P = part_c * z + part_lc
    V = vel_cz * z
    for j in range(ns):
        P += cdc[j] * y[j]
        V += cvc[j] * y[j]
    contact_force_jac_exact(P.real, P.imag, V.real, V.imag, cp, jk)
    dFk = np.zeros(m, np.complex128)
    nm = (1.0, 0.0, 0.0, 1.0, 1.0)  # I - J S out of contact (unused there)
    done = 0
    for _ in range(n_steps):
        step += 1
        if step % 1024 == 0:
            zn = complex(math.cos(omega * h * step), math.sin(omega * h * step))
        else:
            zn = z * rot
        pd = part_c * zn + part_lc
        ud = vel_cz * zn
        for j in range(ns):
            pd += cdE[j] * y[j]
            ud += cvE[j] * y[j]
        if F != 0j:
            pd += cdG0 * F
            ud += cvG0 * F
        # force derivative at the current state, for every tangent vector
        for i in range(m):
            if F != 0j:
                dP = 0j
                dV = 0j
                for j in range(ns):
                    dP += cdc[j] * Q[i, j]
                    dV += cvc[j] * Q[i, j]
                dFk[i] = _force_tangent(jk, dP, dV)
            else:
                dFk[i] = 0j
        F0 = F
        if F != 0j and Fp != 0j:
            F0 = 2.0 * F - Fp
        Fn, it, fn_c, ft_c = solve_contact(pd, ud, sd, sv, F0, cp, jac)
        if it < 0:
            istate[1] = CONTACT_FAILED
            break
        for j in range(ns):
            y[j] = E[j] * y[j] + G0[j] * F + G1[j] * Fn
        P = pd + sd * Fn
        V = ud + sv * Fn
        jk[:, :] = 0.0
        if Fn != 0j:
            contact_force_jac_exact(P.real, P.imag, V.real, V.imag, cp, jk)
            nm = newton_matrix(jk, sd, sv)
        for i in range(m):
            dFn = 0j
            if Fn != 0j:
                dFn = implicit_force_tangent(jk, nm, dFk[i], Q[i], cdE, cvE, cdG0, cvG0)
            for j in range(ns):
                Q[i, j] = E[j] * Q[i, j] + G0[j] * dFk[i] + G1[j] * dFn
        Fp = F
        F = Fn
        z = zn
        done += 1
        if not (P.real * P.real + P.imag * P.imag <= maxd2):
            istate[1] = DIVERGED
            break
        if done % renorm_every == 0:
            if not orthonormalise(Q, logs):
                istate[1] = TANGENTS_DEGENERATE
                break
    if istate[1] == OK and done % renorm_every != 0:
        orthonormalise(Q, logs)
    cstate[0] = F
    cstate[1] = z
    cstate[2] = Fp
    istate[0] = step
    return done
