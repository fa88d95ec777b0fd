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
import sys
import time

import numpy as np

from rubrotor.core.status import Status
from rubrotor.engine.result import TimeRun, to_dataset
from rubrotor.engine.spin_guard import (
    STABILITY,
    STEPS_PER_SAMPLE,
    check_samples,
    estimated_normal,
    refuse_unresolvable,
    run_chunks,
    stiff_terms,
    stiffest,
)
from rubrotor.errors import InputError
from rubrotor.rotors.forces import FreeSpin, TouchdownRing  # their home; kept importable here

__all__ = ["FreeSpin", "TouchdownRing", "SpinResult", "polar_inertia", "simulate_spin",
           "spin_dataset", "simulate_free", "free_problem", "free_run"]  # fmt: skip



_NO_DRIVE = FreeSpin()
"""No drive torque, no drag."""


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


SpinResult = TimeRun
"""Old name of a free-spin run's result: the one :class:`~rubrotor.engine.result.TimeRun`
(``engine = "free-spin"``). Its channels are per contact the ring speed (rad/s), normal and
friction force (N), sliding speed (m/s), ``F_y, F_z`` (N) and friction torque (N m); its extras:
``state`` ``[eta, eta', Omega, theta, omega_ring]`` (modal m sqrt(kg), m sqrt(kg)/s, rad/s, rad,
rad/s) per sample, ``contact`` ``(n_c, 5, n)`` (normal force, friction force, sliding speed,
``F_y``, ``F_z``), ``basis`` (``q = basis eta``), ``reduced``, ``J`` (kg m^2), ``radius`` (m)
and ``rings``; ``spin_speed``, ``spin_angle``, ``ring_speed`` read the state."""


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


def _diagnoser(terms_at, n_x: int, nc: int, max_steps: int, stopped: list):
    """The message of a free-spin run that stopped with a kernel code (recorded in ``stopped``):
    where it stopped, what the run would need and its stiffest term (key, rate 1/s)."""

    def diagnose(code, saved, t, h, steps=None):
        stopped[0] = Status(code)
        normal = np.max(saved[n_x::5], axis=1) if saved.shape[1] else np.zeros(nc)
        rate, key, _, what = stiffest(terms_at(normal))
        where = f"at t = {t:.6g} s (step {h:.3g} s); data up to t = {t:.6g} s kept"
        if code == Status.DIVERGED:
            return (f"diverged {where}: the state is no longer finite; the stiffest term is "
                    f"{key} ({what}, rate {rate:.3g} 1/s)")  # fmt: skip
        more = f"about {steps:.3g} steps" if steps is not None else f"more than {max_steps} steps"
        return (f"{Status(code).message} {where}: the run needs {more} (at most {max_steps}); the "
                f"stiffest term is {key} ({what}, rate {rate:.3g} 1/s, stable steps "
                f"<= {STABILITY / rate:.3g} s)")  # fmt: skip

    return diagnose


def simulate_spin(system, *, J: float, speed: float, duration: float, spacing: float,
                  stations=(), free: FreeSpin = _NO_DRIVE, rings=None, unbalances=(), loads=(),
                  gravity=(0.0, 0.0), fail_time: float = math.inf, failing=(), modes=None,
                  initial="rest", rtol: float = 1e-6, atol: float = 1e-10,
                  max_steps: int = 50_000_000, progress: bool | None = None,
                  sample_keys=("duration", "spacing")) -> SpinResult:  # fmt: skip
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
    max_steps : int
        Steps allowed (at most ``STEPS_PER_SAMPLE`` per saved sample: a motion that much faster
        than the sampling is not one the run was asked to resolve); a run whose stiffest term
        (``rubrotor.engine.spin_guard``) needs more is refused, naming its key, and one that
        comes to need more stops partial.
    progress : bool, optional
        Print a progress line on runs longer than 2 s (default: when stderr is a terminal).
    sample_keys : (str, str)
        Names of ``duration`` and of the sample spacing in messages (the scenario's keys).

    Returns
    -------
    SpinResult
        ``status`` ``"complete"`` (every saved value finite) or ``"partial"`` (``message`` says
        why and where it stopped: diverged, too many steps, or interrupted with Ctrl-C).
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
    rows = x0.size + 5 * nc
    n = check_samples(math.floor(duration / spacing + 1e-9) + 1, rows, sample_keys,
                      (duration, 1.0 / spacing))  # fmt: skip
    t_out = np.arange(n) * spacing
    w, tq = free.table()
    normal, why = estimated_normal(f0, Pc, unb, speed, nc)
    terms = stiff_terms(float(J), float(free.drag), Pc, cp, radius, ring, normal, why)
    max_steps = int(min(max_steps, STEPS_PER_SAMPLE * max(n - 1, 1)))
    refuse_unresolvable(terms, duration, max_steps)
    ctrl = np.concatenate([[rtol, spacing / 64, max_steps],
                           _tolerances(basis, wn, atol, rtol, speed, Pc, radius, nc)])  # fmt: skip
    mats = (grid, Kt, Ct, G, float(fail_time))
    args = (mats, (f0, Pu, unb), (Pc, offs, cp, radius, ring), (float(J), float(free.drag), w, tq))

    stopped = [Status.OK]  # the code of the diagnosed stop
    terms_at = lambda normal: stiff_terms(float(J), float(free.drag), Pc, cp, radius, ring, normal)  # noqa: E731
    diagnose = _diagnoser(terms_at, x0.size, nc, max_steps, stopped)
    show = sys.stderr.isatty() if progress is None else progress
    wall = time.perf_counter()
    out, (acc, rej), reason = run_chunks(spin_dopri, x0, t_out, args, ctrl, rows, show, diagnose)
    wall = time.perf_counter() - wall
    m = out.shape[1]
    red = dict(K=Kt[0, 0], C=Ct[0, 0], G=G, f0=f0, Pc=Pc, Kt=Kt, Ct=Ct, grid=grid)
    state, contact = out[: x0.size, :m], out[x0.size :, :m].reshape(nc, 5, m)
    per_contact = np.concatenate([state[2 * r + 2 :, None], contact,
                                  -radius[:, None, None] * contact[:, 1:2]], axis=1)  # fmt: skip
    code = stopped[0] if not reason or stopped[0] != Status.OK else Status.INTERRUPTED
    return TimeRun(
        time=t_out[:m], stations=np.zeros(0), n_contacts=nc,
        channels=per_contact.reshape(7 * nc, m), events=np.zeros((0, 2)),
        status="partial" if reason else "complete", message=reason or code.message,
        stats={"accepted": acc, "rejected": rej, "wall_s": wall},
        speed=float(speed), engine="free-spin", code=code,
        extras={"state": state, "contact": contact, "basis": basis, "reduced": red, "J": float(J),
                "radius": radius, "rings": rings},
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
    from rubrotor.modelling import model_of

    eng, integ = scenario.engine, integrator or scenario.simulation
    model = model_of(scenario)
    model.require_general_rotor(ScenarioError(
        "speed.profile", "free",
        "a [[section]] rotor (its polar inertia comes from its sections and disks)"))  # fmt: skip
    if integ is None:
        raise ScenarioError("simulation", None, "a [simulation] section (duration or revolutions)")
    if integ.step_seconds(scenario.speed) is not None:
        raise ScenarioError("simulation.dt", integ.dt or integ.dtau,
                            'no fixed step with speed.profile = "free" (adaptive: rtol, atol)')  # fmt: skip
    positions = tuple(s.contact.position for s in eng.stations) + tuple(integ.probes)
    system = model.linear_system(sorted(set(eng.positions + tuple(integ.probes))), only=True)
    forces, law = model.forces(), model.speed_law()
    kwargs = dict(
        J=polar_inertia(scenario.rotor), speed=law.speed,
        duration=integ.total_time(law.speed), spacing=integ.output_spacing(law.speed),
        stations=forces.stations, free=law.free, unbalances=forces.unbalances,
        loads=forces.loads, gravity=forces.gravity, modes=eng.modes, initial=eng.initial,
        rtol=integ.rtol,
        atol=integ.atol, rings=eng.rings, **_failure(scenario.rotor),
        sample_keys=("simulation.duration" if integ.duration is not None
                     else "simulation.revolutions",
                     "simulation.sample_rate" if integ.sample_rate is not None
                     else "simulation.output_dtau"),
    )  # fmt: skip
    return system, kwargs, positions


def free_run(scenario, integrator=None, progress=None):
    """Run a ``[speed] profile = "free"`` scenario: ``(run, system, kwargs, positions)``, the
    :class:`~rubrotor.engine.result.TimeRun` and the :func:`free_problem` it was run from."""
    system, kwargs, positions = free_problem(scenario, integrator)
    return simulate_spin(system, **kwargs, progress=progress), system, kwargs, positions


def simulate_free(scenario, *, integrator=None, progress=None):
    """Run a scenario with ``[speed] profile = "free"`` (see the module docstring).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A ``[[section]]`` rotor scenario whose ``engine.free_spin`` is set.
    integrator : rubrotor.engine.settings.Integrator, optional
        Overrides ``[simulation]`` (see :func:`free_problem`).
    progress : bool, optional
        Print a progress line on runs longer than 2 s (default: when stderr is a terminal).

    Returns
    -------
    xarray.Dataset
        See :func:`spin_dataset`; also ``clearance``, ``contact_radius``, ``ring_radius`` (m)
        on ``contact``.
    """
    res, system, kwargs, positions = free_run(scenario, integrator, progress)
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


def spin_dataset(res: TimeRun, system, positions):
    """The results of a free-spin run as an xarray Dataset (the one builder,
    :func:`rubrotor.engine.result.to_dataset`, on the run's outputs at ``positions``).

    Parameters
    ----------
    res : TimeRun
        A free-spin run (:func:`simulate_spin`).
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
    r, n = res.r, res.time.size
    rows = (np.vstack([system.output_rows(x) for x in positions]) @ res.basis
            if len(positions) else np.zeros((0, r)))  # fmt: skip
    q, qd = rows @ res.state[:r], rows @ res.state[r : 2 * r]
    S = len(positions)
    per_station = np.stack([q[0::2], q[1::2], qd[0::2], qd[1::2]], axis=1).reshape(4 * S, n)
    out = dataclasses.replace(res, stations=np.asarray(positions, float),
                              channels=np.concatenate([per_station, res.channels]))  # fmt: skip
    return to_dataset(out)
