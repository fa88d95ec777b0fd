"""Full-DOF SciPy reference for the general engine (no modal reduction), for tests.

Integrates ``M q'' + D q' + K q = f_s + Re(b_u e^{i Omega t}) + sum_i B_i F_i`` and, for each
flexible stator, ``M_s s'' + C_s s' + K_s s = -F_i`` with ``F_i`` the same contact law on the
relative displacement ``B_i^T q - s_i - offset_i`` (solve_ivp, tight tolerances).
"""

import numpy as np
from scipy.integrate import solve_ivp

from rubrotor.core.contact import contact_force, pack_contact
from rubrotor.engine.parts import speed_at, spin_angle, static_load_vector, unbalance_phasor
from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section

STEEL = Material("steel", 211e9, 7810, poisson_ratio=0.3)


def two_disk_rotor():
    """The engine tests' rotor: 1 m steel shaft (40 mm, 6 elements), disks at 0.33 and 0.67 m,
    anisotropic cross-coupled bearings with cross damping at both ends."""
    return Rotor(
        [Section(1.0, 0.04, STEEL, elements=6)],
        disks=[Disk(0.33, 8.0, 0.04, 0.02), Disk(0.67, 5.0, 0.03, 0.015)],
        bearings=[
            Bearing(0.0, kyy=2e6, kzz=3e6, kyz=4e5, kzy=-3e5, cyy=300, czz=400, cyz=50, czy=50),
            Bearing(1.0, kyy=2.5e6, kzz=2e6, kyz=2e5, kzy=-2e5, cyy=300, czz=300),
        ],
    )


def reference_run(
    system,
    run,
    stations,
    unbalances=(),
    loads=(),
    gravity=(0.0, 0.0),
    method="DOP853",
    rtol=1e-10,
    atol=1e-14,
    x0=None,
):
    """Sample times (s), rotor displacement at each contact (nc, 2, T), stator (nc, 2, T)."""
    w = run.speed
    sm = system.matrices(w)
    M, D, K = sm.M, sm.damping, sm.K
    C, G = sm.C, sm.G
    n = M.shape[0]
    minv = np.linalg.inv(M)
    B = [system.force_map(s.contact.position) for s in stations]
    b_u = sum(
        (
            unbalance_phasor(u, 1.0) * (system.force_map(u.position) @ np.array([1, -1j]))
            for u in unbalances
        ),
        np.zeros(n, complex),
    )
    f_s = static_load_vector(system, tuple(loads), gravity)
    cps = [
        pack_contact(
            1,
            s.contact.law_code,
            s.contact.stiffness,
            s.contact.damping,
            s.contact.clearance,
            s.contact.friction,
            s.contact.sign_code,
            s.contact.radius * w,
            s.contact.friction_regularization,
        )
        for s in stations
    ]
    nc = len(stations)
    flex = [s.stator is not None for s in stations]
    smat = [s.stator.matrices() if s.stator is not None else None for s in stations]
    so = []  # offset of each stator's [s, s'] in the state
    o = 2 * n
    for f in flex:
        so.append(o if f else -1)
        o += 4 if f else 0

    def rhs(t, x):
        q, qd = x[:n], x[n : 2 * n]
        wt, alpha = (float(v) for v in speed_at(run, t))  # piecewise-linear speed profile
        th = float(spin_angle(run, t))
        f = f_s + np.real((wt**2 - 1j * alpha) * b_u * np.exp(1j * th))
        Dt = C + wt * G
        dx = np.empty_like(x)
        for i, s in enumerate(stations):
            p = B[i].T @ q - np.array([s.offset_y, s.offset_z])
            u = B[i].T @ qd
            if flex[i]:
                k = so[i]
                p = p - x[k : k + 2]
                u = u - x[k + 2 : k + 4]
            fy, fz, _, _ = contact_force(p[0], p[1], u[0], u[1], cps[i])
            fc = np.array([fy, fz])
            f = f + B[i] @ fc
            if flex[i]:
                k = so[i]
                ms, cs, ks = smat[i]
                dx[k : k + 2] = x[k + 2 : k + 4]
                dx[k + 2 : k + 4] = np.linalg.solve(
                    ms, -fc - cs @ x[k + 2 : k + 4] - ks @ x[k : k + 2]
                )
        dx[:n] = qd
        dx[n : 2 * n] = minv @ (f - Dt @ qd - K @ q)
        return dx

    if x0 is None:
        x0 = np.zeros(o)
        if run.initial in ("static", "steady"):
            qs = np.linalg.solve(K, f_s)
            x0[:n] = qs
        if run.initial == "steady":
            Q = np.linalg.solve(K - w**2 * M + 1j * w * D, w**2 * b_u)
            x0[:n] += Q.real
            x0[n : 2 * n] = (1j * w * Q).real
    dt = run.step * run.save_every
    nt = int(np.floor(run.duration / dt + 1e-9)) + 1
    t_eval = np.arange(nt) * dt
    sol = solve_ivp(rhs, (0, t_eval[-1]), x0, method=method, t_eval=t_eval, rtol=rtol, atol=atol)
    assert sol.success, sol.message
    rot = np.array([B[i].T @ sol.y[:n] for i in range(nc)])
    st = np.array([sol.y[so[i] : so[i] + 2] if flex[i] else np.zeros((2, nt)) for i in range(nc)])
    probes = [system.output_rows(x) for x in run.probes]
    if probes:
        return t_eval, np.array([r @ sol.y[:n] for r in probes]), st, sol
    return t_eval, rot, st, sol
