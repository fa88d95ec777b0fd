"""Mode shapes along the rotor: each damped mode's whirl orbit at every node, and its direction.

A mode ``lambda`` with shape ``(V(x), W(x))`` (complex, m per unit modal amplitude) moves each
station on the ellipse ``v = Re(V e^{i theta})``, ``w = Re(W e^{i theta})``,
``theta = omega_d t``. The orbit turns forward (from ``+y`` towards ``+z``, with the spin)
where ``Im(conj(V) W) < 0`` and backward where it is ``> 0``
(as ``rubrotor.linear.roots`` labels modes); a station whose orbit is flat (a line) or negligible
(below 1e-4 of the largest) has no direction. The semi-axes are
``(|V + i W| +- |V - i W|) / 2``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubrotor.linear.modes import DampedModes, damped_modes
from rubrotor.rotors.linear import LinearSystem

__all__ = ["ModeShapes", "mode_shapes", "node_whirl"]


def node_whirl(v: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Whirl direction of each station's orbit: ``"forward"``, ``"backward"`` or ``"none"``.

    Parameters
    ----------
    v, w : ndarray, complex
        Complex deflections ``V``, ``W`` (m) at the stations.

    Returns
    -------
    ndarray of str
    """
    spin = np.imag(np.conj(v) * w)
    amp = np.abs(v) ** 2 + np.abs(w) ** 2
    counts = (amp > 1e-8 * amp.max(initial=0.0)) & (np.abs(spin) > 1e-6 * amp)
    out = np.full(v.shape, "none", dtype=object)
    out[counts & (spin < 0)] = "forward"
    out[counts & (spin > 0)] = "backward"
    return out


@dataclass(frozen=True)
class ModeShapes:
    """Damped modes at one speed with their complex shapes at the stations.

    Attributes
    ----------
    modes : DampedModes
        Frequencies (Hz), damping and whirl of the modes.
    x : ndarray, shape (X,)
        Stations (m): the nodes of a finite-element rotor, a grid on a continuous shaft.
    v, w : ndarray, shape (n, X), complex
        ``V``, ``W`` of each mode at each station (normalised: largest deflection 1).
    """

    modes: DampedModes
    x: np.ndarray
    v: np.ndarray
    w: np.ndarray

    @property
    def major(self) -> np.ndarray:
        """Major semi-axis of each orbit (normalised units), shape (n, X)."""
        return 0.5 * (np.abs(self.v + 1j * self.w) + np.abs(self.v - 1j * self.w))

    @property
    def minor(self) -> np.ndarray:
        """Signed minor semi-axis (normalised; ``> 0`` forward, ``< 0`` backward), (n, X)."""
        return 0.5 * (np.abs(self.v + 1j * self.w) - np.abs(self.v - 1j * self.w))

    def to_dict(self) -> dict:
        """JSON form printed by ``rubrotor shapes --json``."""
        out = []
        for k, m in enumerate(self.modes.modes):
            out.append(
                {
                    "index": m.index,
                    "frequency_hz": m.frequency_hz,
                    "damping_ratio": m.damping_ratio,
                    "log_dec": m.log_dec,
                    "whirl": m.whirl,
                    "v_real": self.v[k].real.tolist(),
                    "v_imag": self.v[k].imag.tolist(),
                    "w_real": self.w[k].real.tolist(),
                    "w_imag": self.w[k].imag.tolist(),
                    "major": self.major[k].tolist(),
                    "minor": self.minor[k].tolist(),
                    "node_whirl": list(node_whirl(self.v[k], self.w[k])),
                }
            )
        return {"speed_rad_s": self.modes.speed_rad_s, "x_m": self.x.tolist(), "modes": out}


def mode_shapes(system: LinearSystem, speed: float = 0.0, n: int = 4) -> ModeShapes:
    """The ``n`` lowest damped modes at ``speed`` and their shapes at the stations.

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    speed : float
        Spin speed (rad/s), ``>= 0``.
    n : int
        Number of modes.

    Returns
    -------
    ModeShapes
    """
    modes = damped_modes(system, speed, n=n)
    nodes = getattr(system.basis, "nodes", None)
    x = np.asarray(nodes, float) if nodes is not None else np.linspace(0, system.basis.length, 41)
    rows = np.stack([system.basis.rows(float(xi)) for xi in x])  # (X, 2, n_full)
    shapes = np.array([m.shape for m in modes.modes]).T  # (n_full, n)
    d = np.einsum("xpq,qn->npx", rows, shapes)
    return ModeShapes(modes, x, d[:, 0], d[:, 1])
