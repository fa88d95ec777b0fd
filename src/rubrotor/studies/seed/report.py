"""Report blocks of the settled seed study (rendered by :func:`rubrotor.studies.seed.reproduce._render`).

The lead (verdicts under both formulations, the explanation from
``rubrotor/templates/seed_study.md`` filled with numbers of the run, the robustness table) and
the sections on the seed-form runs, contact stability and rub detection. Every number comes
from the summary of the run.
"""

from __future__ import annotations

import math
from importlib import resources

__all__ = ["lead_blocks", "seed_form_blocks", "stability_blocks", "detection_blocks"]

RADIAL0 = "radial, mu = 0"
ISO0 = "isotropic, mu = 0"


def _verdict(c: dict) -> str:
    return "holds" if c["holds"] else "does not hold"


def _row(table: list, eps0: float, bh: float) -> dict:
    return next(r for r in table if r["eps0_m"] == eps0 and r["bh_nd"] == bh)["results"]


def _status(m: dict) -> str:
    if m["status"] == "complete":
        return f"stays bounded over {m['revolutions']:.0f} revolutions"
    return f"diverges after {m['revolutions']:.1f} revolutions"


def _status_abm(a: dict) -> str:
    if a["status"] == "complete":
        return f"stays bounded over its {a['revolutions']:.0f} revolutions"
    return f"diverges after {a['revolutions']:.1f} revolutions"


def _explanation(s: dict) -> list:
    x = s["seed_study"]
    sf = x["seed_form"]
    r1, r2 = _row(x["stability"], 1e-4, 1e2), _row(x["stability"], 1e-4, 1e3)
    mu_key = next(k for k in r1 if k.startswith("two-field/radial") and k != f"two-field/{RADIAL0}")
    c1 = sf["cases"]["case1"]
    vals = {
        "unbalance": f"{s['unbalance_kg_m']:g}",
        "friction": s["settings"]["friction_sign"],
        "n_two": sum(c["holds"] for c in s["claims"]),
        "n_seed": sum(c["holds"] for c in sf["claims"]),
        "f_seed": r1[f"seed-eq1/{RADIAL0}"]["frequency_hz"],
        "g_seed_1e2": r1[f"seed-eq1/{RADIAL0}"]["growth_per_s"],
        "g_seed_1e3": r2[f"seed-eq1/{RADIAL0}"]["growth_per_s"],
        "ratio": r2[f"seed-eq1/{RADIAL0}"]["growth_per_s"]
        / r1[f"seed-eq1/{RADIAL0}"]["growth_per_s"],
        "g_two_1e2": r1[f"two-field/{RADIAL0}"]["growth_per_s"],
        "seed_case1_status": _status(c1),
        "seed_case1_share": c1["last_third"]["band_share"],
        "seed_case1_peak": c1["last_third"]["peak_hz"],
        "g_iso": r1[f"seed-eq1/{ISO0}"]["growth_per_s"],
        "f_iso": r1[f"seed-eq1/{ISO0}"]["frequency_hz"],
        "g_iso_two": r1[f"two-field/{ISO0}"]["growth_per_s"],
        "mu": mu_key.split("= ")[-1],
        "f_two_mu": r1[mu_key]["frequency_hz"],
        "g_two_mu": r1[mu_key]["growth_per_s"],
        "g_two_mu_damped": x["friction_damped"]["growth_per_s"],
        "n_strong": sum(c["holds"] for c in sf["strong"]["claims"]),
        "strong_factor": f"{sf['strong']['unbalance_factor']:g}",
        "strong_status": _status(sf["strong"]["cases"]["case1"]),
        "strong_share": sf["strong"]["cases"]["case1"]["last_third"]["band_share"],
        "strong_peak": sf["strong"]["cases"]["case1"]["last_third"]["peak_hz"],
        "strong_abm": _status_abm(sf["strong"]["abm"]["case1"]),
    }
    text = resources.files("rubrotor").joinpath("templates/seed_study.md").read_text()
    return [("p", para.strip().format(**vals)) for para in text.split("\n\n") if para.strip()]


def lead_blocks(s: dict) -> list:
    """Verdicts under both formulations, the explanation and the robustness table."""
    x = s["seed_study"]
    sf = x["seed_form"]
    b: list = [("h2", "Verdicts: the seed's claims under our model and under the seed's equations")]
    strong = sf["strong"]
    rows = [
        [
            c["claim"],
            _verdict(c),
            _verdict(d),
            _verdict(e),
            c["numbers"],
            d["numbers"],
            e["numbers"],
        ]
        for c, d, e in zip(s["claims"], sf["claims"], strong["claims"], strict=True)
    ]
    b.append(
        (
            "table",
            [
                "seed claim",
                "two-field (ours)",
                "seed eq. (1) form",
                f"seed eq. (1), unbalance x{strong['unbalance_factor']:g}",
                "measured, two-field",
                "measured, seed eq. (1)",
                f"measured, seed eq. (1), unbalance x{strong['unbalance_factor']:g}",
            ],
            rows,
        )
    )
    b += _explanation(s)
    b += robustness_blocks(s)
    return b


def robustness_blocks(s: dict) -> list:
    """The claim-robustness table (or how to get it)."""
    rob = s["seed_study"]["robustness"]
    b: list = [("h2", "Claim robustness over the assumptions the seed leaves open")]
    if rob is None:
        b.append(
            (
                "p",
                "Not run: `rubrotor reproduce --full` evaluates every claim over unbalance, "
                "modal damping, initial state, friction sign and formulation (a few minutes).",
            )
        )
        return b
    st = rob["settings"]
    b.append(
        (
            "p",
            f"{len(rob['rows'])} configurations: formulation {' / '.join(st['formulations'])} x "
            f"unbalance {' / '.join(f'{f:g}' for f in st['unbalance_factors'])} x "
            f"{s['unbalance_kg_m']:g} kg m x modal damping "
            f"{' / '.join(f'{z:g}' for z in st['damping'])} x initial state "
            f"{' / '.join(st['initial'])} x friction sign {' / '.join(st['friction_signs'])}; "
            f"each: cases 1-3, no contact and the Fig. 6 pair, {st['revolutions']:g} revolutions "
            f"({'fixed d tau = ' + format(st['dtau'], 'g') if st['dtau'] else 'adaptive'}), claims "
            "decided as above. 'with contact': configurations where it holds and all three cases "
            "touch the stator; 'diverged': of those, case 1 diverged.",
        )
    )
    rows = []
    for e in rob["summary"]:
        cells = [e["claim"]]
        for form in st["formulations"]:
            f = e[form]
            cells.append(
                f"{f['holds']}/{f['of']} (with contact {f['with_contact']}, diverged "
                f"{f['case1_diverged']}); {f['conditions']}"
            )
        rows.append(cells)
    b.append(("table", ["seed claim", *[f"holds in: {f}" for f in st["formulations"]]], rows))
    if len(st["formulations"]) == 2:
        f0, f1 = st["formulations"]
        diff = [
            f"'{e['claim'].split(' (')[0].split(':')[0]}': {e[f0]['holds']} vs {e[f1]['holds']}"
            for e in rob["summary"]
            if e[f0]["holds"] != e[f1]["holds"]
        ]
        b.append(
            (
                "p",
                f"Configurations where a claim holds, {f0} vs {f1} (of {rob['summary'][0][f0]['of']} "
                "each): " + "; ".join(diff) + ".",
            )
        )
    return b


def seed_form_blocks(s: dict) -> list:
    """Seed-form cases: metrics, engine vs ABM, CWT maps."""
    sf = s["seed_study"]["seed_form"]
    b: list = [("h2", "The seed study under the seed's equations (formulation seed-eq1)")]
    b.append(
        (
            "p",
            f'Same scenarios, shaft.formulation = "seed-eq1", d tau = 0.001, '
            f"{sf['settings']['seed_revolutions']:g} revolutions with our exponential engine; the "
            f"seed's ABM scheme over {sf['settings']['abm_revolutions']:g} revolutions for "
            "comparison (max |P_ABM - P_engine| / max |P_engine| over the common span).",
        )
    )
    rows = []
    for key, m in sf["cases"].items():
        a = sf["abm"][key]
        lt = m["last_third"]
        rows.append(
            [
                key,
                _status(m),
                f"{m['contact_fraction']:.3g}",
                f"{m['max_normal_force_N']:.3g}",
                f"{m['spectral']['shear1_band_share']:.3g}",
                f"{m['spectral']['shear1_ratio_to_no_contact']:.3g}",
                f"{lt['peak_hz']:.0f}" if math.isfinite(lt["peak_hz"]) else "-",
                f"{a['status']} ({a['revolutions']:.1f} rev), diff {a['max_rel_diff']:.2e}",
            ]
        )
    b.append(
        (
            "table",
            [
                "case",
                "engine run",
                "contact fraction",
                "max F_n (N)",
                "band share (late half)",
                "band vs no contact",
                "last-third peak (Hz, signed)",
                "ABM",
            ],
            rows,
        )
    )
    b.append(
        ("img", "fig7_cwt_maps.png", "Two-field model (ours): CWT maps of cases 1-3 and no contact")
    )
    b.append(
        (
            "img",
            "fig7_cwt_maps_seed_eq1.png",
            "Seed eq. (1) form, same runs: CWT maps (own colour scale)",
        )
    )
    strong = sf["strong"]
    rows = []
    for key, m in strong["cases"].items():
        lt = m["last_third"]
        rows.append(
            [
                key,
                _status(m),
                f"{lt['band_share']:.3g}" if math.isfinite(lt["band_share"]) else "-",
                f"{lt['peak_hz']:.0f}" if math.isfinite(lt["peak_hz"]) else "-",
                _status_abm(strong["abm"][key]),
            ]
        )
    b.append(
        (
            "table",
            [
                f"case, unbalance x{strong['unbalance_factor']:g}",
                "engine run",
                "last third: share in 19.6-25.5 kHz",
                "last third: peak (Hz, signed)",
                "seed's ABM",
            ],
            rows,
        )
    )
    b.append(
        (
            "img",
            "fig7_cwt_maps_seed_eq1_strong.png",
            f"Seed eq. (1) form with {strong['unbalance_factor']:g} x the unbalance: CWT maps "
            "(contact runs shown up to the first |P| = 10 g, before the blow-up; own colour scale)",
        )
    )
    return b


def stability_blocks(s: dict) -> list:
    """Stability table (both formulations, radial and isotropic) and the growth figure."""
    x = s["seed_study"]
    b: list = [("h2", "Linear stability of a pressed contact (mode 1)")]
    keys = list(x["stability"][0]["results"])
    rows = []
    for r in x["stability"]:
        cells = [f"{r['eps0_m']:g}", f"{r['bh_nd']:g}"]
        for k in keys:
            v = r["results"][k]
            cells.append(f"{v['growth_per_s']:+.3g} at {v['frequency_hz']:.0f} Hz")
        rows.append(cells)
    b.append(("table", ["eps0 (m)", "b_h'", *keys], rows))
    b.append(
        (
            "p",
            "Largest real part of the eigenvalues (1/s) of rotor + linearised contact at "
            "1.5x the first critical, k_h' = 1e3, and the signed whirl frequency of that "
            "eigenvalue (negative = backward). 'radial': the Jacobian of the contact law; "
            "'isotropic': stiffness and damping on both deflection components (model-notes "
            "section 6). `rubrotor stability SCENARIO --indentation M` prints the full spectrum.",
        )
    )
    b.append(
        (
            "img",
            "stability_growth.png",
            "Largest growth rate against b_h' for both formulations (solid mu = 0, dashed with "
            "the cases' friction), and the frequency of that eigenvalue",
        )
    )
    return b


def detection_blocks(s: dict) -> list:
    """The rub-detection table."""
    det = s["seed_study"]["detection"]
    st = det["settings"]
    runs = det["runs"]
    n_rub = sum(r["class"] == "rub" for r in runs)
    b: list = [("h2", "Rub detection on a realistic machine, with measurement noise")]
    b.append(
        (
            "p",
            f"Two-field model, physical friction, case-1 contact, modal damping {st['damping']:g}, "
            f"started on the steady no-contact orbit; unbalance "
            f"{' / '.join(format(f, 'g') for f in st['unbalance_factors'])} x the shipped value and "
            f"static radial loads {' / '.join(format(f, 'g') for f in st['loads'])} N: "
            f"{len(runs)} runs of {st['revolutions']:g} revolutions, {n_rub} rub (contact in the "
            f"second half), {len(runs) - n_rub} do not. White noise on every channel at the "
            f"stated SNR, {st['realisations']} realisations per run. Margin = log10 of the gap "
            "between the classes over all runs and realisations (decades; > 0: one threshold "
            "separates every rub from every no-rub measurement).",
        )
    )
    labels = list(det["table"][0]["snr"])
    rows = []
    for t in det["table"]:
        cells = [t["indicator"]]
        for lab in labels:
            v = t["snr"].get(lab)
            cells.append(
                "-"
                if v is None
                else f"{v['margin_decades']:+.2f} ({v['direction']}; medians "
                f"{v['median_rub']:.2g} / {v['median_no_rub']:.2g})"
            )
        rows.append(cells)
    b.append(("table", ["indicator", *[f"margin, {lab}" for lab in labels]], rows))
    b.append(("p", _detection_reading(det["table"], labels)))
    return b


def _detection_reading(table: list, labels: list) -> str:
    """One sentence per noise level: which indicators separate the classes."""
    parts = []
    for lab in labels:
        ok = [
            t["indicator"].split(" (")[0].split(",")[0]
            for t in table
            if t["snr"].get(lab, {}).get("margin_decades", -1) > 0
        ]
        parts.append(f"{lab}: {', '.join(ok) if ok else 'none'}")
    text = (
        "Indicators that separate every rub from every no-rub measurement, "
        + "; ".join(parts)
        + "."
    )
    bursts = next((t for t in table if t["key"] == "impacts_per_rev"), None)
    if bursts and all(v["median_rub"] == 0 for v in bursts["snr"].values()):
        text += (
            " The burst counter (threshold median + 6 MAD on the acceleration without its 1X "
            "part) finds no bursts even without noise: in this damped machine the partial rub is "
            "a smooth once-per-revolution contact, not an impact train, so impacts per "
            "revolution can only be read from a contact sensor (the simulation counts "
            "them exactly)."
        )
    return text
