"""Exceptions raised by rubrotor.

Every error a user can cause names the field, the value and what is allowed, so that the CLI can
print it and exit with status 2 instead of showing a traceback.
"""

__all__ = ["RubrotorError", "ScenarioError", "InputError"]


class RubrotorError(Exception):
    """Base class of every error rubrotor raises on purpose."""


class InputError(RubrotorError, ValueError):
    """A value given to the library is not allowed.

    Parameters
    ----------
    field : str
        Name of the offending argument or scenario key, e.g. ``"shaft.length"``.
    value : object
        The value that was given.
    allowed : str
        What would have been accepted, e.g. ``"a finite number > 0 (m)"``.
    """

    def __init__(self, field: str, value: object, allowed: str):
        self.field = field
        self.value = value
        self.allowed = allowed
        super().__init__(f"{field} = {value!r} is not allowed: expected {allowed}")


class ScenarioError(InputError):
    """A scenario file or mapping has a missing, unknown or invalid key."""
