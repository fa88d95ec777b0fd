"""`rubrotor reproduce --quick`: files, claims table and the numbers behind it."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rubrotor import load_dataset
from rubrotor.cli import main, shipped_scenarios
from rubrotor.studies.seed.reproduce import CASES, case_metrics


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("repro")
    assert main(["reproduce", "--out", str(out), "--quick", "--quiet"]) == 0
    return out, json.loads((out / "summary.json").read_text())


def test_files(quick):
    out, _ = quick
    for key, _stem, _title in CASES:
        assert (out / key / "results.nc").is_file()
        assert (out / key / "response.png").stat().st_size > 20000
    for name in (
        "fig6_timoshenko_vs_euler_bernoulli.png",
        "fig7_cwt_maps.png",
        "fig7_scalograms.png",
        "campbell.png",
        "friction_sign.png",
        "fig7_cwt_maps_seed_eq1.png",
        "fig7_cwt_maps_seed_eq1_strong.png",
        "stability_growth.png",
        "report.md",
    ):
        assert (out / name).stat().st_size > 1000, name
    page = (out / "report.html").read_text()
    # self-contained: every figure embedded, nothing loaded from disk or network
    assert page.count("data:image/png;base64,") == 12
    assert 'src="http' not in page and '.png"' not in page
    md = (out / "report.md").read_text()
    # the verdict table: 7 claims x (two-field, seed form, seed form with a larger unbalance)
    verdicts = [ln for ln in md.splitlines() if ln.startswith("| ") and "| holds |" in ln + "|"]
    assert len(verdicts) >= 1
    head = md.split("## Verdicts", 1)[1].split("\n## ", 1)[0]
    rows = [ln for ln in head.splitlines() if ln.startswith("| ") and not ln.startswith("| seed")]
    assert len(rows) == 7
    assert all(ln.count("| holds |") + ln.count("| does not hold |") >= 1 for ln in rows)


def test_summary_matches_results(quick):
    out, s = quick
    assert s["settings"]["quick"] is True and s["settings"]["dtau"] == 1e-3
    assert s["spin_hz"] == pytest.approx(1848.38, rel=1e-4)
    assert s["shear1_band_hz"][0] == pytest.approx(20672, rel=1e-3)
    assert s["shear1_band_hz"][1] == pytest.approx(24253, rel=1e-3)
    for key, _stem, _title in CASES:
        ds = load_dataset(out / key / "results.nc")
        g = s["cases"][key]["clearance_m"]
        m = case_metrics(ds, g)
        c = s["cases"][key]
        assert c["contact_fraction"] == pytest.approx(m["contact_fraction"])
        assert c["max_normal_force_N"] == pytest.approx(m["max_normal_force_N"])
        assert c["poincare"]["best_k"] == m["poincare"]["best_k"]
        assert ds.attrs["scenario_name"] == f"seed_{key}" if key != "no_contact" else True
    assert s["cases"]["no_contact"]["contact_fraction"] == 0.0
    assert all(s["cases"][k]["contact_fraction"] > 0 for k in ("case1", "case2", "case3"))


def test_claims_numbers(quick):
    _, s = quick
    claims = {c["claim"].split(" (")[0].split(":")[0]: c for c in s["claims"]}
    c = s["cases"]
    hardest = claims["Case 1 rubs hardest"]
    assert hardest["holds"] == (
        c["case1"]["contact_fraction"]
        > max(c["case2"]["contact_fraction"], c["case3"]["contact_fraction"])
        and c["case1"]["mean_normal_force_N"]
        > max(c["case2"]["mean_normal_force_N"], c["case3"]["mean_normal_force_N"])
    )
    lower = claims["Case 3's contact force is lower than case 2's"]
    assert lower["holds"] == (c["case3"]["max_normal_force_N"] < c["case2"]["max_normal_force_N"])
    periodic = claims["Case 2 settles into periodic impacts in steady state"]
    assert periodic["holds"] == (c["case2"]["poincare"]["period"] is not None)
    # band-energy ratio near the mode-1 shear branch, case 1 vs no contact, as computed
    ratio = (
        c["case1"]["spectral"]["shear1_band_energy"]
        / c["no_contact"]["spectral"]["shear1_band_energy"]
    )
    assert c["case1"]["spectral"]["shear1_ratio_to_no_contact"] == pytest.approx(ratio)
    band = claims["Rubbing excites a band near 20 kHz that the no-contact run lacks"]
    assert band["holds"] == (
        min(c[k]["spectral"]["shear1_ratio_to_no_contact"] for k in ("case1", "case2", "case3"))
        > 10
        and band["holds"] in (True, False)
    )
    assert f"x{ratio:.3g}" in band["numbers"]
    # the Timoshenko and Euler-Bernoulli responses of a slender shaft agree closely
    f6 = s["fig6"]
    assert f6["max_rel_diff_w"] < 0.01 and f6["max_rel_diff_v"] < 0.01
    assert claims["The Timoshenko model matches Euler-Bernoulli for a slender shaft"]["holds"]


def test_sensitivity_and_friction(quick):
    _, s = quick
    rows = {(r["unbalance_factor"], r["damping_ratio"]): r for r in s["sensitivity"]}
    # halving the unbalance removes the contact, doubling it gives full annular rub
    assert all(rows[(0.5, 0.0)][k]["contact_fraction"] == 0 for k in ("case1", "case2", "case3"))
    assert all(
        rows[(2.0, 0.0)][k]["regime"] == "full annular rub" for k in ("case1", "case2", "case3")
    )
    other = s["friction_sign_comparison"]["other_runs"]
    assert s["friction_sign_comparison"]["other"] == "seed"
    assert set(other) == {"case1", "case2", "case3"}
    assert all(np.isfinite(o["max_orbit_whole_run_over_clearance"]) for o in other.values())


def test_scenarios_command(capsys):
    names = [s["name"] for s in shipped_scenarios()]
    for n in (
        "seed_case1",
        "seed_case2",
        "seed_case3",
        "seed_no_contact",
        "seed_fig6_timoshenko",
        "seed_fig6_euler_bernoulli",
    ):
        assert n in names
    assert main(["scenarios"]) == 0
    out = capsys.readouterr().out
    assert "seed_case2" in out and "g' = 3.5e-3" in out


def test_seed_study_sections(quick):
    """The seed-form part of the summary is what its own Datasets and functions give: claims
    under the seed's equations from the seed-form metrics, the explanation's numbers from the
    stability table (recomputed here with :func:`rubrotor.linear.stability.contact_stability`)."""
    from rubrotor.linear.stability import contact_stability
    from rubrotor.studies.seed.claims import seed_scenarios

    out, s = quick
    x = s["seed_study"]
    sf = x["seed_form"]
    assert len(sf["claims"]) == len(s["claims"]) == len(sf["strong"]["claims"]) == 7
    c = sf["cases"]
    hardest = sf["claims"][0]["holds"]
    assert hardest == (
        c["case1"]["contact_fraction"]
        > max(c["case2"]["contact_fraction"], c["case3"]["contact_fraction"])
        and c["case1"]["mean_normal_force_N"]
        > max(c["case2"]["mean_normal_force_N"], c["case3"]["mean_normal_force_N"])
    )
    # engine and the seed's ABM integrate the same seed-form equations
    assert all(a["max_rel_diff"] < 1e-4 for a in sf["abm"].values() if a["status"] == "complete")
    row = next(r for r in x["stability"] if r["eps0_m"] == 1e-4 and r["bh_nd"] == 1e2)
    ref = contact_stability(
        seed_scenarios()["case1"], 1e-4, formulation="seed-eq1", contact_damping_nd=1e2,
        modes=1, friction=False,
    )  # fmt: skip
    assert row["results"]["seed-eq1/radial, mu = 0"]["growth_per_s"] == pytest.approx(
        ref.max_growth_rate, rel=1e-9
    )
    md = (out / "report.md").read_text()
    assert f"{ref.max_growth_rate:+.3g} 1/s" in md
    assert "rubrotor reproduce --full" in md  # robustness not run in the default path
    det = x["detection"]
    assert {r["class"] for r in det["runs"]} == {"rub", "no rub"}
    assert all("no noise" in t["snr"] for t in det["table"])
