"""Rub regimes and per-run metrics: one definition used by sweeps, follow sweeps, continuation
and the seed reproduction.

Per-run metrics (over a kept window of whole revolutions ``[t0, t1)``, ``P = v + i w`` (m) the
contact-station deflection):

* :func:`contact_fraction`: share of the samples with a normal force > 0;
* :func:`impacts_per_revolution`: contact onsets (the ``+t`` entries of a simulation's event
  list: exact event times located within the step, so contacts shorter than an output sample
  are counted) in ``[t0, t1)`` divided by the revolutions ``(t1 - t0) Omega / (2 pi)``;
* :func:`find_period`: the Poincare period, the smallest ``k`` such that the once-per-revolution
  samples fall in ``k`` clusters of radius ``PERIOD_RTOL * max |P|`` (``PERIOD_RTOL = 1e-3``);
* :func:`poincare_dimension`: correlation-dimension estimate of the Poincare set.

Regime labels, decided in this order by :func:`classify`:

- ``"no contact"``: ``contact_fraction == 0``.
- ``"indentation > clearance"``: given the clearance ``g`` of a rigid, centred stator with a
   Hertz contact (sweeps pass it for those), the largest ``|P|`` exceeds ``2 g``: the rotor
   runs deeper into the stator than the whole clearance, far outside the local elastic
   indentation the Hertz law models (the seed rotor's rub branch at 1.5 x critical sits at
   4.7 mm against 1.2 mm; at higher speeds at 10 mm). Whatever the contact fraction says,
   this is not a full annular rub of a real machine.
- ``"full annular rub"``: ``contact_fraction >= 0.99`` and ``amplitude_ripple <= 0.05`` (in
   contact all the time with a nearly constant ``|P|``, whatever the whirl direction).
- ``"partial rub (period-k)"``: a Poincare period ``k`` in ``1 .. min(12, K // 2)`` is found.
- ``"quasi-periodic"`` / ``"chaotic"``: no period found. When the largest Lyapunov exponent
   ``lambda_1`` (1/s, :func:`rubrotor.orbits.lyapunov.lyapunov_exponents`) is known, the motion is
   chaotic exactly when its growth per revolution ``lambda_1 2 pi / Omega`` exceeds
   :data:`CHAOS_MARGIN_PER_REV` (0.05, a 5 % divergence per revolution), else quasi-periodic.
   The margin stands above the finite-time estimates of the zero exponent of a torus: measured
   0.002 .. 0.015 per revolution on quasi-periodic rub motions (undamped seed case 1; a
   one-mode rotor past its annular-rub branch) averaged over 100 .. 200 revolutions. Without
   an exponent nothing is called chaotic: the motion is quasi-periodic when its data show a
   torus, ``line_fraction >= 0.9`` (a line spectrum) and ``poincare_dimension <= 1.5`` (or
   NaN), otherwise ``"aperiodic"`` (a broadband motion without a period, chaotic or not: the
   exponent tells, ``--lyapunov``).
- ``"not classified"``: the run did not complete or could not be simulated.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "REGIMES",
    "NO_CONTACT",
    "PARTIAL",
    "FULL",
    "QUASI",
    "CHAOTIC",
    "UNCLASSIFIED",
    "APERIODIC",
    "DEEP",
    "PERIOD_RTOL",
    "CHAOS_MARGIN_PER_REV",
    "contact_fraction",
    "impacts_per_revolution",
    "find_period",
    "poincare_dimension",
    "classify",
    "regime_label",
    "regime_labels",
    "case_regime",
]

PERIOD_RTOL = 1e-3
"""Poincare cluster radius, relative to the largest ``|P|``, below which a period is accepted."""

CHAOS_MARGIN_PER_REV = 0.05
"""Largest Lyapunov exponent per revolution (``lambda_1 2 pi / Omega``) above which a motion
with no Poincare period is chaotic."""

FULL_CONTACT = 0.99
MAX_RIPPLE = 0.05


def contact_fraction(normal_force: np.ndarray) -> float:
    """Share of the samples in contact (normal force > 0 N), 0..1.

    Examples
    --------
    >>> contact_fraction(np.array([0.0, 1.0, 2.0, 0.0]))
    0.5
    """
    return float(np.mean(np.asarray(normal_force) > 0))


def impacts_per_revolution(events: np.ndarray, t0: float, t1: float, speed: float) -> float:
    """Contact onsets per revolution in ``[t0, t1)`` (one definition, see the module docstring).

    Parameters
    ----------
    events : ndarray
        Contact onset ``+t`` and separation ``-t`` times (s), as
        ``rubrotor.engine.simulate.SimulationResult.events`` (a Dataset's ``event_time`` times
        ``event_kind``).
    t0, t1 : float
        Window (s), ``t1 > t0``.
    speed : float
        Spin speed (rad/s).

    Returns
    -------
    float
        Onsets per revolution (1/rev).

    Examples
    --------
    >>> impacts_per_revolution(np.array([0.5, -0.7, 1.5, -1.7]), 0.0, 4.0, math.pi)
    1.0
    """
    ev = np.asarray(events, float)
    onsets = np.count_nonzero((ev > 0) & (ev >= t0) & (ev < t1))
    return float(onsets / ((t1 - t0) * speed / (2 * math.pi)))


REGIMES = (
    "no contact",
    "partial rub",
    "full annular rub",
    "quasi-periodic",
    "chaotic",
    "not classified",
    "aperiodic",
    "indentation > clearance",
)
"""Regime names by code (code 1 is labelled ``"partial rub (period-k)"`` with its period); codes
6 and 7 were added after the others, so stored sweeps keep their meaning."""

NO_CONTACT, PARTIAL, FULL, QUASI, CHAOTIC, UNCLASSIFIED, APERIODIC, DEEP = range(8)


def poincare_dimension(z: np.ndarray, max_points: int = 1000) -> float:
    """Correlation-dimension estimate of Poincare points ``z`` (complex), see the module doc.

    ``D = log(C(8 d) / C(2 d)) / log 4`` where ``C(r)`` counts the pairs of points closer than
    ``r`` and ``d`` is the median nearest-neighbour distance: about 1 for points on a curve,
    about 2 for points filling an area. NaN with fewer than 64 points, coincident points or no
    pair within ``2 d``. At most the first ``max_points`` points are used.
    """
    z = np.asarray(z, complex)[:max_points]
    if z.size < 64:
        return np.nan
    dist = np.abs(z[:, None] - z[None, :])
    np.fill_diagonal(dist, np.inf)
    d = float(np.median(dist.min(axis=1)))
    if not d > 0:
        return np.nan
    c1 = np.count_nonzero(dist < 2 * d)
    c2 = np.count_nonzero(dist < 8 * d)
    if c1 == 0:
        return np.nan
    return float(math.log(c2 / c1) / math.log(4.0))


def find_period(z: np.ndarray, tol: float, max_period: int = 12) -> int:
    """Smallest ``k`` such that the points ``z`` form ``k`` clusters of radius ``tol``; 0 if none.

    Parameters
    ----------
    z : ndarray, complex
        Poincare points in order (one per revolution).
    tol : float
        Largest distance of a point from the mean of its residue class ``j mod k`` (same unit
        as ``z``).
    max_period : int
        Largest ``k`` tried; ``k <= len(z) // 2`` (every cluster seen at least twice).

    Examples
    --------
    >>> find_period(np.array([1, -1, 1, -1, 1, -1], complex), 1e-9)
    2
    """
    for k in range(1, min(max_period, z.size // 2) + 1):
        ok = True
        for r in range(k):
            pts = z[r::k]
            if np.max(np.abs(pts - pts.mean())) > tol:
                ok = False
                break
        if ok:
            return k
    return 0


def classify(
    contact_fraction: float,
    amplitude_ripple: float,
    poincare: np.ndarray,
    line_fraction: float,
    dimension: float = np.nan,
    *,
    lyapunov_per_rev: float = np.nan,
    scale: float | None = None,
    period_rtol: float = PERIOD_RTOL,
    max_period: int = 12,
    full_contact: float = FULL_CONTACT,
    max_ripple: float = MAX_RIPPLE,
    min_line_fraction: float = 0.9,
    max_dimension: float = 1.5,
    chaos_margin: float = CHAOS_MARGIN_PER_REV,
    clearance: float | None = None,
) -> tuple[int, int]:
    """Regime code and period of one run, by the rules of the module docstring.

    Parameters
    ----------
    contact_fraction : float
        Fraction of the kept time in contact (0..1).
    amplitude_ripple : float
        ``(max |P| - min |P|) / max |P|`` over the kept window; NaN when not known (the full
        annular rub is then decided by the contact fraction alone).
    poincare : ndarray, complex
        Once-per-revolution samples of ``P = v + i w`` (m).
    line_fraction : float
        Share of the non-DC spectral power in the 10 largest lines (0..1).
    dimension : float
        Poincare set dimension estimate (:func:`poincare_dimension`); NaN to ignore.
    lyapunov_per_rev : float
        Largest Lyapunov exponent times the revolution period (dimensionless); NaN when not
        computed (the spectral rule decides then).
    scale : float, optional
        Amplitude the period tolerance is relative to (m); default ``max |poincare|``.
    period_rtol, max_period, full_contact, max_ripple, min_line_fraction, max_dimension,
    chaos_margin
        Thresholds, see the module docstring.
    clearance : float, optional
        Radial clearance (m) of a rigid stator centred on the bearing axis; with it a
        ``scale`` (or ``max |poincare|``) above ``2 clearance`` is ``"indentation > clearance"``.

    Returns
    -------
    code : int
        Index into :data:`REGIMES`.
    period : int
        ``k`` for ``"partial rub (period-k)"``, else 0.

    Examples
    --------
    >>> classify(0.0, 0.1, np.ones(10, complex), 1.0)
    (0, 0)
    >>> classify(0.3, 0.5, np.array([1, 2] * 10, complex), 1.0)
    (1, 2)
    >>> classify(0.3, 0.5, np.exp(1j * np.arange(20)), 1.0, lyapunov_per_rev=0.3)
    (4, 0)
    >>> classify(0.3, 0.5, np.exp(1j * np.arange(20)), 0.2)  # broadband, no exponent
    (6, 0)
    >>> classify(1.0, 0.0, 1e-2 * np.exp(1j * np.arange(20)), 1.0, clearance=1.2e-3)
    (7, 0)
    """
    z = np.asarray(poincare, complex)
    if not np.isfinite(contact_fraction) or z.size == 0 or not np.all(np.isfinite(z)):
        return UNCLASSIFIED, 0
    if contact_fraction == 0:
        return NO_CONTACT, 0
    s = float(np.max(np.abs(z))) if scale is None else scale
    if clearance is not None and s > 2 * clearance:
        return DEEP, 0
    if contact_fraction >= full_contact and not (amplitude_ripple > max_ripple):
        return FULL, 0
    k = find_period(z, period_rtol * s, max_period)
    if k:
        return PARTIAL, k
    return _aperiodic(
        line_fraction, dimension, lyapunov_per_rev, min_line_fraction, max_dimension, chaos_margin
    ), 0


def _aperiodic(line_fraction, dimension, lyapunov_per_rev, min_lines, max_dim, margin) -> int:
    """QUASI, CHAOTIC or APERIODIC for a contacting motion without a Poincare period: chaotic
    only from an exponent (module docstring)."""
    if np.isfinite(lyapunov_per_rev):
        return CHAOTIC if lyapunov_per_rev > margin else QUASI
    curve = not (dimension > max_dim)  # NaN counts as a curve
    return QUASI if line_fraction >= min_lines and curve else APERIODIC


def case_regime(m: dict) -> str:
    """Regime label of a seed-reproduction case (:func:`rubrotor.studies.seed.reproduce.case_metrics`).

    The same rules as :func:`classify` on what that summary holds: ``status``,
    ``contact_fraction`` and the Poincare residuals ``max_j |P_{j+k} - P_j| / max |P|`` (a
    cluster of radius ``r`` gives differences up to ``2 r``, so ``k`` is accepted when its
    residual is at most ``2 PERIOD_RTOL``). It has no ripple, spectrum or exponent: a contacting
    motion with no period is labelled ``"partial rub (not periodic)"``.

    Examples
    --------
    >>> case_regime({"status": "complete", "contact_fraction": 0.2,
    ...              "poincare": {"residuals": [0.5, 1e-4]}})
    'partial rub (period-2)'
    """
    if m["status"] != "complete":
        return regime_label(UNCLASSIFIED)
    cf = m["contact_fraction"]
    if cf == 0:
        return regime_label(NO_CONTACT)
    if cf >= FULL_CONTACT:
        return regime_label(FULL)
    res = m["poincare"]["residuals"]
    period = next((k for k, r in enumerate(res, 1) if r <= 2 * PERIOD_RTOL), 0)
    return regime_label(PARTIAL, period) if period else "partial rub (not periodic)"


def regime_label(code: int, period: int = 0) -> str:
    """Text label of a regime code (``"partial rub (period-2)"`` for code 1, period 2)."""
    code = int(code)
    if code == PARTIAL:
        return f"partial rub (period-{int(period)})"
    if 0 <= code < len(REGIMES):
        return REGIMES[code]
    return "not computed"


def regime_labels(ds) -> np.ndarray:
    """Text labels of a sweep Dataset's ``regime`` and ``period``, same shape (object array)."""
    codes = np.asarray(ds["regime"].values)
    periods = np.asarray(ds["period"].values)
    out = np.empty(codes.shape, object)
    for i in np.ndindex(codes.shape):
        out[i] = regime_label(codes[i], periods[i]) if codes[i] >= 0 else "not computed"
    return out
