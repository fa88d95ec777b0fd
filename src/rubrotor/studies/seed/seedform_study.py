"""The seed study under the seed's own equations (``shaft.formulation = "seed-eq1"``).

Cases 1-3 and the no-contact run with the seed's step ``d tau = 0.001``, integrated by our
exponential engine (the runs the claims read) and by the seed's Adams-Bashforth-Moulton scheme
(a shorter run, compared with the engine over the same span); their CWT maps; the Fig. 6 pair;
the seven claims decided as for the two-field model; and the linear stability of a pressed
contact for both formulations (table and growth-rate figure).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from rubrotor.engine.settings import Integrator
from rubrotor.engine.simulate import simulate
from rubrotor.linear.stability import contact_stability

__all__ = ["run_cases", "stability_table", "growth_curves"]

DTAU = 1e-3
SEED = "seed-eq1"


def _stop_rev(ds) -> float:
    return float(ds["tau"].values[-1] / (2 * math.pi))


def run_cases(scen: dict, revolutions: float, save_every: int, abm_revolutions: float) -> dict:
    """Run the cases under the seed form: engine (exponential) and the seed's ABM.

    Parameters
    ----------
    scen : dict
        ``{"case1", "case2", "case3", "no_contact"}`` scenarios (their formulation is replaced).
    revolutions : float
        Engine run length (rev).
    save_every : int
        Saved sample = every k-th step of ``d tau = 0.001``.
    abm_revolutions : float
        ABM run length (rev).

    Returns
    -------
    dict
        ``results`` (engine Datasets), ``abm`` (per case: status, revolutions simulated, max
        ``|P_abm - P_engine| / max |P_engine|`` over the common span).
    """
    results, abm = {}, {}
    for key, sc in scen.items():
        s = sc.with_changes(**{"shaft.formulation": SEED})
        ds = simulate(
            s,
            integrator=Integrator(revolutions=revolutions, dtau=DTAU, save_every=save_every),
            progress=False,
        )
        da = simulate(
            s,
            integrator=Integrator(
                revolutions=abm_revolutions, dtau=DTAU, save_every=save_every, method="abm"
            ),
            progress=False,
        )
        n = min(da.sizes["time"], ds.sizes["time"])
        pe = ds["v"].values[0, :n] + 1j * ds["w"].values[0, :n]
        pa = da["v"].values[0, :n] + 1j * da["w"].values[0, :n]
        results[key] = ds
        abm[key] = {
            "status": da.attrs["status"],
            "revolutions": _stop_rev(da),
            "engine_status": ds.attrs["status"],
            "engine_revolutions": _stop_rev(ds),
            "max_rel_diff": float(np.max(np.abs(pa - pe)) / np.max(np.abs(pe))),
        }
    return {"results": results, "abm": abm}


def fig6_seed(s_t, revolutions: float):
    """The Fig. 6 Timoshenko run under the seed form (the Euler-Bernoulli one is unchanged)."""
    s = s_t.with_changes(**{"shaft.formulation": SEED})
    return s, simulate(
        s, integrator=Integrator(revolutions=revolutions, dtau=DTAU, save_every=16), progress=False
    )


STABILITY_CASES = (
    (1e-4, 0.0),
    (1e-4, 1e2),
    (1e-4, 1e3),
    (3e-4, 1e2),
)


def stability_table(base, modes: int = 1) -> list[dict]:
    """Largest growth rate of a pressed contact for both formulations (model-notes section 6).

    For each ``(eps0, b_h')`` of :data:`STABILITY_CASES`: mu = 0 with the radial and the
    isotropic linearisation, and the scenario's friction (radial), mode 1 alone by default.

    Returns
    -------
    list of dict
        ``eps0_m``, ``bh_nd``, then per ``"<formulation>/<variant>"`` the growth rate (1/s) and
        signed frequency (Hz) of the fastest eigenvalue.
    """
    rows = []
    variants = (
        ("radial, mu = 0", {"friction": False}),
        ("isotropic, mu = 0", {"friction": False, "linearisation": "isotropic"}),
        (f"radial, mu = {base.contact.friction:g}", {}),
    )
    for eps0, bh in STABILITY_CASES:
        row = {"eps0_m": eps0, "bh_nd": bh, "results": {}}
        for vname, kw in variants:
            for form in ("two-field", SEED):
                r = contact_stability(
                    base, eps0, formulation=form, contact_damping_nd=bh, modes=modes, **kw
                )
                row["results"][f"{form}/{vname}"] = {
                    "growth_per_s": r.max_growth_rate,
                    "frequency_hz": r.dominant_frequency_hz,
                }
        rows.append(row)
    return rows


def growth_curves(base, eps0: float = 1e-4, modes: int = 1, n: int = 41) -> dict:
    """Largest growth rate (1/s) against ``b_h'`` for both formulations, mu = 0 and scenario mu.

    Returns
    -------
    dict
        ``bh_nd`` (array) and ``curves``: label to ``(growth rates, signed Hz)`` arrays.
    """
    bh = np.concatenate([[0.0], np.logspace(0, 4, n - 1)])
    curves = {}
    for form in ("two-field", SEED):
        for fr in (False, True):
            g, f = [], []
            for b in bh:
                r = contact_stability(
                    base,
                    eps0,
                    formulation=form,
                    contact_damping_nd=float(b),
                    modes=modes,
                    friction=fr,
                )
                g.append(r.max_growth_rate)
                f.append(r.dominant_frequency_hz)
            mu = base.contact.friction if fr else 0.0
            curves[f"{form}, mu = {mu:g}"] = (np.array(g), np.array(f))
    return {"bh_nd": bh, "eps0_m": eps0, "modes": modes, "curves": curves}


def growth_figure(data: dict):
    """Growth rate of the fastest eigenvalue against ``b_h'`` (symlog), both formulations."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.5, 4.6), layout="constrained")
    ax, axf = fig.subplots(1, 2, width_ratios=[3, 2])
    styles = {
        "two-field": dict(color="tab:blue"),
        SEED: dict(color="tab:red"),
    }
    bh = data["bh_nd"]
    x = np.where(bh > 0, bh, 0.3)
    for label, (g, f) in data["curves"].items():
        form = label.split(",")[0]
        ls = "-" if "mu = 0," in label + "," else "--"
        ax.plot(x, g, ls, label=label, **styles[form])
        axf.plot(x, f / 1e3, ls, **styles[form])
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel("contact damping b_h' (dimensionless; b_h' = 0 drawn at 0.3)")
    ax.set_ylabel("largest growth rate (1/s)")
    ax.set_title(
        f"Pressed contact, eps0 = {data['eps0_m'] * 1e3:g} mm, {data['modes']} mode(s), "
        "radial linearisation"
    )
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    axf.set_xscale("log")
    axf.set_xlabel("contact damping b_h' (dimensionless)")
    axf.set_ylabel("signed frequency of that eigenvalue (kHz)")
    axf.set_title("whirl frequency (negative = backward)")
    axf.grid(True, which="both", alpha=0.3)
    return fig


def seed_settings_note(st) -> dict:
    """JSON-ready description of the seed-form runs (for the summary)."""
    return dataclasses.asdict(st) | {"dtau": DTAU, "formulation": SEED}
