"""Compiled stroboscopic map of the general engine's fixed-step scheme with its exact Jacobian.

The general engine (:func:`rubrotor.core.engine.expo_fixed`) advances complex modal
coordinates ``y`` (ns,) and real contact forces ``F`` (m,) by::

    pd = d0 + Re(Pu z') + Re(C_d E y) + Re(C_d G0 beta) F          (m, no new force)
    pv =      Re(Pv z') + Re(C_v E y) + Re(C_v G0 beta) F          (m/s)
    F' = law(pd + S_d F', pv + S_v F')                              (implicit contact solve)
    y' = E y + G0 beta F + G1 beta F'

(``z'`` the unbalance phasor at the step's end, ``S_d, S_v`` the real sensitivities of the
contact displacement and velocity to the new force, residual flexibility included). The state of
that discrete map is ``(y, F)``. Its exact derivative, the variational equations of the SCHEME
(not of the flow), is, for a tangent ``(dy, dF)``::

    dpd = Re(C_d E dy) + Re(C_d G0 beta) dF,   dpv = Re(C_v E dy) + Re(C_v G0 beta) dF
    (I - J_p S_d - J_u S_v) dF' = J_p dpd + J_u dpv               (implicit function theorem)
    dy' = E dy + G0 beta dF + G1 beta dF'

with ``J_p, J_u`` the exact 2 x 2 blocks of each contact's force Jacobian at the solved state
(:func:`rubrotor.core.contact.contact_force_jac_exact`, the smoothed friction sign
differentiated too; zero for an open contact). ``I - J_p S_d - J_u S_v`` is the Newton matrix
of the contact solve at its solution, so the derivative costs one small ``m x m`` inverse per
step and ``O(ns m)`` per tangent column. The continuous shaft's map does the same with one
complex contact (:mod:`rubrotor.core.shoot`, :mod:`rubrotor.core.tangent`); here the forces are
real ``2 n_c`` vectors and the step may be split in halves where the contact solve fails
(``steps`` carries the coefficients of every level), exactly as ``expo_fixed`` does.

The set-valued closure of a grazing step (``graze_contacts``: no Newton solution, the contact
put on the clearance circle) has no derivative of this form: such steps are counted in
``out[2]`` and the caller differentiates otherwise (central differences).

Everything is read from the engine's named structures (:mod:`rubrotor.engine.structs`):
``steps`` (per-level coefficients), ``contacts`` (rows, laws, divergence bound) and ``outputs``
(the first output station's rows give the largest contact-station radius).
"""

import math

import numpy as np
from numba import njit

from rubrotor.core.engine import (
    SAFE_FASTMATH,
    _rdot,
    graze_contacts,
    solve_contacts,
    solve_one,
    workspace,
)
from rubrotor.core.linalg import invert
from rubrotor.core.status import CONTACT_FAILED as NEWTON_FAILED
from rubrotor.core.status import DIVERGED, OK
from rubrotor.core.terms import FREE_RADIUS, term_jac_exact

__all__ = ["OK", "DIVERGED", "NEWTON_FAILED", "map_tangent"]



@njit(cache=True, fastmath=SAFE_FASTMATH)
def _implicit(pd, pv, Fn, Sd, Sv, cp, lin):
    """Fill ``lin`` (m, 4 + m) ``= [J_p | J_u | A^-1]``: the law Jacobian blocks (m, 2) at the
    solved forces ``Fn`` (N) and the inverse of the Newton matrix ``A = I - J_p S_d - J_u S_v``
    there; False if it is singular."""
    m = Fn.shape[0]
    jac = np.zeros((2, 4))
    for i in range(cp.shape[0]):
        k = 2 * i
        py, pz, uy, uz = pd[k], pd[k + 1], pv[k], pv[k + 1]
        for c in range(m):
            py += Sd[k, c] * Fn[c]
            pz += Sd[k + 1, c] * Fn[c]
            uy += Sv[k, c] * Fn[c]
            uz += Sv[k + 1, c] * Fn[c]
        jac[:, :] = 0.0
        if Fn[k] != 0.0 or Fn[k + 1] != 0.0:
            term_jac_exact(py, pz, uy, uz, cp[i], jac)
        for a in range(2):
            lin[k + a, 0] = jac[a, 0]
            lin[k + a, 1] = jac[a, 1]
            lin[k + a, 2] = jac[a, 2]
            lin[k + a, 3] = jac[a, 3]
    a = np.empty((m, m))
    for r in range(m):
        k = 2 * (r // 2)
        for c in range(m):
            a[r, c] = (1.0 if r == c else 0.0) - (
                lin[r, 0] * Sd[k, c] + lin[r, 1] * Sd[k + 1, c]
                + lin[r, 2] * Sv[k, c] + lin[r, 3] * Sv[k + 1, c]
            )  # fmt: skip
    return invert(a, lin[:, 4:])


@njit(cache=True, fastmath=SAFE_FASTMATH)
def _advance_tangents(lev, steps, Qy, QF, lin, active, scratch):
    """Advance every tangent column ``(Qy[i], QF[i])`` over one step of level ``lev``.

    ``lin`` from :func:`_implicit` (used when ``active``: the new step is in contact);
    ``scratch`` (3, m) work rows ``dpd, dpv, dFn``.
    """
    E, G0, G1, BT = steps.E[lev], steps.G0[lev], steps.G1[lev], steps.BT
    CdE, CvE, CdG0b, CvG0b = steps.CdE[lev], steps.CvE[lev], steps.CdG0b[lev], steps.CvG0b[lev]
    ns = Qy.shape[1]
    m = QF.shape[1]
    for i in range(Qy.shape[0]):
        q = Qy[i]
        dF = QF[i]
        if active:
            for r in range(m):
                a = _rdot(CdE[r], q)
                b = _rdot(CvE[r], q)
                for c in range(m):
                    a += CdG0b[r, c] * dF[c]
                    b += CvG0b[r, c] * dF[c]
                scratch[0, r] = a
                scratch[1, r] = b
            for r in range(m):  # J_p dpd + J_u dpv, block diagonal per contact
                k = 2 * (r // 2)
                dpd_r = lin[r, 0] * scratch[0, k] + lin[r, 1] * scratch[0, k + 1]
                scratch[2, r] = dpd_r + lin[r, 2] * scratch[1, k] + lin[r, 3] * scratch[1, k + 1]
            for r in range(m):
                acc = 0.0
                for c in range(m):
                    acc += lin[r, 4 + c] * scratch[2, c]
                scratch[0, r] = acc
            for r in range(m):
                scratch[2, r] = scratch[0, r]
        else:
            for r in range(m):
                scratch[2, r] = 0.0
        for j in range(ns):
            b0 = 0j
            b1 = 0j
            for c in range(m):
                b0 += BT[c, j] * dF[c]
                b1 += BT[c, j] * scratch[2, c]
            q[j] = E[j] * q[j] + G0[j] * b0 + G1[j] * b1
        for r in range(m):
            dF[r] = scratch[2, r]


@njit(cache=True, fastmath=SAFE_FASTMATH)
def _radius2(y, z, F, outputs):
    """Squared radius (m^2) of the first output station (the first contact) in state ``y``."""
    a = _rdot(outputs.Od[0], y) + (outputs.OPu[0] * z).real + outputs.Od0[0]
    b = _rdot(outputs.Od[1], y) + (outputs.OPu[1] * z).real + outputs.Od0[1]
    for c in range(F.shape[0]):
        a += outputs.ORd[0, c] * F[c]
        b += outputs.ORd[1, c] * F[c]
    return a * a + b * b


@njit(cache=True, fastmath=SAFE_FASTMATH)
def map_tangent(state, tangents, steps, contacts, outputs, omega, n_steps, out):
    """Run ``n_steps`` fixed base steps from ``(y, F)`` at unbalance phase 0, with tangents.

    Parameters
    ----------
    state : tuple ``(y, F)``
        ``y`` ndarray, complex (ns,): modal coordinates (the engine's shifted ones); ``F``
        ndarray (m,): contact forces on the rotor (N) of the start state; both overwritten by
        the end state.
    tangents : tuple ``(Qy, QF)``
        ``Qy`` ndarray, complex (d, ns): modal part of ``d`` tangent columns (rows here);
        ``QF`` ndarray (d, m): their force part (N per unit column); both overwritten by their
        images.
    steps, contacts, outputs : namedtuple
        :class:`rubrotor.engine.structs.Steps`, ``Contacts``, ``Outputs`` of the plant.
    omega : float
        Spin speed (rad/s); ``steps.h[0]`` the base step (s).
    n_steps : int
        Base steps.
    out : ndarray (3,)
        Filled with the largest radius (m) of the first output station over the steps (after
        each base step, as the engine's samples), the status (:data:`OK`, :data:`DIVERGED`,
        :data:`NEWTON_FAILED`) and the number of grazing steps (set-valued closure, where the
        propagated derivative is not exact).

    Returns
    -------
    int
        Base steps completed.
    """
    y, F = state
    Qy, QF = tangents
    E, G0, G1, BT, CdE, CvE = steps.E, steps.G0, steps.G1, steps.BT, steps.CdE, steps.CvE
    CdG0b, CvG0b, Sd, Sv, rot, hs = steps.CdG0b, steps.CvG0b, steps.Sd, steps.Sv, steps.rot, steps.h
    Pu, Pv, d0, cp = contacts.Pu, contacts.Pv, contacts.d0, contacts.cp
    ns = y.shape[0]
    m = F.shape[0]
    nc = cp.shape[0]
    J = E.shape[0] - 1
    full = 1 << J
    pd = np.empty(m)
    pv = np.empty(m)
    Fn = np.zeros(m)
    F0 = np.zeros(m)
    Fp = F.copy()
    fn = np.zeros(nc)
    ft = np.zeros(nc)
    work = workspace(m)
    lin = np.zeros((m, 4 + m))  # [J_p | J_u | A^-1]
    scratch = np.zeros((3, m))  # dpd, dpv, dFn
    bF = np.zeros(ns, np.complex128)
    for c in range(m):
        for j in range(ns):
            bF[j] += BT[c, j] * F[c]
    z = 1.0 + 0j
    hp = hs[0]
    maxd2 = contacts.max_disp * contacts.max_disp
    rmax2 = 0.0
    status = OK
    grazes = 0
    done = 0
    for _ in range(n_steps):
        pos = 0
        lev = 0
        while pos < full:
            units = 1 << (J - lev)
            zn = z * rot[lev]
            loaded = False
            for r in range(m):
                if F[r] != 0.0:
                    loaded = True
            for r in range(m):
                pd[r] = d0[r] + (Pu[r] * zn).real + _rdot(CdE[lev, r], y)
                if loaded:
                    for c in range(m):
                        pd[r] += CdG0b[lev, r, c] * F[c]
            h = hs[lev]
            free = True
            for i in range(nc):
                g = cp[i, FREE_RADIUS]  # < 0: a row that always acts is never free
                if not (g >= 0.0 and pd[2 * i] ** 2 + pd[2 * i + 1] ** 2 <= g * g):
                    free = False
            if free:
                it = 0
                for r in range(m):
                    Fn[r] = 0.0
            else:
                extrap = False
                for r in range(m):
                    if F[r] != 0.0 and Fp[r] != 0.0:
                        extrap = True
                for r in range(m):
                    F0[r] = F[r] + (F[r] - Fp[r]) * (h / hp) if extrap else F[r]
                for r in range(m):
                    pv[r] = (Pv[r] * zn).real + _rdot(CvE[lev, r], y)
                    if loaded:
                        for c in range(m):
                            pv[r] += CvG0b[lev, r, c] * F[c]
                if nc == 1:
                    it = solve_one((pd, pv, Sd[lev], Sv[lev]), F0, cp, (Fn, fn, ft))
                else:
                    it = solve_contacts((pd, pv, Sd[lev], Sv[lev]), F0, cp, (Fn, fn, ft), work)
            if it < 0 and lev == J:
                it = graze_contacts((pd, pv, Sd[lev], Sv[lev]), cp, (Fn, fn, ft), work)
                if it > 0:
                    grazes += 1
            if it < 0:
                if lev < J:
                    lev += 1
                    continue
                status = NEWTON_FAILED
                break
            new = False
            for r in range(m):
                if Fn[r] != 0.0:
                    new = True
            if new:  # (never on a free step: there F' = 0 and pv was not formed)
                if not _implicit(pd, pv, Fn, Sd[lev], Sv[lev], cp, lin):
                    status = NEWTON_FAILED
                    break
            if Qy.shape[0] > 0:
                _advance_tangents(lev, steps, Qy, QF, lin, new, scratch)
            if loaded or new:
                for j in range(ns):
                    b = 0j
                    for c in range(m):
                        b += BT[c, j] * Fn[c]
                    y[j] = E[lev, j] * y[j] + G0[lev, j] * bF[j] + G1[lev, j] * b
                    bF[j] = b
            else:
                for j in range(ns):
                    y[j] = E[lev, j] * y[j]
            pos += units
            bad = False
            for i in range(nc):
                a = pd[2 * i]
                b = pd[2 * i + 1]
                for c in range(m):
                    a += Sd[lev, 2 * i, c] * Fn[c]
                    b += Sd[lev, 2 * i + 1, c] * Fn[c]
                if not (a * a + b * b <= maxd2):
                    bad = True
            for r in range(m):
                Fp[r] = F[r]
                F[r] = Fn[r]
            hp = h
            z = zn
            if bad:
                status = DIVERGED
                break
            if lev > 0 and pos % (2 * units) == 0:
                lev -= 1
        if status != OK:
            break
        done += 1
        tt = omega * (done * hs[0])
        z = complex(math.cos(tt), math.sin(tt))
        rmax2 = max(rmax2, _radius2(y, z, F, outputs))
    out[0] = math.sqrt(rmax2)
    out[1] = status
    out[2] = grazes
    return done
