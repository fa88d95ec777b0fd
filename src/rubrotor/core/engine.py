"""Compiled exponential stepper for a reduced linear rotor with several contacts (SI arrays).

The linear part (rotor modes, flexible stators) is diagonal in complex coordinates ``y``::

    y' = lam y + beta F(t),      F = [F_y1, F_z1, F_y2, F_z2, ...]  (N, force on the rotor)

and each step ``h`` propagates it exactly with the contact force held linear over the step
(first-order hold, second order in the force)::

    y_{n+1} = e^{lam h} y_n + h (phi1 - phi2) beta F_n + h phi2 beta F_{n+1}

with ``F_{n+1}`` solved implicitly: the contact displacement (relative to the stator centre) and
velocity at ``t_{n+1}`` are ``p = p_pred + S_d F_{n+1}``, ``u = u_pred + S_v F_{n+1}`` with real
``2 n_c x 2 n_c`` sensitivities (an anisotropic rotor couples ``F_y`` and ``F_z``; the residual
flexibility of the dropped modes is part of ``S_d``, ``S_v``), and Newton solves
``F = law(p(F), u(F))`` for all contacts together. When Newton fails the step is split in halves
(down to ``h / 2^(levels-1)``) instead of stopping.

Everything the kernel reads is grouped in named tuples (:mod:`rubrotor.engine.structs`):
``steps`` (per-level propagation coefficients), ``contacts`` (contact rows, laws) and ``outputs``
(output rows). Status codes are named in :data:`STATUS_NAMES`.

Saved channels per sample (``out[channel, sample]``): for each output station ``s`` (the rotor at
each contact, then the probes) ``4 s + 0..3`` = v, w (m), v', w' (m/s); then per contact ``i``,
from ``4 S + 8 i``: stator ``s_y, s_z`` (m), ``s_y', s_z'`` (m/s), force on the rotor ``F_y, F_z``
(N), normal force (N), friction force along ``i n`` (N).
"""

import math

import numpy as np
from numba import njit

from rubrotor.core.contact import force_scale, forces_of
from rubrotor.core.linalg import lu_solve as _lu_solve
from rubrotor.core.terms import FREE_RADIUS, can_be_free, length_scale, term, term_jac

__all__ = [
    "OK",
    "DIVERGED",
    "NEWTON_FAILED",
    "EVENT_BUFFER_FULL",
    "STATUS_NAMES",
    "I_STEP",
    "I_EVENTS",
    "I_STATUS",
    "I_SUBSTEPS",
    "I_NEWTON",
    "I_GRAZE",
    "I_ACCEPTED",
    "I_REJECTED",
    "I_LEVEL",
    "N_ISTATE",
    "EVENT_MARGIN",
    "CONTACT_CHANNELS",
    "expo_fixed",
]

from rubrotor.core.flags import SAFE_FASTMATH  # noqa: E402
from rubrotor.core.status import CONTACT_FAILED as NEWTON_FAILED  # noqa: E402
from rubrotor.core.status import DIVERGED, EVENT_BUFFER_FULL, MESSAGES, OK  # noqa: E402

STATUS_NAMES = dict(enumerate(MESSAGES))

EVENT_MARGIN = 128
"""Free event slots per contact required before a base step (more events in one step are
counted, not stored, and stop the run with EVENT_BUFFER_FULL)."""

# slots of the integer state vector
from rubrotor.core.status import I_EVENTS, I_STATUS, I_STEP  # noqa: E402

I_SUBSTEPS, I_NEWTON, I_GRAZE = 3, 4, 5
I_ACCEPTED, I_REJECTED, I_LEVEL = 6, 7, 8
N_ISTATE = 9
CONTACT_CHANNELS = 8


@njit(cache=True, inline="always")
def _rdot(row, y):
    """``Re(row . y)`` without computing the imaginary part."""
    acc = 0.0
    for j in range(y.shape[0]):
        acc += row[j].real * y[j].real - row[j].imag * y[j].imag
    return acc


@njit(cache=True)
def _eval(lin, F, cp, fn, ft, work):
    """Contact positions for forces ``F``, the laws' forces and their Jacobian blocks.

    ``lin = (pd, pv, Sd, Sv)``: the step's contact displacement and velocity without new force
    (m, m/s) and their sensitivities (m/N, m/(s N)); ``work`` the scratch of
    :func:`workspace`, whose ``f, p, u, jp, ju`` receive the forces (N), the positions (m, m/s)
    and the Jacobian blocks; ``fn``, ``ft`` the normal and friction forces (N)."""
    pd, pv, Sd, Sv = lin
    f, p, u, jp, ju = work[0], work[1], work[2], work[6], work[7]
    m = F.shape[0]
    for r in range(m):
        a = pd[r]
        b = pv[r]
        for c in range(m):
            a += Sd[r, c] * F[c]
            b += Sv[r, c] * F[c]
        p[r] = a
        u[r] = b
    for i in range(cp.shape[0]):
        k = 2 * i
        r = term_jac(p[k], p[k + 1], u[k], u[k + 1], cp[i])
        f[k] = r[0]
        f[k + 1] = r[1]
        fn[i] = r[2]
        ft[i] = r[3]
        jp[k, 0] = r[4]
        jp[k, 1] = r[5]
        ju[k, 0] = r[6]
        ju[k, 1] = r[7]
        jp[k + 1, 0] = r[8]
        jp[k + 1, 1] = r[9]
        ju[k + 1, 0] = r[10]
        ju[k + 1, 1] = r[11]


@njit(cache=True)
def workspace(m):
    """Scratch arrays of :func:`solve_contacts` for ``m`` force components (allocated once)."""
    v = np.zeros((6, m))
    return (v[0], v[1], v[2], v[3], v[4], v[5], np.zeros((m, 2)), np.zeros((m, 2)),
            np.zeros((m, m)), np.zeros((2, 4)))  # fmt: skip


@njit(cache=True)
def solve_contacts(lin, F0, cp, res_out, work):
    """Solve ``F = law(pd + Sd F, pv + Sv F)`` for all contacts together.

    ``lin = (pd, pv, Sd, Sv)``: ``pd``, ``pv`` (m, m/s) are the relative displacements and
    velocities the step gives without new force, ``Sd``, ``Sv`` their real sensitivities (m/N,
    m/(s N)); ``F0`` a start (N). Newton on the ``2 n_c`` real unknowns with step halving when
    the residual grows. ``res_out = (F, fn, ft)`` receive the force (N) and each contact's
    normal and friction force (N). Returns the iteration count, ``0`` when no contact closes,
    negative when Newton did not converge.
    """
    pd, pv, Sd, Sv = lin
    F, fn, ft = res_out
    m = F.shape[0]
    nc = cp.shape[0]
    f, zero, last, res = work[0], work[3], work[4], work[5]
    jp, ju, jr = work[6], work[7], work[8]
    start = False
    for r in range(m):
        if F0[r] != 0.0:
            start = True
    if not start:
        _eval(lin, zero, cp, fn, ft, work)
        closed = False
        for i in range(nc):
            if fn[i] != 0.0:
                closed = True
        if not closed:
            for r in range(m):
                F[r] = 0.0
            return 0
    scale = 0.0
    for i in range(nc):
        k = 2 * i
        sdn = max(abs(Sd[k, k]), abs(Sd[k, k + 1]), abs(Sd[k + 1, k]), abs(Sd[k + 1, k + 1]))
        scale = max(scale, force_scale(cp[i], sdn))
    tol = 1e-13 * scale
    for r in range(m):
        F[r] = F0[r] if start else f[r]
    for r in range(m):
        last[r] = 0.0
    rprev = 1e300
    for it in range(1, 60):
        _eval(lin, F, cp, fn, ft, work)
        rn = 0.0
        for r in range(m):
            res[r] = F[r] - f[r]
            rn += res[r] * res[r]
        rn = math.sqrt(rn)
        if rn > rprev and it > 1:
            for r in range(m):
                last[r] *= 0.5
                F[r] += last[r]
            rprev = 1e300
            continue
        if rn <= tol:
            _consistent(F, fn, ft)
            return it
        # J = I - Jp Sd - Ju Sv (Jp, Ju block diagonal, 2x2 per contact)
        for r in range(m):
            k = 2 * (r // 2)
            for c in range(m):
                jr[r, c] = (1.0 if r == c else 0.0) - (
                    jp[r, 0] * Sd[k, c] + jp[r, 1] * Sd[k + 1, c]
                    + ju[r, 0] * Sv[k, c] + ju[r, 1] * Sv[k + 1, c]
                )  # fmt: skip
        if not _lu_solve(jr, res):
            return -it
        dn = 0.0
        fnorm = 0.0
        for r in range(m):
            last[r] = res[r]
            F[r] -= res[r]
            dn += res[r] * res[r]
            fnorm += F[r] * F[r]
        rprev = rn
        if math.sqrt(dn) <= 1e-13 * math.sqrt(fnorm) + tol:
            _consistent(F, fn, ft)
            return it
    return -60


@njit(cache=True, inline="always")
def _consistent(F, fn, ft):
    """``fn``, ``ft`` (N) of the converged forces ``F`` (see :func:`forces_of`)."""
    for i in range(fn.shape[0]):
        fn[i], ft[i] = forces_of(F[2 * i], F[2 * i + 1], fn[i], ft[i])


@njit(cache=True)
def solve_one(lin, F0, cp, res_out):
    """:func:`solve_contacts` for a single contact, on scalars (the common case, ~2x faster)."""
    pd, pv, Sd, Sv = lin
    F, fn, ft = res_out
    c = cp[0]
    f0y, f0z = F0[0], F0[1]
    if f0y == 0.0 and f0z == 0.0:
        r = term(pd[0], pd[1], pv[0], pv[1], c)
        if r[2] == 0.0:
            F[0] = 0.0
            F[1] = 0.0
            fn[0] = 0.0
            ft[0] = 0.0
            return 0
        f0y, f0z = r[0], r[1]
    s00, s01, s10, s11 = Sd[0, 0], Sd[0, 1], Sd[1, 0], Sd[1, 1]
    v00, v01, v10, v11 = Sv[0, 0], Sv[0, 1], Sv[1, 0], Sv[1, 1]
    tol = 1e-13 * force_scale(c, max(abs(s00), abs(s01), abs(s10), abs(s11)))
    fy, fz = f0y, f0z
    ly, lz = 0.0, 0.0
    rprev = 1e300
    for it in range(1, 60):
        py = pd[0] + s00 * fy + s01 * fz
        pz = pd[1] + s10 * fy + s11 * fz
        uy = pv[0] + v00 * fy + v01 * fz
        uz = pv[1] + v10 * fy + v11 * fz
        r = term_jac(py, pz, uy, uz, c)
        fn[0] = r[2]
        ft[0] = r[3]
        ry = fy - r[0]
        rz = fz - r[1]
        rn = math.sqrt(ry * ry + rz * rz)
        if rn > rprev and it > 1:
            ly *= 0.5
            lz *= 0.5
            fy += ly
            fz += lz
            rprev = 1e300
            continue
        if rn <= tol:
            F[0] = fy
            F[1] = fz
            fn[0], ft[0] = forces_of(fy, fz, fn[0], ft[0])
            return it
        a11 = 1.0 - (r[4] * s00 + r[5] * s10 + r[6] * v00 + r[7] * v10)
        a12 = -(r[4] * s01 + r[5] * s11 + r[6] * v01 + r[7] * v11)
        a21 = -(r[8] * s00 + r[9] * s10 + r[10] * v00 + r[11] * v10)
        a22 = 1.0 - (r[8] * s01 + r[9] * s11 + r[10] * v01 + r[11] * v11)
        det = a11 * a22 - a12 * a21
        if det == 0.0:
            return -it
        ly = (a22 * ry - a12 * rz) / det
        lz = (-a21 * ry + a11 * rz) / det
        fy -= ly
        fz -= lz
        rprev = rn
        if math.sqrt(ly * ly + lz * lz) <= 1e-13 * math.sqrt(fy * fy + fz * fz) + tol:
            F[0] = fy
            F[1] = fz
            fn[0], ft[0] = forces_of(fy, fz, fn[0], ft[0])
            return it
    return -60


@njit(cache=True)
def graze_contacts(lin, cp, res_out, work):
    """Set-valued closure when Newton has no solution to converge to (a law that jumps at zero
    penetration, e.g. the linear law's dashpot): each contact in turn gets the fraction ``s`` of
    its law's force at zero new force that puts it exactly on the clearance circle (bisection on
    ``|p(s)| - g``), the complementarity solution ``eps = 0``, ``0 <= F_n <= c eps_dot``.
    Returns 1 when every contact could be placed, else -1. Arguments as
    :func:`solve_contacts`.
    """
    pd, pv, Sd, Sv = lin
    F, fn, ft = res_out
    m = F.shape[0]
    f, p = work[0], work[1]
    for i in range(cp.shape[0]):
        if not can_be_free(cp[i]):
            return -1  # a film or a magnet has no clearance to place a contact on
    for r in range(m):
        F[r] = 0.0
    for i in range(cp.shape[0]):
        _eval(lin, F, cp, fn, ft, work)
        if fn[i] == 0.0:
            continue
        fy, fz = f[2 * i], f[2 * i + 1]
        lo, hi = 0.0, 1.0
        F[2 * i] = fy
        F[2 * i + 1] = fz
        _eval(lin, F, cp, fn, ft, work)
        if math.sqrt(p[2 * i] ** 2 + p[2 * i + 1] ** 2) > cp[i, 4] and fn[i] != 0.0:
            return -1
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            F[2 * i] = mid * fy
            F[2 * i + 1] = mid * fz
            _eval(lin, F, cp, fn, ft, work)
            if math.sqrt(p[2 * i] ** 2 + p[2 * i + 1] ** 2) > cp[i, 4]:
                lo = mid
            else:
                hi = mid
        F[2 * i] = hi * fy
        F[2 * i + 1] = hi * fz
    _eval(lin, F, cp, fn, ft, work)
    for i in range(cp.shape[0]):
        fn[i] = math.sqrt(F[2 * i] ** 2 + F[2 * i + 1] ** 2) / math.sqrt(1.0 + cp[i, 5] ** 2)
    return 1


@njit(cache=True)
def _write(sink, idx, y, z, forces, contacts, outputs):
    """Write sample ``idx`` to ``sink.out`` (and the state to ``sink.ys`` when kept) from the
    state ``y``, phasor ``z`` and ``forces = (F, fn, ft)``: the contact forces ``F`` and the
    normal and friction forces ``fn``, ``ft`` (N) of the last contact solve."""
    out, ys = sink.out, sink.ys
    F, fn, ft = forces
    Od, Ov, ORd, ORv = outputs.Od, outputs.Ov, outputs.ORd, outputs.ORv
    OPu, OPv, Od0 = outputs.OPu, outputs.OPv, outputs.Od0
    nrow = Od.shape[0]
    m = F.shape[0]
    for r in range(nrow):
        d = _rdot(Od[r], y) + (OPu[r] * z).real + Od0[r]
        v = _rdot(Ov[r], y) + (OPv[r] * z).real
        for c in range(m):
            d += ORd[r, c] * F[c]
            v += ORv[r, c] * F[c]
        s, a = r // 2, r % 2
        out[4 * s + a, idx] = d
        out[4 * s + 2 + a, idx] = v
    base = 2 * nrow
    for i in range(fn.shape[0]):
        b = base + 8 * i
        for a in range(2):
            k = 2 * i + a
            if outputs.flex[i] != 0.0:
                out[b + a, idx] = _rdot(outputs.Sd[k], y)
                out[b + 2 + a, idx] = _rdot(outputs.Sv[k], y)
            else:
                out[b + a, idx] = 0.0
                out[b + 2 + a, idx] = 0.0
            out[b + 4 + a, idx] = F[k]
        out[b + 6, idx] = fn[i]
        out[b + 7, idx] = ft[i]
    if ys.shape[0] > 0:
        for j in range(y.shape[0]):
            ys[idx, j] = y[j]


@njit(cache=True, inline="always")
def _phi1(z):
    if abs(z) < 1e-3:
        return 1.0 + z * (0.5 + z / 6.0)
    return (np.exp(z) - 1.0) / z


@njit(cache=True)
def _drive(dy, drive, t, h, E):
    """Modal increment over ``[t, t + h]`` of the unbalance driven at a varying speed."""
    tm = t + 0.5 * h
    om = drive.omega0 + drive.alpha * tm
    th = drive.omega0 * t + 0.5 * drive.alpha * t * t
    amp = complex(om * om, -drive.alpha)
    ep = amp * complex(math.cos(th), math.sin(th))
    em = amp.conjugate() * complex(math.cos(th), -math.sin(th))
    lam = drive.lam
    for j in range(dy.shape[0]):
        cp_ = h * E[j] * _phi1((1j * om - lam[j]) * h)
        cm_ = h * E[j] * _phi1((-1j * om - lam[j]) * h)
        dy[j] = ep * drive.Bp[j] * cp_ + em * drive.Bm[j] * cm_


@njit(cache=True, inline="always", fastmath=SAFE_FASTMATH)
def has_history(Fp, m):
    """Whether the previous step's contact forces exist (a step before this one in contact)."""
    for r in range(m):
        if Fp[r] != 0.0:
            return True
    return False


@njit(cache=True, inline="always", fastmath=SAFE_FASTMATH)
def hold_error(Fn, F, Fp, m, h, hp, a_f, omega):
    """Local error (m) of holding the contact force linear over a step of ``h`` (s): the
    force's second difference over this and the previous step ``hp`` (s) bounds its curvature;
    ``a_f`` maps force to acceleration. Returns ``max(e_v h / 2, e_v / omega)``, the
    displacement error and the velocity error over the spin ``omega`` (rad/s)."""
    f2 = 0.0
    for r in range(m):
        d2 = (Fn[r] - F[r]) / h - (F[r] - Fp[r]) / hp
        f2 += d2 * d2
    f2 = 2.0 * math.sqrt(f2) / (h + hp)
    e_v = a_f * h * h * h * f2 / 12.0
    return max(0.5 * e_v * h, e_v / omega)


@njit(cache=True, fastmath=SAFE_FASTMATH)
def expo_fixed(state, span, sink, steps, contacts, outputs, drive, control):
    """Fixed steps ``h = steps.h[0]``, halved where the contact solve fails.

    ``state`` (``State``, in/out): ``y`` (ns,) complex modal coordinates (shifted by the static
    and unbalance particular solutions), ``F``, ``Fp`` (m,) current and previous contact forces
    (N), ``dprev`` (nc,) last relative radial displacements (m), ``clock = [z]`` the unbalance
    phasor, ``istate`` (I_* slots), ``stats = [h_prev]``. ``span`` (``Span``): writes
    ``n_samples`` samples to ``sink.out[:, offset:offset + n]`` every ``save_every`` steps at
    spin ``omega`` (rad/s) from the run's start ``t0`` (s), and returns the number written;
    stops early on a status (:data:`STATUS_NAMES`). ``sink.events`` (cap, 2) collects
    ``[t, +/-(i + 1)]`` onsets (+) and separations (-) of contact ``i``, located by linear
    interpolation of the radial gap; ``sink.ys`` the modal states when not empty.

    ``drive`` (``Drive``): when ``drive.on``, the unbalance is an input instead of a particular
    solution (speed varying as ``Omega = omega0 + alpha t``): over each step the force
    ``Re((Omega^2 - i alpha) e^{i theta} b)`` enters each mode exactly for the frequency
    ``Omega`` of the step's midpoint (``int_0^h e^{lam (h - s)} e^{i Omega s} ds =
    h e^{lam h} phi1((i Omega - lam) h)``), its amplitude held at the midpoint value.

    ``control`` (``Control``): when ``control.on``, steps are chosen by a local error estimate
    (adaptive mode, one sample per base step ``h_0``): in contact with a force history, the
    error of holding the force linear, ``|a_F| h^3 |F''| / 12`` in velocity and half that times
    ``h`` in displacement (``a_F`` the direct acceleration per N, ``F''`` from the last three
    forces); at onsets and separations the zero- against first-order-hold difference
    ``errc |F_{n+1} - F_n|``, and every change of contact state is refined to the finest level
    (onsets located to ``h_0 / 2^(levels-1)``). A step is rejected and halved when
    ``max(e_d, e_v / Omega) > atol + rtol max(|p|, g)``; it doubles again after steps below 1/20
    of that.
    """
    y, F, Fp, dprev, zt = state.y, state.F, state.Fp, state.dprev, state.clock
    istate, stats = state.istate, state.stats
    n_samples, save_every, offset = span.n_samples, span.save_every, span.offset
    omega, t0 = span.omega, span.t0
    events = sink.events
    E, G0, G1, BT, CdE, CvE = steps.E, steps.G0, steps.G1, steps.BT, steps.CdE, steps.CvE
    CdG0b, CvG0b, Sd, Sv, rot, hs = steps.CdG0b, steps.CvG0b, steps.Sd, steps.Sv, steps.rot, steps.h
    Pu, Pv, d0, cp, max_disp = (contacts.Pu, contacts.Pv, contacts.d0, contacts.cp,
                                contacts.max_disp)  # fmt: skip
    ns = y.shape[0]
    m = F.shape[0]
    nc = cp.shape[0]
    J = E.shape[0] - 1
    full = 1 << J
    pd = np.empty(m)
    pv = np.empty(m)
    Fn = np.zeros(m)
    F0 = np.zeros(m)
    fn = np.zeros(nc)
    ft = np.zeros(nc)
    work = workspace(m)
    bF = np.zeros(ns, np.complex128)  # beta F_n, the modal input of the current force
    for c in range(m):
        for j in range(ns):
            bF[j] += BT[c, j] * F[c]
    z = zt[0]
    h0 = hs[0]
    hp = stats[0]
    dy = np.zeros(ns, np.complex128)  # drive increment of the step
    drv = drive.on != 0.0
    ctl = control.on != 0.0
    gmin = 1e300
    for i in range(nc):
        gmin = min(gmin, length_scale(cp[i]))
    CdU = contacts.Cd
    CvU = contacts.Cv
    written = 0
    cap = events.shape[0]
    while written < n_samples:
        if istate[I_EVENTS] + EVENT_MARGIN * nc > cap:
            istate[I_STATUS] = EVENT_BUFFER_FULL  # the driver grows the buffer and resumes
            break
        step = istate[I_STEP]
        pos = 0
        lev = istate[I_LEVEL] if ctl else 0
        while pos < full:
            units = 1 << (J - lev)
            zn = z * rot[lev]
            if drv:
                _drive(dy, drive, t0 + (step + pos / full) * h0, hs[lev], E[lev])
            loaded = False
            for r in range(m):
                if F[r] != 0.0:
                    loaded = True
            for r in range(m):
                pd[r] = d0[r] + (Pu[r] * zn).real + _rdot(CdE[lev, r], y)
                if loaded:
                    for c in range(m):
                        pd[r] += CdG0b[lev, r, c] * F[c]
                if drv:
                    pd[r] += _rdot(CdU[r], dy)
            h = hs[lev]
            free = True  # every contact inside its clearance without new force: F = 0 solves
            for i in range(nc):
                g = cp[i, FREE_RADIUS]  # < 0: a row that always acts is never free
                if not (g >= 0.0 and pd[2 * i] ** 2 + pd[2 * i + 1] ** 2 <= g * g):  # NaN too
                    free = False
            if free and not loaded:
                # free flight: exact propagation only, no force, no event possible
                for j in range(ns):
                    y[j] = E[lev, j] * y[j]
                if drv:
                    for j in range(ns):
                        y[j] += dy[j]
                for i in range(nc):
                    dprev[i] = math.sqrt(pd[2 * i] ** 2 + pd[2 * i + 1] ** 2)
                for r in range(m):
                    Fp[r] = 0.0
                for i in range(nc):
                    fn[i] = 0.0
                    ft[i] = 0.0
                hp = h
                z = zn
                pos += units
                istate[I_ACCEPTED] += 1
                if lev > 0 and pos % (2 * units) == 0:
                    lev -= 1
                continue
            extrap = False
            for r in range(m):
                if F[r] != 0.0 and Fp[r] != 0.0:
                    extrap = True
            for r in range(m):
                F0[r] = F[r] + (F[r] - Fp[r]) * (h / hp) if extrap else F[r]
            if free:
                it = 0
                for r in range(m):
                    Fn[r] = 0.0
                for i in range(nc):
                    fn[i] = 0.0
                    ft[i] = 0.0
            else:
                for r in range(m):
                    pv[r] = (Pv[r] * zn).real + _rdot(CvE[lev, r], y)
                    if drv:
                        pv[r] += _rdot(CvU[r], dy)
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
                    istate[I_GRAZE] += 1
            if it < 0:
                if lev < J:
                    lev += 1
                    istate[I_SUBSTEPS] += 1
                    continue
                istate[I_STATUS] = NEWTON_FAILED
                break
            istate[I_NEWTON] += it
            new = False
            for r in range(m):
                if Fn[r] != 0.0:
                    new = True
            err = 0.0
            changed = False
            if ctl:
                pmax = 0.0
                for i in range(nc):
                    was = F[2 * i] != 0.0 or F[2 * i + 1] != 0.0
                    now = Fn[2 * i] != 0.0 or Fn[2 * i + 1] != 0.0
                    if was != now:
                        changed = True
                    a = pd[2 * i]
                    b = pd[2 * i + 1]
                    for c in range(m):
                        a += Sd[lev, 2 * i, c] * Fn[c]
                        b += Sd[lev, 2 * i + 1, c] * Fn[c]
                    pmax = max(pmax, math.sqrt(a * a + b * b))
                tol = control.atol + control.rtol * max(pmax, gmin)
                if new and loaded and has_history(Fp, m):
                    err = hold_error(Fn, F, Fp, m, h, hp, control.a_f, omega) / tol
                else:
                    dfn = 0.0
                    for r in range(m):
                        dfn += (Fn[r] - F[r]) ** 2
                    err = control.errc[lev] * math.sqrt(dfn) / tol
                if lev < J and (err > 1.0 or changed):
                    lev += 1
                    istate[I_REJECTED] += 1
                    continue
            istate[I_ACCEPTED] += 1
            if loaded or new:
                if m == 2:
                    f0, f1 = Fn[0], Fn[1]
                    for j in range(ns):
                        b = BT[0, j] * f0 + BT[1, j] * f1
                        y[j] = E[lev, j] * y[j] + G0[lev, j] * bF[j] + G1[lev, j] * b
                        bF[j] = b
                else:
                    for j in range(ns):
                        b = 0j
                        for c in range(m):
                            b += BT[c, j] * Fn[c]
                        y[j] = E[lev, j] * y[j] + G0[lev, j] * bF[j] + G1[lev, j] * b
                        bF[j] = b
            else:
                for j in range(ns):
                    y[j] = E[lev, j] * y[j]
            if drv:
                for j in range(ns):
                    y[j] += dy[j]
            pos += units
            t_new = t0 + (step + pos / full) * h0
            bad = False
            for i in range(nc):
                a = pd[2 * i]
                b = pd[2 * i + 1]
                for c in range(m):
                    a += Sd[lev, 2 * i, c] * Fn[c]
                    b += Sd[lev, 2 * i + 1, c] * Fn[c]
                d = math.sqrt(a * a + b * b)
                if not (d <= max_disp):
                    bad = True
                was = F[2 * i] != 0.0 or F[2 * i + 1] != 0.0
                now = Fn[2 * i] != 0.0 or Fn[2 * i + 1] != 0.0
                if was != now and cp[i, 0] != 0.0 and can_be_free(cp[i]):
                    g = cp[i, FREE_RADIUS]
                    den = d - dprev[i]
                    frac = (g - dprev[i]) / den if den != 0.0 else 1.0
                    frac = min(max(frac, 0.0), 1.0)
                    ne = istate[I_EVENTS]
                    if ne < cap:  # beyond: counted, not stored; reported after the step
                        events[ne, 0] = t_new - (1.0 - frac) * h
                        events[ne, 1] = (i + 1) if now else -(i + 1)
                    istate[I_EVENTS] = ne + 1
                dprev[i] = d
            for r in range(m):
                Fp[r] = F[r]
                F[r] = Fn[r]
            hp = h
            z = zn
            if bad:
                istate[I_STATUS] = DIVERGED
                break
            if lev > 0 and pos % (2 * units) == 0 and (not ctl or (err < 0.05 and not changed)):
                lev -= 1
        if istate[I_STATUS] != OK:
            break
        step += 1
        istate[I_STEP] = step
        istate[I_LEVEL] = lev
        if istate[I_EVENTS] > cap:
            istate[I_STATUS] = EVENT_BUFFER_FULL  # events were lost: the driver stops
        tt = omega * (t0 + step * h0)
        z = complex(math.cos(tt), math.sin(tt))
        if step % save_every == 0:
            _write(sink, offset + written, y, z, (F, fn, ft), contacts, outputs)
            written += 1
    zt[0] = z
    stats[0] = hp
    return written
