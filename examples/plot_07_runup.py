"""
Run-up through the first critical speed, with and without rub
=============================================================

The shipped general rotor with ten times its balance-grade unbalance on the impeller, run up
from 250 to 600 rad/s in 1.5 s (about 100 revolutions) through its first 1X critical speed,
once freely and once with a seal at the impeller (radial clearance 60 um, flexible casing,
gravity). The speed rises linearly in time; the unbalance force includes its
angular-acceleration term and the engine re-diagonalises the rotor every 7 rad/s. For a short
build the rotor is meshed with two elements per shaft section (60 DOFs) instead of the
default mesh.

The free run-up peaks later and lower than the steady-state resonance (the frequency-domain
unbalance response of :func:`rubrotor.linear.response.unbalance_response`, drawn for
reference): a rotor accelerated through a critical has no time to build the steady amplitude,
and beats between its free and forced whirl after it. With the seal, the rotor pushes the
flexible casing around and the contact stiffens it: the resonance moves up by about 60 rad/s
and its peak halves (the shaft's amplitude exceeds the clearance because the casing moves with
it).
"""

import dataclasses
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import rubrotor
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.parts import RubStation, Run, Stator
from rubrotor.linear.response import unbalance_response
from rubrotor.rotors.forces import Contact, Unbalance

scenarios = Path(rubrotor.__file__).parent / "scenarios"
sc = rubrotor.load_scenario(scenarios / "general_rotor.toml")
coarse = tuple(dataclasses.replace(s, elements=2) for s in sc.rotor.sections)
system = dataclasses.replace(sc.rotor, sections=coarse).linear_system((0.45,))
unbalance = Unbalance(10 * sc.unbalance.magnitude, 0.45, 0.0)
seal = Contact(clearance=60e-6, stiffness=5e7, damping=500.0, friction=0.15, position=0.45,
               law="linear", radius=0.15)  # fmt: skip
casing = Stator(mass_y=40.0, mass_z=40.0, stiffness_y=2e7, stiffness_z=2e7,
                damping_y=2e3, damping_z=2e3)  # fmt: skip
w0, w1, duration = 250.0, 600.0, 1.5
run = Run(speed=w0, speed_end=w1, duration=duration, step=2e-5, save_every=5, initial="static",
          cutoff=2 * np.pi * 3000.0, probes=(0.45,), speed_step=7.0)  # fmt: skip
runs = {}
for label, stations in (("free", []), ("seal rub", [RubStation(seal, stator=casing)])):
    res = simulate_general(system, run, stations, [unbalance], gravity=(-9.81, 0.0),
                           progress=False)  # fmt: skip
    runs[label] = res.to_dataset()
    print(label, res.status, f"{res.stats['contact_events']} contact events")

# %%
# Whirl amplitude at the impeller against the instantaneous speed: the largest distance from
# the static (sagged) position over each revolution. The steady unbalance response is the
# reference for the free rotor.
fig, ax = plt.subplots(figsize=(8, 4.5), layout="constrained")
for label, ds in runs.items():
    v = ds.v.isel(station=-1).values
    w = ds.w.isel(station=-1).values
    speed = w0 + (w1 - w0) * ds.time.values / duration
    r = np.hypot(v - v[0], w - w[0])
    per_rev = np.maximum(1, int(2 * np.pi / w0 / float(ds.time[1] - ds.time[0])))
    n = r.size // per_rev * per_rev
    env = r[:n].reshape(-1, per_rev).max(axis=1)
    ax.plot(speed[:n].reshape(-1, per_rev).mean(axis=1), env * 1e6, lw=1.2, label=label)
steady = unbalance_response(system, np.linspace(w0, w1, 400),
                            [(0.45, unbalance.magnitude, 0.0)], [0.45])  # fmt: skip
ax.plot(
    steady.speeds, steady.major[:, 0] * 1e6, "k--", lw=1, label="steady state (frequency domain)"
)
ax.axhline(60.0, color="0.5", lw=0.8, ls=":", label="seal clearance (casing at rest)")
ax.set(xlabel="spin speed (rad/s)", ylabel="whirl amplitude at the impeller (um)",
       title="run-up 250 -> 600 rad/s in 1.5 s")  # fmt: skip
legend = ax.legend(fontsize=8)  # assigned: the gallery would print its repr
