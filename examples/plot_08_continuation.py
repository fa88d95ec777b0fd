"""
Branches of periodic rub responses
==================================

A brute-force sweep sees only the stable response it falls onto. Continuation follows a periodic
orbit through its folds and instabilities and locates the bifurcations from its Floquet
multipliers.

**Full annular rub.** On the one-mode rotor of the hysteresis example the synchronous orbits
(no contact and full annular rub) are circles: the continuation solves them exactly, as
equilibria of the frame turning with the spin. The branch turns twice: at contact onset, where
the free orbit grazes the stator (a corner, reported as ``contact-onset``), and at the fold on
top of the rub branch; between the two the rub orbit is unstable, and the up and down
state-carrying sweeps jump there.
"""

import numpy as np

from rubrotor.orbits.continuation import continue_orbit, switch_period_doubling
from rubrotor.plotting import branch_figure
from rubrotor.scenario import scenario_from_dict
from rubrotor.sweeps.follow import follow_sweep

KEY = "speed.critical_multiple"
rotor = {"length": 0.4, "diameter": 0.1, "youngs_modulus": 71e9, "density": 2660,
         "poisson_ratio": 0.33, "theory": "euler-bernoulli", "modes": 1}  # fmt: skip
annular = scenario_from_dict(
    {
        "shaft": rotor,
        "speed": {"critical_multiple": 1.3},
        "unbalance": {"magnitude": 2e-4},
        "contact": {"law": "linear", "clearance": 1e-4, "stiffness": 5e8, "friction": 0.01},
        "damping": {"ratio": 0.05},
    }
)
branch = continue_orbit(annular, KEY, 1.8, 1.2)  # the exact synchronous route ("auto")
sweep = follow_sweep(annular, KEY, np.linspace(1.2, 1.8, 13), direction="both",
                     transient_revolutions=150, revolutions=180, samples_per_revolution=32,
                     workers=1)  # fmt: skip
print(f"{branch.method} route, {len(branch.points)} points")
for b in branch.bifurcations:
    print(f"  {b.type} at {b.value:.10f} x critical, radius {b.max_radius_m * 1e6:.1f} um")
fig = branch_figure(branch, sweep)

# %%
# **Partial rub and period doubling.** With a side load the rotor touches the stator once per
# revolution. Shooting follows this period-1 orbit; it loses stability at a period doubling,
# regains it at a second one and loses it again at a Neimark-Sacker bifurcation (a torus). The
# period-2 orbit born at the first period doubling is continued by switching branches: it folds
# and returns to the period-1 branch at the second period doubling.

partial = scenario_from_dict(
    {
        "shaft": rotor,
        "speed": {"critical_multiple": 2.0},
        "unbalance": {"magnitude": 2e-4},
        "contact": {"law": "linear", "clearance": 1e-4, "stiffness": 5e8, "friction": 0.02},
        "load": {"force_y": 2e4},
        "damping": {"ratio": 0.02},
    }
)
one = continue_orbit(partial, KEY, 2.03, 2.11)
two = switch_period_doubling(partial, KEY, one, 2.11, points=200)
for b in (*one.bifurcations, *two.bifurcations):
    print(f"  {b.type} at {b.value:.6f} x critical")
fig = branch_figure(one, others=[two])
