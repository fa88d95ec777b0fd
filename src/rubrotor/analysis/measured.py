"""Measured probe records: CSV tables with a time column and a speed or keyphasor column.

A measured file is a CSV with a header row. Columns are found by name (case-insensitive):

* time (s): ``time``, ``t``, ``time_s``; its spacing gives the sampling frequency, so such a
  file needs no ``--fs``;
* speed: ``speed_rad_s``, ``speed``, ``omega`` (rad/s) or ``rpm``, ``speed_rpm`` (rev/min);
* keyphasor (once per revolution, any unit): ``keyphasor``, ``kp``, ``once_per_rev``, ``tacho``.

The spin angle comes from the keyphasor when there is one (the phase reference of a machine),
else from the speed (angle 0 at the first sample).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rubrotor.analysis.orders import SpinAngle, spin_from_keyphasor, spin_from_speed
from rubrotor.errors import InputError

__all__ = ["read_csv_table", "find_column", "time_column", "spin_from_table", "AUXILIARY_NAMES"]

TIME_NAMES = ("time", "t", "time_s")
SPEED_NAMES = ("speed_rad_s", "speed", "omega")
RPM_NAMES = ("rpm", "speed_rpm")
KEYPHASOR_NAMES = ("keyphasor", "kp", "once_per_rev", "tacho")
AUXILIARY_NAMES = TIME_NAMES + SPEED_NAMES + RPM_NAMES + KEYPHASOR_NAMES
"""Column names that are not probe signals."""


def read_csv_table(path) -> dict[str, np.ndarray]:
    """Columns of a CSV file of numbers, keyed by header name and by 0-based index.

    Parameters
    ----------
    path : path-like
        CSV file, comma separated, with an optional header row.

    Returns
    -------
    dict of str to numpy.ndarray
        Named columns (header names, in file order) followed by their indices ``"0"``, ``"1"``...
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8").splitlines()
    except UnicodeDecodeError as exc:
        raise InputError("input", str(path), f"a CSV text file in UTF-8 (ASCII numbers): byte "
                         f"{exc.start} is {exc.object[exc.start:exc.start + 1]!r}") from None  # fmt: skip
    if not text:
        raise InputError("input", str(path), "a CSV file with at least one row")
    first = [c.strip() for c in text[0].split(",")]
    try:
        [float(c) for c in first]
        names, skip = [str(i) for i in range(len(first))], 0
    except ValueError:
        names, skip = first, 1
    try:
        data = np.loadtxt(p, delimiter=",", skiprows=skip, ndmin=2, encoding="utf-8")
    except ValueError as exc:
        raise InputError("input", str(path), f"a CSV file of numbers ({exc})") from None
    if data.shape[1] != len(names):
        raise InputError("input", str(path), "a CSV file with the same number of columns per row")
    out = {n: data[:, i] for i, n in enumerate(names)}
    for i in range(len(names)):
        out.setdefault(str(i), data[:, i])
    return out


def find_column(table: dict, names) -> str | None:
    """The first column whose name matches one of ``names`` (case-insensitive), or None."""
    lower = {k.lower(): k for k in table}
    for n in names:
        if n in lower:
            return lower[n]
    return None


def time_column(table: dict) -> tuple[str, float] | None:
    """The time column's name and the sampling frequency it gives (Hz), or None.

    Raises
    ------
    InputError
        The time column is not strictly increasing and uniform (to 1e-6 of its mean step).
    """
    name = find_column(table, TIME_NAMES)
    if name is None:
        return None
    t = table[name]
    dt = np.diff(t)
    if t.size < 2 or not np.all(dt > 0) or np.ptp(dt) > 1e-6 * np.mean(dt):
        raise InputError(f"column {name}", "non-uniform or non-increasing times",
                         "uniformly sampled, increasing times (s)")  # fmt: skip
    return name, 1.0 / float(np.mean(dt))


def spin_from_table(table: dict, fs: float | None = None) -> SpinAngle | None:
    """The spin angle of a measured table, from its keyphasor or speed column (None without).

    Parameters
    ----------
    table : dict of str to numpy.ndarray
        Columns (:func:`read_csv_table`).
    fs : float, optional
        Sampling frequency (Hz) when the table has no time column.

    Returns
    -------
    SpinAngle or None
    """
    tc = time_column(table)
    n = len(next(iter(table.values())))
    if tc is not None:
        t = table[tc[0]]
    elif fs is not None and math.isfinite(fs) and fs > 0:
        t = np.arange(n) / fs
    else:
        return None
    kp = find_column(table, KEYPHASOR_NAMES)
    if kp is not None:
        return spin_from_keyphasor(t, table[kp])
    sp = find_column(table, SPEED_NAMES)
    if sp is not None:
        return spin_from_speed(t, table[sp])
    rpm = find_column(table, RPM_NAMES)
    if rpm is not None:
        return spin_from_speed(t, table[rpm] * (2 * math.pi / 60))
    return None
