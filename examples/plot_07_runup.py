"""
Run-up through the first critical speed with rub
================================================

The shipped ``runup_rub.toml``: a shaft with a disk on anisotropic bearings accelerates linearly
from 150 to 450 rad/s in one second (``[speed] profile = "linear"``). The engine re-diagonalises
the rotor every 6 rad/s and adds the unbalance with its angular-acceleration term. Near the first
critical speed the disk's orbit reaches the 0.3 mm catcher ring and rubs; the right panel shows
the amplitude at the disk and at the quarter span against the spin speed.
"""

from pathlib import Path

import rubrotor
from rubrotor.plotting_engine import engine_figure

scenarios = Path(rubrotor.__file__).parent / "scenarios"
sc = rubrotor.load_scenario(scenarios / "runup_rub.toml")
ds = rubrotor.simulate(sc, progress=False)
fn = ds["normal_force"].values[0]
t_first = float(ds["time"].values[fn > 0][0])
print(f"first contact at t = {t_first:.3f} s, speed {150 + 300 * t_first:.0f} rad/s")
fig = engine_figure(ds)
