"""The finite plain journal bearing with oil-feed grooves (``[[bearing]] type = "finite_journal"``).

Reynolds' equation of an isothermal, incompressible film over the whole bearing (no short-film
approximation), in the bearing's own frame: the journal's centre at ``(y, z)`` (m) from the
bearing's centre moves at ``(vy, vz)`` (m/s) and spins at ``omega`` (rad/s, from ``y`` towards
``z``). With ``theta`` from ``+y`` towards ``+z``, the film thickness is ``h = c H``,
``H = 1 - (y cos(theta) + z sin(theta)) / c``, ``Z = x / L`` in ``[-1/2, 1/2]`` and the pressure
``p = 6 mu (R / c)^2 P`` (``P`` in 1/s):

    d/dtheta (H^3 dP/dtheta) + (R / L)^2 d/dZ (H^3 dP/dZ) = omega dH/dtheta + 2 dH/dt,
    dH/dt = -(vy cos(theta) + vz sin(theta)) / c,

``P = 0`` at both ends (ambient), periodic in ``theta``. An axial oil-feed groove at the angle
``theta_g`` (rad, in the bearing's frame) holds the supply pressure ``p_s`` (Pa) along the whole
length at the grid line nearest to it (a groove one cell wide). Discretised by conservative
central differences on ``n_theta`` lines (``theta_i = 2 pi i / n_theta``, so that a groove at a
multiple of ``2 pi / n_theta`` sits on a line) and ``n_z`` cells over the length, solved with a
sparse LU factorisation; the Reynolds (Swift-Stieber) condition ``P >= 0`` by the primal-dual
active set of :mod:`rubrotor.forces.reynolds`. The force on the journal is
``F = -R L int int p (cos, sin) dtheta dZ`` (trapezoidal in ``theta``, midpoint in ``Z``).

Raimondi and Boyd (1958) feed the full bearing at its thickest film with ``p = 0`` there: one
groove at the thickest film with ``supply_pressure = 0`` reproduces their boundary condition.

Linearised coefficients (``K = -dF/dq``, ``C = -dF/dq'``) are central differences of this
force (steps ``1e-6 c`` and ``1e-6 c omega``); one force costs one sparse solve per active-set
iteration, and a bearing starts each solve from its previous free set (one or two solves for a
nearby position, as in a Newton step or a difference quotient).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from rubrotor.errors import InputError
from rubrotor.forces.fluid_film import JournalEquilibrium, _newton
from rubrotor.forces.reynolds import _active_set
from rubrotor.rotors.linear import Support

__all__ = ["FiniteJournal", "finite_force", "FINITE_CAVITATION", "L_OVER_D_RANGE"]

FINITE_CAVITATION = ("reynolds", "half_sommerfeld", "full_film")
"""Cavitation models of the finite film (see :mod:`rubrotor.forces.reynolds`)."""

L_OVER_D_RANGE = (1.0 / 16.0, 4.0)
"""Length over diameter the default grid resolves (1): below, use ``short_journal``."""


def _grid_operator(x, y, n_theta, n_z, r_over_l, grooves):
    """The discrete operator (sparse) on ``n_theta x n_z`` unknowns, the film ``H`` at the lines
    and faces, and the groove lines (indices)."""
    dth = 2.0 * math.pi / n_theta
    dz = 1.0 / n_z
    th = np.arange(n_theta) * dth
    hf = 1.0 - x * np.cos(th + 0.5 * dth) - y * np.sin(th + 0.5 * dth)  # face i + 1/2
    hc = 1.0 - x * np.cos(th) - y * np.sin(th)
    n = n_theta * n_z
    idx = np.arange(n).reshape(n_theta, n_z)
    ax = np.repeat(hf**3 / dth**2, n_z).reshape(n_theta, n_z)  # to i + 1
    axm = np.roll(ax, 1, axis=0)  # to i - 1
    az = np.repeat(r_over_l**2 * hc**3 / dz**2, n_z).reshape(n_theta, n_z)
    diag = -(ax + axm) - 2.0 * az
    diag[:, 0] -= az[:, 0]  # the end faces lie half a cell from P = 0
    diag[:, -1] -= az[:, -1]
    rows = [idx.ravel(), idx.ravel(), idx[:, 1:].ravel(), idx[:, :-1].ravel(), idx.ravel()]
    cols = [np.roll(idx, -1, axis=0).ravel(), np.roll(idx, 1, axis=0).ravel(),
            idx[:, :-1].ravel(), idx[:, 1:].ravel(), idx.ravel()]  # fmt: skip
    vals = [ax.ravel(), axm.ravel(), az[:, 1:].ravel(), az[:, :-1].ravel(), diag.ravel()]
    r, c, v = np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
    lines = sorted({int(round(g / dth)) % n_theta for g in grooves})
    if lines:
        fixed = np.zeros(n, bool)
        fixed[idx[lines].ravel()] = True
        keep = ~fixed[r]
        r, c, v = r[keep], c[keep], v[keep]
        dof = np.flatnonzero(fixed)
        r, c, v = np.r_[r, dof], np.r_[c, dof], np.r_[v, -np.ones(dof.size)]  # -P = -P_s
    a = sp.csc_matrix((v, (r, c)), shape=(n, n))
    return a, th, hf, lines


def _active_set_from(a, b, free, max_iter=100):
    """``a p = b`` subject to ``p >= 0`` (``a`` the negative of an M-matrix) by the primal-dual
    active set of :mod:`rubrotor.forces.reynolds`, started from the free set ``free`` (a
    previous solution's): the solution is unique, and from a nearby start it takes one or two
    solves. Returns ``(p, solves, free)``; ``None`` if the set does not settle."""
    n = b.size
    for it in range(1, max_iter + 1):
        p = np.zeros(n)
        if free.any():
            p[free] = splu(a[free][:, free].tocsc()).solve(b[free])
        lam = -(a @ p - b)
        new_free = np.where(free, p > 0.0, lam < 0.0)
        if np.array_equal(new_free, free):
            return np.maximum(p, 0.0), it, free
        free = new_free
    return None


def finite_force(y, z, vy, vz, omega, radius, length, clearance, viscosity, *,
                 cavitation="reynolds", grooves=(), supply_pressure=0.0, n_theta=72,
                 n_z=16, memo=None):  # fmt: skip
    """Force of the finite film on the journal (N), y and z, and the sparse solves it took.

    Parameters
    ----------
    y, z : float
        Journal centre relative to the bearing centre (m), inside the clearance.
    vy, vz : float
        Its velocity (m/s).
    omega : float
        Journal spin (rad/s).
    radius, length, clearance : float
        ``R``, ``L``, ``c`` (m).
    viscosity : float
        ``mu`` (Pa s).
    cavitation : {"reynolds", "half_sommerfeld", "full_film"}
        Cavitation model (module docstring of :mod:`rubrotor.forces.reynolds`).
    grooves : sequence of float
        Axial groove angles (rad, bearing frame, from ``y`` towards ``z``).
    supply_pressure : float
        Pressure held in the grooves (Pa), >= 0.
    n_theta, n_z : int
        Grid lines around the circumference and cells over the length.
    memo : dict, optional
        Keeps the last free set of the Reynolds condition per grid, to start the next solve
        from (the solution does not depend on the start).

    Returns
    -------
    force : ndarray, shape (2,)
        N, along y and z.
    solves : int
        Sparse solves used (1 without the Reynolds condition).
    """
    x, w = y / clearance, z / clearance
    if not math.hypot(x, w) < 1.0:
        return np.full(2, np.nan), 0
    a, th, hf, lines = _grid_operator(x, w, n_theta, n_z, radius / length, grooves)
    dth = 2.0 * math.pi / n_theta
    dhdt = -(vy * np.cos(th) + vz * np.sin(th)) / clearance
    rhs = omega * (hf - np.roll(hf, 1)) / dth + 2.0 * dhdt
    b = np.repeat(rhs, n_z).reshape(n_theta, n_z)
    scale = 6.0 * viscosity * (radius / clearance) ** 2
    if lines:
        b[lines, :] = -supply_pressure / scale
    b = b.ravel()
    if cavitation == "reynolds":
        key = (n_theta, n_z, tuple(lines))
        start = memo.get(key) if memo is not None else None
        done = _active_set_from(a, b, start) if start is not None else None
        if done is None:
            p, solves = _active_set(a, b)
            free = p > 0.0
        else:
            p, solves, free = done
        if memo is not None:
            memo[key] = free
    else:
        p, solves = splu(a).solve(b), 1
        if cavitation == "half_sommerfeld":
            p = np.maximum(p, 0.0)
    mean = p.reshape(n_theta, n_z).sum(axis=1) * (dth / n_z)
    f = -scale * radius * length * np.array([mean @ np.cos(th), mean @ np.sin(th)])
    return f, solves


def _number(field, value, unit, lo=0.0, strict=True):
    ok = not isinstance(value, bool) and isinstance(value, int | float | np.integer | np.floating)
    x = float(value) if ok else math.nan
    if not (math.isfinite(x) and (x > lo if strict else x >= lo)):
        raise InputError(field, value, f"a finite number {'>' if strict else '>='} {lo:g} ({unit})")
    return x


@dataclass(frozen=True)
class FiniteJournal:
    """A finite plain journal bearing with axial oil-feed grooves (module docstring).

    Parameters
    ----------
    diameter : float
        Journal diameter ``D`` (m).
    length : float
        Bearing length ``L`` (m), ``L/D`` in :data:`L_OVER_D_RANGE`.
    radial_clearance : float
        ``c`` (m), below the radius.
    viscosity : float
        ``mu`` (Pa s).
    cavitation : str
        ``"reynolds"`` (Swift-Stieber, the default), ``"half_sommerfeld"`` or ``"full_film"``.
    groove_angles : sequence of float
        Axial feed grooves' angles in the bearing's frame (rad, from ``y`` towards ``z``);
        empty for none.
    supply_pressure : float
        Oil supply pressure in the grooves (Pa), >= 0.
    position : float
        Axial station (m).
    name : str
        Label.
    """

    type: ClassVar[str] = "finite_journal"
    kind: ClassVar[str] = "bearing"
    fail_time: ClassVar[None] = None
    on: ClassVar[None] = None
    link: ClassVar[None] = None
    mass_matrix: ClassVar[np.ndarray] = np.zeros((2, 2))
    nonlinear: ClassVar[bool] = True
    spins: ClassVar[bool] = True
    N_THETA: ClassVar[int] = 72
    N_Z: ClassVar[int] = 16

    diameter: float
    length: float
    radial_clearance: float
    viscosity: float
    cavitation: str = "reynolds"
    groove_angles: tuple = ()
    supply_pressure: float = 0.0
    position: float = 0.0
    name: str = ""
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        d = _number("bearing.diameter", self.diameter, "m")
        ln = _number("bearing.length", self.length, "m")
        c = _number("bearing.radial_clearance", self.radial_clearance, "m")
        _number("bearing.viscosity", self.viscosity, "Pa s")
        _number("bearing.supply_pressure", self.supply_pressure, "Pa", strict=False)
        _number("bearing.position", self.position, "m", lo=-math.inf)
        if self.cavitation not in FINITE_CAVITATION:
            raise InputError("bearing.cavitation", self.cavitation,
                             "one of " + ", ".join(f'"{k}"' for k in FINITE_CAVITATION))  # fmt: skip
        if c >= 0.5 * d:
            raise InputError("bearing.radial_clearance", c,
                             f"a clearance well below the radius {0.5 * d} m (m)")  # fmt: skip
        lo, hi = L_OVER_D_RANGE
        if not lo <= ln / d <= hi:
            raise InputError("bearing.length", ln, f"a length with L/D in [{lo:g}, {hi:g}] for the "
                             f"finite film's grid (L/D = {ln / d:.3g}; shorter: short_journal)")  # fmt: skip
        angles = self.groove_angles
        if isinstance(angles, int | float) and not isinstance(angles, bool):
            angles = (angles,)
        if not isinstance(angles, tuple | list):
            raise InputError("bearing.groove_angles", angles, "a list of angles (rad)")
        for g in angles:
            _number("bearing.groove_angles", g, "rad", lo=-math.inf)
        object.__setattr__(self, "groove_angles", tuple(float(g) for g in angles))
        for key in ("diameter", "length", "radial_clearance", "viscosity", "supply_pressure",
                    "position"):  # fmt: skip
            object.__setattr__(self, key, float(getattr(self, key)))

    # ---- the support-term protocol ---------------------------------------------------------
    @property
    def holds(self) -> bool:
        """True: a loaded journal bearing holds the rotor."""
        return True

    @property
    def _table(self) -> tuple:
        return None, np.zeros((1, 2, 2)), np.zeros((1, 2, 2))

    @property
    def film(self) -> dict:
        """The film's parameters (SI) as :func:`finite_force` takes them."""
        return {"radius": 0.5 * self.diameter, "length": self.length,
                "clearance": self.radial_clearance, "viscosity": self.viscosity,
                "cavitation": self.cavitation, "grooves": self.groove_angles,
                "supply_pressure": self.supply_pressure}  # fmt: skip

    def support(self, node: int, name: str, dofs=None, link=None) -> Support:
        """A placeholder support the Model gives its law (as the short films')."""
        if link is not None:
            raise InputError("bearing.link", link, 'none with type = "finite_journal"')
        zero = np.zeros((1, 2, 2))
        return Support(dofs=tuple(dofs) if dofs is not None else (4 * node, 4 * node + 1),
                       k=zero, c=zero, position=float(self.position), name=name, term=self)  # fmt: skip

    def table_entry(self) -> dict:
        """The ``[[bearing]]`` table that builds this term again."""
        return {"position": self.position, "type": self.type, "name": self.name,
                "diameter": self.diameter, "length": self.length,
                "radial_clearance": self.radial_clearance, "viscosity": self.viscosity,
                "cavitation": self.cavitation, "groove_angles": list(self.groove_angles),
                "supply_pressure": self.supply_pressure}  # fmt: skip

    # ---- the force ---------------------------------------------------------------------------
    def force(self, position, velocity=(0.0, 0.0), spin: float = 0.0) -> np.ndarray:
        """Film force on the journal (N), y and z, at ``position`` (m), ``velocity`` (m/s) and
        ``spin`` (rad/s)."""
        y, z = (float(v) for v in position)
        vy, vz = (float(v) for v in velocity)
        f, _ = finite_force(y, z, vy, vz, float(spin), n_theta=self.N_THETA, n_z=self.N_Z,
                            memo=self._memo, **self.film)  # fmt: skip
        return f

    def _force_jac(self, position, velocity, spin):
        """Force (N) and its Jacobian ``(2, 5)`` by central differences (module docstring)."""
        p = np.asarray(position, float)
        u = np.asarray(velocity, float)
        f = self.force(p, u, spin)
        jac = np.zeros((2, 5))
        hq = 1e-6 * self.radial_clearance
        hv = hq * max(abs(float(spin)), 1.0)
        for j in range(2):
            d = np.zeros(2)
            d[j] = hq
            jac[:, j] = (self.force(p + d, u, spin) - self.force(p - d, u, spin)) / (2 * hq)
            d[j] = hv
            jac[:, 2 + j] = (self.force(p, u + d, spin) - self.force(p, u - d, spin)) / (2 * hv)
        return f, jac

    def static_force(self, position, spin: float):
        """Force (N) on the journal at rest and its stiffness ``-dF/dq`` (N/m)."""
        p = np.asarray(position, float)
        f = self.force(p, (0.0, 0.0), spin)
        k = np.zeros((2, 2))
        hq = 1e-6 * self.radial_clearance
        for j in range(2):
            d = np.zeros(2)
            d[j] = hq
            k[:, j] = -(self.force(p + d, (0, 0), spin) - self.force(p - d, (0, 0), spin)) / (2 * hq)
        return f, k

    def linearise(self, position, spin: float):
        """``(K, C)`` (N/m, N s/m) about the journal at rest at ``position`` (m)."""
        _, jac = self._force_jac(position, (0.0, 0.0), spin)
        return -jac[:, 0:2], -jac[:, 2:4]

    def equilibrium(self, load, spin: float) -> JournalEquilibrium:
        """Static position of this bearing alone under ``load`` (N, y and z) at ``spin``
        (rad/s): Newton with the central-difference Jacobian."""
        spin = _number(f"{self.name or 'bearing'}.speed", spin, "rad/s")
        load = np.asarray(load, dtype=float)
        w = float(np.hypot(*load))
        q = _newton(self, load, spin)
        eps = float(np.hypot(*q)) / self.radial_clearance
        att = math.atan2(load[0] * q[1] - load[1] * q[0], float(load @ q))
        som = self.viscosity * spin / (2 * math.pi) * self.length * self.diameter / w
        return JournalEquilibrium(q, eps, att, som * (0.5 * self.diameter / self.radial_clearance) ** 2)
