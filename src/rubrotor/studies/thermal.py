"""Thermal rub (the Newkirk effect): a rubbing rotor bows towards its hot spot and spirals.

A light rub heats the rotor at the part of its surface that touches the stator (the hot spot);
the rotor bows towards it, the bow changes the synchronous response, which moves the rub. The
model has two time scales (the derivation, the assumptions and the literature are on the
documentation page ``docs/guide/thermal.md``):

* fast (one revolution): for a given bow ``b_j`` (m, complex, rotor-fixed frame) at every
  contact station ``j``, the steady rub orbit of the rotor, on which the bow acts as a bent
  shaft does: a forcing ``K_s Phi_j b_j`` turning with the rotor (``K_s`` the shaft's own
  stiffness without bearings, ``Phi_j`` the bow shape scaled to 1 at station ``j``);
* slow (the thermal time constant ``tau``, minutes): the bow relaxes towards the bow driven by
  the heat input, ``tau b_j' = -b_j + beta exp(-i phi) H_j``, with ``H_j`` (W) the friction power
  ``mu N R Omega`` at station ``j`` averaged over one revolution of the steady orbit, as a
  vector pointing at the contact point in the rotor-fixed frame (the high spot).

:func:`closed_form` solves the Jeffcott rotor (or any isotropic rotor through its receptances at
the contact station) with a linear contact law exactly: steady state, eigenvalues of the slow
dynamics, growth rate and spiral period. :class:`ThermalModel` solves any general rotor the
engine runs: steady orbits by shooting on the engine's map
(``rubrotor.orbits.general_map``), the slow dynamics by :func:`scipy.integrate.solve_ivp`,
the linearisation about the steady bow by central differences.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from rubrotor.errors import InputError, ScenarioError
from rubrotor.rotors.forces import ThermalBow

__all__ = [
    "SlowLinear",
    "arc_shape",
    "closed_form",
    "jeffcott_receptances",
    "ThermalModel",
    "growth_against_speed",
    "slow_run",
]


@dataclass(frozen=True)
class SlowLinear:
    """A steady state of the slow (thermal) dynamics and its linearisation.

    Attributes
    ----------
    speed : float
        Spin speed (rad/s).
    bow : ndarray of complex
        Steady bow per contact station (m, rotor-fixed frame).
    high_spot : ndarray of complex
        Synchronous deflection of the rotor at each contact station relative to its stator
        centre (m, rotor-fixed frame: the high spot's direction and the orbit radius).
    heat : ndarray of complex
        Revolution-averaged heat input per station (W), pointing at the hot spot's high spot.
    eigenvalues : ndarray of complex
        Eigenvalues of the linearised slow dynamics (1/s), largest real part first; of a
        complex pair first the one whose ``Im`` has the sign of the sense the bow turns in
        (rotor-fixed frame: > 0 with the spin, < 0 against it), then its conjugate.
    growth_rate : float
        Largest real part (1/s): > 0 the spiral grows.
    spiral_frequency : float
        ``Im`` of that eigenvalue (rad/s, signed as above).
    spiral_period : float
        ``2 pi / |Im lambda|`` (s) of the eigenvalue with the largest real part (inf if real).
    reason : str
        Why the values are nan (no steady bow found, no steady orbit), ``""`` otherwise.
    """

    speed: float
    bow: np.ndarray
    high_spot: np.ndarray
    heat: np.ndarray
    eigenvalues: np.ndarray
    growth_rate: float
    spiral_period: float
    reason: str = ""

    @property
    def spiral_frequency(self) -> float:
        """``Im`` of the leading eigenvalue (rad/s, signed: > 0 turning with the spin)."""
        return float(self.eigenvalues[0].imag)


def _signed(jac: np.ndarray) -> np.ndarray:
    """Eigenvalues of the real slow Jacobian ``jac`` (1/s, on ``[Re b, Im b]``), largest real
    part first; of a complex pair the one whose sign of ``Im`` is the sense in which the bow
    vectors turn (``e^{i Im(lambda) t}``: > 0 with the spin, < 0 against it)."""
    lam, vec = np.linalg.eig(jac)
    n = jac.shape[0] // 2
    order = np.argsort(-lam.real, kind="stable")
    out, i = [], 0
    while i < len(order):
        k = order[i]
        w = vec[:, k]
        forward = np.sum(np.abs(w[:n] + 1j * w[n:]) ** 2)  # turns as e^{i Im(lam) t}
        backward = np.sum(np.abs(np.conj(w[:n]) + 1j * np.conj(w[n:])) ** 2)
        out.append(lam[k] if forward >= backward else np.conj(lam[k]))
        pair = i + 1 < len(order) and lam[k].imag != 0
        if pair and abs(lam[order[i + 1]] - np.conj(lam[k])) <= 1e-9 * abs(lam[k]):
            out.append(np.conj(out[-1]))  # its partner, second
            i += 1
        i += 1
    return np.array(out, complex)


def _summary(speed, bow, high, heat, jac) -> SlowLinear:
    lam = _signed(np.asarray(jac, float))
    period = 2 * math.pi / abs(lam[0].imag) if lam[0].imag != 0 else math.inf
    return SlowLinear(float(speed), np.atleast_1d(bow), np.atleast_1d(high),
                      np.atleast_1d(heat), lam, float(lam[0].real), float(period))  # fmt: skip


def jeffcott_receptances(mass, stiffness, damping, speed, unbalance=0.0):
    """Receptances of a Jeffcott rotor for :func:`closed_form`.

    Parameters
    ----------
    mass : float
        Disk mass ``m`` (kg).
    stiffness : float
        Shaft stiffness ``k`` (N/m) between the disk and rigid bearings.
    damping : float
        Viscous damping ``c`` (N s/m) on the disk.
    speed : float
        Spin speed ``Omega`` (rad/s).
    unbalance : float
        ``m e`` (kg m) at angle 0 of the rotor-fixed frame.

    Returns
    -------
    contact, bow, unbalance_response : complex
        ``1/D`` (m/N), ``k/D`` (1) and ``m e Omega^2 / D`` (m), ``D = k - m Omega^2 + i c Omega``:
        the forward synchronous deflection per unit contact force, per unit bow, and under the
        unbalance.
    """
    d = stiffness - mass * speed**2 + 1j * damping * speed
    return 1 / d, stiffness / d, unbalance * speed**2 / d


def _steady_amplitude(d, e, f, clearance) -> float:
    """Largest root ``rho > clearance`` of ``|(D + E) rho - E g| = |f|``; nan if none."""
    a = abs(d + e) ** 2
    b = -2 * clearance * (np.conj(e) * (d + e)).real
    c = abs(e) ** 2 * clearance**2 - abs(f) ** 2
    disc = b * b - 4 * a * c
    if disc < 0:
        return math.nan
    rho = (-b + math.sqrt(disc)) / (2 * a)
    return rho if rho > clearance else math.nan


def closed_form(contact, bow, unbalance_response, *, speed, clearance, contact_stiffness,
                friction, radius, thermal: ThermalBow) -> SlowLinear:  # fmt: skip
    """Steady thermal bow and its linear stability for one contact with a linear law, exactly.

    The rotor is isotropic and linear, its stator rigid and centred; at the contact station its
    forward synchronous deflection is ``Z = Z_u + H_b b + H_c F`` (rotor-fixed frame, m) with
    the contact force ``F = -k_c (|Z| - g)(1 + i mu) Z/|Z|`` (N). With ``D = 1/H_c``,
    ``kappa = H_b/H_c``, ``f = Z_u/H_c``, ``G = beta mu R Omega k_c`` and
    ``E = k_c (1 + i mu) - kappa G e^{-i phi}``, the steady radius ``rho`` solves
    ``|(D + E) rho - E g| = |f|`` (a quadratic) and the slow dynamics linearised about it, in the
    frame of the high spot ``v = e^{-i theta} delta b``, is
    ``tau v' = -v + G e^{-i phi} (s a v + c Re(a v))`` with ``s = 1 - g/rho``,
    ``D_s = D + s k_c (1 + i mu)``, ``a = kappa/D_s`` and ``c`` from the radial constraint (see the
    documentation page), a real 2x2 system whose matrix is explicit (its two eigenvalues by
    ``numpy.linalg.eig``). With ``g = 0``
    (``s = 1``) they are ``(-1 + G e^{-i phi} kappa/(D + k_c (1 + i mu)))/tau`` and its conjugate.

    Parameters
    ----------
    contact, bow, unbalance_response : complex
        ``H_c`` (m/N), ``H_b`` (1), ``Z_u`` (m): e.g. :func:`jeffcott_receptances`.
    speed : float
        ``Omega`` (rad/s).
    clearance : float
        ``g`` (m), >= 0.
    contact_stiffness : float
        ``k_c`` (N/m).
    friction : float
        ``mu`` (1).
    radius : float
        ``R`` (m), the rubbing surface radius (sliding speed ``R Omega``).
    thermal : ThermalBow
        ``tau`` (s), ``beta`` (m/W), ``phi`` (rad).

    Returns
    -------
    SlowLinear
        ``high_spot`` is ``Z`` (m); nan everywhere when the steady orbit does not touch.
    """
    d, kap, f = 1 / contact, bow / contact, unbalance_response / contact
    kc, mu, g = contact_stiffness, friction, clearance
    gain = thermal.bow_per_heat * mu * radius * speed * kc
    rot = complex(math.cos(thermal.hot_spot_lag), -math.sin(thermal.hot_spot_lag))
    e = kc * (1 + 1j * mu) - kap * gain * rot
    rho = _steady_amplitude(d, e, f, g)
    if math.isnan(rho):
        nan = complex(math.nan, math.nan)
        return SlowLinear(float(speed), *(np.array([nan]),) * 3, np.array([nan, nan]),
                          math.nan, math.nan)  # fmt: skip
    direction = f / ((d + e) * rho - e * g)
    direction /= abs(direction)
    heat = mu * radius * speed * kc * (rho - g) * direction
    s = 1 - g / rho
    ds = d + s * kc * (1 + 1j * mu)
    kappa_r = (1 - s) * kc * (1 + 1j * mu)
    a = kap / ds
    den = 1 + (kappa_r / ds).real
    p = gain * rot * s * a
    cc = gain * rot * ((1 - s) - s * kappa_r / ds) / den
    m = np.array([[p.real, -p.imag], [p.imag, p.real]])
    m += np.outer([cc.real, cc.imag], [a.real, -a.imag])
    bow0 = thermal.bow_per_heat * rot * heat
    jac = (m - np.eye(2)) / thermal.time_constant  # on [Re v, Im v]; a rotation of delta b
    return _summary(speed, bow0, rho * direction, heat, jac)


# ---- the model on any general rotor ----------------------------------------------------------
ORBIT_TOL = 1e-12
"""Relative Newton step (dimensionless) at which a steady orbit counts as converged."""

TRANSIENT = 200
"""Revolutions simulated before a second Newton attempt on a steady orbit."""

FD_BOW = 1e-4
"""Relative increment of the central differences of the slow dynamics (of the bow scale)."""


def arc_shape(system, supports: tuple[float, float], station: float) -> np.ndarray:
    """The ``"arc"`` bow shape as a forward complex vector on the free DOFs.

    A uniform curvature (to first order the parabola ``(x - x_a)(x - x_b)``) through the two
    supports ``x_a, x_b`` (m), scaled to a deflection of 1 at ``station`` (m). Nodal values are
    the parabola and its slope (the rotation DOFs of :class:`~rubrotor.rotors.linear.NodalBasis`
    are slopes; constant curvature has no shear, so rotation and slope agree for Timoshenko
    elements too). The bow deflection ``Re(b e^{i Omega t} Phi)`` turns with the rotor:
    ``Phi = phi_y - i phi_z``.
    """
    xa, xb = supports
    scale = (station - xa) * (station - xb)
    if abs(scale) <= 1e-12 * max(abs(xb - xa), 1e-12) ** 2:
        raise InputError("contact.position", station, "a contact station off the bearings "
                         "(the arc bow is zero there)")  # fmt: skip
    nodes = system.basis.nodes
    val = (nodes - xa) * (nodes - xb) / scale
    slope = (2 * nodes - xa - xb) / scale
    full = np.zeros(system.M.shape[0], complex)
    full[0::4], full[2::4] = val, slope  # v and its slope
    full[1::4], full[3::4] = -1j * val, -1j * slope  # w, a quarter turn behind
    return full[system.free]


def _supports(scenario) -> tuple[float, float]:
    xs = sorted(b.position for b in scenario.rotor.bearings)
    if len(xs) < 2:
        raise ScenarioError("bearing", len(xs), "two bearings at least (the arc bow's supports)")
    return xs[0], xs[-1]


class ThermalModel:
    """Thermal bow on a general rotor at one constant speed (module docstring).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A general (``[[section]]``) rotor with its ``[[contact]]`` stations, unbalances,
        stators, gravity, and ``[simulation] probes`` (m) for the 1X vectors.
    thermal : ThermalBow, optional
        Default ``scenario.thermal`` (the ``[thermal]`` table).
    speed : float, optional
        Spin speed (rad/s), default the scenario's.
    steps : int
        Fixed steps per revolution of the orbit map (its error is second order in the step).

    Attributes
    ----------
    stations : ndarray
        Contact positions (m), then probe positions (m).
    """

    def __init__(self, scenario, thermal: ThermalBow | None = None, *, speed=None, steps=1024):
        from rubrotor.engine.driver import _particular
        from rubrotor.orbits.general_map import GeneralMap

        thermal = thermal or getattr(scenario, "thermal", None)
        if thermal is None:
            raise ScenarioError("thermal", None, "a [thermal] table (time_constant, bow_per_heat)")
        from rubrotor.modelling import model_of

        model_of(scenario).require_general_rotor(ScenarioError(
            "shaft", "a [shaft] rotor", "a general [[section]] rotor for the thermal bow (its "
            "shape is set between the bearings)"))  # fmt: skip
        sim = scenario.simulation
        probes = tuple(sim.probes) if sim is not None else ()
        self.scenario, self.thermal = scenario, thermal
        self.map = GeneralMap(scenario, 1, steps, speed, probes=probes)
        self.speed, self.steps = self.map.speed, steps
        plant, system = self.map.plant, self.map.system
        self._base = plant
        self._st = scenario.engine.stations
        self.stations = np.asarray(plant.stations, float)
        sm = system.matrices(self.speed)
        ks = system.K[np.ix_(system.free, system.free)]  # the shaft alone: no bearings
        sup = _supports(scenario)
        self._q_bow = [_particular(sm, ks @ arc_shape(system, sup, s.contact.position), self.speed)
                       for s in self._st]  # fmt: skip
        self._rows = np.vstack([system.output_rows(x) for x in plant.stations])
        self._x = self.map.start()
        self._lu = None

    @property
    def n_contacts(self) -> int:
        """Number of contact stations (one bow each)."""
        return len(self._st)

    def _set_bow(self, b: np.ndarray) -> None:
        """Put the bows ``b`` (m) into the map's steady forced response (no re-reduction)."""
        p = self._base
        q = p.q_unbalance + sum(bj * qj for bj, qj in zip(b, self._q_bow, strict=True))
        pu = p.Bmat.T @ q
        opu = self._rows @ q
        iw = 1j * self.speed
        self.map.plant = dataclasses.replace(
            p, q_unbalance=q, contacts=p.contacts._replace(Pu=pu, Pv=iw * pu),
            outputs=p.outputs._replace(OPu=opu, OPv=iw * opu),
        )  # fmt: skip

    def _newton(self) -> np.ndarray:
        """Steady orbit from the last one; if Newton fails, once more after a transient of
        :data:`TRANSIENT` revolutions (an orbit entering or leaving contact)."""
        try:
            return self._chord(self._x)
        except InputError:
            self._lu = None
            x0 = self.map.repeat(TRANSIENT).run(self.map.start())[0]
            return self._chord(x0)

    def _chord(self, x0: np.ndarray) -> np.ndarray:
        """Chord Newton on ``P(x) = x`` from ``x0``, refreshing the Jacobian when it stops
        contracting (a fresh Jacobian's step is always taken)."""
        mp, x = self.map, np.array(x0, float)
        eye, last = np.eye(x.size), math.inf
        for _ in range(80):
            fresh = self._lu is None
            try:
                if fresh:
                    px, jac, _ = mp.run(x, True)
                    self._lu = scipy.linalg.lu_factor(jac - eye)
                else:
                    px = mp.run(x)[0]
            except InputError:
                self._lu = None
                raise
            dx = scipy.linalg.lu_solve(self._lu, x - px)
            step = np.linalg.norm(dx)
            if step > 0.5 * last and not fresh:  # stale Jacobian: refresh and redo from here
                self._lu = None
                continue
            x, last = x + dx, step
            if step <= ORBIT_TOL * max(np.linalg.norm(x), 1e-30):
                self._x = x
                return x
        raise InputError("thermal", "no steady orbit", "a bow near a bounded steady orbit")

    def orbit(self, b) -> dict:
        """The steady orbit under the bows ``b`` (m, complex, one per contact).

        Returns
        -------
        dict
            ``heat`` (W, complex per contact: revolution-averaged friction power ``|F_t| R
            Omega`` as a vector at the contact point, rotor-fixed frame), ``high_spot`` (m,
            complex per contact: 1X of the deflection relative to the stator centre),
            ``one_x`` (m, complex, shape (stations, 2): the 1X phasors ``2 <v e^{-i Omega t}>``
            and ``2 <w e^{-i Omega t}>`` of every contact and probe station).
        """
        self._set_bow(np.asarray(b, complex))
        x = self._newton()
        _, out, _ = self.map._kernel(x, 1)
        out = out[:, 1:]  # sample k at t = k h, k = 1..steps (the last is t = T, angle 0)
        ph = np.exp(-1j * 2 * np.pi * np.arange(1, out.shape[1] + 1) / out.shape[1])
        n_st = len(self.stations)
        v, w = out[0 : 4 * n_st : 4], out[1 : 4 * n_st : 4]
        one_x = np.stack([2 * (v * ph).mean(axis=1), 2 * (w * ph).mean(axis=1)], axis=1)
        heat, high = [], []
        for i, st in enumerate(self._st):
            r = 4 * n_st + 8 * i
            p = (v[i] - out[r] - st.offset_y) + 1j * (w[i] - out[r + 1] - st.offset_z)
            unit = np.where(np.abs(p) > 0, p / np.where(np.abs(p) > 0, np.abs(p), 1.0), 0)
            power = np.abs(out[r + 7]) * st.contact.radius * self.speed
            heat.append(np.mean(power * unit * ph))
            high.append(np.mean(p * ph))
        return {"heat": np.array(heat), "high_spot": np.array(high), "one_x": one_x}

    def rate(self, bvec: np.ndarray) -> np.ndarray:
        """Slow dynamics ``db/dt`` (m/s) on the real vector ``[Re b, Im b]`` (m)."""
        n = self.n_contacts
        b = bvec[:n] + 1j * bvec[n:]
        th = self.thermal
        rot = complex(math.cos(th.hot_spot_lag), -math.sin(th.hot_spot_lag))
        db = (-b + th.bow_per_heat * rot * self.orbit(b)["heat"]) / th.time_constant
        return np.concatenate([db.real, db.imag])

    def _jacobian(self, bvec: np.ndarray, scale: float) -> np.ndarray:
        h = FD_BOW * scale
        cols = []
        for j in range(bvec.size):
            e = np.zeros(bvec.size)
            e[j] = h
            cols.append((self.rate(bvec + e) - self.rate(bvec - e)) / (2 * h))
        return np.column_stack(cols)

    def _scale(self, bvec) -> float:
        gap = min(s.contact.clearance for s in self._st)
        return max(float(np.max(np.abs(bvec))), gap)

    def _backtrack(self, bvec, dx, norm0):
        """``bvec + t dx`` for the largest ``t = 2^-k`` whose orbit exists and whose rate is
        smaller than ``norm0`` (a step at the rounding level is taken as it is)."""
        if np.linalg.norm(dx) <= 1e-9 * self._scale(bvec):
            return bvec + dx
        t = 1.0
        for _ in range(12):
            try:
                if np.linalg.norm(self.rate(bvec + t * dx)) < norm0:
                    return bvec + t * dx
            except InputError:  # a diverging orbit: the step went too far
                self._lu = None
            t /= 2
        raise InputError("thermal", "no steady bow", "a guess nearer a steady bow")

    def steady(self, guess=None, max_iter: int = 20) -> SlowLinear:
        """The steady bow (Newton on ``db/dt = 0``) and the slow dynamics linearised about it.

        Parameters
        ----------
        guess : array of complex, optional
            Start bows (m); default the bow the no-bow orbit's heat drives.
        max_iter : int
            Newton iterations at most.

        Returns
        -------
        SlowLinear
        """
        n = self.n_contacts
        if guess is None:
            th = self.thermal
            rot = complex(math.cos(th.hot_spot_lag), -math.sin(th.hot_spot_lag))
            guess = th.bow_per_heat * rot * self.orbit(np.zeros(n))["heat"]
        g = np.asarray(guess, complex)
        bvec = np.concatenate([g.real, g.imag])
        for _ in range(max_iter):
            r = self.rate(bvec)
            jac = self._jacobian(bvec, self._scale(bvec))
            dx = np.linalg.solve(jac, -r)
            dx *= min(1.0, 2 * self._scale(bvec) / max(np.linalg.norm(dx), 1e-300))
            bvec = self._backtrack(bvec, dx, np.linalg.norm(r))
            if np.linalg.norm(dx) <= 1e-11 * self._scale(bvec):
                break
        else:
            raise InputError("thermal", "no steady bow", "a guess nearer a steady bow")
        jac = self._jacobian(bvec, self._scale(bvec))
        b = bvec[:n] + 1j * bvec[n:]
        orb = self.orbit(b)
        return _summary(self.speed, b, orb["high_spot"], orb["heat"], jac)


def growth_against_speed(scenario, speeds, *, thermal: ThermalBow | None = None,
                         steps: int = 1024) -> list[SlowLinear]:  # fmt: skip
    """Steady bow, growth rate and spiral period of a general rotor at each speed.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A general rotor with contacts and a ``[thermal]`` table (or ``thermal``).
    speeds : sequence of float
        Spin speeds (rad/s), > 0.
    thermal : ThermalBow, optional
        Instead of the scenario's ``[thermal]`` table.
    steps : int
        Fixed steps per revolution of the orbit map.

    Returns
    -------
    list of SlowLinear
        One per speed; the steady bow found at one speed starts Newton at the next. Where no
        steady bow is found (its orbit diverges, Newton fails) every value is nan and
        ``reason`` says why.
    """
    out, guess = [], None
    for w in np.asarray(speeds, float):
        if not w > 0:
            raise InputError("--speeds", float(w), "spin speeds > 0 (rad/s)")
        model = ThermalModel(scenario, thermal, speed=float(w), steps=steps)
        try:
            try:
                lin = model.steady(guess)
            except InputError:
                if guess is None:
                    raise
                lin = model.steady(None)  # the last speed's bow was too far: start afresh
        except InputError as exc:  # no steady bow found (e.g. no steady orbit at the bow): nan
            nan = np.full(model.n_contacts, complex(math.nan, math.nan))
            lin = SlowLinear(float(w), nan, nan, nan, np.full(2, nan[0]), math.nan, math.nan,
                             _no_steady_bow(float(w), exc))  # fmt: skip
        if not lin.reason and not (math.isfinite(lin.growth_rate)
                                   and np.all(np.isfinite(lin.bow))):  # fmt: skip
            lin = dataclasses.replace(lin, reason=f"at {float(w):.6g} rad/s the linearised slow "
                                      "dynamics are not finite (a steady bow at the limit of "
                                      "existence, e.g. exactly at a critical speed)")  # fmt: skip
        guess = None if math.isnan(lin.growth_rate) else lin.bow
        out.append(lin)
    return out


def _no_steady_bow(speed: float, exc: Exception) -> str:
    """Why a speed has no growth rate, with the keys that set it."""
    if "diverging" in str(exc):
        return (f"no growth rate at {speed:.6g} rad/s: the rub has no bounded steady orbit "
                "there (a run from the no-contact orbit diverges: the rub itself is unstable, "
                "e.g. a dry whirl, which contact.stiffness and contact.friction set)")  # fmt: skip
    return (f"no growth rate at {speed:.6g} rad/s: no steady bow found ({exc}); the thermal "
            "loop may have no steady state there (its gain grows with contact.stiffness, "
            "contact.friction and thermal.bow_per_heat)")  # fmt: skip


def slow_run(model: ThermalModel, duration: float, *, bow=None, samples: int = 200,
             rtol: float = 1e-8, max_bow: float | None = None):  # fmt: skip
    """Integrate the slow (thermal) dynamics over ``duration`` seconds of machine time.

    Parameters
    ----------
    model : ThermalModel
        The rotor at its speed.
    duration : float
        Machine time (s), > 0 (hours are thousands of seconds).
    bow : array of complex, optional
        Start bows (m) per contact; default 0 (a straight rotor: the rub starts).
    samples : int
        Output samples (>= 2), evenly spaced in time.
    rtol : float
        Relative tolerance of :func:`scipy.integrate.solve_ivp` (RK45).
    max_bow : float, optional
        Stop (status ``"runaway"``) when a bow exceeds this (m); default 50 clearances.

    Returns
    -------
    xarray.Dataset
        ``one_x`` (m, complex as ``one_x_real``/``one_x_imag`` on ``(time, station, axis)``:
        the 1X phasors of ``v`` and ``w`` at the contacts then the probes), ``bow_real/imag``
        (m) and ``heat_real/imag`` (W) on ``(time, contact)``; attributes ``status``
        (``"complete"`` or ``"runaway"``: then the last sample is the time the bow reached
        ``max_bow``), ``speed_rad_s`` and the thermal parameters.
    """
    import scipy.integrate

    if not (isinstance(duration, int | float) and duration > 0 and math.isfinite(duration)):
        raise InputError("duration", duration, "a machine time > 0 (s)")
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
        raise InputError("samples", samples, "an integer >= 2")
    n = model.n_contacts
    b0 = np.zeros(n, complex) if bow is None else np.asarray(bow, complex)
    gap = max(s.contact.clearance for s in model._st)
    limit = 50 * gap if max_bow is None else float(max_bow)

    def runaway(t, y):
        return limit - np.max(np.hypot(y[:n], y[n:]))

    runaway.terminal = True
    t_eval = np.linspace(0.0, float(duration), samples)

    def rate(t, y):
        try:
            return model.rate(y)
        except InputError as exc:
            raise InputError("contact", f"bow {np.hypot(y[:n], y[n:]).max():.3g} m at "
                             f"t = {t:.6g} s", "a rub with a bounded steady orbit at every bow "
                             f"of the slow run ({_no_steady_bow(model.speed, exc)})") from None

    sol = scipy.integrate.solve_ivp(rate, (0.0, float(duration)),
                                    np.concatenate([b0.real, b0.imag]), method="RK45",
                                    t_eval=t_eval, rtol=rtol, atol=1e-9 * gap,
                                    events=runaway)  # fmt: skip
    status = "runaway" if sol.status == 1 else "complete"
    if sol.status == -1:
        raise InputError("thermal", sol.message, "a slow run that the integrator completes")
    t, y = sol.t, sol.y
    if sol.status == 1:  # the last sample is the runaway itself, not the sample before it
        t = np.append(t, sol.t_events[0][0])
        y = np.column_stack([y, sol.y_events[0][0]])
    return _slow_dataset(model, t, y, status)


def _slow_dataset(model: ThermalModel, t, y, status: str):
    import xarray as xr

    n = model.n_contacts
    bows = y[:n].T + 1j * y[n:].T
    orbits = [model.orbit(b) for b in bows]
    one_x = np.array([o["one_x"] for o in orbits])
    heat = np.array([o["heat"] for o in orbits])
    th = model.thermal
    tdim, sdim = ("time",), ("time", "station", "axis")
    data = {
        "one_x_real": (sdim, one_x.real, {"units": "m", "long_name": "1X phasor, real part"}),
        "one_x_imag": (sdim, one_x.imag, {"units": "m", "long_name": "1X phasor, imaginary"}),
        "bow_real": (tdim + ("contact",), bows.real, {"units": "m"}),
        "bow_imag": (tdim + ("contact",), bows.imag, {"units": "m"}),
        "heat_real": (tdim + ("contact",), heat.real, {"units": "W"}),
        "heat_imag": (tdim + ("contact",), heat.imag, {"units": "W"}),
    }
    coords = {
        "time": ("time", t, {"units": "s", "long_name": "machine time"}),
        "station": ("station", model.stations, {"units": "m", "long_name": "axial position"}),
        "axis": ("axis", ["y", "z"]),
        "contact": ("contact", np.arange(n)),
    }
    attrs = {
        "status": status, "speed_rad_s": model.speed, "n_contacts": n,
        "time_constant_s": th.time_constant, "bow_per_heat_m_per_W": th.bow_per_heat,
        "hot_spot_lag_rad": th.hot_spot_lag, "bow_shape": th.bow_shape,
        "scenario_name": model.scenario.name, "scenario": model.scenario.source,
        "steps_per_revolution": model.steps,
    }  # fmt: skip
    return xr.Dataset(data, coords, attrs)
