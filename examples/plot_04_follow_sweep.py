"""
Hysteresis in a speed sweep
===========================

A one-mode rotor rubbing on a stiff stator has coexisting responses near its critical speed:
full annular rub and no contact. Sweeps that carry the state from point to point expose them: the
up sweep stays on the rub branch until it folds, the down sweep stays off contact until contact
begins.
"""

import matplotlib.pyplot as plt
import numpy as np

from rubrotor.scenario import scenario_from_dict
from rubrotor.sweeps.follow import follow_sweep

sc = scenario_from_dict(
    {
        "shaft": {"length": 0.4, "diameter": 0.1, "youngs_modulus": 71e9, "density": 2660,
                  "poisson_ratio": 0.33, "theory": "euler-bernoulli", "modes": 1},
        "speed": {"critical_multiple": 1.3},
        "unbalance": {"magnitude": 2e-4},
        "contact": {"law": "linear", "clearance": 1e-4, "stiffness": 5e8, "friction": 0.01},
        "damping": {"ratio": 0.05},
    }
)  # fmt: skip
speeds = np.linspace(1.2, 1.8, 25)  # x first forward critical speed
ds = follow_sweep(sc, "speed.critical_multiple", speeds, direction="both",
                  transient_revolutions=150, revolutions=180, samples_per_revolution=32,
                  workers=1)  # fmt: skip

fig, ax = plt.subplots(figsize=(8, 4.2), layout="constrained")
for d, style in (("up", "o-"), ("down", "s--")):
    r = ds["max_displacement"].sel(direction=d)  # m, largest |v + i w| at the contact
    ax.plot(speeds, r * 1e6, style, label=f"sweep {d}")
ax.axhline(sc.contact.clearance * 1e6, color="k", lw=0.8, ls=":", label="clearance")
ax.set(xlabel="speed / first critical speed", ylabel="largest radius (µm)")
legend = ax.legend()  # assigned: no repr in the gallery
