"""The seed's seven claims evaluated on one set of runs (cases 1-3, no contact, the Fig. 6 pair).

Shared by the main reproduction under the seed's equations and by every configuration of the
robustness study, so that a claim is measured the same way everywhere
(:func:`rubrotor.reproduce._claims` decides it).
"""

from __future__ import annotations

import numpy as np

from rubrotor.analysis.overview import mode_entries
from rubrotor.api import modes
from rubrotor.reproduce import CASES, _claims, _scenario, _shear1_band, _spectral, case_metrics

__all__ = ["seed_scenarios", "band_of", "case_numbers", "fig6_numbers", "evaluate_claims"]


def seed_scenarios(**changes) -> dict:
    """The shipped seed cases (and the Fig. 6 pair) with ``changes`` applied.

    Parameters
    ----------
    **changes
        Dotted scenario keys for every scenario (``"shaft.formulation"``, ``"damping.ratio"``,
        ``"initial.state"``); ``"contact.*"`` keys only reach the cases with a contact;
        ``"unbalance.magnitude_factor"`` multiplies each scenario's unbalance (not Fig. 6's).

    Returns
    -------
    dict
        ``{"case1", "case2", "case3", "no_contact", "fig6_t", "fig6_e"}`` to Scenario.
    """
    changes = dict(changes)
    factor = changes.pop("unbalance.magnitude_factor", 1.0)
    out = {}
    stems = [(k, s) for k, s, _ in CASES] + [
        ("fig6_t", "seed_fig6_timoshenko"),
        ("fig6_e", "seed_fig6_euler_bernoulli"),
    ]
    for key, stem in stems:
        sc = _scenario(stem)
        ch = {k: v for k, v in changes.items() if sc.contact is not None or "contact." not in k}
        if not key.startswith("fig6") and sc.unbalance is not None:
            ch["unbalance.magnitude"] = sc.unbalance.magnitude * factor
        out[key] = sc.with_changes(**ch) if ch else sc
    return out


def band_of(scenario) -> tuple[list, tuple]:
    """Mode entries ``(label, Hz, whirl)`` at the scenario speed and the mode-1 shear band (Hz)."""
    entries = mode_entries(modes(scenario, scenario.speed))
    return entries, _shear1_band(entries)


def case_numbers(results: dict, scen: dict, entries, band) -> tuple[dict, dict]:
    """``case_metrics`` and band energies of each case Dataset (as :mod:`rubrotor.reproduce`)."""
    metrics, spectral = {}, {}
    for key, _stem, _title in CASES:
        ds = results[key]
        c = scen[key].contact
        metrics[key] = case_metrics(ds, c.clearance if c else None)
        spectral[key] = _spectral(ds, entries, band)
    nc = spectral["no_contact"]["shear1_band_energy"]
    for sp in spectral.values():
        sp["shear1_ratio_to_no_contact"] = sp["shear1_band_energy"] / nc if nc > 0 else float("inf")
    return metrics, spectral


def fig6_numbers(s_t, s_e, d_t, d_e, revolutions: float) -> dict:
    """The Fig. 6 comparison numbers (relative difference, forward bending frequencies)."""
    rel = {}
    for var in ("v", "w"):
        a, b = d_t[var].values, d_e[var].values
        n = min(a.size, b.size)
        rel[var] = float(np.max(np.abs(a[:n] - b[:n])) / np.max(np.abs(a[:n])))

    def fwd(sc):
        return {
            m.n: m.frequency_hz
            for m in modes(sc, sc.speed)
            if m.branch == "bending" and m.whirl == "forward"
        }

    return {
        "slenderness": s_t.shaft.slenderness,
        "diameter_m": s_t.shaft.diameter,
        "speed_rad_s": s_t.speed,
        "revolutions": revolutions,
        "max_rel_diff_v": rel["v"],
        "max_rel_diff_w": rel["w"],
        "max_w_m": float(np.max(np.abs(d_t["w"].values))),
        "forward_bending_hz_timoshenko": fwd(s_t),
        "forward_bending_hz_euler_bernoulli": fwd(s_e),
    }


def evaluate_claims(metrics, spectral, fig6, band) -> list[dict]:
    """The seven claims (``claim``, ``holds``, ``numbers``), decided as in the main report."""
    return _claims(metrics, spectral, fig6, band)
