"""Compiled adaptive stepper: exact free flight between contacts, error-controlled contact steps.

Same model and state as :func:`rubrotor.core.engine.expo_fixed` (diagonal complex modal
coordinates ``y``, ``y' = lam y + beta F``, the contact force held linear over a step and solved
implicitly). What differs is how time advances:

Free flight (no contact force)
    The solution is known in closed form, ``y(t + s) = e^{lam s} y(t)``, and the relative
    contact displacement is ``p(s) = d0 + Re(Pu z e^{i Omega s}) + Re(Cd e^{lam s} y)``. Over
    ``[0, S]`` it obeys the guaranteed bound (Taylor with remainder)::

        |p(s)| <= b(s) = |p(0) + s p'(0)| + A s^2 / 2,
        A = |(Omega^2 |Pu_y| + sum_j |Cd_yj lam_j^2| |y_j| G, same for z)|,  G = max(1, e^{Re lam S})

    ``b`` is convex, so ``b(S) < g`` certifies every ``s`` in ``[0, S]`` free (``S`` up to
    ``LOOK_AHEAD`` samples): the state jumps from sample to sample (one multiplication per mode)
    with no further check until the certified time. Otherwise the largest
    certified ``s`` (root of ``b = g`` by bisection) is taken and the bound re-evaluated
    (conservative advancement: it converges quadratically to a transversal onset and takes
    steps ``~ sqrt(2 gap / A)`` past a near-graze, so no contact is ever stepped over). The
    onset is located when the gap is below ``tol_x``; contact steps start there.

Contact
    Steps ``h = H 2^-l`` (``H`` the output spacing, ``l`` from ``-LEVELS_UP`` to ``J``) chosen by
    the local error estimate alone (:class:`rubrotor.engine.structs.Control`); per-level
    coefficients are computed on first use and kept. Samples inside a step come from the
    step's own interpolant (exact for the held force)::

        y(t_n + s) = e^{lam s} y_n + s phi1(lam s) beta F_n + (s^2 / h) phi2(lam s) beta (F_{n+1} - F_n)

    A change of contact state inside a step (a separation, or an onset of another contact) is
    located by regula falsi on the radial displacement (the step shortened to the estimated
    crossing) until the crossing lies at a step's start within ``tol_x`` or the step reaches
    the finest ``H / 2^J``. A force the law releases inside the clearance (a dashpot's pull
    clipped to zero) is continuous there: it is left to the error control.

Order-4 contact steps (``plan.order == 4``, stepper ``"collocation"``)
    The force is held quadratic through ``F_n, F_m, F_{n+1}`` at ``0, h/2, h`` and both new
    values are solved implicitly from the contact law at the midpoint and at the end
    (exponential collocation at the Lobatto points; the linear part still exact)::

        y(s) = e^{lam s} y_n + beta (w0(s) F_n + wm(s) F_m + w1(s) F_{n+1}),
        int_0^s e^{lam (s - r)} (r / h)^k dr = k! s^{k+1} phi_{k+1}(lam s) / h^k

    (:func:`colloc_weights`). The local error is Simpson's, estimated from the force's fourth
    divided difference over this and the previous step (:func:`quad_error`); without a
    history (an onset, a chunk's start), from the quadratic-against-linear difference. A step
    whose midpoint alone is in contact (a contact shorter than the step) is halved. Samples
    inside a step: the first from the weights at its offset, the next ones advanced by one
    output spacing each with precomputed ``H^k phi_k(lam H)``. Measured order 3.9 against 2.0
    (tests/test_engine_collocation.py).
"""

import math

import numpy as np
from numba import njit

from rubrotor.core.engine import (
    DIVERGED,
    EVENT_BUFFER_FULL,
    EVENT_MARGIN,
    I_ACCEPTED,
    I_EVENTS,
    I_GRAZE,
    I_NEWTON,
    I_REJECTED,
    I_STATUS,
    I_STEP,
    I_SUBSTEPS,
    NEWTON_FAILED,
    SAFE_FASTMATH,
    _rdot,
    _write,
    graze_contacts,
    has_history,
    hold_error,
    solve_contacts,
    solve_one,
    workspace,
)
from rubrotor.core.terms import FREE_RADIUS, can_be_free, length_scale, term

__all__ = [
    "expo_adaptive",
    "phi012",
    "LEVELS_UP",
    "T_TIME",
    "T_HPREV",
    "T_LEVEL",
    "T_FREE",
    "T_FILLS",
    "N_TSTATE",
]

LEVELS_UP = 4
"""Contact steps may grow to ``2^LEVELS_UP`` output spacings."""

LOOK_AHEAD = 16
"""Free flight is certified up to this many output spacings ahead per bound evaluation."""

# slots of the float state vector
T_TIME, T_HPREV, T_LEVEL, T_FREE, T_FILLS = 0, 1, 2, 3, 4
N_TSTATE = 5


@njit(cache=True, inline="always")
def phi012(z):
    """``(e^z, phi1(z), phi2(z))`` for complex ``z``; ``phi1 = (e^z - 1)/z``,
    ``phi2 = (phi1 - 1)/z``, by their series below ``|z| = 0.1`` (relative error < 1e-14)."""
    ez = np.exp(z)
    if abs(z) < 0.1:
        acc = 1.0 + 0j
        for k in range(11, 2, -1):
            acc = 1.0 + z * acc / k
        p2 = 0.5 * acc
        return ez, 1.0 + z * p2, p2
    p1 = (ez - 1.0) / z
    return ez, p1, (p1 - 1.0) / z


_C3 = np.array([1.0 / math.factorial(j + 3) for j in range(16)])
"""Taylor coefficients of ``phi3``: ``1 / (j + 3)!``, ``j = 0..15``."""


@njit(cache=True, inline="always")
def phi0123(z):
    """``(e^z, phi1(z), phi2(z), phi3(z))`` for complex ``z``; ``phi3 = (phi2 - 1/2)/z``, by
    its Taylor series (16 terms, remainder below ``1e-17``) for ``|z| < 1``, evaluated by
    Estrin's scheme (short dependency chains: ~4x faster than Horner's), ``phi2 = 1/2 + z
    phi3``, ``phi1 = 1 + z phi2`` there."""
    ez = np.exp(z)
    if z.real * z.real + z.imag * z.imag < 1.0:
        c = _C3
        z2 = z * z
        z4 = z2 * z2
        z8 = z4 * z4
        a0 = (c[0] + c[1] * z) + (c[2] + c[3] * z) * z2
        a1 = (c[4] + c[5] * z) + (c[6] + c[7] * z) * z2
        a2 = (c[8] + c[9] * z) + (c[10] + c[11] * z) * z2
        a3 = (c[12] + c[13] * z) + (c[14] + c[15] * z) * z2
        p3 = (a0 + a1 * z4) + (a2 + a3 * z4) * z8
        p2 = 0.5 + z * p3
        return ez, 1.0 + z * p2, p2, p3
    p1 = (ez - 1.0) / z
    p2 = (p1 - 1.0) / z
    return ez, p1, p2, (p2 - 0.5) / z


@njit(cache=True, inline="always")
def colloc_weights(lam, s, h):
    """``(e^{lam s}, w0, wm, w1)``: the state at ``s`` (s) inside a step ``h`` (s) whose force is
    the quadratic through ``F0, Fm, F1`` at ``0, h/2, h`` is ``e^{lam s} y + beta (w0 F0 +
    wm Fm + w1 F1)`` (exact: ``int_0^s e^{lam (s - r)} (r / h)^k dr = k! s^{k+1}
    phi_{k+1}(lam s) / h^k``)."""
    e, p1, p2, p3 = phi0123(lam * s)
    r = s / h
    i0 = s * p1
    i1 = s * r * p2
    i2 = 2.0 * s * r * r * p3
    return e, i0 - 3.0 * i1 + 2.0 * i2, 4.0 * i1 - 4.0 * i2, 2.0 * i2 - i1


@njit(cache=True)
def _fill4(tab4, k, h, lam, rows):
    """Coefficients of a collocation step ``h`` (s) into row ``k`` of ``tab4``: per stage
    (midpoint, end) the propagator and force weights, the contact rows times the propagator, and
    the real responses of the stacked stage rows ``[p(h/2), p(h)]`` to ``F0`` (``P0d, P0v``) and
    to the unknown stage forces ``[Fm, F1]`` (``S2d, S2v``, residual flexibility on the diagonal
    blocks); ``rows = (Cd, Cv, BT, Rd, Rv)`` the contact rows, modal input and residual."""
    E, Em, W, CdE, CvE, CdEm, CvEm, P0d, P0v, S2d, S2v = tab4
    Cd, Cv, BT, Rd, Rv = rows
    ns = lam.shape[0]
    m = Cd.shape[0]
    for j in range(ns):
        e, w0, wm, w1 = colloc_weights(lam[j], h, h)
        E[k, j] = e
        W[k, 3, j], W[k, 4, j], W[k, 5, j] = w0, wm, w1
        e, w0, wm, w1 = colloc_weights(lam[j], 0.5 * h, h)
        Em[k, j] = e
        W[k, 0, j], W[k, 1, j], W[k, 2, j] = w0, wm, w1
    for r in range(m):
        for j in range(ns):
            CdE[k, r, j] = Cd[r, j] * E[k, j]
            CvE[k, r, j] = Cv[r, j] * E[k, j]
            CdEm[k, r, j] = Cd[r, j] * Em[k, j]
            CvEm[k, r, j] = Cv[r, j] * Em[k, j]
    for st in range(2):
        for r in range(m):
            R = st * m + r
            for c in range(m):
                for q in range(3):  # force F0, Fm, F1
                    a = 0.0
                    b = 0.0
                    for j in range(ns):
                        wb = W[k, 3 * st + q, j] * BT[c, j]
                        a += (Cd[r, j] * wb).real
                        b += (Cv[r, j] * wb).real
                    if q == 0:
                        P0d[k, R, c] = a
                        P0v[k, R, c] = b
                    else:
                        C = (q - 1) * m + c
                        S2d[k, R, C] = a + (Rd[r, c] if q - 1 == st else 0.0)
                        S2v[k, R, C] = b + (Rv[r, c] if q - 1 == st else 0.0)


@njit(cache=True)
def _dense4(ysmp, y, bF, bM, bN, lam, s, h):
    """State at ``t_n + s`` (s) from a collocation step's quadratic force (exact for it)."""
    for j in range(y.shape[0]):
        e, w0, wm, w1 = colloc_weights(lam[j], s, h)
        ysmp[j] = e * y[j] + w0 * bF[j] + wm * bM[j] + w1 * bN[j]


@njit(cache=True)
def _dense4_next(ysmp, bF, bM, bN, EH, PH, s, h):
    """Advance the interpolated state ``ysmp`` at ``t_n + s`` (s) by one output spacing ``H``
    inside the collocation step ``h`` (s): the quadratic force re-expanded at ``s``,
    ``F(s + r) = F + r F' + r^2 F'' / 2``, enters exactly as ``y <- e^{lam H} y +
    beta (H phi1 F + H^2 phi2 F' + H^3 phi3 F'')`` with ``PH`` (3, ns) those ``H^k phi_k(lam H)``
    (four complex products per mode instead of an exponential and a series)."""
    th = s / h
    l0 = 2.0 * (th - 0.5) * (th - 1.0)
    lm = -4.0 * th * (th - 1.0)
    l1 = 2.0 * th * (th - 0.5)
    ih = 1.0 / h
    d0 = (4.0 * th - 3.0) * ih
    dm = (4.0 - 8.0 * th) * ih
    d1 = (4.0 * th - 1.0) * ih
    c2 = 4.0 * ih * ih
    for j in range(ysmp.shape[0]):
        g0 = l0 * bF[j] + lm * bM[j] + l1 * bN[j]
        g1 = d0 * bF[j] + dm * bM[j] + d1 * bN[j]
        g2 = c2 * (bF[j] - 2.0 * bM[j] + bN[j])
        ysmp[j] = EH[j] * ysmp[j] + PH[0, j] * g0 + PH[1, j] * g1 + PH[2, j] * g2


@njit(cache=True, inline="always")
def quad_error(forces, m, hp, h, a_f, omega):
    """Local error (m) of a collocation step ``h`` (s) with the force held quadratic: Simpson's
    ``h^5 |F| / 2880`` in velocity per unit acceleration ``a_f``, ``F`` from the fourth
    divided difference of the five forces at ``-hp, -hp/2, 0, h/2, h`` (this and the previous
    step ``hp``, s), ``forces = (Fp, Fpm, F, Fm, Fn)`` (N). Returns ``max(e_v h / 2,
    e_v / omega)`` as :func:`hold_error`."""
    Fp, Fpm, F, Fm, Fn = forces
    x0, x1, x2, x3, x4 = -hp, -0.5 * hp, 0.0, 0.5 * h, h
    f4 = 0.0
    for r in range(m):
        d01 = (Fpm[r] - Fp[r]) / (x1 - x0)
        d12 = (F[r] - Fpm[r]) / (x2 - x1)
        d23 = (Fm[r] - F[r]) / (x3 - x2)
        d34 = (Fn[r] - Fm[r]) / (x4 - x3)
        d012 = (d12 - d01) / (x2 - x0)
        d123 = (d23 - d12) / (x3 - x1)
        d234 = (d34 - d23) / (x4 - x2)
        d0123 = (d123 - d012) / (x3 - x0)
        d1234 = (d234 - d123) / (x4 - x1)
        d4 = (d1234 - d0123) / (x4 - x0)
        f4 += (24.0 * d4) ** 2
    e_v = a_f * h**5 * math.sqrt(f4) / 2880.0
    return max(0.5 * e_v * h, e_v / omega)


@njit(cache=True)
def _fill(tab, k, h, lam, rows):
    """Coefficients of a step ``h`` (s) into row ``k`` of the tables ``tab``; ``rows = (Cd, Cv,
    Wd, Wv, Rd, Rv)`` the contact rows, their products with the modal input and the residual."""
    E, G0, G1, CdE, CvE, Q0d, Q0v, Sd, Sv = tab
    Cd, Cv, Wd, Wv, Rd, Rv = rows
    ns = lam.shape[0]
    m = Cd.shape[0]
    for j in range(ns):
        e, p1, p2 = phi012(lam[j] * h)
        E[k, j] = e
        G0[k, j] = h * (p1 - p2)
        G1[k, j] = h * p2
    for r in range(m):
        for j in range(ns):
            CdE[k, r, j] = Cd[r, j] * E[k, j]
            CvE[k, r, j] = Cv[r, j] * E[k, j]
        for c in range(m):
            a0 = 0.0
            b0 = 0.0
            a1 = 0.0
            b1 = 0.0
            for j in range(ns):
                a0 += (Wd[r, c, j] * G0[k, j]).real
                b0 += (Wv[r, c, j] * G0[k, j]).real
                a1 += (Wd[r, c, j] * G1[k, j]).real
                b1 += (Wv[r, c, j] * G1[k, j]).real
            Q0d[k, r, c] = a0
            Q0v[k, r, c] = b0
            Sd[k, r, c] = a1 + Rd[r, c]
            Sv[k, r, c] = b1 + Rv[r, c]


@njit(cache=True, inline="always")
def _bound(py, pz, vy, vz, a, s):
    """``b(s) = |p + s v| + a s^2 / 2`` (m)."""
    return math.sqrt((py + s * vy) ** 2 + (pz + s * vz) ** 2) + 0.5 * a * s * s


@njit(cache=True)
def _free_look(y, z, S, omega, contacts, look, scratch):
    """Largest certified free advance in ``[0, S]`` (s) from the state ``y``, phasor ``z``.

    ``look = (Ca, grow, tol_x)``: the look-ahead rows, ``grow`` a bound of ``|e^{lam s}|`` for
    ``s <= S`` and the gap ``tol_x`` (m) of a located onset. ``scratch = (ay, p0, v0)``: ``ay``
    for ``|y|``; ``p0``, ``v0`` receive (m, m/s) the relative contact displacement and velocity. Returns
    ``(s, located, rmax)``: ``s`` the certified advance, ``located`` True when a contact's gap is
    below ``tol_x`` (m) (an onset to hand to the contact steps), ``rmax`` the largest radial
    displacement (m, for the divergence check)."""
    Cd, Cv, Pu, Pv, d0, cp = (contacts.Cd, contacts.Cv, contacts.Pu, contacts.Pv, contacts.d0,
                              contacts.cp)  # fmt: skip
    Ca, grow, tol_x = look
    ay, p0, v0 = scratch
    ns = y.shape[0]
    for j in range(ns):
        ay[j] = math.sqrt(y[j].real ** 2 + y[j].imag ** 2)
    best = S
    located = False
    rmax = 0.0
    w2 = omega * omega
    for i in range(cp.shape[0]):
        A2 = 0.0
        for a in range(2):
            r = 2 * i + a
            p0[r] = d0[r] + (Pu[r] * z).real + _rdot(Cd[r], y)
            v0[r] = (Pv[r] * z).real + _rdot(Cv[r], y)
            s2 = 0.0
            for j in range(ns):
                s2 += Ca[r, j] * ay[j]
            A2 += (w2 * math.sqrt(Pu[r].real ** 2 + Pu[r].imag ** 2) + grow * s2) ** 2
        A = math.sqrt(A2)
        py, pz, vy, vz = p0[2 * i], p0[2 * i + 1], v0[2 * i], v0[2 * i + 1]
        g = cp[i, FREE_RADIUS]  # < 0 (a row that always acts): never free, hand over
        d = math.sqrt(py * py + pz * pz)
        if not (d <= rmax):  # keeps a NaN
            rmax = d
        if not (g - d > tol_x):  # NaN too: hand over
            located = True
            best = 0.0
            continue
        if _bound(py, pz, vy, vz, A, best) < g:
            continue
        lo, hi = 0.0, best
        for _ in range(48):
            mid = 0.5 * (lo + hi)
            if _bound(py, pz, vy, vz, A, mid) < g:
                lo = mid
            else:
                hi = mid
        best = lo
    return best, located, rmax


@njit(cache=True)
def _advance_free(y, lam, s, EH, H):
    """``y <- e^{lam s} y`` (the precomputed ``EH`` when ``s == H``)."""
    if s == H:
        for j in range(y.shape[0]):
            y[j] = EH[j] * y[j]
    else:
        for j in range(y.shape[0]):
            y[j] = np.exp(lam[j] * s) * y[j]


@njit(cache=True)
def _dense(ysmp, y, bF, bN, lam, ilam, s, h):
    """State at ``t_n + s`` inside the step ``h`` from the step's interpolant (``ilam`` the
    reciprocals of ``lam``: multiplications instead of divisions away from ``lam s = 0``)."""
    r = s / h
    for j in range(y.shape[0]):
        z = lam[j] * s
        zr, zi = z.real, z.imag
        if zr * zr + zi * zi < 0.01:
            e, p1, p2 = phi012(z)
            a = s * p1
            b = s * r * p2
        else:
            ez = math.exp(zr)
            e = complex(ez * math.cos(zi), ez * math.sin(zi))
            a = (e - 1.0) * ilam[j]  # s phi1
            b = (a - s) * ilam[j] * (1.0 / h)  # s^2 phi2 / h
        ysmp[j] = e * y[j] + (a - b) * bF[j] + b * bN[j]


@njit(cache=True)
def _write_dense(sink, idx, ysmp, z, Fs, contacts, outputs, scratch):
    """Sample from an interpolated state: normal and friction force from the law there
    (``scratch = (fn, ft, pbuf, ubuf)``)."""
    fn, ft, pbuf, ubuf = scratch
    Cd, Cv, Pu, Pv, d0, cp = (contacts.Cd, contacts.Cv, contacts.Pu, contacts.Pv, contacts.d0,
                              contacts.cp)  # fmt: skip
    m = Fs.shape[0]
    for r in range(m):
        pbuf[r] = d0[r] + (Pu[r] * z).real + _rdot(Cd[r], ysmp)
        ubuf[r] = (Pv[r] * z).real + _rdot(Cv[r], ysmp)
        for c in range(m):
            pbuf[r] += contacts.Rd[r, c] * Fs[c]
            ubuf[r] += contacts.Rv[r, c] * Fs[c]
    for i in range(cp.shape[0]):
        law = term(pbuf[2 * i], pbuf[2 * i + 1], ubuf[2 * i], ubuf[2 * i + 1], cp[i])
        fn[i] = law[2]
        ft[i] = law[3]
    _write(sink, idx, ysmp, z, (Fs, fn, ft), contacts, outputs)


@njit(cache=True, inline="always")
def _solve_stages(stage, y, F, Fp, step, tab4, contacts):
    """The collocation step's implicit contact solve: stage rows ``pd2, pv2`` (m, m/s) without
    the unknown stage forces, then Newton (:func:`solve_contacts` on the two stages stacked as
    ``2 n_c`` contacts) for ``X = [F(h/2), F(h)]`` (N) from a start extrapolated along the last
    step. Returns the iteration count (``0``: no contact closes, ``< 0``: failed).

    ``stage = (pd2, pv2, X0, X, fn2, ft2, cp2, work2)`` the stacked stage arrays, ``step =
    (loaded, extrap, h, hp, t, omega, k)``: whether a force acts, whether to extrapolate, the
    step and the previous one (s), its start (s), the spin (rad/s) and its table row."""
    pd2, pv2, X0, X, fn2, ft2, cp2, work2 = stage
    loaded, extrap, h, hp, t, omega, k = step
    E4, Em4, W4, CdE4, CvE4, CdEm4, CvEm4, P0d, P0v, S2d, S2v = tab4
    Pu, Pv, d0 = contacts.Pu, contacts.Pv, contacts.d0
    m = F.shape[0]
    zm = complex(math.cos(omega * (t + 0.5 * h)), math.sin(omega * (t + 0.5 * h)))
    zn = complex(math.cos(omega * (t + h)), math.sin(omega * (t + h)))
    for r in range(m):
        pd2[r] = d0[r] + (Pu[r] * zm).real + _rdot(CdEm4[k, r], y)
        pv2[r] = (Pv[r] * zm).real + _rdot(CvEm4[k, r], y)
        pd2[m + r] = d0[r] + (Pu[r] * zn).real + _rdot(CdE4[k, r], y)
        pv2[m + r] = (Pv[r] * zn).real + _rdot(CvE4[k, r], y)
    if loaded:
        for R in range(2 * m):
            for c in range(m):
                pd2[R] += P0d[k, R, c] * F[c]
                pv2[R] += P0v[k, R, c] * F[c]
    for r in range(m):
        if extrap:
            X0[r] = F[r] + (F[r] - Fp[r]) * (0.5 * h / hp)
            X0[m + r] = F[r] + (F[r] - Fp[r]) * (h / hp)
        else:
            X0[r] = F[r]
            X0[m + r] = F[r]
    return solve_contacts((pd2, pv2, S2d[k], S2v[k]), X0, cp2, (X, fn2, ft2), work2)


@njit(cache=True, fastmath=SAFE_FASTMATH)
def expo_adaptive(state, span, sink, plan, contacts, outputs, control):
    """Advance ``span.n_samples`` output samples (spacing ``plan.H``) with exact free flight and
    error-controlled contact steps (module docstring); returns the number written.

    ``state`` (``State``, in/out) as in :func:`rubrotor.core.engine.expo_fixed` (``y``, ``F``,
    ``Fp``, ``dprev``, ``istate``) with ``clock`` the T_* slots (time (s), previous step (s),
    level, free advances); ``span`` gives ``n_samples``, ``offset`` and the spin ``omega``
    (rad/s). ``plan`` (:class:`rubrotor.engine.structs.Plan`) holds the modes, the lazily
    filled per-level tables and the look-ahead rows. Samples go to ``sink.out[:, offset + k]``,
    events to ``sink.events``.
    """
    y, F, Fp, dprev, tst, istate = (state.y, state.F, state.Fp, state.dprev, state.clock,
                                    state.istate)  # fmt: skip
    n_samples, offset, omega = span.n_samples, span.offset, span.omega
    events = sink.events
    lam, BT, Wd, Wv, Ca, EH = plan.lam, plan.BT, plan.Wd, plan.Wv, plan.Ca, plan.EH
    H, J, have, tab, tol_x = plan.H, plan.J, plan.have, plan.tab, plan.tol_x
    E, G0, G1, CdE, CvE, Q0d, Q0v, Sd, Sv = tab
    tab4 = plan.tab4
    E4, Em4, W4, CdE4, CvE4, CdEm4, CvEm4, P0d, P0v, S2d, S2v = tab4
    quad = plan.order == 4
    Cd, Cv, Pu, Pv, d0, cp = (contacts.Cd, contacts.Cv, contacts.Pu, contacts.Pv, contacts.d0,
                              contacts.cp)  # fmt: skip
    Rd, Rv, max_disp = contacts.Rd, contacts.Rv, contacts.max_disp
    ns = y.shape[0]
    m = F.shape[0]
    nc = cp.shape[0]
    pd = np.empty(m)
    pv = np.empty(m)
    pe = np.empty(m)  # relative contact displacement at a step's end (m)
    Fn = np.zeros(m)
    F0 = np.zeros(m)
    Fs = np.zeros(m)
    fn = np.zeros(nc)
    ft = np.zeros(nc)
    dnew = np.zeros(nc)
    entering = np.zeros(nc, np.bool_)
    pbuf = np.zeros(m)
    ubuf = np.zeros(m)
    work = workspace(m)
    # collocation (order 4): stacked stage unknowns [F(h/2), F(h)], the stage laws
    pd2 = np.empty(2 * m)
    pv2 = np.empty(2 * m)
    X0 = np.zeros(2 * m)
    X = np.zeros(2 * m)
    fn2 = np.zeros(2 * nc)
    ft2 = np.zeros(2 * nc)
    cp2 = np.empty((2 * nc, cp.shape[1]))
    for i in range(nc):
        for q in range(cp.shape[1]):
            cp2[i, q] = cp[i, q]
            cp2[nc + i, q] = cp[i, q]
    work2 = workspace(2 * m)
    Fmid = np.zeros(m)  # this step's midpoint force (N)
    Fpm = np.zeros(m)  # the previous step's midpoint force (N), 0: no history
    bF = np.zeros(ns, np.complex128)
    bM = np.zeros(ns, np.complex128)
    bN = np.zeros(ns, np.complex128)
    ysmp = np.zeros(ns, np.complex128)
    for c in range(m):
        for j in range(ns):
            bF[j] += BT[c, j] * F[c]
    t = tst[T_TIME]
    hp = tst[T_HPREV]
    lev = int(tst[T_LEVEL])
    kfree = LEVELS_UP + J + 1  # the table row for a non-dyadic step
    gmin = 1e300
    for i in range(nc):
        gmin = min(gmin, length_scale(cp[i]))
    k0 = istate[I_STEP]
    t_end = (k0 + n_samples) * H
    cap = events.shape[0]
    written = 0
    hloc = 0.0  # a shortened step locating a change of contact state (0: none)
    on_grid = t == k0 * H  # at a sample time: the free jump to the next is e^{lam H}
    z = complex(math.cos(omega * t), math.sin(omega * t))
    rotH = complex(math.cos(omega * H), math.sin(omega * H))
    grow = 1.0  # bound of |e^{lam s}|, s <= LOOK_AHEAD H
    for j in range(ns):
        grow = max(grow, math.exp(lam[j].real * LOOK_AHEAD * H))
    t_cert = -1.0  # free flight certified up to this time (s)
    ay = np.zeros(ns)
    ilam = np.zeros(ns, np.complex128)
    for j in range(ns):
        ilam[j] = 1.0 / lam[j] if lam[j] != 0.0 else 0.0
    PH = np.zeros((3, ns), np.complex128)  # H^k phi_k(lam H), k = 1..3 (dense output)
    for j in range(ns):
        _, p1, p2, p3 = phi0123(lam[j] * H)
        PH[0, j] = H * p1
        PH[1, j] = H * H * p2
        PH[2, j] = H * H * H * p3
    while written < n_samples:
        if istate[I_EVENTS] + EVENT_MARGIN * nc > cap:
            istate[I_STATUS] = EVENT_BUFFER_FULL
            break
        ts = (k0 + written + 1) * H
        loaded = False
        for r in range(m):
            if F[r] != 0.0:
                loaded = True
        if not loaded:
            if not on_grid:
                z = complex(math.cos(omega * t), math.sin(omega * t))
            if ts <= t_cert:  # certified free by an earlier look-ahead
                s, located = ts - t, False
            else:
                S = min(LOOK_AHEAD * H, t_end - t)
                s, located, rmax = _free_look(y, z, S, omega, contacts, (Ca, grow, tol_x),
                                              (ay, pd, pv))  # fmt: skip
                if not (rmax <= max_disp):
                    istate[I_STATUS] = DIVERGED
                    break
                t_cert = t + s
            if not located and s >= ts - t:
                _advance_free(y, lam, H if on_grid else ts - t, EH, H)
                t = ts
                # the phasor at sample k: rotated on the grid, recomputed every 64 samples
                kk = k0 + written + 1
                z = (
                    z * rotH
                    if on_grid and kk % 64 != 0
                    else complex(math.cos(omega * t), math.sin(omega * t))
                )
                on_grid = True
                tst[T_FREE] += 1.0
                for i in range(nc):
                    fn[i] = 0.0
                    ft[i] = 0.0
                _write(sink, offset + written, y, z, (F, fn, ft), contacts, outputs)
                written += 1
                istate[I_STEP] += 1
                continue
            if not located and s > plan.hmin:
                _advance_free(y, lam, s, EH, H)
                t += s
                on_grid = False
                tst[T_FREE] += 1.0
                continue
            # an onset is located here (or cannot be certified away): contact steps from t
            for i in range(nc):
                dprev[i] = math.sqrt(pd[2 * i] ** 2 + pd[2 * i + 1] ** 2)
                inward = pd[2 * i] * pv[2 * i] + pd[2 * i + 1] * pv[2 * i + 1] > 0.0
                entering[i] = inward and can_be_free(cp[i]) and not (
                    cp[i, FREE_RADIUS] - dprev[i] > tol_x)
            for r in range(m):
                Fp[r] = 0.0
                Fpm[r] = 0.0
        # one contact step attempt of h = H 2^-lev (or the locating step hloc)
        if hloc > 0.0:
            h = hloc
            k = kfree
        else:
            h = H * 2.0 ** (-lev)
            k = lev + LEVELS_UP
        if t + h > t_end:
            h = max(t_end - t, plan.hmin)
            k = kfree
        if k == kfree or have[k] == 0:
            if quad:
                _fill4(tab4, k, h, lam, (Cd, Cv, BT, Rd, Rv))
            else:
                _fill(tab, k, h, lam, (Cd, Cv, Wd, Wv, Rd, Rv))
            tst[T_FILLS] += 1.0
            if k != kfree:
                have[k] = 1
        zn = complex(math.cos(omega * (t + h)), math.sin(omega * (t + h)))
        extrap = False
        for r in range(m):
            if F[r] != 0.0 and Fp[r] != 0.0:
                extrap = True
        finest = h <= plan.hmin * 1.0000001
        if quad:
            it = _solve_stages((pd2, pv2, X0, X, fn2, ft2, cp2, work2), y, F, Fp,
                               (loaded, extrap, h, hp, t, omega, k), tab4, contacts)  # fmt: skip
            if it < 0 and finest:
                it = graze_contacts((pd2, pv2, S2d[k], S2v[k]), cp2, (X, fn2, ft2), work2)
                if it > 0:
                    istate[I_GRAZE] += 1
            for r in range(m):
                Fmid[r] = X[r]
                Fn[r] = X[m + r]
                a = pd2[m + r]
                for c in range(2 * m):
                    a += S2d[k, m + r, c] * X[c]
                pe[r] = a
            for i in range(nc):
                fn[i] = fn2[nc + i]
                ft[i] = ft2[nc + i]
        else:
            for r in range(m):
                pd[r] = d0[r] + (Pu[r] * zn).real + _rdot(CdE[k, r], y)
                pv[r] = (Pv[r] * zn).real + _rdot(CvE[k, r], y)
                if loaded:
                    for c in range(m):
                        pd[r] += Q0d[k, r, c] * F[c]
                        pv[r] += Q0v[k, r, c] * F[c]
            for r in range(m):
                F0[r] = F[r] + (F[r] - Fp[r]) * (h / hp) if extrap else F[r]
            if nc == 1:
                it = solve_one((pd, pv, Sd[k], Sv[k]), F0, cp, (Fn, fn, ft))
            else:
                it = solve_contacts((pd, pv, Sd[k], Sv[k]), F0, cp, (Fn, fn, ft), work)
            if it < 0 and finest:
                it = graze_contacts((pd, pv, Sd[k], Sv[k]), cp, (Fn, fn, ft), work)
                if it > 0:
                    istate[I_GRAZE] += 1
            for r in range(m):
                a = pd[r]
                for c in range(m):
                    a += Sd[k, r, c] * Fn[c]
                pe[r] = a
        if it < 0:
            if finest:
                istate[I_STATUS] = NEWTON_FAILED
                break
            istate[I_SUBSTEPS] += 1
            hloc = 0.0
            lev = min(lev + 1, J)
            continue
        istate[I_NEWTON] += it
        # a located onset moving inward must see contact at the step's end: a longer step
        # could pass over a graze shorter than itself
        retry = False
        for i in range(nc):
            if entering[i] and Fn[2 * i] == 0.0 and Fn[2 * i + 1] == 0.0 and not finest:
                retry = True
        if retry:
            istate[I_REJECTED] += 1
            hloc = 0.0
            lev = min(lev + 1, J)
            continue
        new = False
        for r in range(m):
            if Fn[r] != 0.0 or (quad and Fmid[r] != 0.0):  # any stage in contact
                new = True
        # radial displacements at the step's end and changes of contact state
        pmax = 0.0
        changed = False
        at_start = True
        frac = 1.0
        for i in range(nc):
            a = pe[2 * i]
            b = pe[2 * i + 1]
            dnew[i] = math.sqrt(a * a + b * b)
            pmax = max(pmax, dnew[i])
            was = F[2 * i] != 0.0 or F[2 * i + 1] != 0.0
            now = Fn[2 * i] != 0.0 or Fn[2 * i + 1] != 0.0
            if was != now and can_be_free(cp[i]):
                changed = True
                g = cp[i, FREE_RADIUS]
                # a force released inside the clearance (a dashpot's pull clipped to zero)
                # passes through zero continuously: no crossing to locate, the error control
                # refines the kink
                released = was and dnew[i] > g
                if abs(dprev[i] - g) > tol_x and not released:
                    at_start = False
                    den = dnew[i] - dprev[i]
                    f = (g - dprev[i]) / den if den != 0.0 else 0.5
                    frac = min(frac, min(max(f, 0.0), 1.0))
            elif quad and (Fmid[2 * i] != 0.0 or Fmid[2 * i + 1] != 0.0) != now:
                # the midpoint stage alone differs: a contact (or a separation) that begins
                # and ends inside the step; halve it until a step's end sees it
                changed = True
                at_start = False
                frac = min(frac, 0.5)
        if changed and not at_start and not finest:
            istate[I_REJECTED] += 1
            hloc = max(plan.hmin, h * min(0.9, max(0.98 * frac, 1e-3)))
            continue
        err = 0.0
        if new or loaded:
            tolp = control.atol + control.rtol * max(pmax, gmin)
            if quad:
                if has_history(Fp, m) and has_history(Fpm, m) and new and loaded:
                    err = quad_error((Fp, Fpm, F, Fmid, Fn), m, hp, h, control.a_f, omega) / tolp
                else:
                    # quadratic against linear force (the midpoint bubble): end displacement,
                    # and velocity over Omega
                    ed = 0.0
                    ev = 0.0
                    for r in range(m):
                        a = 0.0
                        b = 0.0
                        for c in range(m):
                            dc = Fmid[c] - 0.5 * (F[c] + Fn[c])
                            a += S2d[k, m + r, c] * dc
                            b += S2v[k, m + r, c] * dc
                        ed += a * a
                        ev += b * b
                    err = max(math.sqrt(ed), math.sqrt(ev) / omega) / tolp
            elif has_history(Fp, m) and new and loaded:
                err = hold_error(Fn, F, Fp, m, h, hp, control.a_f, omega) / tolp
            else:
                # zero- against first-order hold: displacement, and velocity over Omega
                errc = 0.0
                for r in range(m):
                    row = 0.0
                    rowv = 0.0
                    for c in range(m):
                        row += abs(Sd[k, r, c] - Rd[r, c])
                        rowv += abs(Sv[k, r, c] - Rv[r, c])
                    errc = max(errc, row, rowv / omega)
                dfn = 0.0
                for r in range(m):
                    dfn += (Fn[r] - F[r]) ** 2
                err = errc * math.sqrt(dfn) / tolp
            if err > 1.0 and not finest:
                istate[I_REJECTED] += 1
                hloc = 0.0
                up = max(1, int(math.ceil(math.log2(err) / (5.0 if quad else 3.0))))
                lev = min(lev + up, J)
                continue
        istate[I_ACCEPTED] += 1
        # the step is accepted: samples inside it from its interpolant
        for j in range(ns):
            b = 0j
            for c in range(m):
                b += BT[c, j] * Fn[c]
            bN[j] = b
            if quad:
                b = 0j
                for c in range(m):
                    b += BT[c, j] * Fmid[c]
                bM[j] = b
        s_prev = -1.0
        while written < n_samples and (k0 + written + 1) * H <= t + h * (1.0 + 1e-14):
            ts = (k0 + written + 1) * H
            s = min(ts - t, h)
            if quad:
                if s_prev < 0.0:
                    _dense4(ysmp, y, bF, bM, bN, lam, s, h)
                else:
                    _dense4_next(ysmp, bF, bM, bN, EH, PH, s_prev, h)
                s_prev = s
                th = s / h
                l0 = 2.0 * (th - 0.5) * (th - 1.0)
                lm = -4.0 * th * (th - 1.0)
                l1 = 2.0 * th * (th - 0.5)
                for r in range(m):
                    Fs[r] = l0 * F[r] + lm * Fmid[r] + l1 * Fn[r]
            else:
                _dense(ysmp, y, bF, bN, lam, ilam, s, h)
                for r in range(m):
                    Fs[r] = F[r] + (Fn[r] - F[r]) * (s / h)
            zs = complex(math.cos(omega * ts), math.sin(omega * ts))
            _write_dense(sink, offset + written, ysmp, zs, Fs, contacts, outputs,
                         (fn, ft, pbuf, ubuf))  # fmt: skip
            written += 1
            istate[I_STEP] += 1
        if quad:
            for j in range(ns):
                y[j] = (E4[k, j] * y[j] + W4[k, 3, j] * bF[j] + W4[k, 4, j] * bM[j]
                        + W4[k, 5, j] * bN[j])  # fmt: skip
                bF[j] = bN[j]
        else:
            for j in range(ns):
                y[j] = E[k, j] * y[j] + G0[k, j] * bF[j] + G1[k, j] * bN[j]
                bF[j] = bN[j]
        bad = False
        for i in range(nc):
            if not (dnew[i] <= max_disp):
                bad = True
            was = F[2 * i] != 0.0 or F[2 * i + 1] != 0.0
            now = Fn[2 * i] != 0.0 or Fn[2 * i + 1] != 0.0
            if was != now and cp[i, 0] != 0.0 and can_be_free(cp[i]):
                g = cp[i, FREE_RADIUS]
                if abs(dprev[i] - g) <= tol_x:
                    te = t
                else:
                    den = dnew[i] - dprev[i]
                    f = (g - dprev[i]) / den if den != 0.0 else 1.0
                    te = t + min(max(f, 0.0), 1.0) * h
                ne = istate[I_EVENTS]
                if ne < cap:
                    events[ne, 0] = te
                    events[ne, 1] = (i + 1) if now else -(i + 1)
                istate[I_EVENTS] = ne + 1
            dprev[i] = dnew[i]
        for r in range(m):
            Fp[r] = F[r]
            Fpm[r] = Fmid[r]
            F[r] = Fn[r]
        t += h
        t_cert = -1.0
        on_grid = False
        for i in range(nc):
            entering[i] = False
        hp = h
        hloc = 0.0
        if bad:
            istate[I_STATUS] = DIVERGED
            break
        if err < (0.025 if quad else 0.05) and lev > -LEVELS_UP:
            lev -= 1
        if istate[I_EVENTS] > cap:
            istate[I_STATUS] = EVENT_BUFFER_FULL
            break
    tst[T_TIME] = t
    tst[T_HPREV] = hp
    tst[T_LEVEL] = lev
    return written
