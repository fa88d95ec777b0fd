"""One linear rotor: the object every builder makes and every analysis and engine reads.

Equations
---------
A linear rotor spinning at ``Omega`` (rad/s) obeys, in real physical coordinates ``q``::

    M q'' + (C + C_s(Omega) + Omega G) q' + (K + K_s(Omega)) q = f(t)

* ``M`` (symmetric positive definite), ``K`` (symmetric), ``C`` (structural or modal damping) and
  ``G`` (gyroscopic matrix per unit spin, skew-symmetric) do not depend on speed;
* ``K_s``, ``C_s`` are the supports (bearings, seals): 2x2 stiffness and damping matrices acting on
  the two deflection DOFs of one station, possibly tabulated against speed and interpolated
  linearly (held constant outside the table);
* ``fixed`` DOFs are exact constraints (``pinned`` supports): they are removed, not penalised.

Conventions (shared by every builder; the continuous shaft and ROSS import map onto them)
------------------------------------------------------------------------------------------
* Axis ``x`` along the rotor (m from its left end); deflections ``v`` (along ``y``) and ``w``
  (along ``z``), m. Spin runs from ``+y`` towards ``+z``, so whirl from ``+v`` towards ``+w``
  is forward whirl (as in the continuous model).
* A finite-element rotor has four DOFs per node, in the order ``[v, w, psi_v, psi_w]``: the two
  deflections (m) and the two section rotations (rad) that equal the slopes ``dv/dx`` and
  ``dw/dx`` in the Euler-Bernoulli limit. Both bending planes then have identical element
  matrices, and the gyroscopic moment of a spinning section with polar inertia ``Ip`` couples
  the rotations as ``Omega Ip [[0, 1], [-1, 0]]`` acting on ``[psi_v', psi_w']`` (the real form of
  the continuous model's ``-i Omega rho Ip Psi'``).
* A point force ``(F_y, F_z)`` (N) at position ``x`` enters as ``f = B(x) [F_y, F_z]`` and the
  deflection at ``x`` is ``[v, w] = B(x)^T q``: one interpolation row pair serves both.

This module only holds and evaluates matrices; it never simulates or plots.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from rubrotor.errors import InputError

__all__ = ["Basis", "NodalBasis", "Support", "SystemMatrices", "LinearSystem"]


class Basis(Protocol):
    """How the DOFs ``q`` map to the deflection at any axial position."""

    length: float  # m

    def rows(self, position: float) -> np.ndarray:
        """``(2, n_dof)`` real array mapping full ``q`` to ``[v, w]`` (m) at ``position`` (m)."""
        ...


@dataclass(frozen=True)
class NodalBasis:
    """Deflection of a finite-element rotor between its nodes (cubic Hermite interpolation).

    Parameters
    ----------
    nodes : ndarray, shape (N,)
        Node positions (m), strictly increasing, 4 DOFs ``[v, w, psi_v, psi_w]`` per node.

    Notes
    -----
    Between nodes ``i`` and ``i+1`` the deflection is the cubic Hermite interpolant of the two
    deflections and two rotations (exact for Euler-Bernoulli elements, the usual display for
    Timoshenko elements). At a node it is the nodal deflection exactly, so forces and probes
    should sit on nodes (the builders put a node at every station).
    """

    nodes: np.ndarray

    @property
    def length(self) -> float:
        return float(self.nodes[-1] - self.nodes[0])

    @property
    def n_dof(self) -> int:
        return 4 * len(self.nodes)

    def node_at(self, position: float, tol: float = 1e-9) -> int | None:
        """Index of the node at ``position`` (m) within ``tol`` (m), else ``None``."""
        i = int(np.argmin(np.abs(self.nodes - position)))
        return i if abs(self.nodes[i] - position) <= tol else None

    def rows(self, position: float) -> np.ndarray:
        x = float(position)
        if not (self.nodes[0] - 1e-12 <= x <= self.nodes[-1] + 1e-12):
            raise InputError(
                "position",
                position,
                f"a position on the rotor, {self.nodes[0]:g} to {self.nodes[-1]:g} (m)",
            )
        r = np.zeros((2, self.n_dof))
        i = self.node_at(x)
        if i is not None:
            r[0, 4 * i] = 1.0
            r[1, 4 * i + 1] = 1.0
            return r
        e = int(np.searchsorted(self.nodes, x)) - 1
        h = self.nodes[e + 1] - self.nodes[e]
        s = (x - self.nodes[e]) / h
        n1, n2 = 1 - 3 * s**2 + 2 * s**3, h * (s - 2 * s**2 + s**3)
        n3, n4 = 3 * s**2 - 2 * s**3, h * (-(s**2) + s**3)
        for plane in (0, 1):
            r[plane, 4 * e + plane] = n1
            r[plane, 4 * e + 2 + plane] = n2
            r[plane, 4 * (e + 1) + plane] = n3
            r[plane, 4 * (e + 1) + 2 + plane] = n4
        return r


@dataclass(frozen=True)
class Support:
    """A bearing or seal: 2x2 stiffness and damping on the deflection DOFs of one station.

    Parameters
    ----------
    dofs : tuple of int
        Indices ``(i_v, i_w)`` in the full ``q`` of the two deflections it acts on.
    k : ndarray, shape (m, 2, 2)
        Stiffness ``[[kyy, kyz], [kzy, kzz]]`` (N/m) at each tabulated speed.
    c : ndarray, shape (m, 2, 2)
        Damping ``[[cyy, cyz], [czy, czz]]`` (N s/m) at each tabulated speed.
    speeds : ndarray, shape (m,), optional
        Tabulation speeds (rad/s), increasing; ``None`` (or length 1) for constant coefficients.
    position : float
        Axial position (m), for labels and plots.
    name : str
        Label (e.g. ``"bearing 1"``).
    """

    dofs: tuple[int, int]
    k: np.ndarray
    c: np.ndarray
    speeds: np.ndarray | None = None
    position: float = 0.0
    name: str = "support"

    def coefficients(self, speed: float) -> tuple[np.ndarray, np.ndarray]:
        """``(K, C)`` 2x2 arrays (N/m, N s/m) at ``speed`` (rad/s), interpolated linearly."""
        if self.speeds is None or len(self.speeds) == 1:
            return self.k[0], self.c[0]
        w = float(np.clip(speed, self.speeds[0], self.speeds[-1]))
        j = int(np.clip(np.searchsorted(self.speeds, w) - 1, 0, len(self.speeds) - 2))
        t = (w - self.speeds[j]) / (self.speeds[j + 1] - self.speeds[j])
        return (1 - t) * self.k[j] + t * self.k[j + 1], (1 - t) * self.c[j] + t * self.c[j + 1]


@dataclass(frozen=True)
class SystemMatrices:
    """The matrices at one speed, on the free DOFs: ``M q'' + (C + speed G) q' + K q = f``."""

    speed: float  # rad/s
    M: np.ndarray
    C: np.ndarray
    G: np.ndarray
    K: np.ndarray

    @property
    def damping(self) -> np.ndarray:
        """``C + speed G`` (N s/m): everything multiplying ``q'``."""
        return self.C + self.speed * self.G

    def first_order(self) -> tuple[np.ndarray, np.ndarray]:
        """``(A, Binv)``: state ``x = [q, q']``, ``x' = A x + [0; M^-1 f]``; ``Binv = M^-1``."""
        n = self.M.shape[0]
        minv = np.linalg.inv(self.M)
        a = np.zeros((2 * n, 2 * n))
        a[:n, n:] = np.eye(n)
        a[n:, :n] = -minv @ self.K
        a[n:, n:] = -minv @ self.damping
        return a, minv


@dataclass(frozen=True)
class LinearSystem:
    """A linear rotor in real physical coordinates (see the module docstring).

    Parameters
    ----------
    M, K, C, G : ndarray, shape (n, n)
        Mass (kg, kg m^2), stiffness (N/m, N m/rad), speed-independent damping (N s/m) and
        gyroscopic matrix per unit spin (kg m^2, skew), on all ``n`` DOFs.
    basis : Basis
        Maps ``q`` to the deflection at any position.
    supports : tuple of Support
        Bearings and seals (their coefficients are not in ``K``, ``C``).
    fixed : tuple of int
        Constrained DOFs (removed).
    dof_labels : tuple of str
        One label per DOF (e.g. ``"v@0.125"``), for tables and errors.
    name : str
        Where it came from (``"fe"``, ``"continuous"``, ``"ross"``).
    scales : tuple
        Its inputs ranked by their distance (decades) from its own scale, ``(decades, key,
        value, scale)`` (:func:`rubrotor.rotors.scales.rotor_scales`; empty when unknown), so
        that a failed eigenproblem names the scenario key that likely caused it.
    """

    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    G: np.ndarray
    basis: Basis
    supports: tuple[Support, ...] = ()
    fixed: tuple[int, ...] = ()
    dof_labels: tuple[str, ...] = ()
    name: str = "linear"
    scales: tuple = ()
    free: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        n = self.M.shape[0]
        for nm in ("K", "C", "G"):
            if getattr(self, nm).shape != (n, n):
                raise InputError(nm, getattr(self, nm).shape, f"shape ({n}, {n}) like M")
        mask = np.ones(n, bool)
        mask[list(self.fixed)] = False
        object.__setattr__(self, "free", np.flatnonzero(mask))

    @property
    def n_dof(self) -> int:
        """Number of free DOFs."""
        return len(self.free)

    def matrices(self, speed: float = 0.0) -> SystemMatrices:
        """``M, C, G, K`` on the free DOFs at ``speed`` (rad/s), supports included."""
        K = self.K.copy()
        C = self.C.copy()
        for s in self.supports:
            ks, cs = s.coefficients(speed)
            ix = np.ix_(s.dofs, s.dofs)
            K[ix] += ks
            C[ix] += cs
        f = np.ix_(self.free, self.free)
        return SystemMatrices(float(speed), self.M[f], C[f], self.G[f], K[f])

    def force_map(self, position: float) -> np.ndarray:
        """``(n_free, 2)``: a point force ``[F_y, F_z]`` (N) at ``position`` (m) as ``f``."""
        return self.basis.rows(position)[:, self.free].T

    def output_rows(self, position: float) -> np.ndarray:
        """``(2, n_free)``: free ``q`` to ``[v, w]`` (m) at ``position`` (m)."""
        return self.basis.rows(position)[:, self.free]

    def expand(self, q_free: np.ndarray) -> np.ndarray:
        """Full ``q`` (fixed DOFs zero) from free ``q``; works along the first axis."""
        q_free = np.asarray(q_free)
        out = np.zeros((len(self.M),) + q_free.shape[1:], q_free.dtype)
        out[self.free] = q_free
        return out
