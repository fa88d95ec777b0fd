"""rubrotor: rotor-stator rub on real rotors.

The package is laid out by concern: ``rubrotor.scenario`` (scenario files),
``rubrotor.rotors`` (builders: continuous shaft, finite-element rotor, ROSS import, the one
linear system), ``rubrotor.linear`` (modes, Campbell, critical speeds, responses, stability),
``rubrotor.engine`` (reduction, steppers, runs, results), ``rubrotor.core`` (compiled
kernels only), ``rubrotor.orbits`` (shooting, continuation, Lyapunov),
``rubrotor.sweeps``, ``rubrotor.analysis``, ``rubrotor.plotting``,
``rubrotor.studies`` and ``rubrotor.cli``. Module paths of earlier releases
(``rubrotor.simulation``, ``rubrotor.model``, ...) still import, with one warning each
(``rubrotor._moved``).

The public surface, each name defined once in its own module:

* model: :class:`Shaft`, :class:`Dimensionless`; general rotor: :class:`Rotor`, :class:`Section`,
  :class:`Disk`, :class:`Bearing`, :class:`Material` (finite elements); forces: :class:`Unbalance`, :class:`Contact`,
  :class:`RadialLoad`, :class:`ModalDamping`; integration settings: :class:`Integrator`;
  scenarios: :func:`load_scenario`, :class:`Scenario`;
* linear analyses of any rotor (the continuous shaft, a finite-element rotor, a ROSS import),
  each returning what the command of the same name prints: :func:`modes`,
  :func:`critical_speeds`, :func:`campbell`, ``static``, ``unbalance_response``,
  ``frequency_response``, ``clearance_check`` (API 617), ``level1`` (API 684),
  ``ucs``, ``mode_shapes``, ``bearings`` (fluid films at each speed); speed ranges in rad/s, rpm or Hz (``"0:12000rpm:61"``);
* simulation: :func:`simulate` (returns an ``xarray.Dataset``), :func:`converge`;
* analysis: :func:`cwt`, :func:`scalogram`, :func:`full_spectrum`, :func:`amplitude_spectrum`,
  :func:`rub_indicators`;
* parameter maps: ``rubrotor.sweeps.sweep.sweep`` (its module imports zarr/dask lazily),
  state-carrying up/down sweeps ``rubrotor.sweeps.follow.follow_sweep``; Lyapunov exponents:
  :func:`lyapunov_exponents`; a start state: :class:`RotorState`;
* rub risk under scattered tolerances: :func:`risk` (the probability of rub against speed,
  Sobol' indices; ``rubrotor risk``);
* results files: :func:`save_dataset`, :func:`load_dataset`;
* figures: :func:`~rubrotor.plotting.geometry.draw_rotor` (the rotor's geometry; ``rubrotor.plotting`` has the others).
"""

from rubrotor import _moved  # noqa: E402
from rubrotor._version import __version__

_moved.install()

# The public names load on first use (PEP 562): ``import rubrotor`` imports neither SciPy, xarray
# nor numba, so the command line starts in a fraction of a second and a verb imports what it runs.
_PUBLIC = {
    "rubrotor.analysis.indicators": ("rub_indicators",),
    "rubrotor.analysis.spectra": ("amplitude_spectrum", "full_spectrum"),
    "rubrotor.analysis.wavelet": ("cwt", "scalogram"),
    "rubrotor.engine.result": ("load_dataset", "save_dataset"),
    "rubrotor.engine.settings": ("Integrator",),
    "rubrotor.engine.simulate": ("RotorState", "converge", "simulate"),
    "rubrotor.errors": ("InputError", "RubrotorError", "ScenarioError"),
    "rubrotor.linear.front": (
        "bearings", "campbell", "clearance_check", "frequency_response", "level1", "mode_shapes", "static",
        "ucs", "unbalance_response",
    ),
    "rubrotor.linear.verbs": ("critical_speeds", "damped_modes", "linear_system", "modes"),
    "rubrotor.orbits.lyapunov": ("lyapunov_exponents",),
    "rubrotor.plotting.geometry": ("draw_rotor",),
    "rubrotor.rotors.fe": ("Bearing", "Disk", "Material", "Rotor", "Section"),
    "rubrotor.rotors.forces": ("Contact", "ModalDamping", "RadialLoad", "Unbalance"),
    "rubrotor.rotors.ross": ("from_ross",),
    "rubrotor.rotors.shaft": ("Dimensionless", "Shaft"),
    "rubrotor.scenario.load": ("Scenario", "load_scenario"),
    "rubrotor.sweeps.risk": ("RiskResult", "risk"),
}
_HOME = {name: module for module, names in _PUBLIC.items() for name in names}


def __getattr__(name):
    """Import a public name's module on first use and keep the name here (PEP 562)."""
    module = _HOME.get(name)
    if module is None:
        raise AttributeError(f"module 'rubrotor' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))


__all__ = [
    "__version__",
    "Bearing",
    "Contact",
    "Disk",
    "Material",
    "Rotor",
    "Section",
    "Dimensionless",
    "InputError",
    "Integrator",
    "ModalDamping",
    "RadialLoad",
    "RotorState",
    "RubrotorError",
    "Scenario",
    "ScenarioError",
    "Shaft",
    "Unbalance",
    "bearings",
    "campbell",
    "static",
    "unbalance_response",
    "frequency_response",
    "clearance_check",
    "level1",
    "ucs",
    "mode_shapes",
    "converge",
    "critical_speeds",
    "load_dataset",
    "load_scenario",
    "modes",
    "damped_modes",
    "linear_system",
    "save_dataset",
    "simulate",
    "cwt",
    "scalogram",
    "amplitude_spectrum",
    "full_spectrum",
    "rub_indicators",
    "lyapunov_exponents",
    "from_ross",
    "draw_rotor",
    "risk",
    "RiskResult",
]

