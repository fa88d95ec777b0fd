"""Dotted scenario keys: the one resolution of ``"section.key"`` and ``"section[i].key"``.

A key names one value of a scenario's dict form (``rubrotor.scenario.load.scenario_to_dict``):

* ``"section.key"``: a key of a single ``[section]`` table (``"speed.rpm"``), or of the only
  table of a ``[[section]]`` list (``"contact.clearance"`` on a scenario with one
  ``[[contact]]``);
* ``"section[i].key"``: a key of the ``i``-th table of a ``[[section]]`` list, counted from 1
  as in every error message (``"unbalance[2].magnitude"``, ``"bearing[1].kyy"``).

``rubrotor.scenario.Scenario.with_changes``, the sweeps and the risk analysis resolve keys
here; an unknown key is refused by name with the nearest valid keys.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass

from rubrotor.errors import ScenarioError
from rubrotor.scenario.schema import ROTOR_SCHEMA, SCHEMA

__all__ = ["KeyRef", "resolve_key", "valid_keys", "base_key", "index_key"]

_INDEXED = re.compile(r"^([A-Za-z_]+)\[(\d+)\]\.([A-Za-z_]+)$")


@dataclass(frozen=True)
class KeyRef:
    """Where a dotted key points in a scenario's dict form.

    Attributes
    ----------
    text : str
        The key as given.
    section : str
        Table name.
    index : int or None
        Position in a ``[[section]]`` list, from 0 (the key's ``[i]`` less one); None for a
        single ``[section]`` table.
    name : str
        Key inside the table ('' for a whole section).
    kind : str or None
        The schema kind of the key (``"number"``, ``"int"``, ...).
    """

    text: str
    section: str
    index: int | None
    name: str
    kind: str | None

    @property
    def numeric(self) -> bool:
        """Whether the key takes a number."""
        return self.kind in ("number", "int", "number|list", "number|str")


def base_key(key: str) -> str:
    """``"section.key"`` of a possibly indexed key (``"unbalance[1].magnitude"`` ->
    ``"unbalance.magnitude"``), for the per-key tables (units, ranges)."""
    m = _INDEXED.match(key)
    return f"{m.group(1)}.{m.group(3)}" if m else key


def index_key(section: str, index: int, name: str) -> str:
    """The indexed key of the table at list position ``index`` (from 0): ``section[index+1].name``."""
    return f"{section}[{index + 1}].{name}"


def _schema(spec: dict) -> dict:
    return {**SCHEMA, **ROTOR_SCHEMA} if "rotor" in spec or "section" in spec else SCHEMA


def valid_keys(spec: dict, numeric: bool = False) -> list[str]:
    """Every dotted key a scenario's dict form can take (indexed for ``[[...]]`` lists)."""
    schema = _schema(spec)
    out = []
    for section, keys in schema.items():
        table = spec.get(section)
        names = [k for k, kind in keys.items()
                 if not numeric or kind in ("number", "int", "number|list", "number|str")]  # fmt: skip
        if isinstance(table, list):
            heads = [f"{section}[{i + 1}]" for i in range(len(table))]
            if len(table) == 1:
                heads.append(section)
        else:
            heads = [section]
        out += [f"{h}.{n}" for h in heads for n in names]
    return out


def _unknown(spec: dict, key: str, value, what: str) -> ScenarioError:
    near = difflib.get_close_matches(key, valid_keys(spec), n=3, cutoff=0.5)
    hint = f" (nearest: {', '.join(near)})" if near else ""
    return ScenarioError(key, value, what + hint)


def resolve_key(spec: dict, key: str, value=None) -> KeyRef:
    """Resolve a dotted key against a scenario's dict form.

    Parameters
    ----------
    spec : dict
        The scenario's dict form.
    key : str
        ``"section.key"``, ``"section[i].key"`` or ``"section"`` (a whole section).
    value : object
        The value meant for it (only quoted in errors).

    Returns
    -------
    KeyRef

    Raises
    ------
    ScenarioError
        An unknown section or key (naming the nearest valid keys), an index out of range, or an
        unindexed key of a list holding several tables.

    Examples
    --------
    >>> resolve_key({"contact": [{"clearance": 1e-4}]}, "contact.clearance").index
    0
    >>> resolve_key({"unbalance": [{}, {}]}, "unbalance[2].magnitude").index
    1
    """
    schema = _schema(spec)
    m = _INDEXED.match(str(key))
    if m:
        section, index, name = m.group(1), int(m.group(2)) - 1, m.group(3)
    else:
        section, _, name = str(key).partition(".")
        index = None
    if section not in schema:
        return _raise(_unknown(spec, key, value, "a key 'section.key' of " + ", ".join(schema)))
    if name and name not in schema[section]:
        allowed = f"one of the keys {', '.join(schema[section])} of [{section}]"
        return _raise(_unknown(spec, key, value, allowed))
    table = spec.get(section)
    if isinstance(table, list):
        if index is None and len(table) != 1:
            allowed = f"an indexed key {section}[i].{name} with i in 1..{len(table)}"
            return _raise(ScenarioError(key, value, allowed))
        index = 0 if index is None else index
        if not 0 <= index < len(table):
            allowed = f"an index i in 1..{len(table)} of the {len(table)} [[{section}]] tables"
            return _raise(ScenarioError(key, value, allowed))
    elif index is not None:
        return _raise(ScenarioError(key, value, f"{section}.{name} (one [{section}] table)"))
    return KeyRef(str(key), section, index, name, schema[section].get(name) if name else None)


def _raise(exc: Exception):
    raise exc
