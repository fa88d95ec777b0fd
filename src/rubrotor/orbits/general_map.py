"""The stroboscopic map of a general (finite-element) rotor, for shooting and continuation.

The general engine (:mod:`rubrotor.engine`) reduces the rotor to complex modal coordinates
``y`` (rotor modes, then the modes of flexible stators; the rotor's displacement is
``Re(V y)`` plus the static and steady unbalance responses) and advances them by the fixed-step
exponential scheme ``y_{n+1} = E y_n + G0 F_n + G1 F_{n+1}`` with the contact forces ``F``
solved implicitly at every step (residual flexibility included). The state of that discrete
scheme is ``(y_n, F_n)``: the map's unknowns are ``x = [Re y, Im y, F]`` (modal amplitudes in
the engine's units, forces N) at unbalance phase 0, and a periodic orbit of ``k`` revolutions
is a fixed point of the ``k``-revolution map. At the fixed point ``F`` is the contact force
the orbit itself produces; its directions add multipliers near zero (a force is set by the
state it acts on), which never decide stability.

Monodromy: the exact derivative of the discrete map, propagated in the same compiled run
(:func:`rubrotor.core.engine_tangent.map_tangent`: the implicit contact step differentiated by
the implicit function theorem, as the seed rotor's map in :mod:`rubrotor.orbits.shooting`
does); central differences of the plain map (:meth:`GeneralMap.differences`, ``2 dim + 1``
runs, each increment ``6e-6`` of the component's scale) remain as the second route and where a
step closed a grazing contact by its set-valued rule. A map at another speed
(:meth:`GeneralMap.at_speed`) updates only the speed-dependent parts of the plant
(:class:`rubrotor.orbits.speed_family.SpeedFamily`).
"""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np

from rubrotor.core.engine import (
    CONTACT_CHANNELS,
    DIVERGED,
    I_EVENTS,
    I_STATUS,
    N_ISTATE,
    OK,
    expo_fixed,
)
from rubrotor.core.engine_tangent import map_tangent
from rubrotor.core.terms import FORCE_SCALE
from rubrotor.engine.driver import _control, _no_drive, _steps, build_plant
from rubrotor.engine.settings import Integrator
from rubrotor.engine.structs import Sink, State, span
from rubrotor.errors import InputError

FD_STEP = 6e-6
"""Relative increment of the central differences (balances truncation and rounding)."""


class GeneralMap:
    """The ``k``-revolution map of a general rotor at constant speed, prepared once.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A general rotor with its contacts, stators, unbalances, loads and gravity.
    k : int
        Revolutions per map.
    steps : int
        Fixed steps per revolution.
    speed : float, optional
        Spin speed (rad/s) instead of the scenario's.
    reference : GeneralMap, optional
        Align the modes with this map's (:func:`aligned`), so that states mean the same in
        both (continuation along a key).
    probes : sequence of float
        Axial stations (m) whose deflection the kernel writes after the contact stations'
        (``_kernel``'s samples); the orbit itself does not depend on them.
    family : rubrotor.orbits.speed_family.SpeedFamily, optional
        Take the plant from this family of the same rotor (only the speed-dependent parts
        updated; its probes) instead of building it (:meth:`at_speed` passes it).
    """

    def __init__(self, scenario, k: int, steps: int, speed: float | None = None,
                 reference: GeneralMap | None = None, probes=(), family=None):  # fmt: skip
        from rubrotor.engine.general import engine_problem
        from rubrotor.modelling import model_of

        eng = scenario.engine
        model_of(scenario).require_general_rotor(
            InputError("rotor", "a [shaft] rotor", "a general rotor for GeneralMap")
        )
        if eng.speed_end is not None or eng.speed_table:
            raise InputError(
                "speed.profile", "a varying speed", "a constant speed (periodic orbits)"
            )
        if not eng.stations:
            raise InputError(
                "contact", None, "at least one [contact] or [[contact]] table: sweeps and "
                "periodic orbits of a general rotor follow its rub (a rotor without a contact "
                "has no rub to map; its linear response: `rubrotor unbalance`, `rubrotor response`)")
        self.scenario, self.k, self.steps = scenario, int(k), int(steps)
        self.speed = float(scenario.speed if speed is None else speed)
        if family is None:
            integ = Integrator(revolutions=float(k), dtau=2 * math.pi / steps, save_every=1,
                               probes=tuple(probes))  # fmt: skip
            system, run, kw, _ = engine_problem(scenario, integ)
        else:  # the same rotor and settings: nothing to rebuild but the speed's parts
            system, run, kw = family.problem
        self.system = system
        T = 2 * math.pi / self.speed
        run = dataclasses.replace(run, speed=self.speed, initial="steady", duration=k * T,
                                  step=T / steps, save_every=1)  # fmt: skip
        if family is None:  # exact modes: maps are compared across key values (ARPACK's
            plant = build_plant(system, run, **kw, dense=True)  # tolerance: ~1e-10 noise)
        else:
            plant = family.plant(self.speed)
        self.family, self._problem = family, (system, run, kw)
        self.reference = reference
        if reference is not None:
            plant = aligned(plant, reference.plant)
        self.plant = plant
        self._steps = _steps(plant, run.step, run.sublevels + 1)
        self._control = _control(plant, self._steps, run)
        self._drive = _no_drive(plant.lam.size)
        self.ns, self.m = plant.lam.size, plant.beta.shape[1]
        self.dim = 2 * self.ns + self.m
        # the state holds each row force over its scale: 1 for a contact (zero when free), the
        # force scale (N) for a support's row, whose remainder about a load of hundreds of N
        # carries that load's round-off: in N it would hold the shooting tolerance hostage
        fs = np.ones(self.m)
        nc = plant.n_contacts
        fs[2 * nc :] = np.repeat(plant.contacts.cp[nc:, FORCE_SCALE], 2)
        self._fs = fs
        self._nch = 4 * len(plant.stations) + CONTACT_CHANNELS * len(plant.outputs.flex)

    def at_speed(self, speed: float) -> GeneralMap:
        """The same map at another spin speed (rad/s), its modes aligned with this map's (or
        its reference's), so that ``x`` means the same there. Only the speed-dependent parts
        of the plant are updated (:class:`rubrotor.orbits.speed_family.SpeedFamily`, shared by
        every map derived from this one): no dense eigen-decomposition per speed."""
        from rubrotor.orbits.speed_family import SpeedFamily

        if self.family is None:
            self.family = SpeedFamily(*self._problem, self.plant)
        family = self.family if self.family.usable else None  # else rebuilt (non-symmetric
        # mass, stiffness or damping bands: no transposed problem to reuse)
        return GeneralMap(self.scenario, self.k, self.steps, speed, self.reference or self,
                          family=family)  # fmt: skip

    def repeat(self, k: int) -> GeneralMap:
        """The same map over ``k`` revolutions (the same plant and step coefficients)."""
        other = copy.copy(self)
        other.k = int(k)
        return other

    def start(self) -> np.ndarray:
        """The steady no-contact response as a start vector (``y = 0``, no force)."""
        return np.zeros(self.dim)

    def _kernel(self, x: np.ndarray, save_every: int = 1):
        """Run the kernel over the map from ``x``: end vector, samples, events, status."""
        ns, m = self.ns, self.m
        y = x[:ns] + 1j * x[ns : 2 * ns]
        F = np.array(x[2 * ns :], float) * self._fs
        n = self.k * self.steps // save_every
        out = np.zeros((self._nch, n + 1))
        istate = np.zeros(N_ISTATE, np.int64)
        events = np.zeros((1 << 12, 2))
        state = State(y, F, F.copy(), np.zeros(m // 2), np.ones(1, complex), istate,
                      np.array([self._steps.h[0]]))  # fmt: skip
        sink = Sink(out, np.zeros((0, ns), complex), events)
        wrote = expo_fixed(state, span(n, save_every, 1, self.speed), sink, self._steps,
                           self.plant.contacts, self.plant.outputs, self._drive, self._control)
        status = int(istate[I_STATUS])
        if status == DIVERGED or (status != OK and wrote < n):
            raise InputError("shooting.start", "a diverging run", "a guess near a bounded orbit")
        events = events[: min(int(istate[I_EVENTS]), len(events))]
        return np.concatenate([y.real, y.imag, F / self._fs]), out, events

    def _run(self, x: np.ndarray):
        px, out, _ = self._kernel(x)
        return px, float(np.max(np.hypot(out[0, 1:], out[1, 1:])))

    def orbit_result(self, x: np.ndarray, samples_per_revolution: int = 256):
        """The orbit through the fixed point ``x`` over the map's revolutions, as the engine's
        result (samples every ``steps / samples_per_revolution`` steps; sample 0 is the last,
        the orbit being periodic)."""
        from rubrotor.engine.driver import EngineResult

        save = max(1, self.steps // samples_per_revolution)
        px, out, events = self._kernel(x, save)
        out[:, 0] = out[:, -1]
        dt = 2 * math.pi / self.speed / self.steps * save
        return EngineResult(
            time=np.arange(out.shape[1]) * dt, stations=self.plant.stations,
            n_contacts=self.m // 2, channels=out, events=events,
            states=np.zeros((0, self.ns), complex), status="complete", message="", stats={},
            speed=self.speed, final_state=px,
        )  # fmt: skip

    def run(self, x: np.ndarray, jacobian: bool = False):
        """``(P(x), dP/dx or None, largest contact-station radius m)`` of the map from ``x``.

        The Jacobian is the exact derivative of the discrete map, propagated in the same
        compiled run (:func:`rubrotor.core.engine_tangent.map_tangent`); where a step closed a
        grazing contact by its set-valued rule (no derivative of that form) it falls back to
        central differences (:meth:`differences`).
        """
        x = np.asarray(x, float)
        if not jacobian:
            px, radius = self._run(x)
            return px, None, radius
        px, jac, radius, grazes = self.tangent(x)
        if grazes:
            return self.differences(x)
        return px, jac, radius

    def tangent(self, x: np.ndarray, columns: np.ndarray | None = None):
        """``(P(x), dP/dx @ columns, radius m, grazing steps)`` by the compiled variational run;
        ``columns`` (dim, d) tangent vectors in the units of ``x``, by default the identity
        (the whole Jacobian)."""
        ns = self.ns
        y = x[:ns] + 1j * x[ns : 2 * ns]
        F = np.array(x[2 * ns :], float) * self._fs
        V = np.eye(self.dim) if columns is None else np.asarray(columns, float)
        Qy = np.ascontiguousarray((V[:ns] + 1j * V[ns : 2 * ns]).T)
        QF = np.ascontiguousarray(V[2 * ns :].T * self._fs[None, :])
        out = np.zeros(3)
        done = map_tangent((y, F), (Qy, QF), self._steps, self.plant.contacts,
                           self.plant.outputs, self.speed, self.k * self.steps, out)  # fmt: skip
        if int(out[1]) != OK or done < self.k * self.steps:
            raise InputError("shooting.start", "a diverging run", "a guess near a bounded orbit")
        jac = np.vstack([Qy.real.T, Qy.imag.T, QF.T / self._fs[:, None]])
        return np.concatenate([y.real, y.imag, F / self._fs]), jac, float(out[0]), int(out[2])

    def differences(self, x: np.ndarray):
        """``(P(x), dP/dx, radius m)`` with the Jacobian by central differences (``2 dim``
        runs, increments :data:`FD_STEP` of each component's scale): the second route."""
        x = np.asarray(x, float)
        px, radius = self._run(x)
        scale = self._scales(x)
        jac = np.empty((x.size, x.size))
        for j in range(x.size):
            e = np.zeros(x.size)
            e[j] = FD_STEP * scale[j]
            jac[:, j] = (self._run(x + e)[0] - self._run(x - e)[0]) / (2 * e[j])
        return px, jac, radius

    def _scales(self, x: np.ndarray) -> np.ndarray:
        """Per-component difference scales: the largest modal amplitude, the largest force."""
        ns = self.ns
        amp = max(float(np.max(np.abs(x[: 2 * ns]))), 1e-12)
        force = max(float(np.max(np.abs(x[2 * ns :]), initial=0.0)), 1e-6)
        return np.concatenate([np.full(2 * ns, amp), np.full(self.m, force)])


def aligned(plant, ref):
    """``plant`` with its rotor modes matched, ordered and scaled to those of ``ref``.

    The modal coordinates of a rebuilt plant (another speed, another key value) come in the
    eigen-solver's order, normalisation and phase. Each of ``ref``'s rotor modes is matched to
    the mode of ``plant`` whose shape overlaps it most (an assignment on the normalised overlaps
    ``|V_ref^H V|``) and that mode is rescaled by the complex factor ``c`` that brings its shape
    closest to ``ref``'s (least squares): ``V' = V c``, ``y' = y / c``, so inputs ``beta / c``
    and rows ``C c``. The dynamics are unchanged; only the coordinates follow ``ref``'s, which
    makes the map's state continuous in the key (the stator modes do not change).
    """
    import scipy.optimize

    nsr, ns = plant.n_rotor, plant.lam.size
    if nsr != ref.n_rotor or ns != ref.lam.size:
        raise InputError("simulation.modes", nsr, f"the same number of modes at every key value "
                         f"({ref.n_rotor} at the first): set simulation.modes")  # fmt: skip
    A, B = ref.rotor.Vq, plant.rotor.Vq
    ov = np.abs(A.conj().T @ B) / np.outer(np.linalg.norm(A, axis=0), np.linalg.norm(B, axis=0))
    order = scipy.optimize.linear_sum_assignment(-ov)[1]
    c = np.array([(B[:, i].conj() @ A[:, j]) / (B[:, i].conj() @ B[:, i])
                  for j, i in enumerate(order)])  # fmt: skip
    idx = np.concatenate([order, np.arange(nsr, ns)])
    scale = np.concatenate([c, np.ones(ns - nsr)])
    cts, out = plant.contacts, plant.outputs

    def cols(a):
        return np.ascontiguousarray(a[:, idx] * scale[None, :])

    return dataclasses.replace(
        plant, lam=plant.lam[idx], beta=plant.beta[idx] / scale[:, None],
        contacts=cts._replace(Cd=cols(cts.Cd), Cv=cols(cts.Cv)),
        outputs=out._replace(Od=cols(out.Od), Ov=cols(out.Ov), Sd=cols(out.Sd), Sv=cols(out.Sv)),
        y0=plant.y0[idx] / scale,
    )  # fmt: skip
