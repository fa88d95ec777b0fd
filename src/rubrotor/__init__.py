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
* modal analysis: :func:`modes`, :func:`critical_speeds`, :func:`campbell`;
* simulation: :func:`simulate` (returns an ``xarray.Dataset``), :func:`converge`;
* analysis: :func:`cwt`, :func:`scalogram`, :func:`full_spectrum`, :func:`amplitude_spectrum`,
  :func:`rub_indicators`;
* parameter maps: ``rubrotor.sweeps.sweep.sweep`` (its module imports zarr/dask lazily),
  state-carrying up/down sweeps ``rubrotor.sweeps.follow.follow_sweep``; Lyapunov exponents:
  :func:`lyapunov_exponents`; a start state: :class:`RotorState`;
* results files: :func:`save_dataset`, :func:`load_dataset`;
* figures: :func:`~rubrotor.plotting.geometry.draw_rotor` (the rotor's geometry; ``rubrotor.plotting`` has the others).
"""

from rubrotor import _moved  # noqa: E402
from rubrotor._version import __version__

_moved.install()

from rubrotor.analysis.indicators import rub_indicators  # noqa: E402
from rubrotor.analysis.spectra import amplitude_spectrum, full_spectrum  # noqa: E402
from rubrotor.analysis.wavelet import cwt, scalogram  # noqa: E402
from rubrotor.engine.result import load_dataset, save_dataset  # noqa: E402
from rubrotor.engine.settings import Integrator  # noqa: E402
from rubrotor.engine.simulate import RotorState, converge, simulate  # noqa: E402
from rubrotor.errors import InputError, RubrotorError, ScenarioError  # noqa: E402
from rubrotor.linear.shaft import campbell  # noqa: E402
from rubrotor.linear.verbs import critical_speeds, damped_modes, linear_system, modes  # noqa: E402
from rubrotor.orbits.lyapunov import lyapunov_exponents  # noqa: E402
from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section  # noqa: E402
from rubrotor.rotors.forces import Contact, ModalDamping, RadialLoad, Unbalance  # noqa: E402
from rubrotor.rotors.ross import from_ross  # noqa: E402
from rubrotor.rotors.shaft import Dimensionless, Shaft  # noqa: E402
from rubrotor.scenario.load import Scenario, load_scenario  # noqa: E402

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
    "campbell",
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
]


def __getattr__(name):
    # matplotlib is imported only when a figure is asked for: ``rubrotor.draw_rotor``
    if name == "draw_rotor":
        from rubrotor.plotting.geometry import draw_rotor

        return draw_rotor
    raise AttributeError(f"module 'rubrotor' has no attribute {name!r}")
