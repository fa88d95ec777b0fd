"""
Wavelet transform of a rub signal
=================================

The analytic Morlet CWT of the horizontal acceleration of seed case 1 (30 revolutions): the spin
harmonics and the rotor's bending modes ring after each impact.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import rubrotor
from rubrotor import Integrator

scenarios = Path(rubrotor.__file__).parent / "scenarios"
sc = rubrotor.load_scenario(scenarios / "seed_case1.toml")
ds = rubrotor.simulate(sc, integrator=Integrator(revolutions=30))
acc = ds["v_ddot"].values[0]  # station 0: the contact station
fs = 1.0 / float(ds["time"][1] - ds["time"][0])  # Hz
freqs = np.geomspace(500.0, 30000.0, 96)  # Hz
res = rubrotor.cwt(acc, fs=fs, frequencies=freqs)

fig, ax = plt.subplots(figsize=(9, 4.2), layout="constrained")
t = ds["time"].values * 1e3
mesh = ax.pcolormesh(t[::8], freqs / 1e3, np.abs(res.coefficients)[:, ::8], shading="auto")
ax.set(yscale="log", xlabel="time (ms)", ylabel="frequency (kHz)", title="|W| of v'' (m/s^2)")
cbar = fig.colorbar(mesh, ax=ax, label="|W| (m/s^2)")  # assigned: no repr in the gallery
