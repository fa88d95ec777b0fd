"""Full-DOF SciPy reference for free-spin runs (:mod:`rubrotor.engine.spin`), for tests.

Integrates in physical coordinates, without the modal basis and the compiled kernel::

    M q'' + (C + Omega G) q' + K q = f_s + sum_u B_u F_u(Omega, Omega', theta) + sum_i B_i F_i
    J Omega' = sum_i R_i ft_i,   J_i omega_i' = -r_i ft_i - d_i omega_i,   theta' = Omega

with the supports listed in ``failing`` removed from ``K``, ``C`` from ``fail_time`` on
(solve_ivp with ``t_eval``; the run is split at ``fail_time``). Constant bearing coefficients
only.
"""

import dataclasses
import math

import numpy as np
from scipy.integrate import solve_ivp

from rubrotor.core.contact import contact_force, pack_contact
from rubrotor.engine.parts import static_load_vector


def free_spin_reference(system, J, speed, times, stations, *, rings=None, unbalances=(),
                        gravity=(0.0, 0.0), fail_time=math.inf, failing=(), initial="rest",
                        rtol=1e-10, atol=1e-14, method="DOP853"):  # fmt: skip
    """States ``q`` (n, len(times)), ``Omega``, ``theta``, ``omega_rings`` (n_c, len(times))."""
    sm0 = system.matrices(speed)
    kept = tuple(s for i, s in enumerate(system.supports) if i not in failing)
    sm1 = dataclasses.replace(system, supports=kept).matrices(speed)
    n, nc = sm0.M.shape[0], len(stations)
    minv = np.linalg.inv(sm0.M)
    fs = static_load_vector(system, (), gravity)
    B = [system.force_map(s.contact.position) for s in stations]
    Bu = [system.force_map(u.position) for u in unbalances]
    cps = [pack_contact(1, s.contact.law_code, s.contact.stiffness, s.contact.damping,
                        s.contact.clearance, s.contact.friction, 0, 0.0,
                        s.contact.friction_regularization) for s in stations]  # fmt: skip
    rings = rings or (None,) * nc

    def rhs(t, y, sm):
        q, qd, om, th = y[:n], y[n : 2 * n], y[2 * n], y[2 * n + 1]
        f = fs - sm.K @ q - (sm.C + om * sm.G) @ qd
        torque, dw = 0.0, np.zeros(nc)
        for i, s in enumerate(stations):
            p, u = B[i].T @ q, B[i].T @ qd
            cp = cps[i].copy()
            rr = 0.0 if rings[i] is None else rings[i].radius
            cp[7] = s.contact.radius * om - rr * y[2 * n + 2 + i]
            fy, fz, fn, ft = contact_force(p[0] - s.offset_y, p[1] - s.offset_z, u[0], u[1], cp)
            f += B[i] @ np.array([fy, fz])
            torque += s.contact.radius * ft
            if rings[i] is not None:
                g = rings[i]
                dw[i] = (-g.radius * ft - g.drag * y[2 * n + 2 + i]) / g.inertia
        omd = torque / J
        for k, ub in enumerate(unbalances):
            a = th + ub.phase
            fu = ub.magnitude * np.array([om**2 * math.cos(a) + omd * math.sin(a),
                                          om**2 * math.sin(a) - omd * math.cos(a)])  # fmt: skip
            f += Bu[k] @ fu
        return np.concatenate([qd, minv @ f, [omd, om], dw])

    y0 = np.zeros(2 * n + 2 + nc)
    y0[2 * n] = speed
    if initial == "static":
        y0[:n] = np.linalg.solve(sm0.K, fs)
    times = np.asarray(times, float)
    out = np.zeros((y0.size, times.size))
    pieces = [(0.0, min(fail_time, times[-1]), sm0), (fail_time, times[-1], sm1)]
    for t0, t1, sm in pieces:
        if t1 <= t0:
            continue
        sel = (times >= t0) & (times <= t1)
        sol = solve_ivp(rhs, (t0, t1), y0, method=method, t_eval=times[sel], rtol=rtol,
                        atol=atol, args=(sm,), dense_output=True)  # fmt: skip
        out[:, sel] = sol.y
        y0 = sol.sol(t1)
    return out[:n], out[2 * n], out[2 * n + 1], out[2 * n + 2 :]
