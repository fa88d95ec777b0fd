"""rubrotor: rotor-stator rub in a continuous Timoshenko rotor."""

__version__ = "0.1.0"
