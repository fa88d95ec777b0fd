"""Periodic orbits and their stability: stroboscopic maps, shooting, synchronous orbits,
continuation with bifurcations, Lyapunov exponents.

* :mod:`rubrotor.orbits.shooting`: the continuous shaft's compiled map and :func:`~rubrotor.orbits.shooting.shoot`;
* :mod:`rubrotor.orbits.general_map`: the general rotor's map;
* :mod:`rubrotor.orbits.synchronous`: circular orbits as equilibria of the rotating frame;
* :mod:`rubrotor.orbits.continuation`: pseudo-arclength continuation in any key;
* :mod:`rubrotor.orbits.lyapunov`: Lyapunov exponents;
* :mod:`rubrotor.orbits.points`: the scenario at each point of a continuation or a sweep.
"""
