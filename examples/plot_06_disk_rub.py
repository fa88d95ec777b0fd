"""
General rotor: rub at the impeller seal under gravity
=====================================================

The shipped finite-element rotor (``general_rotor.toml``: stepped shaft, impeller, balance
disk, anisotropic cross-coupled bearings) at 6000 rpm, with ten times its balance-grade
unbalance on the impeller (a blade lost its coating, say). A seal at the impeller (radius
0.15 m, radial clearance 60 um) sits on a flexible casing (40 kg, 20 MN/m); gravity sags the
shaft 45 um at the seal, so the whirl orbit rubs the bottom of the seal once per revolution:
a partial rub. The general engine (``rubrotor.engine.driver.simulate_general``) keeps the
modes below 3 kHz with the static correction of the dropped ones, solves the contact
implicitly and starts on the steady no-contact orbit.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import rubrotor
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.model import RubStation, Run, Stator
from rubrotor.forces import Contact, Unbalance

scenarios = Path(rubrotor.__file__).parent / "scenarios"
sc = rubrotor.load_scenario(scenarios / "general_rotor.toml")
system = rubrotor.linear_system(sc)
speed = sc.speed  # 628.3 rad/s
seal = Contact(clearance=60e-6, stiffness=5e7, damping=500.0, friction=0.15, position=0.45,
               law="linear", radius=0.15)  # fmt: skip
casing = Stator(mass_y=40.0, mass_z=40.0, stiffness_y=2e7, stiffness_z=2e7,
                damping_y=2e3, damping_z=2e3)  # fmt: skip
run = Run(speed=speed, duration=60 * 2 * np.pi / speed, step=2e-5, initial="steady",
          cutoff=2 * np.pi * 3000.0)  # fmt: skip
res = simulate_general(system, run, [RubStation(seal, stator=casing)],
                       [Unbalance(10 * sc.unbalance.magnitude, 0.45, 0.0)],
                       gravity=(-9.81, 0.0), progress=False)  # fmt: skip
ds = res.to_dataset()
print(res.status, f"{res.stats['modes']} of {res.stats['modes_total']} modes kept,",
      f"{res.stats['contact_events']} contact events")  # fmt: skip

# %%
# Orbit of the shaft relative to the casing (last 20 revolutions) against the seal clearance,
# the normal force, and the full spectrum of the relative motion ``y + i z`` (positive
# frequencies whirl forward, negative backward).
late = ds.time > ds.time[-1] - 20 * 2 * np.pi / speed
rel_y = (ds.v.isel(station=0) - ds.stator_y.isel(contact=0))[late]
rel_z = (ds.w.isel(station=0) - ds.stator_z.isel(contact=0))[late]
fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(13, 4.2), layout="constrained")
th = np.linspace(0, 2 * np.pi, 200)
ax1.plot(rel_z * 1e6, rel_y * 1e6, lw=0.6)
ax1.plot(60 * np.cos(th), 60 * np.sin(th), "k--", lw=1, label="seal clearance")
ax1.set(xlabel="z, horizontal (um)", ylabel="y, vertical (um)", aspect="equal",
        title="shaft orbit in the seal")  # fmt: skip
ax1.legend(loc="upper right", fontsize=8)
t_ms = (ds.time[late] - ds.time[late][0]) * 1e3
ax2.plot(t_ms, ds.normal_force.isel(contact=0)[late] / 1e3, lw=0.7)
ax2.set(xlabel="time (ms)", ylabel="normal force (kN)", title="seal contact force")
z = (rel_y - rel_y.mean()).values + 1j * (rel_z - rel_z.mean()).values
dt = float(ds.time[1] - ds.time[0])
spec = np.fft.fftshift(np.abs(np.fft.fft(z * np.hanning(z.size)))) / (0.5 * z.size)  # Hann: 0.5
freq = np.fft.fftshift(np.fft.fftfreq(z.size, dt))
ax3.semilogy(freq / (speed / (2 * np.pi)), spec * 1e6, lw=0.8)
ax3.set(xlim=(-4, 4), ylim=(1e-3, None), xlabel="frequency / spin frequency (-)",
        ylabel="amplitude (um)", title="full spectrum of y + i z")  # fmt: skip
for k in range(-4, 5):
    ax3.axvline(k, color="0.85", lw=0.6, zorder=0)
