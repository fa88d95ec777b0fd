"""Compiled time loops for the modal rotor with contact (plain arrays, SI units).

The rotor is diagonalised once (:mod:`rubrotor.engine.shaft_modal`): with ``y`` the complex eigen-
coordinates of the first-order modal system, ``y' = lam * y + beta_c F_c + beta_u F_u + beta_l F_l``.

``expo_fixed`` and ``expo_adaptive`` integrate the shifted coordinates ``y~ = y - y_p(t)``, where
``y_p`` is the exact steady response to unbalance and constant load, with the exact propagator::

    y~_{k+1} = e^{lam h} y~_k + (h phi1 - h phi2) beta_c F_k + h phi2 beta_c F_{k+1}

(the contact force held linear over the step, solved implicitly for ``F_{k+1}``): exact for the
linear rotor, second order in the contact force, and unconditionally stable for the stiff linear
part. ``abm_fixed`` is the seed's 4th-order Adams-Bashforth-Moulton PECE on the unshifted ``y``.

Saved channels per sample (``out[channel, sample]``), per output station ``s`` (station 0 is the
contact station): ``6s + 0..5`` = v, w (m), v', w' (m/s), v'', w'' (m/s^2); then after ``6 S``:
normal force (N) and friction force along the tangent ``i n`` (N). The force components on the
rotor follow as ``F = -(F_n + i F_t) n`` with ``n = P / |P|``.
"""

import math

import numpy as np
from numba import njit

from rubrotor.core.contact import solve_contact
from rubrotor.core.flags import SAFE_FASTMATH
from rubrotor.core.status import (
    CONTACT_FAILED,
    DIVERGED,
    EVENT_BUFFER_FULL,
    I_EVENTS,
    I_STATUS,
    I_STEP,
    MESSAGES,
    OK,
)
from rubrotor.core.terms import term_force

__all__ = [
    "expo_fixed",
    "expo_adaptive",
    "abm_fixed",
    "STATUS",
    "OK",
    "DIVERGED",
    "CONTACT_FAILED",
    "EVENT_BUFFER_FULL",
    "I_STEP",
    "I_EVENTS",
    "I_STATUS",
    "I_LEVEL",
    "I_PREV_LEVEL",
    "N_ISTATE",
    "C_ACCEPTED",
    "C_REJECTED",
    "C_NEWTON",
    "n_channels",
]

STATUS = dict(enumerate(MESSAGES))
"""Messages of the status codes (:mod:`rubrotor.core.status`) a kernel leaves in
``istate[I_STATUS]``. ``EVENT_BUFFER_FULL``: before a saved sample the event buffer has less
room than ``event_reserve`` (no event lost: the driver grows the buffer and goes on), or events
of the last sample were counted but not stored."""

I_LEVEL, I_PREV_LEVEL = 3, 4
"""Slots of ``istate`` after the shared ``I_STEP, I_EVENTS, I_STATUS`` (steps taken, saved
samples for the adaptive kernel; contact events counted; status): the adaptive kernel's current
and previous step levels."""
N_ISTATE = 5
C_ACCEPTED, C_REJECTED, C_NEWTON = 0, 1, 2
"""Slots of ``counts`` (adaptive kernel): accepted and rejected steps, Newton iterations."""


def n_channels(n_stations: int) -> int:
    """Number of saved channels for ``n_stations`` output stations."""
    return 6 * n_stations + 2


@njit(cache=True, inline="always")
def _station(y, z, F, s, rows):
    """Complex displacement (m), velocity (m/s) and acceleration (m/s^2) at output station ``s``.

    ``rows`` (:class:`rubrotor.engine.shaft_steppers.Rows`): rows mapping the eigen-coordinates to each
    quantity, the direct acceleration per N of contact force, and the contributions of the
    particular (steady) solution as multiples of the unbalance phasor ``z`` and constants.
    """
    P = rows.part_u[s] * z + rows.part_l[s]
    V = rows.vel_z[s] * z
    A = rows.acc_z[s] * z + rows.acc_c[s] + rows.acc_fc[s] * F
    for j in range(y.shape[0]):
        yj = y[j]
        P += rows.d[s, j] * yj
        V += rows.v[s, j] * yj
        A += rows.a[s, j] * yj
    return P, V, A


@njit(cache=True, inline="always")
def _put(out, idx, s, P, V, A):
    b = 6 * s
    out[b, idx] = P.real
    out[b + 1, idx] = P.imag
    out[b + 2, idx] = V.real
    out[b + 3, idx] = V.imag
    out[b + 4, idx] = A.real
    out[b + 5, idx] = A.imag


@njit(cache=True)
def _write_probes(out, idx, y, z, F, rows, fn, ft):
    """Write stations 1.. (probes) from ``y`` and the given normal and friction forces (N)."""
    nst = rows.d.shape[0]
    for s in range(1, nst):
        P, V, A = _station(y, z, F, s, rows)
        _put(out, idx, s, P, V, A)
    b = 6 * nst
    out[b, idx] = fn
    out[b + 1, idx] = ft


@njit(cache=True)
def _write_sample(out, idx, y, z, F, cp, rows):
    """Write one sample computed from ``y``; the contact forces from station 0's state."""
    P, V, A = _station(y, z, F, 0, rows)
    _put(out, idx, 0, P, V, A)
    fy, fz, fn, ft = term_force(P.real, P.imag, V.real, V.imag, cp)
    _write_probes(out, idx, y, z, F, rows, fn, ft)


@njit(cache=True, inline="always")
def _write_contact_sample(out, idx, y, zF, rows, contact):
    """Write one sample of ``y`` (phasor and force ``zF = (z, F)``) whose station 0 reuses
    ``contact = (P, V, fn, ft)``: the contact-station displacement (m), velocity (m/s) and the
    normal and friction forces (N) of the last step."""
    z, F = zF
    P, V, fn_c, ft_c = contact
    A0 = rows.acc_z[0] * z + rows.acc_c[0] + rows.acc_fc[0] * F
    for j in range(y.shape[0]):
        A0 += rows.a[0, j] * y[j]
    _put(out, idx, 0, P, V, A0)
    nst = rows.d.shape[0]
    if nst > 1:
        _write_probes(out, idx, y, z, F, rows, fn_c, ft_c)
    else:  # no probes: only the contact forces
        out[6, idx] = fn_c
        out[7, idx] = ft_c


@njit(cache=True, inline="always")
def _record_event(events, istate, t):
    """Store an onset (``t > 0``) or separation (``-t``) time (s); count it even when full."""
    ne = istate[I_EVENTS]
    if ne < events.shape[0]:
        events[ne] = t
    istate[I_EVENTS] = ne + 1


@njit(cache=True, inline="always")
def _buffer_short(events, istate, reserve):
    """Flag ``EVENT_BUFFER_FULL`` when events were lost or fewer than ``reserve`` slots remain."""
    if events.shape[0] - istate[I_EVENTS] < reserve:
        istate[I_STATUS] = EVENT_BUFFER_FULL
        return True
    return False


@njit(cache=True)
def _friction_power(y, z, cp, cdc, cvc, part_c, vel_c_z, part_lc):
    """Power (W) of the friction force on the lateral motion of the shaft centre."""
    P = part_c * z + part_lc
    V = vel_c_z * z
    for j in range(y.shape[0]):
        P += cdc[j] * y[j]
        V += cvc[j] * y[j]
    fy, fz, fn, ft = term_force(P.real, P.imag, V.real, V.imag, cp)
    if fn == 0.0:
        return 0.0
    d = abs(P)
    return ft * ((-P.imag / d) * V.real + (P.real / d) * V.imag)


@njit(cache=True)
def _powers(y, zF, en, cp, cdc, cvc, part, qv):
    """Instantaneous powers (W): unbalance, constant load, contact force, modal damping, friction.

    ``en`` (:class:`rubrotor.engine.shaft_steppers.Energy`): rows giving the modal velocities, the damping
    matrix, the velocity rows of the unbalance and load stations (with their particular-solution
    parts) and the force amplitudes; ``zF = (z, F)`` the unbalance phasor and contact force (N);
    ``cdc, cvc`` the contact rows and ``part = (part_c, vel_c_z, part_lc)`` the contact
    station's particular parts (m and m/s per unit phasor, m).
    """
    z, F = zF
    part_c, vel_c_z, part_lc = part
    ns = y.shape[0]
    vu = en.vel_u_z * z
    vl = en.vel_l_z * z
    vc = vel_c_z * z
    for j in range(ns):
        vu += en.vel_u_row[j] * y[j]
        vl += en.vel_l_row[j] * y[j]
        vc += cvc[j] * y[j]
    fu = en.fu0 * z
    fl = en.fl
    p_u = fu.real * vu.real + fu.imag * vu.imag
    p_l = fl.real * vl.real + fl.imag * vl.imag
    p_c = F.real * vc.real + F.imag * vc.imag
    wv, wz, cmat = en.wv, en.wz, en.cmat
    nq = wv.shape[0]
    for i in range(nq):
        acc = wz[i] * z
        for j in range(ns):
            acc += wv[i, j] * y[j]
        qv[i] = acc
    p_d = 0.0
    for i in range(nq):
        for k2 in range(nq):
            c = cmat[i, k2]
            if c != 0.0:
                p_d += c * (qv[i].real * qv[k2].real + qv[i].imag * qv[k2].imag)
    p_f = _friction_power(y, z, cp, cdc, cvc, part_c, vel_c_z, part_lc)
    return p_u, p_l, p_c, p_d, p_f


@njit(cache=True, inline="always")
def phasor(z, rot, step, wh):
    """Unbalance phasor ``exp(i omega h step)`` after ``step`` fixed steps: ``z rot`` from the
    previous one (``rot = exp(i omega h)``), re-seeded exactly every 1024 steps (``wh = omega h``,
    rad)."""
    if step % 1024 == 0:
        return complex(math.cos(wh * step), math.sin(wh * step))
    return z * rot


@njit(cache=True, fastmath=SAFE_FASTMATH)
def fixed_coefficients(E, G0, G1, sd, sv, cdc, cvc, part):
    """What :func:`fixed_step` reads, ``(prop, scal)``.

    ``prop`` (5, ns) complex: rows ``E, G0, G1`` the step coefficients and ``cdE = cdc E``,
    ``cvE = cvc E`` the propagate-and-project rows of the contact station; ``scal = (sd, sv,
    cdG0, cvG0, part_c, part_lc, vel_cz)``: the contact-station displacement (m/N) and velocity
    (m/(s N)) per N of the new force and of the old one (``cdG0 = cdc . G0``, ...), and
    ``part = (part_c, part_lc, vel_cz)`` the station's particular solution (m per unit phasor,
    m, m/s per unit phasor). One array and a tuple of numbers: a compiled step reads them
    without reference counting.
    """
    ns = E.shape[0]
    prop = np.empty((5, ns), np.complex128)
    for j in range(ns):  # loops: slice assignments and array expressions cost first compile time
        prop[0, j] = E[j]
        prop[1, j] = G0[j]
        prop[2, j] = G1[j]
        prop[3, j] = cdc[j] * E[j]
        prop[4, j] = cvc[j] * E[j]
    cdG0 = 0j
    cvG0 = 0j
    for j in range(ns):
        cdG0 += cdc[j] * G0[j]
        cvG0 += cvc[j] * G0[j]
    part_c, part_lc, vel_cz = part
    return prop, (sd, sv, cdG0, cvG0, part_c, part_lc, vel_cz)


@njit(cache=True, inline="always")
def fixed_step(y, F, Fp, zn, prop, scal, cp, jac):
    """One fixed exponential step of the shifted eigen-coordinates ``y`` (in place).

    ``F, Fp`` the contact forces (N, complex) of the current and previous step, ``zn`` the
    unbalance phasor at the step's end, ``prop, scal`` from :func:`fixed_coefficients`, ``cp``
    the packed contact law, ``jac`` (2, 4) work. The new force is solved implicitly from the
    predicted contact-station displacement and velocity (Newton from the linear extrapolation
    of the force history); ``y <- E y + G0 F + G1 F_new``. Returns ``(F_new, iterations, fn,
    ft, P, V)``: iterations negative when the contact solve failed (``y`` then unchanged), the
    normal and friction forces (N), the contact-station displacement (m) and velocity (m/s) at
    the end.
    """
    sd, sv, cdG0, cvG0, part_c, part_lc, vel_cz = scal
    ns = y.shape[0]
    pd = part_c * zn + part_lc
    ud = vel_cz * zn
    for j in range(ns):
        yj = y[j]
        pd += prop[3, j] * yj
        ud += prop[4, j] * yj
    if F != 0j:
        pd += cdG0 * F
        ud += cvG0 * F
    # Newton start: linear extrapolation of the force history
    F0 = F
    if F != 0j and Fp != 0j:
        F0 = 2.0 * F - Fp
    Fn, it, fn_c, ft_c = solve_contact(pd, ud, sd, sv, F0, cp, jac)
    if it >= 0:
        if F != 0j or Fn != 0j:
            for j in range(ns):
                y[j] = prop[0, j] * y[j] + prop[1, j] * F + prop[2, j] * Fn
        else:
            for j in range(ns):
                y[j] = prop[0, j] * y[j]
    return Fn, it, fn_c, ft_c, pd + sd * Fn, ud + sv * Fn


@njit(cache=True, fastmath=SAFE_FASTMATH)
def expo_fixed(st, n_samples, out_offset, k, cp, rows, en):
    """Fixed-step exponential integrator over ``n_samples`` saved samples.

    Parameters (named tuples of :mod:`rubrotor.engine.shaft_steppers`): ``st`` (:class:`RunState`) the run
    state, in/out: ``y`` (complex eigen-coordinates, shifted), ``cstate = [F, z, F_prev,
    d_prev]`` (contact force N, unbalance phasor ``exp(i Omega t)``, previous force N, previous
    contact-point displacement m, carried so that chunking changes nothing), ``istate`` (slots
    ``I_*``), ``work`` (J), ``out`` and ``events``; ``k`` (:class:`FixedStep`) the step
    coefficients, ``h`` (s), ``omega`` (rad/s), ``save_every``, ``max_disp`` (m),
    ``event_reserve`` (free event slots required before a sample); ``cp`` the
    packed contact law; ``rows`` (:class:`Rows`) the output rows; ``en`` (:class:`Energy`)
    energy tracking (``en.on``). Writes samples ``out[:, out_offset : out_offset + n]`` and
    returns the number written. ``work`` accumulates the work of unbalance, load, contact
    force, modal damping (dissipated) and friction. Contact onset (+t) and separation (-t) times
    (s) are located by linear interpolation of ``|P| - g`` within the step.

    The step is :func:`fixed_step`'s (the maps' kernel, :func:`rubrotor.core.tangent.expo_tangent`)
    written out: through the shared inline step the simulation measured about 10 % slower.
    """
    y, istate, out, events = st.y, st.istate, st.out, st.events
    E, G0, G1, sd, sv, cdc, cvc = k.E, k.G0, k.G1, k.sd, k.sv, k.cdc, k.cvc
    omega, h, save_every = k.omega, k.h, k.save_every
    ns = y.shape[0]
    jac = np.zeros((2, 4))
    qv = np.zeros(en.wv.shape[0], np.complex128)
    # propagate-and-project vectors: pd = sum(cdE * y) + cdG0 * F, same for the velocity
    cdE = cdc * E
    cvE = cvc * E
    cdG0 = 0j
    cvG0 = 0j
    for j in range(ns):
        cdG0 += cdc[j] * G0[j]
        cvG0 += cvc[j] * G0[j]
    F = st.cstate[0]
    z = st.cstate[1]
    Fp = st.cstate[2]
    step = istate[I_STEP]
    part_c = rows.part_u[0]
    part_lc = rows.part_l[0]
    vel_cz = rows.vel_z[0]
    g = cp[4]
    maxd2 = k.max_disp * k.max_disp
    rot = complex(math.cos(omega * h), math.sin(omega * h))
    written = 0
    P = 0j
    V = 0j
    fn_c = 0.0
    ft_c = 0.0
    d_prev = st.cstate[3].real
    pw0 = (0.0, 0.0, 0.0, 0.0, 0.0)
    if en.on:
        pw0 = _powers(y, (z, F), en, cp, cdc, cvc, (part_c, vel_cz, part_lc), qv)
    for s_i in range(n_samples):
        if _buffer_short(events, istate, k.event_reserve):
            break
        for _ in range(save_every):
            step += 1
            if step % 1024 == 0:
                zn = complex(math.cos(omega * h * step), math.sin(omega * h * step))
            else:
                zn = z * rot
            pd = part_c * zn + part_lc
            ud = vel_cz * zn
            for j in range(ns):
                yj = y[j]
                pd += cdE[j] * yj
                ud += cvE[j] * yj
            if F != 0j:
                pd += cdG0 * F
                ud += cvG0 * F
            # Newton start: linear extrapolation of the force history
            F0 = F
            if F != 0j and Fp != 0j:
                F0 = 2.0 * F - Fp
            Fn, it, fn_c, ft_c = solve_contact(pd, ud, sd, sv, F0, cp, jac)
            if it < 0:
                istate[I_STATUS] = CONTACT_FAILED
                break
            if F != 0j or Fn != 0j:
                for j in range(ns):
                    y[j] = E[j] * y[j] + G0[j] * F + G1[j] * Fn
            else:
                for j in range(ns):
                    y[j] = E[j] * y[j]
            P = pd + sd * Fn
            V = ud + sv * Fn
            d2 = P.real * P.real + P.imag * P.imag
            d = math.sqrt(d2)
            if (Fn != 0j) != (F != 0j) and cp[0] != 0.0:
                den = d - d_prev
                frac = (g - d_prev) / den if den != 0.0 else 1.0
                frac = min(max(frac, 0.0), 1.0)
                te = (step - 1 + frac) * h
                _record_event(events, istate, te if Fn != 0j else -te)
            d_prev = d
            Fp = F
            F = Fn
            z = zn
            if en.on:
                pw1 = _powers(y, (z, F), en, cp, cdc, cvc, (part_c, vel_cz, part_lc), qv)
                for c in range(5):
                    st.work[c] += 0.5 * h * (pw0[c] + pw1[c])
                pw0 = pw1
            if not (d2 <= maxd2):
                istate[I_STATUS] = DIVERGED
                break
        if istate[I_STATUS] != OK:
            break
        # station 0 reuses P, V of the step; the contact forces come from the Newton solve
        _write_contact_sample(out, out_offset + s_i, y, (z, F), rows, (P, V, fn_c, ft_c))
        written += 1
    st.cstate[0] = F
    st.cstate[1] = z
    st.cstate[2] = Fp
    st.cstate[3] = d_prev
    istate[I_STEP] = step
    return written


@njit(cache=True, fastmath=SAFE_FASTMATH)
def expo_adaptive(st, n_samples, out_offset, k, cp, rows):
    """Error-controlled exponential integrator with dyadic steps ``H / 2^level``.

    Saves one sample every ``k.H`` (s). ``k`` (:class:`rubrotor.engine.shaft_steppers.AdaptiveStep`): level
    arrays ``E, G0, G1, cdE, cvE, Q0, Qm, Q1`` have shape (levels, ns) and ``cdG0, cvG0, sd, sv,
    errc, rot, cdQ0, cvQ0, cdQm, cvQm, sdq, svq`` shape (levels,); ``cdE = cd * E`` etc. are the
    propagate-and-project vectors of the contact station.

    Local error control. While the rotor stays in contact over consecutive steps, the error of
    holding the force linear over a step is estimated from the second difference of the force,
    ``F'' ~ 2 (s_k - s_{k-1}) / (h_k + h_{k-1})`` with ``s`` the force slopes: the velocity error is
    ``|a_F| h^3 |F''| / 12`` and the displacement error ``|a_F| h^4 |F''| / 24`` (``a_F`` the
    contact-station acceleration per N). At contact onsets and separations, where the force has
    a kink and no history, the (larger) difference between first- and zero-order holds,
    ``errc |F_{k+1} - F_k|``, is used instead, and every change of contact state is refined to
    the finest level. A step is rejected and halved when
    ``max(e_d, e_v / Omega) > atol + rtol max(|P|, g)``; it grows again (doubles) after steps
    with an error below 1/20 of that.

    Third order in contact phases: after two accepted steps in contact at the same level, the
    force is held quadratic through ``F_{k-1}, F_k, F_{k+1}`` (coefficients ``Q0, Qm, Q1`` from
    ``phi1..phi3``), while the step is still controlled by the second-order estimate above (local
    extrapolation); a step that leaves contact falls back to the linear hold.

    ``st`` (:class:`rubrotor.engine.shaft_steppers.RunState`): ``cstate = [F, z, F_prev, -]``, ``istate`` (slots
    ``I_*``, ``I_STEP`` counts saved samples), ``counts`` (slots ``C_*``).
    """
    y, istate, out, stats, events = st.y, st.istate, st.out, st.counts, st.events
    E, G0, G1, cdE, cvE, cdG0, cvG0 = k.E, k.G0, k.G1, k.cdE, k.cvE, k.cdG0, k.cvG0
    sd, sv, errc, rot = k.sd, k.sv, k.errc, k.rot
    Q0, Qm, Q1, cdQ0, cvQ0, cdQm, cvQm = k.Q0, k.Qm, k.Q1, k.cdQ0, k.cvQ0, k.cdQm, k.cvQm
    sdq, svq = k.sdq, k.svq
    omega, H, rtol, atol = k.omega, k.H, k.rtol, k.atol
    # station 0's output rows, read once: the same reads per sample through the inlined
    # _write_contact_sample took 22 % of this kernel's time on seed case 1
    rows_a, nst = rows.a, rows.d.shape[0]
    acc_z0, acc_c0, acc_fc0 = rows.acc_z[0], rows.acc_c[0], rows.acc_fc[0]
    ns = y.shape[0]
    nlev = E.shape[0]
    J = nlev - 1
    full = 1 << J
    jac = np.zeros((2, 4))
    F = st.cstate[0]
    z = st.cstate[1]
    Fp = st.cstate[2]
    part_c = rows.part_u[0]
    part_lc = rows.part_l[0]
    vel_cz = rows.vel_z[0]
    g = cp[4]
    a_f = abs(rows.acc_fc[0])
    maxd2 = k.max_disp * k.max_disp
    lev = istate[I_LEVEL]
    lev_prev = istate[I_PREV_LEVEL]
    written = 0
    P = 0j
    V = 0j
    fn_c = 0.0
    ft_c = 0.0
    for s_i in range(n_samples):
        if _buffer_short(events, istate, k.event_reserve):
            break
        sample = istate[I_STEP]
        t_start = sample * H
        pos = 0
        while pos < full:
            units = 1 << (J - lev)
            while pos % units != 0 or pos + units > full:
                lev += 1
                units = 1 << (J - lev)
            h = H / (1 << lev)
            zn = z * rot[lev]
            pd = part_c * zn + part_lc + cdG0[lev] * F
            ud = vel_cz * zn + cvG0[lev] * F
            for j in range(ns):
                yj = y[j]
                pd += cdE[lev, j] * yj
                ud += cvE[lev, j] * yj
            F0 = F
            am3 = F != 0j and Fp != 0j and lev == lev_prev
            if F != 0j and Fp != 0j:
                hp = H / (1 << lev_prev)
                F0 = F + (F - Fp) * (h / hp)
            if am3:
                # quadratic hold through F_{k-1}, F_k, F_{k+1} (equal steps): third order
                pd = pd - cdG0[lev] * F + cdQ0[lev] * F + cdQm[lev] * Fp
                ud = ud - cvG0[lev] * F + cvQ0[lev] * F + cvQm[lev] * Fp
                Fn, it, fnn, ftn = solve_contact(pd, ud, sdq[lev], svq[lev], F0, cp, jac)
                if it >= 0 and Fn == 0j:
                    # left contact within the step: redo it with the linear hold
                    pd = pd + cdG0[lev] * F - cdQ0[lev] * F - cdQm[lev] * Fp
                    ud = ud + cvG0[lev] * F - cvQ0[lev] * F - cvQm[lev] * Fp
                    am3 = False
            if not am3:
                Fn, it, fnn, ftn = solve_contact(pd, ud, sd[lev], sv[lev], F0, cp, jac)
            stats[C_NEWTON] += max(it, 0)
            changed = (Fn != 0j) != (F != 0j)
            Pn = pd + (sdq[lev] if am3 else sd[lev]) * Fn
            tol = atol + rtol * max(abs(Pn), g)
            if Fn != 0j and F != 0j and Fp != 0j:
                hp = H / (1 << lev_prev)
                f2 = 2.0 * abs((Fn - F) / h - (F - Fp) / hp) / (h + hp)
                e_v = a_f * h * h * h * f2 / 12.0
                e_d = 0.5 * e_v * h
                err = max(e_d, e_v / omega) / tol
            else:
                err = errc[lev] * abs(Fn - F) / tol
            if lev < J and (it < 0 or err > 1.0 or changed):
                lev += 1
                stats[C_REJECTED] += 1
                continue
            if it < 0:
                istate[I_STATUS] = CONTACT_FAILED
                break
            if am3:
                for j in range(ns):
                    y[j] = E[lev, j] * y[j] + Q0[lev, j] * F + Qm[lev, j] * Fp + Q1[lev, j] * Fn
            elif F != 0j or Fn != 0j:
                for j in range(ns):
                    y[j] = E[lev, j] * y[j] + G0[lev, j] * F + G1[lev, j] * Fn
            else:
                for j in range(ns):
                    y[j] = E[lev, j] * y[j]
            stats[C_ACCEPTED] += 1
            pos += units
            if changed:
                tt = t_start + pos * (H / full)
                _record_event(events, istate, tt if Fn != 0j else -tt)
            Fp = F
            F = Fn
            z = zn
            P = Pn
            V = ud + (svq[lev] if am3 else sv[lev]) * Fn
            fn_c = fnn
            ft_c = ftn
            lev_prev = lev
            d2 = P.real * P.real + P.imag * P.imag
            if not (d2 <= maxd2):
                istate[I_STATUS] = DIVERGED
                break
            if err < 0.05 and not changed and lev > 0 and pos % (2 * units) == 0:
                lev -= 1
        if istate[I_STATUS] != OK:
            break
        sample += 1
        istate[I_STEP] = sample
        if sample % 64 == 0:
            # re-seed the phasor recurrence with the exact value
            tt = sample * H
            z = complex(math.cos(omega * tt), math.sin(omega * tt))
        # station 0 reuses P, V and the contact forces of the last step (_write_contact_sample
        # written out with the rows read above)
        idx = out_offset + s_i
        A0 = acc_z0 * z + acc_c0 + acc_fc0 * F
        for j in range(ns):
            A0 += rows_a[0, j] * y[j]
        _put(out, idx, 0, P, V, A0)
        if nst > 1:
            _write_probes(out, idx, y, z, F, rows, fn_c, ft_c)
        else:  # no probes: only the contact forces
            out[6, idx] = fn_c
            out[7, idx] = ft_c
        written += 1
    st.cstate[0] = F
    st.cstate[1] = z
    st.cstate[2] = Fp
    istate[I_LEVEL] = lev
    istate[I_PREV_LEVEL] = lev_prev
    return written


@njit(cache=True)
def _rhs(t, y, k, cp, dy):
    """Derivative ``dy`` of the unshifted eigen-coordinates at time ``t`` (s); returns ``F`` (N)."""
    P = 0j
    V = 0j
    for j in range(y.shape[0]):
        P += k.cdc[j] * y[j]
        V += k.cvc[j] * y[j]
    fy, fz, fn, ft = term_force(P.real, P.imag, V.real, V.imag, cp)
    F = complex(fy, fz)
    fu = k.fu0 * complex(math.cos(k.omega * t), math.sin(k.omega * t))
    for j in range(y.shape[0]):
        dy[j] = k.lam[j] * y[j] + k.beta_c[j] * F + k.beta_u[j] * fu + k.beta_l[j] * k.fl
    return F


@njit(cache=True)
def _rk4_start(y, hist, step, t, k, cp, work):
    """One RK4 step (``k.h``, s) of the ABM start; fills the derivative history ``hist`` (newest
    first). ``work = (k1, k2, k3, k4, yt)``: stage derivatives and the stage state (ns,)."""
    k1, k2, k3, k4, yt = work
    h = k.h
    ns = y.shape[0]
    _rhs(t, y, k, cp, k1)
    for j in range(ns):
        hist[3 - step, j] = k1[j]
        yt[j] = y[j] + 0.5 * h * k1[j]
    _rhs(t + 0.5 * h, yt, k, cp, k2)
    for j in range(ns):
        yt[j] = y[j] + 0.5 * h * k2[j]
    _rhs(t + 0.5 * h, yt, k, cp, k3)
    for j in range(ns):
        yt[j] = y[j] + h * k3[j]
    _rhs(t + h, yt, k, cp, k4)
    for j in range(ns):
        y[j] = y[j] + h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])
    if step == 2:
        _rhs(t + h, y, k, cp, k1)
        for j in range(ns):
            hist[0, j] = k1[j]


@njit(cache=True)
def abm_fixed(st, n_samples, out_offset, k, cp, rows):
    """Seed scheme: fixed-step 4th-order Adams-Bashforth-Moulton PECE, RK4 start.

    ``st`` (:class:`rubrotor.engine.shaft_steppers.RunState`): ``y`` the unshifted complex eigen-coordinates,
    ``hist`` (4, ns) the last four derivatives (newest first), ``cstate[0]`` the contact force
    (N) of the last step (carried across calls, for the events), ``istate`` (slots ``I_*``);
    ``k`` (:class:`rubrotor.engine.shaft_steppers.AbmStep`): modes, force inputs, forces, contact rows,
    ``omega`` (rad/s), ``h`` (s), ``save_every``, ``max_disp`` (m), ``event_reserve``.
    """
    y, hist, istate, out, events = st.y, st.hist, st.istate, st.out, st.events
    h, cdc, cvc = k.h, k.cdc, k.cvc
    ns = y.shape[0]
    k1 = np.empty(ns, np.complex128)
    k2 = np.empty(ns, np.complex128)
    k3 = np.empty(ns, np.complex128)
    k4 = np.empty(ns, np.complex128)
    yt = np.empty(ns, np.complex128)
    fp = np.empty(ns, np.complex128)
    rk4_work = (k1, k2, k3, k4, yt)
    maxd2 = k.max_disp * k.max_disp
    written = 0
    step = istate[I_STEP]
    F = st.cstate[0]
    for s_i in range(n_samples):
        if _buffer_short(events, istate, k.event_reserve):
            break
        for _ in range(k.save_every):
            t = step * h
            if step < 3:
                _rk4_start(y, hist, step, t, k, cp, rk4_work)
            else:
                # hist[0] = f_n, hist[1] = f_{n-1}, ...
                for j in range(ns):
                    yt[j] = y[j] + h / 24.0 * (
                        55.0 * hist[0, j] - 59.0 * hist[1, j] + 37.0 * hist[2, j] - 9.0 * hist[3, j]
                    )
                _rhs(t + h, yt, k, cp, fp)
                for j in range(ns):
                    y[j] = y[j] + h / 24.0 * (
                        9.0 * fp[j] + 19.0 * hist[0, j] - 5.0 * hist[1, j] + hist[2, j]
                    )
                for j in range(ns):
                    hist[3, j] = hist[2, j]
                    hist[2, j] = hist[1, j]
                    hist[1, j] = hist[0, j]
                Fn = _rhs(t + h, y, k, cp, k1)
                for j in range(ns):
                    hist[0, j] = k1[j]
                if (Fn != 0j) != (F != 0j):
                    _record_event(events, istate, (t + h) if Fn != 0j else -(t + h))
                F = Fn
            step += 1
            P = 0j
            for j in range(ns):
                P += cdc[j] * y[j]
            d2 = P.real * P.real + P.imag * P.imag
            if not (d2 <= maxd2):
                istate[I_STATUS] = DIVERGED
                break
        if istate[I_STATUS] != OK:
            break
        z = complex(math.cos(k.omega * step * h), math.sin(k.omega * step * h))
        # contact force consistent with the saved state
        P = 0j
        V = 0j
        for j in range(ns):
            P += cdc[j] * y[j]
            V += cvc[j] * y[j]
        fy, fz, fn, ft = term_force(P.real, P.imag, V.real, V.imag, cp)
        _write_sample(out, out_offset + s_i, y, z, complex(fy, fz), cp, rows)
        written += 1
    st.cstate[0] = F
    istate[I_STEP] = step
    return written
