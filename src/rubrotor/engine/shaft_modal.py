"""The rotor's first-order modal system, diagonalised (two-field continuous shaft).

:func:`assemble_modal` builds and diagonalises the modal system of a shaft at one spin speed and
returns a :class:`ModalSystem` (eigenvalues, eigenvectors and the rows that map eigen-coordinates
to deflections and velocities); :func:`phi_functions` are the exponential integrators' ``phi_k``
and :func:`damping_matrix` the viscous damping of given modal damping ratios.
:func:`rubrotor.engine.simulate.assemble` chooses between this form and the seed's
(:mod:`rubrotor.rotors.seed_form`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rubrotor.errors import InputError
from rubrotor.rotors.forces import ModalDamping
from rubrotor.rotors.shaft import Shaft, damping_matrix, modal_matrices

__all__ = ["ModalSystem", "assemble_modal", "damping_matrix", "phi_functions"]


def phi_functions(z: np.ndarray, third: bool = False):
    """``phi1 = (e^z - 1)/z``, ``phi2 = (e^z - 1 - z)/z^2`` (and ``phi3 = (e^z - 1 - z - z^2/2)/z^3``).

    Accurate for small ``|z|`` (Taylor series below 0.25, the recurrence
    ``phi_{k+1} = (phi_k - 1/k!)/z`` above).

    Parameters
    ----------
    z : ndarray, complex
        Arguments (dimensionless).
    third : bool
        Also return ``phi3``.

    Returns
    -------
    phi1, phi2[, phi3] : ndarray, complex

    Examples
    --------
    >>> p1, p2 = phi_functions(np.array([1e-12 + 0j, 1.0 + 0j]))
    >>> bool(np.allclose(p1, [1.0, np.e - 1])), bool(np.allclose(p2, [0.5, np.e - 2]))
    (True, True)
    """
    z = np.asarray(z, dtype=complex)
    small = np.abs(z) < 0.25
    out = [np.empty_like(z) for _ in range(3)]
    zs = z[small]
    # Taylor series: phi_k(z) = sum_j z^j / (j + k)!
    term = np.ones_like(zs)
    acc = [np.zeros_like(zs) for _ in range(3)]
    for j in range(0, 20):
        for k in range(3):
            acc[k] = acc[k] + term / math.factorial(j + k + 1)
        term = term * zs
    zl = z[~small]
    big = [(np.exp(zl) - 1) / zl]
    big.append((big[0] - 1) / zl)
    big.append((big[1] - 0.5) / zl)
    for k in range(3):
        out[k][small] = acc[k]
        out[k][~small] = big[k]
    return (out[0], out[1], out[2]) if third else (out[0], out[1])


def _block_diag(blocks: list[np.ndarray]) -> np.ndarray:
    """Block-diagonal matrix of square blocks (cheaper than scipy's for a few small blocks)."""
    n = sum(b.shape[0] for b in blocks)
    out = np.zeros((n, n), dtype=np.result_type(*blocks))
    o = 0
    for b in blocks:
        k = b.shape[0]
        out[o : o + k, o : o + k] = b
        o += k
    return out


@dataclass
class ModalSystem:
    """The rotor in diagonal (eigen) coordinates of its first-order modal system.

    Physical state ``x = [q_1; q_1'; q_2; q_2'; ...]`` (complex, ``q_n = [P_n, Psi_n]`` or
    ``[P_n]``) is ``x = V y``; ``y' = lam y + beta(a) F`` for a point force ``F`` (N) at ``a``.
    """

    shaft: Shaft
    speed: float
    lam: np.ndarray
    V: np.ndarray
    Vinv: np.ndarray
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    q_index: np.ndarray  # indices of q in x
    qd_index: np.ndarray  # indices of q' in x
    defl_index: np.ndarray  # index in x of the deflection P_n of each mode
    wavenumbers: np.ndarray
    cond: float = field(default=1.0)

    def force_input(self, position: float) -> np.ndarray:
        """``beta`` (eigen-coordinates per N) of a point force at ``position`` (m)."""
        b = np.zeros(self.V.shape[0], complex)
        mdiag = np.diag(self.M)
        for n_i, xi in enumerate(self.defl_index):
            vel = self.qd_index[np.searchsorted(self.q_index, xi)]
            b[vel] = (
                math.sin(self.wavenumbers[n_i] * position)
                / mdiag[np.searchsorted(self.q_index, xi)]
            )
        return self.Vinv @ b

    def displacement_row(self, position: float) -> np.ndarray:
        """Row mapping ``y`` to the complex deflection ``v + i w`` (m) at ``position`` (m)."""
        r = np.zeros(self.V.shape[0], complex)
        for n_i, xi in enumerate(self.defl_index):
            r[xi] = math.sin(self.wavenumbers[n_i] * position)
        return r @ self.V

    def velocity_row(self, position: float) -> np.ndarray:
        """Row mapping ``y`` to the complex velocity (m/s) at ``position`` (m)."""
        r = np.zeros(self.V.shape[0], complex)
        for n_i, xi in enumerate(self.defl_index):
            vel = self.qd_index[np.searchsorted(self.q_index, xi)]
            r[vel] = math.sin(self.wavenumbers[n_i] * position)
        return r @ self.V

    def energy(self, y: np.ndarray) -> float:
        """Kinetic plus strain energy (J) of the physical state ``V y``."""
        x = self.V @ y
        q = x[self.q_index]
        qd = x[self.qd_index]
        return 0.5 * float(np.real(qd.conj() @ self.M @ qd) + np.real(q.conj() @ self.K @ q))


def assemble_modal(shaft: Shaft, speed: float, damping: ModalDamping | None = None) -> ModalSystem:
    """Assemble and diagonalise the two-field first-order modal system at ``speed`` (rad/s).

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    speed : float
        Spin speed ``Omega`` (rad/s).
    damping : ModalDamping, optional
        Modal damping ratios; none by default.

    Returns
    -------
    ModalSystem
    """
    damping = damping or ModalDamping()
    blocks_a, blocks_m, blocks_k, blocks_c = [], [], [], []
    q_idx, qd_idx, defl = [], [], []
    off = 0
    for n in range(1, shaft.modes + 1):
        mm = modal_matrices(shaft, n)
        m = mm.size
        c = damping_matrix(mm.M, mm.K, damping.ratio(n))
        minv = np.linalg.inv(mm.M)
        a = np.zeros((2 * m, 2 * m), complex)
        a[:m, m:] = np.eye(m)
        a[m:, :m] = -minv @ mm.K
        a[m:, m:] = -minv @ (c + speed * mm.G)
        blocks_a.append(a)
        blocks_m.append(mm.M)
        blocks_k.append(mm.K)
        blocks_c.append(c)
        q_idx.extend(range(off, off + m))
        qd_idx.extend(range(off + m, off + 2 * m))
        defl.append(off)
        off += 2 * m
    ns = sum(a.shape[0] for a in blocks_a)
    lam = np.empty(ns, complex)
    V = np.zeros((ns, ns), complex)
    Vinv = np.zeros((ns, ns), complex)
    cond = 1.0
    o = 0
    for a in blocks_a:
        k = a.shape[0]
        lam_b, v = np.linalg.eig(a)
        v = v / np.linalg.norm(v, axis=0)
        vinv = np.linalg.inv(v)
        cond = max(cond, np.abs(v).sum(axis=0).max() * np.abs(vinv).sum(axis=0).max())  # 1-norm
        lam[o : o + k] = lam_b
        V[o : o + k, o : o + k] = v
        Vinv[o : o + k, o : o + k] = vinv
        o += k
    if cond > 1e12:
        raise InputError(
            "speed", speed, "a speed where the modal system is diagonalisable (move it slightly)"
        )
    q_index = np.array(q_idx)
    order = np.argsort(q_index)
    return ModalSystem(
        shaft=shaft,
        speed=speed,
        lam=lam,
        V=V,
        Vinv=Vinv,
        M=_block_diag(blocks_m),
        K=_block_diag(blocks_k),
        C=_block_diag(blocks_c),
        q_index=q_index[order],
        qd_index=np.array(qd_idx)[order],
        defl_index=np.array(defl),
        wavenumbers=np.array([shaft.wavenumber(n) for n in range(1, shaft.modes + 1)]),
        cond=cond,
    )
