"""Time simulation of the rotor under unbalance with rotor-stator contact.

:func:`~rubrotor.engine.simulate.simulate_system` is the array-level entry point (shaft, speed, forces,
integrator); it assembles and diagonalises the modal system (:mod:`rubrotor.engine.shaft_modal`),
plans the run (rows, particular solution, initial state), asks the stepper table
:data:`rubrotor.engine.shaft_steppers.FACTORIES` for the method's chunk function, runs one shared chunk loop
(progress, Ctrl-C, event-buffer growth and status between chunks, never per step) and returns a
``SimulationResult``. :func:`rubrotor.engine.result.to_dataset` turns that into an xarray Dataset.
:class:`PreparedRun` splits that in two, set up once (modal system, rows, coefficients) and run
many times from different start states: the array-level path of sweeps and continuation.
"""

from __future__ import annotations

import math
import sys
import time as _time
from dataclasses import dataclass

import numpy as np

from rubrotor.core.contact import pack_contact
from rubrotor.core.integrate import (
    DIVERGED,
    EVENT_BUFFER_FULL,
    I_EVENTS,
    I_STATUS,
    N_ISTATE,
    OK,
    STATUS,
    _write_sample,
    n_channels,
)
from rubrotor.core.status import Status
from rubrotor.engine.result import TimeRun
from rubrotor.engine.settings import SHAFT_INITIAL_STATES as INITIAL_STATES
from rubrotor.engine.settings import Integrator
from rubrotor.engine.shaft_modal import ModalSystem, assemble_modal, phi_functions
from rubrotor.engine.shaft_steppers import FACTORIES, Plan, Rows, RunState
from rubrotor.errors import InputError
from rubrotor.forces.contact import law_of
from rubrotor.rotors.forces import Contact, ModalDamping, RadialLoad, Unbalance
from rubrotor.rotors.shaft import Shaft

__all__ = [
    "ModalSystem",
    "PreparedRun",
    "RotorState",
    "SimulationResult",
    "TimeRun",
    "assemble",
    "simulate_system",
    "simulate_scenario",
    "simulate",
    "time_run",
    "converge",
    "phi_functions",
]

EVENT_BUFFER = 200_000
"""Initial length of the contact-event buffer; it doubles when full, up to ``EVENT_BUFFER_MAX``."""
EVENT_BUFFER_MAX = 1 << 26
SMALL_OUTPUT = 1 << 26
"""Saved samples of at most this many bytes (64 MiB) are not checked against the free memory."""


def assemble(shaft: Shaft, speed: float, damping: ModalDamping | None = None) -> ModalSystem:
    """Assemble and diagonalise the first-order modal system at spin ``speed`` (rad/s).

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
        Or a :class:`rubrotor.rotors.seed_form.SeedModalSystem` (same interface) for a Timoshenko shaft
        with ``formulation = "seed-eq1"``.
    """
    if shaft.formulation == "seed-eq1" and shaft.theory == "timoshenko":
        from rubrotor.rotors.seed_form import assemble_seed

        return assemble_seed(shaft, speed, damping)
    return assemble_modal(shaft, speed, damping)


@dataclass(frozen=True)
class RotorState:
    """A physical state of the rotor, to start a simulation from (and returned at its end).

    Carried in physical modal coordinates, not in the eigen-coordinates of one speed, so that a
    state can start a run at another speed, clearance, unbalance ... (the eigen-basis and the
    particular solution of the new run are applied to it by :func:`~rubrotor.engine.simulate.simulate_system`).

    Attributes
    ----------
    q : ndarray, complex, shape (n,)
        Generalised coordinates ``q = [P_1, (Psi_1), P_2, ...]`` in the order of
        ``rubrotor.engine.simulate.ModalSystem.q_index``: modal deflections ``v + i w`` (m) and, for Timoshenko
        shafts, modal rotations (rad).
    qd : ndarray, complex, shape (n,)
        Their time derivatives (m/s, rad/s).
    phase : float
        Angle of the unbalance at this state, ``Omega t`` reduced to ``[-pi, pi]`` (rad); 0 (to
        rounding) at the end of a run of a whole number of revolutions.
    """

    q: np.ndarray
    qd: np.ndarray
    phase: float = 0.0


SimulationResult = TimeRun
"""Old name of the seed shaft engine's result: the one :class:`~rubrotor.engine.result.TimeRun`
(``engine = "shaft"``: per station ``v, w, v', w', v'', w''`` rows, then normal and friction
force; ``final_state`` a :class:`RotorState`; ``work``, ``unbalance_force``,
``unbalance_position`` and ``contact`` in its extras)."""


def _start_coordinates(sysm: ModalSystem, start: RotorState, load) -> np.ndarray:
    """Unshifted eigen-coordinates ``y = V^-1 x`` of a start state, turned to unbalance phase 0.

    The run starts with the unbalance at angle 0. A state taken at unbalance angle ``phi`` is
    turned by ``exp(-i phi)`` (every complex coordinate): the isotropic rotor, the annular
    stator and the rotating unbalance are invariant under that rotation, so the turned state
    continues the same motion seen in a frame turned by ``-phi``. A constant radial load breaks
    the symmetry, so with a load the state must be taken at angle 0 (whole revolutions).
    """
    n = sysm.q_index.size
    q = np.asarray(start.q, dtype=complex)
    qd = np.asarray(start.qd, dtype=complex)
    if q.shape != (n,) or qd.shape != (n,) or not np.all(np.isfinite(q) & np.isfinite(qd)):
        raise InputError("start", f"q, qd of shapes {q.shape}, {qd.shape}", f"finite ({n},) arrays")
    turn = complex(math.cos(start.phase), -math.sin(start.phase))
    has_load = load is not None and (load.force_y != 0 or load.force_z != 0)
    if abs(turn - 1) > 1e-6:
        if has_load:
            raise InputError(
                "start.phase", start.phase, "0 (a state after whole revolutions) with a load"
            )
        q, qd = q * turn, qd * turn
    x = np.zeros(sysm.V.shape[0], complex)
    x[sysm.q_index] = q
    x[sysm.qd_index] = qd
    return sysm.Vinv @ x


def _state_of(sysm: ModalSystem, y_full: np.ndarray, phase: float) -> RotorState:
    """The physical state of unshifted eigen-coordinates ``y_full``."""
    x = sysm.V @ y_full
    return RotorState(
        q=x[sysm.q_index].copy(),
        qd=x[sysm.qd_index].copy(),
        phase=math.remainder(phase, 2 * math.pi),
    )


def _start_force(y: np.ndarray, cp: np.ndarray, orows) -> complex:
    """Contact force (N) of the start state (the held force of the first exponential step)."""
    from rubrotor.core.terms import term_force

    rows_d, rows_v, _, _, part_u, part_l, vel_z = orows[:7]
    P = complex(rows_d[0] @ y + part_u[0] + part_l[0])
    V = complex(rows_v[0] @ y + vel_z[0])
    fy, fz, _, _ = term_force(P.real, P.imag, V.real, V.imag, cp)
    return complex(fy, fz)


def contact_parameters(shaft: Shaft, speed: float, contact: Contact | None) -> np.ndarray:
    """The packed contact law the kernels take (:data:`rubrotor.core.contact.CP_FIELDS`).

    Parameters
    ----------
    shaft : Shaft
        The rotor (its radius is the default contact radius, m).
    speed : float
        Spin speed (rad/s); the surface speed is ``radius * speed`` (m/s).
    contact : Contact or None
        The contact; None packs an inactive law.

    Returns
    -------
    ndarray
    """
    if contact is None:
        return pack_contact(0, 0, 1.0, 0.0, 1.0, 0.0, 0, 0.0, 1.0)
    radius = contact.radius if contact.radius is not None else shaft.diameter / 2
    return pack_contact(
        1,
        contact.law_code,
        contact.stiffness,
        contact.damping,
        contact.clearance,
        contact.friction,
        contact.sign_code,
        radius * speed,
        contact.friction_regularization,
    )


def _available_memory() -> int:
    """Bytes of memory available to this process (MemAvailable; 8 GiB when unknown)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 8 << 30


def _check_output_size(nbytes: int, integrator: Integrator) -> None:
    """Refuse, before it starts, a run whose saved samples cannot fit in half the free memory."""
    if nbytes <= SMALL_OUTPUT:
        return  # no need to read /proc/meminfo (0.1 ms) on every short run
    limit = _available_memory() // 2
    if nbytes > limit:
        raise InputError(
            "simulation.revolutions",
            integrator.revolutions,
            f"a run whose saved samples fit in memory: this one needs {nbytes / 2**30:.3g} GiB "
            f"(limit {limit / 2**30:.3g} GiB); lower simulation.revolutions, or save fewer "
            "samples with simulation.save_every / simulation.output_dtau, or a larger "
            "simulation.dtau",
        )


def _check_station(name: str, x: float, length: float) -> float:
    if not (0 < x < length):
        raise InputError(name, x, f"an axial position in (0, {length:g}) m")
    return float(x)


def _check_initial(initial) -> None:
    if initial not in INITIAL_STATES:
        raise InputError("initial.state", initial, " or ".join(f'"{x}"' for x in INITIAL_STATES))


def _check_call(shaft: Shaft, speed, initial: str, track_energy: bool) -> float:
    """The spin speed (rad/s) as a float, after checking the arguments that need no model."""
    _check_initial(initial)
    if track_energy and shaft.formulation == "seed-eq1" and shaft.theory == "timoshenko":
        raise InputError(
            "track_energy", True, 'shaft.formulation = "two-field" (the seed form has no energy)'
        )
    if (
        isinstance(speed, bool)
        or not isinstance(speed, int | float)
        or not (speed > 0 and math.isfinite(speed))
    ):
        raise InputError("speed", speed, "a finite spin speed > 0 (rad/s)")
    return float(speed)


def _positions(shaft: Shaft, integrator: Integrator, unbalance: Unbalance, contact, load):
    """Axial positions (m) of unbalance, contact and load, and the output stations."""
    L = shaft.length
    a_u = _check_station(
        "unbalance.position", unbalance.position if unbalance.position is not None else L / 2, L
    )
    a_c = L / 2
    if contact is not None:
        a_c = _check_station(
            "contact.position", contact.position if contact.position is not None else L / 2, L
        )
    a_l = L / 2
    if load is not None and load.position is not None:
        a_l = _check_station("load.position", load.position, L)
    probes = [_check_station("simulation.probes", p, L) for p in integrator.probes]
    return a_u, a_c, a_l, np.array([a_c, *probes])


def _particular(sysm, speed: float, beta_u, beta_l, fu0: complex, fl: complex, unbalance):
    """Steady unbalance response (at phase 0) and static load response, eigen-coordinates."""
    lam = sysm.lam
    res = 1j * speed - lam
    if np.min(np.abs(res) / np.abs(lam)) < 1e-9 and unbalance.magnitude > 0:
        raise InputError(
            "speed",
            speed,
            "a speed that is not exactly an undamped critical speed (add damping or move it)",
        )
    return beta_u * fu0 / res, -beta_l * fl / lam


def _frame_rows(sysm, stations, speed, beta_c, beta_u, beta_l, fu0, fl, y_u, y_l, shifted):
    """Output rows; the exponential kernels' shifted frame adds the particular solution."""
    lam = sysm.lam
    rows_d = np.array([sysm.displacement_row(x) for x in stations])
    rows_v = np.array([sysm.velocity_row(x) for x in stations])
    n = len(stations)
    if shifted:
        part_u = rows_d @ y_u
        part_l = rows_d @ y_l
        vel_z = 1j * speed * part_u
        acc_z = -(speed**2) * part_u
        acc_c = np.zeros(n, complex)
    else:
        part_u = part_l = vel_z = np.zeros(n, complex)
        acc_z = rows_v @ beta_u * fu0
        acc_c = rows_v @ beta_l * fl
    arrays = (rows_d, rows_v, rows_v * lam[None, :], rows_v @ beta_c, part_u, part_l, vel_z,
              acc_z, acc_c)  # fmt: skip
    return Rows(*(np.ascontiguousarray(a, dtype=complex) for a in arrays))


def _plan(shaft, speed, integrator, unbalance, contact, load, damping, track_energy):
    """Assemble the modal system and everything the steppers read; the output stations (m)."""
    a_u, a_c, a_l, stations = _positions(shaft, integrator, unbalance, contact, load)
    sysm = assemble(shaft, speed, damping)
    beta_c, beta_u, beta_l = (sysm.force_input(a) for a in (a_c, a_u, a_l))
    fu0 = (
        unbalance.magnitude
        * speed**2
        * complex(math.cos(unbalance.phase), math.sin(unbalance.phase))
    )
    fl = complex(load.force_y, load.force_z) if load is not None else 0j
    shifted = integrator.method == "exponential"
    if shifted:
        y_u, y_l = _particular(sysm, speed, beta_u, beta_l, fu0, fl, unbalance)
    else:  # the ABM kernel integrates the unshifted coordinates
        y_u = y_l = np.zeros(sysm.lam.size, complex)
    max_disp = integrator.max_displacement
    if max_disp is None:
        max_disp = 1000 * contact.clearance if contact is not None else 0.1 * shaft.length
    h = integrator.step_seconds(speed)
    plan = Plan(
        sysm=sysm, speed=speed, beta_c=beta_c, beta_u=beta_u, beta_l=beta_l, fu0=fu0, fl=fl,
        y_u=y_u, y_l=y_l, cp=contact_parameters(shaft, speed, contact), max_disp=max_disp,
        rows=_frame_rows(sysm, stations, speed, beta_c, beta_u, beta_l, fu0, fl, y_u, y_l, shifted),
        h=h, H=None if h is not None else integrator.output_spacing(speed),
        save_every=integrator.save_every, rtol=integrator.rtol, atol=integrator.atol,
        track_energy=track_energy, a_u=a_u, a_l=a_l,
    )  # fmt: skip
    return plan, stations


def _initial_y(plan: Plan, method: str, initial: str, start, load) -> tuple[np.ndarray, complex]:
    """Kernel coordinates of the initial state and the contact force (N) it holds."""
    ns = plan.sysm.lam.size
    shifted = method == "exponential"
    if start is not None:
        y = _start_coordinates(plan.sysm, start, load)
        if shifted:
            y = y - (plan.y_u + plan.y_l)
        return y, _start_force(y, plan.cp, plan.rows)
    if shifted:  # shifted coordinates: -(particular solution) is rest, 0 is the steady orbit
        y = -(plan.y_u + plan.y_l) if initial == "rest" else np.zeros(ns, complex)
    else:
        y = np.zeros(ns, complex)
        if initial == "steady":
            lam = plan.sysm.lam
            y = plan.beta_u * plan.fu0 / (1j * plan.speed - lam) - plan.beta_l * plan.fl / lam
    return y, 0j


def _sample_grid(integrator: Integrator, speed: float) -> tuple[int, float]:
    """Number of saved samples after the first and their spacing (s)."""
    t_total = integrator.total_time(speed)
    h = integrator.step_seconds(speed)
    if h is not None:
        n_steps = int(round(t_total / h))
        if n_steps < 1:
            raise InputError(
                "simulation.dtau", integrator.dtau or integrator.dt, "a step shorter than the run"
            )
        n_samples, sample_dt = n_steps // integrator.save_every, h * integrator.save_every
    else:
        sample_dt = integrator.output_spacing(speed)
        n_samples = int(round(t_total / sample_dt))
    if n_samples < 1:
        raise InputError(
            "simulation.revolutions", integrator.revolutions, "a run long enough for one sample"
        )
    return n_samples, sample_dt


def _run_state(plan: Plan, y: np.ndarray, f_start: complex, n_out: int) -> RunState:
    """Fresh kernel state with ``n_out`` sample columns; the first sample written."""
    ns = y.size
    st = RunState(
        y=y, cstate=np.array([f_start, 1 + 0j, 0j, 0j]), istate=np.zeros(N_ISTATE, np.int64),
        counts=np.zeros(3, np.int64), hist=np.zeros((4, ns), complex), work=np.zeros(5),
        out=np.empty((n_channels(plan.rows.d.shape[0]), n_out)), events=np.zeros(EVENT_BUFFER),
    )  # fmt: skip
    _write_sample(st.out, 0, y, 1 + 0j, f_start, plan.cp, plan.rows)
    return st


def _grow_events(st: RunState) -> RunState | None:
    """The state with a doubled event buffer, or None when events were lost or it is at its
    largest (:data:`EVENT_BUFFER_MAX`)."""
    n = st.events.size
    if (
        st.istate[I_STATUS] != EVENT_BUFFER_FULL
        or st.istate[I_EVENTS] > n
        or 2 * n > EVENT_BUFFER_MAX
    ):
        return None
    st.istate[I_STATUS] = OK
    return st._replace(events=np.concatenate([st.events, np.zeros(n)]))


def _progress_line(done: int, n_samples: int, sample_dt: float, speed: float, el: float) -> None:
    frac = done / n_samples
    print(
        f"\rrubrotor: {100 * frac:5.1f} % ({done * sample_dt * speed / (2 * math.pi):.0f} rev)"
        f" {el:.0f} s, ~{el / max(frac, 1e-9) - el:.0f} s left",
        end="",
        file=sys.stderr,
    )


def _loop(chunk, st: RunState, n_samples: int, chunk_samples: int, show: bool, sample_dt, speed):
    """Shared chunk loop: progress between chunks, Ctrl-C, event-buffer growth, status.

    Returns the final state, the samples written after the first, whether the user
    interrupted and the wall time (s).
    """
    t0 = _time.perf_counter()
    done, interrupted = 0, False
    try:
        while done < n_samples:
            done += chunk(st, 1 + done, min(chunk_samples, n_samples - done))
            if st.istate[I_EVENTS] > st.events.size:  # counted, not stored
                st.istate[I_STATUS] = EVENT_BUFFER_FULL
            if st.istate[I_STATUS] != OK:
                grown = _grow_events(st)
                if grown is None:
                    break
                st = grown
                continue
            el = _time.perf_counter() - t0
            if show and el > 2.0:
                _progress_line(done, n_samples, sample_dt, speed, el)
    except KeyboardInterrupt:
        interrupted = True
    if show and _time.perf_counter() - t0 > 2.0:
        print(file=sys.stderr)
    return st, done, interrupted, _time.perf_counter() - t0


def _status_message(status: int, interrupted: bool, t_stop: float, sample_dt, max_disp, st):
    """``""`` for a complete run, else why and where it stopped."""
    if interrupted:
        return f"interrupted by the user after t = {t_stop:.6g} s"
    if status == OK:
        return ""
    where = f"at t = {t_stop + sample_dt:.6g} s; data up to t = {t_stop:.6g} s kept"
    if status == DIVERGED:
        return f"diverged: contact-point displacement exceeded {max_disp:.3g} m {where}"
    if status == EVENT_BUFFER_FULL:
        lost = max(0, int(st.istate[I_EVENTS]) - st.events.size)
        return f"{STATUS[status]} ({st.events.size} contact events, {lost} not stored) {where}"
    return f"{STATUS[status]} {where}"


def _energy_balance(plan: Plan, st: RunState, e0: float, n_out: int, contact) -> dict:
    """Start and end energies and the work of each force (J) of a fixed-step run."""
    y_full = st.y + plan.y_u * st.cstate[1] + plan.y_l
    p_end = st.out[0, n_out - 1] + 1j * st.out[1, n_out - 1]
    u_c = 0.0
    if contact is not None:
        eps = abs(p_end) - contact.clearance
        if eps > 0:
            u_c = law_of(contact).energy(contact.stiffness, eps)
    work = st.work
    return {
        "mechanical_energy_start_J": e0,
        "mechanical_energy_end_J": plan.sysm.energy(y_full),
        "contact_potential_end_J": u_c,
        "work_unbalance_J": work[0],
        "work_load_J": work[1],
        "work_contact_J": work[2],
        "dissipated_modal_damping_J": work[3],
        "work_friction_J": work[4],
        # elastic contact work is minus the potential change (zero at the start)
        "dissipated_contact_damping_J": -(work[2] - work[4]) - u_c,
    }


class PreparedRun:
    """A simulation set up once and run many times: the array-level path (no Dataset).

    Building it checks the arguments, assembles and diagonalises the modal system, solves the
    particular (steady) solution, packs the output rows and the contact law, sizes the sample
    grid and precomputes the stepper's coefficients; :meth:`run` then only allocates the
    output buffers, runs the compiled kernel from a start state and wraps its arrays (no copy)
    in a frozen ``SimulationResult``. :func:`simulate_system` is ``PreparedRun(...).run()``;
    sweeps, follow sweeps and repeated runs of one model (shooting, continuation) build one per
    parameter point and call :meth:`run` for each start state.

    Parameters
    ----------
    shaft, speed, integrator, unbalance, contact, load, damping, track_energy
        As in :func:`simulate_system` (speed in rad/s).

    Attributes
    ----------
    plan : rubrotor.engine.shaft_steppers.Plan
        Modal system, forces, rows and run settings (SI).
    stations : ndarray
        Axial positions (m) of the output stations (contact station first).
    n_samples : int
        Saved samples after the first.
    sample_dt : float
        Spacing of the saved samples (s).
    """

    def __init__(
        self,
        shaft: Shaft,
        speed: float,
        integrator: Integrator,
        unbalance: Unbalance | None = None,
        contact: Contact | None = None,
        load: RadialLoad | None = None,
        damping: ModalDamping | None = None,
        *,
        track_energy: bool = False,
    ) -> None:
        self.speed = _check_call(shaft, speed, "rest", track_energy)
        self.shaft, self.integrator, self.contact, self.load = shaft, integrator, contact, load
        unbalance = unbalance or Unbalance(0.0)
        self.plan, self.stations = _plan(
            shaft, self.speed, integrator, unbalance, contact, load, damping, track_energy
        )
        self.method = integrator.method
        self.n_samples, self.sample_dt = _sample_grid(integrator, self.speed)
        nbytes = n_channels(len(self.stations)) * (self.n_samples + 1) * 8
        _check_output_size(nbytes, integrator)
        self.kind = self.method if self.method == "abm" or self.plan.h is not None else "adaptive"
        # a stepper's coefficients depend on the plan only; with energy tracking it also holds
        # the start state's energy, so it is then rebuilt per run
        self._stepper = None

    @classmethod
    def from_scenario(cls, scenario, integrator: Integrator, *, track_energy: bool = False):
        """The prepared run of a scenario's shaft, speed (rad/s), forces and damping."""
        return cls(scenario.shaft, scenario.speed, integrator, scenario.unbalance,
                   scenario.contact, scenario.load, scenario.damping,
                   track_energy=track_energy)  # fmt: skip

    def _stepper_for(self, st: RunState):
        if self.plan.track_energy:
            return FACTORIES[self.kind](self.plan, st)
        if self._stepper is None:
            self._stepper = FACTORIES[self.kind](self.plan, st)
        return self._stepper

    def run(
        self,
        *,
        initial: str = "rest",
        start: RotorState | None = None,
        progress: bool | None = False,
        chunk_samples: int = 1 << 15,
    ) -> SimulationResult:
        """Run the prepared simulation from rest, the steady orbit or ``start``.

        Parameters
        ----------
        initial : {"rest", "steady"}
            Initial state when ``start`` is None (see :func:`simulate_system`).
        start : RotorState, optional
            Physical state to start from.
        progress : bool, optional
            Progress on stderr for long runs (None: when stderr is a terminal).
        chunk_samples : int
            Samples computed per compiled call.

        Returns
        -------
        SimulationResult
            Frozen; ``channels`` is a view of the kernel's output buffer (no copy).
        """
        _check_initial(initial)
        plan, speed, n_samples, sample_dt = self.plan, self.speed, self.n_samples, self.sample_dt
        y, f_start = _initial_y(plan, self.method, initial, start, self.load)
        st = _run_state(plan, y, f_start, n_samples + 1)
        stepper = self._stepper_for(st)
        show = sys.stderr.isatty() if progress is None else progress
        st, done, interrupted, wall = _loop(
            stepper.chunk, st, n_samples, chunk_samples, show, sample_dt, speed
        )
        code = int(st.istate[I_STATUS])
        complete = code == OK and not interrupted
        n_out, t_stop = 1 + done, done * sample_dt
        integ = self.integrator
        stats = {"method": self.method, "order": integ.order, "modes": self.shaft.modes,
                 "eig_cond": plan.sysm.cond, **stepper.stats, "wall_s": wall,
                 **stepper.counts(st), "contact_events": int(st.istate[I_EVENTS])}  # fmt: skip
        final = None
        if complete:
            final = _state_of(plan.sysm, stepper.full_state(st), speed * t_stop)
        work = {}
        if stepper.e0 is not None:  # energy tracked (fixed-step exponential)
            work = _energy_balance(plan, st, stepper.e0, n_out, self.contact)
        return TimeRun(
            time=np.arange(n_out) * sample_dt,
            stations=self.stations,
            n_contacts=0 if self.contact is None else 1,
            channels=st.out[:, :n_out],
            events=st.events[: min(int(st.istate[I_EVENTS]), st.events.size)].copy(),
            status="complete" if complete else "partial",
            message=_status_message(code, interrupted, t_stop, sample_dt, plan.max_disp, st),
            stats=stats,
            speed=speed,
            final_state=final,
            engine="shaft",
            code=Status(code),
            extras={"work": work, "unbalance_force": plan.fu0,
                    "unbalance_position": plan.a_u, "contact": self.contact},  # fmt: skip
        )


def simulate_system(
    shaft: Shaft,
    speed: float,
    integrator: Integrator,
    unbalance: Unbalance | None = None,
    contact: Contact | None = None,
    load: RadialLoad | None = None,
    damping: ModalDamping | None = None,
    *,
    track_energy: bool = False,
    progress: bool | None = None,
    chunk_samples: int = 1 << 15,
    initial: str = "rest",
    start: RotorState | None = None,
) -> SimulationResult:
    """Simulate the rotor from rest, from its steady no-contact orbit or from a given state.

    ``PreparedRun(shaft, speed, integrator, ...).run(initial=..., start=...)``: build a
    :class:`PreparedRun` yourself to run one model from several start states.

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    speed : float
        Constant spin speed ``Omega`` (rad/s), > 0.
    integrator : Integrator
        Method, steps, length of the run and what to save.
    unbalance : Unbalance, optional
        Rotating unbalance; none by default.
    contact : Contact, optional
        Stator contact; none by default (free rotor).
    load : RadialLoad, optional
        Constant radial load; none by default.
    damping : ModalDamping, optional
        Modal damping ratios; 0 by default (as in the seed).
    track_energy : bool
        Accumulate the work of every force (exponential fixed-step only), for energy checks.
    progress : bool, optional
        Print progress to stderr on runs longer than a few seconds (default: when stderr is a
        terminal).
    chunk_samples : int
        Samples computed per compiled call.
    initial : {"rest", "steady"}
        Initial state: at rest and undeflected (default), or on the steady no-contact orbit
        (the particular solution of unbalance and load, exact in the modal model). Ignored
        when ``start`` is given.
    start : RotorState, optional
        Start from this physical state (e.g. the ``final_state`` of a run at a neighbouring
        parameter value); see :class:`RotorState` for the unbalance angle.

    Returns
    -------
    SimulationResult
        With ``final_state`` (:class:`RotorState`) when the run completed.
    """
    _check_initial(initial)
    prepared = PreparedRun(shaft, speed, integrator, unbalance, contact, load, damping,
                           track_energy=track_energy)  # fmt: skip
    return prepared.run(
        initial=initial, start=start, progress=progress, chunk_samples=chunk_samples
    )


# units of resolved object fields that are not scenario keys (see rubrotor.scenario.KEY_UNITS)
_FIELD_UNITS = {"shaft.kappa": "1", "unbalance.phase": "rad"}


def scenario_parameters(scenario) -> dict:
    """Every parameter of a scenario as ``{"section.key": [value, unit]}`` (SI), for provenance.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The scenario.

    Returns
    -------
    dict
    """
    import dataclasses

    from rubrotor.scenario.load import key_unit

    def unit(key, value=0.0):
        if isinstance(value, bool) or not isinstance(value, int | float | tuple):
            return ""  # names, flags and switches have no unit
        return _FIELD_UNITS.get(key) or key_unit(key)

    out: dict = {}
    sh = scenario.shaft
    for f in dataclasses.fields(sh):
        if f.init:
            val = getattr(sh, f.name)
            out[f"shaft.{f.name}"] = [val, unit(f"shaft.{f.name}", val)]
    out["shaft.shear_modulus"] = [sh.G, "Pa"]
    out["shaft.poisson_ratio"] = [sh.nu, "1"]
    out["shaft.kappa"] = [sh.kappa, "1"]
    out["speed.rad_per_s"] = [scenario.speed, "rad/s"]
    out["initial.state"] = [getattr(scenario, "initial", "rest"), ""]
    for sec in ("unbalance", "load", "contact", "damping", "simulation"):
        obj = getattr(scenario, sec, None)
        if obj is None:
            continue
        for f in dataclasses.fields(obj):
            key = f"{sec}.{f.name}"
            u = unit(key, getattr(obj, f.name))
            if sec == "contact" and f.name == "stiffness":
                u = law_of(obj).stiffness_unit
            if sec == "contact" and f.name == "damping":
                u = law_of(obj).damping_unit
            out[key] = [getattr(obj, f.name), u]
    return out


def simulate_scenario(scenario, integrator: Integrator, **kwargs) -> SimulationResult:
    """:func:`~rubrotor.engine.simulate.simulate_system` on the parts of a scenario (raw arrays, no Dataset).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        Shaft, speed (rad/s), unbalance, contact, load and damping.
    integrator : Integrator
        How to integrate.
    **kwargs
        ``track_energy``, ``progress``, ``chunk_samples`` of :func:`~rubrotor.engine.simulate.simulate_system`.

    Returns
    -------
    SimulationResult
    """
    from rubrotor.modelling import model_of

    model_of(scenario).require_shaft_engine(
        "the seed engine's time simulation (simulate_scenario)"
    )
    return simulate_system(
        scenario.shaft,
        scenario.speed,
        integrator,
        scenario.unbalance,
        scenario.contact,
        scenario.load,
        scenario.damping,
        **({"initial": getattr(scenario, "initial", "rest")} | kwargs),
    )


def simulate(
    scenario,
    *,
    integrator: Integrator | None = None,
    progress: bool | None = None,
    track_energy: bool = False,
):
    """Simulate a scenario and return the results Dataset.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario or path-like
        Shaft, speed, unbalance, load, contact, damping and ``[simulation]`` settings; a path is
        read with :func:`~rubrotor.load_scenario`.
    integrator : Integrator, optional
        Overrides the scenario's ``[simulation]`` section.
    progress : bool, optional
        Print progress on long runs (default: when stderr is a terminal).
    track_energy : bool
        Accumulate the work of every force (fixed-step exponential only).

    Returns
    -------
    xarray.Dataset
        See :func:`rubrotor.engine.result.to_dataset`; ``attrs["status"]`` is ``"complete"`` or
        ``"partial"`` (then ``attrs["status_message"]`` says why and where it stopped).
    """
    from rubrotor.errors import instance_argument
    from rubrotor.modelling import model_of
    from rubrotor.scenario.load import as_scenario

    instance_argument("integrator", integrator, Integrator, "a rubrotor.Integrator (or None: "
                      "the scenario's [simulation] section)")  # fmt: skip
    scenario = as_scenario(scenario)
    runner = model_of(scenario).runner  # the engine the Model chose
    if runner != "shaft" and track_energy:
        raise InputError("track_energy", True, "False with the general engine")
    return _RUNS[runner](scenario, integrator, progress, track_energy)


def _simulate_general(scenario, integrator, progress, track_energy):
    """A general-engine or free-spin scenario (:func:`rubrotor.engine.general.simulate_engine`)."""
    from rubrotor.engine.general import simulate_engine

    return simulate_engine(scenario, integrator=integrator, progress=progress)


def _simulate_shaft(scenario, integrator, progress, track_energy):
    """A scenario of the seed shaft's engine, as a Dataset."""
    from rubrotor.engine.result import to_dataset

    res = _run_shaft(scenario, integrator, progress, track_energy)
    params = scenario_parameters(scenario)
    if integrator is not None:
        import dataclasses

        for f in dataclasses.fields(integrator):
            params[f"simulation.{f.name}"] = [getattr(integrator, f.name), ""]
    return to_dataset(res, params, getattr(scenario, "source", ""), getattr(scenario, "name", ""))


_RUNS = {"shaft": _simulate_shaft, "general": _simulate_general, "free-spin": _simulate_general}
"""Runner (:attr:`rubrotor.modelling.Model.runner`) -> ``(scenario, integrator, progress,
track_energy) -> Dataset``."""


def _run_shaft(scenario, integrator, progress, track_energy):
    integ = integrator or scenario.simulation
    if integ is None:
        raise InputError("simulation", None, "a [simulation] section (revolutions or duration)")
    return simulate_scenario(scenario, integ, track_energy=track_energy, progress=progress)


def _run_general(scenario, integrator, progress, track_energy):
    from rubrotor.engine.general import engine_run

    return engine_run(scenario, integrator=integrator, progress=progress)[0]


def _run_free(scenario, integrator, progress, track_energy):
    from rubrotor.engine.spin import free_run

    return free_run(scenario, integrator)[0]


_TIME_RUNS = {"shaft": _run_shaft, "general": _run_general, "free-spin": _run_free}
"""Runner -> ``(scenario, integrator, progress, track_energy) -> TimeRun``."""


def time_run(
    scenario,
    *,
    integrator: Integrator | None = None,
    progress: bool | None = None,
    track_energy: bool = False,
) -> TimeRun:
    """Run a scenario on the engine its Model chose and return the one result type.

    The array-level twin of ``simulate``: the same run, as a frozen
    :class:`~rubrotor.engine.result.TimeRun` (views of the kernel's buffers, no Dataset) for
    every rotor and engine: the seed shaft's, the general one, the free-spin one.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario or path-like
        The scenario; a path is read with :func:`~rubrotor.load_scenario`.
    integrator : Integrator, optional
        Overrides the scenario's ``[simulation]`` section.
    progress : bool, optional
        Print progress on long runs (default: when stderr is a terminal).
    track_energy : bool
        Accumulate the work of every force (the seed shaft's fixed-step exponential only).

    Returns
    -------
    TimeRun
        ``status`` ``"complete"`` or ``"partial"``, ``code`` from
        ``rubrotor.core.status.Status``, ``message``; ``to_dataset()`` gives a Dataset.
    """
    from rubrotor.modelling import model_of
    from rubrotor.scenario.load import as_scenario

    scenario = as_scenario(scenario)
    runner = model_of(scenario).runner
    if runner != "shaft" and track_energy:
        raise InputError("track_energy", True, "False with the general engine")
    return _TIME_RUNS[runner](scenario, integrator, progress, track_energy)


def converge(
    scenario,
    *,
    dtau: float | None = None,
    halvings: int = 4,
    max_modes: int | None = None,
    revolutions: float | None = None,
    method: str | None = None,
) -> list[dict]:
    """The seed's step and mode convergence procedure.

    Runs the scenario with fixed steps ``dtau, dtau/2, ..., dtau/2^halvings`` (all saved at the
    spacing ``dtau``) with the scenario's modes, then with ``1 .. max_modes`` modes at ``dtau``,
    and reports the difference between successive runs: ``max |P_a - P_b|`` over the run (m) and
    relative to ``max |P_b|``, where ``P = v + i w`` at the contact station.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The scenario; its ``[simulation]`` section gives the method and length unless overridden.
    dtau : float, optional
        Base step (rad of spin); default the scenario's ``dtau`` or 0.001 (the seed's value).
    halvings : int
        Number of step halvings (the seed used 4: down to ``dtau/16``).
    max_modes : int, optional
        Largest mode count compared; default the scenario's.
    revolutions : float, optional
        Length of each run (rev); default the scenario's.
    method : {"exponential", "abm"}, optional
        Integrator; default the scenario's.

    Returns
    -------
    list of dict
        One row per compared pair: ``{"study": "step"|"modes", "a": ..., "b": ..., "max_diff_m": ...,
        "rel_diff": ..., "wall_s": ...}``.
    """
    import dataclasses

    from rubrotor.modelling import model_of
    from rubrotor.scenario.load import as_scenario

    scenario = as_scenario(scenario)
    model_of(scenario).require_shaft_engine("the convergence study")
    base = scenario.simulation or Integrator(revolutions=revolutions or 20)
    dtau = dtau or base.dtau or 1e-3
    revs = revolutions or base.revolutions or base.duration * scenario.speed / (2 * math.pi)
    method = method or base.method
    max_modes = max_modes or scenario.shaft.modes

    def run(shaft, k):
        integ = Integrator(revolutions=revs, method=method, dtau=dtau / 2**k, save_every=2**k)
        t0 = _time.perf_counter()
        r = simulate_system(
            shaft,
            scenario.speed,
            integ,
            scenario.unbalance,
            scenario.contact,
            scenario.load,
            scenario.damping,
            progress=False,
        )
        return r.channels[0] + 1j * r.channels[1], _time.perf_counter() - t0, r.status

    def compare(study, runs):
        """Rows comparing each run of ``runs = [(label, shaft, k), ...]`` with the previous one."""
        rows, prev = [], None
        for label, shaft, k in runs:
            p, wall, status = run(shaft, k)
            if prev is not None:
                n = min(len(p), len(prev[1]))
                diff = float(np.max(np.abs(p[:n] - prev[1][:n])))
                rows.append(
                    {
                        "study": study,
                        "a": prev[0],
                        "b": label,
                        "max_diff_m": diff,
                        "rel_diff": diff / float(np.max(np.abs(p[:n]))),
                        "wall_s": wall,
                        "status": status,
                    }
                )
            prev = (label, p)
        return rows

    steps = [(f"dtau/{2**k}", scenario.shaft, k) for k in range(halvings + 1)]
    modes = [
        (f"{m} modes", dataclasses.replace(scenario.shaft, modes=m), 0)
        for m in range(1, max_modes + 1)
    ]
    rows = compare("step", steps) + compare("modes", modes)
    return rows
