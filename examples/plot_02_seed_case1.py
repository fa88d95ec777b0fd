"""
Seed case 1: partial rub
========================

The seed's strongest rub case (k_h' = 1e3, b_h' = 1e2, g' = 3e-3, mu = 0.02, 1.5 times the first
critical speed), 60 revolutions from rest: the orbit at midspan against the clearance circle and
the normal contact force.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import rubrotor
from rubrotor import Integrator

scenarios = Path(rubrotor.__file__).parent / "scenarios"
sc = rubrotor.load_scenario(scenarios / "seed_case1.toml")
ds = rubrotor.simulate(sc, integrator=Integrator(revolutions=60))

g = sc.contact.clearance
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.2), layout="constrained")
ax1.plot(ds["v"][0] * 1e3, ds["w"][0] * 1e3, lw=0.5)  # station 0: the contact station
th = np.linspace(0, 2 * np.pi, 200)
ax1.plot(g * 1e3 * np.cos(th), g * 1e3 * np.sin(th), "k--", lw=1, label="clearance")
ax1.set(xlabel="v (mm)", ylabel="w (mm)", aspect="equal", title="orbit at midspan")
ax1.legend(loc="upper right")
ax2.plot(ds["time"] * 1e3, ds["normal_force"][0] / 1e3, lw=0.6)  # contact 0
ax2.set(xlabel="time (ms)", ylabel="normal force (kN)", title="contact force")
print(f"contact fraction: {float((ds['normal_force'][0] > 0).mean()):.3f}")
