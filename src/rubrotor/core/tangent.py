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

from rubrotor.core.integrate import SAFE_FASTMATH, fixed_coefficients, fixed_step, phasor
from rubrotor.core.status import CONTACT_FAILED, DIVERGED, OK, TANGENTS_DEGENERATE
from rubrotor.core.terms import term_jac_exact

__all__ = ["expo_tangent", "orthonormalise", "force_tangents", "advance_tangents"]


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
def implicit_force_tangent(jk, nm, dF, Q, i, prop, scal):
    """The new force's increment ``dF_{k+1}`` (N) of tangent vector ``Q[i]`` (implicit function
    theorem on the contact equation): ``(I - J S)^-1 J (dpd, dud)``, ``nm`` from
    :func:`newton_matrix`, ``dF`` the old force's increment, ``prop, scal`` the step
    (:func:`rubrotor.core.integrate.fixed_coefficients`)."""
    cdG0, cvG0 = scal[2], scal[3]
    dpd = cdG0 * dF
    dud = cvG0 * dF
    for j in range(Q.shape[1]):
        dpd += prop[3, j] * Q[i, j]
        dud += prop[4, j] * Q[i, j]
    b = _force_tangent(jk, dpd, dud)
    a11, a12, a21, a22, det = nm
    return complex((a22 * b.real - a12 * b.imag) / det, (-a21 * b.real + a11 * b.imag) / det)


@njit(cache=True, inline="always")
def force_tangents(Q, F, jk, cdc, cvc, dFk):
    """``dFk[i] = J_k (dP, dV)`` (N) of every tangent row ``Q[i]`` at the current state (zero
    out of contact): ``jk`` the exact force Jacobian there, ``cdc, cvc`` the contact rows."""
    for i in range(Q.shape[0]):
        if F != 0j:
            dP = 0j
            dV = 0j
            for j in range(Q.shape[1]):
                dP += cdc[j] * Q[i, j]
                dV += cvc[j] * Q[i, j]
            dFk[i] = _force_tangent(jk, dP, dV)
        else:
            dFk[i] = 0j


@njit(cache=True, inline="always")
def advance_tangents(Q, dFk, new, prop, scal, cp, jk, nm):
    """Advance the tangent rows ``Q`` over the step :func:`rubrotor.core.integrate.fixed_step`
    just took (``prop, scal``) to ``new = (F_new, P, V)``: the new force (N) and the
    contact-station displacement (m) and velocity (m/s); ``dFk`` from :func:`force_tangents`.
    Updates ``jk`` to the force Jacobian of the new state and returns its Newton matrix (``nm``
    kept out of contact)."""
    if Q.shape[0] == 0:
        return nm
    Fn, P, V = new
    jk[:, :] = 0.0
    if Fn != 0j:
        term_jac_exact(P.real, P.imag, V.real, V.imag, cp, jk)
        nm = newton_matrix(jk, scal[0], scal[1])
    for i in range(Q.shape[0]):
        dFn = 0j
        if Fn != 0j:
            dFn = implicit_force_tangent(jk, nm, dFk[i], Q, i, prop, scal)
        for j in range(Q.shape[1]):
            Q[i, j] = prop[0, j] * Q[i, j] + prop[1, j] * dFk[i] + prop[2, j] * dFn
    return nm


@njit(cache=True, fastmath=SAFE_FASTMATH)
def expo_tangent(y, cstate, istate, Q, logs, k, cp, renorm_every):
    """Advance the state ``k.n_steps`` fixed exponential steps with tangent vectors ``Q``.

    The one stepping kernel of the continuous shaft's maps: the stroboscopic map of shooting
    (:func:`rubrotor.core.shoot.expo_strobe`, tangents not re-orthonormalised) and the
    Lyapunov exponents (re-orthonormalised). Each step is
    :func:`rubrotor.core.integrate.fixed_step`, the simulation's step.

    Parameters
    ----------
    y : ndarray, complex (ns,)
        Shifted eigen-coordinates; overwritten by the end state.
    cstate : ndarray, complex (4,)
        ``[F (N), z, F_prev (N), r]`` in/out: contact force, unbalance phasor
        ``exp(i omega t)``, previous force, and the largest contact-station radius (m) over
        the start and every step (real part, kept across calls).
    istate : ndarray, int (2,)
        ``[step, status]`` in/out (status a code of :mod:`rubrotor.core.status`).
    Q : ndarray, complex (m, ns)
        Tangent vectors as rows, overwritten by their images.
    logs : ndarray (m,)
        Log growths of the rows added at every re-orthonormalisation.
    k : namedtuple (:class:`rubrotor.engine.shaft_steppers.MapStep`)
        Step coefficients and run length (SI units).
    cp : ndarray
        Packed contact law.
    renorm_every : int
        Steps between re-orthonormalisations (modified Gram-Schmidt, and once at the end); 0
        never.

    Returns
    -------
    int
        Steps done.
    """
    cdc, cvc, omega, h = k.cdc, k.cvc, k.omega, k.h
    part = (k.part_c, k.part_lc, k.vel_cz)
    prop, scal = fixed_coefficients(k.E, k.G0, k.G1, k.sd, k.sv, cdc, cvc, part)
    jac = np.zeros((2, 4))
    jk = np.zeros((2, 4))  # exact Jacobian at the current state
    F = cstate[0]
    z = cstate[1]
    Fp = cstate[2]
    step = istate[0]
    maxd2 = k.max_disp * k.max_disp
    rot = complex(math.cos(omega * h), math.sin(omega * h))
    wh = omega * h
    # the Jacobian at the start state
    P = k.part_c * z + k.part_lc
    V = k.vel_cz * z
    for j in range(y.shape[0]):
        P += cdc[j] * y[j]
        V += cvc[j] * y[j]
    term_jac_exact(P.real, P.imag, V.real, V.imag, cp, jk)
    rmax2 = max(cstate[3].real ** 2, P.real * P.real + P.imag * P.imag)
    dFk = np.zeros(Q.shape[0], np.complex128)
    nm = (1.0, 0.0, 0.0, 1.0, 1.0)  # I - J S out of contact (unused there)
    done = 0
    for _ in range(k.n_steps):
        step += 1
        zn = phasor(z, rot, step, wh)
        force_tangents(Q, F, jk, cdc, cvc, dFk)
        Fn, it, fn_c, ft_c, P, V = fixed_step(y, F, Fp, zn, prop, scal, cp, jac)
        if it < 0:
            istate[1] = CONTACT_FAILED
            break
        nm = advance_tangents(Q, dFk, (Fn, P, V), prop, scal, cp, jk, nm)
        Fp = F
        F = Fn
        z = zn
        done += 1
        d2 = P.real * P.real + P.imag * P.imag
        if d2 > rmax2:
            rmax2 = d2
        if not (d2 <= maxd2):
            istate[1] = DIVERGED
            break
        if renorm_every > 0 and done % renorm_every == 0:
            if not orthonormalise(Q, logs):
                istate[1] = TANGENTS_DEGENERATE
                break
    if istate[1] == OK and renorm_every > 0 and done % renorm_every != 0:
        orthonormalise(Q, logs)
    cstate[0] = F
    cstate[1] = z
    cstate[2] = Fp
    cstate[3] = math.sqrt(rmax2)
    istate[0] = step
    return done
