"""Figures, one module per figure family, each function returning a Figure.

* :mod:`rubrotor.plotting.figures`: simulation runs, signals, sweeps, branches and the seed study;
* :mod:`rubrotor.plotting.linear`: Campbell diagram, unbalance response, mode shapes;
* :mod:`rubrotor.plotting.rub`: a general rotor's rub run; :mod:`rubrotor.plotting.dry_whirl`.

The names of :mod:`rubrotor.plotting.figures` are read here too (``rubrotor.plotting.campbell_figure``).
"""


def __getattr__(name):
    import importlib

    figures = importlib.import_module("rubrotor.plotting.figures")

    try:
        return getattr(figures, name)
    except AttributeError:
        raise AttributeError(f"module 'rubrotor.plotting' has no attribute {name!r}") from None
