"""Linear stability of a pressed contact state, for either shaft formulation.

The rotor is held at a static contact position ``P0 = (g + eps0) e_y`` (the force that holds it,
e.g. a radial load, does not enter the perturbation equations) with zero whirl velocity. The
contact force is linearised there with the engine's own Jacobian
(``rubrotor.core.terms.term``): radial stiffness ``1.5 k_h eps0^0.5``,
Hunt-Crossley damping ``k_h eps0^1.5 b_h`` (N s/m), the geometric term of the normal force turning
with the position (``F_n0 / (g + eps0)``) and the friction ``mu`` times all of these along the
tangent; the derivative of the smoothed friction sign is neglected (the surface speed
``R Omega`` dominates the sliding velocity). The perturbation obeys ``y' = lam y + beta dF`` in
the diagonal coordinates of the shaft (``rubrotor.engine.simulate.assemble``), with ``dF`` a real-
linear (not complex-linear) function of ``P`` and ``P'``; the eigenvalues are those of the real
``2 ns x 2 ns`` matrix. A complex pair ``s, conj(s)`` of that matrix is one whirl motion; its
signed frequency is ``+Im s`` when the forward (``exp(+i w t)``) part of ``P`` dominates the
eigenvector and ``-Im s`` otherwise.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.optimize

from rubrotor.errors import InputError
from rubrotor.linear.modes import _modes
from rubrotor.linear.roots import _check_speed
from rubrotor.rotors.linear import LinearSystem
from rubrotor.rotors.shaft import FORMULATIONS

__all__ = [
    "ContactStability",
    "contact_stability",
    "general_contact_stability",
    "GROWTH_RTOL",
    "stability_threshold",
    "is_undamped",
    "ZETA_ROUNDOFF",
]

TWO_PI = 2 * math.pi

#: Growth rates within this fraction of the largest eigenvalue modulus are round-off: the
#: eigenvalues of the real ``2 ns x 2 ns`` matrix carry an absolute error of about
#: ``eps ||A|| cond`` (``eps`` = 2.2e-16); 1e-10 leaves six decades for the eigenvector
#: condition number. For the seed rotor (``|s|`` up to 1.7e5 rad/s) that is 1.7e-5 1/s, a time
#: constant of 16 hours; undamped whirls computed at +3e-11 1/s are neutral, not unstable.
GROWTH_RTOL = 1e-10

#: Damping ratios of modulus at or below this are round-off: ``|Re s| <= 1e-9 |s|``. An
#: undamped rotor's modes come out of the eigensolver with ratios of +-1e-17 to +-1e-26; they
#: are "undamped", neither unstable nor a stability threshold at 0 rad/s.
ZETA_ROUNDOFF = 1e-9


@dataclass(frozen=True)
class ContactStability:
    """Eigenvalues of rotor plus linearised contact.

    Attributes
    ----------
    formulation : str
        ``"two-field"`` or ``"seed-eq1"``.
    indentation : float
        ``eps0`` (m).
    contact_damping : float
        Hunt-Crossley ``b_h`` used (s/m).
    radial_stiffness : float
        ``d F_n / d eps`` at ``eps0`` (N/m).
    radial_damping : float
        ``d F_n / d eps'`` at ``eps0`` (N s/m).
    normal_force : float
        ``F_n0`` (N).
    eigenvalues : ndarray, complex
        One per whirl motion (or real mode): real part the growth rate (1/s), imaginary part the
        signed whirl frequency (rad/s; negative = backward). Sorted by growth rate, largest first.
    """

    formulation: str
    indentation: float
    contact_damping: float
    radial_stiffness: float
    radial_damping: float
    normal_force: float
    eigenvalues: np.ndarray

    @property
    def growth_rates(self) -> np.ndarray:
        """Real parts of :attr:`eigenvalues` (1/s)."""
        return self.eigenvalues.real

    @property
    def frequencies_hz(self) -> np.ndarray:
        """Signed whirl frequencies (Hz)."""
        return self.eigenvalues.imag / TWO_PI

    @property
    def growth_tolerance(self) -> float:
        """Growth rates of modulus below this are round-off (1/s): ``GROWTH_RTOL`` times
        the largest eigenvalue modulus."""
        return GROWTH_RTOL * float(np.max(np.abs(self.eigenvalues), initial=0.0))

    def verdict(self, eigenvalue: complex) -> str:
        """``"unstable"``, ``"neutral"`` (growth rate within ``growth_tolerance``) or
        ``"stable"`` for one eigenvalue (rad/s)."""
        tol = self.growth_tolerance
        return "unstable" if eigenvalue.real > tol else "stable" if eigenvalue.real < -tol else (
            "neutral")  # fmt: skip

    @property
    def unstable(self) -> bool:
        """Whether a growth rate exceeds ``growth_tolerance`` (the contact state grows)."""
        return self.max_growth_rate > self.growth_tolerance

    @property
    def max_growth_rate(self) -> float:
        """Largest growth rate (1/s); above ``growth_tolerance`` the contact state is
        unstable."""
        return float(self.eigenvalues[0].real)

    @property
    def dominant_frequency_hz(self) -> float:
        """Signed frequency (Hz) of the eigenvalue with the largest growth rate."""
        return float(self.eigenvalues[0].imag / TWO_PI)

    def to_dict(self) -> dict:
        """JSON-ready form (``as_dict``: the name every result type shares)."""
        return self.as_dict()

    def as_dict(self) -> dict:
        """JSON-ready form (SI units; eigenvalues as ``[growth 1/s, frequency Hz]`` pairs)."""
        return {
            "formulation": self.formulation,
            "indentation_m": self.indentation,
            "contact_damping_s_per_m": self.contact_damping,
            "radial_stiffness_N_per_m": self.radial_stiffness,
            "radial_damping_N_s_per_m": self.radial_damping,
            "normal_force_N": self.normal_force,
            "max_growth_rate_per_s": self.max_growth_rate,
            "growth_tolerance_per_s": self.growth_tolerance,
            "unstable": self.unstable,
            "dominant_frequency_hz": self.dominant_frequency_hz,
            "eigenvalues": [[float(e.real), float(e.imag / TWO_PI)] for e in self.eigenvalues],
            "verdicts": [self.verdict(e) for e in self.eigenvalues],
        }


def _linear_map(sysm, position: float, jac: np.ndarray) -> np.ndarray:
    """Real ``2 ns x 2 ns`` matrix of ``y' = lam y + beta dF(y)`` on ``[Re y, Im y]``."""
    ns = sysm.lam.size
    cd, cv = sysm.displacement_row(position), sysm.velocity_row(position)
    beta = sysm.force_input(position)
    a = np.empty((2 * ns, 2 * ns))
    for j in range(2 * ns):
        y = np.zeros(ns, complex)
        y[j % ns] = 1.0 if j < ns else 1j
        p, u = cd @ y, cv @ y
        f = jac @ np.array([p.real, p.imag, u.real, u.imag])
        dy = sysm.lam * y + beta * complex(f[0], f[1])
        a[:ns, j], a[ns:, j] = dy.real, dy.imag
    return a


def _whirl_eigenvalues(a: np.ndarray, cd: np.ndarray) -> np.ndarray:
    """One signed complex eigenvalue per conjugate pair of the real matrix ``a`` (see module)."""
    ns = a.shape[0] // 2
    s, vec = np.linalg.eig(a)
    out = []
    for i in np.flatnonzero(s.imag >= 0):
        v = vec[:, i]
        re, im = v[:ns], v[ns:]
        fwd = abs(cd @ (re + 1j * im))
        bwd = abs(cd @ (np.conj(re) + 1j * np.conj(im)))
        if abs(s[i].imag) > 0 and bwd > fwd:
            out.append(complex(s[i].real, -s[i].imag))
        else:
            out.append(complex(s[i]))
    arr = np.array(out)
    return arr[np.argsort(-arr.real, kind="stable")]


def contact_stability(
    scenario,
    indentation: float,
    *,
    formulation: str | None = None,
    contact_damping_nd: float | None = None,
    modes: int | None = None,
    friction: bool = True,
    linearisation: str = "radial",
) -> ContactStability:
    """Eigenvalues of the rotor pressed into the stator by ``indentation``.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        Shaft, speed (rad/s), modal damping and a Hertz ``[contact]`` (stiffness, damping,
        clearance, friction, sign, position), or the first of its ``[[contact]]`` tables. A
        general rotor (``[[section]]`` tables) goes to :func:`rubrotor.linear.stability.general_contact_stability`.
    indentation : float
        Static indentation ``eps0`` (m), > 0.
    formulation : {"two-field", "seed-eq1"}, optional
        Shaft formulation; default the scenario's.
    contact_damping_nd : float, optional
        Replace the contact damping by ``b_h'`` (dimensionless, ``b_h = b_h' / (L Omega)``).
    modes : int, optional
        Number of shaft modes; default the scenario's.
    friction : bool
        Include the friction terms (default) or set ``mu = 0``.
    linearisation : {"radial", "isotropic"}
        ``"radial"`` (default): the Jacobian of the contact law, which resists only the radial
        motion (and turns with the tangential one). ``"isotropic"``: the radial stiffness and
        damping (times ``1 + i mu``-type friction factor) act on both components of ``P``, a
        complex-linear force ``-(k_r dP + c_r dP')``; this is the linearisation of
        model-notes section 6, kept to compare with it (it doubles the contact's effect on a
        circular whirl).

    Returns
    -------
    ContactStability

    Raises
    ------
    InputError
        No Hertz contact, a non-positive indentation, an unknown formulation.
    """
    # the compiled contact law (numba): imported by the pressed-contact analyses only
    from rubrotor.core.contact import pack_contact
    from rubrotor.core.terms import term
    from rubrotor.engine.simulate import assemble
    from rubrotor.forces.contact import law_of
    from rubrotor.modelling import model_of
    from rubrotor.scenario.load import as_scenario

    scenario = as_scenario(scenario)
    model = model_of(scenario)
    if model.linear == "matrix":
        return general_contact_stability(scenario, indentation, friction=friction)
    c = model.first_contact  # [contact], or the first [[contact]] table
    if c is None or not law_of(c).indentation:
        raise InputError("contact", None if c is None else c.law, "a Hertz [contact] section")
    if isinstance(indentation, bool) or not (
        isinstance(indentation, int | float) and math.isfinite(indentation) and indentation > 0
    ):
        raise InputError("indentation", indentation, "a finite indentation > 0 (m)")
    form = formulation or scenario.shaft.formulation
    if form not in FORMULATIONS:
        raise InputError("formulation", form, " or ".join(f'"{f}"' for f in FORMULATIONS))
    shaft = dataclasses.replace(
        scenario.shaft, formulation=form, modes=modes or scenario.shaft.modes
    )
    speed = scenario.speed
    bh = c.damping if contact_damping_nd is None else contact_damping_nd / (shaft.length * speed)
    radius = c.radius if c.radius is not None else shaft.diameter / 2
    cp = pack_contact(
        1,
        c.law_code,
        c.stiffness,
        bh,
        c.clearance,
        c.friction if friction else 0.0,
        c.sign_code,
        radius * speed,
        c.friction_regularization,
    )
    if linearisation not in ("radial", "isotropic"):
        raise InputError("linearisation", linearisation, '"radial" or "isotropic"')
    jac = np.reshape(term(c.clearance + indentation, 0.0, 0.0, 0.0, cp)[4:], (2, 4))
    if linearisation == "isotropic":
        a_, c_ = complex(jac[0, 0], jac[1, 0]), complex(jac[0, 2], jac[1, 2])
        jac = np.array(
            [[a_.real, -a_.imag, c_.real, -c_.imag], [a_.imag, a_.real, c_.imag, c_.real]]
        )
    sysm = assemble(shaft, speed, scenario.damping)
    a = _linear_map(sysm, c.position, jac)
    eig = _whirl_eigenvalues(a, sysm.displacement_row(c.position))
    return ContactStability(
        formulation=form,
        indentation=float(indentation),
        contact_damping=float(bh),
        radial_stiffness=1.5 * c.stiffness * math.sqrt(indentation),
        radial_damping=c.stiffness * indentation**1.5 * bh,
        normal_force=c.stiffness * indentation**1.5,
        eigenvalues=eig,
    )


def _pressed_jacobian(station, speed: float, indentation: float, friction: bool):
    """``d(F_y, F_z) / d(p_y, p_z, u_y, u_z)`` (2 x 4) of a station's contact law at
    ``p = (g + eps) e_y`` relative to its stator centre, at rest relative to it; and ``F_n0``."""
    # the compiled contact law (numba): imported by the pressed-contact analyses only
    from rubrotor.core.contact import pack_contact
    from rubrotor.core.terms import term

    c = station.contact
    cp = pack_contact(1, c.law_code, c.stiffness, c.damping or 0.0, c.clearance,
                      c.friction if friction else 0.0, c.sign_code, c.radius * speed,
                      c.friction_regularization)  # fmt: skip
    r = term(c.clearance + indentation, 0.0, 0.0, 0.0, cp)
    return np.reshape(r[4:], (2, 4)), float(r[2])


def _with_stator(mats, fmap: np.ndarray, stator):
    """``M, D, K`` (rotor, plus the stator's two DOFs when flexible) and ``E`` (``p = E^T x``:
    rotor deflection at the contact minus stator displacement; ``fmap`` the rotor's ``(n, 2)``
    force map at the contact)."""
    m, d, k = mats.M, mats.C + mats.speed * mats.G, mats.K
    if stator is None:
        return m, d, k, fmap
    n = m.shape[0]
    big = [np.zeros((n + 2, n + 2)) for _ in range(3)]
    for b, small, diag in zip(big, (m, d, k), (
            (stator.mass_y, stator.mass_z), (stator.damping_y, stator.damping_z),
            (stator.stiffness_y, stator.stiffness_z)), strict=True):  # fmt: skip
        b[:n, :n] = small
        b[n:, n:] = np.diag(diag)
    return (*big, np.vstack([fmap, -np.eye(2)]))


def general_contact_stability(scenario, indentation: float, *, friction: bool = True,
                              contact: int = 0) -> ContactStability:  # fmt: skip
    """Eigenvalues of a general rotor pressed into one of its ``[[contact]]`` stators.

    The finite-element rotor (bearings at the scenario's speed, gyroscopic, damped) plus the
    contact law linearised at ``p = (g + eps) e_y`` relative to the stator centre (any offset:
    only the relative position enters), at rest relative to it, and the stator's two DOFs when
    it is flexible: ``M x'' + (D - E J_u E^T) x' + (K - E J_p E^T) x = 0`` with ``J`` the law's
    Jacobian (``rubrotor.core.terms.term``) and ``p = E^T x``. The force
    that holds the rotor there (a load, gravity) does not enter the perturbation.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        A general rotor with ``[[contact]]`` tables.
    indentation : float
        Static indentation ``eps0`` (m), > 0.
    friction : bool
        Include friction (default) or set ``mu = 0``.
    contact : int
        Which ``[[contact]]`` table, 0-based (0: the first).

    Returns
    -------
    ContactStability
        ``formulation = "general"``; ``radial_stiffness`` and ``radial_damping`` are
        ``-dF_y/dp_y`` and ``-dF_y/du_y`` (N/m, N s/m); ``contact_damping`` the table's
        ``damping``.

    Raises
    ------
    InputError
        No such contact table, a non-positive indentation.
    """
    from rubrotor.linear.verbs import linear_system
    from rubrotor.modelling import model_of

    stations = model_of(scenario).contact_stations
    if not 0 <= contact < len(stations):
        raise InputError("contact", contact, f"0 .. {len(stations) - 1} ([[contact]] tables, "
                         "0-based)" if stations else "a [[contact]] table")  # fmt: skip
    if isinstance(indentation, bool) or not (
        isinstance(indentation, int | float) and math.isfinite(indentation) and indentation > 0
    ):
        raise InputError("indentation", indentation, "a finite indentation > 0 (m)")
    st = stations[contact]
    system = linear_system(scenario)
    jac, fn = _pressed_jacobian(st, scenario.speed, indentation, friction)
    m, d, k, e = _with_stator(system.matrices(scenario.speed), system.force_map(
        st.contact.position), st.stator)  # fmt: skip
    n = m.shape[0]
    kc, dc = k - e @ jac[:, :2] @ e.T, d - e @ jac[:, 2:] @ e.T
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n], a[n:, n:] = np.linalg.solve(m, -kc), np.linalg.solve(m, -dc)
    lam, vec = np.linalg.eig(a)
    rows = e.T  # (2, n): p from x
    out = []
    for i in np.flatnonzero(lam.imag >= 0):
        vw = rows @ vec[:n, i]
        fwd, bwd = abs(vw[0] + 1j * vw[1]), abs(vw[0] - 1j * vw[1])
        out.append(complex(lam[i].real, -lam[i].imag) if lam[i].imag > 0 and bwd > fwd
                   else complex(lam[i]))  # fmt: skip
    eig = np.array(out)
    return ContactStability(
        formulation="general", indentation=float(indentation),
        contact_damping=float(st.contact.damping or 0.0), radial_stiffness=float(-jac[0, 0]),
        radial_damping=float(-jac[0, 2]), normal_force=fn,
        eigenvalues=eig[np.argsort(-eig.real, kind="stable")],
    )  # fmt: skip


def stability_threshold(
    system: LinearSystem, max_speed: float, n: int | None = None, points: int = 200,
    min_speed: float | None = None,
) -> float | None:
    """The lowest speed (rad/s) where a mode's damping ratio crosses zero, or None up to
    ``max_speed``.

    Parameters
    ----------
    system : LinearSystem
        The rotor (cross-coupled bearings or seals make thresholds).
    max_speed : float
        Upper end of the search (rad/s), > 0.
    n : int, optional
        Modes considered (default all): the ``n`` lowest by frequency, overdamped roots left
        out (they never set the threshold).
    points : int
        Scan points; the crossing is refined by ``brentq`` to 1e-10 relative. With ``n`` given
        the scan is one batched Campbell sweep over the points
        (:func:`~rubrotor.linear.campbell.campbell_data`: projected starts refined by Newton,
        each speed's neighbours' mean as the start between them), not a modal analysis per
        point; ``brentq`` then solves the same modes densely on the bracket.
    min_speed : float, optional
        Lower end of the search (rad/s), >= 0, below ``max_speed``; default 0, or with journal
        bearings (no film at rest) the scan's first step ``max_speed / (points - 1)``.

    Returns
    -------
    float or None
        The threshold speed (rad/s); ``min_speed`` when the rotor is already unstable there. A
        damping ratio counts as negative below ``-ZETA_ROUNDOFF`` (``Re s > 1e-9 |s|``): an
        undamped rotor (ratios at round-off, see :func:`is_undamped`) has no threshold (None).
    """
    max_speed = _check_speed("max_speed", max_speed)
    if min_speed is None:
        from rubrotor.forces.equilibrium import first_speed

        min_speed = first_speed(system, max_speed, points)
    min_speed = _check_speed("min_speed", min_speed)
    if not min_speed < max_speed:
        raise InputError("min_speed", min_speed, f"a speed below max_speed = {max_speed:g} rad/s")
    _check_count(n)

    from rubrotor.linear.campbell import _dense_modes, campbell_data

    def least(w):
        # the n lowest by frequency (the Campbell rows): overdamped roots never set the least
        if n is None:
            return _least_ratio(system, w, n)
        return min(m.damping_ratio for m in _dense_modes(system, w, n))

    def shifted(w):  # "< 0" where the ratio is below the round-off band
        return least(w) + ZETA_ROUNDOFF

    z_prev = least(min_speed)
    if z_prev < -ZETA_ROUNDOFF:
        return min_speed
    grid = np.linspace(min_speed, max_speed, points)
    if n is None:
        below = (least(float(w)) < -ZETA_ROUNDOFF for w in grid[1:])
    else:  # one batched sweep; a log dec d is the damping ratio d / sqrt(4 pi^2 + d^2)
        with np.errstate(invalid="ignore"):
            d = np.nanmin(campbell_data(system, grid, n).log_dec[1:], axis=1)
        below = iter(d / np.sqrt(4 * np.pi**2 + d**2) < -ZETA_ROUNDOFF)
    for k, flag in enumerate(below, start=1):
        if flag and least(float(grid[k])) < -ZETA_ROUNDOFF:
            lo, hi = float(grid[k - 1]), float(grid[k])
            # the zero crossing itself where the bracket holds it, else the band's edge
            f = least if least(lo) >= 0 else shifted
            return float(scipy.optimize.brentq(f, lo, hi, xtol=1e-12, rtol=1e-10))
    return None


def _check_count(n) -> None:
    if n is not None and (isinstance(n, bool) or not isinstance(n, int) or n < 1):
        raise InputError("n", n, "a number of modes >= 1")


def _least_ratio(system: LinearSystem, speed: float, n: int | None) -> float:
    return min(m.damping_ratio for m in _modes(system, speed, n, natural=False).modes)


def is_undamped(system: LinearSystem, speeds, n: int | None = None) -> bool:
    """Whether every mode is undamped at every one of ``speeds``: each damping ratio of
    modulus at most ``ZETA_ROUNDOFF`` (``|Re s| <= 1e-9 |s|``, round-off of an eigensolver).

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    speeds : sequence of float
        Spin speeds (rad/s) to look at.
    n : int, optional
        Modes considered (default all), the lowest by frequency.

    Returns
    -------
    bool
    """
    _check_count(n)
    for w in speeds:
        ratios = [m.damping_ratio for m in _modes(system, float(w), n, natural=False).modes]
        if max(abs(z) for z in ratios) > ZETA_ROUNDOFF:
            return False
    return True
