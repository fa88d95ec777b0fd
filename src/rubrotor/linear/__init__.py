"""Linear rotordynamics on the one linear system.

* :mod:`rubrotor.linear.verbs`: the verbs on a scenario, shaft, rotor or linear system
  (``modes``, ``damped_modes``, ``critical_speeds``);
* :mod:`rubrotor.linear.analysis`: damped modes, Campbell, critical speeds, stability threshold,
  unbalance response;
* :mod:`rubrotor.linear.shaft`: the continuous shaft's whirl frequencies in closed form;
* :mod:`rubrotor.linear.stability`: stability of a pressed contact.

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
