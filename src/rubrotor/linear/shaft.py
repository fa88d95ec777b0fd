"""Natural frequencies, Campbell diagrams and critical speeds of the undamped rotor.

Two independent routes give the whirl frequencies of each mode ``n`` at spin ``Omega``:

* **characteristic equation** (:func:`whirl_frequencies`, the default): with ``P, Psi ~ exp(i w t)``
  the determinant of ``K - w^2 M + i w Omega G`` is a quartic in the signed whirl frequency ``w``
  (Timoshenko; a quadratic for Rayleigh and Euler-Bernoulli)::

      rho A rho I w^4 - rho A Omega rho Ip w^3 - (rho A (EI k^2 + kGA) + rho I kGA k^2) w^2
          + kGA k^2 Omega rho Ip w + kGA EI k^4 = 0

  solved as a polynomial (companion roots) and polished by Newton's method;
* **assembled modal matrices** (:func:`whirl_frequencies_eig`): eigenvalues ``lambda = i w`` of the
  generalized state-space problem built from ``M``, ``G``, ``K`` of ``rubrotor.rotors.shaft``.

``w > 0`` is forward whirl, ``w < 0`` backward. For Timoshenko, of the two roots of one sign the
smaller in magnitude is the bending branch, the larger the shear (second) branch.

Critical speeds solve ``w(Omega) = +Omega`` (forward) or ``-Omega`` (backward). Substituting
``w = s Omega`` turns the quartic into a quadratic in ``X = Omega^2``, solved in closed form
(:func:`critical_speeds`); :func:`critical_speeds_numeric` finds them on the eigenvalue route by
root bracketing, as a second route.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from rubrotor.errors import InputError
from rubrotor.rotors.shaft import Shaft, modal_matrices

__all__ = [
    "Mode",
    "CriticalSpeed",
    "whirl_frequencies",
    "whirl_frequencies_eig",
    "natural_frequencies",
    "campbell",
    "critical_speeds",
    "critical_speeds_numeric",
    "first_forward_critical",
]

TWO_PI = 2 * math.pi


@dataclass(frozen=True)
class Mode:
    """One natural whirl frequency.

    Attributes
    ----------
    n : int
        Mode number (half-waves along the span).
    branch : str
        ``"bending"`` or ``"shear"`` (the second Timoshenko spectrum).
    whirl : str
        ``"forward"`` or ``"backward"``.
    frequency_hz : float
        Whirl frequency (Hz), positive.
    """

    n: int
    branch: str
    whirl: str
    frequency_hz: float

    @property
    def frequency_rad_s(self) -> float:
        """Whirl frequency (rad/s), positive."""
        return self.frequency_hz * TWO_PI


@dataclass(frozen=True)
class CriticalSpeed:
    """A spin speed at which a whirl frequency equals the spin.

    Attributes
    ----------
    n : int
        Mode number.
    branch : str
        ``"bending"`` or ``"shear"``.
    whirl : str
        ``"forward"`` or ``"backward"``.
    speed_rad_s : float
        Critical spin speed (rad/s).
    """

    n: int
    branch: str
    whirl: str
    speed_rad_s: float

    @property
    def speed_hz(self) -> float:
        """Critical spin speed (Hz, revolutions per second)."""
        return self.speed_rad_s / TWO_PI


def _check_speed(speed) -> np.ndarray:
    arr = np.asarray(speed, dtype=float)
    if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise InputError("speed", speed, "finite spin speeds >= 0 (rad/s)")
    return arr


def _poly_coefficients(shaft: Shaft, n: int, speed: np.ndarray) -> np.ndarray:
    """Characteristic polynomial in ``w`` (rad/s), highest power first; shape ``(S, deg+1)``."""
    k = shaft.wavenumber(n)
    rho = shaft.density
    rho_a, rho_i = shaft.mass_per_length, rho * shaft.second_moment
    rho_ip = rho * shaft.polar_moment * (1.0 if shaft.gyroscopic else 0.0)
    ei = shaft.bending_stiffness
    om = np.atleast_1d(speed).astype(float)
    one = np.ones_like(om)
    if shaft.theory == "timoshenko":
        kga = shaft.shear_stiffness
        return np.stack(
            [
                rho_a * rho_i * one,
                -rho_a * rho_ip * om,
                -(rho_a * (ei * k**2 + kga) + rho_i * kga * k**2) * one,
                kga * k**2 * rho_ip * om,
                kga * ei * k**4 * one,
            ],
            axis=-1,
        )
    if shaft.theory == "rayleigh":
        return np.stack(
            [(rho_a + rho_i * k**2) * one, -rho_ip * k**2 * om, -ei * k**4 * one], axis=-1
        )
    return np.stack([rho_a * one, 0 * om, -ei * k**4 * one], axis=-1)


def _frequency_scale(shaft: Shaft, n: int) -> float:
    """Euler-Bernoulli frequency of mode ``n`` (rad/s), used to scale the polynomial."""
    k = shaft.wavenumber(n)
    return math.sqrt(shaft.bending_stiffness * k**4 / shaft.mass_per_length)


def _sorted_signed(roots: np.ndarray) -> np.ndarray:
    """Order signed roots as [backward shear, backward bending, forward bending, forward shear]."""
    return np.sort(roots, axis=-1)


def whirl_frequencies(shaft: Shaft, n: int, speed) -> np.ndarray:
    """Signed whirl frequencies of mode ``n`` from the characteristic equation.

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    n : int
        Mode number ``>= 1``.
    speed : float or array_like
        Spin speed(s) ``Omega`` (rad/s), ``>= 0``.

    Returns
    -------
    ndarray, shape (..., 4) or (..., 2)
        Signed whirl frequencies ``w`` (rad/s) in ascending order: Timoshenko
        ``[backward shear, backward bending, forward bending, forward shear]``; Rayleigh and
        Euler-Bernoulli ``[backward, forward]``.

    Examples
    --------
    >>> s = Shaft(length=0.4, diameter=0.1, youngs_modulus=71e9, density=2660,
    ...           shear_modulus=26.2e9, shear_coefficient="seed")
    >>> w = whirl_frequencies(s, 1, 0.0)
    >>> [round(float(abs(x)) / (2 * 3.141592653589793), 1) for x in w]
    [22381.4, 1193.2, 1193.2, 22381.4]
    """
    om = _check_speed(speed)
    coeffs = _poly_coefficients(shaft, n, om.ravel())
    deg = coeffs.shape[1] - 1
    scale = _frequency_scale(shaft, n)
    # scaled polynomial in u = w / scale, made monic; companion matrices solved as one stack
    powers = scale ** np.arange(deg, -1, -1)
    sc = coeffs * powers
    sc = sc / sc[:, :1]
    comp = np.zeros((len(om.ravel()), deg, deg))
    comp[:, 0, :] = -sc[:, 1:]
    comp[:, np.arange(1, deg), np.arange(deg - 1)] = 1.0
    u = np.linalg.eigvals(comp).real
    # Newton polish on the scaled polynomial (roots are real and simple for an undamped rotor)
    dc = sc[:, :-1] * np.arange(deg, 0, -1)
    for _ in range(4):
        p = np.zeros_like(u)
        dp = np.zeros_like(u)
        for j in range(deg + 1):
            p = p * u + sc[:, j : j + 1]
        for j in range(deg):
            dp = dp * u + dc[:, j : j + 1]
        step = np.divide(p, dp, out=np.zeros_like(p), where=dp != 0)
        u = u - step
    out = _sorted_signed(u * scale)
    return out.reshape(om.shape + (deg,))


def whirl_frequencies_eig(shaft: Shaft, n: int, speed: float) -> np.ndarray:
    """Signed whirl frequencies of mode ``n`` from the eigenvalues of the modal matrices.

    Independent of :func:`whirl_frequencies`. With ``q ~ exp(i w t)`` the free rotor gives the
    Hermitian quadratic problem ``(w^2 M - w Omega g - K) q = 0`` where ``G = -i g``. Mass
    normalisation (``Kt = M^-1/2 K M^-1/2``, ``gt = M^-1/2 g M^-1/2``) and ``Lt = Kt^1/2`` turn it
    into the real symmetric eigenproblem ``[[Omega gt, Lt], [Lt, 0]] z = w z``, solved by
    ``scipy.linalg.eigh`` to near machine precision.

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    n : int
        Mode number ``>= 1``.
    speed : float
        Spin speed ``Omega`` (rad/s).

    Returns
    -------
    ndarray
        Signed whirl frequencies (rad/s), ascending, as :func:`whirl_frequencies`.
    """
    om = float(_check_speed(speed))
    mm = modal_matrices(shaft, n)
    scale = _frequency_scale(shaft, n)
    m_isqrt = np.diag(1.0 / np.sqrt(np.diag(mm.M)))  # M is diagonal
    kt = m_isqrt @ mm.K @ m_isqrt / scale**2
    gt = (m_isqrt @ (1j * mm.G) @ m_isqrt).real / scale
    lam, vec = scipy.linalg.eigh(kt)
    lt = (vec * np.sqrt(lam)) @ vec.T
    z = np.zeros_like(kt)
    h = np.block([[om * gt, lt], [lt, z]])
    return scipy.linalg.eigh(h, eigvals_only=True) * scale


def _labels(shaft: Shaft) -> list[tuple[str, str]]:
    if shaft.theory == "timoshenko":
        return [
            ("shear", "backward"),
            ("bending", "backward"),
            ("bending", "forward"),
            ("shear", "forward"),
        ]
    return [("bending", "backward"), ("bending", "forward")]


def natural_frequencies(shaft: Shaft, speed: float = 0.0) -> list[Mode]:
    """Every whirl frequency of every mode at one spin speed, labelled.

    Parameters
    ----------
    shaft : Shaft
        The rotor (``shaft.modes`` modes).
    speed : float
        Spin speed ``Omega`` (rad/s), ``>= 0``.

    Returns
    -------
    list of Mode
        Sorted by mode number, then branch (bending first), then whirl (backward first).
    """
    out = []
    labels = _labels(shaft)
    for n in range(1, shaft.modes + 1):
        w = whirl_frequencies(shaft, n, speed)
        for (branch, whirl), wi in zip(labels, w, strict=True):
            out.append(Mode(n, branch, whirl, abs(float(wi)) / TWO_PI))
    order = {"bending": 0, "shear": 1, "backward": 0, "forward": 1}
    out.sort(key=lambda m: (m.n, order[m.branch], order[m.whirl]))
    return out


def campbell(shaft: Shaft, speeds) -> dict:
    """Campbell diagram data: whirl frequencies of every mode over a speed range.

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    speeds : array_like, shape (S,)
        Spin speeds (rad/s), ``>= 0``.

    Returns
    -------
    dict
        ``"speed_rad_s"`` (S,), ``"n"`` (N,), ``"labels"`` list of (branch, whirl) of length B and
        ``"frequency_hz"`` array (S, N, B) of positive whirl frequencies (Hz).
    """
    sp = _check_speed(speeds).ravel()
    freqs = np.stack(
        [np.abs(whirl_frequencies(shaft, n, sp)) / TWO_PI for n in range(1, shaft.modes + 1)],
        axis=1,
    )
    return {
        "speed_rad_s": sp,
        "n": np.arange(1, shaft.modes + 1),
        "labels": _labels(shaft),
        "frequency_hz": freqs,
    }


def _critical_quadratic(shaft: Shaft, n: int, s: int) -> list[float]:
    """Positive roots ``X = Omega^2`` of the characteristic equation with ``w = s Omega``."""
    c = _poly_coefficients(shaft, n, np.array([1.0]))[0]
    if shaft.theory == "timoshenko":
        # c4 w^4 + c3' Om w^3 + c2 w^2 + c1' Om w + c0 with w = s Om; s^3 = s
        qa = c[0] + s * c[1]
        qb = c[2] + s * c[3]
        qc = c[4]
    else:
        qa = c[0] + s * c[1]
        qb = c[2]
        qc = 0.0
    if shaft.theory != "timoshenko":
        return [-qb / qa] if qa > 0 else []
    disc = qb * qb - 4 * qa * qc
    if disc < 0:
        return []
    sq = math.sqrt(disc)
    # numerically stable quadratic roots
    q = -0.5 * (qb + math.copysign(sq, qb))
    roots = []
    if qa != 0:
        roots.append(q / qa)
    if q != 0:
        roots.append(qc / q)
    return sorted(x for x in roots if x > 0)


def _branch_at(shaft: Shaft, n: int, speed: float, s: int) -> str:
    w = whirl_frequencies(shaft, n, speed)
    idx = int(np.argmin(np.abs(w - s * speed)))
    return _labels(shaft)[idx][0]


def critical_speeds(shaft: Shaft, max_speed: float | None = None) -> list[CriticalSpeed]:
    """Forward and backward critical speeds of every mode, in closed form.

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    max_speed : float, optional
        Drop critical speeds above this (rad/s).

    Returns
    -------
    list of CriticalSpeed
        Sorted by speed.

    Examples
    --------
    >>> s = Shaft(length=0.4, diameter=0.1, youngs_modulus=71e9, density=2660,
    ...           shear_modulus=26.2e9, shear_coefficient="seed")
    >>> round(first_forward_critical(s), 1)
    7742.5
    """
    out = []
    for n in range(1, shaft.modes + 1):
        for s, whirl in ((1, "forward"), (-1, "backward")):
            for x in _critical_quadratic(shaft, n, s):
                om = math.sqrt(x)
                if max_speed is not None and om > max_speed:
                    continue
                out.append(CriticalSpeed(n, _branch_at(shaft, n, om, s), whirl, om))
    out.sort(key=lambda c: c.speed_rad_s)
    return out


def critical_speeds_numeric(shaft: Shaft, n: int, whirl: str, branch: str = "bending") -> float:
    """One critical speed found on the eigenvalue route by bracketing (second route).

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    n : int
        Mode number.
    whirl : {"forward", "backward"}
        Whirl direction.
    branch : {"bending", "shear"}
        Branch.

    Returns
    -------
    float
        Speed ``Omega`` (rad/s) where that whirl frequency equals ``+-Omega``.
    """
    labels = _labels(shaft)
    idx = labels.index((branch, whirl))
    s = 1 if whirl == "forward" else -1

    def f(om):
        return abs(whirl_frequencies_eig(shaft, n, om)[idx]) - om

    hi = abs(whirl_frequencies_eig(shaft, n, 0.0)[idx])
    while f(hi) > 0:
        hi *= 2
        if hi > 1e9:
            raise InputError(
                "whirl", whirl, f"a branch that crosses the spin line (mode {n}, {branch})"
            )
    del s
    import scipy.optimize  # only here: its import costs 0.2-0.4 s of every CLI call

    return scipy.optimize.brentq(f, 0.0, hi, xtol=1e-12 * hi, rtol=1e-15, maxiter=500)


def first_forward_critical(shaft: Shaft) -> float:
    """First forward critical speed (rad/s): forward bending whirl of mode 1 equal to spin.

    Parameters
    ----------
    shaft : Shaft
        The rotor.

    Returns
    -------
    float
        Speed (rad/s).
    """
    for c in critical_speeds(shaft):
        if c.n == 1 and c.whirl == "forward" and c.branch == "bending":
            return c.speed_rad_s
    raise InputError("shaft", shaft, "a rotor whose mode 1 has a forward critical speed")
