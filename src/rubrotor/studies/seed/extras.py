"""The parts of ``rubrotor reproduce`` added by the settled seed study: the seed's equations,
contact stability, rub detection and (with ``--full``) claim robustness.

:func:`run_extras` is called by :func:`rubrotor.studies.seed.reproduce.reproduce` after its own runs; it
writes its figures into the output directory and returns the JSON-ready part of the summary.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

__all__ = ["ExtraSettings", "EXTRA_DEFAULT", "EXTRA_QUICK", "run_extras"]


@dataclass(frozen=True)
class ExtraSettings:
    """Run lengths of the added parts.

    Attributes
    ----------
    seed_revolutions : float
        Seed-form case runs with the engine (rev).
    abm_revolutions : float
        Seed-form case runs with the seed's ABM (rev), compared with the engine.
    curve_points : int
        Points of the growth-rate curves.
    strong_factor : float
        Unbalance factor of the second seed-form set (the seed gives no unbalance).
    """

    seed_revolutions: float = 300
    abm_revolutions: float = 60
    curve_points: int = 41
    strong_factor: float = 2.0


EXTRA_DEFAULT = ExtraSettings()
EXTRA_QUICK = ExtraSettings(seed_revolutions=40, abm_revolutions=10, curve_points=9)


def _progress(msg: str, t0: float, quiet: bool) -> None:
    if not quiet:
        import sys

        print(f"[{time.perf_counter() - t0:6.1f} s] {msg}", file=sys.stderr, flush=True)


def _savefig(fig, path: Path) -> None:
    from rubrotor.engine.result import atomic_write

    atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=110))


def run_extras(
    out: Path,
    scen: dict,
    *,
    entries,
    band,
    freqs,
    spin_hz: float,
    save_every: int,
    quick: bool,
    full: bool,
    workers: int | None = None,
    scheduler: str | None = None,
    quiet: bool = False,
    t0: float | None = None,
) -> dict:
    """Run the seed-form study, the stability analysis, detection and (``full``) robustness.

    Parameters
    ----------
    out : Path
        Output directory (figures are written there).
    scen : dict
        The main cases ``{"case1", "case2", "case3", "no_contact"}``.
    entries, band, freqs
        Mode entries, mode-1 shear band and CWT frequencies (Hz) of the main study.
    spin_hz : float
        Spin frequency (Hz).
    save_every : int
        Output decimation of the seed-form runs (as the main runs).
    quick : bool
        Short runs (tests).
    full : bool
        Also run the robustness grid (:data:`rubrotor.studies.seed.robustness.FULL_GRID`) and the
        larger detection grid.
    workers, scheduler
        Sweep back end of the robustness grid (local processes or a Dask scheduler).
    quiet : bool
        No progress lines.
    t0 : float, optional
        ``time.perf_counter()`` at the start of the reproduction (progress lines).

    Returns
    -------
    dict
        ``seed_form`` (metrics, spectral, claims, fig6, abm comparison), ``stability``,
        ``growth_curves``, ``detection``, ``robustness`` (None without ``full``), ``timing_s``.
    """
    from rubrotor.studies.seed import detection, robustness

    t0 = time.perf_counter() if t0 is None else t0
    xs = EXTRA_QUICK if quick else EXTRA_DEFAULT
    timing = {}

    t = time.perf_counter()
    _progress(
        "the seed's equations (seed-eq1): cases 1-3 and no contact, engine and ABM", t0, quiet
    )
    seed_form = _seed_form_part(out, scen, xs, entries, band, freqs, spin_hz, save_every, quick)
    _progress(f"seed-eq1 with {xs.strong_factor:g} x the unbalance", t0, quiet)
    seed_form["strong"] = _strong_part(
        out, scen, xs, entries, band, freqs, spin_hz, save_every, seed_form["fig6"]
    )
    timing["seed_form"] = time.perf_counter() - t

    t = time.perf_counter()
    _progress("linear stability of a pressed contact, both formulations", t0, quiet)
    stability = _stability_part(out, scen["case1"], xs)
    timing["stability"] = time.perf_counter() - t

    t = time.perf_counter()
    _progress("rub detection with measurement noise", t0, quiet)
    dset = detection.QUICK if quick else (detection.DEFAULT if full else detection.LIGHT)
    det = detection.run(dset)
    timing["detection"] = time.perf_counter() - t

    rob = None
    if full:
        t = time.perf_counter()
        _progress("claim robustness grid (sweep machinery)", t0, quiet)
        grid = robustness.QUICK_GRID if quick else robustness.FULL_GRID
        rob = robustness.run(grid, workers=workers, scheduler=scheduler)
        timing["robustness"] = time.perf_counter() - t

    return {
        "seed_form": seed_form,
        **stability,
        "detection": det,
        "robustness": rob,
        "timing_s": timing,
    }


def _cwt_maps(results: dict, spectral: dict, freqs, label: str, clip=None) -> dict:
    """Binned CWT maps of each case's horizontal acceleration (``clip(key, ds, a)`` cuts it)."""
    from rubrotor.analysis.wavelet import cwt_binned
    from rubrotor.studies.seed.cases import CASES

    maps = {}
    for key, _stem, title in CASES:
        a = results[key]["v_ddot"].values[0]  # the contact station
        if clip is not None:
            a = clip(key, results[key], a)
        if a.size > 64:
            maps[f"{label}: {title}"] = cwt_binned(
                a, spectral[key]["fs_hz"], freqs, min(500, a.size)
            )
    return maps


def _save_maps(out: Path, maps: dict, entries, spin_hz: float, title: str, name: str) -> None:
    from rubrotor.plotting import signals as plotting

    fig = plotting.scalogram_map_figure(maps, modes=entries, spin_hz=spin_hz, title=title)
    _savefig(fig, out / name)


def _seed_form_part(out, scen, xs, entries, band, freqs, spin_hz, save_every, quick) -> dict:
    """Cases 1-3 and no contact under the seed's equations (engine and ABM), Fig. 6, claims."""
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate
    from rubrotor.studies.seed import seedform_study
    from rubrotor.studies.seed.cases import CASES
    from rubrotor.studies.seed.claims import (
        case_numbers,
        evaluate_claims,
        fig6_numbers,
        seed_scenarios,
    )

    runs = seedform_study.run_cases(scen, xs.seed_revolutions, save_every, xs.abm_revolutions)
    res = runs["results"]
    metrics, spectral = case_numbers(res, scen, entries, band)
    f6 = seed_scenarios()
    f6_rev = 5 if quick else 20
    s_t, d_t = seedform_study.fig6_seed(f6["fig6_t"], f6_rev)
    d_e = simulate(
        f6["fig6_e"],
        integrator=Integrator(revolutions=f6_rev, dtau=1e-3, save_every=16),
        progress=False,
    )
    fig6 = fig6_numbers(s_t, f6["fig6_e"], d_t, d_e, f6_rev)
    _save_maps(
        out,
        _cwt_maps(res, spectral, freqs, "seed eq. 1"),
        entries,
        spin_hz,
        "Seed eq. (1) form: CWT of the horizontal acceleration (max |W| per time bin)",
        "fig7_cwt_maps_seed_eq1.png",
    )
    return {
        "settings": asdict(xs),
        "cases": {
            k: metrics[k] | {"spectral": spectral[k], "last_third": _last_part_peak(res[k])}
            for k, _, _ in CASES
        },
        "abm": runs["abm"],
        "fig6": fig6,
        "claims": evaluate_claims(metrics, spectral, fig6, band),
    }


def _strong_part(out, scen, xs, entries, band, freqs, spin_hz, save_every, fig6) -> dict:
    """The seed's equations with ``xs.strong_factor`` times the unbalance."""
    from rubrotor.studies.seed import seedform_study
    from rubrotor.studies.seed.cases import CASES
    from rubrotor.studies.seed.claims import case_numbers, evaluate_claims

    strong_scen = {
        k: sc.with_changes(**{"unbalance.magnitude": sc.unbalance.magnitude * xs.strong_factor})
        for k, sc in scen.items()
    }
    s_runs = seedform_study.run_cases(
        strong_scen, xs.seed_revolutions, save_every, xs.abm_revolutions
    )
    s_metrics, s_spectral = case_numbers(s_runs["results"], strong_scen, entries, band)

    def onset(key, d, a):  # up to the first time |P| exceeds 10 g: the onset, not the blow-up
        c = strong_scen[key].contact
        if c is None:
            return a
        big = np.flatnonzero(np.hypot(d["v"].values[0], d["w"].values[0]) > 10 * c.clearance)
        return a[: big[0]] if big.size else a

    maps = _cwt_maps(
        s_runs["results"], s_spectral, freqs, f"seed eq. 1, x{xs.strong_factor:g}", onset
    )
    _save_maps(
        out,
        maps,
        entries,
        spin_hz,
        f"Seed eq. (1) form, {xs.strong_factor:g} x the unbalance: CWT of the horizontal "
        "acceleration (contact runs up to |P| = 10 g)",
        "fig7_cwt_maps_seed_eq1_strong.png",
    )
    return {
        "unbalance_factor": xs.strong_factor,
        "unbalance_kg_m": strong_scen["case1"].unbalance.magnitude,
        "cases": {
            k: s_metrics[k]
            | {"spectral": s_spectral[k], "last_third": _last_part_peak(s_runs["results"][k])}
            for k, _, _ in CASES
        },
        "abm": s_runs["abm"],
        "claims": evaluate_claims(s_metrics, s_spectral, fig6, band),
    }


def _stability_part(out: Path, base, xs) -> dict:
    """Pressed-contact stability table, growth-rate curves (figure) and the damped friction case."""
    from rubrotor.linear.stability import contact_stability
    from rubrotor.studies.seed import seedform_study

    table = seedform_study.stability_table(base)
    curves = seedform_study.growth_curves(base, n=xs.curve_points)
    damped = contact_stability(
        base.with_changes(**{"damping.ratio": 1e-3}), 1e-4, formulation="two-field", modes=1
    )
    _savefig(seedform_study.growth_figure(curves), out / "stability_growth.png")
    return {
        "stability": table,
        "growth_curves": {
            "bh_nd": curves["bh_nd"].tolist(),
            "eps0_m": curves["eps0_m"],
            "curves": {k: [g.tolist(), f.tolist()] for k, (g, f) in curves["curves"].items()},
        },
        "friction_damped": {
            "damping_ratio": 1e-3,
            "growth_per_s": damped.max_growth_rate,
            "frequency_hz": damped.dominant_frequency_hz,
        },
    }


def _last_part_peak(ds) -> dict:
    """Full-spectrum peak (signed Hz) and 19.6-25.5 kHz share of the last third's acceleration."""
    from rubrotor.analysis.overview import band_energy
    from rubrotor.analysis.spectra import full_spectrum

    n = ds["time"].size
    sl = slice(n - n // 3, n)
    av, aw = ds["v_ddot"].values[0, sl], ds["w_ddot"].values[0, sl]
    fs = 1.0 / float(ds["time"].values[1] - ds["time"].values[0])
    if av.size < 16:
        return {"peak_hz": math.nan, "band_share": math.nan}
    spec = full_spectrum(av, aw, fs)
    total = band_energy(av, fs, 0.0, fs / 2, w=aw)
    share = band_energy(av, fs, 19.6e3, 25.5e3, w=aw) / total if total > 0 else 0.0
    return {
        "peak_hz": float(spec.frequencies[int(np.argmax(spec.amplitudes))]),
        "band_share": float(share),
    }
