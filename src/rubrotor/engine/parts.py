"""What the general engine simulates besides the rotor: contact stations with their stators,
unbalance planes, static loads and the run settings (frozen dataclasses, SI units)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.engine.settings import INITIAL_STATES
from rubrotor.errors import InputError
from rubrotor.forces.loads import static_load as _static_load
from rubrotor.forces.unbalance import unbalance_phasor as _unbalance_phasor
from rubrotor.rotors.forces import Contact

__all__ = ["Stator", "RubStation", "Run", "INITIAL_STATES"]

RUNUP_REDUCTIONS = ("ritz", "full")


def _num(field: str, value, unit: str, minimum: float | None = None, strict=False) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise InputError(field, value, f"a number ({unit})")
    v = float(value)
    ok = math.isfinite(v) and (minimum is None or (v > minimum if strict else v >= minimum))
    if not ok:
        bound = "" if minimum is None else f" {'>' if strict else '>='} {minimum:g}"
        raise InputError(field, value, f"a finite number{bound} ({unit})")
    return v


@dataclass(frozen=True)
class Stator:
    """A flexible stator: mass, stiffness and damping per direction, connected to ground.

    Parameters
    ----------
    mass_y, mass_z : float
        Modal masses (kg), > 0.
    stiffness_y, stiffness_z : float
        Stiffness to ground (N/m), > 0.
    damping_y, damping_z : float
        Damping to ground (N s/m), >= 0.
    """

    mass_y: float
    mass_z: float
    stiffness_y: float
    stiffness_z: float
    damping_y: float = 0.0
    damping_z: float = 0.0

    def __post_init__(self):
        for a in ("y", "z"):
            _num(f"contact.stator_mass_{a}", getattr(self, f"mass_{a}"), "kg", 0, True)
            _num(f"contact.stator_stiffness_{a}", getattr(self, f"stiffness_{a}"), "N/m", 0, True)
            _num(f"contact.stator_damping_{a}", getattr(self, f"damping_{a}"), "N s/m", 0)

    @classmethod
    def isotropic(cls, mass: float, stiffness: float, damping: float = 0.0) -> Stator:
        """The same mass (kg), stiffness (N/m) and damping (N s/m) in both directions."""
        return cls(mass, mass, stiffness, stiffness, damping, damping)

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(M, C, K)`` 2x2 diagonal (kg, N s/m, N/m) on ``[s_y, s_z]``."""
        return (
            np.diag([self.mass_y, self.mass_z]),
            np.diag([self.damping_y, self.damping_z]),
            np.diag([self.stiffness_y, self.stiffness_z]),
        )


@dataclass(frozen=True)
class RubStation:
    """One contact station: the contact law at an axial position against a stator.

    Parameters
    ----------
    contact : rubrotor.rotors.forces.Contact
        Law, clearance (m), stiffness, damping, friction; its ``position`` (m) is required and
        its ``radius`` (m) gives the sliding speed ``R Omega``.
    offset_y, offset_z : float
        Stator centre (m) from the rotor axis.
    stator : Stator, optional
        Flexible stator; rigid when ``None``.
    """

    contact: Contact
    offset_y: float = 0.0
    offset_z: float = 0.0
    stator: Stator | None = None

    def __post_init__(self):
        if not isinstance(self.contact, Contact):
            raise InputError("contact", self.contact, "a rubrotor.rotors.forces.Contact")
        if self.contact.position is None:
            raise InputError("contact.position", None, "an axial position on the rotor (m)")
        if self.contact.radius is None:
            raise InputError("contact.radius", None, "the rubbing radius (m)")
        _num("contact.offset_y", self.offset_y, "m")
        _num("contact.offset_z", self.offset_z, "m")
        if self.stator is not None and not isinstance(self.stator, Stator):
            raise InputError("contact.stator", self.stator, "a Stator or None (rigid)")


@dataclass(frozen=True)
class Run:
    """How to run: speed, step, length, reduction and initial state.

    Parameters
    ----------
    speed : float
        Constant spin speed ``Omega`` (rad/s), > 0.
    duration : float
        Simulated time (s), > 0.
    step : float
        Fixed step (s), > 0; a failing contact solve halves it locally (``sublevels`` times).
    save_every : int
        Steps per saved sample.
    modes : int, optional
        Retained modes (see ``rubrotor.engine.reduce``); all by default.
    cutoff : float, optional
        Retain the modes with ``|lambda| <= cutoff`` (rad/s) instead.
    residual : bool
        Add the static correction of the dropped modes.
    initial : {"rest", "static", "steady"} or ndarray
        At rest undeflected; static equilibrium (gravity and loads); the steady no-contact orbit
        (static plus exact unbalance response); or an explicit state ``[q, q']`` on the free DOFs.
    probes : tuple of float
        Output positions (m) besides the contact stations.
    sublevels : int
        Halvings allowed when the contact solve fails.
    save_state : bool
        Also keep the modal state at every sample (for energy checks and restarts).
    max_displacement : float, optional
        Divergence threshold on any contact's relative displacement (m); default 1000 clearances.
    speed_end : float, optional
        Run-up or coast-down: the speed varies linearly from ``speed`` to ``speed_end`` (rad/s)
        over ``duration``.
    speed_table : sequence of (float, float), optional
        A speed profile as a table of ``(time (s), speed (rad/s))`` rows, linear between rows
        (run-up, hold, coast-down in one run): times start at 0, increase strictly, reach
        ``duration`` and are whole multiples of the sample spacing ``step * save_every`` (the
        unbalance drive changes its angular acceleration there). Replaces ``speed`` and
        ``speed_end`` (set from the table's first row and its value at ``duration``).
    speed_step : float, optional
        Largest speed change (rad/s) between re-diagonalisations; default 1/200 of the range.
    runup_reduction : {"ritz", "full"}
        How a run-up re-diagonalises at each speed step: the system projected on a fixed basis
        of the kept modes and static responses (``"ritz"``, a small eigenproblem) or the full
        model (``"full"``); see ``rubrotor.engine.driver._runup_factory`` and
        ``docs/guide/simulation.md``. Used only when modes are dropped (``modes`` or ``cutoff``).
    rtol : float, optional
        Adaptive steps: relative tolerance of the local error; ``step`` is then the output
        spacing (s), subdivided dyadically, and ``save_every`` must be 1.
    atol : float
        Absolute tolerance (m) of the adaptive steps.
    """

    speed: float
    duration: float
    step: float
    save_every: int = 1
    modes: int | None = None
    cutoff: float | None = None
    residual: bool = True
    initial: str | np.ndarray = "rest"
    probes: tuple = ()
    sublevels: int = 20
    save_state: bool = False
    max_displacement: float | None = None
    speed_end: float | None = None
    speed_table: tuple | None = None
    speed_step: float | None = None
    rtol: float | None = None
    atol: float = 1e-10
    runup_reduction: str = "ritz"

    def __post_init__(self):
        if self.runup_reduction not in RUNUP_REDUCTIONS:
            raise InputError("runup_reduction", self.runup_reduction,
                             " or ".join(f'"{s}"' for s in RUNUP_REDUCTIONS))  # fmt: skip
        if self.rtol is not None:
            _num("simulation.rtol", self.rtol, "1", 0, True)
            _num("simulation.atol", self.atol, "m", 0, True)
            if self.save_every != 1:
                raise InputError("simulation.save_every", self.save_every, "1 with adaptive steps")
        if self.speed_table is not None:
            self._set_table()
        if self.speed_end is not None:
            _num("speed.to", self.speed_end, "rad/s", 0, True)
            if self.speed_step is None:
                tt, ww = self.speed_profile()
                object.__setattr__(self, "speed_step", np.sum(np.abs(np.diff(ww))) / 200 or 1.0)
            _num("speed.step", self.speed_step, "rad/s", 0, True)
        _num("speed", self.speed, "rad/s", 0, True)
        _num("simulation.duration", self.duration, "s", 0, True)
        _num("simulation.step", self.step, "s", 0, True)
        se = self.save_every
        if isinstance(se, bool) or not isinstance(se, int) or se < 1:
            raise InputError("simulation.save_every", se, "an integer >= 1")
        if isinstance(self.initial, str) and self.initial not in INITIAL_STATES:
            raise InputError(
                "initial.state", self.initial, " or ".join(f'"{s}"' for s in INITIAL_STATES)
            )
        if not isinstance(self.sublevels, int) or not 0 <= self.sublevels <= 30:
            raise InputError("simulation.sublevels", self.sublevels, "an integer 0..30")

    def _set_table(self) -> None:
        """Check ``speed_table`` and set ``speed``/``speed_end`` from it."""
        allowed = (
            "rows (time s, speed rad/s): >= 2 rows, times from 0 strictly increasing to "
            ">= simulation.duration, whole multiples of the sample spacing, speeds >= 0"
        )
        try:
            tab = np.array(self.speed_table, dtype=float)
        except (TypeError, ValueError):
            raise InputError("speed.times / speed.speeds", self.speed_table, allowed) from None
        dt = self.step * self.save_every
        ok = (tab.ndim == 2 and tab.shape[1] == 2 and tab.shape[0] >= 2
              and np.all(np.isfinite(tab)) and tab[0, 0] == 0.0 and np.all(np.diff(tab[:, 0]) > 0)
              and tab[-1, 0] >= self.duration * (1 - 1e-12) and np.all(tab[:, 1] >= 0))  # fmt: skip
        if ok:
            k = tab[:, 0] / dt
            ok = bool(np.all(np.abs(k - np.rint(k)) <= 1e-6 * np.maximum(1.0, k)))
        if not ok:
            raise InputError("speed.times / speed.speeds", self.speed_table, allowed)
        object.__setattr__(self, "speed_table", tuple(map(tuple, tab.tolist())))
        object.__setattr__(self, "speed", float(tab[0, 1]))
        object.__setattr__(self, "speed_end", float(np.interp(self.duration, tab[:, 0], tab[:, 1])))

    def speed_profile(self) -> tuple[np.ndarray, np.ndarray]:
        """Break times (s, from 0 to ``duration``) and speeds (rad/s) of the piecewise-linear
        profile: one row for a constant speed, two for a linear run-up, the table's rows (cut at
        ``duration``) for a table."""
        if self.speed_table is not None:
            tab = np.array(self.speed_table)
            inside = tab[:, 0] < self.duration * (1 - 1e-12)
            tt = np.append(tab[inside, 0], self.duration)
            return tt, np.interp(tt, tab[:, 0], tab[:, 1])
        if self.speed_end is None:
            return np.array([0.0]), np.array([self.speed])
        return np.array([0.0, self.duration]), np.array([self.speed, self.speed_end])


def spin_angle(run: Run, t) -> np.ndarray:
    """Spin angle (rad) at times ``t`` (s): the exact integral of the piecewise-linear speed."""
    tt, ww = run.speed_profile()
    t = np.asarray(t, float)
    if tt.size == 1:
        return ww[0] * t
    a = np.diff(ww) / np.diff(tt)
    theta = np.concatenate([[0.0], np.cumsum(0.5 * (ww[1:] + ww[:-1]) * np.diff(tt))])
    i = np.clip(np.searchsorted(tt, t, side="right") - 1, 0, tt.size - 2)
    s = t - tt[i]
    return theta[i] + ww[i] * s + 0.5 * a[i] * s * s


def speed_at(run: Run, t) -> np.ndarray:
    """Spin speed (rad/s) at times ``t`` (s) and the angular acceleration (rad/s^2) there."""
    tt, ww = run.speed_profile()
    t = np.asarray(t, float)
    if tt.size == 1:
        return np.full(t.shape, ww[0]), np.zeros(t.shape)
    a = np.diff(ww) / np.diff(tt)
    i = np.clip(np.searchsorted(tt, t, side="right") - 1, 0, tt.size - 2)
    return ww[i] + a[i] * (t - tt[i]), a[i]


# The unbalance and load terms live in rubrotor.forces; their old names stay here.
unbalance_phasor = _unbalance_phasor
static_load_vector = _static_load
