"""
A general rotor: Campbell diagram with stability and unbalance response
========================================================================

The shipped ``general_rotor.toml``: a 1.3 m stepped steel shaft with an impeller and a coupling
disk on two anisotropic, cross-coupled bearings. Damped natural frequencies against speed, coloured
by logarithmic decrement, with the 1X critical speeds; then the unbalance response at the impeller.
"""

from pathlib import Path

import numpy as np

import rubrotor
from rubrotor.linear_analysis import campbell_data, linear_critical_speeds, unbalance_response
from rubrotor.plotting_linear import campbell_stability_figure, unbalance_response_figure

scenarios = Path(rubrotor.__file__).parent / "scenarios"
sc = rubrotor.load_scenario(scenarios / "general_rotor.toml")
system = rubrotor.linear_system(sc)
speeds = np.linspace(0.0, 1500.0, 60)  # rad/s
data = campbell_data(system, speeds, n=8)
crit = linear_critical_speeds(system, 1500.0, n=8, points=60)
fig = campbell_stability_figure(data, crit, sc.speed, title="general_rotor.toml")

u = sc.unbalance
resp = unbalance_response(
    system, np.linspace(20.0, 1500.0, 400), [(u.position, u.magnitude, u.phase)], [u.position]
)
fig2 = unbalance_response_figure(resp)
for c in crit:
    print(f"critical speed {c.speed_rad_s:8.1f} rad/s ({c.speed_rpm:6.0f} rpm), {c.whirl} whirl")
