"""Rotor builders and the one linear system they make.

* :mod:`rubrotor.rotors.shaft`: the continuous (seed) shaft and its exact modal equations;
  :mod:`rubrotor.rotors.seed_form`: the seed's own single-equation form;
  :mod:`rubrotor.rotors.shaft_system`: the shaft as a :class:`~rubrotor.rotors.linear.LinearSystem`;
* :mod:`rubrotor.rotors.elements`, :mod:`rubrotor.rotors.fe`: finite-element rotors;
* :mod:`rubrotor.rotors.ross`: ROSS rotors imported;
* :mod:`rubrotor.rotors.linear`: the :class:`~rubrotor.rotors.linear.LinearSystem` every builder
  makes; :mod:`rubrotor.rotors.forces`: unbalance, loads, damping and the contact law.
"""
