"""Compiled rotor-stator contact law on plain floats (SI).

Parameters are packed in a float64 array ``cp`` (see ``CP_FIELDS``) so that the kernels take
one argument for the whole law. Units: displacements m, velocities m/s, forces N.
"""

import math

import numpy as np
from numba import njit

__all__ = [
    "CP_FIELDS",
    "LAW_EXPONENTS",
    "pack_contact",
    "contact_force",
    "contact_force_jac",
    "contact_force_jac_exact",
    "solve_contact",
    "force_scale",
    "forces_of",
]

CP_FIELDS = (
    "active",  # 1.0 when a contact law is present
    "law",  # 0 Hertz/Hunt-Crossley, 1 linear spring-dashpot
    "stiffness",  # N/m^1.5 or N/m
    "damping",  # s/m (Hunt-Crossley b_h) or N s/m
    "clearance",  # m
    "friction",  # mu
    "sign",  # 0 physical, 1 seed
    "surface_speed",  # R Omega, m/s
    "v_reg",  # m/s
    "force_scale",  # N, for tolerances
)


LAW_EXPONENTS = (1.5, 1.0)
"""Exponent ``a`` of ``F_n = k eps^a`` of each law code (0 Hertz, 1 linear): the force scale
``k g^a`` of the tolerances (the law terms: ``rubrotor.forces.contact``)."""


def pack_contact(
    active, law, stiffness, damping, clearance, friction, sign, surface_speed, v_reg
) -> np.ndarray:
    """Pack the contact parameters into the array the kernels take (SI units)."""
    scale = stiffness * clearance ** LAW_EXPONENTS[law] if active else 1.0
    return np.array(
        [
            float(active),
            float(law),
            stiffness,
            damping,
            clearance,
            friction,
            float(sign),
            surface_speed,
            v_reg,
            max(scale, 1e-300),
        ]
    )


@njit(cache=True, inline="always")
def _law(py, pz, uy, uz, cp):
    """The contact law and its Jacobian, written once.

    Returns ``(fy, fz, fn, ft, j00, j01, j02, j03, j10, j11, j12, j13)`` with
    ``j[i][k] = d(fy, fz)[i] / d(py, pz, uy, uz)[k]``; the derivative of the smoothed friction
    sign is neglected (a quasi-Newton Jacobian). Inlined, so callers that drop the derivatives do
    not compute them.
    """
    if cp[0] == 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    d = math.sqrt(py * py + pz * pz)
    g = cp[4]
    if d <= g:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    ny = py / d
    nz = pz / d
    eps = d - g
    epsd = ny * uy + nz * uz
    k = cp[2]
    c = cp[3]
    # d(epsd)/dp = (u - epsd n) / d
    dey = (uy - epsd * ny) / d
    dez = (uz - epsd * nz) / d
    if cp[1] == 0.0:
        se = math.sqrt(eps)
        s = eps * se
        fn = k * s * (1.0 + c * epsd)
        a = 1.5 * k * se * (1.0 + c * epsd)
        b = k * s * c
        dfn_py = a * ny + b * dey
        dfn_pz = a * nz + b * dez
        dfn_uy = b * ny
        dfn_uz = b * nz
    else:
        fn = k * eps + c * epsd
        dfn_py = k * ny + c * dey
        dfn_pz = k * nz + c * dez
        dfn_uy = c * ny
        dfn_uz = c * nz
    if fn <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    mu = cp[5]
    if cp[6] == 0.0:
        vs = cp[7] - nz * uy + ny * uz
        sig = vs / math.sqrt(vs * vs + cp[8] * cp[8])
    else:
        sig = -1.0
    ms = mu * sig
    # F = -fn w, w = (I + ms J) n, J = [[0, -1], [1, 0]]; dw/dp = (I + ms J)(I - n n^T) / d
    wy = ny - ms * nz
    wz = nz + ms * ny
    p11 = (1.0 - ny * ny) / d
    p12 = -ny * nz / d
    p22 = (1.0 - nz * nz) / d
    w11 = p11 - ms * p12
    w12 = p12 - ms * p22
    w21 = p12 + ms * p11
    w22 = p22 + ms * p12
    return (
        -fn * wy,
        -fn * wz,
        fn,
        -ms * fn,
        -(wy * dfn_py + fn * w11),
        -(wy * dfn_pz + fn * w12),
        -wy * dfn_uy,
        -wy * dfn_uz,
        -(wz * dfn_py + fn * w21),
        -(wz * dfn_pz + fn * w22),
        -wz * dfn_uy,
        -wz * dfn_uz,
    )


@njit(cache=True, inline="always")
def contact_force(py, pz, uy, uz, cp):
    """Contact force on the rotor.

    Parameters
    ----------
    py, pz : float
        Shaft-centre displacement at the contact station (m).
    uy, uz : float
        Its velocity (m/s).
    cp : ndarray
        Packed parameters (``CP_FIELDS``).

    Returns
    -------
    fy, fz : float
        Force components on the rotor (N).
    fn : float
        Normal force magnitude (N), >= 0.
    ft : float
        Friction force along the tangent ``t = i n`` (N); negative opposes the spin direction.
    """
    r = _law(py, pz, uy, uz, cp)
    return r[0], r[1], r[2], r[3]


@njit(cache=True, inline="always")
def contact_force_jac(py, pz, uy, uz, cp, jac):
    """Contact force and its Jacobian.

    ``jac`` (2 x 4, filled in place) holds ``d(fy, fz) / d(py, pz, uy, uz)``; the derivative of
    the smoothed friction sign is neglected (a quasi-Newton Jacobian). Returns
    ``(fy, fz, fn, ft)`` as :func:`contact_force`.
    """
    r = _law(py, pz, uy, uz, cp)
    jac[0, 0] = r[4]
    jac[0, 1] = r[5]
    jac[0, 2] = r[6]
    jac[0, 3] = r[7]
    jac[1, 0] = r[8]
    jac[1, 1] = r[9]
    jac[1, 2] = r[10]
    jac[1, 3] = r[11]
    return r[0], r[1], r[2], r[3]


@njit(cache=True)
def solve_contact(pd, ud, sd, sv, f0, cp, jac):
    """Solve ``F = f(pd + sd F, ud + sv F)`` for the complex contact force ``F = Fy + i Fz``.

    ``pd``, ``ud`` are the contact-point displacement (m) and velocity (m/s) the step would give
    with ``F = 0``; ``sd`` (m/N), ``sv`` (m/(s N)) their complex sensitivities to ``F``; ``f0`` a
    starting guess (N). Newton's method on the two real unknowns, with step halving when the
    residual grows; it stops when the Newton step is below ``1e-13`` of the force (quadratic
    convergence leaves an error of the order of the step squared).

    Returns
    -------
    F : complex
        Contact force (N).
    iterations : int
        Newton iterations; negative when it did not converge.
    fn, ft : float
        Normal and friction force (N) of the converged force (:func:`forces_of`).
    """
    if cp[0] == 0.0:
        return 0j, 0, 0.0, 0.0
    # The force-free step staying inside the clearance means F = 0 is the solution: a non-zero
    # force pushes the centre further inwards (sd is close to a positive compliance).
    if abs(pd) <= cp[4]:
        return 0j, 0, 0.0, 0.0
    tol = 1e-13 * force_scale(cp, abs(sd))
    F = f0
    if F == 0j:
        fy, fz, fn, ft = contact_force(pd.real, pd.imag, ud.real, ud.imag, cp)
        F = complex(fy, fz)
    rnorm_prev = 1e300
    last = 0j
    fn = 0.0
    ft = 0.0
    for it in range(1, 60):
        p = pd + sd * F
        u = ud + sv * F
        fy, fz, fn, ft = contact_force_jac(p.real, p.imag, u.real, u.imag, cp, jac)
        ry = F.real - fy
        rz = F.imag - fz
        rnorm = math.sqrt(ry * ry + rz * rz)
        if rnorm > rnorm_prev and it > 1:
            # halve the last Newton step
            last = 0.5 * last
            F = F + last
            rnorm_prev = 1e300
            continue
        if rnorm <= tol:
            fn, ft = forces_of(F.real, F.imag, fn, ft)
            return F, it, fn, ft
        # JR = I - (Jp Sd + Ju Sv), with complex multiplication as 2x2 real matrices
        a11 = 1.0 - (
            jac[0, 0] * sd.real + jac[0, 1] * sd.imag + jac[0, 2] * sv.real + jac[0, 3] * sv.imag
        )
        a12 = -(
            -jac[0, 0] * sd.imag + jac[0, 1] * sd.real - jac[0, 2] * sv.imag + jac[0, 3] * sv.real
        )
        a21 = -(
            jac[1, 0] * sd.real + jac[1, 1] * sd.imag + jac[1, 2] * sv.real + jac[1, 3] * sv.imag
        )
        a22 = 1.0 - (
            -jac[1, 0] * sd.imag + jac[1, 1] * sd.real - jac[1, 2] * sv.imag + jac[1, 3] * sv.real
        )
        det = a11 * a22 - a12 * a21
        dy = (a22 * ry - a12 * rz) / det
        dz = (-a21 * ry + a11 * rz) / det
        last = complex(dy, dz)
        F = F - last
        rnorm_prev = rnorm
        if math.sqrt(dy * dy + dz * dz) <= 1e-13 * abs(F) + tol:
            fn, ft = forces_of(F.real, F.imag, fn, ft)
            return F, it, fn, ft
    return F, -1, fn, ft


@njit(cache=True, inline="always")
def force_scale(cp, sdn):
    """Force scale (N) of the Newton tolerances: ``min(k g^a, g / |S_d|)``.

    ``k g^a`` (``cp[9]``, the law's force at a penetration of one clearance) is the scale of a
    soft contact; a contact stiffer than the step (``k |S_d| > 1``, ``|S_d|`` (m/N) the largest
    sensitivity of the contact displacement to its force over the step) is limited by the rotor
    instead: ``g / |S_d|`` moves the contact point by one clearance. With ``k g^a`` alone the
    tolerance grew with the stiffness (``1e-13 k g``: 4e12 N at ``k = 1e30`` N/m on
    seal_rub.toml) and accepted unconverged forces.
    """
    if sdn > 0.0 and cp[4] >= 0.0:  # a row that is not a contact (cp[4] < 0): its own scale
        return min(cp[9], cp[4] / sdn)
    return cp[9]


@njit(cache=True, inline="always")
def forces_of(fy, fz, fn, ft):
    """Normal and friction force (N) of the converged contact force ``(fy, fz)`` (N).

    ``F = -f_n (n + m J n)`` with ``m = -f_t / f_n`` the friction ratio of the last law
    evaluation, so ``f_n = |F| / sqrt(1 + m^2)``. Newton's last evaluation is one iterate behind
    the converged force; for a contact much stiffer than the step its normal force is that
    iterate's penetration times ``k``: with ``k = 1e17`` N/m it read 6.9e6 N where the applied
    force was 1.1e3 N. The force itself is well conditioned (its error is the penetration's
    round-off over ``|S_d|``), so the reported forces are taken from it.
    """
    if fn <= 0.0:
        return math.sqrt(fy * fy + fz * fz), 0.0
    r = ft / fn
    n = math.sqrt(fy * fy + fz * fz) / math.sqrt(1.0 + r * r)
    return n, r * n


@njit(cache=True, inline="always")
def contact_force_jac_exact(py, pz, uy, uz, cp, jac):
    """Contact force and its exact Jacobian, the smoothed friction sign differentiated too.

    As :func:`contact_force_jac` plus the term the quasi-Newton Jacobian leaves out: with the
    physical sign the friction coefficient is ``mu s(v_s)``, ``s = v_s / sqrt(v_s^2 + v_r^2)``,
    ``v_s = R Omega + t . u`` the sliding speed (``t = i n`` the tangent), so
    ``dF = -f_n (J n) mu s'(v_s) dv_s`` with ``s' = v_r^2 / (v_s^2 + v_r^2)^1.5`` and
    ``dv_s = t . du + u . (dt/dp) dp``. Used for tangent (variational) dynamics, where the
    derivative must be the true one. Returns ``(fy, fz, fn, ft)``.
    """
    fy, fz, fn, ft = contact_force_jac(py, pz, uy, uz, cp, jac)
    if fn == 0.0 or cp[6] != 0.0:
        return fy, fz, fn, ft
    d = math.sqrt(py * py + pz * pz)
    ny = py / d
    nz = pz / d
    vs = cp[7] - nz * uy + ny * uz
    vr2 = cp[8] * cp[8]
    q = vs * vs + vr2
    dsig = vr2 / (q * math.sqrt(q))
    p11 = (1.0 - ny * ny) / d
    p12 = -ny * nz / d
    p22 = (1.0 - nz * nz) / d
    # d v_s / d(py, pz, uy, uz); dn/dp = (I - n n^T) / d
    d0 = -p12 * uy + p11 * uz
    d1 = -p22 * uy + p12 * uz
    d2 = -nz
    d3 = ny
    # dF / d(mu s) = -fn J n = fn (nz, -ny)
    ay = fn * nz * cp[5] * dsig
    az = -fn * ny * cp[5] * dsig
    jac[0, 0] += ay * d0
    jac[0, 1] += ay * d1
    jac[0, 2] += ay * d2
    jac[0, 3] += ay * d3
    jac[1, 0] += az * d0
    jac[1, 1] += az * d1
    jac[1, 2] += az * d2
    jac[1, 3] += az * d3
    return fy, fz, fn, ft
