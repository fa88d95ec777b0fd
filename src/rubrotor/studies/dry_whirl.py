r"""Dry whirl and dry whip: the friction threshold of backward rub and its whirl frequency.

A Jeffcott rotor (mass ``m``, stiffness ``k``, damping ``c_r`` at the contact station) spins
at ``Omega`` inside a stator (rigid, or a mass ``m_s`` on a spring ``k_s`` and dashpot ``c_s``)
with a radial clearance ``g``, the linear contact law ``F_n = k_c (|D| - g)`` on the relative
displacement ``D = P - S`` (rotor ``P = v + i w``, stator ``S``) and Coulomb friction ``mu`` at
the rubbing radius ``R``. :func:`scan_friction` simulates it with the general engine
(:func:`rubrotor.engine.driver.simulate_general`) at several frictions and reads the whirl
frequency from the full spectrum (positive frequencies forward, negative backward) of ``D``.

Steady backward whirl in full contact (closed form)
---------------------------------------------------
Look for ``P = A e^{i omega t}``, ``S = B e^{i omega t}``, ``D = (A - B) e^{i omega t}``
with ``omega < 0``. With ``Z_r = k - m omega^2 + i c_r omega`` and ``Z_s`` alike for the stator
(``1/Z_s = 0`` when rigid), the contact force ``F`` on the rotor gives ``A = F / Z_r``,
``B = -F / Z_s``, hence ``D = F H`` with the receptance ``H = 1/Z_r + 1/Z_s`` and the
equivalent impedance ``Z = 1/H``. The contact force is ``F = -F_n (1 + i tau) n`` with
``n = D / |D|`` and ``tau`` the tangential-to-normal force ratio; ``D = F H`` then needs
``(1 + i tau) H`` real and negative::

    tau = Im Z / Re Z,     F_n = -|D| Re Z   (so Re Z < 0),     |D| = g + F_n / k_c
    =>  |D| = g k_c / (k_c + Re Z)            (so -k_c < Re Z < 0).

* **Rolling (dry whirl).** The surface does not slide: ``R Omega + omega |D| = 0``, the rolling
  condition ``omega = -Omega R / |D|`` (``-Omega R / g`` for a stiff contact). With ``|D|``
  from above it is one real equation for ``omega``, solved by :func:`rolling_whirls`. It needs
  the friction ``tau <= mu``: ``mu_roll = Im Z / Re Z`` at that frequency is the smallest
  friction that can hold it.
* **Bounds.** ``-k_c < Re Z < 0`` holds in bands bounded by the rotor's own natural frequency
  and the coupled natural frequencies of rotor, contact spring and stator locked together, the
  roots of ``1/Re Z_r + 1/Re Z_s + 1/k_c = 0`` (undamped): :func:`coupled_frequencies`. A rigid
  stator has one band, up to ``sqrt((k + k_c)/m)``; a flexible one two, below the lower coupled
  frequency (``~ sqrt((k + k_s)/(m + m_s))`` for a stiff contact) and from the stator's own
  natural frequency up to the upper one. As ``Omega R / g`` grows the indentation grows and the
  whirl frequency bends away from ``-Omega R / g`` towards the band's coupled frequency (the
  whip limit), never past it.
* **Regularised friction.** The engine smooths the sign of the sliding speed over ``v_r``
  (``Contact.friction_regularization``), so "rolling" slides at ``v_s ~ v_r (tau/mu) /
  sqrt(1 - (tau/mu)^2)``; the simulated frequency sits ``v_s / (R Omega)`` (relative) above the
  closed form, largest just above ``mu_roll``.

All frequencies in rad/s, lengths in m, forces in N.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import scipy.optimize

from rubrotor.analysis.spectra import full_spectrum
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.parts import RubStation, Run, Stator
from rubrotor.errors import InputError
from rubrotor.forces.contact import law_of
from rubrotor.rotors.forces import Contact
from rubrotor.rotors.linear import LinearSystem

__all__ = [
    "Jeffcott",
    "DryWhirlCase",
    "RollingWhirl",
    "DryWhirlScan",
    "rolling_whirls",
    "coupled_frequencies",
    "whirl_frequency",
    "scan_friction",
    "scan_speed",
    "relative_system",
]


@dataclass(frozen=True)
class _PointBasis:
    """Both DOFs are the deflection ``[v, w]`` of the disk, wherever one looks."""

    length: float = 1.0

    def rows(self, position: float) -> np.ndarray:
        """``(2, 2)`` identity: ``[v, w]`` (m) at any ``position`` (m)."""
        return np.eye(2)


@dataclass(frozen=True)
class Jeffcott:
    """A Jeffcott rotor seen at its disk.

    Parameters
    ----------
    mass : float
        Disk mass ``m`` (kg), > 0.
    stiffness : float
        Shaft stiffness ``k`` (N/m), > 0.
    damping : float
        Viscous damping ``c_r`` (N s/m), >= 0.
    """

    mass: float
    stiffness: float
    damping: float = 0.0

    def __post_init__(self):
        for name, unit, strict in (("mass", "kg", True), ("stiffness", "N/m", True),
                                   ("damping", "N s/m", False)):  # fmt: skip
            v = getattr(self, name)
            ok = isinstance(v, int | float) and np.isfinite(v) and (v > 0 if strict else v >= 0)
            if not ok:
                raise InputError(
                    f"rotor.{name}", v, f"a finite number {'>' if strict else '>='} 0 ({unit})"
                )

    def system(self) -> LinearSystem:
        """The rotor as a 2-DOF :class:`rubrotor.rotors.linear.LinearSystem` (DOFs ``v, w`` in m)."""
        eye = np.eye(2)
        return LinearSystem(self.mass * eye, self.stiffness * eye, self.damping * eye,
                            np.zeros((2, 2)), _PointBasis(), dof_labels=("v@0.5", "w@0.5"))  # fmt: skip

    def impedance(self, omega):
        """``k - m omega^2 + i c_r omega`` (N/m) at the whirl frequency ``omega`` (rad/s)."""
        return self.stiffness - self.mass * omega**2 + 1j * self.damping * omega


@dataclass(frozen=True)
class DryWhirlCase:
    """A Jeffcott rotor spinning against a stator with a linear contact law.

    Parameters
    ----------
    rotor : Jeffcott
    contact : rubrotor.rotors.forces.Contact
        ``law="linear"``, clearance ``g`` (m), stiffness ``k_c`` (N/m), radius ``R`` (m); its
        friction is replaced by the scanned values.
    speed : float
        Spin ``Omega`` (rad/s), > 0.
    stator : rubrotor.engine.parts.Stator, optional
        Isotropic flexible stator; rigid when ``None``.
    """

    rotor: Jeffcott
    contact: Contact
    speed: float
    stator: Stator | None = None

    def __post_init__(self):
        c = self.contact
        if not law_of(c).linear or c.radius is None:
            raise InputError("contact", c, 'law = "linear" with a radius (m)')
        if not (isinstance(self.speed, int | float) and self.speed > 0):
            raise InputError("speed", self.speed, "a number > 0 (rad/s)")
        s = self.stator
        if s is not None and (s.mass_y != s.mass_z or s.stiffness_y != s.stiffness_z
                              or s.damping_y != s.damping_z):  # fmt: skip
            raise InputError("contact.stator", s, "an isotropic stator (steady whirl is circular)")

    def rolling_whirls(self, points: int = 4001) -> tuple[RollingWhirl, ...]:
        """:func:`rolling_whirls` of this case (so figures draw it without importing the study)."""
        return rolling_whirls(self, points)

    def at_speed(self, speed: float) -> DryWhirlCase:
        """The same rotor, contact and stator at spin ``speed`` (rad/s)."""
        return DryWhirlCase(self.rotor, self.contact, float(speed), self.stator)

    def impedance(self, omega):
        """Equivalent impedance ``Z = 1 / (1/Z_r + 1/Z_s)`` (N/m) at ``omega`` (rad/s)."""
        zr = self.rotor.impedance(omega)
        if self.stator is None:
            return zr
        s = self.stator
        zs = s.stiffness_y - s.mass_y * omega**2 + 1j * s.damping_y * omega
        return 1.0 / (1.0 / zr + 1.0 / zs)


@dataclass(frozen=True)
class RollingWhirl:
    """The steady rolling (dry-whirl) orbit of :func:`rolling_whirls`.

    Attributes
    ----------
    frequency : float
        Whirl frequency ``omega`` (rad/s), < 0 (backward).
    gap : float
        Relative orbit radius ``|D|`` (m), >= clearance.
    normal_force : float
        ``F_n`` (N).
    friction_needed : float
        ``mu_roll = Im Z / Re Z``: the least friction coefficient that holds the rolling.
    rotor_amplitude, stator_amplitude : complex
        ``A`` and ``B`` (m) with the orbit ``D`` along the real axis at ``t = 0``.
    """

    frequency: float
    gap: float
    normal_force: float
    friction_needed: float
    rotor_amplitude: complex
    stator_amplitude: complex


def coupled_frequencies(case: DryWhirlCase) -> tuple[float, ...]:
    """Coupled natural frequencies (rad/s) of rotor, contact spring and stator locked together.

    The undamped roots of ``1/Re Z_r + 1/Re Z_s + 1/k_c = 0``: ``sqrt((k + k_c)/m)`` for a
    rigid stator; for a flexible one the two natural frequencies of the chain ground - ``k`` -
    ``m`` - ``k_c`` - ``m_s`` - ``k_s`` - ground (increasing). See the module docstring.
    """
    r, kc = case.rotor, case.contact.stiffness
    if case.stator is None:
        return (float(np.sqrt((r.stiffness + kc) / r.mass)),)
    s = case.stator
    # det([[k + k_c - m w^2, -k_c], [-k_c, k_s + k_c - m_s w^2]]) = 0, a quadratic in w^2
    a = r.mass * s.mass_y
    b = -(r.mass * (s.stiffness_y + kc) + s.mass_y * (r.stiffness + kc))
    c = (r.stiffness + kc) * (s.stiffness_y + kc) - kc**2
    disc = np.sqrt(b * b - 4 * a * c)
    return (float(np.sqrt((-b - disc) / (2 * a))), float(np.sqrt((-b + disc) / (2 * a))))


def _rolling_at(case: DryWhirlCase, w: float) -> RollingWhirl:
    """The rolling orbit at whirl speed ``w = -omega`` (rad/s) once ``w |D(w)| = R Omega``."""
    g, kc = case.contact.clearance, case.contact.stiffness
    z = case.impedance(-w)
    d = g * kc / (kc + z.real)
    fn = -d * z.real
    force = -fn * (1 + 1j * z.imag / z.real)  # on the rotor, with n = 1
    zr = case.rotor.impedance(-w)
    b = 0j if case.stator is None else -force * (1.0 / z - 1.0 / zr)  # B = -F / Z_s
    return RollingWhirl(-w, d, fn, z.imag / z.real, force / zr, b)


def rolling_whirls(case: DryWhirlCase, points: int = 4001) -> tuple[RollingWhirl, ...]:
    """Every steady rolling backward whirl ``omega = -Omega R / |D|`` (module docstring).

    The full-contact orbit exists where ``-k_c < Re Z(omega) < 0``: one band above the rotor's
    natural frequency for a rigid stator, two for a flexible one (below the first coupled
    frequency, and above the stator's own natural frequency). In each band ``|omega| |D|`` is
    matched to ``R Omega`` by Brent's method on a bracket found on a grid of ``points``
    frequencies up to the highest coupled frequency.

    Returns
    -------
    tuple of RollingWhirl
        Increasing ``|omega|``; empty when ``Omega R`` is too small for any band.
    """
    g, kc, big_r = case.contact.clearance, case.contact.stiffness, case.contact.radius
    v = big_r * case.speed  # surface speed (m/s)

    def residual(w):  # w |D(w)| - R Omega (m/s); nan where no full-contact orbit
        re = case.impedance(-w).real
        return w * g * kc / (kc + re) - v if -kc < re < 0 else np.nan

    w_lo = np.sqrt(case.rotor.stiffness / case.rotor.mass)
    grid = np.linspace(w_lo, max(coupled_frequencies(case)), points)[1:-1]
    vals = np.array([residual(w) for w in grid])
    ok = np.isfinite(vals[:-1]) & np.isfinite(vals[1:])
    idx = np.flatnonzero(ok & (np.sign(vals[:-1]) != np.sign(vals[1:])))
    roots = [
        scipy.optimize.brentq(residual, grid[i], grid[i + 1], xtol=1e-13, rtol=1e-15) for i in idx
    ]
    return tuple(_rolling_at(case, w) for w in roots)


def whirl_frequency(time: np.ndarray, v: np.ndarray, w: np.ndarray) -> float:
    """Frequency (rad/s, signed: < 0 backward) of the tallest line of the full spectrum of ``v + i w``.

    The tallest line of the Hann-windowed full spectrum
    (:func:`rubrotor.full_spectrum`), then the maximum of the windowed
    spectrum's continuous magnitude ``|sum_n w_n z_n e^{-i 2 pi f t_n}|`` within one line of it
    (bounded Brent search): for a steady circular whirl it is the whirl frequency itself, not
    the nearest line.
    """
    dt = time[1] - time[0]
    z = (v - np.mean(v)) + 1j * (w - np.mean(w))
    spec = full_spectrum(z.real, z.imag, 1.0 / dt)
    k = int(np.argmax(spec.amplitudes))
    df = spec.frequencies[1] - spec.frequencies[0]
    tn = np.arange(len(z)) * dt
    zw = z * np.hanning(len(z) + 1)[:-1]

    def neg_mag(f):
        return -abs(np.sum(zw * np.exp(-2j * np.pi * f * tn)))

    f0 = spec.frequencies[k]
    opt = scipy.optimize.minimize_scalar(
        neg_mag, bounds=(f0 - df, f0 + df), method="bounded", options={"xatol": 1e-9 * df}
    )
    return float(2 * np.pi * opt.x)


@dataclass(frozen=True)
class DryWhirlScan:
    """Result of :func:`scan_friction` (or :func:`scan_speed`: one friction, several speeds).

    Attributes
    ----------
    frictions : ndarray
        Friction coefficient of each run (dimensionless).
    speeds : ndarray
        Spin speed of each run (rad/s).
    whirl_frequency : ndarray
        Whirl frequency of ``D`` over the last half of each run (rad/s, full spectrum, < 0
        backward).
    contact_fraction : ndarray
        Fraction of the last half in contact.
    gap : ndarray
        Mean ``|D|`` over the last half (m).
    backward : ndarray of bool
        Sustained backward whirl: in contact throughout the last half, whirl frequency < 0.
    threshold : float or None
        Friction scan: the smallest friction from which on every run whirls backward (``None``
        if the highest does not).
    rolling : tuple of tuple of RollingWhirl
        Per run, the closed-form rolling whirls at its speed (:func:`rolling_whirls`).
    coupled_frequencies : tuple of float
        Closed-form coupled natural frequencies (rad/s).
    rolling_condition : ndarray
        ``-Omega R / g`` (rad/s) of each run: the rolling condition for a stiff contact.
    case : DryWhirlCase
    """

    frictions: np.ndarray
    speeds: np.ndarray
    whirl_frequency: np.ndarray
    contact_fraction: np.ndarray
    gap: np.ndarray
    backward: np.ndarray
    threshold: float | None
    rolling: tuple
    coupled_frequencies: tuple
    rolling_condition: np.ndarray
    case: DryWhirlCase = field(repr=False)

    def predicted(self, index: int) -> RollingWhirl | None:
        """The closed-form rolling whirl nearest the measured frequency of run ``index``."""
        roll = self.rolling[index]
        if not roll:
            return None
        f = self.whirl_frequency[index]
        return min(roll, key=lambda r: abs(r.frequency - f))


@dataclass(frozen=True)
class _RelativeBasis:
    """DOFs ``[v, w, s_y, s_z]``: the contact station sees ``D = P - S``."""

    length: float = 1.0

    def rows(self, position: float) -> np.ndarray:
        """``(2, 4)``: ``[v - s_y, w - s_z]`` (m) at any ``position`` (m)."""
        return np.hstack([np.eye(2), -np.eye(2)])


def relative_system(case: DryWhirlCase) -> LinearSystem:
    """Rotor and flexible stator as one 4-DOF LinearSystem whose contact station reads ``D``.

    DOFs ``[v, w, s_y, s_z]`` (m). A contact on it acts ``+F`` on the rotor and ``-F`` on the
    stator, which is the flexible stator written as part of the rotor: it lets the stator start
    anywhere (the engine's own :class:`~rubrotor.engine.parts.Stator` starts at rest).
    """
    r, s = case.rotor, case.stator
    m = np.diag([r.mass, r.mass, s.mass_y, s.mass_z])
    k = np.diag([r.stiffness, r.stiffness, s.stiffness_y, s.stiffness_z])
    c = np.diag([r.damping, r.damping, s.damping_y, s.damping_z])
    return LinearSystem(m, k, c, np.zeros((4, 4)), _RelativeBasis())


def _rolling_state(case: DryWhirlCase) -> np.ndarray:
    """State on the rolling orbit of highest frequency (rotor, then stator when flexible)."""
    roll = rolling_whirls(case)
    if not roll:
        raise InputError("speed", case.speed, "a speed at which a rolling whirl exists")
    r = roll[-1]
    amps = [r.rotor_amplitude] + ([r.stator_amplitude] if case.stator is not None else [])
    q = [f(a) for a in amps for f in (np.real, np.imag)]
    qd = [f(1j * r.frequency * a) for a in amps for f in (np.real, np.imag)]
    return np.array(q + qd)


def _initial_state(case: DryWhirlCase, start) -> np.ndarray:
    if isinstance(start, np.ndarray) and start.shape == (4,):
        return start.astype(float)
    if isinstance(start, str) and start == "kick":
        return np.array([1.5 * case.contact.clearance, 0.0, 0.0, 0.0])
    if isinstance(start, str) and start == "rolling":
        return _rolling_state(case)
    raise InputError("start", start, '"kick", "rolling" or [v, w, v\', w\'] (m, m/s)')


def _one_run(case: DryWhirlCase, mu: float, x0, duration: float, step: float, save_every: int):
    contact = Contact(**{**case.contact.__dict__, "friction": float(mu)})
    if case.stator is not None and len(x0) == 8:  # the stator's state is given too
        system, station = relative_system(case), RubStation(contact)
    else:
        system, station = case.rotor.system(), RubStation(contact, stator=case.stator)
    run = Run(speed=case.speed, duration=duration, step=step, save_every=save_every, initial=x0)
    res = simulate_general(system, run, [station], progress=False)
    if res.status != "complete":
        raise InputError("simulation", res.message, "a run that completes (reduce the step)")
    ch = res.channels
    n = ch.shape[1]
    tail = slice(n // 2, n)
    dv, dw = ch[0, tail] - ch[4, tail], ch[1, tail] - ch[5, tail]
    freq = whirl_frequency(res.time[tail], dv, dw)
    frac = float(np.mean(ch[10, tail] > 0))
    return freq, frac, float(np.mean(np.hypot(dv, dw)))


def _scan(cases, mus, duration, step, save_every, start) -> DryWhirlScan:
    rows = [_one_run(c, mu, _initial_state(c, start), duration, step, save_every)
            for c, mu in zip(cases, mus, strict=True)]  # fmt: skip
    freq, frac, gap = (np.array(c) for c in zip(*rows, strict=True))
    back = (frac >= 0.999) & (freq < 0)
    threshold = None
    if back[-1]:
        first = 0 if back.all() else len(back) - int(np.argmin(back[::-1]))
        threshold = float(mus[first])
    speeds = np.array([c.speed for c in cases])
    return DryWhirlScan(np.asarray(mus, float), speeds, freq, frac, gap, back, threshold,
                        tuple(rolling_whirls(c) for c in cases), coupled_frequencies(cases[0]),
                        -speeds * cases[0].contact.radius / cases[0].contact.clearance,
                        cases[0])  # fmt: skip


def _check_values(name: str, values, strict: bool) -> np.ndarray:
    x = np.sort(np.asarray(values, float).ravel())
    bad = not len(x) or np.any(~np.isfinite(x)) or np.any(x <= 0 if strict else x < 0)
    if bad:
        raise InputError(name, values, f"a non-empty list of numbers {'>' if strict else '>='} 0")
    return x


def scan_friction(case: DryWhirlCase, frictions, *, duration: float = 0.4, step: float = 1e-5,
                  save_every: int = 4, start="kick") -> DryWhirlScan:  # fmt: skip
    """Simulate the rub at each friction and find the backward-whirl threshold.

    Parameters
    ----------
    case : DryWhirlCase
    frictions : sequence of float
        Friction coefficients (dimensionless), >= 0.
    duration : float
        Simulated time per run (s); the last half is analysed.
    step : float
        Fixed step (s) of the exponential integrator.
    save_every : int
        Steps per sample.
    start : {"kick", "rolling"} or ndarray
        Initial state: the rotor displaced by 1.5 clearances at rest (a flexible stator at
        rest), the closed-form rolling orbit of highest frequency (:func:`rolling_whirls`; rotor
        and stator on it), or ``[v, w, v', w']`` (m, m/s).

    Returns
    -------
    DryWhirlScan
    """
    mus = _check_values("frictions", frictions, strict=False)
    return _scan([case] * len(mus), mus, duration, step, save_every, start)


def scan_speed(case: DryWhirlCase, speeds, friction: float, *, duration: float = 0.4,
               step: float = 1e-5, save_every: int = 4, start="kick") -> DryWhirlScan:  # fmt: skip
    """Simulate the rub at one friction and several spin speeds (rad/s); see :func:`scan_friction`.

    Shows the whirl frequency following the rolling condition and bounded by the coupled
    frequencies (the result's ``threshold`` is ``None``).
    """
    om = _check_values("speeds", speeds, strict=True)
    cases = [DryWhirlCase(case.rotor, case.contact, float(w), case.stator) for w in om]
    res = _scan(cases, [float(friction)] * len(om), duration, step, save_every, start)
    return dataclasses.replace(res, threshold=None)
