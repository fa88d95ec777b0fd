"""Old module paths of rubrotor, kept importable after the package was laid out by concern.

``import rubrotor.simulation`` (or any path below) still works: an import hook hands back the
module at its new path, with one :class:`FutureWarning` per old path and process. The module
object is the same (``rubrotor.simulation is rubrotor.engine.simulate``), so attributes set on
either are seen through both. ``rubrotor.linear``, now the package of linear analyses, keeps the
names of the old module (``LinearSystem``, ``NodalBasis``, ``Support``) the same way, in
:mod:`rubrotor.linear`. These aliases will be removed in a later release.
"""

import importlib
import importlib.abc
import importlib.util
import sys
import types
import warnings

#: old module (below ``rubrotor.``) -> its new path (below ``rubrotor.``)
MOVED = {
    "schema": "scenario.schema",
    "schema_export": "scenario.export",
    "scenario_rotor": "scenario.rotor",
    "scenario_engine": "scenario.dynamics",
    "model": "rotors.shaft",
    "elements": "rotors.elements",
    "rotor": "rotors.fe",
    "interop": "rotors.ross",
    "forces": "rotors.forces",
    "seedform": "rotors.seed_form",
    "engine.continuous": "rotors.shaft_system",
    "modal": "linear.shaft",
    "api": "linear.verbs",
    "stability": "linear.stability",
    "modal_system": "engine.shaft_modal",
    "integrator": "engine.settings",
    "simulation": "engine.simulate",
    "simulate_engine": "engine.general",
    "steppers": "engine.shaft_steppers",
    "results": "engine.result",
    "engine.model": "engine.parts",
    "shooting": "orbits.shooting",
    "shooting_general": "orbits.general_map",
    "synchronous": "orbits.synchronous",
    "continuation": "orbits.continuation",
    "lyapunov": "orbits.lyapunov",
    "sweep": "sweeps.sweep",
    "follow": "sweeps.follow",
    "regimes": "sweeps.regimes",
    "plotting_linear": "plotting.linear",
    "plotting_engine": "plotting.rub",
    "plotting_dry_whirl": "plotting.dry_whirl",
    "dry_whirl": "studies.dry_whirl",
    "reproduce": "studies.seed.reproduce",
    "study.cases": "studies.seed.cases",
    "study.claims": "studies.seed.claims",
    "study.detection": "studies.seed.detection",
    "study.extras": "studies.seed.extras",
    "study.report": "studies.seed.report",
    "study.robustness": "studies.seed.robustness",
    "study.seedform_study": "studies.seed.seedform_study",
    "study": "studies.seed",
}

#: old module (below ``rubrotor.``) split by concern -> the modules its names now live in
_ANALYSIS = (
    "linear.roots",
    "linear.band",
    "linear.modes",
    "linear.campbell",
    "linear.critical",
    "linear.stability",
    "linear.response",
)
SPLIT = {
    "linear.analysis": _ANALYSIS,
    "linear_analysis": _ANALYSIS,
    "linear.api": ("linear.api617", "linear.api684"),
}


def moved_warning(old, new):
    """Warn once that ``rubrotor.OLD`` is now ``rubrotor.NEW`` (a :class:`FutureWarning`)."""
    warnings.warn(
        f"rubrotor.{old} moved to rubrotor.{new}; import it from there "
        "(the old path will be removed in a later release)",
        FutureWarning,
        stacklevel=3,
    )


def _split_module(name, old):
    """A module ``rubrotor.OLD`` holding every name of the modules :data:`SPLIT` gives for it."""
    new = ", ".join("rubrotor." + n for n in SPLIT[old])
    warnings.warn(
        f"rubrotor.{old} was split into {new}; import its names from there "
        "(the old path will be removed in a later release)",
        FutureWarning,
        stacklevel=4,
    )
    module = types.ModuleType(name, f"Names of ``rubrotor.{old}``, now in {new}.")
    names = []
    for path in SPLIT[old]:
        part = importlib.import_module("rubrotor." + path)
        vars(module).update({k: v for k, v in vars(part).items() if not k.startswith("__")})
        names += getattr(part, "__all__", ())
    module.__all__ = names
    return module


class _Alias(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds an old module path and loads it as the module at its new path (or, for a split
    module, as a module of the names of its new modules)."""

    def find_spec(self, fullname, path=None, target=None):
        old = fullname.removeprefix("rubrotor.")
        if fullname == old or (old not in MOVED and old not in SPLIT):
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec):
        old = spec.name.removeprefix("rubrotor.")
        if old in SPLIT:
            return _split_module(spec.name, old)
        moved_warning(old, MOVED[old])
        return importlib.import_module("rubrotor." + MOVED[old])

    def exec_module(self, module):
        """Nothing to run: the module at the new path is already imported."""


def install():
    """Put the alias finder first on :data:`sys.meta_path` (once)."""
    if not any(isinstance(f, _Alias) for f in sys.meta_path):
        sys.meta_path.insert(0, _Alias())
