"""The Python route of docs/howto/import-ross.md; run in CI in the ROSS 2.3 and 3.x venvs."""

import ross as rs

import rubrotor

rotor = rs.rotor_example()  # any ross.Rotor
system = rubrotor.from_ross(rotor)  # the same M, K, C, G and supports
modes = rubrotor.damped_modes(system, speed=0.0)
for m in modes.modes[:6]:
    print(f"{m.index:2d} {m.frequency_hz:9.3f} Hz  log dec {m.log_dec:.4f}  {m.whirl}")
