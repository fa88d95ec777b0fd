"""The seed's continuous shaft (rubrotor.rotors.shaft.Shaft) as a real :class:`rubrotor.rotors.linear.LinearSystem`.

The shaft's exact modal equations (one block per mode) on real DOFs, with its modal damping as a
viscous matrix, so the general engine and the linear analyses run the continuous shaft like any
other rotor.
"""

import numpy as np

__all__ = ["SineBasis", "continuous_system"]


class SineBasis:
    """Deflection of the continuous pinned-pinned shaft: ``sum_n sin(k_n x) [v_n, w_n]``."""

    def __init__(self, shaft, dofs_per_mode):
        self.length = shaft.length
        self.k = np.array([shaft.wavenumber(n) for n in range(1, shaft.modes + 1)])
        self.per = dofs_per_mode

    def rows(self, position: float) -> np.ndarray:
        """``(2, n_dof)`` rows giving ``[v, w]`` (m) at ``position`` (m)."""
        r = np.zeros((2, 2 * self.per * len(self.k)))
        for i, k in enumerate(self.k):
            o = 2 * self.per * i
            r[0, o] = r[1, o + 1] = np.sin(k * position)
        return r


def continuous_system(shaft, damping=None):
    """The seed's continuous shaft as a real LinearSystem (per mode ``[v, w, psi_v, psi_w]``).

    The complex modal matrices of :func:`rubrotor.rotors.shaft.modal_matrices` act on ``P = v + i w``;
    the real parts of ``M``, ``K`` act on each plane and ``-i g`` on ``Psi'`` becomes
    ``g [[0, 1], [-1, 0]]`` on ``[psi_v', psi_w']`` (the convention of rubrotor.rotors.linear).

    Parameters
    ----------
    shaft : rubrotor.rotors.shaft.Shaft
        The continuous shaft.
    damping : rubrotor.rotors.forces.ModalDamping, optional
        Modal damping ratios: each mode's block gets the viscous matrix
        :func:`rubrotor.rotors.shaft.damping_matrix` (N s/m) on both planes, the damping
        the shaft's own engine applies. None: undamped.
    """
    from rubrotor.rotors.linear import LinearSystem
    from rubrotor.rotors.shaft import damping_matrix, modal_matrices

    blocks = [modal_matrices(shaft, n) for n in range(1, shaft.modes + 1)]
    per = blocks[0].M.shape[0]
    n = 2 * per * len(blocks)
    M, K, G, C = (np.zeros((n, n)) for _ in range(4))
    for i, b in enumerate(blocks):
        zeta = damping.ratio(i + 1) if damping is not None else 0.0
        c_block = damping_matrix(b.M, b.K, zeta).real
        for a in range(per):
            for c in range(per):
                for plane in range(2):
                    r, s = 2 * per * i + 2 * a + plane, 2 * per * i + 2 * c + plane
                    M[r, s] = b.M[a, c].real
                    K[r, s] = b.K[a, c].real
                    C[r, s] = c_block[a, c]
                g = -b.G[a, c].imag  # G = -i g
                r, s = 2 * per * i + 2 * a, 2 * per * i + 2 * c
                G[r, s + 1] += g
                G[r + 1, s] -= g
    return LinearSystem(M, K, C, G, SineBasis(shaft, per), name="continuous")
