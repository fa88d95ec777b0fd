"""Independent references for tests and benchmarks (SciPy only; slow by design).

Nothing here uses the diagonalised system or the compiled kernels of rubrotor: the modal matrices
come from :func:`rubrotor.rotors.shaft.modal_matrices` (the physics under test), the contact law is
re-implemented from the equations of the model notes, and the time integration is SciPy's (matrix
exponential or ``solve_ivp`` DOP853 at tight tolerance).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.integrate
import scipy.linalg

from rubrotor.forces.contact import law_named
from rubrotor.rotors.shaft import Shaft, modal_matrices


def physical_system(shaft: Shaft, speed: float, zeta: float = 0.0):
    """First-order complex system x' = A x + B(a) F with x = [q_1, q_1', q_2, q_2', ...]."""
    blocks, defl = [], []
    off = 0
    for n in range(1, shaft.modes + 1):
        mm = modal_matrices(shaft, n)
        m = mm.size
        if zeta:
            w2, phi = scipy.linalg.eigh(mm.K, mm.M)
            c = mm.M @ phi @ np.diag(2 * zeta * np.sqrt(w2)) @ phi.T @ mm.M
        else:
            c = np.zeros_like(mm.M)
        minv = np.linalg.inv(mm.M)
        a = np.zeros((2 * m, 2 * m), complex)
        a[:m, m:] = np.eye(m)
        a[m:, :m] = -minv @ mm.K
        a[m:, m:] = -minv @ (c + speed * mm.G)
        blocks.append(a)
        defl.append((off, off + m, mm.M[0, 0], shaft.wavenumber(n)))
        off += 2 * m
    A = scipy.linalg.block_diag(*blocks)

    def b_of(x):
        b = np.zeros(A.shape[0], complex)
        for _p, pv, m0, k in defl:
            b[pv] = math.sin(k * x) / m0
        return b

    def row_d(x):
        r = np.zeros(A.shape[0], complex)
        for p, _pv, _m0, k in defl:
            r[p] = math.sin(k * x)
        return r

    def row_v(x):
        r = np.zeros(A.shape[0], complex)
        for _p, pv, _m0, k in defl:
            r[pv] = math.sin(k * x)
        return r

    return A, b_of, row_d, row_v


def exact_unbalance_response(shaft, speed, me, a_u, x_out, times, zeta=0.0):
    """Exact response from rest to the unbalance force me Omega^2 exp(i Omega t) at a_u.

    Particular harmonic solution plus the matrix-exponential transient; returns the complex
    deflection v + i w (m) at x_out for each time (s).
    """
    A, b_of, row_d, _ = physical_system(shaft, speed, zeta)
    b = b_of(a_u) * me * speed**2
    xp = np.linalg.solve(1j * speed * np.eye(A.shape[0]) - A, b)
    x0 = -xp
    r = row_d(x_out)
    out = np.empty(len(times), complex)
    dt = times[1] - times[0]
    step = scipy.linalg.expm(A * dt)
    x = x0.copy()
    for i, t in enumerate(times):
        if i % 2000 == 0:
            x = scipy.linalg.expm(A * t) @ x0
        out[i] = r @ (x + xp * np.exp(1j * speed * t))
        x = step @ x
    return out


def contact_force_reference(P, V, *, law, k, c, g, mu, surface_speed, v_reg, seed_sign=False):
    """Contact force on the rotor from the model-notes equations (complex N)."""
    d = abs(P)
    if d <= g:
        return 0j
    n = P / d
    eps = d - g
    epsd = (np.conj(n) * V).real
    fn = law_named(law).normal_force(k, c, eps, epsd)
    if fn <= 0:
        return 0j
    t = 1j * n
    if seed_sign:
        sig = -1.0
    else:
        vs = surface_speed + (np.conj(t) * V).real
        sig = vs / math.sqrt(vs * vs + v_reg * v_reg)
    return -fn * n - mu * sig * fn * t


def reference_rhs(
    shaft, speed, *, me=0.0, a_u=None, load=0j, a_l=None, contact=None, a_c=None, zeta=0.0
):
    """Right-hand side of the physical modal system with unbalance, load and contact.

    Returns ``(rhs, rd, rv, n)``: ``rhs(t, x)`` for the complex state ``x`` (length ``n``), and
    the rows giving the complex deflection (m) and velocity (m/s) at the contact station.
    ``contact`` is a dict of :func:`contact_force_reference` keyword arguments.
    """
    L = shaft.length
    a_u = L / 2 if a_u is None else a_u
    a_l = L / 2 if a_l is None else a_l
    a_c = L / 2 if a_c is None else a_c
    A, b_of, row_d, row_v = physical_system(shaft, speed, zeta)
    bu, bl, bc = b_of(a_u), b_of(a_l), b_of(a_c)
    rd, rv = row_d(a_c), row_v(a_c)
    fu0 = me * speed**2

    def rhs(t, x):
        f = A @ x + bu * (fu0 * np.exp(1j * speed * t)) + bl * load
        if contact is not None:
            f = f + bc * contact_force_reference(rd @ x, rv @ x, **contact)
        return f

    return rhs, rd, rv, A.shape[0]


def solve_ivp_reference(shaft, speed, times, *, rtol=1e-11, atol=1e-16, method="DOP853", **forces):
    """Reference response with SciPy ``solve_ivp`` on the physical system.

    The complex state is integrated as its real and imaginary parts (so every SciPy method,
    implicit ones included, can be used). ``forces`` are the keyword arguments of
    :func:`reference_rhs`. Returns the complex deflection (m) at the contact station at
    ``times`` (s).
    """
    rhs, rd, _rv, n = reference_rhs(shaft, speed, **forces)

    def real_rhs(t, xr):
        f = rhs(t, xr[:n] + 1j * xr[n:])
        return np.concatenate([f.real, f.imag])

    sol = scipy.integrate.solve_ivp(
        real_rhs,
        (0, times[-1]),
        np.zeros(2 * n),
        method=method,
        t_eval=times,
        rtol=rtol,
        atol=atol,
    )
    if not sol.success:
        raise RuntimeError(sol.message)
    return rd @ (sol.y[:n] + 1j * sol.y[n:])
