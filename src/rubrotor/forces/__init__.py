"""Force terms: every force the engine applies, one module per family.

Each term has its parameters as a named structure, its force (and Jacobian where the implicit
contact step needs it) as one kernel, its states where it has some, and its output variables
(``rubrotor.forces.terms`` lists the families and where each enters the engine).

- :mod:`~rubrotor.forces.contact`: contact laws (Hertz, linear) and their packed rows;
- :mod:`~rubrotor.forces.supports`: the ``[[bearing]] type`` table of support terms;
- :mod:`~rubrotor.forces.muszynska`: Muszynska's fluid-ring force and its whirl threshold;
- :mod:`~rubrotor.forces.unbalance`, :mod:`~rubrotor.forces.loads`: unbalance, loads, gravity;
- ``rubrotor.forces.terms``: ``Terms`` and :func:`build_terms`, what the model builds;
- ``rubrotor.forces.fluid_film``, ``rubrotor.forces.finite_journal``: the fluid-film support
  types ``short_journal``, ``squeeze_film`` and ``finite_journal`` (``rubrotor.forces.reynolds``:
  the finite film in its load-line frame), linearised at the rotor's static equilibrium by
  ``rubrotor.forces.equilibrium`` for the linear analyses (the time runs do not carry them yet);
- ``rubrotor.forces.magnetic``: magnetic bearings with their controller (physics and checks;
  not yet a support type of a scenario).

Importing this package compiles nothing and imports no numba: ``Terms`` and
:func:`build_terms` (with the contact kernels behind them) load on first use, so that a linear
verb reading ``rubrotor.forces.loads`` does not pay numba's import.

``rubrotor.forces`` was the module of the force parameters (``Contact``, ``Unbalance``,
``RadialLoad``, ...); those names are still read here, with one :class:`FutureWarning`, and live
in ``rubrotor.rotors.forces``.
"""

__all__ = ["Terms", "build_terms"]

_WARNED = set()


def __dir__():
    return sorted(set(globals()) | set(__all__))  # the lazy names too (the API reference)


def __getattr__(name):
    if name in __all__:  # the terms, imported on first use (numba behind them)
        from rubrotor.forces import terms

        return getattr(terms, name)
    from rubrotor import _moved
    from rubrotor.rotors import forces

    if name.startswith("__") or not hasattr(forces, name):
        raise AttributeError(f"module 'rubrotor.forces' has no attribute {name!r}")
    if name not in _WARNED:
        _WARNED.add(name)
        _moved.moved_warning(f"forces.{name}", f"rotors.forces.{name}")
    return getattr(forces, name)
