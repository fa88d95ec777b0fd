"""The scenario schema as one table of data (:mod:`rubrotor.schema`): every row is consistent,
and the views the validation uses are generated from the rows."""

from __future__ import annotations

import math

import pytest

from rubrotor.schema import KEYS, KINDS, TABLES, allowed_text, check_value, key_row


@pytest.mark.parametrize("row", KEYS, ids=lambda k: k.dotted)
def test_every_row_is_consistent(row):
    """Kinds are known, tables exist, choices go with strings only, numbers carry a unit,
    strings and flags none, bounds are ordered, and a default passes the row's own check."""
    assert row.kind in KINDS
    assert row.table in {t.name for t in TABLES}
    assert row.description
    assert not row.choices or row.kind in ("str", "number|str")
    assert (row.unit == "") == (row.kind in ("str", "bool"))
    if row.minimum is not None and row.maximum is not None:
        assert row.minimum < row.maximum
    if row.default is not None:
        assert check_value(row.dotted, row.default, row) == row.default
    assert not (row.required and row.default is not None)


def test_keys_are_unique_and_groups_name_existing_keys():
    names = [k.dotted for k in KEYS]
    assert len(names) == len(set(names))
    for t in TABLES:
        for group, _ in t.groups:
            for key in group:
                assert key_row(t.name, key)


def test_range_bounds_are_enforced_exactly():
    """At and just beyond each finite bound: closed bounds accept the bound, open ones refuse
    it, and one ulp outside is refused (``math.nextafter``)."""
    for row in KEYS:
        if row.kind not in ("number", "number|list", "list"):
            continue
        for bound, exclusive, outward in (
            (row.minimum, row.exclusive_minimum, -math.inf),
            (row.maximum, row.exclusive_maximum, math.inf),
        ):
            if bound is None:
                continue
            if not (bound == 0 and row.zero):
                if exclusive:
                    with pytest.raises(ValueError):
                        check_value(row.dotted, float(bound), row)
                else:
                    assert check_value(row.dotted, float(bound), row) == bound
            beyond = math.nextafter(float(bound), outward)
            if beyond == 0 and row.zero:
                continue
            with pytest.raises(ValueError, match=row.dotted.replace(".", r"\.")):
                check_value(row.dotted, beyond, row)
    assert allowed_text(key_row("shaft", "length")) == "a number in [1e-09, 1000] (m)"
