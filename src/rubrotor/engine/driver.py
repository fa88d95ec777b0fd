"""The general engine: any linear rotor, several contacts, flexible offset stators, gravity.

:func:`simulate_general` reduces the rotor (:mod:`rubrotor.engine.reduce`), builds the plant
(rotor modes plus stator modes, contact and output rows, the exact static and unbalance
particular solutions of the FULL model), asks the stepper table :data:`STEPPERS` for the
method's chunk function (each factory precomputes its coefficients once) and runs one shared
chunk/progress/status loop. It returns a frozen :class:`EngineResult`; ``to_dataset()`` makes
the xarray Dataset.

State shift
-----------
The kernel integrates ``x~ = x - x_s - x_p(t)``: ``x_s = [K^-1 f_s, 0]`` the exact static
deflection under gravity and constant loads, ``x_p = Re([Q, i Omega Q] e^{i Omega t})`` with
``Q = (K - Omega^2 M + i Omega D)^-1 b_u`` the exact steady unbalance response (both of the full
model, so they carry no truncation error); the reduced modes then only carry the transient and
the contact response.
"""

from __future__ import annotations

import dataclasses
import json
import math
import signal
import sys
import threading
import time as _time
from dataclasses import dataclass, field

import numpy as np

from rubrotor.core.engine import (
    CONTACT_CHANNELS,
    EVENT_BUFFER_FULL,
    I_ACCEPTED,
    I_EVENTS,
    I_GRAZE,
    I_NEWTON,
    I_REJECTED,
    I_STATUS,
    I_STEP,
    I_SUBSTEPS,
    N_ISTATE,
    NEWTON_FAILED,
    OK,
    STATUS_NAMES,
    expo_fixed,
)
from rubrotor.core.engine_adaptive import (
    LEVELS_UP,
    N_TSTATE,
    T_FILLS,
    T_FREE,
    T_HPREV,
    T_TIME,
    expo_adaptive,
)
from rubrotor.core.status import Status
from rubrotor.core.terms import ROW_WIDTH, length_scales
from rubrotor.engine import restart
from rubrotor.engine.parts import (
    RubStation,
    Run,
    speed_at,
    spin_angle,
)
from rubrotor.engine.reduce import (
    IllConditioned,
    Modes,
    RitzBasis,
    basis_from_modes,
    reduce_auto,
    reduce_matrices,
    reduce_projected,
)
from rubrotor.engine.restart import physical_state
from rubrotor.engine.result import TimeRun, _jsonable, to_dataset
from rubrotor.engine.settings import ADAPTIVE_LEVELS
from rubrotor.engine.shaft_modal import phi_functions
from rubrotor.engine.stream import NetcdfSink, check_size
from rubrotor.engine.structs import (
    Contacts,
    Control,
    Drive,
    Outputs,
    Plan,
    Sink,
    State,
    Steps,
    span,
)
from rubrotor.errors import InputError
from rubrotor.forces.terms import Terms
from rubrotor.forces.unbalance import unbalance_load
from rubrotor.rotors.scales import explain

__all__ = ["Plant", "EngineResult", "build_plant", "simulate_general", "result_dataset", "STEPPERS"]

DEFAULT_ADAPTIVE = "collocation"
"""The stepper of a run with ``rtol`` when no method is named."""
EVENT_BUFFER = 1 << 16
EVENT_BUFFER_MAX = 1 << 26


@dataclass(frozen=True)
class Plant:
    """The reduced rotor, its stators and every row the kernels read (SI)."""

    lam: np.ndarray  # (ns,) rotor modes then stator modes
    beta: np.ndarray  # (ns, m) modal input per N of contact force on the rotor
    contacts: Contacts
    outputs: Outputs
    stations: np.ndarray  # output positions (m): contacts, then probes
    y0: np.ndarray  # initial modal state
    rotor: Modes
    n_rotor: int
    q_static: np.ndarray  # (n,) m or rad
    q_unbalance: np.ndarray  # (n,) complex amplitude of the steady unbalance response
    speed: float
    Bmat: np.ndarray  # (n, m) force map of the row forces
    n_contacts: int = 0  # rows 0 .. n_contacts - 1 are contacts, the rest supports
    supports: tuple = ()  # support rows (``FilmRow``), after the contacts


def _stator_modes(st: RubStation):
    if st.stator is None:
        return None
    M, C, K = st.stator.matrices()
    return reduce_matrices(M, C, K)


class NearCritical(InputError):
    """The dynamic stiffness at the spin speed is singular to rounding (reciprocal condition
    number ``rcond`` of the equilibrated matrix)."""

    def __init__(self, speed: float, rcond: float):
        self.reason = f"the dynamic stiffness at {speed:g} rad/s is singular (rcond {rcond:.3g})"
        super().__init__("speed", speed, "a speed off an undamped critical speed (add damping)")


def _particular(sm, b_u: np.ndarray, speed: float) -> np.ndarray:
    """Steady unbalance response ``(K - Omega^2 M + i Omega D)^-1 b_u``: one LU of the matrix
    equilibrated by its diagonal, ``S A S`` with ``S = |diag A|^-1/2``, whose condition number
    (LAPACK ``gecon``) tells a speed on an undamped critical from a matrix with a few large
    entries (a bearing far stiffer than the shaft: unscaled, its rcond fell below 1e-14 at
    any speed)."""
    import scipy.linalg

    if not np.any(b_u):
        return np.zeros(len(b_u), complex)
    dyn = sm.K - speed**2 * sm.M + 1j * speed * sm.damping
    d = np.abs(np.diag(dyn))
    s = 1.0 / np.sqrt(np.where(d > 0, d, 1.0))
    dyn = dyn * s[:, None] * s[None, :]
    lu = scipy.linalg.lu_factor(dyn, check_finite=False)
    rcond = scipy.linalg.lapack.zgecon(lu[0], np.abs(dyn).sum(axis=0).max(), norm="1")[0]
    if not rcond > 1e-14:
        raise NearCritical(speed, rcond)
    return s * scipy.linalg.lu_solve(lu, s * b_u, check_finite=False)


def _initial(run: Run, modes: Modes, q_s, Q, speed) -> np.ndarray:
    n = len(q_s)
    x_s = np.concatenate([q_s, np.zeros(n)])
    x_p = np.concatenate([Q.real, (1j * speed * Q).real])
    if isinstance(run.initial, str):
        shift = {"rest": -(x_s + x_p), "static": -x_p, "steady": np.zeros(2 * n)}[run.initial]
    else:
        x = np.asarray(run.initial, float)
        if x.shape != (2 * n,):
            raise InputError("initial.state", x.shape, f"a state [q, q'] of shape ({2 * n},)")
        if not np.all(np.isfinite(x)):
            bad = int(np.flatnonzero(~np.isfinite(x))[0])
            raise InputError("initial.state", f"{x[bad]} at index {bad}", "finite values")
        shift = x - x_s - x_p
    return modes.project(shift)


def build_plant(system, run: Run, stations=(), unbalances=(), loads=(), gravity=(0.0, 0.0),
                basis=None, dense=False, supports=()):  # fmt: skip
    """Reduce the rotor and assemble rows, particular solutions and initial state.

    Parameters
    ----------
    system : rubrotor.rotors.linear.LinearSystem
        The rotor.
    run : Run
        Speed (rad/s), reduction, initial state, probes (m).
    stations : sequence of RubStation
        Contact stations.
    unbalances : sequence of rubrotor.rotors.forces.Unbalance
        Unbalance planes (positions required, m; magnitudes kg m; phases rad).
    loads : sequence of rubrotor.rotors.forces.RadialLoad
        Constant point loads (N) at positions (m).
    gravity : (float, float)
        ``(g_y, g_z)`` (m/s^2) on the rotor's masses (not on the stators).
    basis : rubrotor.engine.reduce.RitzBasis, optional
        Diagonalise the system projected on this basis (run-up segments) instead of the full
        model (:func:`rubrotor.engine.reduce.reduce_auto`: a few modes of a large model by
        ARPACK, otherwise a dense eigen-decomposition).
    dense : bool
        Always the dense eigen-decomposition (modes exact to rounding, not to ARPACK's
        tolerance: for maps compared across key values, as in continuation).
    supports : sequence of rubrotor.forces.film_row.FilmRow
        Nonlinear supports whose linearisation is in ``system``: rows after the contacts, their
        stations saved after the probes, their constant part in the static load.

    Returns
    -------
    Plant
    """
    speed = float(run.speed)
    sm = system.matrices(speed)
    nc = len(stations) + len(supports)
    m = 2 * nc
    Bc = [system.force_map(s.contact.position) for s in stations]
    Bc += [system.force_map(b.position) for b in supports]
    Bmat = np.hstack(Bc) if nc else np.zeros((sm.M.shape[0], 0))
    try:
        if basis is not None:
            modes = reduce_projected(sm.M, sm.damping, sm.K, basis, run.modes, run.cutoff)
        elif dense:
            modes = reduce_matrices(sm.M, sm.damping, sm.K, run.modes, run.cutoff)
        else:
            modes = reduce_auto(sm.M, sm.damping, sm.K, run.modes, run.cutoff, fmap=Bmat)
    except IllConditioned as exc:  # name the scenario key far off the rotor's scale, if any
        raise explain(exc, system.scales) from None
    Rq, Rv = (modes.Rq, modes.Rv) if run.residual else (0 * modes.Rq, 0 * modes.Rv)
    st_modes = [_stator_modes(s) for s in stations] + [None] * len(supports)
    nsr = modes.size
    ns = nsr + sum(s.size for s in st_modes if s is not None)
    lam = np.concatenate([modes.lam] + [s.lam for s in st_modes if s is not None])
    beta = np.zeros((ns, m), complex)
    beta[:nsr] = modes.input(Bmat)
    Cd = np.zeros((m, ns), complex)
    Cd[:, :nsr] = Bmat.T @ modes.Vq
    Sd = np.zeros((m, ns), complex)
    o = nsr
    for i, sm_i in enumerate(st_modes):
        if sm_i is None:
            continue
        k = sm_i.size
        beta[o : o + k, 2 * i : 2 * i + 2] = sm_i.input(-np.eye(2))
        Sd[2 * i : 2 * i + 2, o : o + k] = sm_i.Vq
        o += k
    Cd = Cd - Sd
    terms = Terms(tuple(stations), tuple(unbalances), tuple(loads), tuple(gravity))
    b_u = terms.unbalance_load(system, speed)
    try:
        Q = _particular(sm, b_u, speed)
    except NearCritical as exc:  # name the scenario key far off the rotor's scale, if any
        raise explain(exc, system.scales) from None
    f_s = terms.static_load(system)
    for i, b in enumerate(supports):  # the supports' constant part: F0 + K0 P0
        f_s = f_s + Bc[len(stations) + i] @ b.static_force(speed)
    q_s = np.linalg.solve(sm.K, f_s) if np.any(f_s) else np.zeros_like(f_s)
    offs = np.array([[s.offset_y, s.offset_z] for s in stations] + [[0.0, 0.0]] * len(supports))
    offs = offs.ravel()
    Pu = Bmat.T @ Q
    cps = terms.contact_rows(speed)
    if supports:
        cps = np.vstack([np.pad(cps, ((0, 0), (0, ROW_WIDTH - cps.shape[1]))),
                         [b.row(speed) for b in supports]])  # fmt: skip
    max_d = run.max_displacement or (
        1000 * max((s.contact.clearance for s in stations), default=0.0)
        or 10 * max((b.scale for b in supports), default=0.0)
        or 0.1 * system.basis.length
    )
    contacts = Contacts(
        Cd=np.ascontiguousarray(Cd), Cv=np.ascontiguousarray(Cd * lam[None, :]),
        Rd=Bmat.T @ Rq @ Bmat, Rv=Bmat.T @ Rv @ Bmat, Pu=Pu, Pv=1j * speed * Pu,
        d0=Bmat.T @ q_s - offs, cp=cps, max_disp=float(max_d),
    )  # fmt: skip
    positions = np.array([s.contact.position for s in stations] + list(run.probes)
                         + [b.position for b in supports], float)  # fmt: skip
    orow = np.vstack([system.output_rows(x) for x in positions]) if len(positions) else None
    if orow is None:
        raise InputError(
            "simulation.probes", list(run.probes) or None, "at least one station (m) to save "
            "when the rotor has no [[contact]] (whose station is saved otherwise)"
        )  # fmt: skip
    Od = np.zeros((len(orow), ns), complex)
    Od[:, :nsr] = orow @ modes.Vq
    outputs = Outputs(
        Od=Od, Ov=Od * lam[None, :], ORd=orow @ Rq @ Bmat, ORv=orow @ Rv @ Bmat,
        OPu=orow @ Q, OPv=1j * speed * (orow @ Q), Od0=orow @ q_s,
        Sd=np.ascontiguousarray(Sd), Sv=np.ascontiguousarray(Sd * lam[None, :]),
        flex=np.array([float(s.stator is not None) for s in stations] + [0.0] * len(supports)),
    )  # fmt: skip
    y0 = np.zeros(ns, complex)
    y0[:nsr] = _initial(run, modes, q_s, Q, speed)
    return Plant(lam, beta, contacts, outputs, positions, y0, modes, nsr, q_s, Q, speed, Bmat,
                 len(stations), tuple(supports))  # fmt: skip


def stiffness_hint(plant: Plant, h: float, status: int) -> str:
    """Why a contact solve can fail: a contact far stiffer than the step resolves.

    ``k_e |S_d|`` compares the contact's stiffness ``k_e = F(g) / g`` (N/m, its force at one
    clearance of penetration over that clearance) with the step's compliance ``|S_d|`` (m/N,
    the largest sensitivity of the contact displacement to its force over a step ``h``).
    Above 1 the step cannot follow the contact's own oscillation, and far above (``> 1e6``)
    the law's force is the penetration's round-off times ``k``. Returns ``""`` (also when the
    kernel's ``status`` is not a failed contact solve) or a hint naming ``contact[i].stiffness``
    and ``simulation.dt``.
    """
    c = plant.contacts
    if status != NEWTON_FAILED or c.cp.shape[0] == 0:
        return ""
    Sd = _steps(plant, h, 1).Sd[0]
    worst, which = 0.0, 0
    for i in range(plant.n_contacts):
        ks = c.cp[i, 9] / c.cp[i, 4] * np.max(np.abs(Sd[2 * i : 2 * i + 2, 2 * i : 2 * i + 2]))
        if ks > worst:
            worst, which = ks, i
    if worst <= 1.0:
        return ""
    return (
        f" (contact[{which + 1}] is {worst:.2g} times stiffer than a step of {h:.3g} s "
        f"resolves: lower contact[{which + 1}].stiffness or simulation.dt)"
    )


def _steps(plant: Plant, h0: float, levels: int) -> Steps:
    """Per-level exponential coefficients for ``h_l = h0 / 2^l`` (first-order force hold)."""
    hs = h0 / 2.0 ** np.arange(levels)
    z = np.outer(hs, plant.lam)
    p1, p2 = phi_functions(z.ravel())
    p1, p2 = p1.reshape(z.shape), p2.reshape(z.shape)
    E = np.exp(z)
    G0 = hs[:, None] * (p1 - p2)
    G1 = hs[:, None] * p2
    beta = plant.beta
    bG0 = G0[:, :, None] * beta[None]
    bG1 = G1[:, :, None] * beta[None]
    c = plant.contacts
    CdE = c.Cd[None] * E[:, None, :]
    CvE = c.Cv[None] * E[:, None, :]
    return Steps(
        E=E, G0=G0, G1=G1, BT=np.ascontiguousarray(beta.T), CdE=CdE, CvE=CvE,
        CdG0b=np.real(np.einsum("rj,ljc->lrc", c.Cd, bG0)),
        CvG0b=np.real(np.einsum("rj,ljc->lrc", c.Cv, bG0)),
        Sd=np.real(np.einsum("rj,ljc->lrc", c.Cd, bG1)) + c.Rd[None],
        Sv=np.real(np.einsum("rj,ljc->lrc", c.Cv, bG1)) + c.Rv[None],
        rot=np.exp(1j * plant.speed * hs), h=hs,
    )  # fmt: skip


@dataclass
class _Chunks:
    """Mutable run state shared by the loop and one stepper (not returned to users)."""

    out: np.ndarray
    ys: np.ndarray
    events: np.ndarray
    istate: np.ndarray = field(default_factory=lambda: np.zeros(N_ISTATE, np.int64))
    flushed: int = 0  # events already handed to a sink (streamed runs)
    kernel: dict | None = None  # the stepper's kernel state (restartable steppers only)


@dataclass(frozen=True)
class Problem:
    """What is simulated besides the run settings (see :func:`build_plant`)."""

    system: object
    stations: tuple
    unbalances: tuple
    loads: tuple
    gravity: tuple
    supports: tuple = ()


def _no_drive(ns: int) -> Drive:
    z = np.zeros(ns, complex)
    return Drive(z, z, z, 0.0, 0.0, 0.0)


def _kernel_state(plant: Plant, run: Run):
    m = plant.beta.shape[1]
    return dict(y=plant.y0.copy(), F=np.zeros(m), Fp=np.zeros(m), dprev=np.zeros(m // 2),
                zt=np.ones(1, complex), hp=np.array([run.step]))  # fmt: skip


def _state(k: dict, clock: np.ndarray, chunks) -> State:
    """The kernels' :class:`State` of the kernel arrays ``k`` with ``clock`` (``zt`` or ``tst``)."""
    return State(k["y"], k["F"], k["Fp"], k["dprev"], clock, chunks.istate, k["hp"])


def _sink(chunks) -> Sink:
    """The kernels' :class:`Sink`: the chunk buffers (replaced when the event buffer grows)."""
    return Sink(chunks.out, chunks.ys, chunks.events)


def _first_sample(state, k, plant):
    from rubrotor.core.engine import _write

    nc = len(plant.outputs.flex)
    _write(_sink(state), 0, k["y"], k["zt"][0], (k["F"], np.zeros(nc), np.zeros(nc)),
           plant.contacts, plant.outputs)  # fmt: skip


def _control(plant: Plant, steps: Steps, run: Run) -> Control:
    """Adaptive control constants (off for fixed steps)."""
    if run.rtol is None:
        return Control(0.0, 0.0, 0.0, 0.0, np.zeros(len(steps.h)))
    c = plant.contacts
    a_f = float(np.max(np.abs(np.real(c.Cv @ plant.beta)).sum(axis=1), initial=0.0))
    errc = np.abs(steps.CdG0b).sum(axis=2).max(axis=1) if c.Cd.shape[0] else np.zeros(len(steps.h))
    return Control(1.0, float(run.rtol), float(run.atol), a_f, np.ascontiguousarray(errc))


def _plan(plant: Plant, run: Run, levels: int, order: int = 2) -> Plan:
    """The adaptive kernel's plan: look-ahead rows and empty per-level tables (filled on use)
    for contact steps of ``order`` 2 (linear force hold) or 4 (quadratic collocation)."""
    lam, beta, c = plant.lam, plant.beta, plant.contacts
    ns, m = beta.shape
    L = LEVELS_UP + levels + 1
    o2, o4 = (L, 1)[order == 4], (1, L)[order == 4]  # the other order's tables stay 1 row
    tab = (np.zeros((o2, ns), complex), np.zeros((o2, ns), complex), np.zeros((o2, ns), complex),
           np.zeros((o2, m, ns), complex), np.zeros((o2, m, ns), complex), np.zeros((o2, m, m)),
           np.zeros((o2, m, m)), np.zeros((o2, m, m)), np.zeros((o2, m, m)))  # fmt: skip
    tab4 = (np.zeros((o4, ns), complex), np.zeros((o4, ns), complex),
            np.zeros((o4, 6, ns), complex), *(np.zeros((o4, m, ns), complex) for _ in range(4)),
            np.zeros((o4, 2 * m, m)), np.zeros((o4, 2 * m, m)), np.zeros((o4, 2 * m, 2 * m)),
            np.zeros((o4, 2 * m, 2 * m)))  # fmt: skip
    gmin = float(np.min(length_scales(c.cp))) if m else 0.0
    H = float(run.step)
    return Plan(
        lam=lam, BT=np.ascontiguousarray(beta.T),
        Wd=np.ascontiguousarray(c.Cd[:, None, :] * beta.T[None]),
        Wv=np.ascontiguousarray(c.Cv[:, None, :] * beta.T[None]),
        Ca=np.ascontiguousarray(np.abs(c.Cd * lam[None, :] ** 2)), EH=np.exp(lam * H), H=H,
        J=levels - 1, hmin=H / 2.0 ** (levels - 1), tol_x=1e-3 * (run.atol + run.rtol * gmin),
        have=np.zeros(L, np.int64), tab=tab, order=order, tab4=tab4,
    )  # fmt: skip


def _adaptive_factory(problem: Problem, plant: Plant, run: Run, state: _Chunks, order=2):
    """Adaptive steps (``run.rtol``): exact free flight to each sample or located onset,
    contact steps by the error estimate alone, samples from the steps' interpolants
    (:func:`rubrotor.core.engine_adaptive.expo_adaptive`). Stepper ``"free-flight"``: the
    contact force held linear over a step (order 2); ``order=4`` is ``"collocation"``."""
    if run.rtol is None:
        name = "collocation" if order == 4 else "free-flight"
        raise InputError("simulation.rtol", None, f'a relative tolerance > 0 for method "{name}"')
    levels = max(run.sublevels, ADAPTIVE_LEVELS - 1) + 1
    plan = _plan(plant, run, levels, order)
    c = plant.contacts
    a_f = float(np.max(np.abs(np.real(c.Cv @ plant.beta)).sum(axis=1), initial=0.0))
    control = Control(1.0, float(run.rtol), float(run.atol), a_f, np.zeros(1))
    k = _kernel_state(plant, run)
    tst = np.zeros(N_TSTATE)
    tst[T_HPREV] = run.step
    k["tst"] = tst
    state.kernel = k

    stats = {"step_s": run.step, "min_step_s": plan.hmin, "adaptive": True}

    def chunk(offset: int, count: int, done: int) -> int:
        wrote = expo_adaptive(_state(k, tst, state), span(count, 1, offset, plant.speed),
                              _sink(state), plan, c, plant.outputs, control)  # fmt: skip
        # the counters after every chunk: the result's stats hold them however the run ends
        stats["free_advances"] = int(tst[T_FREE])
        stats["coefficient_fills"] = int(tst[T_FILLS])
        return wrote

    def final():
        z = np.exp(1j * plant.speed * tst[T_TIME])
        return physical_state(plant, k["y"], k["F"], z)

    return chunk, lambda: _first_sample(state, k, plant), stats, final


def _collocation_factory(problem: Problem, plant: Plant, run: Run, state: _Chunks):
    """Stepper ``"collocation"``: the ``"free-flight"`` stepper (exact free flight, located
    onsets, samples from the steps' interpolants) with contact steps of order 4: the force held
    quadratic through its values at the step's start, midpoint and end, both new values solved
    implicitly (exponential Lobatto collocation); error from the force's fourth difference."""
    return _adaptive_factory(problem, plant, run, state, order=4)


def _fixed_factory(problem: Problem, plant: Plant, run: Run, state: _Chunks):
    """Stepper ``"exponential"``: fixed steps, contact solve sub-steps where Newton fails; with
    ``run.rtol`` adaptive steps (dyadic subdivisions of the output spacing ``run.step``)."""
    levels = run.sublevels + 1 if run.rtol is None else max(run.sublevels, ADAPTIVE_LEVELS - 1) + 1
    steps = _steps(plant, run.step, levels)
    control = _control(plant, steps, run)
    k = _kernel_state(plant, run)
    state.kernel = k
    drive = _no_drive(plant.lam.size)

    def chunk(offset: int, count: int, done: int) -> int:
        return expo_fixed(_state(k, k["zt"], state), span(count, run.save_every, offset,
                          plant.speed), _sink(state), steps, plant.contacts, plant.outputs, drive,
                          control)  # fmt: skip

    stats = {"step_s": run.step, "min_step_s": float(steps.h[-1]), "adaptive": run.rtol is not None}

    def final():
        return physical_state(plant, k["y"], k["F"], k["zt"][0])

    return chunk, lambda: _first_sample(state, k, plant), stats, final


def _transfer(y, F, a: Plant, b: Plant) -> np.ndarray:
    """Modal state on plant ``b`` of the physical state held by ``y`` on plant ``a``."""
    n = a.q_static.size
    ya = y[: a.n_rotor]
    fq = a.Bmat @ F
    q = np.real(a.rotor.Vq @ ya) + a.rotor.Rq @ fq + a.q_static
    qd = np.real(a.rotor.Vq @ (a.rotor.lam * ya)) + a.rotor.Rv @ fq
    x = np.concatenate([q - b.q_static - b.rotor.Rq @ fq, qd - b.rotor.Rv @ fq])
    out = np.empty(b.lam.size, complex)
    out[: b.n_rotor] = b.rotor.project(x)
    out[b.n_rotor :] = y[a.n_rotor :]
    assert x.size == 2 * n
    return out


def _runup_basis(problem: Problem, run: Run, plant: Plant) -> RitzBasis | None:
    """The fixed basis the run-up's segments are projected on (``run.runup_reduction ==
    "ritz"``), or ``None`` to re-diagonalise the full model (``"full"``, or every mode kept).

    The basis spans the kept modes (right and left displacement vectors) at the start, middle
    and end speeds and the static responses to unit forces at the contacts and unbalance
    planes at those speeds (:func:`rubrotor.engine.reduce.basis_from_modes`)."""
    if run.runup_reduction == "full" or (run.modes is None and run.cutoff is None):
        return None
    system = problem.system
    fmap = np.hstack([plant.Bmat] + [system.force_map(u.position) for u in problem.unbalances])
    mods, Ks = [], []
    _, ww = run.speed_profile()
    for w in (ww.min(), 0.5 * (ww.min() + ww.max()), ww.max()):
        sm = system.matrices(w)
        mods.append(reduce_auto(sm.M, sm.damping, sm.K, run.modes, run.cutoff, fmap=fmap))
        Ks.append(sm.K)
    return basis_from_modes(mods, Ks, fmap)


def _runup_segments(run: Run, dt: float):
    """Segment bounds (sample indices), the profile's break samples and, per profile interval,
    the drive's ``(omega0 (rad/s), alpha (rad/s^2), phase (rad))``.

    Each interval of the piecewise-linear speed profile is cut into segments of at most
    ``run.speed_step`` speed change (equal in time, rounded to samples), so no segment straddles
    a break. In interval ``i`` the kernel's drive sees ``Omega = omega0 + alpha t`` and the spin
    angle ``omega0 t + alpha t^2 / 2`` from ``t = 0``; ``phase`` adds what the earlier intervals
    turned beyond that, so the unbalance phase is the exact integral of the profile."""
    tt, ww = run.speed_profile()
    n_total = int(math.floor(run.duration / dt + 1e-9))
    brk = np.minimum(np.rint(tt / dt).astype(np.int64), n_total)
    bounds = [0]
    drives = []
    for i in range(tt.size - 1):
        n_i = max(1, math.ceil(abs(ww[i + 1] - ww[i]) / run.speed_step - 1e-9))
        n_i = min(n_i, max(1, int(brk[i + 1] - brk[i])))
        bounds += [int(round(brk[i] + (brk[i + 1] - brk[i]) * (j + 1) / n_i)) for j in range(n_i)]
        alpha = (ww[i + 1] - ww[i]) / (tt[i + 1] - tt[i])
        om0 = ww[i] - alpha * tt[i]
        phase = float(spin_angle(run, tt[i])) - (om0 * tt[i] + 0.5 * alpha * tt[i] ** 2)
        drives.append((om0, alpha, phase))
    bounds[-1] = max(bounds[-1], n_total)
    return np.unique(np.array(bounds, np.int64)), brk[:-1], drives


def _runup_factory(problem: Problem, plant: Plant, run: Run, state: _Chunks):
    """Stepper for a speed varying in time: linearly from ``run.speed`` to ``run.speed_end``, or
    piecewise linearly through ``run.speed_table`` (``Run.speed_profile``).

    The speed is frozen within each segment (speed change at most ``run.speed_step``), whose
    modes are those at its mid-speed; the state is carried across segments as the physical
    state. The unbalance (with its angular-acceleration term) is an exact modal input per step
    (``Drive``).

    Re-diagonalisation (``run.runup_reduction``), chosen by the measurements in
    ``docs/guide/simulation.md``: ``"ritz"`` (default when modes are dropped) projects ``M``, ``C + Omega
    G`` and the supports at each segment's speed on one fixed basis (:func:`_runup_basis`,
    some ``2 (modes + stations)`` to ``6 (modes + stations)`` vectors) and diagonalises that
    small system; ``"full"`` re-diagonalises the full model at every segment. Both agree with
    the full-DOF SciPy reference to the same error (the frozen-speed error per segment
    dominates), and the Ritz route costs a small eigenproblem per segment instead of a
    ``2 n``-sized one. With every mode kept there is nothing to project: the full route.
    """
    dt = run.step * run.save_every
    bounds, brk, drives = _runup_segments(run, dt)
    n_seg = bounds.size - 1
    k = _kernel_state(plant, run)
    cur = {"index": -1, "plant": plant}
    b0 = unbalance_load(problem.system, problem.unbalances, 1.0)
    basis = _runup_basis(problem, run, plant)

    def segment(index: int):
        t_mid = 0.5 * (bounds[index] + bounds[index + 1]) * dt
        w = float(speed_at(run, t_mid)[0])
        r = dataclasses.replace(run, speed=w, speed_table=None, speed_end=None,
                                initial=run.initial if index == 0 else "static")  # fmt: skip
        new = build_plant(problem.system, r, problem.stations, (), problem.loads, problem.gravity,
                          basis=basis)  # fmt: skip
        if cur["index"] >= 0:
            k["y"] = _transfer(k["y"], k["F"], cur["plant"], new)
        else:
            k["y"] = new.y0.copy()
        ub = np.zeros(new.lam.size, complex)
        ub[: new.n_rotor] = new.rotor.U @ b0
        u_conj = np.zeros(new.lam.size, complex)
        u_conj[: new.n_rotor] = new.rotor.U @ b0.conj()
        # the profile's interval holding this segment (segments never straddle a break)
        om0, alpha, phase = drives[np.searchsorted(brk, bounds[index], side="right") - 1]
        rot = complex(math.cos(phase), math.sin(phase))
        drive = Drive(new.lam, 0.5 * ub * rot, 0.5 * u_conj * rot.conjugate(), om0, alpha, 1.0)
        steps = _steps(new, run.step, run.sublevels + 1)
        cur.update(index=index, plant=new, steps=steps, drive=drive,
                   control=Control(0.0, 0.0, 0.0, 0.0, np.zeros(len(steps.h))))  # fmt: skip

    segment(0)

    def chunk(offset: int, count: int, done: int) -> int:
        index = int(np.searchsorted(bounds, done, side="right")) - 1
        if index != cur["index"]:
            segment(index)
        count = min(count, int(bounds[index + 1]) - done)
        p = cur["plant"]
        return expo_fixed(_state(k, k["zt"], state), span(count, run.save_every, offset, p.speed),
                          _sink(state), cur["steps"], p.contacts, p.outputs, cur["drive"],
                          cur["control"])  # fmt: skip

    stats = {"step_s": run.step, "segments": n_seg, "speed_end_rad_s": run.speed_end,
             "angular_acceleration_rad_s2": [float(d[1]) for d in drives],
             "runup_reduction": "full" if basis is None else "ritz",
             "ritz_basis_size": 0 if basis is None else basis.T.shape[1]}  # fmt: skip

    def final():
        return physical_state(cur["plant"], k["y"], k["F"], 1.0)

    return chunk, lambda: _first_sample(state, k, cur["plant"]), stats, final


STEPPERS = {
    "exponential": _fixed_factory,
    "free-flight": _adaptive_factory,
    "collocation": _collocation_factory,
    "runup": _runup_factory,
}
"""Method name -> factory ``(problem, plant, run, state) -> (chunk, first_sample, stats, final)``."""


EngineResult = TimeRun
"""Old name of the general engine's result: the one :class:`~rubrotor.engine.result.TimeRun`
(``engine = "general"``: per station ``v, w, v', w'`` rows, then per contact the stator's
motion and force rows; ``final_state`` the rotor state ``[q, q']`` on the free DOFs at the end
of the last completed chunk, ``restart`` the full restart state)."""


class _Signals:
    """SIGINT and SIGTERM noted while running, acted on between chunks (so never inside a
    file write); the previous handlers are restored on exit. Only in the main thread, and a
    signal the process ignores stays ignored."""

    NAMES = {
        signal.SIGINT: "interrupted by the user (SIGINT)",
        signal.SIGTERM: "terminated (SIGTERM)",
    }

    def __enter__(self):
        self.got, self.old = None, {}
        if threading.current_thread() is threading.main_thread():
            for sig in self.NAMES:
                if signal.getsignal(sig) is not signal.SIG_IGN:
                    self.old[sig] = signal.signal(sig, self._note)
        return self

    def _note(self, signum, frame) -> None:
        self.got = signum

    def __exit__(self, *exc) -> None:
        for sig, handler in self.old.items():
            signal.signal(sig, handler)


def _first_bad(block: np.ndarray) -> int | None:
    """Index of the first sample (column) holding a non-finite value, or ``None``."""
    ok = np.isfinite(block).all(axis=0)
    return None if ok.all() else int(np.argmin(ok))


def _loop(chunk, n_samples: int, state: _Chunks, progress: bool, sample_dt: float, sink=None,
          checkpoint=None):  # fmt: skip
    """Shared chunk loop: progress between chunks, SIGINT/SIGTERM, event-buffer growth, status.

    Without ``sink`` the samples fill ``state.out`` in place; with one, every chunk is written
    at the start of the (chunk-sized) buffer and handed to ``sink.write``. After every chunk
    that ends well, ``checkpoint(done)`` keeps the state. Non-finite samples stop the run
    (kept up to the last finite one).
    """
    done, t0, stop = 0, _time.perf_counter(), ""
    width = state.out.shape[1] - 1
    try:
        with _Signals() as sig:
            while done < n_samples:
                offset = 1 if sink is not None else 1 + done
                wrote = chunk(offset, min(width, n_samples - done), done)
                bad = _first_bad(state.out[:, offset : offset + wrote])
                if bad is not None:
                    wrote = bad
                    stop = (f"non-finite values at t = {(done + bad + 1) * sample_dt:.6g} s "
                            "(the run cannot be resolved at this step)")  # fmt: skip
                if sink is not None:
                    sink.write(state.out[:, (0 if done == 0 else 1) : 1 + wrote])
                done += wrote
                if stop:
                    break
                st = int(state.istate[I_STATUS])
                if _grow_events(state, st, sink):
                    continue
                if st != OK:
                    break
                if checkpoint is not None:
                    checkpoint(done)
                if sig.got is not None:
                    stop = sig.NAMES[sig.got]
                    break
                el = _time.perf_counter() - t0
                if progress and el > 2.0:
                    print(f"\rrubrotor: {100 * done / n_samples:5.1f} %", end="", file=sys.stderr)
    except KeyboardInterrupt:  # outside the main thread's handler
        stop = "interrupted by the user"
    if progress and _time.perf_counter() - t0 > 2.0:
        print(file=sys.stderr)
    st = int(state.istate[I_STATUS])
    msg = ""
    if stop:
        msg = f"{stop}; data up to t = {done * sample_dt:.6g} s kept"
    elif st != OK:
        msg = f"{STATUS_NAMES[st]} at t = {(done + 1) * sample_dt:.6g} s; data up to t = {done * sample_dt:.6g} s kept"
    return done, msg, _time.perf_counter() - t0


def _grow_events(state: _Chunks, st: int, sink) -> bool:
    """After a chunk stopped for a full event buffer: flush (streamed) or grow the buffer and
    return True to resume; False when the run goes on as usual or must stop."""
    lost = state.istate[I_EVENTS] > len(state.events)
    if sink is not None and not lost:
        flushed = _flush_events(state, sink)
        if st == EVENT_BUFFER_FULL:
            if not flushed:  # smaller than the kernel's margin: grow it once
                state.events = np.concatenate([state.events, np.zeros_like(state.events)])
            state.istate[I_STATUS] = OK
            return True
    if st == EVENT_BUFFER_FULL and not lost and len(state.events) < EVENT_BUFFER_MAX:
        state.events = np.concatenate([state.events, np.zeros_like(state.events)])
        state.istate[I_STATUS] = OK
        return True
    return False


def _flush_events(state: _Chunks, sink) -> int:
    """Hand the chunk's events to the sink and empty the buffer (bounded memory); their count."""
    ne = int(state.istate[I_EVENTS])
    sink.write_events(state.events[:ne])
    state.flushed += ne
    state.istate[I_EVENTS] = 0
    return ne


def _check_call(method: str | None, stations, run: Run, chunk_samples) -> str:
    """The stepper (default by ``run.rtol``); refuse an unknown one, a station that is not a
    :class:`RubStation` or a chunk size below one sample."""
    if method is None:
        method = "exponential" if run.rtol is None else DEFAULT_ADAPTIVE
    if method not in STEPPERS:
        raise InputError("simulation.method", method, " or ".join(f'"{k}"' for k in STEPPERS))
    for i, s in enumerate(stations):
        if not isinstance(s, RubStation):
            raise InputError(f"contact[{i + 1}]", s, "a RubStation")
    if (
        isinstance(chunk_samples, bool)
        or not isinstance(chunk_samples, int | np.integer)
        or (chunk_samples < 1)
    ):
        raise InputError("chunk_samples", chunk_samples, "an integer >= 1 (samples per call)")
    return method


def _add_counts(stats: dict, state: _Chunks, method: str, plant: Plant, run: Run, wall: float):
    """The run's counters (named slots of the kernel's integer state) into ``stats``; returns
    the hint to add to a failed contact solve's message (:func:`stiffness_hint`), else ``""``."""
    ist = state.istate
    stats.update(
        method=method, modes=plant.n_rotor, modes_total=plant.rotor.n_total,
        eig_cond=plant.rotor.cond, steps=int(ist[I_STEP]), substeps=int(ist[I_SUBSTEPS]),
        newton_iterations=int(ist[I_NEWTON]), accepted_steps=int(ist[I_ACCEPTED]),
        rejected_steps=int(ist[I_REJECTED]), grazing_closures=int(ist[I_GRAZE]),
        contact_events=int(ist[I_EVENTS]) + state.flushed, wall_s=wall, residual=run.residual,
    )  # fmt: skip
    return stiffness_hint(plant, run.step, int(ist[I_STATUS]))


def _phasor(state: _Chunks, plant: Plant) -> complex:
    """Unbalance phasor ``e^{i Omega t}`` of the kernel state (fixed or adaptive steps)."""
    k = state.kernel
    if "tst" in k:
        return complex(np.exp(1j * plant.speed * k["tst"][T_TIME]))
    return complex(k["zt"][0])


class _Keeper:
    """The state at the end of the last good chunk, and the streamed file's checkpoints."""

    def __init__(self, plant, state, final, sink, t0: float, sample_dt: float, status_attrs):
        self.plant, self.state, self.final, self.sink = plant, state, final, sink
        self.t0, self.dt, self.status_attrs = t0, sample_dt, status_attrs
        self.snap, self.x = None, None
        self(0, sync=False)

    def __call__(self, done: int, sync: bool = True) -> None:
        if self.state.kernel is not None:
            self.snap = restart.snapshot(self.plant, self.state.kernel,
                                         _phasor(self.state, self.plant), done * self.dt)  # fmt: skip
            self.x = np.array(self.snap["x"])
        else:
            self.x = self.final()
        if self.sink is not None and sync:
            if self.snap is None:
                self.sink.checkpoint()
            else:
                vec = restart.flatten(self.snap)
                self.sink.checkpoint(self.t0 + self.snap["time_s"], vec)

    def attrs(self, done: int) -> dict:
        """Attributes of the kept state (the times count from the file's start)."""
        return {**self.status_attrs(), "end_time_s": self.t0 + done * self.dt,
                "final_state": self.x.tolist()}  # fmt: skip


def simulate_general(
    system,
    run: Run,
    stations=(),
    unbalances=(),
    loads=(),
    gravity=(0.0, 0.0),
    *,
    method: str | None = None,
    progress: bool | None = None,
    stream: str | None = None,
    chunk_samples: int = 1 << 14,
    plant: Plant | None = None,
    attrs: dict | None = None,
    resume: dict | None = None,
    t0: float = 0.0,
    supports=(),
) -> EngineResult:
    """Simulate a linear rotor with rub at several stations (see the module docstring).

    Parameters
    ----------
    system : rubrotor.rotors.linear.LinearSystem
        The rotor.
    run : Run
        Speed (rad/s), duration (s), step (s), reduction, initial state, probes.
    stations, unbalances, loads, gravity
        As in ``build_plant``.
    method : {"exponential", "free-flight", "collocation"}, optional
        Stepper (``STEPPERS``): by default ``"collocation"`` with ``run.rtol`` (exact free
        flight, order-4 contact steps by the error estimate), else ``"exponential"`` (fixed
        steps); ``"free-flight"``: order-2 contact steps; ``"runup"`` with ``run.speed_end``.
    progress : bool, optional
        Progress on stderr for long runs (default: when stderr is a terminal).
    stream : str, optional
        Write samples and events to this netCDF file chunk by chunk (bounded memory; read it
        with :func:`rubrotor.load_dataset`), flushed after every chunk with ``status =
        "partial"`` and the state kept so far (``rubrotor.engine.stream``); the result then
        holds neither (``time``, ``channels``, ``events`` empty), only ``stats``
        (``"contact_events"`` counts them) and the final state.
    chunk_samples : int
        Samples per compiled call (>= 1; the buffer size when streaming).
    plant : Plant, optional
        A plant already built by ``build_plant`` for the same rotor, stations, loads and
        ``run`` (speed, reduction, initial state): skips the reduction (the array-level path
        for repeated runs; the caller vouches that it matches).
    attrs : dict, optional
        Extra attributes of a streamed file (provenance); the state attributes are added.
    resume : dict, optional
        A restart state (``EngineResult.restart``) of this model to continue exactly: the
        unbalance phases must be advanced by ``Omega t`` to its time and ``run.initial`` be its
        ``x`` (constant speed only).
    t0 : float
        Time (s) of the first sample in a streamed file (a continued run's start).
    supports : sequence of rubrotor.forces.film_row.FilmRow
        Nonlinear supports (see ``build_plant``); their outputs are the ``bearing`` variables.

    Returns
    -------
    EngineResult

    Raises
    ------
    InputError
        Bad input, or an output too large for memory (or disk when streamed), before running.
    """
    method = _check_call(method, stations, run, chunk_samples)
    problem = Problem(system, tuple(stations), tuple(unbalances), tuple(loads), tuple(gravity),
                      tuple(supports))  # fmt: skip
    if supports and (resume is not None or run.speed_end is not None):
        what = "a restarted run" if resume is not None else "a run-up"

        raise InputError(f"bearing[{supports[0].name}]", "fluid film",
                         f"a support type this run takes: {what} does not carry fluid-film "
                         "bearings yet; constant-speed runs, streamed or in memory, "
                         "continuation and shooting do")  # fmt: skip
    if run.speed_end is not None:
        method = "runup"
        if not isinstance(run.initial, str) or run.initial not in ("rest", "static"):
            raise InputError(
                "initial.state", run.initial, '"rest" or "static" with a speed profile'
            )
        plant = build_plant(system, run, stations, (), loads, gravity)
    elif plant is None:
        plant = build_plant(system, run, stations, unbalances, loads, gravity, supports=supports)
    sample_dt = run.step * run.save_every
    n_samples = int(math.floor(run.duration / sample_dt + 1e-9))
    if n_samples < 1:
        raise InputError("simulation.duration", run.duration, f">= one sample ({sample_dt:g} s)")
    nst, nc = len(plant.stations), len(plant.outputs.flex)
    nch = 4 * nst + CONTACT_CHANNELS * nc
    check_size(n_samples + 1, nch, plant.lam.size if run.save_state else 0, stream)
    width = min(chunk_samples, n_samples) if stream is not None else n_samples
    state = _Chunks(
        out=np.empty((nch, width + 1)),
        ys=np.zeros((n_samples + 1 if run.save_state else 0, plant.lam.size), complex),
        events=np.empty((EVENT_BUFFER, 2)),
    )
    chunk, first, stats, final = STEPPERS[method](problem, plant, run, state)
    if resume is not None:
        if state.kernel is None:
            raise InputError("initial.state", "file", "a constant-speed run to continue")
        restart.resume(plant, state.kernel, resume, stations)
    first()
    if stream is None and chunk_samples < n_samples:
        inner = chunk

        def chunk(offset, count, done):  # the in-memory run still calls in bounded chunks
            return inner(offset, min(count, chunk_samples), done)

    return _run(chunk, final, stats, state, plant, run, method,
                (progress, stream, attrs, t0, n_samples, sample_dt))  # fmt: skip


def _run(chunk, final, stats, state, plant, run, method, opts) -> EngineResult:
    """Run the chunk loop (into the sink when streaming) and gather the result."""
    progress, stream, attrs, t0, n_samples, sample_dt = opts
    show = sys.stderr.isatty() if progress is None else progress
    wall = [0.0]

    def status_attrs() -> dict:
        _add_counts(stats, state, method, plant, run, wall[0])
        return {"speed_rad_s": plant.speed, "integrator_stats": json.dumps(_jsonable(stats))}

    sink = None
    if stream is not None:
        lay = None
        if state.kernel is not None:
            lay = restart.layout(restart.snapshot(plant, state.kernel, 1.0, 0.0))
        sink = NetcdfSink(stream, plant.stations, plant.n_contacts, sample_dt, plant.speed,
                          t0=t0, tau=lambda t: spin_angle(run, t) + run.speed * t0,
                          attrs={**(attrs or {}), **status_attrs()},
                          restart_layout=lay, supports=plant.supports)  # fmt: skip
    keep = _Keeper(plant, state, final, sink, t0, sample_dt, status_attrs)
    if sink is not None:
        keep(0)  # the initial state: a run killed in its first chunk can restart from it
    try:
        done, msg, wall[0] = _loop(chunk, n_samples, state, show, sample_dt, sink, keep)
    except BaseException as exc:
        if sink is not None:
            sink.close({"status": "partial", "status_message": f"stopped by an error: {exc!r}"})
        raise
    msg += _add_counts(stats, state, method, plant, run, wall[0])
    n_out = done + 1
    events = state.events[: min(int(state.istate[I_EVENTS]), len(state.events))].copy()
    status = "complete" if not msg else "partial"
    if msg and keep.snap is not None and keep.snap["time_s"] < done * sample_dt:
        msg += f"; restart state at t = {t0 + keep.snap['time_s']:.6g} s (the last completed chunk)"
    if msg and keep.snap is not None and stream is not None:
        msg += f'; continue it with [initial] state = "file", path = "{stream}"'
    if sink is not None:
        sink.write_events(events)
        sink.close({**keep.attrs(done), "status": status, "status_message": msg,
                    "end_time_s": t0 + done * sample_dt})  # fmt: skip
        stats["stream"] = str(stream)
        n_out = 0
    return TimeRun(
        time=np.arange(n_out) * sample_dt, stations=plant.stations, n_contacts=plant.n_contacts,
        channels=state.out[:, :n_out], events=events, states=state.ys[:n_out], status=status,
        message=msg, stats=stats, speed=plant.speed, final_state=keep.x, restart=keep.snap,
        engine="general", code=Status(int(state.istate[I_STATUS])),
        extras={"supports": plant.supports} if plant.supports else {},
    )  # fmt: skip


def result_dataset(res: TimeRun, *, coords=None, data=None, attrs=None):
    """The results as an xarray Dataset whose sample variables view ``res.channels`` (no copy):
    :func:`rubrotor.engine.result.to_dataset`, the one builder.

    Parameters
    ----------
    res : TimeRun
        The run.
    coords, data : dict of str to xarray.Variable, optional
        Coordinates and variables that replace or extend the defaults (``time`` in s from 0,
        ``tau = Omega t`` in rad).
    attrs : dict, optional
        Attributes added to the defaults.

    Returns
    -------
    xarray.Dataset
    """
    return to_dataset(res, coords=coords, data=data, attrs=attrs)
