r"""Muszynska's fluid force of a seal or a lightly loaded bearing: a linear support term.

The model
---------
The fluid in an annular seal or bearing rotates at the average circumferential speed
``lambda Omega`` (``lambda`` the swirl ratio, about 0.5 for a plain journal bearing, lower with
anti-swirl devices). In a frame rotating with the fluid at ``lambda Omega``, the journal's complex
deflection ``z_r = z e^{-i lambda Omega t}`` (``z = v + i w``, m) meets a plain spring-damper
(Muszynska 1986; Bently and Muszynska 1988; fluid inertia left out)::

    F_r = -K_f z_r - D_f dz_r/dt                       (rotating frame)

With ``dz_r/dt = (z' - i lambda Omega z) e^{-i lambda Omega t}``, back in fixed coordinates::

    F = -(K_f - i lambda Omega D_f) z - D_f z'          (fixed frame)

that is, with ``F = F_y + i F_z``::

    F_y = -K_f v - D_f v' - lambda Omega D_f w
    F_z = -K_f w - D_f w' + lambda Omega D_f v

a direct stiffness ``K_f`` (N/m), a direct damping ``D_f`` (N s/m) and the cross-coupled stiffness
``lambda Omega D_f`` (N/m) that pushes the journal forward along its whirl: the support
coefficients ``kyy = kzz = K_f``, ``kyz = -kzy = lambda Omega D_f``, ``cyy = czz = D_f``.

Whirl threshold of a Jeffcott rotor
-----------------------------------
A rotor of mass ``M`` (kg) on a shaft of stiffness ``K`` (N/m) with damping ``D`` (N s/m) in
such a fluid ring obeys ``M z'' + (D + D_f) z' + (K + K_f - i lambda Omega D_f) z = 0``. Its
eigenvalues are the roots of ``M s^2 + (D + D_f) s + K + K_f - i lambda Omega D_f = 0``::

    s = (-(D + D_f) +/- sqrt((D + D_f)^2 - 4 M (K + K_f - i lambda Omega D_f))) / (2 M)

At the threshold a root is ``s = i omega``: the real part of the characteristic equation gives
``omega^2 = (K + K_f) / M``, its imaginary part ``(D + D_f) omega = lambda Omega D_f``, so::

    Omega_th = (1 + D / D_f) sqrt((K + K_f) / M) / lambda

(``(1 / lambda) sqrt((K + K_f) / M)`` without rotor damping). Above it the forward mode grows
and whirls at ``omega = sqrt((K + K_f) / M)`` (close to ``lambda Omega_th``: the whirl, then the
whip locked on the natural frequency). :func:`jeffcott_eigenvalue` and :func:`whirl_threshold`
evaluate both closed forms.

Scenario key: ``[[bearing]] type = "muszynska"`` with ``fluid_stiffness``, ``fluid_damping``,
``swirl_ratio`` (a support table has its ``type``: coefficients, this model, and later the
nonlinear fluid films of the same tables).
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from rubrotor.errors import InputError
from rubrotor.rotors.linear import Support

__all__ = ["MuszynskaSeal", "muszynska_force", "jeffcott_eigenvalue", "whirl_threshold"]  # noqa: F822 (module __getattr__)


def _muszynska_force(v, w, vd, wd, omega, params):
    """Force on the rotor (N) and its Jacobian.

    Parameters
    ----------
    v, w : float
        Journal deflection (m).
    vd, wd : float
        Its velocity (m/s).
    omega : float
        Spin speed (rad/s).
    params : ndarray
        ``(K_f, D_f, lambda)`` in N/m, N s/m, 1 (:attr:`MuszynskaSeal.params`).

    Returns
    -------
    fy, fz : float
        Force components (N).
    jac : ndarray, shape (2, 4)
        ``d(fy, fz) / d(v, w, v', w')`` (N/m, N s/m).
    """
    kf, df, lam = params[0], params[1], params[2]
    kx = lam * omega * df
    fy = -kf * v - df * vd - kx * w
    fz = -kf * w - df * wd + kx * v
    jac = np.array([[-kf, -kx, -df, 0.0], [kx, -kf, 0.0, -df]])
    return fy, fz, jac


def __getattr__(name):
    """``muszynska_force``: the kernel above, compiled (``numba.njit(cache=True)``) on first use,
    so that reading a scenario with a fluid ring (the linear verbs) imports no numba."""
    if name != "muszynska_force":
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    from numba import njit

    kernel = njit(cache=True)(_muszynska_force)
    kernel.__doc__ = _muszynska_force.__doc__
    globals()[name] = kernel
    return kernel


def _num(name: str, value, unit: str, lo: float, lo_open: bool, hi: float = math.inf,
         hi_open: bool = False) -> float:  # fmt: skip
    ok = not isinstance(value, bool) and isinstance(value, int | float | np.integer | np.floating)
    v = float(value) if ok else math.nan
    ok = ok and math.isfinite(v) and (v > lo if lo_open else v >= lo)
    ok = ok and (v < hi if hi_open else v <= hi)
    if not ok:
        left = ">" if lo_open else ">="
        right = "" if hi == math.inf else f" and {'<' if hi_open else '<='} {hi:g}"
        raise InputError(name, value, f"a finite number {left} {lo:g}{right} ({unit})")
    return v


@dataclass(frozen=True)
class MuszynskaSeal:
    """Muszynska's linear fluid-ring force at one station (module docstring).

    Parameters
    ----------
    position : float
        Axial station (m).
    fluid_stiffness : float
        ``K_f`` (N/m), >= 0.
    fluid_damping : float
        ``D_f`` (N s/m), > 0.
    swirl_ratio : float
        ``lambda``, the fluid's average circumferential speed over ``Omega`` (1), in [0, 1).
    name : str
        Label.
    """

    type: ClassVar[str] = "muszynska"
    kind: ClassVar[str] = "bearing"
    fail_time: ClassVar[None] = None
    on: ClassVar[None] = None  # between the rotor and the ground
    link: ClassVar[None] = None
    mass_matrix: ClassVar[np.ndarray] = np.zeros((2, 2))  # no fluid inertia (M_f left out)

    position: float
    fluid_stiffness: float = 0.0
    fluid_damping: float = 0.0
    swirl_ratio: float = 0.5
    name: str = ""
    _table: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        _num("bearing.position", self.position, "m", -math.inf, False)
        kf = _num("bearing.fluid_stiffness", self.fluid_stiffness, "N/m", 0.0, False)
        df = _num("bearing.fluid_damping", self.fluid_damping, "N s/m", 0.0, True)
        lam = _num("bearing.swirl_ratio", self.swirl_ratio, "1", 0.0, False, 1.0, True)
        for key, val in (("fluid_stiffness", kf), ("fluid_damping", df), ("swirl_ratio", lam)):
            object.__setattr__(self, key, val)
        # K(Omega) = K0 + Omega K1 is linear in the speed: tabulated at 0 and 1 rad/s and
        # continued linearly, the support's interpolation is exact at every speed.
        speeds = np.array([0.0, 1.0])
        k = np.array([self.stiffness(0.0), self.stiffness(1.0)])
        c = np.array([self.damping(), self.damping()])
        object.__setattr__(self, "_table", (speeds, k, c))

    @property
    def params(self) -> np.ndarray:
        """``(K_f, D_f, lambda)`` (N/m, N s/m, 1): the kernel's parameter row."""
        return np.array([self.fluid_stiffness, self.fluid_damping, self.swirl_ratio])

    @property
    def holds(self) -> bool:
        """True when ``K_f > 0`` (it holds the rotor on its own)."""
        return self.fluid_stiffness > 0

    def stiffness(self, speed: float) -> np.ndarray:
        """``[[K_f, lambda Omega D_f], [-lambda Omega D_f, K_f]]`` (N/m) at ``speed`` (rad/s)."""
        kx = self.swirl_ratio * speed * self.fluid_damping
        return np.array([[self.fluid_stiffness, kx], [-kx, self.fluid_stiffness]])

    def damping(self) -> np.ndarray:
        """``D_f I`` (N s/m)."""
        return self.fluid_damping * np.eye(2)

    def support(self, node: int, name: str, dofs=None, link=None) -> Support:
        """This term as a :class:`rubrotor.rotors.linear.Support` on node ``node`` (or on the
        DOFs ``dofs``); a fluid ring acts between the rotor and the ground (``link`` None)."""
        if link is not None:
            raise InputError("bearing.link", link, 'none with type = "muszynska"')
        speeds, k, c = self._table
        return Support(dofs=tuple(dofs) if dofs is not None else (4 * node, 4 * node + 1), k=k,
                       c=c, speeds=speeds, position=float(self.position), name=name,
                       extrapolation="linear", exact=True, kind="seal")  # fmt: skip

    def table_entry(self) -> dict:
        """The ``[[bearing]]`` table that builds this term again."""
        return {"position": self.position, "type": self.type, "name": self.name,
                "fluid_stiffness": self.fluid_stiffness, "fluid_damping": self.fluid_damping,
                "swirl_ratio": self.swirl_ratio}  # fmt: skip


def jeffcott_eigenvalue(mass, stiffness, damping, seal: MuszynskaSeal, speed) -> complex:
    """Forward-whirl eigenvalue (1/s) of a Jeffcott rotor in the fluid ring (closed form).

    ``mass`` (kg), ``stiffness`` ``K`` (N/m) and ``damping`` ``D`` (N s/m) of the rotor,
    ``speed`` (rad/s). The root of ``M s^2 + (D + D_f) s + K + K_f - i lambda Omega D_f`` with
    the positive whirl frequency (module docstring).
    """
    b = damping + seal.fluid_damping
    c = stiffness + seal.fluid_stiffness - 1j * seal.swirl_ratio * speed * seal.fluid_damping
    root = cmath.sqrt(b * b - 4 * mass * c)
    roots = ((-b + root) / (2 * mass), (-b - root) / (2 * mass))
    return max(roots, key=lambda s: s.imag)


def whirl_threshold(mass, stiffness, damping, seal: MuszynskaSeal) -> float:
    """Onset speed (rad/s) of fluid-induced whirl: ``(1 + D/D_f) sqrt((K + K_f)/M) / lambda``.

    ``inf`` for ``lambda = 0`` (no swirl, no cross-coupling: stable at every speed).
    """
    if seal.swirl_ratio == 0.0:
        return math.inf
    wn = math.sqrt((stiffness + seal.fluid_stiffness) / mass)
    return (1.0 + damping / seal.fluid_damping) * wn / seal.swirl_ratio
