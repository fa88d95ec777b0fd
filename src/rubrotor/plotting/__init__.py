"""Figures, one module per figure family, each function returning a Figure.

* :mod:`rubrotor.plotting.linear`: Campbell diagrams (continuous shaft; any rotor with
  stability), unbalance response, mode shapes, undamped critical speed map;
* :mod:`rubrotor.plotting.response`: static deflection, frequency response, API checks;
* :mod:`rubrotor.plotting.runs`: the continuous shaft's time runs (response, theories, envelopes);
* :mod:`rubrotor.plotting.rub`: a general rotor's rub run; :mod:`rubrotor.plotting.touchdown`,
  :mod:`rubrotor.plotting.thermal`, :mod:`rubrotor.plotting.dry_whirl`;
* :mod:`rubrotor.plotting.signals`: scalograms, full spectra, the analysis figure;
* :mod:`rubrotor.plotting.diagnostics`: orders, cascades, centreline, rub verdict;
* :mod:`rubrotor.plotting.orbits`: continuation branches;
* :mod:`rubrotor.plotting.sweeps`: bifurcation diagrams and regime maps.

The names of the former ``rubrotor.plotting.figures`` (now split into ``linear``, ``sweeps``,
``signals``, ``runs`` and ``orbits``) are read here too (``rubrotor.plotting.campbell_figure``).
"""

#: the modules the former ``rubrotor.plotting.figures`` was split into
FIGURES = ("linear", "sweeps", "signals", "runs", "orbits")


def __getattr__(name):
    import importlib

    for family in FIGURES:
        module = importlib.import_module(f"rubrotor.plotting.{family}")
        if not name.startswith("__") and name in vars(module):
            return vars(module)[name]
    raise AttributeError(f"module 'rubrotor.plotting' has no attribute {name!r}")
