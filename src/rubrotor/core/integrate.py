"""Compiled time loops for the modal rotor with contact (plain arrays, SI units).

The rotor is diagonalised once (in :mod:`rubrotor.simulate`): with ``y`` the complex eigen-
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

from rubrotor.core.contact import contact_force, solve_contact

SAFE_FASTMATH = {"contract", "reassoc", "arcp", "nsz"}
"""LLVM fast-math flags that allow vectorisation but keep NaN and infinity semantics, so the
divergence checks ``not (d2 <= limit)`` still see a NaN."""

__all__ = ["expo_fixed", "expo_adaptive", "abm_fixed", "STATUS", "n_channels"]

STATUS = {0: "complete", 1: "diverged", 2: "contact solve failed", 3: "event buffer full"}


def n_channels(n_stations: int) -> int:
    """Number of saved channels for ``n_stations`` output stations."""
    return 6 * n_stations + 2


@njit(cache=True, inline="always")
def _station(y, z, F, s, orows):
    """Complex displacement (m), velocity (m/s) and acceleration (m/s^2) at output station ``s``.

    ``orows = (rows_d, rows_v, rows_a, acc_fc, part_u, part_l, vel_z, acc_z, acc_c)``: rows
    mapping the eigen-coordinates to each quantity, the direct acceleration per N of contact
    force, and the contributions of the particular (steady) solution as multiples of the
    unbalance phasor ``z`` and constants.
    """
    rows_d, rows_v, rows_a, acc_fc, part_u, part_l, vel_z, acc_z, acc_c = orows
    P = part_u[s] * z + part_l[s]
    V = vel_z[s] * z
    A = acc_z[s] * z + acc_c[s] + acc_fc[s] * F
    for j in range(y.shape[0]):
        yj = y[j]
        P += rows_d[s, j] * yj
        V += rows_v[s, j] * yj
        A += rows_a[s, j] * yj
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
def _write_probes(out, idx, y, z, F, orows, fn, ft):
    """Write stations 1.. (probes) from ``y`` and the given normal and friction forces (N)."""
    nst = orows[0].shape[0]
    for s in range(1, nst):
        P, V, A = _station(y, z, F, s, orows)
        _put(out, idx, s, P, V, A)
    b = 6 * nst
    out[b, idx] = fn
    out[b + 1, idx] = ft


@njit(cache=True)
def _write_sample(out, idx, y, z, F, cp, orows):
    """Write one sample computed from ``y``; the contact forces from station 0's state."""
    P, V, A = _station(y, z, F, 0, orows)
    _put(out, idx, 0, P, V, A)
    fy, fz, fn, ft = contact_force(P.real, P.imag, V.real, V.imag, cp)
    _write_probes(out, idx, y, z, F, orows, fn, ft)


@njit(cache=True)
def _friction_power(y, z, cp, cdc, cvc, part_c, vel_c_z, part_lc):
    """Power (W) of the friction force on the lateral motion of the shaft centre."""
    P = part_c * z + part_lc
    V = vel_c_z * z
    for j in range(y.shape[0]):
        P += cdc[j] * y[j]
        V += cvc[j] * y[j]
    fy, fz, fn, ft = contact_force(P.real, P.imag, V.real, V.imag, cp)
    if fn == 0.0:
        return 0.0
    d = abs(P)
    return ft * ((-P.imag / d) * V.real + (P.real / d) * V.imag)


@njit(cache=True)
def _powers(y, z, F, etrack, cp, cdc, cvc, part_c, vel_c_z, part_lc, qv):
    """Instantaneous powers (W): unbalance, constant load, contact force, modal damping, friction.

    ``etrack = (wv, wz, cmat, vel_u_row, vel_u_z, fu0, vel_l_row, vel_l_z, fl)``: rows giving the
    modal velocities, the damping matrix, the velocity rows of the unbalance and load stations
    (with their particular-solution parts) and the force amplitudes.
    """
    wv, wz, cmat, vel_u_row, vel_u_z, fu0, vel_l_row, vel_l_z, fl = etrack
    ns = y.shape[0]
    vu = vel_u_z * z
    vl = vel_l_z * z
    vc = vel_c_z * z
    for j in range(ns):
        vu += vel_u_row[j] * y[j]
        vl += vel_l_row[j] * y[j]
        vc += cvc[j] * y[j]
    fu = fu0 * z
    p_u = fu.real * vu.real + fu.imag * vu.imag
    p_l = fl.real * vl.real + fl.imag * vl.imag
    p_c = F.real * vc.real + F.imag * vc.imag
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


@njit(cache=True, fastmath=SAFE_FASTMATH)
def expo_fixed(
    y, cstate, istate, n_samples, save_every, out, out_offset,
    E, G0, G1, sd, sv, cdc, cvc, cp,
    orows,
    omega, h, max_disp,
    energy, etrack, work,
    events,
):  # fmt: skip
    """Fixed-step exponential integrator over ``n_samples`` saved samples.

    State in/out: ``y`` (complex eigen-coordinates, shifted), ``cstate = [F, z, F_prev]``
    (contact force N, unbalance phasor ``exp(i Omega t)``, previous force N),
    ``istate = [step, n_events, status]``. Writes samples ``out[:, out_offset : out_offset + n]``;
    returns the number written. ``work`` accumulates (J) the work of unbalance, load, contact
    force, modal damping (dissipated) and friction when ``energy`` is true. ``events`` collects
    contact onset (+t) and separation (-t) times (s), located by linear interpolation of
    ``|P| - g`` within the step.
    """
    ns = y.shape[0]
    jac = np.zeros((2, 4))
    qv = np.zeros(etrack[0].shape[0], np.complex128)
    # propagate-and-project vectors: pd = sum(cdE * y) + cdG0 * F, same for the velocity
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
    rows_a, acc_fc, part_u, part_l, vel_z = orows[2], orows[3], orows[4], orows[5], orows[6]
    acc_z, acc_c = orows[7], orows[8]
    part_c = part_u[0]
    part_lc = part_l[0]
    vel_cz = vel_z[0]
    g = cp[4]
    maxd2 = max_disp * max_disp
    rot = complex(math.cos(omega * h), math.sin(omega * h))
    written = 0
    P = 0j
    V = 0j
    fn_c = 0.0
    ft_c = 0.0
    d_prev = 0.0
    pw0 = (0.0, 0.0, 0.0, 0.0, 0.0)
    if energy:
        pw0 = _powers(y, z, F, etrack, cp, cdc, cvc, part_c, vel_cz, part_lc, qv)
    for s_i in range(n_samples):
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
                istate[2] = 2
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
                ne = istate[1]
                if ne < events.shape[0]:
                    den = d - d_prev
                    frac = (g - d_prev) / den if den != 0.0 else 1.0
                    frac = min(max(frac, 0.0), 1.0)
                    te = (step - 1 + frac) * h
                    events[ne] = te if Fn != 0j else -te
                    istate[1] = ne + 1
            d_prev = d
            Fp = F
            F = Fn
            z = zn
            if energy:
                pw1 = _powers(y, z, F, etrack, cp, cdc, cvc, part_c, vel_cz, part_lc, qv)
                work[0] += 0.5 * h * (pw0[0] + pw1[0])
                work[1] += 0.5 * h * (pw0[1] + pw1[1])
                work[2] += 0.5 * h * (pw0[2] + pw1[2])
                work[3] += 0.5 * h * (pw0[3] + pw1[3])
                work[4] += 0.5 * h * (pw0[4] + pw1[4])
                pw0 = pw1
            if not (d2 <= maxd2):
                istate[2] = 1
                break
        if istate[2] != 0:
            break
        A0 = acc_z[0] * z + acc_c[0] + acc_fc[0] * F
        for j in range(ns):
            A0 += rows_a[0, j] * y[j]
        # station 0 reuses P, V of the step; the contact forces come from the Newton solve
        _put(out, out_offset + s_i, 0, P, V, A0)
        _write_probes(out, out_offset + s_i, y, z, F, orows, fn_c, ft_c)
        written += 1
    cstate[0] = F
    cstate[1] = z
    cstate[2] = Fp
    istate[0] = step
    return written


@njit(cache=True, fastmath=SAFE_FASTMATH)
def expo_adaptive(
    y, cstate, istate, n_samples, out, out_offset,
    E, G0, G1, cdE, cvE, cdG0, cvG0, sd, sv, errc, rot, cdc, cvc, cp,
    Q0, Qm, Q1, cdQ0, cvQ0, cdQm, cvQm, sdq, svq,
    orows,
    omega, H, max_disp, rtol, atol,
    events, stats,
):  # fmt: skip
    """Error-controlled exponential integrator with dyadic steps ``H / 2^level``.

    Saves one sample every ``H`` (s). Level arrays ``E, G0, G1, cdE, cvE`` have shape
    (levels, ns) and ``cdG0, cvG0, sd, sv, errc, rot`` shape (levels,); ``cdE = cd * E`` etc. are
    the propagate-and-project vectors of the contact station.

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

    ``cstate = [F, z, F_prev]``, ``istate = [sample, n_events, status, level, prev_level]``,
    ``stats = [accepted, rejected, newton iterations]``.
    """
    ns = y.shape[0]
    nlev = E.shape[0]
    J = nlev - 1
    full = 1 << J
    jac = np.zeros((2, 4))
    F = cstate[0]
    z = cstate[1]
    Fp = cstate[2]
    rows_a, acc_fc, acc_z, acc_c = orows[2], orows[3], orows[7], orows[8]
    part_c = orows[4][0]
    part_lc = orows[5][0]
    vel_cz = orows[6][0]
    g = cp[4]
    a_f = abs(orows[3][0])
    maxd2 = max_disp * max_disp
    lev = istate[3]
    lev_prev = istate[4]
    written = 0
    P = 0j
    V = 0j
    fn_c = 0.0
    ft_c = 0.0
    for s_i in range(n_samples):
        sample = istate[0]
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
            stats[2] += max(it, 0)
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
                stats[1] += 1
                continue
            if it < 0:
                istate[2] = 2
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
            stats[0] += 1
            pos += units
            if changed:
                ne = istate[1]
                if ne < events.shape[0]:
                    tt = t_start + pos * (H / full)
                    events[ne] = tt if Fn != 0j else -tt
                    istate[1] = ne + 1
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
                istate[2] = 1
                break
            if err < 0.05 and not changed and lev > 0 and pos % (2 * units) == 0:
                lev -= 1
        if istate[2] != 0:
            break
        sample += 1
        istate[0] = sample
        if sample % 64 == 0:
            # re-seed the phasor recurrence with the exact value
            tt = sample * H
            z = complex(math.cos(omega * tt), math.sin(omega * tt))
        # station 0 reuses P, V and the contact forces of the last step
        A0 = acc_z[0] * z + acc_c[0] + acc_fc[0] * F
        for j in range(ns):
            A0 += rows_a[0, j] * y[j]
        _put(out, out_offset + s_i, 0, P, V, A0)
        _write_probes(out, out_offset + s_i, y, z, F, orows, fn_c, ft_c)
        written += 1
    cstate[0] = F
    cstate[1] = z
    cstate[2] = Fp
    istate[3] = lev
    istate[4] = lev_prev
    return written


@njit(cache=True)
def _rhs(t, y, lam, beta_c, beta_u, beta_l, fu0, fl, omega, cdc, cvc, cp, dy):
    P = 0j
    V = 0j
    for j in range(y.shape[0]):
        P += cdc[j] * y[j]
        V += cvc[j] * y[j]
    fy, fz, fn, ft = contact_force(P.real, P.imag, V.real, V.imag, cp)
    F = complex(fy, fz)
    fu = fu0 * complex(math.cos(omega * t), math.sin(omega * t))
    for j in range(y.shape[0]):
        dy[j] = lam[j] * y[j] + beta_c[j] * F + beta_u[j] * fu + beta_l[j] * fl
    return F


@njit(cache=True)
def abm_fixed(
    y, hist, istate, n_samples, save_every, out, out_offset,
    lam, beta_c, beta_u, beta_l, fu0, fl, cdc, cvc, cp,
    orows,
    omega, h, max_disp, events,
):  # fmt: skip
    """Seed scheme: fixed-step 4th-order Adams-Bashforth-Moulton PECE, RK4 start.

    ``y`` are the unshifted complex eigen-coordinates; ``hist`` (4, ns) keeps the last four
    derivatives (newest first); ``istate = [step, n_events, status]``.
    """
    ns = y.shape[0]
    k1 = np.empty(ns, np.complex128)
    k2 = np.empty(ns, np.complex128)
    k3 = np.empty(ns, np.complex128)
    k4 = np.empty(ns, np.complex128)
    yt = np.empty(ns, np.complex128)
    fp = np.empty(ns, np.complex128)
    maxd2 = max_disp * max_disp
    written = 0
    step = istate[0]
    F = 0j
    for s_i in range(n_samples):
        for _ in range(save_every):
            t = step * h
            if step < 3:
                _rhs(t, y, lam, beta_c, beta_u, beta_l, fu0, fl, omega, cdc, cvc, cp, k1)
                for j in range(ns):
                    hist[3 - step, j] = k1[j]
                    yt[j] = y[j] + 0.5 * h * k1[j]
                _rhs(t + 0.5 * h, yt, lam, beta_c, beta_u, beta_l, fu0, fl, omega, cdc, cvc, cp, k2)
                for j in range(ns):
                    yt[j] = y[j] + 0.5 * h * k2[j]
                _rhs(t + 0.5 * h, yt, lam, beta_c, beta_u, beta_l, fu0, fl, omega, cdc, cvc, cp, k3)
                for j in range(ns):
                    yt[j] = y[j] + h * k3[j]
                _rhs(t + h, yt, lam, beta_c, beta_u, beta_l, fu0, fl, omega, cdc, cvc, cp, k4)
                for j in range(ns):
                    y[j] = y[j] + h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])
                if step == 2:
                    _rhs(t + h, y, lam, beta_c, beta_u, beta_l, fu0, fl, omega, cdc, cvc, cp, k1)
                    for j in range(ns):
                        hist[0, j] = k1[j]
            else:
                # hist[0] = f_n, hist[1] = f_{n-1}, ...
                for j in range(ns):
                    yt[j] = y[j] + h / 24.0 * (
                        55.0 * hist[0, j] - 59.0 * hist[1, j] + 37.0 * hist[2, j] - 9.0 * hist[3, j]
                    )
                _rhs(t + h, yt, lam, beta_c, beta_u, beta_l, fu0, fl, omega, cdc, cvc, cp, fp)
                for j in range(ns):
                    y[j] = y[j] + h / 24.0 * (
                        9.0 * fp[j] + 19.0 * hist[0, j] - 5.0 * hist[1, j] + hist[2, j]
                    )
                for j in range(ns):
                    hist[3, j] = hist[2, j]
                    hist[2, j] = hist[1, j]
                    hist[1, j] = hist[0, j]
                Fn = _rhs(t + h, y, lam, beta_c, beta_u, beta_l, fu0, fl, omega, cdc, cvc, cp, k1)
                for j in range(ns):
                    hist[0, j] = k1[j]
                if (Fn != 0j) != (F != 0j):
                    ne = istate[1]
                    if ne < events.shape[0]:
                        events[ne] = (t + h) if Fn != 0j else -(t + h)
                        istate[1] = ne + 1
                F = Fn
            step += 1
            P = 0j
            for j in range(ns):
                P += cdc[j] * y[j]
            d2 = P.real * P.real + P.imag * P.imag
            if not (d2 <= maxd2):
                istate[2] = 1
                break
        if istate[2] != 0:
            break
        z = complex(math.cos(omega * step * h), math.sin(omega * step * h))
        # contact force consistent with the saved state
        P = 0j
        V = 0j
        for j in range(ns):
            P += cdc[j] * y[j]
            V += cvc[j] * y[j]
        fy, fz, fn, ft = contact_force(P.real, P.imag, V.real, V.imag, cp)
        _write_sample(out, out_offset + s_i, y, z, complex(fy, fz), cp, orows)
        written += 1
    istate[0] = step
    return written
