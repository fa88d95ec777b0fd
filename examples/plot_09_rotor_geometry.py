"""
Rotor geometry: what the model holds
====================================

Before any analysis, look at the rotor: :func:`rubrotor.plotting.geometry.draw_rotor` (``rubrotor draw SCENARIO
--out rotor.png`` on the command line) draws the shaft sections (bores white), the disks
(hatched, as the uniform disk of their mass and polar inertia), the bearings (triangles and
springs to the ground, open triangles for pinned ends), the contacts (dark stator blocks, gap
enlarged, clearances listed under the drawing), the unbalance planes and the finite-element
nodes. Here the seal-rub rotor and the touchdown-bearing rotor.
"""

import rubrotor

seal = rubrotor.load_scenario("seal_rub.toml")
fig_seal = rubrotor.draw_rotor(seal)

# %%
# A rotor on magnetic bearings with two touchdown bearings (the contacts C1 and C2)
drop = rubrotor.load_scenario("touchdown_drop.toml")
fig_drop = rubrotor.draw_rotor(drop)
