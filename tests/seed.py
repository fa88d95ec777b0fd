"""The seed paper's rotor (Table 1, rho = 2660 kg/m^3, seed shear convention), for tests."""

from rubrotor.rotors.shaft import Shaft


def seed_shaft(**changes) -> Shaft:
    """The seed rotor with some fields changed (SI units, see :class:`rubrotor.rotors.shaft.Shaft`)."""
    base = dict(
        length=0.4,
        diameter=0.1,
        youngs_modulus=71e9,
        density=2660.0,
        shear_modulus=26.2e9,
        shear_coefficient="seed",
    )
    base.update(changes)
    return Shaft(**base)
