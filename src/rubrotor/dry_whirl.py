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
  from above it is one real equation for ``omega``, solved by :func:`rolling_whirl`. It needs
  the friction ``tau <= mu``: ``mu_roll = Im Z / Re Z`` at that frequency is the smallest
  friction that can hold it.
* **Bounds.** ``-k_c < Re Z < 0`` holds between the rotor's own natural frequency and the
  coupled natural frequency of rotor, contact spring and stator in series, the root of
  ``1/Re Z_r + 1/Re Z_s + 1/k_c = 0`` (undamped; ``sqrt((k + k_c)/m)`` for a rigid stator,
  ``~ sqrt((k + k_s)/(m + m_s))`` for a flexible stator and a stiff contact):
  :func:`coupled_frequency`. As ``Omega R / g`` approaches it the penetration grows and the
  whirl stays below it; this is where a rolling whirl turns into whip.

All frequencies in rad/s, lengths in m, forces in N.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.optimize

from rubrotor.analysis.spectra import full_spectrum
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.model import RubStation, Run, Stator
from rubrotor.errors import InputError
from rubrotor.forces import Contact
from rubrotor.linear import LinearSystem

__all__ = [
    "Jeffcott",
    "DryWhirlCase",
    "RollingWhirl",
    "DryWhirlScan",
    "rolling_whirl",
    "coupled_frequency",
    "whirl_frequency",
    "scan_friction",
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
        """The rotor as a 2-DOF :class:`rubrotor.linear.LinearSystem` (DOFs ``v, w`` in m)."""
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
    contact : rubrotor.forces.Contact
        ``law="linear"``, clearance ``g`` (m), stiffness ``k_c`` (N/m), radius ``R`` (m); its
        friction is replaced by the scanned values.
    speed : float
        Spin ``Omega`` (rad/s), > 0.
    stator : rubrotor.engine.model.Stator, optional
        Isotropic flexible stator; rigid when ``None``.
    """

    rotor: Jeffcott
    contact: Contact
    speed: float
    stator: Stator | None = None

    def __post_init__(self):
        c = self.contact
        if c.law != "linear" or c.radius is None:
            raise InputError("contact", c, 'law = "linear" with a radius (m)')
        if not (isinstance(self.speed, int | float) and self.speed > 0):
            raise InputError("speed", self.speed, "a number > 0 (rad/s)")
        s = self.stator
        if s is not None and (s.mass_y != s.mass_z or s.stiffness_y != s.stiffness_z
                              or s.damping_y != s.damping_z):  # fmt: skip
            raise InputError("contact.stator", s, "an isotropic stator (steady whirl is circular)")

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
    """The steady rolling (dry-whirl) orbit of :func:`rolling_whirl`.

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


def coupled_frequency(case: DryWhirlCase) -> float:
    """Coupled natural frequency (rad/s) of rotor, contact spring and stator in series.

    The undamped root above the rotor's ``sqrt(k/m)`` of ``1/Re Z_r + 1/Re Z_s + 1/k_c = 0``
    (``sqrt((k + k_c)/m)`` for a rigid stator); see the module docstring.
    """
    r, kc = case.rotor, case.contact.stiffness
    if case.stator is None:
        return float(np.sqrt((r.stiffness + kc) / r.mass))
    s = case.stator
    # in series: the equivalent stiffness at the rotor of (contact spring + stator) in series
    k_rot, m_rot, k_st, m_st = r.stiffness, r.mass, s.stiffness_y, s.mass_y

    def chain(w2):
        return (k_rot - m_rot * w2) * (k_st - m_st * w2 + kc) + kc * (k_st - m_st * w2)

    # chain(w2) = 0 is a quadratic in w2: both natural frequencies of the 2-mass chain
    a = m_rot * m_st
    b = -(m_rot * (k_st + kc) + k_rot * m_st + kc * m_st)
    c = k_rot * (k_st + kc) + kc * k_st
    roots = np.sort(np.roots([a, b, c]).real)
    lo = roots[0]
    assert abs(chain(lo)) <= 1e-9 * c
    return float(np.sqrt(lo))


def rolling_whirl(case: DryWhirlCase) -> RollingWhirl:
    """The steady rolling backward whirl ``omega = -Omega R / |D|`` (see the module docstring).

    Returns
    -------
    RollingWhirl

    Raises
    ------
    InputError
        When no rolling whirl exists at this speed (``Omega R / g`` at or below the rotor's
        natural frequency).
    """
    g, kc, big_r = case.contact.clearance, case.contact.stiffness, case.contact.radius
    v = big_r * case.speed  # surface speed (m/s)
    w_lo = np.sqrt(case.rotor.stiffness / case.rotor.mass)
    w_hi = coupled_frequency(case)

    def gap(w):  # |D| (m) at whirl speed w = -omega > 0 (inf where no full-contact orbit)
        re = case.impedance(-w).real
        return g * kc / (kc + re) if -kc < re < 0 else np.inf

    def residual(w):
        return w * gap(w) - v

    # Re Z < 0 just above w_lo (and the stator's resonances) and -> -k_c at w_hi
    grid = np.linspace(w_lo, w_hi, 2001)[1:-1]
    vals = np.array([residual(w) for w in grid])
    ok = np.isfinite(vals)
    idx = np.flatnonzero(ok[:-1] & ok[1:] & (np.sign(vals[:-1]) != np.sign(vals[1:])))
    if not len(idx):
        raise InputError(
            "speed",
            case.speed,
            "a speed with Omega R / clearance above the rotor's natural frequency",
        )
    i = idx[0]
    w = scipy.optimize.brentq(residual, grid[i], grid[i + 1], xtol=1e-14, rtol=1e-15)
    z = case.impedance(-w)
    d = gap(w)
    fn = -d * z.real
    force = -fn * (1 + 1j * z.imag / z.real)  # on the rotor, with n = 1
    zr = case.rotor.impedance(-w)
    b = 0j if case.stator is None else -force * (1.0 / z - 1.0 / zr)  # B = -F / Z_s
    return RollingWhirl(-w, d, fn, z.imag / z.real, force / zr, b)


def whirl_frequency(time: np.ndarray, v: np.ndarray, w: np.ndarray) -> float:
    """Frequency (rad/s, signed) of the tallest line of the full spectrum of ``v + i w``.

    The peak of the Hann-windowed full spectrum (:func:`rubrotor.analysis.spectra.full_spectrum`)
    refined by a parabola through the log amplitudes of the three lines around it.
    """
    fs = 1.0 / (time[1] - time[0])
    spec = full_spectrum(v - np.mean(v), w - np.mean(w), fs)
    a = np.log(spec.amplitudes + 1e-300)
    k = int(np.argmax(a))
    df = spec.frequencies[1] - spec.frequencies[0]
    shift = 0.0
    if 0 < k < len(a) - 1:
        den = a[k - 1] - 2 * a[k] + a[k + 1]
        shift = 0.5 * (a[k - 1] - a[k + 1]) / den if den else 0.0
    return float(2 * np.pi * (spec.frequencies[k] + shift * df))


@dataclass(frozen=True)
class DryWhirlScan:
    """Result of :func:`scan_friction`.

    Attributes
    ----------
    frictions : ndarray
        Scanned friction coefficients, increasing.
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
        The smallest scanned friction from which on every run whirls backward (``None`` if none).
    rolling : RollingWhirl or None
        The closed-form rolling whirl at this speed (``None`` when none exists).
    coupled_frequency : float
        Closed-form coupled natural frequency (rad/s).
    rolling_frequency : float
        ``-Omega R / g`` (rad/s): the rolling condition for a stiff contact.
    case : DryWhirlCase
    """

    frictions: np.ndarray
    whirl_frequency: np.ndarray
    contact_fraction: np.ndarray
    gap: np.ndarray
    backward: np.ndarray
    threshold: float | None
    rolling: RollingWhirl | None
    coupled_frequency: float
    rolling_frequency: float
    case: DryWhirlCase = field(repr=False)


def _initial_state(case: DryWhirlCase, start) -> np.ndarray:
    g = case.contact.clearance
    if isinstance(start, str) and start == "kick":
        return np.array([1.5 * g, 0.0, 0.0, 0.0])
    if isinstance(start, str) and start == "rolling":
        roll = rolling_whirl(case)
        a = roll.rotor_amplitude
        return np.array(
            [a.real, a.imag, (1j * roll.frequency * a).real, (1j * roll.frequency * a).imag]
        )
    raise InputError("start", start, '"kick" (rotor at 1.5 clearances, at rest) or "rolling"')


def _one_run(case: DryWhirlCase, mu: float, x0, duration: float, step: float, save_every: int):
    contact = Contact(**{**case.contact.__dict__, "friction": float(mu)})
    station = RubStation(contact, stator=case.stator)
    run = Run(speed=case.speed, duration=duration, step=step, save_every=save_every, initial=x0)
    res = simulate_general(case.rotor.system(), run, [station], progress=False)
    ch = res.channels
    n = ch.shape[1]
    tail = slice(n // 2, n)
    dv, dw = ch[0, tail] - ch[4, tail], ch[1, tail] - ch[5, tail]
    freq = whirl_frequency(res.time[tail], dv, dw)
    frac = float(np.mean(ch[10, tail] > 0))
    return freq, frac, float(np.mean(np.hypot(dv, dw))), res


def scan_friction(
    case: DryWhirlCase,
    frictions,
    *,
    duration: float = 0.4,
    step: float = 1e-5,
    save_every: int = 4,
    start="kick",
) -> DryWhirlScan:
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
        Initial state: the rotor displaced by 1.5 clearances at rest, the closed-form rolling
        orbit, or ``[v, w, v', w']`` (m, m/s); a flexible stator starts at rest.

    Returns
    -------
    DryWhirlScan
    """
    mus = np.sort(np.asarray(frictions, float))
    if mus.ndim != 1 or not len(mus) or np.any(~np.isfinite(mus)) or np.any(mus < 0):
        raise InputError("frictions", frictions, "a non-empty list of numbers >= 0")
    x0 = start if isinstance(start, np.ndarray) else _initial_state(case, start)
    rows = [_one_run(case, mu, x0, duration, step, save_every)[:3] for mu in mus]
    freq, frac, gap = (np.array(c) for c in zip(*rows, strict=True))
    back = (frac >= 0.999) & (freq < 0)
    threshold = None
    if back[-1]:
        first = len(back) - int(np.argmin(back[::-1])) if not back.all() else 0
        threshold = float(mus[first])
    try:
        roll = rolling_whirl(case)
    except InputError:
        roll = None
    g = case.contact.clearance
    return DryWhirlScan(mus, freq, frac, gap, back, threshold, roll, coupled_frequency(case),
                        -case.speed * case.contact.radius / g, case)  # fmt: skip
