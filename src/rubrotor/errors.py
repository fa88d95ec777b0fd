"""Exceptions raised by rubrotor.

Every error a user can cause names the field, the value and what is allowed, so that the CLI can
print it and exit with status 2 instead of showing a traceback.
"""

import re

__all__ = ["RubrotorError", "ScenarioError", "InputError", "path_argument", "instance_argument"]


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
        where = _which_table(field)
        if value is None:  # a key or argument that is absent: say so, not "None"
            super().__init__(f"{field} is missing{where}: expected {allowed}")
        else:
            super().__init__(f"{field} = {value!r} is not allowed{where}: expected {allowed}")


_ORDINALS = ("first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth",
             "ninth", "tenth")  # fmt: skip


def _which_table(field: object) -> str:
    """`` (contact[2]: the second [[contact]] table, counted from 1)`` for an indexed field.

    Tables of which a file may hold several (``[[contact]]``, ``[[section]]``, ...) are
    numbered from 1 in field names; the message says so, and which table it is.
    """
    m = re.match(r"([A-Za-z_]+)\[(\d+)\]", str(field))
    if m is None:
        return ""
    name, index = m.group(1), int(m.group(2))
    nth = _ORDINALS[index - 1] if 1 <= index <= len(_ORDINALS) else f"{index}th"
    return f" ({name}[{index}]: the {nth} [[{name}]] table, counted from 1)"


class ScenarioError(InputError):
    """A scenario file or mapping has a missing, unknown or invalid key."""


def path_argument(name: str, value, allowed: str = "a file path (str or os.PathLike)"):
    """``value`` as a :class:`pathlib.Path`, or ``InputError`` naming the argument ``name``
    (``None``, a number, ... given where the Python API takes a path)."""
    import os
    from pathlib import Path

    if isinstance(value, bool) or not isinstance(value, str | os.PathLike):
        raise InputError(name, value, allowed)
    return Path(value)


def instance_argument(name: str, value, kind: type, allowed: str):
    """``value`` when it is a ``kind`` (or None), else ``InputError`` naming ``name``."""
    if value is not None and not isinstance(value, kind):
        raise InputError(name, value, allowed)
    return value
