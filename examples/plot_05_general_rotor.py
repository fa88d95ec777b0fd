"""
General rotor: Campbell diagram and unbalance response
======================================================

The shipped finite-element rotor (1.3 m stepped steel shaft, an impeller and a balance disk, two
anisotropic cross-coupled bearings): damped whirl frequencies against spin speed coloured by
logarithmic decrement, the 1X critical speeds, and the steady response at the impeller to its
unbalance (4 um eccentricity, balance grade G2.5 at 6000 rpm) through those criticals.
"""

from pathlib import Path

import numpy as np

import rubrotor
from rubrotor.linear.campbell import campbell_data
from rubrotor.linear.critical import linear_critical_speeds
from rubrotor.linear.response import unbalance_response
from rubrotor.plotting.linear import campbell_stability_figure, unbalance_response_figure

scenarios = Path(rubrotor.__file__).parent / "scenarios"
sc = rubrotor.load_scenario(scenarios / "general_rotor.toml")
system = rubrotor.linear_system(sc)
speeds = np.linspace(0.0, 1500.0, 41)  # rad/s
criticals = linear_critical_speeds(system, max_speed=1500.0, n=4, points=60)
fig = campbell_stability_figure(
    campbell_data(system, speeds, n=4),
    criticals,
    operating_speed=sc.speed,
    title="general rotor",
)
for c in criticals:
    print(c)

# %%
# Unbalance response at the impeller (0.45 m) from 10 to 1500 rad/s, sampled densely within
# 10 % of each critical speed so that the polar plot's resonance circles are smooth curves
u = sc.unbalance
near = [np.linspace(0.9 * c.speed_rad_s, 1.1 * c.speed_rad_s, 200) for c in criticals]
speeds_r = np.unique(np.concatenate([np.linspace(10.0, 1500.0, 300), *near]))
resp = unbalance_response(system, speeds_r, [(u.position, u.magnitude, 0.0)], [0.45])
fig2 = unbalance_response_figure(resp, probe=0)
