"""External forces on the rotor: unbalance, radial load, modal damping and the contact law.

Every object here is a small frozen dataclass in SI units, validated on construction; the seed's
dimensionless values are converted by :class:`rubrotor.rotors.shaft.Dimensionless` before they get here.

Contact (seed eqs. 10-16, corrected as in the model notes)
----------------------------------------------------------
With ``P = v + i w`` the displacement of the shaft centre at the contact station, ``d = |P|``,
``n = P / d`` and ``eps = d - g``:

* ``law = "hertz"`` (Hunt-Crossley): ``F_n = k_h eps^1.5 (1 + b_h eps_dot)`` for ``eps > 0``,
  with ``eps_dot = Re(conj(n) P')``; ``F_n`` is clipped at 0 (no adhesion).
* ``law = "linear"`` (penalty spring-dashpot, as in Jeffcott-rub models and ROSS):
  ``F_n = k eps + c eps_dot``, clipped at 0.
* Coulomb friction ``F_t = mu F_n`` along the tangent ``t = i n``. With ``friction_sign =
  "physical"`` (default) it opposes the sliding velocity of the rotor surface on the stator,
  ``v_s = R Omega + Im(conj(n) P')`` (spin runs from +v towards +w); the sign function is
  regularised as ``v_s / sqrt(v_s^2 + v_r^2)`` with ``v_r = friction_regularization`` (m/s).
  ``friction_sign = "seed"`` reproduces seed eqs. (15)-(16) literally: the friction always points
  along ``+t``, i.e. *with* the spin. It feeds energy into forward whirl and is non-physical; it
  exists only to show what the seed's equations do.

The force on the rotor is ``F = -F_n n (1 + i mu sigma)`` with ``sigma = sign(v_s)`` (physical)
or ``-1`` (seed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError

__all__ = [
    "Unbalance",
    "RadialLoad",
    "Contact",
    "ModalDamping",
    "restitution_damping",
    "ThermalBow",
    "BOW_SHAPES",
    "CONTACT_LAWS",
    "FRICTION_SIGNS",
    "RESTITUTION_MODELS",
    "FreeSpin",
    "TouchdownRing",
]

CONTACT_LAWS = ("hertz", "linear")
_LAW_UNITS = {"hertz": ("N/m^1.5", "s/m"), "linear": ("N/m", "N s/m")}  # stiffness, damping
FRICTION_SIGNS = ("physical", "seed")
RESTITUTION_MODELS = ("hunt-crossley", "lankarani-nikravesh", "flores")
BOW_SHAPES = ("arc",)
"""Bow shapes of a thermal bow along the rotor (see :class:`ThermalBow`)."""


def _number(field: str, value, unit: str, *, minimum=None, strict=False, maximum=None) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise InputError(field, value, f"a number ({unit})")
    v = float(value)
    ok = math.isfinite(v)
    if ok and minimum is not None:
        ok = v > minimum if strict else v >= minimum
    if ok and maximum is not None:
        ok = v <= maximum
    if not ok:
        rng = []
        if minimum is not None:
            rng.append(f"{'>' if strict else '>='} {minimum:g}")
        if maximum is not None:
            rng.append(f"<= {maximum:g}")
        raise InputError(
            field, value, f"a finite number {' and '.join(rng)} ({unit})".replace("  ", " ")
        )
    return v


def restitution_damping(
    restitution: float, impact_speed: float, model: str = "hunt-crossley"
) -> float:
    """Hertz damping factor ``b_h`` (s/m) from a coefficient of restitution.

    Parameters
    ----------
    restitution : float
        Coefficient of restitution ``e`` in (0, 1] (dimensionless).
    impact_speed : float
        Normal approach speed at impact ``v0`` (m/s), > 0.
    model : {"hunt-crossley", "lankarani-nikravesh", "flores"}
        ``3 (1 - e) / (2 v0)`` (Hunt and Crossley 1975), ``3 (1 - e^2) / (4 v0)`` (Lankarani and
        Nikravesh 1990) or ``8 (1 - e) / (5 e v0)`` (Flores et al. 2011).

    Returns
    -------
    float
        ``b_h`` (s/m) in ``F_n = k_h eps^1.5 (1 + b_h eps_dot)``. It grows as ``e`` falls: a larger
        ``b_h`` means a *less* elastic impact (the seed states the opposite).

    Examples
    --------
    >>> restitution_damping(0.8, 1.0)
    0.29999999999999993
    """
    e = _number(
        "contact.restitution", restitution, "dimensionless", minimum=0, strict=True, maximum=1
    )
    v0 = _number("contact.impact_speed", impact_speed, "m/s", minimum=0, strict=True)
    if model == "hunt-crossley":
        return 3 * (1 - e) / (2 * v0)
    if model == "lankarani-nikravesh":
        return 3 * (1 - e * e) / (4 * v0)
    if model == "flores":
        return 8 * (1 - e) / (5 * e * v0)
    raise InputError(
        "contact.restitution_model", model, " or ".join(f'"{m}"' for m in RESTITUTION_MODELS)
    )


@dataclass(frozen=True)
class Unbalance:
    """Mass unbalance rotating with the spin.

    Parameters
    ----------
    magnitude : float
        ``m e`` (kg m), >= 0. The force is ``m e Omega^2`` (N), rotating forward.
    position : float
        Axial station ``a_u`` (m) in (0, L).
    phase : float
        Angle of the unbalance at ``t = 0`` from the +v axis towards +w (rad).
    """

    magnitude: float = 0.0
    position: float | None = None
    phase: float = 0.0

    def __post_init__(self):
        object.__setattr__(
            self, "magnitude", _number("unbalance.magnitude", self.magnitude, "kg m", minimum=0)
        )
        if self.position is not None:
            object.__setattr__(self, "position", _number("unbalance.position", self.position, "m"))
        object.__setattr__(self, "phase", _number("unbalance.phase", self.phase, "rad"))


@dataclass(frozen=True)
class RadialLoad:
    """A constant radial point force (gravity or a side load).

    Parameters
    ----------
    force_y, force_z : float
        Components (N) along v and w.
    position : float, optional
        Axial station (m) in (0, L); midspan by default.
    """

    force_y: float = 0.0
    force_z: float = 0.0
    position: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "force_y", _number("load.force_y", self.force_y, "N"))
        object.__setattr__(self, "force_z", _number("load.force_z", self.force_z, "N"))
        if self.position is not None:
            object.__setattr__(self, "position", _number("load.position", self.position, "m"))


@dataclass(frozen=True)
class ModalDamping:
    """Viscous modal damping, a ratio per mode.

    The ratio ``zeta_n`` of mode ``n`` damps both branches of that mode (bending and shear):
    ``C_n = M_n Phi diag(2 zeta_n omega_j) Phi^T M_n`` with ``Phi`` the mass-normalised
    non-rotating eigenvectors and ``omega_j`` the non-rotating frequencies (rad/s). It is
    stationary (non-rotating) damping; it adds no internal (rotating) damping instability.

    Parameters
    ----------
    ratios : tuple of float
        ``zeta_n`` (dimensionless, >= 0, < 1) for ``n = 1, 2, ...``; a single value applies to all
        modes; a shorter tuple is padded with its last value.
    """

    ratios: tuple = (0.0,)

    def __post_init__(self):
        r = self.ratios
        if isinstance(r, int | float) and not isinstance(r, bool):
            r = (r,)
        if not isinstance(r, tuple | list) or len(r) == 0:
            raise InputError("damping.ratio", self.ratios, "a number or a non-empty list in [0, 1)")
        vals = tuple(
            _number("damping.ratio", x, "dimensionless", minimum=0, maximum=0.999999) for x in r
        )
        object.__setattr__(self, "ratios", vals)

    def ratio(self, n: int) -> float:
        """``zeta_n`` of mode ``n`` (dimensionless)."""
        return self.ratios[min(n, len(self.ratios)) - 1]


@dataclass(frozen=True)
class Contact:
    """Rotor-stator contact with a rigid, centred, circular stator.

    Parameters
    ----------
    clearance : float
        Radial gap ``g`` (m), > 0.
    stiffness : float
        Hertz ``k_h`` (N/m^1.5) for ``law = "hertz"``, spring ``k`` (N/m) for ``"linear"``; > 0.
    damping : float
        Hunt-Crossley ``b_h`` (s/m) for ``"hertz"``; dashpot ``c`` (N s/m) for ``"linear"``; >= 0.
    friction : float
        Coulomb coefficient ``mu`` (dimensionless), >= 0.
    position : float, optional
        Axial station (m) in (0, L); midspan by default.
    law : {"hertz", "linear"}
        Contact law (see the module docstring).
    friction_sign : {"physical", "seed"}
        ``"physical"`` opposes sliding; ``"seed"`` is the seed's literal, non-physical sign.
    radius : float, optional
        Radius of the rubbing surface (m) used for the sliding speed ``R Omega``; the shaft radius
        by default.
    friction_regularization : float
        Velocity scale ``v_r`` (m/s) of the smoothed sign of the sliding velocity.
    """

    clearance: float
    stiffness: float
    damping: float = 0.0
    friction: float = 0.0
    position: float | None = None
    law: str = "hertz"
    friction_sign: str = "physical"
    radius: float | None = None
    friction_regularization: float = 1e-3

    def __post_init__(self):
        object.__setattr__(
            self,
            "clearance",
            _number("contact.clearance", self.clearance, "m", minimum=0, strict=True, maximum=1e3),
        )
        if self.law not in CONTACT_LAWS:
            raise InputError("contact.law", self.law, " or ".join(f'"{x}"' for x in CONTACT_LAWS))
        unit_k, unit_c = _LAW_UNITS[self.law]
        object.__setattr__(
            self,
            "stiffness",
            _number("contact.stiffness", self.stiffness, unit_k, minimum=0, strict=True),
        )
        object.__setattr__(
            self, "damping", _number("contact.damping", self.damping, unit_c, minimum=0)
        )
        object.__setattr__(
            self, "friction", _number("contact.friction", self.friction, "dimensionless", minimum=0)
        )
        if self.position is not None:
            object.__setattr__(self, "position", _number("contact.position", self.position, "m"))
        if self.friction_sign not in FRICTION_SIGNS:
            raise InputError(
                "contact.friction_sign", self.friction_sign, '"physical" or "seed" (non-physical)'
            )
        if self.radius is not None:
            object.__setattr__(
                self, "radius", _number("contact.radius", self.radius, "m", minimum=0, strict=True)
            )
        object.__setattr__(
            self,
            "friction_regularization",
            _number(
                "contact.friction_regularization",
                self.friction_regularization,
                "m/s",
                minimum=0,
                strict=True,
            ),
        )

    @property
    def law_code(self) -> int:
        """Integer code of the law for the compiled kernel: 0 Hertz, 1 linear."""
        return CONTACT_LAWS.index(self.law)

    @property
    def sign_code(self) -> int:
        """Integer code of the friction sign for the kernel: 0 physical, 1 seed."""
        return FRICTION_SIGNS.index(self.friction_sign)


@dataclass(frozen=True)
class ThermalBow:
    """Thermal bow of the rotor at its rubbing stations (the Newkirk effect).

    Each contact station ``j`` carries a complex bow ``b_j`` (m) in the rotor-fixed frame: the
    bow's deflection at that station, its angle measured from the unbalance reference of the
    rotor towards the spin. It relaxes towards the bow driven by the revolution-averaged heat
    input ``H_j`` (W, a complex vector pointing at the hot spot)::

        tau db_j/dt = -b_j + beta exp(-i phi) H_j

    (:mod:`rubrotor.studies.thermal` derives it and documents where the heat goes).

    Parameters
    ----------
    time_constant : float
        Thermal time constant ``tau`` (s), > 0.
    bow_per_heat : float
        ``beta`` (m/W): the steady bow at the rubbing station per watt of heat input, >= 0.
    hot_spot_lag : float
        ``phi`` (rad): angle by which the hot spot lags the high spot (behind it, against the
        spin), in (-pi, pi); 0 puts the hot spot at the high spot.
    bow_shape : {"arc"}
        Shape along the rotor: ``"arc"`` is a uniform curvature (a circular arc, to first
        order a parabola) through the outermost two bearings, scaled to ``b_j`` at station
        ``j``.
    """

    time_constant: float
    bow_per_heat: float
    hot_spot_lag: float = 0.0
    bow_shape: str = "arc"

    def __post_init__(self):
        tau = _number("thermal.time_constant", self.time_constant, "s", minimum=0, strict=True)
        beta = _number("thermal.bow_per_heat", self.bow_per_heat, "m/W", minimum=0)
        lag = _number("thermal.hot_spot_lag", self.hot_spot_lag, "rad")
        if not -math.pi < lag < math.pi:
            raise InputError("thermal.hot_spot_lag", lag, "an angle in (-pi, pi) rad")
        if self.bow_shape not in BOW_SHAPES:
            raise InputError("thermal.bow_shape", self.bow_shape, f"one of {BOW_SHAPES}")
        object.__setattr__(self, "time_constant", tau)
        object.__setattr__(self, "bow_per_heat", beta)
        object.__setattr__(self, "hot_spot_lag", lag)


@dataclass(frozen=True)
class FreeSpin:
    """The spin equation's torques.

    Parameters
    ----------
    drive_torque : float or tuple of float
        Motor torque (N m): a constant, or values at ``drive_speeds`` (linear between them,
        constant beyond).
    drive_speeds : tuple of float, optional
        Speeds (rad/s, increasing) of a torque table.
    drag : float
        Windage/bearing drag coefficient (N m s): torque ``-drag Omega``.
    """

    drive_torque: float | tuple = 0.0
    drive_speeds: tuple | None = None
    drag: float = 0.0

    def table(self) -> tuple[np.ndarray, np.ndarray]:
        """Speeds (rad/s) and torques (N m) of the drive as arrays (one row for a constant)."""
        tq = np.atleast_1d(np.asarray(self.drive_torque, float))
        if self.drive_speeds is None:
            if tq.size != 1:
                raise InputError("speed.drive_speeds", None, "speeds (rad/s) for a torque table")
            return np.zeros(1), tq
        w = np.asarray(self.drive_speeds, float)
        if w.shape != tq.shape or w.size < 2 or np.any(np.diff(w) <= 0):
            raise InputError("speed.drive_speeds", self.drive_speeds,
                             "increasing speeds (rad/s), one per drive_torque value, >= 2")  # fmt: skip
        return w, tq


@dataclass(frozen=True)
class TouchdownRing:
    """The spinning inner ring of a touchdown bearing, the stator of one contact.

    Parameters
    ----------
    inertia : float
        Polar inertia of the ring (kg m^2), > 0.
    radius : float
        Radius of the ring's bore where the rotor touches it (m), > 0.
    drag : float
        The ring bearing's drag coefficient (N m s): torque ``-drag omega_ring``.
    """

    inertia: float
    radius: float
    drag: float = 0.0

    def __post_init__(self):
        for name in ("inertia", "radius"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"contact.ring_{name}", v, "a number > 0")
        if not (math.isfinite(self.drag) and self.drag >= 0):
            raise InputError("contact.ring_drag", self.drag, "a number >= 0 (N m s)")
