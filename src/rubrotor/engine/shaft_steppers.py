"""Steppers of the continuous-shaft simulation (:func:`rubrotor.engine.simulate.simulate_system`).

:data:`FACTORIES` maps each stepper (named in :data:`rubrotor.engine.settings.STEPPERS`, the one
stepper table with each stepper's order) to a factory ``(plan, state) -> Stepper`` that
precomputes the method's coefficients once and returns the chunk function the shared loop of
:mod:`rubrotor.engine.simulate` calls. The compiled kernels (:mod:`rubrotor.core.integrate`) take
the named tuples defined here; they live outside ``rubrotor.core``, which imports only numpy
and numba, and numba reads a named tuple of arrays and numbers by field name.
"""

from __future__ import annotations

from collections import namedtuple
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rubrotor.core.integrate import (
    C_ACCEPTED,
    C_NEWTON,
    C_REJECTED,
    I_STEP,
    abm_fixed,
    expo_adaptive,
    expo_fixed,
)
from rubrotor.engine.settings import ADAPTIVE_LEVELS
from rubrotor.engine.shaft_modal import phi_functions
from rubrotor.errors import InputError

__all__ = [
    "Rows",
    "RunState",
    "FixedStep",
    "Energy",
    "AdaptiveStep",
    "AbmStep",
    "MapStep",
    "Plan",
    "Stepper",
    "FACTORIES",
    "ADAPTIVE_LEVELS",
    "SHAFT_EVENT_RESERVE",
]

SHAFT_EVENT_RESERVE = 4096
"""Free event slots a kernel requires before a saved sample (at most one event per step, so a
fixed-step sample needs ``min(save_every, SHAFT_EVENT_RESERVE)``); see
:data:`rubrotor.core.integrate.STATUS`."""

Rows = namedtuple("Rows", ["d", "v", "a", "acc_fc", "part_u", "part_l", "vel_z", "acc_z", "acc_c"])
"""Output rows per station (S, ns) mapping the eigen-coordinates to displacement ``d`` (m),
velocity ``v`` (m/s) and acceleration ``a`` (m/s^2); ``acc_fc`` (S,) the direct acceleration per
N of contact force (m/(s^2 N)); the particular (steady) solution as multiples of the unbalance
phasor (``part_u`` m, ``vel_z`` m/s, ``acc_z`` m/s^2) and constants (``part_l`` m, ``acc_c``
m/s^2), all (S,) complex."""

RunState = namedtuple(
    "RunState", ["y", "cstate", "istate", "counts", "hist", "work", "out", "events"]
)
"""State a kernel reads and updates: ``y`` (ns,) eigen-coordinates; ``cstate`` ``[F (N), z,
F_prev (N), d_prev (m)]``; ``istate`` (slots ``I_*`` of :mod:`rubrotor.core.integrate`); ``counts`` (slots
``C_*``); ``hist`` (4, ns) ABM derivative history; ``work`` (5,) J; ``out`` the saved channels;
``events`` onset (+t) and separation (-t) times (s)."""

FixedStep = namedtuple(
    "FixedStep",
    ["E", "G0", "G1", "sd", "sv", "cdc", "cvc", "omega", "h", "save_every", "max_disp",
     "event_reserve"],
)  # fmt: skip
"""Fixed exponential step ``h`` (s): ``E = e^{lam h}``, ``G0 = h (phi1 - phi2) beta_c``,
``G1 = h phi2 beta_c`` (ns,); ``sd, sv`` contact-station displacement (m/N) and velocity
(m/(s N)) per N of the new force; contact rows ``cdc, cvc`` (ns,); ``omega`` (rad/s),
``save_every``, ``max_disp`` (m), ``event_reserve``."""

Energy = namedtuple(
    "Energy",
    ["on", "wv", "wz", "cmat", "vel_u_row", "vel_u_z", "fu0", "vel_l_row", "vel_l_z", "fl"],
)
"""Energy tracking (``on``): modal-velocity rows ``wv`` (nq, ns) and their particular part
``wz`` (m/s), damping matrix ``cmat`` (N s/m), velocity rows and particular parts of the
unbalance and load stations (m/s), unbalance amplitude ``fu0`` and load ``fl`` (N)."""

AdaptiveStep = namedtuple(
    "AdaptiveStep",
    ["E", "G0", "G1", "cdE", "cvE", "cdG0", "cvG0", "sd", "sv", "errc", "rot", "cdc", "cvc",
     "Q0", "Qm", "Q1", "cdQ0", "cvQ0", "cdQm", "cvQm", "sdq", "svq",
     "omega", "H", "max_disp", "rtol", "atol", "event_reserve"],
)  # fmt: skip
"""Dyadic steps ``H / 2^level``: per-level coefficients of the linear (``G*``) and quadratic
(``Q*``) force holds and their contact-station projections (see
:func:`rubrotor.core.integrate.expo_adaptive`); ``H`` (s) the output spacing, ``rtol`` (1),
``atol`` (m)."""

AbmStep = namedtuple(
    "AbmStep",
    ["lam", "beta_c", "beta_u", "beta_l", "fu0", "fl", "cdc", "cvc", "omega", "h",
     "save_every", "max_disp", "event_reserve"],
)  # fmt: skip
"""Seed ABM scheme: modes ``lam`` (1/s), force inputs (per N) of contact, unbalance and load,
unbalance amplitude ``fu0`` and load ``fl`` (N), contact rows, ``omega`` (rad/s), ``h`` (s)."""


MapStep = namedtuple(
    "MapStep",
    ["E", "G0", "G1", "sd", "sv", "cdc", "cvc", "part_c", "part_lc", "vel_cz", "omega", "h",
     "n_steps", "max_disp"],
)  # fmt: skip
"""A map of ``n_steps`` fixed exponential steps with tangents (:func:`rubrotor.core.tangent.expo_tangent`,
:func:`rubrotor.core.shoot.expo_strobe`): ``E, G0, G1`` (ns,) as :class:`FixedStep`, ``sd, sv``
contact-station displacement (m/N) and velocity (m/(s N)) per N of the new force, contact rows
``cdc, cvc`` (ns,), ``part_c`` (m) and ``vel_cz`` (m/s) the particular solution at the contact
station per unit phasor, ``part_lc`` (m) its constant-load part, ``omega`` (rad/s), ``h`` (s),
``max_disp`` (m)."""

@dataclass(frozen=True)
class Plan:
    """What every stepper reads: the modal system, forces, rows and run settings (SI)."""

    sysm: object  # ModalSystem or SeedModalSystem
    speed: float
    beta_c: np.ndarray
    beta_u: np.ndarray
    beta_l: np.ndarray
    fu0: complex
    fl: complex
    y_u: np.ndarray  # steady unbalance response (eigen-coordinates at phase 0)
    y_l: np.ndarray  # static load response
    rows: Rows
    cp: np.ndarray
    max_disp: float
    h: float | None  # fixed step (s), None for adaptive steps
    H: float | None  # output spacing of adaptive steps (s)
    save_every: int
    rtol: float
    atol: float
    track_energy: bool
    a_u: float
    a_l: float


@dataclass(frozen=True)
class Stepper:
    """A method ready to run: ``chunk(state, offset, count) -> samples written``.

    ``stats`` are its settings for the result; ``counts(state)`` its step counters;
    ``full_state(state)`` the unshifted eigen-coordinates at the end; ``e0`` the mechanical
    energy (J) at the start when energy is tracked.
    """

    chunk: Callable
    stats: dict
    counts: Callable
    full_state: Callable
    e0: float | None = None


def _cd_cv(plan: Plan) -> tuple[np.ndarray, np.ndarray]:
    return np.ascontiguousarray(plan.rows.d[0]), np.ascontiguousarray(plan.rows.v[0])


def _shifted_full(plan: Plan) -> Callable:
    """Unshifted coordinates of the exponential kernels' shifted ``y`` (phasor in ``cstate``)."""
    return lambda st: st.y + plan.y_u * st.cstate[1] + plan.y_l


def _steps_taken(st) -> dict:
    return {"steps": int(st.istate[I_STEP])}


def _energy(plan: Plan, y: np.ndarray) -> tuple[Energy, float | None]:
    """Energy-tracking rows (off unless ``plan.track_energy``) and the start energy (J)."""
    sysm, ns = plan.sysm, plan.y_u.size
    if not plan.track_energy:
        z = np.zeros(ns, complex)
        off = Energy(False, np.zeros((0, ns), complex), np.zeros(0, complex), np.zeros((0, 0)),
                     z, 0j, complex(plan.fu0), z, 0j, complex(plan.fl))  # fmt: skip
        return off, None
    wv = sysm.V[sysm.qd_index, :]
    vel_u_row = sysm.velocity_row(plan.a_u)
    vel_l_row = sysm.velocity_row(plan.a_l)
    en = Energy(
        True,
        wv,
        wv @ plan.y_u,  # y_u is a full state: its q-dot rows are velocities
        sysm.C,
        vel_u_row,
        complex(1j * plan.speed * complex(sysm.displacement_row(plan.a_u) @ plan.y_u)),
        complex(plan.fu0),
        vel_l_row,
        complex(vel_l_row @ plan.y_u),
        complex(plan.fl),
    )
    return en, sysm.energy(y + plan.y_u + plan.y_l)


def _fixed_factory(plan: Plan, st: RunState) -> Stepper:
    """``"exponential"`` with a fixed step: the exact propagator with a linear force hold."""
    h, lam, beta_c = plan.h, plan.sysm.lam, plan.beta_c
    cdc, cvc = _cd_cv(plan)
    p1, p2 = phi_functions(lam * h)
    G1 = h * p2 * beta_c
    k = FixedStep(
        np.exp(lam * h), (h * p1 - h * p2) * beta_c, G1, complex(cdc @ G1), complex(cvc @ G1),
        cdc, cvc, plan.speed, h, plan.save_every, plan.max_disp,
        min(plan.save_every, SHAFT_EVENT_RESERVE),
    )  # fmt: skip
    en, e0 = _energy(plan, st.y)
    rows, cp = plan.rows, plan.cp

    def chunk(state: RunState, offset: int, count: int) -> int:
        return expo_fixed(state, count, offset, k, cp, rows, en)

    return Stepper(chunk, {"step_s": h}, _steps_taken, _shifted_full(plan), e0)


def _adaptive_coefficients(plan: Plan) -> AdaptiveStep:
    """Per-level coefficients for ``h = H / 2^level``, ``level = 0 .. ADAPTIVE_LEVELS - 1``."""
    lam, beta_c, H, speed = plan.sysm.lam, plan.beta_c, plan.H, plan.speed
    cdc, cvc = _cd_cv(plan)
    hs = H / 2.0 ** np.arange(ADAPTIVE_LEVELS)
    E = np.exp(np.outer(hs, lam))
    p1, p2, p3 = phi_functions(np.outer(hs, lam), third=True)
    G0 = (hs[:, None] * (p1 - p2)) * beta_c[None, :]
    # quadratic hold through F_{k-1}, F_k, F_{k+1} at equal steps
    Q1 = (hs[:, None] * (0.5 * p2 + p3)) * beta_c[None, :]
    Q0 = (hs[:, None] * (p1 - 2 * p3)) * beta_c[None, :]
    Qm = (hs[:, None] * (p3 - 0.5 * p2)) * beta_c[None, :]
    G1 = (hs[:, None] * p2) * beta_c[None, :]
    c = np.ascontiguousarray
    return AdaptiveStep(
        E=E, G0=G0, G1=G1, cdE=c(E * cdc[None, :]), cvE=c(E * cvc[None, :]),
        cdG0=c(G0 @ cdc), cvG0=c(G0 @ cvc), sd=c(G1 @ cdc), sv=c(G1 @ cvc),
        errc=np.abs(G0 @ cdc), rot=np.exp(1j * speed * hs), cdc=cdc, cvc=cvc,
        Q0=Q0, Qm=Qm, Q1=Q1, cdQ0=Q0 @ cdc, cvQ0=Q0 @ cvc, cdQm=Qm @ cdc, cvQm=Qm @ cvc,
        sdq=c(Q1 @ cdc), svq=c(Q1 @ cvc), omega=speed, H=H, max_disp=plan.max_disp,
        rtol=plan.rtol, atol=plan.atol, event_reserve=SHAFT_EVENT_RESERVE,
    )  # fmt: skip


def _adaptive_factory(plan: Plan, st: RunState) -> Stepper:
    """``"exponential"`` with error-controlled dyadic steps and one sample every ``H``."""
    if plan.track_energy:
        raise InputError("track_energy", True, "a fixed step (dtau or dt) for energy tracking")
    k = _adaptive_coefficients(plan)
    rows, cp = plan.rows, plan.cp

    def chunk(state: RunState, offset: int, count: int) -> int:
        return expo_adaptive(state, count, offset, k, cp, rows)

    def counts(state: RunState) -> dict:
        c = state.counts
        return {"accepted_steps": int(c[C_ACCEPTED]), "rejected_steps": int(c[C_REJECTED]),
                "newton_iterations": int(c[C_NEWTON])}  # fmt: skip

    stats = {"output_spacing_s": plan.H, "min_step_s": plan.H / 2.0 ** (ADAPTIVE_LEVELS - 1)}
    return Stepper(chunk, stats, counts, _shifted_full(plan))


def _abm_factory(plan: Plan, st: RunState) -> Stepper:
    """``"abm"``: the seed's Adams-Bashforth-Moulton PECE on the unshifted coordinates."""
    cdc, cvc = _cd_cv(plan)
    k = AbmStep(
        plan.sysm.lam, plan.beta_c, plan.beta_u, plan.beta_l, plan.fu0, plan.fl, cdc, cvc,
        plan.speed, plan.h, plan.save_every, plan.max_disp, min(plan.save_every, SHAFT_EVENT_RESERVE),
    )  # fmt: skip
    rows, cp = plan.rows, plan.cp

    def chunk(state: RunState, offset: int, count: int) -> int:
        return abm_fixed(state, count, offset, k, cp, rows)

    return Stepper(chunk, {"step_s": plan.h}, _steps_taken, lambda state: state.y)


FACTORIES = {"exponential": _fixed_factory, "adaptive": _adaptive_factory, "abm": _abm_factory}
"""Stepper name -> factory ``(plan, state) -> Stepper`` of the continuous shaft:
``"exponential"`` (fixed step), ``"adaptive"`` (exponential with error control, chosen when no
fixed step is given) and ``"abm"``; their orders in :data:`rubrotor.engine.settings.STEPPERS`."""
