"""The seed's cases and the measurements every seed study shares.

Which shipped scenarios are the seed's cases, and how a case run is measured (contact numbers,
Poincare period, band energies of the acceleration near the mode-1 shear branch). Used by
:mod:`rubrotor.studies.seed.reproduce` and by the studies of :mod:`rubrotor.studies.seed`; it imports neither of them, so
the reproduction depends on the studies and never the other way round.
"""

from __future__ import annotations

import math
from importlib import resources

import numpy as np

from rubrotor.analysis.overview import band_energy
from rubrotor.scenario.load import Scenario, load_scenario

__all__ = [
    "CASES",
    "PERIOD_TOL",
    "seed_scenario",
    "poincare_period",
    "case_metrics",
    "shear1_band",
    "spectral_numbers",
    "regime",
]

TWO_PI = 2 * math.pi

CASES = [
    ("case1", "seed_case1", "Case 1: g' = 3e-3, b_h' = 1e2"),
    ("case2", "seed_case2", "Case 2: g' = 3.5e-3, b_h' = 1e2"),
    ("case3", "seed_case3", "Case 3: g' = 3.5e-3, b_h' = 1e3"),
    ("no_contact", "seed_no_contact", "No contact"),
]
"""(key, scenario file stem, title) of the seed's cases, in the seed's order."""


PERIOD_TOL = 0.01  # Poincare residual (relative to max |P|) below which a period is accepted


def seed_scenario(stem: str) -> Scenario:
    """The shipped scenario ``rubrotor/scenarios/<stem>.toml``."""
    return load_scenario(resources.files("rubrotor") / "scenarios" / f"{stem}.toml")


def poincare_period(ds, max_k: int = 12, tol: float = PERIOD_TOL) -> dict:
    """Period of the late response from once-per-revolution (Poincare) samples.

    The orbit ``P = v + i w`` is interpolated at ``tau = 2 pi j`` over the second half of the
    run; for each ``k`` the residual ``max_j |P_{j+k} - P_j| / max |P|`` is computed.

    Parameters
    ----------
    ds : xarray.Dataset
        Results.
    max_k : int
        Largest period tried (revolutions).
    tol : float
        Residual below which the response counts as period-k.

    Returns
    -------
    dict
        ``period`` (smallest k with residual < tol, or None), ``best_k`` and ``best_residual``
        (the k with the smallest residual), ``residuals`` (list, k = 1..max_k), ``samples``.
    """
    tau = ds["tau"].values
    p = ds["v"].values[0] + 1j * ds["w"].values[0]  # the contact station
    half = tau[-1] / 2
    jj = np.arange(math.ceil(half / TWO_PI), math.floor(tau[-1] / TWO_PI) + 1)
    pts = np.interp(jj * TWO_PI, tau, p.real) + 1j * np.interp(jj * TWO_PI, tau, p.imag)
    scale = float(np.max(np.abs(p[tau >= half])))
    res = []
    for k in range(1, max_k + 1):
        if pts.size <= k + 2:
            res.append(float("nan"))
            continue
        res.append(float(np.max(np.abs(pts[k:] - pts[:-k])) / scale))
    arr = np.array(res)
    ok = [k for k, r in enumerate(res, 1) if r < tol]
    if np.all(np.isnan(arr)):  # too few revolutions (e.g. a run that diverged early)
        return {"period": None, "best_k": 0, "best_residual": float("nan"), "residuals": res,
                "samples": int(pts.size)}  # fmt: skip
    best = int(np.nanargmin(arr)) + 1
    return {
        "period": ok[0] if ok else None,
        "best_k": best,
        "best_residual": res[best - 1],
        "residuals": res,
        "samples": int(pts.size),
    }


def case_metrics(ds, clearance: float | None) -> dict:
    """Contact and orbit numbers of the late response (second half of the run).

    Parameters
    ----------
    ds : xarray.Dataset
        Results.
    clearance : float or None
        Radial clearance (m); None without contact.

    Returns
    -------
    dict
        ``status``, ``contact_fraction`` (share of late samples in contact),
        ``max_orbit_over_clearance`` (``max |P| / g``), ``max_orbit_m``, ``max_normal_force_N``,
        ``mean_normal_force_N``, ``impacts_per_rev`` (contact onsets per revolution),
        ``poincare`` (see ``poincare_period``), ``revolutions`` (simulated).
    """
    tau = ds["tau"].values
    late = tau >= tau[-1] / 2
    p = np.hypot(ds["v"].values[0], ds["w"].values[0])  # the contact station
    fn = ds["normal_force"].values.sum(axis=0)  # one contact row; none: zeros
    inc = fn[late] > 0
    onsets = int(np.sum(np.diff(inc.astype(np.int8)) == 1))
    revs_late = (tau[-1] - tau[late][0]) / TWO_PI
    out = {
        "status": ds.attrs["status"],
        "revolutions": float(tau[-1] / TWO_PI),
        "contact_fraction": float(np.mean(inc)),
        "max_orbit_m": float(p[late].max()),
        "max_orbit_over_clearance": float(p[late].max() / clearance) if clearance else None,
        "max_normal_force_N": float(fn[late].max()),
        "mean_normal_force_N": float(fn[late].mean()),
        "impacts_per_rev": onsets / revs_late if revs_late > 0 else 0.0,
        "poincare": poincare_period(ds),
    }
    return out


def shear1_band(entries) -> tuple[float, float, float, float]:
    """Mode-1 shear branch ``(backward, forward, low edge, high edge)`` (Hz) of mode entries."""
    f = {lab: fr for lab, fr, _ in entries}
    lo, hi = f["1B shear"], f["1F shear"]
    return lo, hi, 0.95 * lo, 1.05 * hi


def spectral_numbers(ds, entries, band) -> dict:
    """Band energies of the acceleration orbit near the mode-1 shear branch and elsewhere."""
    fs = 1.0 / float(np.mean(np.diff(ds["time"].values)))
    tau = ds["tau"].values
    late = tau >= tau[-1] / 2
    a_v = ds["v_ddot"].values[0, late]  # the contact station
    a_w = ds["w_ddot"].values[0, late]
    total = float(np.mean(a_v**2 + a_w**2))
    e1 = band_energy(a_v, fs, band[2], band[3], w=a_w)
    # share of the same (Hann-windowed) periodogram: a growing record is not dominated by its
    # last, windowed-out samples
    total_w = band_energy(a_v, fs, 0.0, fs / 2, w=a_w)
    f = {lab: fr for lab, fr, _ in entries}
    e3 = band_energy(a_v, fs, 0.95 * f["3B shear"], 1.05 * f["3F shear"], w=a_w)
    # strongest line of the full spectrum inside the mode-1 shear band
    from rubrotor.analysis.spectra import full_spectrum

    spec = full_spectrum(a_v, a_w, fs)
    sel = (np.abs(spec.frequencies) >= band[2]) & (np.abs(spec.frequencies) <= band[3])
    k = int(np.argmax(np.where(sel, spec.amplitudes, -1.0)))
    return {
        "fs_hz": fs,
        "acc_mean_square": total,
        "shear1_band_hz": [band[2], band[3]],
        "shear1_band_energy": e1,
        "shear1_band_share": e1 / total_w if total_w > 0 else 0.0,
        "shear3_band_energy": e3,
        "shear1_peak_hz": float(spec.frequencies[k]),
    }


def regime(m: dict) -> str:
    """Regime label of a case's ``case_metrics`` (see :func:`rubrotor.sweeps.regimes.case_regime`)."""
    from rubrotor.sweeps.regimes import case_regime

    return case_regime(m)
