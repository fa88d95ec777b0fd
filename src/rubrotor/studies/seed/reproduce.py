r"""Reproduce the seed study end to end: ``rubrotor reproduce --out DIR``.

Runs the shipped seed scenarios (``seed_case1..3``, ``seed_no_contact``, the Fig. 6 pair
``seed_fig6_timoshenko`` / ``seed_fig6_euler_bernoulli``), measures what the seed claims, and
writes per case ``DIR/<case>/results.nc`` and ``response.png`` (seed Figs. 3-5), the Fig. 6
comparison, the Fig. 7 CWT maps and scalogram curves, the Campbell diagram, a friction-sign
study, an unbalance/damping sensitivity table, ``summary.json``, ``report.md`` and a
self-contained ``report.html``.

Every run starts from rest (the seed gives no initial state) and uses the seed's fixed step
``d tau = 0.001`` with the exponential integrator, saving every k-th step (363 kHz in the full run,
181 kHz with ``quick``), which resolves the 20-32 kHz shear branches without decimation. The
sensitivity runs use the default adaptive integrator (same physics, faster).

The report leads with the verdicts under both formulations: the same cases under the seed's own
eq. (1) form (``shaft.formulation = "seed-eq1"``, also with a larger unbalance), the linear
stability of a pressed contact that explains the difference, and a rub-detection table
(:mod:`rubrotor.studies.seed`). ``full=True`` (``rubrotor reproduce --full``) adds the claim-robustness
grid over unbalance, damping, initial state, friction sign and formulation.
"""

from __future__ import annotations

import base64
import dataclasses
import html
import json
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rubrotor.analysis.overview import mode_entries
from rubrotor.analysis.wavelet import cwt_binned, inner_scalogram, log_frequencies, scalogram
from rubrotor.engine.result import atomic_write, save_dataset
from rubrotor.engine.settings import Integrator
from rubrotor.engine.simulate import simulate
from rubrotor.linear.verbs import critical_speeds, modes
from rubrotor.scenario.load import Scenario
from rubrotor.studies.seed.cases import (
    CASES,
    TWO_PI,
    case_metrics,
    poincare_period,
    regime,
    seed_scenario,
    shear1_band,
    spectral_numbers,
)
from rubrotor.studies.seed.claims import evaluate_claims, fig6_numbers

__all__ = ["Settings", "FULL", "QUICK", "CASES", "reproduce", "case_metrics", "poincare_period"]


@dataclass(frozen=True)
class Settings:
    """Lengths and output rates of a reproduction.

    Attributes
    ----------
    revolutions : float
        Length of each case run (spin revolutions).
    save_every : int
        Saved sample = every k-th step of ``d tau = 0.001`` (``fs = Omega / (d tau k)``).
    fig6_revolutions : float
        Length of the Fig. 6 runs (revolutions of the slender shaft).
    sensitivity_revolutions : float
        Length of each sensitivity run (revolutions).
    sensitivity : tuple of (float, float)
        ``(unbalance factor, modal damping ratio)`` pairs of the sensitivity table; the factor
        multiplies the scenario unbalance.
    """

    revolutions: float = 300
    save_every: int = 32
    fig6_revolutions: float = 50
    sensitivity_revolutions: float = 300
    sensitivity: tuple = (
        (0.5, 0.0),
        (1.0, 0.0),
        (4 / 3, 0.0),
        (2.0, 0.0),
        (1.0, 3e-4),
        (4 / 3, 3e-4),
        (1.0, 0.005),
    )


FULL = Settings()
QUICK = Settings(
    revolutions=80,
    save_every=64,
    fig6_revolutions=20,
    sensitivity_revolutions=150,
    sensitivity=((0.5, 0.0), (1.0, 0.0), (2.0, 0.0)),
)
DTAU = 1e-3


def _progress(msg: str, t0: float, quiet: bool) -> None:
    if not quiet:
        print(f"[{time.perf_counter() - t0:6.1f} s] {msg}", file=sys.stderr, flush=True)


def _run(sc: Scenario, revolutions: float, save_every: int):
    integ = Integrator(revolutions=revolutions, dtau=DTAU, save_every=save_every)
    return simulate(sc, integrator=integ, progress=False)


def _savefig(fig, path: Path) -> Path:
    atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=110))
    return path


def _fmt(x, spec=".3g") -> str:
    if x is None:
        return "-"
    if isinstance(x, float) and not math.isfinite(x):
        return "inf"
    return format(x, spec)


# ---- report rendering -----------------------------------------------------------------------
def _render(blocks, out: Path) -> tuple[str, str]:
    """Markdown and self-contained HTML from a list of blocks."""
    md, body = [], []
    for b in blocks:
        kind = b[0]
        if kind in ("h1", "h2", "h3"):
            md.append("#" * int(kind[1]) + " " + b[1] + "\n")
            body.append(f"<{kind}>{html.escape(b[1])}</{kind}>")
        elif kind == "p":
            md.append(b[1] + "\n")
            body.append(f"<p>{html.escape(b[1])}</p>")
        elif kind == "ul":
            md.append("\n".join(f"- {x}" for x in b[1]) + "\n")
            body.append("<ul>" + "".join(f"<li>{html.escape(x)}</li>" for x in b[1]) + "</ul>")
        elif kind == "table":
            headers, rows = b[1], b[2]
            md.append("| " + " | ".join(h.replace("|", "\\|") for h in headers) + " |")
            md.append("|" + "---|" * len(headers))
            md += ["| " + " | ".join(str(c).replace("|", "\\|") for c in r) + " |" for r in rows]
            md.append("")
            th = "".join(f"<th>{html.escape(h)}</th>" for h in headers)
            trs = []
            for r in rows:
                tds = []
                for c in r:
                    c = str(c)
                    cls = (
                        ' class="ok"'
                        if c.startswith("holds")
                        else (' class="no"' if c.startswith("does not") else "")
                    )
                    tds.append(f"<td{cls}>{html.escape(c)}</td>")
                trs.append("<tr>" + "".join(tds) + "</tr>")
            body.append(f"<table><tr>{th}</tr>{''.join(trs)}</table>")
        elif kind == "img":
            rel, caption = b[1], b[2]
            md.append(f"![{caption}]({rel})\n\n*{caption}*\n")
            data = base64.b64encode((out / rel).read_bytes()).decode("ascii")
            body.append(
                f'<figure><img src="data:image/png;base64,{data}" alt="'
                f'{html.escape(caption)}"><figcaption>{html.escape(caption)}'
                "</figcaption></figure>"
            )
    style = (
        "body{font-family:sans-serif;max-width:1250px;margin:auto;padding:1em;line-height:1.4}"
        "table{border-collapse:collapse;margin:0.6em 0;font-size:0.9em}"
        "td,th{border:1px solid #bbb;padding:3px 7px;text-align:left;vertical-align:top}"
        "th{background:#eee}td.ok{background:#dff0d8}td.no{background:#f8d7da}"
        "img{max-width:100%;border:1px solid #ddd}figcaption{font-style:italic;color:#444}"
    )
    page = (
        "<!DOCTYPE html><html><head><meta charset='utf-8'><title>rubrotor: seed reproduction"
        f"</title><style>{style}</style></head><body>{''.join(body)}</body></html>"
    )
    return "\n".join(md), page


@dataclass(frozen=True)
class _Context:
    """What every part of a reproduction reads: settings, scenarios, modes, output folder."""

    out: Path
    st: Settings
    scen: dict
    entries: list
    band: tuple
    spin_hz: float
    main_sign: str
    other_sign: str
    t0: float
    quiet: bool

    def progress(self, msg: str) -> None:
        _progress(msg, self.t0, self.quiet)


def _case_scenarios(seed_friction: bool) -> dict:
    """The seed cases; cases 1-3 with the seed's friction sign when ``seed_friction``."""
    scen = {key: seed_scenario(stem) for key, stem, _ in CASES}
    if seed_friction:
        for key in ("case1", "case2", "case3"):
            src = scen[key].source
            scen[key] = dataclasses.replace(
                scen[key].with_changes(**{"contact.friction_sign": "seed"}),
                source=src.replace('friction_sign = "physical"', 'friction_sign = "seed"'),
            )
    return scen


def _run_cases(cx: _Context) -> tuple[dict, dict, dict]:
    """The four cases: results, ``case_metrics`` and band numbers; ``<case>/response.png``."""
    from rubrotor.plotting import runs as plotting

    st, out = cx.st, cx.out
    results, metrics, spectral = {}, {}, {}
    for key, _stem, title in CASES:
        cx.progress(f"simulate {title} ({st.revolutions:g} rev, d tau = {DTAU:g})")
        sc = cx.scen[key]
        ds = _run(sc, st.revolutions, st.save_every)
        results[key] = ds
        save_dataset(ds, out / key / "results.nc")
        g = sc.contact.clearance if sc.contact else None
        metrics[key] = case_metrics(ds, g)
        spectral[key] = spectral_numbers(ds, cx.entries, cx.band)
        fig = plotting.response_figure(
            ds,
            clearance=g,
            title=f"{title}: responses at midspan ({metrics[key]['revolutions']:.0f} rev from rest, "
            f"friction sign {sc.contact.friction_sign if sc.contact else '-'})",
        )
        _savefig(fig, out / key / "response.png")
    nc_e = spectral["no_contact"]["shear1_band_energy"]
    for key in spectral:
        e = spectral[key]["shear1_band_energy"]
        spectral[key]["shear1_ratio_to_no_contact"] = e / nc_e if nc_e > 0 else float("inf")
    return results, metrics, spectral


def _inner_peaks(in_: np.ndarray, freqs: np.ndarray, n: int = 6) -> list[float]:
    """Frequencies (Hz) of the ``n`` highest local maxima of an inner scalogram."""
    from scipy.signal import find_peaks

    idx, _ = find_peaks(np.concatenate([[0.0], in_, [0.0]]))
    idx = idx - 1
    idx = idx[np.argsort(in_[idx])[::-1]][:n]
    return [float(freqs[i]) for i in idx]


def _cwt_part(cx: _Context, results: dict, spectral: dict) -> np.ndarray:
    """CWT maps and scalograms of the horizontal acceleration (seed Fig. 7); the frequencies."""
    from rubrotor.plotting import signals as plotting

    cx.progress("CWT maps and scalograms of the acceleration")
    band, entries = cx.band, cx.entries
    fs = spectral["case1"]["fs_hz"]
    freqs = log_frequencies(300.0, min(0.4 * fs, 2.0 * max(f for _, f, _ in entries)), 120)
    maps, curves = {}, {}
    for key, _stem, title in CASES:
        a = results[key]["v_ddot"].values[0]  # the contact station
        maps[title] = cwt_binned(a, fs, freqs, 500)
        sc_, in_ = scalogram(a, fs, freqs), inner_scalogram(a, fs, freqs)
        curves[title] = (sc_, in_)
        j = (freqs >= band[2]) & (freqs <= band[3])
        spectral[key]["inner_scalogram_shear1_max"] = float(in_[j].max())
        spectral[key]["inner_scalogram_peaks_hz"] = _inner_peaks(in_, freqs)
    _savefig(
        plotting.scalogram_map_figure(
            maps,
            modes=entries,
            spin_hz=cx.spin_hz,
            title="CWT of the horizontal acceleration at midspan (seed Fig. 7): max |W| per time bin",
        ),
        cx.out / "fig7_cwt_maps.png",
    )
    _savefig(
        plotting.scalogram_curves_figure(
            freqs,
            curves,
            modes=entries,
            spin_hz=cx.spin_hz,
            title="Scalogram and inner scalogram of the horizontal acceleration",
        ),
        cx.out / "fig7_scalograms.png",
    )
    return freqs


def _fig6_part(cx: _Context) -> dict:
    """Timoshenko against Euler-Bernoulli for the slender shaft (seed Fig. 6)."""
    from rubrotor.plotting import runs as plotting

    cx.progress("Fig. 6: Timoshenko vs Euler-Bernoulli at r = 0.0013")
    out, revs = cx.out, cx.st.fig6_revolutions
    s_t, s_e = seed_scenario("seed_fig6_timoshenko"), seed_scenario("seed_fig6_euler_bernoulli")
    d_t = _run(s_t, revs, 16)
    d_e = _run(s_e, revs, 16)
    save_dataset(d_t, out / "fig6" / "timoshenko.nc")
    save_dataset(d_e, out / "fig6" / "euler_bernoulli.nc")
    _savefig(
        plotting.theory_comparison_figure(
            d_t,
            d_e,
            variable="w",
            title=f"Seed Fig. 6: no contact, r = {s_t.shaft.slenderness:g} (D = "
            f"{s_t.shaft.diameter * 1e3:.2f} mm), {s_t.speed:.1f} rad/s, 3 modes, from rest",
        ),
        out / "fig6_timoshenko_vs_euler_bernoulli.png",
    )
    return fig6_numbers(s_t, s_e, d_t, d_e, revs)


def _campbell_part(cx: _Context) -> None:
    from rubrotor.plotting import linear as plotting

    cx.progress("Campbell diagram")
    base = cx.scen["case1"]
    speed = base.speed
    _savefig(
        plotting.campbell_figure(base.shaft, np.linspace(0, 3 * speed, 301), operating_speed=speed),
        cx.out / "campbell.png",
    )


def _friction_part(cx: _Context, results: dict) -> dict:
    """Cases 1-3 with the other friction sign; ``friction_sign.png`` (orbit envelopes)."""
    from rubrotor.plotting import runs as plotting

    cx.progress(f"cases 1-3 with the {cx.other_sign} friction sign")
    st, scen = cx.st, cx.scen
    friction, env = {}, {}
    for key in ("case1", "case2", "case3"):
        sc_o = scen[key].with_changes(**{"contact.friction_sign": cx.other_sign})
        d_o = _run(sc_o, st.revolutions, st.save_every)
        m_o = case_metrics(d_o, sc_o.contact.clearance)
        m_o["status_message"] = d_o.attrs["status_message"]
        m_o["max_orbit_whole_run_over_clearance"] = float(
            np.max(np.hypot(d_o["v"].values[0], d_o["w"].values[0])) / sc_o.contact.clearance
        )
        friction[key] = m_o
        for sign, d in ((cx.main_sign, results[key]), (cx.other_sign, d_o)):
            env[(key, sign)] = _envelope(d, scen[key].contact.clearance)
    _savefig(
        plotting.envelope_figure(
            env, title="Orbit envelope (max over 5 revolutions): friction sign"
        ),
        cx.out / "friction_sign.png",
    )
    return friction


def _sensitivity_row(cx: _Context, fac: float, zeta: float) -> dict:
    """Contact numbers and band-energy ratios of cases 1-3 at one unbalance factor and damping."""
    me0 = cx.scen["case1"].unbalance.magnitude
    row = {"unbalance_kg_m": me0 * fac, "unbalance_factor": fac, "damping_ratio": zeta}
    energy = {}
    for key in ("no_contact", "case1", "case2", "case3"):
        sc_s = cx.scen[key].with_changes(
            **{"unbalance.magnitude": me0 * fac, "damping.ratio": zeta}
        )
        d = simulate(
            sc_s,
            integrator=Integrator(
                revolutions=cx.st.sensitivity_revolutions, output_dtau=TWO_PI / 64
            ),
            progress=False,
        )
        energy[key] = spectral_numbers(d, cx.entries, cx.band)["shear1_band_energy"]
        if key == "no_contact":
            continue
        m = case_metrics(d, sc_s.contact.clearance)
        keys = ("contact_fraction", "max_orbit_over_clearance", "max_normal_force_N", "status")
        row[key] = {k: m[k] for k in keys}
        row[key]["regime"] = regime(m)
        row[key]["shear1_ratio_to_no_contact"] = (
            energy[key] / energy["no_contact"] if energy["no_contact"] > 0 else float("inf")
        )
    return row


def _summary(cx: _Context, parts: dict, quick: bool, full: bool) -> dict:
    """The content of ``summary.json`` (plain JSON types)."""
    base, entries, band, scen = cx.scen["case1"], cx.entries, cx.band, cx.scen
    metrics, spectral = parts["metrics"], parts["spectral"]
    summary = {
        "settings": dataclasses.asdict(cx.st)
        | {"dtau": DTAU, "quick": quick, "friction_sign": cx.main_sign},
        "speed_rad_s": base.speed,
        "spin_hz": cx.spin_hz,
        "first_forward_critical_rad_s": next(
            c.speed_rad_s
            for c in critical_speeds(base)
            if c.whirl == "forward" and c.branch == "bending" and c.n == 1
        ),
        "natural_frequencies_hz": {lab: fr for lab, fr, _ in entries},
        "shear1_band_hz": [band[0], band[1]],
        "unbalance_kg_m": base.unbalance.magnitude,
        "damping_ratio": base.damping.ratios[0],
        "initial_state": "rest (zero displacement and velocity), full spin speed from t = 0",
        "cases": {
            k: metrics[k]
            | {
                "spectral": spectral[k],
                "clearance_m": scen[k].contact.clearance if scen[k].contact else None,
            }
            for k, _, _ in CASES
        },
        "fig6": parts["fig6"],
        "friction_sign_comparison": {
            "main": cx.main_sign,
            "other": cx.other_sign,
            "other_runs": parts["friction"],
        },
        "sensitivity": parts["sensitivity"],
        "claims": evaluate_claims(metrics, spectral, parts["fig6"], band),
        "seed_study": parts["extras"] | {"full": full},
        "wall_time_s": time.perf_counter() - cx.t0,
    }
    return json.loads(json.dumps(summary, default=_json_default))


def _write_outputs(cx: _Context, summary: dict, metrics: dict) -> None:
    """``summary.json``, ``report.md`` and the self-contained ``report.html``."""
    out = cx.out
    atomic_write(
        out / "summary.json", lambda tmp: Path(tmp).write_text(json.dumps(summary, indent=2))
    )
    m1, m2, m3 = metrics["case1"], metrics["case2"], metrics["case3"]
    md, page = _render(_report_blocks(summary, cx.scen, m1, m2, m3), out)
    atomic_write(out / "report.md", lambda tmp: Path(tmp).write_text(md))
    atomic_write(out / "report.html", lambda tmp: Path(tmp).write_text(page))


# ---- the reproduction -----------------------------------------------------------------------
def reproduce(
    out,
    *,
    quick: bool = False,
    seed_friction: bool = False,
    quiet: bool = False,
    full: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
) -> dict:
    """Run the seed reproduction and write its files.

    Parameters
    ----------
    out : path-like
        Output directory (created).
    quick : bool
        Shorter runs and coarser output (:data:`QUICK` instead of :data:`FULL`), for tests.
    seed_friction : bool
        Run cases 1-3 with the seed's literal friction sign (``contact.friction_sign = "seed"``)
        as the main cases; the comparison with the other sign is reported either way.
    quiet : bool
        No progress lines on stderr.
    full : bool
        Also run the claim-robustness grid and the larger detection grid
        (:mod:`rubrotor.studies.seed.extras`).
    workers : int, optional
        Local worker processes of the robustness grid (default: all cores).
    scheduler : str, optional
        Dask scheduler address for the robustness grid.

    Returns
    -------
    dict
        The content of ``summary.json``.
    """
    from rubrotor.studies.seed.extras import run_extras

    t0 = time.perf_counter()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    scen = _case_scenarios(seed_friction)
    base = scen["case1"]
    entries = mode_entries(modes(base, base.speed))
    cx = _Context(
        out=out, st=QUICK if quick else FULL, scen=scen, entries=entries,
        band=shear1_band(entries), spin_hz=base.speed / TWO_PI,
        main_sign="seed" if seed_friction else "physical",
        other_sign="physical" if seed_friction else "seed", t0=t0, quiet=quiet,
    )  # fmt: skip
    results, metrics, spectral = _run_cases(cx)  # 1. the four cases
    freqs = _cwt_part(cx, results, spectral)  # 2. seed Fig. 7
    parts = {"metrics": metrics, "spectral": spectral, "fig6": _fig6_part(cx)}  # 3. Fig. 6
    _campbell_part(cx)  # 4.
    parts["friction"] = _friction_part(cx, results)  # 5. the other friction sign
    cx.progress("sensitivity: unbalance and damping")  # 6. adaptive integrator
    parts["sensitivity"] = [_sensitivity_row(cx, fac, zeta) for fac, zeta in cx.st.sensitivity]
    # 6b. the seed's own equations, contact stability, detection, robustness (--full)
    parts["extras"] = run_extras(
        out, scen, entries=entries, band=cx.band, freqs=freqs, spin_hz=cx.spin_hz,
        save_every=cx.st.save_every, quick=quick, full=full, workers=workers,
        scheduler=scheduler, quiet=quiet, t0=t0,
    )  # fmt: skip
    cx.progress("claims, summary and report")  # 7. claims
    summary = _summary(cx, parts, quick, full)
    _write_outputs(cx, summary, metrics)
    cx.progress(f"done in {time.perf_counter() - t0:.1f} s: {out / 'report.html'}")
    return summary


def _json_default(o):
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.floating):
        return float(o)
    raise TypeError(type(o))


def _envelope(ds, clearance: float, block: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Max |P|/g per block of revolutions: (block start revolution, value)."""
    tau = ds["tau"].values
    p = np.hypot(ds["v"].values[0], ds["w"].values[0]) / clearance
    idx = np.floor(tau / (TWO_PI * block)).astype(np.int64)
    n = int(idx[-1]) + 1
    out = np.full(n, np.nan)
    np.fmax.at(out, idx, p)
    return np.arange(n) * block, out


INCONSISTENCIES = [
    (
        "Density '26.6 N/m^3'",
        "A specific weight in kN/m^3; we use the mass density 2660 kg/m^3, "
        "the only value that reproduces a ~20 kHz rub band.",
    ),
    (
        "nu = 0.334 vs E/(2G) - 1 = 0.355",
        "We give E and G (Table 1) and derive nu = 0.355; the "
        "seed's delta = (9/5)(1 + nu) is reproduced through kappa = 10/9 (below).",
    ),
    (
        "Shear coefficient 10/9 vs Cowper",
        "The seed's delta = E/(kappa G) implies kappa = 10/9; "
        'the seed scenarios use it (shear_coefficient = "seed"). Cowper\'s 0.886 is the library '
        "default for physical work (first critical 1218.5 Hz instead of 1232.3 Hz).",
    ),
    (
        "Single-equation forced form (eq. 1)",
        "Putting point forces on the right side of the "
        "4th-order single equation drops the d2F/dx2 and d2F/dt2 terms; we integrate the two-field "
        "(deflection + rotation) model, which has the same free vibration and takes point forces "
        "correctly.",
    ),
    (
        "Friction sign (eqs. 15-16)",
        "The seed's friction feeds forward whirl. Default: friction "
        'opposing sliding (physical); the seed\'s sign is a switch (contact.friction_sign = "seed", '
        "rubrotor reproduce --seed-friction); its effect is measured below.",
    ),
    (
        "Contact units",
        "k_h = 1e3 N/m^1.5, b_h = 1e2 s/m, g = 3e-3 mm give ~1e-5 N forces in SI; "
        "they are values of the dimensionless model (k_h' = k_h L^3.5/(EI), b_h' = b_h L Omega, "
        "g' = g/L), and the scenarios give them so (stiffness_nd, damping_nd, clearance_nd).",
    ),
    (
        "Operating speed 2.6 kHz",
        "1.5 x the first forward critical speed of the Table 1 rotor is "
        "1.5 x 1232.3 = 1848.4 Hz (11614 rad/s); 2.6 kHz cannot be obtained from the table. We run at "
        "1848.4 Hz (speed.critical_multiple = 1.5).",
    ),
    (
        "b_h and restitution",
        "The seed says a larger b_h makes impacts more elastic; with "
        "Hunt-Crossley b_h = 3(1 - e)/(2 v0) a larger b_h means a lower restitution e (more "
        "dissipation). Case 3 is run as specified; the report states the measured force.",
    ),
    (
        "Unbalance, structural damping, initial state",
        "Not given; chosen below and varied in the sensitivity table.",
    ),
]


def _intro_blocks(s: dict) -> list:
    """Title and how the report was made."""
    st = s["settings"]
    b: list = [
        (
            "h1",
            "rubrotor: reproduction of the seed study (IFToMM 2018, 'Rubbing Effect "
            "Analysis in a Continuous Rotor Model')",
        )
    ]
    b.append(
        (
            "p",
            f"Generated by `rubrotor reproduce` in {s['wall_time_s']:.1f} s"
            f"{' (quick settings: shortened runs, coarser output)' if st['quick'] else ''}."
            f" Friction sign of the main cases: {st['friction_sign']}.",
        )
    )
    return b


def _two_field_note_blocks() -> list:
    """Why the rub-band claims fail in the two-field model."""
    b: list = []
    b.append(("h2", "Two-field model: why its rub-band claims fail"))
    b.append(
        (
            "p",
            "Why the rub-band claims fail here: started from rest without structural "
            "damping, every run (the no-contact one included) rings at all natural "
            "frequencies, the mode-1 shear branch among them, for ever; the impacts are "
            "soft (contact lasting a good part of a 1.25 kHz bending period, far longer "
            "than the 45 us shear period), so they add little there. With a little "
            "damping (0.03 %, sensitivity table), which lets the start-up ringing of the "
            "shear branch decay, case 1 reaches only a few times the no-contact band "
            "energy, far from the seed's dominant 20 kHz band. Why case 2 is not periodic: its "
            "partial rub is carried by the undamped mode-1 free vibration (about 2/3 of "
            "the spin frequency, hence the near period 3), which is not locked to the "
            "spin.",
        )
    )
    return b


def _parameter_blocks(s: dict, scen: dict) -> list:
    """Parameters and assumptions of the runs."""
    st = s["settings"]
    b: list = []
    b.append(("h2", "Parameters and assumptions"))
    sh = scen["case1"].shaft
    c1, c3 = scen["case1"].contact, scen["case3"].contact
    b.append(
        (
            "ul",
            [
                f"Shaft (seed Table 1): L = {sh.length} m, D = {sh.diameter * 1e3:g} mm "
                f"(r = {sh.slenderness:g}), E = {sh.youngs_modulus / 1e9:g} GPa, G = {sh.G / 1e9:g} GPa, "
                f"rho = {sh.density:g} kg/m^3, kappa = {sh.kappa:.4g} (seed), Timoshenko with gyroscopic "
                f"moments, simply supported, {sh.modes} modes (mode 2 is not excited at midspan).",
                f"Speed: 1.5 x first forward critical = {s['speed_rad_s']:.1f} rad/s = "
                f"{s['spin_hz']:.1f} Hz.",
                f"Contact at midspan: Hertz-Hunt-Crossley, k_h' = 1e3 (k_h = {c1.stiffness:.3g} "
                f"N/m^1.5), b_h' = 1e2 / 1e3 (b_h = {c1.damping:.3g} / {c3.damping:.3g} s/m), g' = 3e-3 / "
                f"3.5e-3 (g = {c1.clearance * 1e3:.2f} / {scen['case2'].contact.clearance * 1e3:.2f} mm), "
                f"mu = {c1.friction}.",
                f"Unbalance (assumed): {s['unbalance_kg_m']:g} kg m at midspan. Chosen so that, started "
                "from rest, cases 1-3 are in partial rub with case 1 the hardest (the seed's picture); "
                "0.5x gives no contact, 2x gives full annular rub in every case (table below).",
                f"Structural damping (assumed): modal ratio {s['damping_ratio']:g}, as in the seed's "
                "undamped model. With 0.5 % the start-up transient dies and the rub with it (table).",
                f"Initial state (assumed): {s['initial_state']}.",
                f"Integration: exponential integrator, fixed d tau = {st['dtau']:g} (the seed's step), "
                f"{st['revolutions']:g} revolutions per case, one step in {st['save_every']} saved "
                f"(fs = {s['cases']['case1']['spectral']['fs_hz'] / 1e3:.1f} kHz). 'Late' numbers are "
                "over the second half of each run.",
                "Natural frequencies at the operating speed (Hz): "
                + ", ".join(f"{k} {v:.0f}" for k, v in s["natural_frequencies_hz"].items()),
            ],
        )
    )
    return b


def _case_blocks(s: dict) -> list:
    """Cases 1-3 and the no-contact run (seed Figs. 3-5)."""
    b: list = []
    b.append(("h2", "Cases 1-3 and the no-contact run (seed Figs. 3-5)"))
    rows = []
    for key, _stem, title in CASES:
        m = s["cases"][key]
        sp = m["spectral"]
        per = m["poincare"]
        rows.append(
            [
                title,
                _fmt(m["contact_fraction"]),
                _fmt(m["max_orbit_over_clearance"]),
                _fmt(m["max_normal_force_N"]),
                _fmt(m["mean_normal_force_N"]),
                _fmt(m["impacts_per_rev"]),
                f"{per['period'] or '-'} (best k {per['best_k']}, {per['best_residual']:.2g})",
                _fmt(sp["shear1_band_energy"]),
                _fmt(sp["shear1_ratio_to_no_contact"]),
                ", ".join(f"{f / 1e3:.3g}" for f in sp["inner_scalogram_peaks_hz"][:4]),
            ]
        )
    b.append(
        (
            "table",
            [
                "case",
                "contact fraction",
                "max |P|/g",
                "max F_n (N)",
                "mean F_n (N)",
                "impacts/rev",
                "period (Poincare)",
                "acc. energy 19.6-25.5 kHz ((m/s^2)^2)",
                "vs no contact",
                "inner-scalogram peaks (kHz)",
            ],
            rows,
        )
    )
    for key, _stem, title in CASES:
        b.append(
            (
                "img",
                f"{key}/response.png",
                f"{title}: (a) v and (c) w against time (black: clearance), (b), (d) phase "
                "portraits, (e) normal contact force, (f) orbit with the clearance circle",
            )
        )
    return b


def _cwt_blocks() -> list:
    """The CWT of the acceleration (seed Fig. 7)."""
    b: list = []
    b.append(("h2", "CWT of the acceleration (seed Fig. 7)"))
    b.append(
        (
            "p",
            "Analytic Morlet (omega0 = 6), L1 normalization; horizontal acceleration at "
            "midspan over the whole run. Dashed lines: bending branch, dotted: shear "
            "branch; blue forward, pink backward whirl; green: 1X-3X spin harmonics.",
        )
    )
    b.append(("img", "fig7_scalograms.png", "Scalogram and inner scalogram (two-field model)"))
    return b


def _fig6_blocks(s: dict) -> list:
    """Timoshenko against Euler-Bernoulli (seed Fig. 6) and the Campbell diagram."""
    b: list = []
    f6 = s["fig6"]
    b.append(("h2", "Timoshenko vs Euler-Bernoulli (seed Fig. 6)"))
    b.append(
        (
            "p",
            f"No contact, r = {f6['slenderness']:g} (D = {f6['diameter_m'] * 1e3:.2f} mm), "
            f"same speed ({f6['speed_rad_s']:.2f} rad/s) and unbalance for both theories, "
            f"{f6['revolutions']:g} revolutions from rest. The 3-mode response is the 1X "
            "orbit plus the undamped free vibration of modes 1 and 3 started at t = 0; the "
            "theories differ only through the slightly different natural frequencies "
            "(mode 1 forward: "
            f"{f6['forward_bending_hz_timoshenko']['1']:.7g} Hz Timoshenko, "
            f"{f6['forward_bending_hz_euler_bernoulli']['1']:.7g} Hz Euler-Bernoulli), so "
            "the difference grows slowly with time as the free vibrations drift apart: "
            f"max |w_T - w_EB| / max |w| = {f6['max_rel_diff_w']:.2e}.",
        )
    )
    b.append(
        (
            "img",
            "fig6_timoshenko_vs_euler_bernoulli.png",
            "Vertical displacement, both theories, and difference",
        )
    )
    b.append(("h2", "Campbell diagram"))
    b.append(("img", "campbell.png", "Campbell diagram of the seed rotor with the operating speed"))
    return b


def _friction_blocks(s: dict) -> list:
    """The two friction signs."""
    b: list = []
    fr = s["friction_sign_comparison"]
    b.append(("h2", f"Friction sign: {fr['main']} (main runs) vs {fr['other']}"))
    rows = []
    for key in ("case1", "case2", "case3"):
        o = fr["other_runs"][key]
        m = s["cases"][key]
        rows.append(
            [
                key,
                f"{regime(m)}; max |P|/g {_fmt(m['max_orbit_over_clearance'])}",
                f"{regime(o)}; max |P|/g over the run "
                f"{_fmt(o['max_orbit_whole_run_over_clearance'])}; "
                f"{o['revolutions']:.0f} rev simulated; {o['status_message'] or 'complete'}",
            ]
        )
    b.append(("table", ["case", f"{fr['main']} sign", f"{fr['other']} sign"], rows))
    b.append(
        (
            "p",
            "The seed's sign (eqs. 15-16) puts the friction force along the forward "
            "whirl: energy flows into the orbit during contact (model-notes section 3).",
        )
    )
    b.append(
        (
            "img",
            "friction_sign.png",
            "Largest |P|/g in each block of 5 revolutions, both friction signs",
        )
    )
    return b


def _sensitivity_blocks(s: dict) -> list:
    """Sensitivity to the unbalance and the structural damping."""
    st = s["settings"]
    b: list = []
    b.append(("h2", "Sensitivity to the unbalance and the structural damping"))
    b.append(
        (
            "p",
            "Adaptive integrator, from rest, "
            f"{st['sensitivity_revolutions']:g} revolutions, late half, 64 samples per "
            "revolution. Regime per case with contact fraction, max |P|/g, max normal "
            "force and the acceleration energy in the mode-1 shear band relative to the "
            "no-contact run with the same unbalance and damping.",
        )
    )
    rows = []
    for r in s["sensitivity"]:
        cells = [
            f"{r['unbalance_kg_m']:.3g} ({r['unbalance_factor']:.3g}x)",
            f"{r['damping_ratio']:g}",
        ]
        for key in ("case1", "case2", "case3"):
            c = r[key]
            cells.append(
                f"{c['regime']}: {c['contact_fraction']:.2f}, "
                f"{_fmt(c['max_orbit_over_clearance'])}, "
                f"{_fmt(c['max_normal_force_N'])} N; band x"
                f"{_fmt(c['shear1_ratio_to_no_contact'])}"
            )
        rows.append(cells)
    b.append(("table", ["unbalance (kg m)", "damping ratio", "case 1", "case 2", "case 3"], rows))
    return b


def _report_blocks(s: dict, scen: dict, m1, m2, m3) -> list:
    """The report as a list of blocks (see :func:`_render`), in reading order."""
    from rubrotor.studies.seed import report as seed_report

    b = _intro_blocks(s)
    b += seed_report.lead_blocks(s)
    b += _two_field_note_blocks()
    b += _parameter_blocks(s, scen)
    b += _case_blocks(s)
    b += _cwt_blocks()
    b += seed_report.seed_form_blocks(s)
    b += seed_report.stability_blocks(s)
    b += seed_report.detection_blocks(s)
    b += _fig6_blocks(s)
    b += _friction_blocks(s)
    b += _sensitivity_blocks(s)
    b.append(("h2", "Inconsistencies in the seed and what we did"))
    b.append(("table", ["seed", "what we did"], [list(x) for x in INCONSISTENCIES]))
    return b
