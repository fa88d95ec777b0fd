"""Active magnetic bearings with their controller (``[[bearing]] type = "magnetic"``).

Each of the two lateral axes (y, z) is a differential electromagnet pair
(:mod:`rubrotor.core.amb`) closed by its own controller: the sensor and amplifier act as one
first-order low-pass of cut-off ``cutoff_hz`` on the measured displacement, and a PID law on the
filtered signal ``m`` sets the control current,

    m' = wc (x - m),    s' = -m,    i = -kp m + ki s - kd m',    wc = 2 pi cutoff_hz,

so that ``I(s) = -(kp + ki / s + kd s) wc / (s + wc) X(s)``. The controller's two states per axis
(``m``, ``s``) are integrated with the rotor in the time runs; the linear verbs use the bearing's
linearised force ``ks x + ki i`` with these states appended.

The electromagnet is given either by its build (``coil_turns``, ``pole_area`` m^2,
``pole_angle_rad``, ``nominal_gap`` m, ``bias_current`` A) or directly by its linearised
``ki`` (N/A) and ``ks`` (N/m) with ``nominal_gap`` and ``bias_current`` (the pole constant is then
``ki g0^2 / (4 i0)``, which gives ``ks = ki i0 / g0``: a given ``ks`` must agree to 1e-6).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.core.amb import MU0, MagnetAxis
from rubrotor.errors import InputError

__all__ = ["MagneticBearing"]


def _number(field, value, unit, *, minimum=0.0, strict=True):
    try:
        x = float(value)
    except (TypeError, ValueError):
        x = math.nan
    ok = math.isfinite(x) and (x > minimum if strict else x >= minimum)
    if not ok:
        sign = ">" if strict else ">="
        raise InputError(field, value, f"a finite number {sign} {minimum:g} ({unit})")
    return x


@dataclass(frozen=True)
class MagneticBearing:
    """One radial magnetic bearing and its per-axis PID controller (SI).

    Parameters
    ----------
    nominal_gap : float
        Air gap at the centre ``g0`` (m).
    bias_current : float
        ``i0`` (A).
    max_current : float
        Largest coil current the amplifier gives (A), above ``bias_current``.
    kp : float
        Proportional gain (A/m).
    ki : float
        Integral gain (A/(m s)).
    kd : float
        Derivative gain (A s/m).
    cutoff_hz : float
        Sensor and amplifier low-pass cut-off (Hz).
    coil_turns, pole_area, pole_angle_rad : float, optional
        The magnet's build (turns per magnet, one pole face's area m^2, pole half angle rad).
    current_gain, position_stiffness : float, optional
        Or its linearised ``ki`` (N/A) and ``ks`` (N/m) directly.
    name : str
        Key prefix in error messages, e.g. ``"bearing[1]"``.
    """

    nominal_gap: float
    bias_current: float
    max_current: float
    kp: float
    ki: float
    kd: float
    cutoff_hz: float
    coil_turns: float | None = None
    pole_area: float | None = None
    pole_angle_rad: float = 0.0
    current_gain: float | None = None
    position_stiffness: float | None = None
    name: str = "bearing"

    def __post_init__(self):
        n = self.name
        _number(f"{n}.nominal_gap", self.nominal_gap, "m")
        i0 = _number(f"{n}.bias_current", self.bias_current, "A")
        _number(f"{n}.max_current", self.max_current, "A", minimum=i0)
        _number(f"{n}.kp", self.kp, "A/m", strict=False)
        _number(f"{n}.ki", self.ki, "A/(m s)", strict=False)
        _number(f"{n}.kd", self.kd, "A s/m", strict=False)
        _number(f"{n}.cutoff_hz", self.cutoff_hz, "Hz")
        built = self.coil_turns is not None or self.pole_area is not None
        given = self.current_gain is not None
        if built == given:
            raise InputError(f"{n}.current_gain", self.current_gain,
                             "either the magnet's build (coil_turns, pole_area) or its "
                             "current_gain (N/A), not both and not neither")  # fmt: skip
        if built:
            _number(f"{n}.coil_turns", self.coil_turns, "1")
            _number(f"{n}.pole_area", self.pole_area, "m^2")
            if not 0.0 <= float(self.pole_angle_rad) < 0.5 * math.pi:
                raise InputError(f"{n}.pole_angle_rad", self.pole_angle_rad, "a number in [0, pi/2) (rad)")
        else:
            _number(f"{n}.current_gain", self.current_gain, "N/A")
            if self.position_stiffness is not None:
                ks = _number(f"{n}.position_stiffness", self.position_stiffness, "N/m")
                expected = self.current_gain * i0 / self.nominal_gap
                if abs(ks - expected) > 1e-6 * expected:
                    raise InputError(f"{n}.position_stiffness", ks,
                                     f"ki i0 / g0 = {expected:.6g} N/m for this current gain, "
                                     "bias and gap (one magnet pair)")  # fmt: skip

    @property
    def pole_constant(self) -> float:
        """``k = mu0 N^2 A cos(alpha) / 4`` (N m^2 / A^2)."""
        if self.current_gain is not None:
            return self.current_gain * self.nominal_gap**2 / (4.0 * self.bias_current)
        return MU0 * self.coil_turns**2 * self.pole_area * math.cos(self.pole_angle_rad) / 4.0

    @property
    def axis(self) -> MagnetAxis:
        """The compiled force's parameters."""
        return MagnetAxis(self.pole_constant, self.nominal_gap, self.bias_current, self.max_current)

    @property
    def linear_gains(self) -> tuple[float, float]:
        """``(ki, ks)``: the force's current gain (N/A) and negative stiffness (N/m) at the centre."""
        k, g0, i0 = self.pole_constant, self.nominal_gap, self.bias_current
        return 4.0 * k * i0 / g0**2, 4.0 * k * i0**2 / g0**3

    def controller(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """One axis's controller ``(A, B, C, D)``: states ``(m, s)``, input ``x`` (m), output ``i`` (A).

        ``[m', s'] = A [m, s] + B x`` and ``i = C [m, s] + D x``.
        """
        wc = 2.0 * math.pi * self.cutoff_hz
        a = np.array([[-wc, 0.0], [-1.0, 0.0]])
        b = np.array([[wc], [0.0]])
        c = np.array([[-self.kp + self.kd * wc, self.ki]])
        d = np.array([[-self.kd * wc]])
        return a, b, c, d

    def closed_loop(self, mass: float) -> np.ndarray:
        """State matrix of one axis carrying ``mass`` (kg) at rest: states ``(x, v, m, s)``."""
        ki, ks = self.linear_gains
        a, b, c, d = self.controller()
        out = np.zeros((4, 4))
        out[0, 1] = 1.0
        out[1, 0] = (ks + ki * d[0, 0]) / mass
        out[1, 2:] = ki * c[0] / mass
        out[2:, 0] = b[:, 0]
        out[2:, 2:] = a
        return out

    def check_stable_at_rest(self, mass: float) -> None:
        """Refuse a controller that does not hold ``mass`` (kg) at rest, naming its eigenvalue.

        Raises
        ------
        InputError
            On ``{name}.kp``, with the closed loop's eigenvalue of largest real part (1/s).
        """
        lam = np.linalg.eigvals(self.closed_loop(mass))
        worst = lam[np.argmax(lam.real)]
        if worst.real >= 0.0:
            ki, ks = self.linear_gains
            raise InputError(f"{self.name}.kp", self.kp,
                             f"gains that hold the {mass:g} kg it carries at rest: the closed loop "
                             f"has the eigenvalue {worst.real:.4g}{worst.imag:+.4g}j 1/s "
                             f"(kp ki_magnet must exceed ks: kp > {ks / ki:.4g} A/m, and kd > 0)")  # fmt: skip
