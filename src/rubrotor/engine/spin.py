"""Runs with the spin speed as a state: ``[speed] profile = "free"`` and touchdown rings.

The rotor's spin obeys ``J dOmega/dt = T_drive(Omega) - drag Omega + sum_i R_i ft_i`` (``ft_i``
the friction force of contact ``i`` on the rotor along ``i n``, so ``-R_i ft_i = mu N R`` is
the braking torque), with ``J`` the rotor's polar inertia (:func:`polar_inertia`). A contact may
have a touchdown ring as its stator, a spinning inner ring with its own inertia and drag that the
friction drives: ``J_ring omega_ring' = -r_ring ft - drag_ring omega_ring``, the friction acting
on the sliding speed ``R Omega - r_ring omega_ring + t . u``. Supports can fail at a time (a
magnetic bearing losing levitation): from then on their stiffness and damping are gone.

How the speed reaches the rotor: the rotor is projected once on a fixed real basis, its
mass-normalised undamped modes at the start speed (all of them by default, so the projection is
exact; ``modes`` keeps the lowest). In that basis the gyroscopic matrix is ``Omega G_r`` with the
current speed at every stage, and bearing coefficients tabulated against speed are reduced at
each tabulated speed and interpolated linearly in the current speed, which is exactly the
supports' own linear interpolation: no re-diagonalisation and no lag. The compiled kernel
(``rubrotor.core.spin.spin_dopri``) integrates rotor, spin, spin angle and ring speeds
together with an error-controlled Dormand-Prince 5(4) pair; the unbalance forcing follows the
integrated spin angle ``theta`` (``m e (Omega^2 (cos, sin) + Omega' (sin, -cos))``).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError

__all__ = ["FreeSpin", "TouchdownRing", "SpinResult", "polar_inertia", "simulate_spin",
           "spin_dataset", "simulate_free", "free_problem"]  # fmt: skip

from rubrotor.core.status import MESSAGES as _STATUS  # noqa: E402


@dataclass(frozen=True)
class FreeSpin:
    """The spin equation's torques.

    Parameters
    ----------
    drive_torque : float or tuple of float
        Motor torque (N m): a constant, or values at ``drive_speeds`` (linear between them,
        constant beyond).
    drive_speeds : tuple of float, optional
        Speeds (rad/s, increasing) of a torque table.
    drag : float
        Windage/bearing drag coefficient (N m s): torque ``-drag Omega``.
    """

    drive_torque: float | tuple = 0.0
    drive_speeds: tuple | None = None
    drag: float = 0.0

    def table(self) -> tuple[np.ndarray, np.ndarray]:
        """Speeds (rad/s) and torques (N m) of the drive as arrays (one row for a constant)."""
        tq = np.atleast_1d(np.asarray(self.drive_torque, float))
        if self.drive_speeds is None:
            if tq.size != 1:
                raise InputError("speed.drive_speeds", None, "speeds (rad/s) for a torque table")
            return np.zeros(1), tq
        w = np.asarray(self.drive_speeds, float)
        if w.shape != tq.shape or w.size < 2 or np.any(np.diff(w) <= 0):
            raise InputError("speed.drive_speeds", self.drive_speeds,
                             "increasing speeds (rad/s), one per drive_torque value, >= 2")  # fmt: skip
        return w, tq


@dataclass(frozen=True)
class TouchdownRing:
    """The spinning inner ring of a touchdown bearing, the stator of one contact.

    Parameters
    ----------
    inertia : float
        Polar inertia of the ring (kg m^2), > 0.
    radius : float
        Radius of the ring's bore where the rotor touches it (m), > 0.
    drag : float
        The ring bearing's drag coefficient (N m s): torque ``-drag omega_ring``.
    """

    inertia: float
    radius: float
    drag: float = 0.0

    def __post_init__(self):
        for name in ("inertia", "radius"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"contact.ring_{name}", v, "a number > 0")
        if not (math.isfinite(self.drag) and self.drag >= 0):
            raise InputError("contact.ring_drag", self.drag, "a number >= 0 (N m s)")


def polar_inertia(rotor) -> float:
    """The rotor's polar moment of inertia about its axis (kg m^2).

    ``J = sum_sections rho pi (D^4 - d^4) / 32 L + sum_disks Ip``: the shaft's ``rho I_p`` per
    length integrated over each section, plus each disk's polar inertia (the quantities the
    finite-element builder puts in the gyroscopic matrix).

    Parameters
    ----------
    rotor : rubrotor.rotors.fe.Rotor

    Returns
    -------
    float
    """
    shaft = sum(s.material.density * math.pi * (s.diameter**4 - s.bore_diameter**4) / 32
                * s.length for s in rotor.sections)  # fmt: skip
    return float(shaft + sum(d.polar_inertia for d in rotor.disks))


@dataclass
class SpinResult:
    """A free-spin run.

    Attributes
    ----------
    time : ndarray (n,)
        Sample times (s).
    state : ndarray (n_x, n)
        ``[eta, eta', Omega, theta, omega_ring]`` (modal m sqrt(kg), m sqrt(kg)/s, rad/s, rad,
        rad/s) per sample.
    contact : ndarray (n_c, 5, n)
        Normal force (N), friction force ``ft`` (N, along ``i n`` on the rotor), sliding speed
        (m/s), ``F_y``, ``F_z`` (N, on the rotor).
    basis : ndarray (n_free, r)
        Mass-normalised basis: ``q = basis eta``.
    reduced : dict
        ``K``, ``C`` (before a failure, at the start speed), ``G``, ``f0``, ``Pc``, ``Pout``.
    J, radius, rings, status, stats
        Polar inertia (kg m^2), contact radii (m), rings, status text, integrator counts.
    """

    time: np.ndarray
    state: np.ndarray
    contact: np.ndarray
    basis: np.ndarray
    reduced: dict
    J: float
    radius: np.ndarray
    rings: tuple
    status: str
    stats: dict

    @property
    def r(self) -> int:
        """Retained coordinates."""
        return self.basis.shape[1]

    @property
    def spin_speed(self) -> np.ndarray:
        """Spin speed (rad/s) per sample."""
        return self.state[2 * self.r]

    @property
    def spin_angle(self) -> np.ndarray:
        """Integrated spin angle (rad) per sample."""
        return self.state[2 * self.r + 1]

    @property
    def ring_speed(self) -> np.ndarray:
        """Ring speeds (rad/s), ``(n_c, n)`` (zero for a fixed stator)."""
        return self.state[2 * self.r + 2 :]


def _grid(system, failing) -> np.ndarray:
    """Every tabulation speed of the supports (rad/s): the reduced tables' breakpoints."""
    sp = [s.speeds for s in system.supports if s.speeds is not None and len(s.speeds) > 1]
    return np.unique(np.concatenate(sp)) if sp else np.zeros(1)


def _tables(system, basis, grid, failing):
    """Reduced ``K``, ``C`` (1/s^2, 1/s) at every grid speed, before and after the failure."""
    kept = tuple(s for i, s in enumerate(system.supports) if i not in failing)
    after = dataclasses.replace(system, supports=kept)
    Kt = np.empty((2, grid.size, basis.shape[1], basis.shape[1]))
    Ct = np.empty_like(Kt)
    for a, sysa in enumerate((system, after)):
        for j, w in enumerate(grid):
            sm = sysa.matrices(float(w))
            Kt[a, j] = basis.T @ sm.K @ basis
            Ct[a, j] = basis.T @ sm.C @ basis
    return Kt, Ct


def _basis(system, speed: float, modes: int | None):
    """Mass-normalised undamped modes at ``speed`` (symmetric part of K), lowest ``modes``."""
    from scipy.linalg import eigh

    sm = system.matrices(speed)
    lam, phi = eigh(0.5 * (sm.K + sm.K.T), sm.M)
    if modes is not None:
        if not 1 <= modes <= lam.size:
            raise InputError("simulation.modes", modes, f"an integer in 1..{lam.size}")
        lam, phi = lam[:modes], phi[:, :modes]
    return phi, np.sqrt(np.maximum(lam, 0.0)), sm


def _contact_arrays(system, basis, stations, rings):
    """``Pc`` (2 n_c, r), offsets (m), packed laws, radii (m) and ring rows of the contacts."""
    from rubrotor.core.contact import pack_contact

    nc = len(stations)
    if rings is not None and len(rings) != nc:
        raise InputError("rings", len(rings), f"one entry (or None) per contact ({nc})")
    rings = tuple(rings) if rings is not None else (None,) * nc
    Pc = np.zeros((2 * nc, basis.shape[1]))
    cp = np.zeros((nc, 10))
    ring = np.zeros((nc, 3))
    for i, s in enumerate(stations):
        c = s.contact
        if s.stator is not None:
            raise InputError("contact.stator_mass", s.stator.mass_y,
                             'no flexible stator with speed.profile = "free"')  # fmt: skip
        if c.sign_code != 0:
            raise InputError("contact.friction_sign", c.friction_sign,
                             '"physical" with speed.profile = "free"')  # fmt: skip
        Pc[2 * i : 2 * i + 2] = system.output_rows(c.position) @ basis
        cp[i] = pack_contact(1, c.law_code, c.stiffness, c.damping, c.clearance, c.friction,
                             0, 0.0, c.friction_regularization)  # fmt: skip
        if rings[i] is not None:
            ring[i] = (rings[i].inertia, rings[i].drag, rings[i].radius)
    offs = np.array([[s.offset_y, s.offset_z] for s in stations], float).reshape(-1)
    radius = np.array([s.contact.radius for s in stations], float)
    return Pc, offs, cp, radius, ring, rings


def _forces(system, basis, unbalances, loads, gravity):
    """Modal constant force ``f0`` (N/sqrt(kg)), unbalance rows ``Pu`` and ``[m e, phase]``."""
    from rubrotor.engine.parts import static_load_vector

    f0 = basis.T @ static_load_vector(system, tuple(loads), gravity)
    Pu = np.zeros((2 * len(unbalances), basis.shape[1]))
    unb = np.zeros((len(unbalances), 2))
    for u, ub in enumerate(unbalances):
        if ub.position is None:
            raise InputError("unbalance.position", None, "an axial position (m)")
        Pu[2 * u : 2 * u + 2] = system.output_rows(ub.position) @ basis
        unb[u] = (ub.magnitude, ub.phase)
    return f0, Pu, unb


def simulate_spin(system, *, J: float, speed: float, duration: float, spacing: float,
                  stations=(), free: FreeSpin = FreeSpin(), rings=None, unbalances=(), loads=(),
                  gravity=(0.0, 0.0), fail_time: float = math.inf, failing=(), modes=None,
                  initial="rest", rtol: float = 1e-6, atol: float = 1e-10,
                  max_steps: int = 50_000_000) -> SpinResult:  # fmt: skip
    """Simulate a rotor whose spin speed is a state (see the module docstring).

    Parameters
    ----------
    system : rubrotor.rotors.linear.LinearSystem
        The rotor (its supports included).
    J : float
        Polar inertia of the rotor (kg m^2), e.g. :func:`polar_inertia`.
    speed : float
        Spin speed at ``t = 0`` (rad/s).
    duration, spacing : float
        Simulated time and spacing of the saved samples (s).
    stations : tuple of rubrotor.engine.parts.RubStation
        Contacts (rigid stators, possibly offset; ``contact.radius`` is ``R``, m).
    free : FreeSpin
        Drive torque and drag of the spin.
    rings : tuple of (TouchdownRing or None), optional
        Per contact, a touchdown ring as its stator (None: a fixed stator).
    unbalances, loads : tuple
        :class:`~rubrotor.Unbalance` planes (kg m, rad), radial loads (N).
    gravity : (float, float)
        ``(g_y, g_z)`` (m/s^2).
    fail_time : float
        Time (s) from which the supports ``failing`` (indices into ``system.supports``) are gone.
    modes : int, optional
        Keep the lowest modes (default all: the projection is exact).
    initial : {"rest", "static"} or ndarray
        Start state of the rotor: at rest on the axis, static under the constant loads, or
        ``[q, q']`` on the free DOFs (m, m/s; rad, rad/s for rotations).
    rtol, atol : float
        Relative tolerance and absolute tolerance (m) of the displacements; the other states'
        absolute tolerances follow from it (``_tolerances``).

    Returns
    -------
    SpinResult
    """
    from rubrotor.core.spin import spin_dopri

    if not (math.isfinite(J) and J > 0):
        raise InputError("J", J, "a polar inertia > 0 (kg m^2)")
    if not (math.isfinite(speed) and speed >= 0):
        raise InputError("speed.rad_per_s", speed, "a start speed >= 0 (rad/s)")
    failing = tuple(int(i) for i in failing)
    basis, wn, sm = _basis(system, speed, modes)
    grid = _grid(system, failing)
    Kt, Ct = _tables(system, basis, grid, failing)
    G = basis.T @ sm.G @ basis
    f0, Pu, unb = _forces(system, basis, unbalances, loads, gravity)
    Pc, offs, cp, radius, ring, rings = _contact_arrays(system, basis, stations, rings)
    r, nc = basis.shape[1], len(stations)
    x0 = np.zeros(2 * r + 2 + nc)
    x0[2 * r] = speed
    if isinstance(initial, str) and initial == "static":
        x0[:r] = _static(basis.T @ sm.K @ basis, f0)
    elif not isinstance(initial, str):  # [q, q'] on the free DOFs: project (Phi^T M Phi = I)
        q = np.asarray(initial, float).reshape(2, -1)
        x0[: 2 * r] = (basis.T @ sm.M @ q.T).T.reshape(-1)
    elif initial != "rest":
        raise InputError("initial.state", initial, '"rest" or "static" with a free spin speed')
    n = int(math.floor(duration / spacing + 1e-9)) + 1
    t_out = np.arange(n) * spacing
    w, tq = free.table()
    ctrl = np.concatenate([[rtol, spacing / 64, max_steps],
                           _tolerances(basis, wn, atol, rtol, speed, Pc, radius, nc)])  # fmt: skip
    out = np.zeros((x0.size + 5 * nc, n))
    ist = np.zeros(4, np.int64)
    wall = time.perf_counter()
    mats = (grid, Kt, Ct, G, float(fail_time))
    spin_dopri(x0, t_out, mats, (f0, Pu, unb), (Pc, offs, cp, radius, ring),
               (float(J), float(free.drag), w, tq), ctrl, (out, ist))  # fmt: skip
    wall = time.perf_counter() - wall
    m = int(ist[3])
    red = dict(K=Kt[0, 0], C=Ct[0, 0], G=G, f0=f0, Pc=Pc, Kt=Kt, Ct=Ct, grid=grid)
    return SpinResult(
        time=t_out[:m], state=out[: x0.size, :m], contact=out[x0.size :, :m].reshape(nc, 5, m),
        basis=basis, reduced=red, J=float(J), radius=radius, rings=rings,
        status=_STATUS[int(ist[0])], stats={"accepted": int(ist[1]), "rejected": int(ist[2]), "wall_s": wall},
    )  # fmt: skip


def _static(k: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Static modal deflection ``k^-1 f``; a singular or overflowing stiffness is refused."""
    try:
        x = np.linalg.solve(k, f)
    except np.linalg.LinAlgError:
        x = np.full(f.shape, np.nan)
    if not np.all(np.isfinite(x)):
        raise InputError("initial.state", "static", "a rotor whose stiffness matrix can be "
                         "solved (check the bearing and section values), or \"rest\"")  # fmt: skip
    return x


def _tolerances(basis, wn, atol, rtol, speed, Pc, radius, nc):
    """Absolute tolerances per state: ``atol`` (m) turned into each mode's coordinate by its
    largest deflection, times its frequency for the velocity; the speeds to ``rtol`` of the start
    speed times 1e-3, the spin angle to ``rtol`` rad."""
    amp = np.max(np.abs(basis), axis=0)
    a_eta = atol / np.maximum(amp, 1e-300)
    a_vel = a_eta * np.maximum(wn, 1.0)
    a_om = max(1e-3 * rtol * speed, 1e-12)
    return np.concatenate([a_eta, a_vel, [a_om, rtol], np.full(nc, a_om)])


def free_problem(scenario, integrator=None) -> tuple:
    """The rotor and the :func:`simulate_spin` arguments of a ``[speed] profile = "free"``
    scenario: ``(system, kwargs, positions)`` (``positions``: the contacts', then the probes', m).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A ``[[section]]`` rotor scenario whose ``engine.free_spin`` is set.
    integrator : rubrotor.engine.settings.Integrator, optional
        Overrides ``[simulation]``: ``duration`` (s) or ``revolutions`` (at the start speed),
        ``rtol``, ``atol`` (m), ``sample_rate`` or ``output_dtau``, ``probes``.
    """
    from rubrotor.errors import ScenarioError

    eng, integ = scenario.engine, integrator or scenario.simulation
    if not scenario.model.fe_rotor:
        raise ScenarioError("speed.profile", "free", "a [[section]] rotor (its polar inertia "
                            "comes from its sections and disks)")  # fmt: skip
    if integ is None:
        raise ScenarioError("simulation", None, "a [simulation] section (duration or revolutions)")
    if integ.step_seconds(scenario.speed) is not None:
        raise ScenarioError("simulation.dt", integ.dt or integ.dtau,
                            'no fixed step with speed.profile = "free" (adaptive: rtol, atol)')  # fmt: skip
    positions = tuple(s.contact.position for s in eng.stations) + tuple(integ.probes)
    system = scenario.rotor.linear_system(tuple(sorted(set(eng.positions + tuple(integ.probes)))))
    kwargs = dict(
        J=polar_inertia(scenario.rotor), speed=scenario.speed,
        duration=integ.total_time(scenario.speed), spacing=integ.output_spacing(scenario.speed),
        stations=eng.stations, free=eng.free_spin, unbalances=eng.unbalances, loads=eng.loads,
        gravity=eng.gravity, modes=eng.modes, initial=eng.initial, rtol=integ.rtol,
        atol=integ.atol, rings=eng.rings, **_failure(scenario.rotor),
    )  # fmt: skip
    return system, kwargs, positions


def simulate_free(scenario, *, integrator=None):
    """Run a scenario with ``[speed] profile = "free"`` (see the module docstring).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A ``[[section]]`` rotor scenario whose ``engine.free_spin`` is set.
    integrator : rubrotor.engine.settings.Integrator, optional
        Overrides ``[simulation]`` (see :func:`free_problem`).

    Returns
    -------
    xarray.Dataset
        See :func:`spin_dataset`; also ``clearance``, ``contact_radius``, ``ring_radius`` (m)
        on ``contact``.
    """
    system, kwargs, positions = free_problem(scenario, integrator)
    res = simulate_spin(system, **kwargs)
    ds = spin_dataset(res, system, positions)
    st = kwargs["stations"]
    ds["clearance"] = ("contact", [s.contact.clearance for s in st], {"units": "m"})
    ds["contact_radius"] = ("contact", res.radius, {"units": "m", "long_name": "rotor radius R"})
    ds["ring_radius"] = ("contact", [0.0 if g is None else g.radius for g in res.rings],
                         {"units": "m", "long_name": "ring bore radius (0: fixed stator)"})  # fmt: skip
    ds.attrs.update(scenario_name=scenario.name, scenario=scenario.source)
    return ds


def _failure(rotor) -> dict:
    """``fail_time`` (s) and ``failing`` (indices into the LinearSystem's supports: the
    non-pinned bearings in order) of the bearings with ``fail_time``."""
    held = [b for b in rotor.bearings if b.kind != "pinned"]
    failing = tuple(i for i, b in enumerate(held) if b.fail_time is not None)
    if not failing:
        return {}
    return {"fail_time": float(held[failing[0]].fail_time), "failing": failing}


def spin_dataset(res: SpinResult, system, positions):
    """The results of a free-spin run as an xarray Dataset.

    Parameters
    ----------
    res : SpinResult
    system : rubrotor.rotors.linear.LinearSystem
        The rotor the run used.
    positions : sequence of float
        Output stations (m): the contacts first, then probes.

    Returns
    -------
    xarray.Dataset
        ``v, w`` (m), ``v_dot, w_dot`` (m/s) on ``(station, time)``; ``spin_speed`` (rad/s)
        and ``spin_angle`` (rad) on ``time``; ``normal_force``, ``friction_force`` (N, along
        ``i n`` on the rotor), ``sliding_speed`` (m/s), ``force_y``, ``force_z`` (N),
        ``friction_torque`` (N m, ``-R ft``, braking the rotor) and ``ring_speed`` (rad/s) on
        ``(contact, time)``; attributes ``status``, ``polar_inertia_kg_m2``, ``engine``.
    """
    import xarray as xr

    r = res.r
    rows = (np.vstack([system.output_rows(x) for x in positions]) @ res.basis
            if len(positions) else np.zeros((0, r)))  # fmt: skip
    q, qd = rows @ res.state[:r], rows @ res.state[r : 2 * r]
    st, ct = ("station", "time"), ("contact", "time")
    m, v = {"units": "m"}, {"units": "m/s"}
    data = {"v": (st, q[0::2], m), "w": (st, q[1::2], m), "v_dot": (st, qd[0::2], v),
            "w_dot": (st, qd[1::2], v),
            "spin_speed": ("time", res.spin_speed, {"units": "rad/s", "long_name": "spin speed"}),
            "spin_angle": ("time", res.spin_angle, {"units": "rad"}),
            "ring_speed": (ct, res.ring_speed, {"units": "rad/s"})}  # fmt: skip
    names = ("normal_force", "friction_force", "sliding_speed", "force_y", "force_z")
    for k, name in enumerate(names):
        data[name] = (ct, res.contact[:, k], v if name == "sliding_speed" else {"units": "N"})
    data["friction_torque"] = (ct, -res.radius[:, None] * res.contact[:, 1], {"units": "N m"})
    coords = {"time": ("time", res.time, {"units": "s"}),
              "station": ("station", np.asarray(positions, float), m)}  # fmt: skip
    import json

    touching = res.contact[:, 0] > 0
    events = int(np.sum(touching[:, 1:] & ~touching[:, :-1]))  # contact onsets between samples
    stats = {**res.stats, "contact_events": events}
    attrs = {"status": res.status, "status_message": res.status, "engine": "free-spin",
             "polar_inertia_kg_m2": res.J, "speed_rad_s": float(res.spin_speed[0]),
             "speed_end_rad_s": float(res.spin_speed[-1]),
             "integrator_stats": json.dumps(stats)}  # fmt: skip
    return xr.Dataset(data, coords=coords, attrs=attrs)
