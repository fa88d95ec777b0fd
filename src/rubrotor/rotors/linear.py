"""One linear rotor: the object every builder makes and every analysis and engine reads.

Equations
---------
A linear rotor spinning at ``Omega`` (rad/s) obeys, in real physical coordinates ``q``::

    M q'' + (C + C_s(Omega) + Omega G) q' + (K + K_s(Omega)) q = f(t)

* ``M`` (symmetric positive definite), ``K`` (symmetric), ``C`` (structural or modal damping) and
  ``G`` (gyroscopic matrix per unit spin, skew-symmetric) do not depend on speed;
* ``K_s``, ``C_s`` are the supports (bearings, seals): 2x2 stiffness and damping matrices acting on
  the two deflection DOFs of one station (or between two stations: a bearing and its housing),
  possibly tabulated against speed and interpolated linearly (held constant outside the table)
  or, as :class:`Support` options, with ROSS's PCHIP interpolant and linear extrapolation;
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

__all__ = [
    "Basis",
    "NodalBasis",
    "Support",
    "SystemMatrices",
    "LinearSystem",
    "TableExtrapolationWarning",
    "check_table_axes",
]


class TableExtrapolationWarning(UserWarning):
    """An analysis reads a bearing or seal table outside its axis (extrapolated)."""


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
    extra : int
        DOFs after the ``4 N`` nodal ones that carry no shaft deflection (e.g. the ``[v, w]`` of
        point masses that hold bearing housings); ``rows`` gives them zero weight.

    Notes
    -----
    Between nodes ``i`` and ``i+1`` the deflection is the cubic Hermite interpolant of the two
    deflections and two rotations (exact for Euler-Bernoulli elements, the usual display for
    Timoshenko elements). At a node it is the nodal deflection exactly, so forces and probes
    should sit on nodes (the builders put a node at every station).
    """

    nodes: np.ndarray
    extra: int = 0

    @property
    def length(self) -> float:
        return float(self.nodes[-1] - self.nodes[0])

    @property
    def n_dof(self) -> int:
        return 4 * len(self.nodes) + self.extra

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


INTERPOLATIONS = ("linear", "pchip")
EXTRAPOLATIONS = ("hold", "linear")
AXES = ("speed", "frequency")


@dataclass(frozen=True)
class Support:
    """A bearing or seal: 2x2 stiffness, damping and mass between one station and the ground or
    a second station (a housing).

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
    interpolation : str
        Between table speeds: ``"linear"`` (piecewise linear, the default) or ``"pchip"`` (the
        shape-preserving piecewise cubic Hermite interpolant of each coefficient, as ROSS 3.x
        interpolates its tables). Both pass through the table values.
    extrapolation : str
        Outside the table: ``"hold"`` (the end values, the default) or ``"linear"`` (continued
        with the interpolant's end slope, as ROSS 3.x does).
    link : tuple of int, optional
        ``(j_v, j_w)``: the deflections of a second station (e.g. a bearing housing carried by
        a point mass). The support then acts on the relative deflection, its matrices entering
        as ``[[A, -A], [-A, A]]`` on ``dofs + link``. ``None``: to the ground.
    axis : {"speed", "frequency"}
        What ``speeds`` tabulates: the spin speed (``"speed"``, the default; a fluid-film
        bearing, a seal) or the whirl (excitation) frequency (``"frequency"``; a magnetic
        bearing's controller, a squeeze-film damper), as ROSS 3.x's ``speed=`` and
        ``frequency=`` tables. :meth:`coefficients` reads each table on its own axis.
    kind : {"bearing", "seal"}
        A seal carries no static load in API 617's check (ROSS's ``SealElement``).
    exact : bool
        True when the coefficients are exactly linear along the axis (a term whose law is, such as
        a Muszynska fluid ring's cross-coupling ``lambda Omega D_f``): continued linearly beyond
        the table they stay exact, and no extrapolation warning is given.
    law : callable, optional
        ``law(speed) -> (K, C)`` (2x2 each, N/m and N s/m) evaluated exactly at every speed
        asked (rad/s), instead of a table: a nonlinear support (a fluid film) linearised at the
        rotor's static equilibrium at that speed. ``k``, ``c`` are then unused placeholders.
    term : object, optional
        The nonlinear support term this support linearises (None for a linear support).
    """

    dofs: tuple[int, int]
    k: np.ndarray
    c: np.ndarray
    speeds: np.ndarray | None = None
    position: float = 0.0
    name: str = "support"
    interpolation: str = "linear"
    extrapolation: str = "hold"
    link: tuple[int, int] | None = None
    axis: str = "speed"
    exact: bool = False
    kind: str = "bearing"
    law: object = field(default=None, repr=False, compare=False)
    term: object = field(default=None, repr=False, compare=False)
    _pchip: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        if self.interpolation not in INTERPOLATIONS:
            raise InputError(
                f"{self.name}.interpolation", self.interpolation, " or ".join(INTERPOLATIONS)
            )
        if self.extrapolation not in EXTRAPOLATIONS:
            raise InputError(
                f"{self.name}.extrapolation", self.extrapolation, " or ".join(EXTRAPOLATIONS)
            )
        if self.axis not in AXES:
            raise InputError(f"{self.name}.axis", self.axis, " or ".join(AXES))

    @property
    def tabulated(self) -> bool:
        """True when its coefficients vary along its axis (a table of two or more points, or a
        speed law)."""
        return self.law is not None or (self.speeds is not None and len(self.speeds) > 1)

    @property
    def all_dofs(self) -> tuple[int, ...]:
        """The DOFs its matrices act on: ``dofs``, then ``link`` when linked."""
        return tuple(self.dofs) + (tuple(self.link) if self.link is not None else ())

    def block(self, a: np.ndarray) -> np.ndarray:
        """A 2x2 coefficient matrix ``a`` (or a stack ``(..., 2, 2)``) on :attr:`all_dofs`."""
        if self.link is None:
            return a
        return np.concatenate(
            [np.concatenate([a, -a], axis=-1), np.concatenate([-a, a], axis=-1)], axis=-2
        )

    def tabulate(self, speeds) -> tuple[np.ndarray, np.ndarray]:
        """``(K, C)`` of shape ``(S, 2, 2)`` (N/m, N s/m) at each of ``speeds`` (rad/s)."""
        s = np.atleast_1d(np.asarray(speeds, float))
        if self.law is not None:
            pairs = [self.law(float(v)) for v in s]
            return (np.array([np.asarray(k, float) for k, _ in pairs]).reshape(s.size, 2, 2),
                    np.array([np.asarray(c, float) for _, c in pairs]).reshape(s.size, 2, 2))
        if self.speeds is None or len(self.speeds) == 1:
            return (np.broadcast_to(self.k[0], (s.size, 2, 2)).copy(),
                    np.broadcast_to(self.c[0], (s.size, 2, 2)).copy())  # fmt: skip
        return _interpolate(self, "k", s), _interpolate(self, "c", s)

    def coefficients(self, speed: float, frequency: float | None = None):
        """``(K, C)`` 2x2 arrays (N/m, N s/m) at spin ``speed`` and whirl ``frequency``
        (rad/s; default ``speed``: synchronous), each table read on its ``axis``."""
        at = speed if self.axis == "speed" or frequency is None else frequency
        k, c = self.tabulate([at])
        return k[0], c[0]


def _interpolate(sup: Support, name: str, s: np.ndarray) -> np.ndarray:
    """``sup.k`` or ``sup.c`` (``name``; (m, 2, 2)) at speeds ``s`` (rad/s), as ``sup``
    interpolates and extrapolates."""
    table = getattr(sup, name)
    x = np.asarray(sup.speeds, float)
    w = np.clip(s, x[0], x[-1])
    if sup.interpolation == "pchip" and len(x) > 2:
        if name not in sup._pchip:  # SciPy's PCHIP, built once per support and table
            from scipy.interpolate import PchipInterpolator

            f = PchipInterpolator(x, table, axis=0)
            sup._pchip[name] = (f, f.derivative()(x[[0, -1]]))
        f, slopes = sup._pchip[name]
        out = f(w)
    else:
        j = np.clip(np.searchsorted(x, w) - 1, 0, len(x) - 2)
        t = ((w - x[j]) / (x[j + 1] - x[j]))[:, None, None]
        out = (1 - t) * table[j] + t * table[j + 1]
        slopes = np.array([table[1] - table[0], table[-1] - table[-2]])
        slopes /= np.array([x[1] - x[0], x[-1] - x[-2]])[:, None, None]
    if sup.extrapolation == "linear":
        below, above = (s - w)[:, None, None], s > x[-1]
        out = out + below * np.where(above[:, None, None], slopes[1], slopes[0])
    return out


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
    masses : tuple of (float, float, float)
        ``(left m, right m, mass kg)`` of every shaft element (sleeves included) and, with
        ``left == right``, every lumped mass (disks, point masses at their station): what the
        rotor outboard of a bearing weighs (API 617's overhung ``W``, as ROSS computes it).
        Empty when unknown.
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
    masses: tuple = ()
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

    def matrices(self, speed: float = 0.0, frequency: float | None = None) -> SystemMatrices:
        """``M, C, G, K`` on the free DOFs at spin ``speed`` (rad/s), supports included, their
        frequency tables read at the whirl ``frequency`` (rad/s; default ``speed``)."""
        K = self.K.copy()
        C = self.C.copy()
        for s in self.supports:
            ks, cs = s.coefficients(speed, frequency)
            ix = np.ix_(s.all_dofs, s.all_dofs)
            K[ix] += s.block(ks)
            C[ix] += s.block(cs)
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


def check_table_axes(system: LinearSystem, what: str, speed=None, frequency=None) -> None:
    """Warn, as ROSS 3.x does, when ``what`` reads a support's table outside its axis.

    Each tabulated support is checked on its own axis: the spin speeds ``speed`` (rad/s)
    against a table of ``axis == "speed"``, the excitation (whirl) frequencies ``frequency``
    (rad/s) against a table of ``axis == "frequency"``. The warning
    (:class:`TableExtrapolationWarning`) names the element, the axis, its range and the values
    asked. Tables that extrapolate linearly (ROSS's way, ``extrapolation = "linear"``) are
    checked; tables held at their end values (rubrotor's default) are not.

    Parameters
    ----------
    system : LinearSystem
    what : str
        The analysis, for the message.
    speed, frequency : float or array_like, optional
        Values read on each axis (rad/s); ``None``: that axis is not checked.
    """
    import warnings

    asked = {"speed": speed, "frequency": frequency}
    for sup in system.supports:
        values = asked.get(sup.axis)
        if (values is None or not sup.tabulated or sup.law is not None
                or sup.extrapolation == "hold" or sup.exact):
            continue
        v = np.atleast_1d(np.asarray(values, float))
        lo, hi = float(sup.speeds[0]), float(sup.speeds[-1])
        if v.size and (v.min() < lo or v.max() > hi):
            how = "extrapolated linearly from the end slope"
            warnings.warn(
                f"{what}: the coefficients of {sup.name!r} are read outside its {sup.axis} axis "
                f"({lo:.4g} to {hi:.4g} rad/s; asked {v.min():.4g} to {v.max():.4g} rad/s) and "
                f"{how}",
                TableExtrapolationWarning,
                stacklevel=3,
            )
