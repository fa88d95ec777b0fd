"""Write a scenario mapping as a TOML file (the inverse of :func:`rubrotor.load_scenario`).

Numbers are written with ``repr`` (the shortest text that reads back to the same double), so
a scenario written and loaded again holds bit-identical values. Files are written atomically
(a temporary file in the same folder, then renamed).
"""

from __future__ import annotations

import json
import math
import os
import re
import tempfile
from collections.abc import Mapping
from pathlib import Path

from rubrotor.errors import InputError

__all__ = ["scenario_toml", "write_scenario"]

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k) -> str:
    k = str(k)
    return k if _BARE.match(k) else json.dumps(k)


def _value(v, where: str) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise InputError(where, v, "a finite number (TOML files hold no inf or nan here)")
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_value(x, where) for x in v) + "]"
    if hasattr(v, "item"):  # numpy scalar
        return _value(v.item(), where)
    raise InputError(where, v, "a number, string, boolean or list")


def _body(table: Mapping, where: str) -> list[str]:
    return [f"{_key(k)} = {_value(v, f'{where}.{k}')}" for k, v in table.items() if v is not None]


def scenario_toml(mapping: Mapping, header: str = "") -> str:
    """TOML text of a scenario mapping (tables, arrays of tables, named tables).

    Parameters
    ----------
    mapping : Mapping
        ``{"speed": {...}, "section": [{...}, ...], "materials": {"steel": {...}}, ...}``.
    header : str
        Comment lines put first (without the ``#``).

    Returns
    -------
    str
    """
    lines = [f"# {h}".rstrip() for h in header.splitlines()]
    for name, value in mapping.items():
        if isinstance(value, list) and all(isinstance(v, Mapping) for v in value):
            for item in value:
                lines += ["", f"[[{_key(name)}]]", *_body(item, name)]
        elif (
            isinstance(value, Mapping)
            and value
            and all(isinstance(v, Mapping) for v in value.values())
        ):
            for label, item in value.items():
                lines += ["", f"[{_key(name)}.{_key(label)}]", *_body(item, f"{name}.{label}")]
        elif isinstance(value, Mapping):
            lines += ["", f"[{_key(name)}]", *_body(value, name)]
        else:
            raise InputError(name, value, "a table or an array of tables")
    return "\n".join(lines).lstrip("\n") + "\n"


def write_scenario(mapping: Mapping, path, header: str = "") -> Path:
    """Write ``mapping`` as TOML to ``path`` atomically; return the path."""
    out = Path(path)
    text = scenario_toml(mapping, header)
    out.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, out)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return out
