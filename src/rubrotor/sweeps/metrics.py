"""Per-point reduction of a sweep: a kept window of one run to rub metrics and a regime.

The metrics and their definitions are listed in :mod:`rubrotor.sweeps.sweep`; every sweep (plain,
state-carrying, on the continuous shaft or a general rotor) reduces its kept window here, and
labels it with :func:`rubrotor.sweeps.regimes.classify`.
"""

from __future__ import annotations

import functools

import numpy as np

from rubrotor.sweeps.regimes import (
    UNCLASSIFIED,
    classify,
    contact_fraction,
    impacts_per_revolution,
    poincare_dimension,
)

__all__ = ["N_PEAKS", "point_metrics", "window_metrics"]

N_PEAKS = 3
"""Spectral peaks kept per point."""


# ---- per-point reduction -----------------------------------------------------------------------
@functools.lru_cache(maxsize=8)
def _window_tables(n: int, samples_per_rev: int):
    """Periodic Hann window, its gain, FFT bin frequencies (cycles per revolution) and the
    positive-frequency mask of an ``n``-sample window: the same at every point of a sweep."""
    w = 0.5 - 0.5 * np.cos(2 * np.pi * np.arange(n) / n)
    freq = np.fft.fftfreq(n, d=1.0 / samples_per_rev)
    positive = freq > 0
    for a in (w, freq, positive):
        a.flags.writeable = False
    return w, w.sum(), freq, positive


def _largest_first(idx: np.ndarray, mag: np.ndarray, count: int) -> np.ndarray:
    """The first ``count`` of ``idx`` stably sorted by decreasing ``mag[idx]`` (ties keep their
    order), without sorting all of them: only those at least as large as the ``count``-th
    largest value (ties included) are sorted."""
    m = -mag[idx]
    if m.size > count:
        cut = np.partition(m, count - 1)[count - 1]
        keep = np.flatnonzero(m <= cut)
        return idx[keep[np.argsort(m[keep], kind="stable")]][:count]
    return idx[np.argsort(m, kind="stable")]


def _spectrum(p: np.ndarray, samples_per_rev: int, revs: int):
    """Peaks, forward share and line fraction of the complex signal ``p`` (see module doc)."""
    n = p.size
    w, gain, freq, positive = _window_tables(n, samples_per_rev)
    X = np.fft.fft((p - p.mean()) * w)
    mag = np.abs(X)
    power = mag**2
    power[0] = 0.0
    total = power.sum()
    out_f = np.full(N_PEAKS, np.nan)
    out_a = np.full(N_PEAKS, np.nan)
    if total <= 0 or not np.isfinite(total):
        return out_f, out_a, np.nan, np.nan
    # local maxima (circular neighbours, as np.roll would give, without the two copies)
    is_peak = np.empty(n, bool)
    np.greater(mag[1:-1], mag[:-2], out=is_peak[1:-1])
    is_peak[1:-1] &= mag[1:-1] >= mag[2:]
    is_peak[-1] = mag[-1] > mag[-2] and mag[-1] >= mag[0]
    is_peak[0] = False
    idx = _largest_first(np.flatnonzero(is_peak), mag, 10)
    lines = np.zeros(n, bool)
    for i in idx[:10]:
        lines[(i + np.arange(-2, 3)) % n] = True
    lines[0] = False
    line_fraction = float(power[lines].sum() / total)
    for j, i in enumerate(idx[:N_PEAKS]):
        a, b, c = (np.log(max(mag[(i + d) % n], 1e-300)) for d in (-1, 0, 1))
        den = a - 2 * b + c
        delta = 0.5 * (a - c) / den if den < 0 else 0.0
        delta = min(max(delta, -0.5), 0.5)
        out_f[j] = freq[i] + delta / revs
        out_a[j] = float(np.exp(b - 0.25 * (a - c) * delta)) / gain
    forward = float(power[positive].sum() / total)
    return out_f, out_a, forward, line_fraction


def point_metrics(
    time: np.ndarray,
    p: np.ndarray,
    normal_force: np.ndarray,
    events: np.ndarray,
    speed: float,
    transient_revolutions: int,
    revolutions: int,
    samples_per_revolution: int,
    complete: bool = True,
    lyapunov: float = np.nan,
) -> dict:
    """Reduce one simulation to the sweep's metrics (see the module docstring).

    Parameters
    ----------
    time : ndarray
        Sample times (s), spaced ``2 pi / (N Omega)`` from 0.
    p : ndarray, complex
        ``v + i w`` at the contact station (m).
    normal_force : ndarray
        Normal contact force (N).
    events : ndarray
        Contact onsets ``+t`` and separations ``-t`` (s).
    speed : float
        Spin speed ``Omega`` (rad/s).
    transient_revolutions, revolutions, samples_per_revolution : int
        ``T``, ``R`` and ``N``.
    complete : bool
        Whether the run completed; otherwise every metric is NaN and the regime
        ``"not classified"``.
    lyapunov : float
        Largest Lyapunov exponent (1/s), NaN when not computed.

    Returns
    -------
    dict
        Arrays and scalars keyed by the Dataset variable names.
    """
    n_rev = samples_per_revolution
    i0, i1 = transient_revolutions * n_rev, revolutions * n_rev
    if not complete or p.size < i1 + 1:
        return _empty_metrics(revolutions - transient_revolutions)
    return window_metrics(p[i0:i1], normal_force[i0:i1], events, speed, transient_revolutions,
                          revolutions, samples_per_revolution, lyapunov)  # fmt: skip


def window_metrics(
    pw: np.ndarray,
    fn: np.ndarray,
    events: np.ndarray,
    speed: float,
    transient_revolutions: int,
    revolutions: int,
    samples_per_revolution: int,
    lyapunov: float = np.nan,
    clearance: float | None = None,
) -> dict:
    """:func:`point_metrics` of the kept window alone (the samples ``T N .. R N - 1``).

    Parameters
    ----------
    pw : ndarray, complex, shape ((R - T) N,)
        ``v + i w`` at the contact station (m) over the kept window.
    fn : ndarray, shape ((R - T) N,)
        Normal contact force (N) over the kept window.
    events, speed, transient_revolutions, revolutions, samples_per_revolution, lyapunov
        As in :func:`point_metrics` (s, rad/s, counts, 1/s).
    clearance : float, optional
        Clearance (m) of a rigid stator centred on the axis, for the ``"indentation >
        clearance"`` regime (:func:`rubrotor.sweeps.regimes.classify`).

    Returns
    -------
    dict
        Arrays and scalars keyed by the Dataset variable names.
    """
    n_rev = samples_per_revolution
    k = revolutions - transient_revolutions
    out = _empty_metrics(k)
    z = pw[::n_rev]
    absp = np.abs(pw)
    out["poincare_v"] = z.real.copy()
    out["poincare_w"] = z.imag.copy()
    out["peak_normal_force"] = float(fn.max())
    out["rms_normal_force"] = float(np.sqrt(np.mean(fn**2)))
    cf = contact_fraction(fn)
    out["contact_fraction"] = cf
    t0 = transient_revolutions * 2 * np.pi / speed
    t1 = revolutions * 2 * np.pi / speed
    out["impacts_per_revolution"] = impacts_per_revolution(events, t0, t1, speed)
    out["max_displacement"] = float(absp.max())
    ripple = float((absp.max() - absp.min()) / absp.max()) if absp.max() > 0 else 0.0
    out["amplitude_ripple"] = ripple
    f, a, fwd, lines = _spectrum(pw, n_rev, k)
    out["frequency"] = f
    out["frequency_amplitude"] = a
    out["forward_share"] = fwd
    out["line_fraction"] = lines
    dim = poincare_dimension(z)
    out["poincare_dimension"] = dim
    out["lyapunov_exponent"] = lyapunov
    per_rev = lyapunov * 2 * np.pi / speed
    code, period = classify(cf, ripple, z, lines, dim, lyapunov_per_rev=per_rev,
                            scale=float(absp.max()), clearance=clearance)  # fmt: skip
    out["regime"] = code
    out["period"] = period
    out["status"] = 1
    return out


_SCALARS = {
    # name: (dtype, fill, units, long_name)
    "peak_normal_force": ("f8", np.nan, "N", "peak normal contact force"),
    "rms_normal_force": (
        "f8",
        np.nan,
        "N",
        "RMS normal contact force (time out of contact counts)",
    ),
    "contact_fraction": ("f8", np.nan, "1", "fraction of the time in contact"),
    "impacts_per_revolution": ("f8", np.nan, "1", "contact onsets per revolution"),
    "max_displacement": ("f8", np.nan, "m", "largest |v + i w| at the contact station"),
    "amplitude_ripple": ("f8", np.nan, "1", "(max |P| - min |P|) / max |P|"),
    "forward_share": ("f8", np.nan, "1", "share of non-DC spectral power in forward whirl"),
    "line_fraction": ("f8", np.nan, "1", "share of non-DC spectral power in the 10 largest lines"),
    "poincare_dimension": ("f8", np.nan, "1", "dimension estimate of the Poincare set"),
    "lyapunov_exponent": ("f8", np.nan, "1/s", "largest Lyapunov exponent (NaN: not computed)"),
    "regime": ("i1", UNCLASSIFIED, "1", "rub regime code"),
    "period": ("i2", 0, "1", "period (revolutions) of a periodic partial rub, else 0"),
    "status": ("i1", 0, "1", "1 when the simulation completed"),
}


def _empty_metrics(k: int) -> dict:
    out = {name: (np.nan if spec[0] == "f8" else spec[1]) for name, spec in _SCALARS.items()}
    out["poincare_v"] = np.full(k, np.nan)
    out["poincare_w"] = np.full(k, np.nan)
    out["frequency"] = np.full(N_PEAKS, np.nan)
    out["frequency_amplitude"] = np.full(N_PEAKS, np.nan)
    return out
