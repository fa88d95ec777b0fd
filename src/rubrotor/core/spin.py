"""Compiled adaptive stepper with the spin speed (and touchdown-ring speeds) as states (SI arrays).

The rotor is projected on a fixed real basis ``Phi`` (mass-normalised modes of the rotor at the
start speed, so ``Phi^T M Phi = I``); in its coordinates ``eta`` the whole state is::

    x = [eta (r), eta' (r), Omega (rad/s), theta (rad), omega_ring (n_c, rad/s)]

and its derivative is, with ``K(Omega)``, ``C(Omega)`` interpolated linearly in the speed (the
bearings' tables) and switched to the ``after`` set from ``fail_time`` (s) on::

    eta''  = -(C + Omega G) eta' - K eta + f0 + Pc^T F_contact + Pu^T F_unbalance
    J Omega' = T_drive(Omega) - drag Omega + sum_i R_i ft_i
    J_i omega_ring_i' = -r_i ft_i - d_i omega_ring_i
    theta' = Omega

``ft_i`` (N) is the friction force of contact ``i`` along ``i n`` on the rotor (negative when the
rotor surface slides forward), evaluated by :func:`rubrotor.core.terms.term` with the sliding
speed ``R_i Omega - r_i omega_ring_i + t . u``. The unbalance force of a plane ``m e`` at angle
``theta + phase`` is ``m e (Omega^2 (cos, sin) + Omega' (sin, -cos))``.

Every stage of the Dormand-Prince 5(4) pair evaluates all of it together, so the spin and ring
equations are integrated inside the same step with the contact forces of that step (no lag), and
the error estimate controls every state. Steps are clipped to land on each output time and on
``fail_time``.

Saved channels per sample: ``x`` (``2 r + 2 + n_c``), then per contact ``i`` from
``n_x + 5 i``: normal force (N), friction force ``ft`` (N), sliding speed (m/s), ``F_y``, ``F_z``
(N, on the rotor).
"""

import math

import numpy as np
from numba import njit

from rubrotor.core.terms import term

__all__ = ["spin_dopri", "SPIN_OK", "SPIN_STEP_TOO_SMALL", "SPIN_DIVERGED", "SPIN_MAX_STEPS"]

from rubrotor.core.status import DIVERGED as SPIN_DIVERGED  # noqa: E402
from rubrotor.core.status import MAX_STEPS as SPIN_MAX_STEPS  # noqa: E402
from rubrotor.core.status import OK as SPIN_OK  # noqa: E402
from rubrotor.core.status import STEP_TOO_SMALL as SPIN_STEP_TOO_SMALL  # noqa: E402

# Dormand-Prince 5(4) tableau
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = np.array(
    [
        [0, 0, 0, 0, 0, 0],
        [1 / 5, 0, 0, 0, 0, 0],
        [3 / 40, 9 / 40, 0, 0, 0, 0],
        [44 / 45, -56 / 15, 32 / 9, 0, 0, 0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0, 0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0],
        [35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
    ]
)
_B = np.array([35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0])
_E = np.array(
    [71 / 57600, 0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40]
)  # b5 - b4


@njit(cache=True)
def _interp(xs, x):
    """Bracket of ``x`` in the increasing ``xs``, clamped to the ends: index ``j`` and weight
    ``w`` so that a tabulated ``y(x) = (1 - w) y[j] + w y[j + 1]``."""
    n = xs.shape[0]
    if n == 1 or x <= xs[0]:
        return 0, 0.0
    if x >= xs[n - 1]:
        return n - 2, 1.0
    j = 0
    while xs[j + 1] < x:
        j += 1
    return j, (x - xs[j]) / (xs[j + 1] - xs[j])


@njit(cache=True)
def _rhs(t, x, mats, forces, cont, spin, dx, rec):
    """``dx = f(t, x)``; ``rec`` gets the contact channels (5 per contact)."""
    sg, Kt, Ct, G, fail_time = mats
    f0, Pu, unb = forces
    Pc, offs, cp, radius, ring = cont
    J, drag, tq_w, tq_t = spin
    r = G.shape[0]
    nc = cp.shape[0]
    om = x[2 * r]
    th = x[2 * r + 1]
    s = 1 if t >= fail_time else 0
    j, w = _interp(sg, om)
    j1 = j + 1 if sg.shape[0] > 1 else j
    for a in range(r):
        acc = f0[a]
        for b in range(r):
            k = (1.0 - w) * Kt[s, j, a, b] + w * Kt[s, j1, a, b]
            c = (1.0 - w) * Ct[s, j, a, b] + w * Ct[s, j1, a, b]
            acc -= k * x[b] + (c + om * G[a, b]) * x[r + b]
        dx[r + a] = acc
        dx[a] = x[r + a]
    torque = 0.0
    cpi = np.empty(cp.shape[1])
    for i in range(nc):
        py = -offs[2 * i]
        pz = -offs[2 * i + 1]
        uy = 0.0
        uz = 0.0
        for b in range(r):
            py += Pc[2 * i, b] * x[b]
            pz += Pc[2 * i + 1, b] * x[b]
            uy += Pc[2 * i, b] * x[r + b]
            uz += Pc[2 * i + 1, b] * x[r + b]
        wr = x[2 * r + 2 + i]
        for k in range(cp.shape[1]):
            cpi[k] = cp[i, k]
        cpi[7] = radius[i] * om - ring[i, 2] * wr
        res = term(py, pz, uy, uz, cpi)
        fy, fz, fn, ft = res[0], res[1], res[2], res[3]
        for b in range(r):
            dx[r + b] += Pc[2 * i, b] * fy + Pc[2 * i + 1, b] * fz
        torque += radius[i] * ft
        if ring[i, 0] > 0.0:
            dx[2 * r + 2 + i] = (-ring[i, 2] * ft - ring[i, 1] * wr) / ring[i, 0]
        else:
            dx[2 * r + 2 + i] = 0.0
        d = math.sqrt(py * py + pz * pz)
        vs = cpi[7]
        if d > 0.0:
            vs += (-pz * uy + py * uz) / d
        rec[5 * i] = fn
        rec[5 * i + 1] = ft
        rec[5 * i + 2] = vs
        rec[5 * i + 3] = fy
        rec[5 * i + 4] = fz
    k, wt = _interp(tq_w, om)
    k1 = k + 1 if tq_w.shape[0] > 1 else k
    drive = (1.0 - wt) * tq_t[k] + wt * tq_t[k1]
    omd = (drive - drag * om + torque) / J
    dx[2 * r] = omd
    dx[2 * r + 1] = om
    for u in range(unb.shape[0]):
        ang = th + unb[u, 1]
        ca = math.cos(ang)
        sa = math.sin(ang)
        fy = unb[u, 0] * (om * om * ca + omd * sa)
        fz = unb[u, 0] * (om * om * sa - omd * ca)
        for b in range(r):
            dx[r + b] += Pu[2 * u, b] * fy + Pu[2 * u + 1, b] * fz


@njit(cache=True)
def spin_dopri(x0, t_out, mats, forces, cont, spin, ctrl, sink):
    """Integrate from ``t_out[0]`` through ``t_out`` with Dormand-Prince 5(4), saving every time.

    Parameters
    ----------
    x0 : ndarray (n_x,)
        Start state (see the module docstring).
    t_out : ndarray
        Output times (s), increasing.
    mats : tuple
        ``(sg (n_s,) rad/s, Kt (2, n_s, r, r) 1/s^2, Ct (2, n_s, r, r) 1/s, G (r, r) per rad/s
        ... 1/rad, fail_time s)``: the reduced stiffness and damping tabulated against speed,
        before (index 0) and after (index 1) ``fail_time``.
    forces : tuple
        ``(f0 (r,) N/sqrt(kg), Pu (2 n_u, r), unb (n_u, 2) [m e kg m, phase rad])``.
    cont : tuple
        ``(Pc (2 n_c, r), offs (2 n_c,) m, cp (n_c, 10), radius (n_c,) m,
        ring (n_c, 3) [J kg m^2, drag N m s, r m])``; ``J = 0`` for a fixed stator.
    spin : tuple
        ``(J kg m^2, drag N m s, speeds (n,) rad/s, torques (n,) N m)``.
    ctrl : ndarray (3 + n_x,)
        ``[rtol, h0 s, max_steps, atol per state...]``; ``ctrl[1]`` gets the next step size (s)
        on return, to continue with.
    sink : tuple
        ``(out, istate)``: ``out`` (n_x + 5 n_c, len(t_out)) is filled with the saved channels;
        ``istate`` (4,) int64 gets ``[status, accepted, rejected, samples saved]``.
    """
    out, istate = sink
    n = x0.shape[0]
    nc = cont[2].shape[0]
    rtol = ctrl[0]
    h = ctrl[1]
    max_steps = int(ctrl[2])
    atol = ctrl[3:]
    fail_time = mats[4]
    k = np.zeros((7, n))
    rec = np.zeros(5 * nc)
    xs = np.zeros(n)
    x5 = np.zeros(n)
    x = x0.copy()
    t = t_out[0]
    _rhs(t, x, mats, forces, cont, spin, k[0], rec)
    out[:n, 0] = x
    out[n:, 0] = rec
    acc = 0
    rej = 0
    m = 1
    while m < t_out.shape[0]:
        target = t_out[m]
        if t < fail_time < target:
            target = fail_time
        hit = False
        if t + h >= target:
            h = target - t
            hit = True
        for s in range(1, 7):
            for q in range(n):
                v = x[q]
                for p in range(s):
                    v += h * _A[s, p] * k[p, q]
                xs[q] = v
            _rhs(t + _C[s] * h, xs, mats, forces, cont, spin, k[s], rec)
        err = 0.0
        for q in range(n):
            x5[q] = xs[q]  # stage 7 is evaluated at the 5th-order solution (FSAL)
            e = 0.0
            for p in range(7):
                e += _E[p] * k[p, q]
            sc = atol[q] + rtol * max(abs(x[q]), abs(x5[q]))
            v = abs(h * e) / sc
            if not v <= err:  # a NaN state is not a small error: it propagates
                err = v
        if not math.isfinite(err):
            istate[0] = SPIN_DIVERGED
            break
        if err <= 1.0:
            t = target if hit else t + h
            for q in range(n):
                x[q] = x5[q]
                k[0, q] = k[6, q]
            acc += 1
            if hit and target == t_out[m]:
                _rhs(t, x, mats, forces, cont, spin, k[0], rec)
                out[:n, m] = x
                out[n:, m] = rec
                m += 1
            elif hit:  # at fail_time: the right-hand side changes, re-evaluate
                _rhs(t, x, mats, forces, cont, spin, k[0], rec)
            fac = 0.9 * err ** (-0.2) if err > 0 else 5.0
            h = h * min(5.0, max(0.2, fac))
        else:
            rej += 1
            h = h * max(0.1, 0.9 * err ** (-0.25))
            if h < 1e-14 * max(abs(t), 1e-3):
                istate[0] = SPIN_STEP_TOO_SMALL
                break
        if acc + rej > max_steps:
            istate[0] = SPIN_MAX_STEPS
            break
    istate[1] = acc
    istate[2] = rej
    istate[3] = m
    ctrl[1] = h  # the next step, so that a run continued from here takes the same steps
