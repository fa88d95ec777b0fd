"""Which roots of a linear rotor are modes, and which way a mode whirls: the conventions every
linear analysis of :mod:`rubrotor.linear` shares, and the checks of its speed arguments.

Conventions
-----------
The state ``x = [q, q']`` obeys ``x' = A(Omega) x`` (see :meth:`rubrotor.rotors.linear.SystemMatrices.first_order`).
An eigenvalue ``lambda = -zeta omega_n + i omega_d`` with ``omega_d > 0`` is one physical mode:

* frequency ``f = omega_d / (2 pi)`` (Hz, the damped natural frequency);
* damping ratio ``zeta = -Re(lambda) / |lambda|`` (negative when the mode grows);
* logarithmic decrement ``delta = -2 pi Re(lambda) / Im(lambda)``.

Overdamped (real) eigenvalues are not modes and are left out. Eigenvalues come in conjugate
pairs; only the ``Im > 0`` member is kept, so at zero speed an isotropic rotor's two equal
frequencies (one per plane) are two modes, and stay two modes as the speed splits them.

Whirl: a mode shape gives at each station the complex deflections ``V``, ``W``; the orbit
``v + i w`` turns from ``+v`` towards ``+w`` (forward, the spin direction) when
``Im(conj(V) W) < 0``. A mode is ``"forward"`` or ``"backward"`` when every station with a
significant, non-flat orbit turns that way, ``"mixed"`` otherwise (anisotropic supports). Within a
cluster of equal eigenvalues (isotropic rotor at rest) the shapes are first rotated into the
combinations of extreme whirl (the eigenvectors of the 2x2 Hermitian "whirl" form), so that the
pair is reported as one forward and one backward circular mode, as the limit of a slowly spinning
rotor.
"""

from __future__ import annotations

import math

import numpy as np

from rubrotor.errors import InputError
from rubrotor.rotors.linear import LinearSystem, NodalBasis

__all__ = ["OSCILLATING", "OVERDAMPED", "TWO_PI"]

TWO_PI = 2 * math.pi


OSCILLATING = 1e-4
"""A root is complex (a mode that oscillates) when ``Im(lam) > OSCILLATING |lam|`` (damping ratio
below ``1 - 5e-9``), else real.

A critically damped pair of real eigenvalues (heavily damped bearings make them) splits under
rounding into a complex pair with ``Im(lam) ~ sqrt(eps cond) |lam|`` (about ``1e-6 |lam|`` on
the shipped general rotor): without a margin such a pair would appear, or not, as a spurious
zero-frequency mode and shift the numbering of the others."""


OVERDAMPED = 1e-2
"""A mode is marked overdamped when ``Im(lam) <= OVERDAMPED |lam|``: real roots, and complex
ones with damping ratio ``zeta >= 0.99995`` (log dec >= 628: one would-be period shrinks the
motion by ``e^-628``, so nothing oscillates). Heavy element damping makes such roots (ROSS's
``rotor_example_amb_simple`` at 300 rad/s: ``|lam|`` near 1e4 rad/s with ``Im(lam)`` 1-5 rad/s);
ranked by frequency they would come first, ranked by ``|lam|`` they fall where they belong."""


def _check_speed(name: str, speed) -> float:
    if isinstance(speed, bool) or not isinstance(speed, int | float | np.integer | np.floating):
        raise InputError(name, speed, "a spin speed (rad/s)")
    if not (math.isfinite(speed) and speed >= 0):
        raise InputError(name, speed, "a finite spin speed >= 0 (rad/s)")
    return float(speed)


def _speed_array(name: str, speeds) -> np.ndarray:
    s = np.asarray(speeds, dtype=float)
    if s.ndim != 1 or s.size < 2 or not np.all(np.isfinite(s)) or np.any(s < 0):
        raise InputError(name, speeds, "at least 2 finite spin speeds >= 0 (rad/s)")
    if np.any(np.diff(s) <= 0):
        raise InputError(name, speeds, "increasing spin speeds (rad/s)")
    return s


def _stations(system: LinearSystem) -> np.ndarray:
    """``(2 S, n_full)`` rows giving ``V``, ``W`` at the stations whirl is judged at."""
    basis = system.basis
    if isinstance(basis, NodalBasis):  # at a node: the node's v and w DOFs
        count = len(basis.nodes)
        rows = np.zeros((2 * count, basis.n_dof))
        rows[np.arange(2 * count), 4 * np.repeat(np.arange(count), 2) + np.tile([0, 1], count)] = 1
        return rows
    xs = np.linspace(0.0, basis.length, 23)[1:-1]
    return np.vstack([basis.rows(float(x)) for x in xs])


def _circularise(rows: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """Rotate a cluster of equal-eigenvalue shapes into the combinations of extreme whirl."""
    d = rows @ shapes
    v, w = d[0::2], d[1::2]
    h = (np.conj(v).T @ w - np.conj(w).T @ v) / 2j  # Hermitian whirl form
    _, u = np.linalg.eigh(h)
    return shapes @ u


def _select(lam: np.ndarray, n: int | None, natural: bool) -> np.ndarray:
    """Indices of the modes among the roots ``lam``, in their order.

    By frequency: the roots with ``Im > OSCILLATING |lam|``, by ``Im``, the first ``n``. By
    natural frequency (``natural``): the roots with ``Im > OVERDAMPED |lam|`` by ``|lam|``, the
    first ``n``; then, marked overdamped by the caller, the real roots (``|Im| <= OSCILLATING
    |lam|``, each once) and the nearly real ones, by ``|lam|``, those up to the last mode's
    ``|lam|`` (all when ``n`` is None)."""
    a = np.abs(lam)
    if not natural:
        idx = np.flatnonzero(lam.imag > OSCILLATING * a)
        return idx[np.argsort(lam.imag[idx], kind="stable")][:n]
    osc = np.flatnonzero(lam.imag > OVERDAMPED * a)
    osc = osc[np.argsort(a[osc], kind="stable")][:n]
    over = np.flatnonzero((lam.imag > -OSCILLATING * a) & (lam.imag <= OVERDAMPED * a))
    if n is not None:
        over = over[a[over] <= (a[osc].max() if osc.size else np.inf)]
    return np.concatenate([osc, over[np.argsort(a[over], kind="stable")]])


def _real_made_real(lam: np.ndarray) -> np.ndarray:
    """Roots with ``|Im| <= OSCILLATING |lam|`` as exactly real numbers (a rounding split)."""
    return np.where(np.abs(lam.imag) <= OSCILLATING * np.abs(lam), lam.real + 0j, lam)


def _clusters(lam: np.ndarray):
    """``(speed index, first, end)`` of each run of equal eigenvalues (within 1e-7) at a speed."""
    close = np.abs(np.diff(lam, axis=1)) <= 1e-7 * np.abs(lam[:, 1:])
    for i in np.flatnonzero(close.any(axis=1)):
        j = 0
        while j < lam.shape[1]:
            k = j + 1
            while k < lam.shape[1] and close[i, k - 1]:
                k += 1
            if k - j > 1:
                yield i, j, k
            j = k


def _whirl_labels(shapes: np.ndarray) -> np.ndarray:
    """The whirl of every shape at once (see the module docstring): ``shapes`` (..., 2 stations)
    holds ``V, W`` pairs. A station counts when its orbit is significant (``|V|^2 + |W|^2`` above
    1e-4 of the largest) and not flat (``|Im(conj(V) W)|`` above 1e-6 of it); ``"forward"`` or
    ``"backward"`` when all such stations turn that way, ``"mixed"`` otherwise or when none
    counts."""
    v, w = shapes[..., 0::2], shapes[..., 1::2]
    spin = np.imag(np.conj(v) * w)
    amp = np.abs(v) ** 2 + np.abs(w) ** 2
    big = amp > 1e-4 * amp.max(axis=-1, keepdims=True)
    turning = big & (np.abs(spin) > 1e-6 * amp)
    fwd = np.all(~turning | (spin < 0), axis=-1)
    bwd = np.all(~turning | (spin > 0), axis=-1)
    out = np.full(shapes.shape[:-1], "mixed", dtype=object)
    any_turn = turning.any(axis=-1)
    out[any_turn & fwd] = "forward"
    out[any_turn & bwd] = "backward"
    return out
