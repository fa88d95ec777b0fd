"""Modal masses and stiffnesses of a rotor referred to a station.

An unbalance ``U`` (kg m) exciting a mode is an eccentricity ``U / m_s`` of that mode's modal
mass ``m_s``; a contact stiffness compares with the modal stiffness ``k_s``. Both depend on the
normalisation of the mode shape, so they are given for one plain, stated convention:

* the undamped planar modes of the rotor at rest, ``K_s phi = omega^2 M phi``, where ``K_s`` is
  the symmetric part of the stiffness with the bearings' coefficients at the given speed
  (gyroscopic, damping and the skew, circulatory part of cross-coupled bearings are left out);
* ``phi`` mass-normalised, ``phi^T M phi = 1`` (``phi`` in kg^-1/2);
* referred to a station ``x`` (m): with ``u(x)`` the modulus of the mode's deflection there
  (``sqrt(v^2 + w^2)``, m kg^-1/2), the modal mass is ``m_s = 1 / u(x)^2`` (kg) and the modal
  stiffness ``k_s = omega^2 m_s`` (N/m). A single-degree-of-freedom oscillator of mass ``m_s``
  and stiffness ``k_s`` at ``x`` has the mode's frequency and the mode's kinetic and strain
  energy for the same deflection at ``x``.

By default the station is where the mode deflects most (``m_s`` is then the smallest modal
mass of the mode). For a uniform pinned-pinned shaft's first mode at midspan this gives
``m_s = rho A L / 2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from rubrotor.errors import InputError

__all__ = ["ModalMass", "modal_masses", "NORMALISATION"]

NORMALISATION = (
    "undamped planar modes at rest (bearings at the given speed, symmetric stiffness), "
    "phi^T M phi = 1; m = 1/u(x)^2 with u the deflection at station x, k = omega^2 m"
)
"""The convention of :func:`modal_masses`, in one line (printed by ``rubrotor modes``)."""


@dataclass(frozen=True)
class ModalMass:
    """Modal mass and stiffness of one undamped mode referred to a station.

    Attributes
    ----------
    index : int
        Mode number, 1-based, by increasing frequency.
    frequency_hz : float
        Undamped natural frequency (Hz).
    station : float
        Axial position ``x`` (m) the mass and stiffness are referred to.
    modal_mass : float
        ``m_s = 1 / u(x)^2`` (kg), ``phi`` mass-normalised.
    modal_stiffness : float
        ``k_s = omega^2 m_s`` (N/m).
    direction : float
        Angle of the deflection at ``x`` from the ``y`` axis (rad, in ``[0, pi)``).
    """

    index: int
    frequency_hz: float
    station: float
    modal_mass: float
    modal_stiffness: float
    direction: float

    def to_dict(self) -> dict:
        """JSON-ready form (SI units, key names carry them)."""
        return {
            "index": self.index,
            "frequency_hz": self.frequency_hz,
            "station_m": self.station,
            "modal_mass_kg": self.modal_mass,
            "modal_stiffness_N_per_m": self.modal_stiffness,
            "direction_rad": self.direction,
        }


def _grid(system) -> np.ndarray:
    """Stations (m) searched for the largest deflection: the nodes, or 401 points."""
    nodes = getattr(system.basis, "nodes", None)
    if nodes is not None:
        return np.asarray(nodes, float)
    return np.linspace(0.0, system.basis.length, 401)


def modal_masses(obj, speed: float | None = None, station: float | None = None,
                 n: int | None = None) -> list[ModalMass]:  # fmt: skip
    """Modal masses (kg) and stiffnesses (N/m) of the lowest undamped modes at a station.

    Parameters
    ----------
    obj : Scenario, Rotor, Shaft or LinearSystem
        The rotor (see :func:`rubrotor.linear_system`).
    speed : float, optional
        Speed (rad/s, >= 0) at which speed-dependent bearing coefficients are taken; default
        the scenario's, or 0. The modes themselves are those of the rotor at rest.
    station : float, optional
        Axial position (m) the masses are referred to; default, per mode, the position of its
        largest deflection.
    n : int, optional
        Number of modes, lowest first (default all, at most 20).

    Returns
    -------
    list of ModalMass
        By increasing frequency; rigid-body modes (``omega^2 <= 0``) are left out.

    Raises
    ------
    InputError
        A negative or non-finite speed, a station off the rotor, ``n < 1``.
    """
    from rubrotor.linear.verbs import linear_system
    from rubrotor.scenario.load import Scenario

    default = obj.speed if isinstance(obj, Scenario) else 0.0
    speed = default if speed is None else speed
    if isinstance(speed, bool) or not (math.isfinite(speed) and speed >= 0):
        raise InputError("speed", speed, "a finite spin speed >= 0 (rad/s)")
    if n is not None and (isinstance(n, bool) or not isinstance(n, int) or n < 1):
        raise InputError("n", n, "a number of modes >= 1")
    system = linear_system(obj)
    mats = system.matrices(speed)
    w2, phi = scipy.linalg.eigh(0.5 * (mats.K + mats.K.T), mats.M)  # phi^T M phi = I
    keep = np.flatnonzero(w2 > 1e-9 * np.max(np.abs(w2)))[: n or 20]
    stations = _grid(system) if station is None else np.array([float(station)])
    rows = np.stack([system.basis.rows(x)[:, system.free] for x in stations])  # (S, 2, n)
    out = []
    for i, j in enumerate(keep):
        vw = rows @ phi[:, j]  # (S, 2): deflection per station
        s = int(np.argmax(np.hypot(vw[:, 0], vw[:, 1])))
        u2 = float(vw[s, 0] ** 2 + vw[s, 1] ** 2)
        if u2 == 0.0:
            raise InputError("station", float(stations[s]), f"a station where mode {i + 1} moves")
        mass = 1.0 / u2
        angle = math.atan2(vw[s, 1], vw[s, 0]) % math.pi
        out.append(ModalMass(i + 1, math.sqrt(w2[j]) / (2 * math.pi), float(stations[s]), mass,
                             float(w2[j]) * mass, angle))  # fmt: skip
    return out
