"""The seed's seven claims evaluated on one set of runs (cases 1-3, no contact, the Fig. 6 pair).

Shared by the main reproduction under the seed's equations and by every configuration of the
robustness study, so that a claim is measured the same way everywhere
(:func:`evaluate_claims` decides it).
"""

from __future__ import annotations

import numpy as np

from rubrotor.analysis.overview import mode_entries
from rubrotor.linear.verbs import modes
from rubrotor.studies.seed.cases import (
    CASES,
    PERIOD_TOL,
    case_metrics,
    seed_scenario,
    shear1_band,
    spectral_numbers,
)

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
        sc = seed_scenario(stem)
        ch = {k: v for k, v in changes.items() if sc.contact is not None or "contact." not in k}
        if not key.startswith("fig6") and sc.unbalance is not None:
            ch["unbalance.magnitude"] = sc.unbalance.magnitude * factor
        out[key] = sc.with_changes(**ch) if ch else sc
    return out


def band_of(scenario) -> tuple[list, tuple]:
    """Mode entries ``(label, Hz, whirl)`` at the scenario speed and the mode-1 shear band (Hz)."""
    entries = mode_entries(modes(scenario, scenario.speed))
    return entries, shear1_band(entries)


def case_numbers(results: dict, scen: dict, entries, band) -> tuple[dict, dict]:
    """``case_metrics`` and band energies of each case Dataset (as :mod:`rubrotor.studies.seed.reproduce`)."""
    metrics, spectral = {}, {}
    for key, _stem, _title in CASES:
        ds = results[key]
        c = scen[key].contact
        metrics[key] = case_metrics(ds, c.clearance if c else None)
        spectral[key] = spectral_numbers(ds, entries, band)
    nc = spectral["no_contact"]["shear1_band_energy"]
    for sp in spectral.values():
        sp["shear1_ratio_to_no_contact"] = sp["shear1_band_energy"] / nc if nc > 0 else float("inf")
    return metrics, spectral


def fig6_numbers(s_t, s_e, d_t, d_e, revolutions: float) -> dict:
    """The Fig. 6 comparison numbers (relative difference, forward bending frequencies)."""
    rel = {}
    for var in ("v", "w"):
        a, b = d_t[var].values[0], d_e[var].values[0]  # the contact station
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
        "max_w_m": float(np.max(np.abs(d_t["w"].values[0]))),
        "forward_bending_hz_timoshenko": fwd(s_t),
        "forward_bending_hz_euler_bernoulli": fwd(s_e),
    }


def evaluate_claims(metrics, spectral, fig6, band) -> list[dict]:
    """The seven claims (``claim``, ``holds``, ``numbers``), as every report decides them."""
    m1, m2, m3 = metrics["case1"], metrics["case2"], metrics["case3"]
    s = spectral
    rows = []
    hardest = m1["contact_fraction"] > max(m2["contact_fraction"], m3["contact_fraction"]) and m1[
        "mean_normal_force_N"
    ] > max(m2["mean_normal_force_N"], m3["mean_normal_force_N"])
    rows.append(
        {
            "claim": "Case 1 rubs hardest (seed Fig. 3, 7a)",
            "holds": bool(hardest),
            "numbers": (
                f"late contact fraction {m1['contact_fraction']:.3f} / "
                f"{m2['contact_fraction']:.3f} / {m3['contact_fraction']:.3f}; mean normal "
                f"force {m1['mean_normal_force_N']:.3g} / {m2['mean_normal_force_N']:.3g} / "
                f"{m3['mean_normal_force_N']:.3g} N (cases 1/2/3)"
            ),
        }
    )
    per = m2["poincare"]
    rows.append(
        {
            "claim": "Case 2 settles into periodic impacts in steady state (seed Fig. 4)",
            "holds": bool(m2["contact_fraction"] > 0 and per["period"] is not None),
            "numbers": (
                f"contact fraction {m2['contact_fraction']:.3f}, "
                f"{m2['impacts_per_rev']:.2f} impacts/rev; Poincare (once per rev, last "
                f"{per['samples']} rev): best k = {per['best_k']} with residual "
                f"{per['best_residual']:.3f} of max |P| (period accepted below "
                f"{PERIOD_TOL})"
            ),
        }
    )
    rows.append(
        {
            "claim": "Case 3's contact force is lower than case 2's (seed Fig. 5e)",
            "holds": bool(m3["max_normal_force_N"] < m2["max_normal_force_N"]),
            "numbers": (
                f"late max normal force {m3['max_normal_force_N']:.3g} N (case 3) vs "
                f"{m2['max_normal_force_N']:.3g} N (case 2); mean "
                f"{m3['mean_normal_force_N']:.3g} vs {m2['mean_normal_force_N']:.3g} N"
            ),
        }
    )
    r = [s[k]["shear1_ratio_to_no_contact"] for k in ("case1", "case2", "case3")]
    pk = [s[k]["shear1_peak_hz"] for k in ("case1", "case2", "case3")]
    in_band = all(band[0] * 0.97 <= abs(p) <= band[1] * 1.03 for p in pk)
    rows.append(
        {
            "claim": (
                "Rubbing excites a band near 20 kHz that the no-contact run lacks: the shear "
                "branch of mode 1"
            ),
            "holds": bool(min(r) > 10 and in_band),
            "numbers": (
                f"acceleration energy in {band[2] / 1e3:.1f}-{band[3] / 1e3:.1f} kHz vs "
                f"no contact: x{r[0]:.3g} / x{r[1]:.3g} / x{r[2]:.3g} (cases 1/2/3); "
                f"strongest line there at {abs(pk[0]) / 1e3:.2f} / {abs(pk[1]) / 1e3:.2f} / "
                f"{abs(pk[2]) / 1e3:.2f} kHz ({'forward' if pk[0] > 0 else 'backward'} in "
                f"case 1); mode-1 shear branch {band[0] / 1e3:.2f} (B) - "
                f"{band[1] / 1e3:.2f} (F) kHz"
            ),
        }
    )
    share = [s[k]["shear1_band_share"] for k in ("case1", "case2", "case3")]
    rows.append(
        {
            "claim": (
                "In case 1 the ~20 kHz band dominates the acceleration (seed: 'no other "
                "frequency rather than the 20 kHz appears')"
            ),
            "holds": bool(share[0] > 0.5),
            "numbers": (
                f"share of the acceleration mean square in the band: {share[0]:.3g} / "
                f"{share[1]:.3g} / {share[2]:.3g} (cases 1/2/3)"
            ),
        }
    )
    rows.append(
        {
            "claim": "The rub band carries more energy in case 3 than in case 2 (seed Fig. 7b, c)",
            "holds": bool(s["case3"]["shear1_band_energy"] > s["case2"]["shear1_band_energy"]),
            "numbers": (
                f"band energy {s['case3']['shear1_band_energy']:.3g} vs "
                f"{s['case2']['shear1_band_energy']:.3g} (m/s^2)^2 (case 3 vs case 2)"
            ),
        }
    )
    rows.append(
        {
            "claim": "The Timoshenko model matches Euler-Bernoulli for a slender shaft (Fig. 6)",
            "holds": bool(max(fig6["max_rel_diff_v"], fig6["max_rel_diff_w"]) < 0.05),
            "numbers": (
                f"r = {fig6['slenderness']:g}, {fig6['revolutions']:g} rev: max |w_T - w_EB| "
                f"/ max |w| = {fig6['max_rel_diff_w']:.2e}, same for v "
                f"{fig6['max_rel_diff_v']:.2e}; first forward bending frequency "
                f"{fig6['forward_bending_hz_timoshenko'][1]:.7g} vs "
                f"{fig6['forward_bending_hz_euler_bernoulli'][1]:.7g} Hz"
            ),
        }
    )
    return rows
