"""Claim robustness: every seed claim over the assumptions the seed leaves open.

A configuration is one choice of formulation, unbalance (a factor on the shipped scenarios'
value), modal damping ratio, initial state and friction sign. For each, cases 1-3, the
no-contact run and the Fig. 6 pair are simulated (adaptive exponential integrator, output
``revolutions x samples_per_rev``) and the seven claims decided exactly as in the main report
(:mod:`rubrotor.studies.seed.claims`). Configurations run on the sweep machinery
(:func:`rubrotor.sweeps.sweep.map_tasks`: local processes or Dask).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import asdict, dataclass

from rubrotor.engine.settings import Integrator

__all__ = ["RobustnessSettings", "FULL_GRID", "QUICK_GRID", "configurations", "evaluate", "run"]

FACTORS = ("formulation", "unbalance_factor", "damping", "initial", "friction_sign")


@dataclass(frozen=True)
class RobustnessSettings:
    """The grid of assumptions and the run length.

    Attributes
    ----------
    formulations : tuple of str
        Shaft formulations.
    unbalance_factors : tuple of float
        Multiples of the shipped unbalance (1.5e-3 kg m).
    damping : tuple of float
        Modal damping ratios (dimensionless).
    initial : tuple of str
        ``"rest"`` and/or ``"steady"``.
    friction_signs : tuple of str
        ``"physical"`` and/or ``"seed"``.
    revolutions : float
        Length of each case run (rev); the claims read the second half.
    samples_per_rev : int
        Output samples per revolution (118 kHz at 64: resolves the 20-34 kHz shear bands).
    fig6_revolutions : float
        Length of the Fig. 6 runs (rev).
    dtau : float or None
        Fixed step (rad of spin; the seed's 0.001) of the exponential integrator, saving about
        ``samples_per_rev`` samples per revolution; None: the adaptive integrator.
    """

    formulations: tuple = ("two-field", "seed-eq1")
    unbalance_factors: tuple = (0.5, 0.75, 1.0, 1.5, 2.0, 3.0)
    damping: tuple = (0.0, 1e-3, 1e-2)
    initial: tuple = ("rest", "steady")
    friction_signs: tuple = ("physical", "seed")
    revolutions: float = 300
    samples_per_rev: int = 64
    fig6_revolutions: float = 20
    dtau: float | None = 1e-3


FULL_GRID = RobustnessSettings()
QUICK_GRID = RobustnessSettings(
    unbalance_factors=(1.0,),
    damping=(0.0,),
    initial=("rest",),
    friction_signs=("physical",),
    revolutions=30,
    fig6_revolutions=5,
)


def configurations(st: RobustnessSettings) -> list[dict]:
    """One task dict per configuration (the grid of ``st``), numbered by ``key``."""
    grid = itertools.product(
        st.formulations, st.unbalance_factors, st.damping, st.initial, st.friction_signs
    )
    base = {
        "revolutions": st.revolutions,
        "samples_per_rev": st.samples_per_rev,
        "fig6_revolutions": st.fig6_revolutions,
        "dtau": st.dtau,
    }
    return [
        dict(zip(FACTORS, values, strict=True)) | base | {"key": i} for i, values in enumerate(grid)
    ]


def evaluate(task: dict) -> dict:
    """Simulate one configuration and decide the seven claims (a worker function).

    Parameters
    ----------
    task : dict
        A configuration from :func:`configurations`.

    Returns
    -------
    dict
        ``{"key", "config", "holds": [bool x 7], "claims": [short names], "regimes": {case:
        label}, "shear1_share_case1", "band_ratio": [x3]}``.
    """
    from rubrotor.engine.simulate import simulate
    from rubrotor.studies.seed.cases import CASES, regime
    from rubrotor.studies.seed.claims import (
        band_of,
        case_numbers,
        evaluate_claims,
        fig6_numbers,
        seed_scenarios,
    )

    scen = seed_scenarios(
        **{
            "shaft.formulation": task["formulation"],
            "unbalance.magnitude_factor": task["unbalance_factor"],
            "damping.ratio": task["damping"],
            "initial.state": task["initial"],
            "contact.friction_sign": task["friction_sign"],
        }
    )
    if task["dtau"] is None:
        integ = Integrator(
            revolutions=task["revolutions"], output_dtau=2 * math.pi / task["samples_per_rev"]
        )
    else:
        every = max(1, round(2 * math.pi / task["dtau"] / task["samples_per_rev"]))
        integ = Integrator(revolutions=task["revolutions"], dtau=task["dtau"], save_every=every)
    results = {k: simulate(scen[k], integrator=integ, progress=False) for k, _, _ in CASES}
    entries, band = band_of(scen["case1"])
    metrics, spectral = case_numbers(results, scen, entries, band)
    i6 = Integrator(revolutions=task["fig6_revolutions"], dtau=1e-3, save_every=16)
    d_t = simulate(scen["fig6_t"], integrator=i6, progress=False)
    d_e = simulate(scen["fig6_e"], integrator=i6, progress=False)
    fig6 = fig6_numbers(scen["fig6_t"], scen["fig6_e"], d_t, d_e, task["fig6_revolutions"])
    claims = evaluate_claims(metrics, spectral, fig6, band)
    return {
        "key": task["key"],
        "config": {k: task[k] for k in FACTORS},
        "holds": [bool(c["holds"]) for c in claims],
        "claims": [c["claim"] for c in claims],
        "regimes": {k: regime(metrics[k]) for k, _, _ in CASES if k != "no_contact"},
        "shear1_share_case1": spectral["case1"]["shear1_band_share"],
        "band_ratio": [
            spectral[k]["shear1_ratio_to_no_contact"] for k in ("case1", "case2", "case3")
        ],
    }


def conditions(rows: list[dict], claim: int, st: RobustnessSettings) -> str:
    """Where claim ``claim`` holds, in words: the factor levels common to every holding row."""
    hold = [r for r in rows if r["holds"][claim]]
    if not hold:
        return "never"
    if len(hold) == len(rows):
        return "always"
    levels = {
        "unbalance_factor": st.unbalance_factors,
        "damping": st.damping,
        "initial": st.initial,
        "friction_sign": st.friction_signs,
    }
    parts = []
    for f, allowed in levels.items():
        seen = sorted({r["config"][f] for r in hold}, key=list(allowed).index)
        if len(seen) < len(allowed):
            parts.append(f"{f.replace('_', ' ')} {' or '.join(str(x) for x in seen)}")
    return "only with " + "; ".join(parts) if parts else "some of every level (no single factor)"


def summarise(rows: list[dict], st: RobustnessSettings) -> list[dict]:
    """Per claim and formulation: configurations where it holds, of how many, how many of those
    have contact in all three cases and a diverged case 1, and the conditions."""
    rows = sorted(rows, key=lambda r: r["key"])
    out = []
    for i, claim in enumerate(rows[0]["claims"]):
        entry = {"claim": claim}
        for form in st.formulations:
            sub = [r for r in rows if r["config"]["formulation"] == form]
            hold = [r for r in sub if r["holds"][i]]
            entry[form] = {
                "holds": len(hold),
                "of": len(sub),
                "with_contact": sum(
                    all(v != "no contact" for v in r["regimes"].values()) for r in hold
                ),
                "case1_diverged": sum(r["regimes"]["case1"] == "diverged" for r in hold),
                "conditions": conditions(sub, i, st),
            }
        out.append(entry)
    return out


def run(
    st: RobustnessSettings = FULL_GRID,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
) -> dict:
    """Run the robustness study.

    Parameters
    ----------
    st : RobustnessSettings
        Grid and run lengths.
    workers : int, optional
        Local worker processes (default: all cores).
    scheduler : str, optional
        Dask scheduler address.

    Returns
    -------
    dict
        ``{"settings", "rows" (one per configuration), "summary" (per claim)}``.
    """
    from rubrotor.sweeps.sweep import map_tasks

    rows = list(map_tasks(evaluate, configurations(st), workers=workers, scheduler=scheduler))
    rows.sort(key=lambda r: r["key"])
    return {"settings": asdict(st), "rows": rows, "summary": summarise(rows, st)}
