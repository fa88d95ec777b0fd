"""Support force terms: what a ``[[bearing]]`` table becomes, chosen by its ``type`` key.

A support term acts between one rotor station and the ground. Its force is linear in the
station's deflection and velocity (``F = -K(Omega) q - C(Omega) q'``, ``q = (v, w)``), so it
enters the rotor's linear system through its coefficients (exactly its Jacobian): every linear
analysis sees it, and every time run integrates it exactly in the exponential step.

Every support term has ``position`` (m), ``name``, ``kind`` (``"bearing"`` or ``"pinned"``),
``fail_time`` (s or None), ``holds`` (True when it holds the rotor in both directions),
``_table`` ``(speeds, K, C)`` (its coefficients tabulated, for scale checks),
``support(node, name)`` (a :class:`rubrotor.rotors.linear.Support`) and ``table_entry()`` (the
scenario table that builds it back).

A *nonlinear* support (``nonlinear = True``: the fluid films ``short_journal``,
``squeeze_film``, ``finite_journal``) also has ``static_force(p, spin)`` (its force on the
journal at rest and ``-dF/dp``), ``linearise(p, spin)`` (``K``, ``C``), ``radial_clearance`` and
``spins`` (whether its journal turns with the rotor); its support carries the term, and the
Model gives it its coefficients at the rotor's static equilibrium at each speed
(``rubrotor.forces.equilibrium``). :data:`SUPPORT_TYPES` maps the ``type`` key to the term;
a new support model is one module in ``rubrotor.forces`` and one line here.
"""

from __future__ import annotations

import dataclasses

from rubrotor.errors import InputError
from rubrotor.forces.finite_journal import FiniteJournal
from rubrotor.forces.fluid_film import ShortJournal, SqueezeFilm
from rubrotor.forces.muszynska import MuszynskaSeal
from rubrotor.rotors.fe import Bearing

__all__ = ["SUPPORT_TYPES", "DEFAULT_SUPPORT", "support_term"]

DEFAULT_SUPPORT = "coefficients"
SUPPORT_TYPES: dict[str, type] = {
    DEFAULT_SUPPORT: Bearing,  # kyy ... czz (optionally tabulated against speed), or pinned
    MuszynskaSeal.type: MuszynskaSeal,
    ShortJournal.type: ShortJournal,  # Ocvirk's short journal bearing (nonlinear)
    SqueezeFilm.type: SqueezeFilm,  # the short squeeze-film damper (nonlinear)
    FiniteJournal.type: FiniteJournal,  # Reynolds' equation with feed grooves (nonlinear)
}
"""``[[bearing]] type`` -> the support term class built from the table's other keys."""


def support_term(row: dict, field: str = "bearing"):
    """The support term of one ``[[bearing]]`` table (``row``: key -> value, lists allowed).

    Raises
    ------
    InputError
        For an unknown ``type``, or a key the chosen type does not take (naming both).
    """
    kwargs = {k: (tuple(v) if isinstance(v, list) else v) for k, v in row.items()}
    name = kwargs.pop("type", DEFAULT_SUPPORT)
    cls = SUPPORT_TYPES.get(name) if isinstance(name, str) else None
    if cls is None:
        raise InputError(f"{field}.type", name, " or ".join(f'"{t}"' for t in SUPPORT_TYPES))
    taken = {f.name for f in dataclasses.fields(cls) if f.init}
    for key, value in kwargs.items():
        if key not in taken:
            raise InputError(
                f"{field}.{key}", value,
                f'no value with type = "{name}" (its keys: {", ".join(sorted(taken))})',
            )  # fmt: skip
    for f in dataclasses.fields(cls):
        if f.init and f.name not in kwargs and f.default is dataclasses.MISSING \
                and f.default_factory is dataclasses.MISSING:  # fmt: skip
            raise InputError(f"{field}.{f.name}", None, f'a value with type = "{name}"')
    label = kwargs.get("name", "")
    try:
        return cls(**kwargs)
    except InputError as exc:  # a film names its keys after its label: name them by the table
        head, dot, rest = str(exc.field).partition(".")
        if dot and head in (label, "film"):
            raise InputError(f"{field}.{rest}", exc.value, exc.allowed) from None
        raise
