"""
Campbell diagram of the seed rotor
==================================

Whirl frequencies of the seed's continuous Timoshenko rotor (L = 0.4 m, D = 0.1 m, aluminium)
against spin speed: forward whirl rises and backward whirl falls with the gyroscopic moments; the
first forward critical speed is where the forward bending branch of mode 1 meets the 1X line.
"""

from pathlib import Path

import numpy as np

import rubrotor
from rubrotor import plotting

scenarios = Path(rubrotor.__file__).parent / "scenarios"
sc = rubrotor.load_scenario(scenarios / "seed_rotor.toml")
speeds = np.linspace(0.0, 60000.0, 200)  # rad/s
fig = plotting.campbell_figure(sc.shaft, speeds)
first = min(c.speed_rad_s for c in rubrotor.critical_speeds(sc) if c.whirl == "forward")
print(f"first forward critical speed: {first:.1f} rad/s")
