"""Linear rotordynamics on the one linear system, one module per analysis.

* :mod:`rubrotor.linear.verbs`: the verbs on a scenario, shaft, rotor or linear system
  (``modes``, ``damped_modes``, ``critical_speeds``);
* :mod:`rubrotor.linear.modes`: damped modes at one speed (frequencies, damping, whirl, shapes);
* :mod:`rubrotor.linear.campbell`: the Campbell diagram with stability over a speed sweep;
* :mod:`rubrotor.linear.critical`: critical speeds, the first forward one;
* :mod:`rubrotor.linear.stability`: the stability threshold speed, stability of a pressed contact;
* :mod:`rubrotor.linear.response`: unbalance and frequency response;
* :mod:`rubrotor.linear.static`, :mod:`rubrotor.linear.ucs`, :mod:`rubrotor.linear.shapes`,
  :mod:`rubrotor.linear.modal_mass`: static deflection, undamped critical speed map, mode shapes,
  modal masses;
* :mod:`rubrotor.linear.api617`, :mod:`rubrotor.linear.api684`: API 617's close-clearance check,
  API 684's Level I stability;
* :mod:`rubrotor.linear.shaft`: the continuous shaft's whirl frequencies in closed form;
* :mod:`rubrotor.linear.roots` (which roots are modes, whirl) and :mod:`rubrotor.linear.band`
  (band storage, Ritz projection): what the analyses share.

``rubrotor.linear.analysis`` (now ``roots``, ``band``, ``modes``, ``campbell``, ``critical``,
``stability``, ``response``) and ``rubrotor.linear.api`` (now ``api617`` and ``api684``) still
import, with one :class:`FutureWarning` (:mod:`rubrotor._moved`).

``rubrotor.linear`` was the module of :class:`~rubrotor.rotors.linear.LinearSystem`; its names
(``LinearSystem``, ``NodalBasis``, ``Support``, ...) are still read here, with one
:class:`FutureWarning`, and live in :mod:`rubrotor.rotors.linear`.
"""

_WARNED = set()


def __getattr__(name):
    from rubrotor import _moved
    from rubrotor.rotors import linear

    if name.startswith("__") or not hasattr(linear, name):
        raise AttributeError(f"module 'rubrotor.linear' has no attribute {name!r}")
    if name not in _WARNED:
        _WARNED.add(name)
        _moved.moved_warning(f"linear.{name}", f"rotors.linear.{name}")
    return getattr(linear, name)
