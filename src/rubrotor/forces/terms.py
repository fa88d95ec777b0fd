"""The force terms of a run, built once, and what the engine asks of them.

:func:`build_terms` is the builder the model calls: it takes the scenario's engine tables (the
``EngineSpec`` of ``rubrotor.scenario.dynamics``: contact stations, unbalance planes, loads,
gravity) and the rotor's support terms, and returns one ``Terms``. The engine's plant asks
``Terms`` for the packed contact rows, the unbalance load and the static load; it never asks
which law or which support type a term is.

Term families and where they enter the engine
---------------------------------------------
===========================  ==============================  ===============================
family (module)              enters as                        states / outputs
===========================  ==============================  ===============================
supports (``supports``,      coefficients in the linear       none / bearing reactions
``muszynska``)               system (exact in every step)     (linear analyses)
fluid films (``fluid_film``, linearisation at the static     none / film force, eccentricity
``film_row``,                equilibrium in the linear        ratio (``bearing`` variables)
``equilibrium``)             system, the rest as rows of the
                             implicit step (``core.terms``)
contacts and stators         packed rows of the implicit      stator modes / stator
(``contact``)                contact step (force + Jacobian   deflection and velocity, force,
                             through ``core.terms.term``)     normal and friction force
unbalance (``unbalance``)    particular solution or input     none
loads, gravity (``loads``)   static deflection                none
thermal bow, drive torque,   ``rubrotor.studies.thermal``,    bow / spin speed and ring
ring drag                    the free-speed kernel            speeds (``core.spin``)
===========================  ==============================  ===============================
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubrotor.forces.contact import pack_rows
from rubrotor.forces.loads import static_load
from rubrotor.forces.unbalance import unbalance_load

__all__ = ["Terms", "build_terms", "CONTACT_OUTPUTS"]

CONTACT_OUTPUTS = (
    ("stator_y", "m"), ("stator_z", "m"), ("stator_y_dot", "m/s"), ("stator_z_dot", "m/s"),
    ("force_y", "N"), ("force_z", "N"), ("normal_force", "N"), ("friction_force", "N"),
)  # fmt: skip
"""Output variables of a contact term, in the order of its channels in the engine's samples."""


@dataclass(frozen=True)
class Terms:
    """Every force term of a run (SI).

    Attributes
    ----------
    stations : tuple of rubrotor.engine.parts.RubStation
        Contact terms: law, clearance, stator.
    unbalances : tuple of rubrotor.rotors.forces.Unbalance
    loads : tuple of rubrotor.rotors.forces.RadialLoad
    gravity : (float, float)
        ``(g_y, g_z)`` (m/s^2).
    supports : tuple
        Support terms (:mod:`rubrotor.forces.supports`), already in the linear system.
    """

    stations: tuple = ()
    unbalances: tuple = ()
    loads: tuple = ()
    gravity: tuple = (0.0, 0.0)
    supports: tuple = ()

    def contact_rows(self, speed: float) -> np.ndarray:
        """``(n_c, 10)`` packed contact rows at spin ``speed`` (rad/s)."""
        return pack_rows([s.contact for s in self.stations], speed)

    def unbalance_load(self, system, speed: float) -> np.ndarray:
        """Complex unbalance load ``b_u`` (N) on the free DOFs at ``speed`` (rad/s)."""
        return unbalance_load(system, self.unbalances, speed)

    def static_load(self, system) -> np.ndarray:
        """Constant load (N) on the free DOFs: point loads and gravity."""
        return static_load(system, tuple(self.loads), self.gravity)


def build_terms(engine=None, rotor=None) -> Terms:
    """The ``Terms`` of a scenario's engine tables and rotor.

    Parameters
    ----------
    engine : rubrotor.scenario.dynamics.EngineSpec, optional
        Its ``stations``, ``unbalances``, ``loads``, ``gravity``.
    rotor : rubrotor.rotors.fe.Rotor, optional
        Its ``bearings`` (support terms).
    """
    supports = tuple(getattr(rotor, "bearings", ()) or ())
    if engine is None:
        return Terms(supports=supports)
    return Terms(tuple(engine.stations), tuple(engine.unbalances), tuple(engine.loads),
                 tuple(engine.gravity), supports)  # fmt: skip
