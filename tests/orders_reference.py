"""Shared inputs of the order-tracking tests: a slow contact-free run-up scenario and a
synthetic probe signal of known orders."""

import numpy as np

# A slow run-up of a contact-free two-bearing rotor (the runup_rub rotor on 6 elements with
# ten times its bearing damping: first forward critical 272 rad/s, damping ratio 0.025): held at
# 120 rad/s for 1 s so the start transient decays, then 30 rad/s^2 up to 420 rad/s.
SLOW_RUNUP = """
[meta]
name = "slow_runup"
[materials.steel]
youngs_modulus = 211e9
poisson_ratio = 0.3
density = 7810
[[section]]
length = 1.0
diameter = 0.04
material = "steel"
elements = 6
[[disk]]
position = 0.5
mass = 8.0
polar_inertia = 0.04
diametral_inertia = 0.02
[[bearing]]
position = 0.0
kyy = 2.0e6
kzz = 3.0e6
kyz = 4.0e5
kzy = -3.0e5
cyy = 2000.0
czz = 2500.0
[[bearing]]
position = 1.0
kyy = 2.5e6
kzz = 2.0e6
cyy = 2000.0
czz = 2000.0
[speed]
profile = "table"
times = [0.0, 1.0, 11.0]
speeds = [120.0, 120.0, 420.0]
step = 6.0
[[unbalance]]
position = 0.5
magnitude = 2e-4
phase = 0.7
[simulation]
duration = 11.0
dt = 2e-4
save_every = 2
probes = [0.25, 0.5]
modes = 6
"""


def synthetic(t, theta):
    """Known orders: 1X (25 um, 0.7 rad / 18 um, -1.2 rad) and 2X (6 um, -2.0 / 4 um, 0.4)."""
    y = 25e-6 * np.cos(theta + 0.7) + 6e-6 * np.cos(2 * theta - 2.0) + 3e-6
    z = 18e-6 * np.cos(theta - 1.2) + 4e-6 * np.cos(2 * theta + 0.4) - 5e-6
    return y, z


KNOWN = {1.0: ((25e-6, 0.7), (18e-6, -1.2)), 2.0: ((6e-6, -2.0), (4e-6, 0.4))}
