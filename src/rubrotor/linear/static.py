"""Static analysis of any linear rotor: deflection under gravity and constant loads, and the
forces the bearings apply to the rotor.

Equations
---------
At spin speed ``Omega`` the static deflection ``q`` (free DOFs) solves
``(K + K_s(Omega)) q = f`` with ``f`` the constant loads: gravity ``(g_y, g_z)`` acting on the
shaft's distributed mass and the disks (the consistent load ``M r`` of a finite-element rotor,
``r`` the rigid translation along ``g``; ``int rho A g B(x)^T dx`` on the continuous shaft) plus
point loads ``B(x) [F_y, F_z]``. Damping and the gyroscopic matrix do not act on a static
deflection; cross-coupled bearings (``kyz``, ``kzy``) do, and deflect the rotor sideways.

With fluid-film supports (``short_journal``, ``squeeze_film``, ``finite_journal``) the problem is
nonlinear: ``K q - f - sum_b B_b^T F_b(B_b q, Omega) = 0``, solved by Newton's method with the
films' Jacobians (:mod:`rubrotor.forces.equilibrium`); each film then also reports its journal's
eccentricity ratio and attitude angle.

Reactions are the forces (N) the supports apply to the rotor:

* a bearing or seal: ``-K_s(Omega) [v, w]`` at its station;
* a fluid film: its force on the journal at the static position;
* a pinned support (an exact constraint): the residual ``K q - f`` on its DOFs;
* the continuous shaft, pinned at both ends: the two end forces from the balance of forces and
  moments (it is statically determinate).

They balance the applied loads exactly: ``sum R + W = 0`` with ``W`` the total applied force.
Contacts (nonlinear, with a clearance) are not part of the static solution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from rubrotor.errors import InputError
from rubrotor.forces.equilibrium import nonlinear_supports, solve_equilibrium
from rubrotor.rotors.linear import LinearSystem, NodalBasis

__all__ = ["STANDARD_GRAVITY", "BearingReaction", "StaticResult", "static_analysis"]

STANDARD_GRAVITY = 9.80665
"""Standard acceleration of gravity (m/s^2); the default gravity is ``(-g, 0)`` (along -y)."""


@dataclass(frozen=True)
class BearingReaction:
    """The force (N) one support applies to the rotor.

    Attributes
    ----------
    name : str
        Label of the support.
    position : float
        Axial position (m).
    force_y, force_z : float
        Force components (N) along ``y`` and ``z`` on the rotor.
    eccentricity_ratio : float or None
        A fluid film's journal eccentricity over its radial clearance (1); None for a support
        of coefficients.
    attitude_angle_rad : float or None
        A fluid film's angle from the load on the journal to its eccentricity, positive in the
        spin's sense (rad); None for a support of coefficients.
    """

    name: str
    position: float
    force_y: float
    force_z: float
    eccentricity_ratio: float | None = None
    attitude_angle_rad: float | None = None


@dataclass(frozen=True)
class StaticResult:
    """Static deflection and support reactions of a rotor.

    Attributes
    ----------
    speed_rad_s : float
        Spin speed (rad/s) at which speed-dependent bearings were evaluated.
    gravity : tuple of float
        ``(g_y, g_z)`` (m/s^2) applied.
    x : ndarray, shape (P,)
        Axial positions (m): the nodes of a finite-element rotor, a fine grid on a continuous
        shaft.
    deflection : ndarray, shape (P, 2)
        Deflections ``v``, ``w`` (m) at ``x``.
    bearings : tuple of BearingReaction
        Forces (N) the supports apply to the rotor, in axial order.
    applied : ndarray, shape (2,)
        Total applied force ``W`` (N): the weight plus the point loads; ``sum R = -W``.
    q : ndarray
        Static displacement on the free DOFs (m, rad).
    """

    speed_rad_s: float
    gravity: tuple
    x: np.ndarray
    deflection: np.ndarray
    bearings: tuple
    applied: np.ndarray
    q: np.ndarray

    def to_dict(self) -> dict:
        """The JSON form printed by ``rubrotor static --json`` (SI units in the key names)."""
        return {
            "speed_rad_s": self.speed_rad_s,
            "gravity_m_s2": list(self.gravity),
            "x_m": self.x.tolist(),
            "deflection_y_m": self.deflection[:, 0].tolist(),
            "deflection_z_m": self.deflection[:, 1].tolist(),
            "bearings": [_reaction_dict(b) for b in self.bearings],
        }


def _reaction_dict(b: BearingReaction) -> dict:
    out = {"name": b.name, "position_m": b.position, "force_y_N": b.force_y,
           "force_z_N": b.force_z}  # fmt: skip
    if b.eccentricity_ratio is not None:
        out["eccentricity_ratio"] = b.eccentricity_ratio
        att = b.attitude_angle_rad  # NaN without load (a damper's spring carrying nothing)
        out["attitude_angle_rad"] = att if math.isfinite(att) else None
    return out


def _gravity_nodal(system: LinearSystem, g: np.ndarray) -> np.ndarray:
    """Consistent gravity load ``M r`` (N) on all DOFs of a labelled (FE or ROSS) rotor."""
    labels = system.dof_labels
    r = np.array(
        [g[0] if s.startswith("v@") else g[1] if s.startswith("w@") else 0.0 for s in labels]
    )
    return system.M @ r


def _gravity_continuous(system: LinearSystem, g: np.ndarray, mass_per_length: float) -> np.ndarray:
    """``int_0^L rho A g B(x)^T dx`` (N) by Gauss-Legendre quadrature, 12 points per half-wave
    of the highest retained mode (the integrand is a sum of sines: exact to rounding)."""
    basis = system.basis
    waves = len(getattr(basis, "k", ())) or 8
    panels = max(8, waves)
    t, w = np.polynomial.legendre.leggauss(12)
    edges = np.linspace(0.0, basis.length, panels + 1)
    f = np.zeros(len(system.M))
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        for ti, wi in zip(t, w, strict=True):
            x = 0.5 * (a + b) + 0.5 * (b - a) * ti
            f += 0.5 * (b - a) * wi * mass_per_length * (basis.rows(x).T @ g)
    return f


def _solve(system: LinearSystem, speed: float, f_free: np.ndarray) -> np.ndarray:
    k = system.matrices(speed).K
    try:
        lu = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(k))
    except RuntimeError:  # exactly singular: a support missing
        raise InputError("bearing", len(system.supports), "supports that hold the rotor") from None
    q = lu.solve(f_free)
    if not np.all(np.isfinite(q)):
        raise InputError("bearing", len(system.supports), "supports that hold the rotor")
    return q


def _reactions(system: LinearSystem, speed: float, q_full: np.ndarray, f_full: np.ndarray):
    """Forces (N) of the spring supports, the fluid films and the pinned DOFs of a nodal rotor."""
    from rubrotor.forces.equilibrium import linearise

    out = []
    for s in system.supports:
        if getattr(s.term, "nonlinear", False):
            st = linearise(s, q_full, speed)
            out.append(BearingReaction(s.name, float(s.position), float(st.force[0]),
                                       float(st.force[1]), st.eccentricity_ratio,
                                       st.attitude_angle_rad))  # fmt: skip
            continue
        ks, _ = s.coefficients(speed)
        force = -ks @ q_full[list(s.dofs)]
        out.append(BearingReaction(s.name, float(s.position), float(force[0]), float(force[1])))
    if system.fixed:
        from rubrotor.forces.equilibrium import _film_sum, _linear_stiffness, nonlinear_supports

        films, _ = _film_sum(system, nonlinear_supports(system), q_full, speed)
        residual = _linear_stiffness(system, speed) @ q_full - f_full - films
        nodes = system.basis.nodes
        fixed = sorted(system.fixed)
        for node in sorted({d // 4 for d in fixed}):
            fy = residual[4 * node] if 4 * node in fixed else 0.0
            fz = residual[4 * node + 1] if 4 * node + 1 in fixed else 0.0
            x = float(nodes[node])
            out.append(BearingReaction(f"pinned at {x:g} m", x, float(fy), float(fz)))
    return tuple(sorted(out, key=lambda r: r.position))


def _end_reactions(length: float, points: list[tuple[float, np.ndarray]]) -> tuple:
    """The two end forces (N) of a beam pinned at 0 and ``length`` (m) under point forces
    ``(x, [F_y, F_z])``: balance of forces and of moments about the left end."""
    total = sum((f for _, f in points), np.zeros(2))
    moment = sum((x * f for x, f in points), np.zeros(2))
    right = -moment / length
    left = -total - right
    return (
        BearingReaction("pinned at 0 m", 0.0, float(left[0]), float(left[1])),
        BearingReaction(f"pinned at {length:g} m", float(length), float(right[0]), float(right[1])),
    )


def _check_gravity(gravity) -> np.ndarray:
    try:
        g = np.asarray(gravity, float)
    except (TypeError, ValueError):  # text, or a ragged sequence
        g = np.full(0, np.nan)
    if g.shape != (2,) or not np.all(np.isfinite(g)):
        raise InputError("gravity", gravity, "(g_y, g_z): two finite accelerations (m/s^2)")
    return g


def _inputs(obj, speed, gravity, loads):
    """The system, the continuous shaft (or None), speed, gravity and loads of any rotor."""
    import os

    from rubrotor.modelling import Model
    from rubrotor.scenario.load import Scenario

    model = Model.of(obj)
    shaft = None if isinstance(obj, str | os.PathLike) else model.shaft
    if isinstance(obj, Scenario):
        speed = obj.speed if speed is None else speed
        if gravity is None:
            gravity = obj.gravity
        loads = obj.loads if loads is None else loads
    if gravity is None:
        gravity = (-STANDARD_GRAVITY, 0.0)
    speed = 0.0 if speed is None else speed
    if isinstance(speed, bool) or not (isinstance(speed, int | float) and math.isfinite(speed)):
        raise InputError("speed", speed, "a finite spin speed >= 0 (rad/s)")
    if speed < 0:
        raise InputError("speed", speed, "a finite spin speed >= 0 (rad/s)")
    return model.linear_system(), shaft, float(speed), _check_gravity(gravity), tuple(loads or ())


def static_analysis(obj, speed: float | None = None, gravity=None, loads=None) -> StaticResult:
    """Static deflection under gravity and constant loads, and the bearing reactions.

    Parameters
    ----------
    obj : Scenario, Rotor, Shaft or LinearSystem
        The rotor (see :func:`rubrotor.linear_system`). A scenario gives its
        speed, its ``[gravity]`` and its loads (``[load]`` / ``[[load]]``).
    speed : float, optional
        Spin speed (rad/s) at which speed-dependent bearings are evaluated; default the
        scenario's, else 0.
    gravity : (float, float), optional
        ``(g_y, g_z)`` (m/s^2); default the scenario's ``[gravity]``, else standard gravity
        along ``-y``, ``(-9.80665, 0)``. Pass ``(0, 0)`` for loads alone.
    loads : sequence of RadialLoad, optional
        Point loads (N at m); default the scenario's.

    Returns
    -------
    StaticResult
        Deflection (m) along the rotor and the forces (N) of the supports on the rotor.

    Examples
    --------
    >>> from rubrotor.rotors.fe import Bearing, Material, Rotor, Section
    >>> steel = Material("steel", 211e9, 7810, poisson_ratio=0.3)
    >>> rotor = Rotor([Section(1.0, 0.05, steel)],
    ...               bearings=[Bearing(0.0, kind="pinned"), Bearing(1.0, kind="pinned")])
    >>> res = static_analysis(rotor)
    >>> round(sum(b.force_y for b in res.bearings) / (rotor.mass * 9.80665), 9)
    1.0
    """
    system, shaft, speed, g, loads = _inputs(obj, speed, gravity, loads)
    n = len(system.M)
    points = []
    for ld in loads:
        if ld.position is None:
            raise InputError("load.position", None, "an axial position (m)")
        points.append((float(ld.position), np.array([ld.force_y, ld.force_z], float)))
    if shaft is not None:
        f_full = _gravity_continuous(system, g, shaft.mass_per_length)
        weight = g * shaft.mass_per_length * shaft.length
    elif isinstance(system.basis, NodalBasis) and len(system.dof_labels) == n:
        f_full = _gravity_nodal(system, g)
        # the translational mass along each axis (point masses may differ along y and z)
        mass = [float(t @ system.M @ t) for t in
                (np.array([1.0 if s.startswith(a) else 0.0 for s in system.dof_labels])
                 for a in ("v@", "w@"))]  # fmt: skip
        weight = g * np.array(mass)
    elif np.any(g != 0):
        raise InputError("gravity", tuple(g), "(0, 0) for a rotor without nodal DOF labels")
    else:
        f_full, weight = np.zeros(n), np.zeros(2)
    for x, f in points:
        f_full = f_full + system.basis.rows(x).T @ f
    if nonlinear_supports(system):  # fluid films: Newton on the nonlinear static problem
        q_full = solve_equilibrium(system, speed, f_full)
        q = q_full[system.free]
    else:
        q = _solve(system, speed, f_full[system.free])
        q_full = system.expand(q)
    if shaft is not None:
        x = np.linspace(0.0, shaft.length, 201)
        bearings = _end_reactions(shaft.length, points + [(shaft.length / 2, weight)])
    else:
        x = np.asarray(system.basis.nodes, float)
        bearings = _reactions(system, speed, q_full, f_full)
    defl = np.array([system.basis.rows(float(xi)) @ q_full for xi in x])
    applied = weight + sum((f for _, f in points), np.zeros(2))
    return StaticResult(speed, tuple(float(v) for v in g), x, defl, bearings, applied, q)
