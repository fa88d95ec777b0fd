"""Integrator settings: which method, which steps, what to save.

A value object, validated on construction, read by :func:`rubrotor.simulate.simulate`.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass

from rubrotor.errors import InputError
from rubrotor.rotors.forces import _number

__all__ = [
    "Integrator",
    "METHODS",
    "DEFAULT_SAMPLES_PER_REV",
    "STEPPERS",
    "StepperSpec",
    "INITIAL_STATES",
    "SHAFT_INITIAL_STATES",
    "ADAPTIVE_LEVELS",
]

StepperSpec = namedtuple("StepperSpec", ["order", "engines", "adaptive", "summary"])
"""One stepper: its design ``order`` of accuracy, the ``engines`` that offer it (``"shaft"``:
the continuous shaft's modal engine, :mod:`rubrotor.engine.shaft_steppers`; ``"general"``: the
general rotor's engine, :mod:`rubrotor.engine.driver`), whether it chooses its own steps
(``adaptive``) and a one-line ``summary``."""

STEPPERS = {
    "exponential": StepperSpec(
        2, ("shaft", "general"), False,
        "fixed steps: the linear rotor propagated exactly, the contact force held linear over a "
        "step and solved implicitly",
    ),
    "adaptive": StepperSpec(
        2, ("shaft",), True,
        "exponential with error-controlled dyadic steps; the force held quadratic (order 3) "
        "while the rotor stays in contact at a constant step",
    ),
    "abm": StepperSpec(
        4, ("shaft",), False,
        "the seed's Adams-Bashforth-Moulton PECE on the modal system, started with RK4",
    ),
    "free-flight": StepperSpec(
        2, ("general",), True,
        "exact free flight to each sample or located onset, contact steps with the force held "
        "linear",
    ),
    "collocation": StepperSpec(
        4, ("general",), True,
        "exact free flight, contact steps by exponential Lobatto collocation (force held "
        "quadratic)",
    ),
    "runup": StepperSpec(
        2, ("general",), False,
        "fixed steps at a speed varying in time, the unbalance an input at the varying speed",
    ),
}  # fmt: skip
"""Every stepper of every engine (name -> :class:`StepperSpec`). The engines' factory tables
(``rubrotor.engine.shaft_steppers.FACTORIES``, the general engine's) are keyed by these names."""

METHODS = {name: STEPPERS[name].order for name in ("exponential", "abm")}
"""The ``simulation.method`` choices of :class:`Integrator` and their design orders of
accuracy (``"adaptive"`` is ``"exponential"`` without a fixed step)."""

INITIAL_STATES = ("rest", "static", "steady")
"""States a run may start from: at rest (zero displacement and velocity), the static deflection
under the constant loads, or the steady (synchronous unbalance plus static) response. The
continuous shaft offers :data:`SHAFT_INITIAL_STATES`."""
SHAFT_INITIAL_STATES = ("rest", "steady")
"""The initial states of the continuous shaft's runs."""

ADAPTIVE_LEVELS = 21
"""Dyadic levels of the adaptive steppers: the finest step is ``H / 2^(ADAPTIVE_LEVELS - 1)``."""

DEFAULT_SAMPLES_PER_REV = 256


@dataclass(frozen=True)
class Integrator:
    """How to integrate.

    Parameters
    ----------
    revolutions : float, optional
        Simulated length in spin revolutions. Give this or ``duration``.
    duration : float, optional
        Simulated length (s).
    method : {"exponential", "abm"}
        ``"exponential"`` (default): the linear rotor is propagated exactly (diagonalised modal
        propagator, unbalance and constant load integrated exactly); the contact force is held
        linear over a step and solved implicitly (Newton on its 2 components): order 2 with a
        fixed step. Adaptive runs hold it quadratic through the last three forces while the rotor
        stays in contact at a constant step (order 3), with the step controlled by the
        second-order error estimate (local extrapolation).
        ``"abm"``: the seed's fixed-step 4th-order Adams-Bashforth-Moulton predictor-corrector
        (PECE), started with classical Runge-Kutta, on the real first-order modal system.
    dtau : float, optional
        Fixed step as a fraction of a spin radian, ``d tau = Omega dt`` (dimensionless).
    dt : float, optional
        Fixed step (s). Give at most one of ``dtau`` and ``dt``. With neither, ``"exponential"``
        chooses its own steps (dyadic subdivisions of the output spacing) to meet ``rtol``/``atol``
        and refines every contact onset and separation; ``"abm"`` needs a step.
    rtol : float
        Relative tolerance of the adaptive steps (dimensionless).
    atol : float
        Absolute tolerance of the adaptive steps on the contact-point displacement (m).
    output_dtau : float, optional
        Spacing of the saved samples in spin radians for adaptive runs; default
        ``2 pi / 256`` (256 samples per revolution).
    sample_rate : float, optional
        Sample rate of the saved signal (Hz) for adaptive runs; alternative to ``output_dtau``.
    save_every : int
        Save every k-th fixed step (>= 1).
    probes : tuple of float
        Extra axial stations (m) where displacement, velocity and acceleration are saved.
    max_displacement : float, optional
        A run whose contact-point displacement exceeds this (m) is stopped as diverged and returned
        marked partial; default 1000 x the clearance or 0.1 L without contact.
    """

    revolutions: float | None = None
    duration: float | None = None
    method: str = "exponential"
    dtau: float | None = None
    dt: float | None = None
    rtol: float = 1e-6
    atol: float = 1e-10
    output_dtau: float | None = None
    sample_rate: float | None = None
    save_every: int = 1
    probes: tuple = ()
    max_displacement: float | None = None

    def __post_init__(self):
        if (self.revolutions is None) == (self.duration is None):
            raise InputError(
                "simulation.revolutions / simulation.duration",
                (self.revolutions, self.duration),
                "exactly one of the two",
            )
        if self.revolutions is not None:
            object.__setattr__(
                self,
                "revolutions",
                _number("simulation.revolutions", self.revolutions, "rev", minimum=0, strict=True),
            )
        if self.duration is not None:
            object.__setattr__(
                self,
                "duration",
                _number("simulation.duration", self.duration, "s", minimum=0, strict=True),
            )
        if self.method not in METHODS:
            raise InputError(
                "simulation.method", self.method, " or ".join(f'"{m}"' for m in METHODS)
            )
        if self.dtau is not None and self.dt is not None:
            raise InputError(
                "simulation.dtau / simulation.dt", (self.dtau, self.dt), "at most one of the two"
            )
        for name, unit in (("dtau", "rad of spin"), ("dt", "s"), ("output_dtau", "rad of spin")):
            val = getattr(self, name)
            if val is not None:
                object.__setattr__(
                    self, name, _number(f"simulation.{name}", val, unit, minimum=0, strict=True)
                )
        if self.sample_rate is not None:
            object.__setattr__(
                self,
                "sample_rate",
                _number("simulation.sample_rate", self.sample_rate, "Hz", minimum=0, strict=True),
            )
            if self.output_dtau is not None:
                raise InputError(
                    "simulation.sample_rate / simulation.output_dtau",
                    (self.sample_rate, self.output_dtau),
                    "at most one of the two",
                )
        if self.method == "abm" and self.dtau is None and self.dt is None:
            raise InputError(
                "simulation.dtau", None, 'a fixed step (dtau or dt) for method = "abm"'
            )
        object.__setattr__(
            self,
            "rtol",
            _number("simulation.rtol", self.rtol, "dimensionless", minimum=0, strict=True),
        )
        object.__setattr__(
            self, "atol", _number("simulation.atol", self.atol, "m", minimum=0, strict=True)
        )
        se = self.save_every
        if isinstance(se, bool) or not isinstance(se, int) or se < 1:
            raise InputError("simulation.save_every", se, "an integer >= 1")
        probes = self.probes
        if not isinstance(probes, tuple | list):
            raise InputError("simulation.probes", probes, "a list of axial positions (m)")
        object.__setattr__(
            self, "probes", tuple(_number("simulation.probes", p, "m") for p in probes)
        )
        if self.max_displacement is not None:
            object.__setattr__(
                self,
                "max_displacement",
                _number(
                    "simulation.max_displacement",
                    self.max_displacement,
                    "m",
                    minimum=0,
                    strict=True,
                ),
            )

    @property
    def fixed_step(self) -> bool:
        """True when a step (``dtau`` or ``dt``) is given."""
        return self.dtau is not None or self.dt is not None

    @property
    def order(self) -> int:
        """Design order of accuracy of the method."""
        return METHODS[self.method]

    def step_seconds(self, speed: float) -> float | None:
        """Fixed step (s) at spin ``speed`` (rad/s), or None for adaptive runs."""
        if self.dt is not None:
            return self.dt
        if self.dtau is not None:
            return self.dtau / speed
        return None

    def output_spacing(self, speed: float) -> float:
        """Spacing of saved samples (s) of an adaptive run at spin ``speed`` (rad/s)."""
        if self.sample_rate is not None:
            return 1.0 / self.sample_rate
        dtau = (
            self.output_dtau
            if self.output_dtau is not None
            else 2 * math.pi / DEFAULT_SAMPLES_PER_REV
        )
        return dtau / speed

    def total_time(self, speed: float) -> float:
        """Simulated length (s) at spin ``speed`` (rad/s)."""
        if self.duration is not None:
            return self.duration
        return self.revolutions * 2 * math.pi / speed
