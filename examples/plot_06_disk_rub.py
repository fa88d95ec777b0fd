"""
General rotor: rub at a seal against a flexible, offset casing
==============================================================

The shipped ``seal_rub.toml``: the stepped shaft of the general rotor (impeller and balance disk
on two anisotropic, cross-coupled bearings) under gravity, with two unbalance planes, rubs at a
seal whose casing sits 25 um low on a flexible support. The general engine keeps 16 rotor modes
plus the static correction of the others at the seal. After a transient of impacts the rotor
settles into a full annular forward rub: the orbit relative to the casing hugs the clearance
circle, the normal force varies twice per revolution, and the full spectrum is dominated by +1X.
"""

from pathlib import Path

import rubrotor
from rubrotor.plotting.rub import engine_figure

scenarios = Path(rubrotor.__file__).parent / "scenarios"
sc = rubrotor.load_scenario(scenarios / "seal_rub.toml")
ds = rubrotor.simulate(sc, progress=False)
print(
    ds.attrs["status"], "- contacts:", ds.sizes["contact"], "- stations (m):", ds["station"].values
)
print(f"largest normal force {float(ds['normal_force'].max()):.0f} N")
fig = engine_figure(ds)
