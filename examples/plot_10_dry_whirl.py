"""
Dry whirl: the friction threshold and the whirl frequency
=========================================================

A Jeffcott rotor (10 kg, 1 MN/m, 5 % damping) rubs in a seal of 0.1 mm clearance at 10 mm
radius (linear contact law, 1e8 N/m), against a rigid stator and against a flexible one
(10 kg on 4 MN/m). A friction scan from a kick finds the friction above which the rub turns
into backward rolling whirl; the measured whirl frequency (full spectrum of the relative
displacement) is set against the closed form ``omega = -Omega R / |D|`` of
:mod:`rubrotor.studies.dry_whirl`, the friction it needs, the rolling condition ``-Omega R / g`` and
the coupled rotor-stator natural frequencies.
"""

import numpy as np

from rubrotor.engine.parts import Stator
from rubrotor.plotting.dry_whirl import dry_whirl_figure
from rubrotor.rotors.forces import Contact
from rubrotor.studies.dry_whirl import DryWhirlCase, Jeffcott, scan_friction, scan_speed

rotor = Jeffcott(10.0, 1e6, 316.0)
contact = Contact(clearance=1e-4, stiffness=1e8, law="linear", radius=0.01, position=0.5,
                  friction_regularization=1e-5)  # fmt: skip
rigid = DryWhirlCase(rotor, contact, 6.0)
flexible = DryWhirlCase(rotor, contact, 8.0, Stator.isotropic(10.0, 4e6, 632.0))
mus = np.round(np.arange(0.02, 0.81, 0.02), 2)
scans_mu = [scan_friction(c, mus, duration=0.3) for c in (rigid, flexible)]
speeds = [3, 4, 5, 6, 8, 10, 15, 20, 30, 40, 60, 80]
scans_speed = [scan_speed(c, speeds, 0.8, duration=0.3) for c in (rigid, flexible)]
fig = dry_whirl_figure(scans_mu, scans_speed, ["rigid stator", "flexible stator"])
for lab, s in zip(["rigid", "flexible"], scans_mu, strict=True):
    print(lab, "threshold", s.threshold, "mu_roll", s.predicted(-1).friction_needed)
