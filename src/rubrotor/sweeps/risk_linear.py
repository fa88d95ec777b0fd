"""The linear rub screen of a risk analysis: does a sample's 1X orbit reach the clearance?

Equations
---------
At spin ``Omega`` a contact station (axial position ``x_c``) of a linear rotor sits at its
static deflection ``s(Omega)`` (gravity and constant loads, with the bearings read at
``Omega``) and whirls on the steady unbalance orbit ``Re(U e^{i theta})``, ``theta = Omega t``,
with ``U = [V, W]`` (m, complex). The response is linear in the unbalance:

    ``U(Omega) = sum_p m_p e^{i phi_p} R_p(Omega)``

with ``R_p`` the response to a unit unbalance (1 kg m, phase 0) of plane ``p``. The stator
centre is ``o = (offset_y, offset_z)`` (m), so the orbit's distance from it is

    ``r(theta) = |s - o + Re(U) cos(theta) - Im(U) sin(theta)|``

and the sample *rubs* at ``Omega`` when ``max_theta r >= c`` (``c`` the radial clearance) at
any contact; its *margin* is ``min_c (c - max_theta r)`` (m, negative when it rubs).
``r^2`` is a trigonometric polynomial of degree 2 in ``theta`` (at most two maxima): it is
sampled at 32 angles and refined by Newton's method from the two best sampled local maxima
(``rubrotor.core.reach``).

Unbalance magnitudes and phases, clearances and stator offsets therefore need no new solve:
one set of unit responses ``R_p`` and static deflections per rotor serves every sample
(:class:`LinearBasis`, :func:`linear_basis`); a sample that changes the rotor or its bearings
gets its own basis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError
from rubrotor.modelling import model_of

__all__ = [
    "LinearBasis",
    "linear_basis",
    "orbit_reach",
    "CHEAP_KEYS",
    "evaluate",
    "Screen",
    "nominal_clearance",
]

CHEAP_KEYS = {
    "unbalance": ("magnitude", "phase"),
    "contact": ("clearance", "offset_y", "offset_z"),
}
"""Keys a sample can change without a new solve (per table)."""


@dataclass(frozen=True)
class LinearBasis:
    """What the linear screen of one rotor needs, computed once.

    Attributes
    ----------
    speeds : ndarray, shape (S,)
        Spin speeds (rad/s).
    unit : ndarray, shape (P, S, C, 2), complex
        ``[V, W]`` (m) at each contact for a unit unbalance (1 kg m, phase 0) of each plane.
    static : ndarray, shape (S, C, 2)
        Static deflection ``[v, w]`` (m) at each contact and speed.
    magnitude, phase : ndarray, shape (P,)
        The scenario's unbalance of each plane (kg m, rad).
    clearance : ndarray, shape (C,)
        Radial clearance of each contact (m).
    offset : ndarray, shape (C, 2)
        Stator centre ``(offset_y, offset_z)`` of each contact (m).
    positions : ndarray, shape (C,)
        Contact positions (m).
    """

    speeds: np.ndarray
    unit: np.ndarray
    static: np.ndarray
    magnitude: np.ndarray
    phase: np.ndarray
    clearance: np.ndarray
    offset: np.ndarray
    positions: np.ndarray


def _contacts(scenario):
    model = model_of(scenario)
    stations = model.contact_stations
    if stations:
        rows = [(s.contact.position, s.contact.clearance, s.offset_y, s.offset_z)
                for s in stations]  # fmt: skip
    elif scenario.contact is not None and scenario.contact.position is not None:
        c = scenario.contact
        rows = [(c.position, c.clearance, 0.0, 0.0)]
    else:
        raise InputError("contact", None, "a [contact] or [[contact]] table with its position (m)")
    a = np.array(rows, float)
    return a[:, 0], a[:, 1], a[:, 2:4]


def nominal_clearance(scenario) -> float:
    """The smallest radial clearance (m) of the scenario's contacts."""
    return float(_contacts(scenario)[1].min())


def _static(scenario, system, speeds: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """Static deflection (m) at the contacts, shape (S, C, 2); one solve per speed when a
    bearing table depends on the speed, else one."""
    from rubrotor.linear.static import static_analysis

    forces = model_of(scenario).forces()
    g = tuple(float(x) for x in forces.gravity)
    if not any(g) and not forces.loads:
        return np.zeros((speeds.size, positions.size, 2))
    rows = np.stack([system.basis.rows(float(x)) for x in positions])  # (C, 2, n)
    by_speed = any(getattr(s, "tabulated", False) and getattr(s, "axis", "speed") == "speed"
                   for s in system.supports)  # fmt: skip
    out = np.empty((speeds.size, positions.size, 2))
    for i, w in enumerate(speeds if by_speed else speeds[:1]):
        q = system.expand(static_analysis(scenario, float(w), g, forces.loads).q)
        out[i] = rows @ q
    if not by_speed:
        out[:] = out[0]
    return out


def linear_basis(scenario, speeds) -> LinearBasis:
    """Unit unbalance responses and static deflections at the contacts of ``scenario``.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        With at least one contact and one unbalance plane.
    speeds : array_like
        Increasing spin speeds (rad/s), > 0.

    Returns
    -------
    LinearBasis
    """
    from rubrotor.linear.response import unbalance_response

    planes = scenario.unbalances
    if not planes:
        raise InputError("unbalance", None, "an [unbalance] or [[unbalance]] table (kg m at m)")
    positions, clearance, offset = _contacts(scenario)
    system = model_of(scenario).linear_system(tuple(positions))
    s = np.asarray(speeds, float)
    # the frequency-domain sweep takes two speeds or more: one speed is solved beside a neighbour
    solve_at = s if s.size > 1 else np.array([s[0] * (1 - 1e-9), s[0]])
    unit = np.stack([
        unbalance_response(system, solve_at, [(u.position, 1.0, 0.0)], list(positions))
        .complex_response[-s.size :]
        for u in planes
    ])  # fmt: skip
    # static deflection on the same mesh as the linear system
    static = _static(scenario, model_of(scenario).linear_system(), s, positions)
    return LinearBasis(
        speeds=s, unit=unit, static=static,
        magnitude=np.array([u.magnitude for u in planes], float),
        phase=np.array([u.phase for u in planes], float),
        clearance=clearance, offset=offset, positions=positions,
    )  # fmt: skip


def orbit_reach(d: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Largest distance (m) of the orbit ``d + Re(u e^{i theta})`` from the origin.

    Parameters
    ----------
    d : ndarray, shape (..., 2)
        Orbit centre (m) relative to the stator centre.
    u : ndarray, shape (..., 2), complex
        ``[V, W]`` (m).

    Returns
    -------
    ndarray, shape (...)
        ``max_theta |d + Re(u) cos theta - Im(u) sin theta|`` (m), by the compiled kernel
        ``rubrotor.core.reach.reach_kernel``.

    Examples
    --------
    >>> float(orbit_reach(np.array([1.0, 0.0]), np.array([2.0, 2.0j])))
    3.0
    """
    from rubrotor.core.reach import reach_kernel

    d, u = np.broadcast_arrays(np.asarray(d, float), np.asarray(u, complex))
    shape = d.shape[:-1]
    out = np.empty(int(np.prod(shape)))
    reach_kernel(np.ascontiguousarray(d.reshape(-1, 2)),
                 np.ascontiguousarray(u.real.reshape(-1, 2)),
                 np.ascontiguousarray(u.imag.reshape(-1, 2)), out)  # fmt: skip
    return out.reshape(shape)


def evaluate(basis: LinearBasis, magnitude, phase, clearance, offset) -> np.ndarray:
    """Rub margin (m) of a batch of samples against speed.

    Parameters
    ----------
    basis : LinearBasis
        The rotor's unit responses and static deflections.
    magnitude, phase : ndarray, shape (n, P)
        Unbalance of each plane per sample (kg m, rad).
    clearance : ndarray, shape (n, C)
        Radial clearances (m).
    offset : ndarray, shape (n, C, 2)
        Stator centres (m).

    Returns
    -------
    ndarray, shape (n, S)
        ``min_c (c - max_theta r)`` (m); ``<= 0`` where the sample rubs.
    """
    z = magnitude * np.exp(1j * phase)  # (n, P)
    u = (z @ basis.unit.reshape(z.shape[1], -1)).reshape(z.shape[0], *basis.unit.shape[1:])
    d = basis.static[None] - offset[:, None]  # (n, S, C, 2)
    reach = orbit_reach(d, u)  # (n, S, C)
    return (clearance[:, None, :] - reach).min(-1)


class Screen:
    """Margins of batches of samples; one basis per distinct rotor.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The nominal scenario.
    refs : sequence of rubrotor.scenario.keys.KeyRef
        The varied keys; those of :data:`CHEAP_KEYS` need no new solve, any other gives each
        distinct value its own basis (the last 64 kept).
    speeds : ndarray
        Spin speeds (rad/s).
    """

    def __init__(self, scenario, refs, speeds):
        self.base, self.refs, self.speeds = scenario, refs, speeds
        self.cheap = [r.name in CHEAP_KEYS.get(r.section, ()) for r in refs]
        self.bases: dict = {}
        if all(self.cheap):
            self.bases[()] = linear_basis(scenario, speeds)

    def _basis(self, row):
        key = tuple(float(v) for v, c in zip(row, self.cheap, strict=True) if not c)
        if key not in self.bases:
            changes = {r.text: v for r, v, c in zip(self.refs, [float(v) for v in row], self.cheap,
                                                    strict=True) if not c}  # fmt: skip
            if len(self.bases) > 64:  # continuous structural keys: no reuse worth keeping
                self.bases.clear()
            self.bases[key] = linear_basis(self.base.with_changes(**changes), self.speeds)
        return key, self.bases[key]

    def margins(self, values: np.ndarray) -> np.ndarray:
        """Margin (m) per sample and speed, shape (n, S)."""
        out = np.empty((len(values), self.speeds.size))
        groups: dict = {}
        for i, row in enumerate(values):
            groups.setdefault(self._basis(row)[0], []).append(i)
        for key, rows in groups.items():
            b = self.bases[key]
            n = len(rows)
            mag, ph = np.tile(b.magnitude, (n, 1)), np.tile(b.phase, (n, 1))
            cl, off = np.tile(b.clearance, (n, 1)), np.tile(b.offset, (n, 1, 1))
            for j, (r, c) in enumerate(zip(self.refs, self.cheap, strict=True)):
                if not c:
                    continue
                k = r.index or 0
                col = values[rows, j]
                if r.name == "magnitude":
                    mag[:, k] = col
                elif r.name == "phase":
                    ph[:, k] = col
                elif r.name == "clearance":
                    cl[:, k] = col
                else:
                    off[:, k, 0 if r.name == "offset_y" else 1] = col
            out[rows] = evaluate(b, mag, ph, cl, off)
        return out
