"""Speed and frequency ranges in the units engineers write them: rad/s, rpm or Hz.

``"0:12000rpm:61"`` is 61 speeds from 0 to 12000 rpm, returned in rad/s (SI, as everywhere
inside rubrotor). A unit written after STOP applies to START too unless START has its own;
without a unit the values are rad/s. The command line's ``--speeds`` and ``--frequencies`` and
the Python functions taking ``speeds`` read ranges with :func:`parse_range`.
"""

from __future__ import annotations

import math
import re

import numpy as np

from rubrotor.errors import InputError

__all__ = ["TO_RAD_PER_S", "parse_range", "parse_speed", "as_speeds"]

TO_RAD_PER_S = {"rad/s": 1.0, "rpm": 2 * math.pi / 60, "hz": 2 * math.pi}
"""Factor from each accepted unit (lower case) to rad/s."""

_VALUE = re.compile(r"^\s*([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?|[-+]?inf|nan)\s*(rad/s|rpm|hz)?\s*$",
                    re.IGNORECASE)  # fmt: skip


def _value(text: str, field: str, allowed: str) -> tuple[float, str | None]:
    m = _VALUE.match(text)
    if m is None:
        raise InputError(field, text, allowed)
    return float(m.group(1)), (m.group(2).lower() if m.group(2) else None)


def parse_speed(text: str, field: str = "--speed") -> float:
    """One spin speed, ``"500"`` (rad/s) or with a unit after the number (``"12000rpm"``,
    ``"200hz"``, ``"500rad/s"``), in rad/s: finite and >= 0, else an InputError naming ``field``.

    Examples
    --------
    >>> round(parse_speed("12000rpm"), 6)
    1256.637061
    """
    allowed = "a finite spin speed >= 0: rad/s, or a unit after the number (12000rpm, 200hz)"
    value, unit = _value(str(text), field, allowed)
    speed = value * TO_RAD_PER_S[unit or "rad/s"]
    if not (math.isfinite(speed) and speed >= 0):
        raise InputError(field, text, allowed)
    return speed


def parse_range(text: str, field: str = "--speeds", minimum: float = 0.0) -> np.ndarray:
    """Parse ``START:STOP:COUNT`` (rad/s, or rpm / Hz written after a number) into ``COUNT``
    evenly spaced values in rad/s.

    Parameters
    ----------
    text : str
        E.g. ``"0:60000:200"`` (rad/s), ``"0:12000rpm:61"`` (rpm), ``"5hz:200hz:40"`` (Hz):
        ``minimum <= START < STOP``, integer ``COUNT`` in 2..1000000.
    field : str
        The option or argument named in an error.
    minimum : float
        Smallest allowed START (rad/s).

    Returns
    -------
    ndarray, shape (COUNT,)
        Values in rad/s.

    Raises
    ------
    InputError
        Naming ``field``, the text and the accepted form.

    Examples
    --------
    >>> parse_range("0:100:3")
    array([  0.,  50., 100.])
    >>> parse_range("0:60rpm:3").round(6)
    array([0.      , 3.141593, 6.283185])
    """
    allowed = (f"START:STOP:COUNT with {minimum:g} <= START < STOP (rad/s, or a unit after the "
               "number: 0:12000rpm:61, 5hz:200hz:40) and an integer COUNT >= 2")  # fmt: skip
    parts = str(text).split(":")
    if len(parts) != 3:
        raise InputError(field, text, allowed)
    (start, u0), (stop, u1) = (_value(p, field, allowed) for p in parts[:2])
    unit0 = u0 or u1 or "rad/s"
    unit1 = u1 or "rad/s"
    try:
        count = int(parts[2])
    except ValueError:
        raise InputError(field, text, allowed) from None
    start, stop = start * TO_RAD_PER_S[unit0], stop * TO_RAD_PER_S[unit1]
    if not (math.isfinite(start) and math.isfinite(stop)) or not minimum <= start < stop:
        raise InputError(field, text, allowed)
    if not 2 <= count <= 1_000_000:
        raise InputError(field, text, allowed.replace(">= 2", "in 2..1000000"))
    return np.linspace(start, stop, count)


def as_speeds(value, field: str = "speeds") -> np.ndarray:
    """Speeds (rad/s) from an array-like (rad/s) or a range string (:func:`parse_range`)."""
    if isinstance(value, str):
        return parse_range(value, field)
    return np.atleast_1d(np.asarray(value, float))
