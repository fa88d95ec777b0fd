"""Contact-law force terms: every question about a contact law is answered here.

A contact station's force is one compiled kernel, ``rubrotor.core.contact._law`` (force and
Jacobian, written once), reading one packed parameter row per contact (``CP_FIELDS``). What
differs between laws outside that kernel (units of the coefficients, the tangent stiffness that
sizes a step, the stored elastic energy, the dimensionless groups of the seed form, whether the
coefficient of restitution applies) is a method or attribute of the law's term object here, so
nothing outside ``rubrotor.forces`` tests a law's name.

Laws (``F_n`` normal force, N; ``eps`` penetration, m; ``eps_dot`` its rate, m/s):

- ``"hertz"`` (Hunt-Crossley): ``F_n = k eps^1.5 (1 + b eps_dot)``, ``k`` in N/m^1.5, ``b`` in s/m;
- ``"linear"`` (penalty spring-dashpot): ``F_n = k eps + c eps_dot``, ``k`` in N/m, ``c`` in N s/m;

both clipped at zero (no adhesion), with Coulomb friction along the tangent (module docstring of
``rubrotor.rotors.forces``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubrotor.core.contact import CP_FIELDS, pack_contact
from rubrotor.errors import InputError

__all__ = ["ContactLaw", "HERTZ", "LINEAR", "LAWS", "law_of", "law_named", "pack_row", "pack_rows",
           "CP_FIELDS"]  # fmt: skip


@dataclass(frozen=True)
class ContactLaw:
    """A normal contact law: its name, the code its parameter row carries, units and methods.

    Attributes
    ----------
    name : str
        The scenario's ``contact.law`` value.
    code : int
        The ``law`` column of the packed row (``CP_FIELDS``) the kernel reads.
    exponent : float
        ``a`` in ``F_n = k eps^a`` (dimensionless).
    stiffness_unit, damping_unit : str
        Units of ``contact.stiffness`` and ``contact.damping``.
    indentation : bool
        True when the law models the local elastic indentation of two solids (Hertz): a
        penetration beyond the clearance lies outside the law's range.
    restitution : bool
        True when the damping is a velocity factor that a coefficient of restitution sets
        (``contact.restitution``, ``contact.damping_nd``).
    linear : bool
        True when the normal force is linear in the penetration and its rate (closed forms of
        a spring-dashpot stator apply).
    """

    name: str
    code: int
    exponent: float
    stiffness_unit: str
    damping_unit: str
    indentation: bool
    restitution: bool
    linear: bool

    def normal_force(self, k: float, c: float, eps: float, eps_dot: float) -> float:
        """Unclipped normal force (N) at penetration ``eps`` (m), rate ``eps_dot`` (m/s)."""
        raise NotImplementedError

    def energy(self, k: float, eps: float) -> float:
        """Elastic energy (J) stored at penetration ``eps`` (m) > 0."""
        raise NotImplementedError

    def tangent_stiffness(self, k: float, eps: float) -> float:
        """``dF_n / d eps`` (N/m) of the elastic part at penetration ``eps`` (m)."""
        raise NotImplementedError

    def stiffness_si(self, nd, k_nd: float) -> float:
        """SI stiffness of the seed form's dimensionless one (``nd``: a ``Dimensionless``)."""
        raise NotImplementedError

    def dimensionless(self, nd, contact) -> dict:
        """The seed form's dimensionless law parameters of ``contact`` (``nd``: ``Dimensionless``)."""
        raise NotImplementedError


class _Hertz(ContactLaw):
    def normal_force(self, k, c, eps, eps_dot):
        return k * eps**1.5 * (1 + c * eps_dot)

    def energy(self, k, eps):
        return 0.4 * k * eps**2.5

    def tangent_stiffness(self, k, eps):
        return 1.5 * k * math.sqrt(eps)

    def stiffness_si(self, nd, k_nd):
        return nd.contact_stiffness_si(k_nd)

    def dimensionless(self, nd, contact):
        return {"k_h": nd.contact_stiffness_nd(contact.stiffness),
                "b_h": nd.contact_damping_nd(contact.damping)}  # fmt: skip


class _Linear(ContactLaw):
    def normal_force(self, k, c, eps, eps_dot):
        return k * eps + c * eps_dot

    def energy(self, k, eps):
        return 0.5 * k * eps**2

    def tangent_stiffness(self, k, eps):
        return k

    def stiffness_si(self, nd, k_nd):
        return nd.linear_stiffness_si(k_nd)

    def dimensionless(self, nd, contact):
        return {"k_linear": nd.linear_stiffness_nd(contact.stiffness)}


HERTZ = _Hertz("hertz", 0, 1.5, "N/m^1.5", "s/m", indentation=True, restitution=True, linear=False)
LINEAR = _Linear(
    "linear", 1, 1.0, "N/m", "N s/m", indentation=False, restitution=False, linear=True
)
LAWS = {law.name: law for law in (HERTZ, LINEAR)}
"""Every contact law by its ``contact.law`` name (codes as ``CP_FIELDS`` ``law``)."""


def law_named(name: str, field: str = "contact.law") -> ContactLaw:
    """The law called ``name``; an ``InputError`` naming ``field`` otherwise."""
    try:
        return LAWS[name]
    except (KeyError, TypeError):
        raise InputError(field, name, " or ".join(f'"{x}"' for x in LAWS)) from None


def law_of(contact) -> ContactLaw:
    """The law of a :class:`rubrotor.rotors.forces.Contact` (or anything with ``.law``)."""
    return law_named(contact.law)


def pack_row(contact, surface_speed: float, active: bool = True) -> np.ndarray:
    """The packed parameter row (``CP_FIELDS``) of ``contact`` sliding at
    ``surface_speed`` (m/s, ``R Omega``), as the compiled kernels read it."""
    return pack_contact(
        int(active),
        law_of(contact).code,
        contact.stiffness,
        contact.damping,
        contact.clearance,
        contact.friction,
        contact.sign_code,
        surface_speed,
        contact.friction_regularization,
    )


def pack_rows(contacts, speed: float) -> np.ndarray:
    """``(n, 10)`` rows of ``contacts`` (each with its ``radius``, m) at spin ``speed`` (rad/s)."""
    rows = [pack_row(c, c.radius * speed) for c in contacts]
    return np.array(rows).reshape(len(rows), len(CP_FIELDS))
