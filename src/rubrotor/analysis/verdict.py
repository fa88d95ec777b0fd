r"""A rub verdict, "rub: yes / no / possible", with the evidence it rests on.

For a simulation the contact data decide: any contact time is "yes", none is "no" (the closest
approach is given as evidence). For a measured probe record there is no contact data; the
verdict weighs the signs of rub that machinery engineers read on probe data (see e.g.
Muszynska, *Rotordynamics*, 2005), each reported with its number so a reader can judge:

* **proximity**: the largest orbit radius about the stator centre reaches ``PROXIMITY`` (0.9)
  of the radial clearance (needs the clearance);
* **backward whirl**: at least ``BACKWARD_SHARE`` (0.2) of the orbit's full-spectrum energy is
  backward (a dry-friction rub drives the rotor backwards);
* **sub-harmonics**: 1/2X or 1/3X reaches ``SUB_RATIO`` (0.1) of 1X somewhere in the run;
* **super-harmonics**: 2X or 3X reaches ``SUPER_RATIO`` (0.3) of 1X (truncated, flattened
  orbits; also misalignment, so it only supports the others).

Measured verdict: "yes" with proximity and one more sign, or, without a clearance, backward
whirl and sub-harmonics together; "possible" with any one sign; "no" with none. These are
rules of thumb, not a classifier: the evidence is what to read.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from rubrotor.analysis.orders import SpinAngle, track_orders
from rubrotor.errors import InputError

__all__ = ["RubVerdict", "rub_evidence", "rub_verdict", "dataset_verdict"]

PROXIMITY = 0.9
BACKWARD_SHARE = 0.2
SUB_RATIO = 0.1
SUPER_RATIO = 0.3
SUB = (1 / 3, 0.5)
SUPER = (2.0, 3.0)


@dataclass(frozen=True)
class RubVerdict:
    """A rub verdict and its evidence.

    Attributes
    ----------
    verdict : str
        ``"yes"``, ``"no"`` or ``"possible"``.
    reasons : tuple of str
        One sentence per sign found (or why none).
    evidence : dict
        The numbers (SI; see :func:`rub_evidence`), JSON-able.
    """

    verdict: str
    reasons: tuple = ()
    evidence: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """``{"rub": verdict, "reasons": [...], "evidence": {...}}``."""
        return {"rub": self.verdict, "reasons": list(self.reasons), "evidence": self.evidence}


def _amp(track, k: float) -> np.ndarray:
    i = track.order_index(k)
    return (
        np.abs(track.y[i]) if track.w is None else np.hypot(np.abs(track.y[i]), np.abs(track.w[i]))
    )


def _backward_share(y, w) -> float:
    """Backward (negative-frequency) share of the orbit's energy, DC removed (Hann, uniform)."""
    from scipy.signal import get_window

    z = np.asarray(y, float) + 1j * np.asarray(w, float)
    z = z - z.mean()
    p = np.abs(np.fft.fft(z * get_window("hann", z.size, fftbins=True))) ** 2
    f = np.fft.fftfreq(z.size)
    total = p[f != 0].sum()
    return float(p[f < 0].sum() / total) if total > 0 else 0.0


def rub_evidence(
    spin: SpinAngle, y, w, *, clearance: float | None = None, centre=(0.0, 0.0)
) -> dict:
    """Signal evidence of rub at one probe (orbit ``y, w``, m).

    Parameters
    ----------
    spin : SpinAngle
        Spin angle and speed at the samples.
    y : array_like, shape (n,)
        Displacement along y (m) at ``spin.time``.
    w : array_like, shape (n,), optional
        Displacement along z (m); without it there is no backward-whirl share and the radius
        is ``|y - centre_y|``.
    clearance : float, optional
        Radial clearance at this probe (m).
    centre : (float, float)
        Stator centre (m).

    Returns
    -------
    dict
        ``revolutions``; ``backward_share`` (energy fraction, None for one direction);
        ``subharmonic`` and
        ``superharmonic``: ``{order: {"max_ratio": ..., "speed_rad_s": ...}}`` (amplitude over 1X,
        largest over the run, and the speed there; only the orders the record is long enough
        for: 1/3X needs 13 revolutions, 0.5X five, 2X and 3X three); ``max_radius_m``; with a
        clearance also
        ``max_radius_over_clearance`` and ``centreline_offset_over_clearance`` (largest mean
        position per revolution about the centre, over the clearance).
    """
    from rubrotor.analysis.diagnostics import shaft_centreline

    sl = spin.valid
    y = np.asarray(y, float)
    w = None if w is None else np.asarray(w, float)
    revs = (spin.angle[sl][-1] - spin.angle[sl][0]) / (2 * math.pi)
    harm = _harmonics(spin, y, w, revs)
    radius = (
        np.abs(y[sl] - centre[0]) if w is None else np.hypot(y[sl] - centre[0], w[sl] - centre[1])
    )
    out = {
        "revolutions": float(revs),
        "backward_share": None if w is None else _backward_share(y[sl], w[sl]),
        **harm,
        "max_radius_m": float(radius.max()),
    }
    if clearance is not None:
        if not (math.isfinite(clearance) and clearance > 0):
            raise InputError("clearance", clearance, "a radial clearance > 0 (m)")
        out["clearance_m"] = float(clearance)
        out["max_radius_over_clearance"] = float(radius.max() / clearance)
        if w is not None and revs >= 2:
            cl = shaft_centreline(spin, y, w)
            off = np.hypot(cl.y - centre[0], cl.z - centre[1])
            out["centreline_offset_over_clearance"] = float(off.max() / clearance)
    return out


def _harmonics(spin: SpinAngle, y, w, revs: float) -> dict:
    """Largest sub- and super-harmonic ratios to 1X over the run (orders that fit the record:
    1/3X needs 12 revolutions per Hann block, 0.5X four, 2X and 3X two, and below the Nyquist
    frequency at the top speed)."""
    sl = spin.valid
    nyquist = math.pi / float(np.max(np.diff(spin.time[sl])))  # rad/s
    top = float(np.max(spin.speed[sl]))
    sub = tuple(k for k, need in zip(SUB, (12, 4), strict=True) if revs >= need + 1)
    sup = tuple(k for k in SUPER if k * top < nyquist) if revs >= 3 else ()
    harm: dict = {"subharmonic": {}, "superharmonic": {}}
    if not sup:
        return harm
    track = track_orders(spin, y, w, orders=(*sub, 1.0, *sup))
    one = _amp(track, 1.0)
    one = np.where(one > 0, one, np.inf)
    for name, group in (("subharmonic", sub), ("superharmonic", sup)):
        for k in group:
            r = _amp(track, k) / one
            j = int(np.argmax(r))
            harm[name][f"{k:.4g}"] = {"max_ratio": float(r[j]), "speed_rad_s": float(track.speed_rad_s[j])}  # fmt: skip
    return harm


def _signs(ev: dict) -> list[tuple[str, str]]:
    signs = []
    if ev.get("max_radius_over_clearance", 0.0) >= PROXIMITY:
        signs.append(("proximity", f"orbit reaches {ev['max_radius_over_clearance']:.0%} of the clearance"))  # fmt: skip
    if (ev["backward_share"] or 0.0) >= BACKWARD_SHARE:
        signs.append(("backward", f"backward whirl holds {ev['backward_share']:.0%} of the orbit energy"))  # fmt: skip
    for name, lim in (("subharmonic", SUB_RATIO), ("superharmonic", SUPER_RATIO)):
        for k, d in ev[name].items():
            if d["max_ratio"] >= lim:
                signs.append((name, f"{float(k):.3g}X reaches {d['max_ratio']:.2f} of 1X at {d['speed_rad_s']:.4g} rad/s"))  # fmt: skip
    return signs


def rub_verdict(ev: dict, contact: dict | None = None) -> RubVerdict:
    """The verdict from evidence (:func:`rub_evidence`) and, for a simulation, contact data.

    Parameters
    ----------
    ev : dict
        Signal evidence.
    contact : dict, optional
        ``contact_time_s``, ``contact_fraction``, ``impacts``, ``impacts_per_revolution`` of a
        simulation; they decide the verdict.

    Returns
    -------
    RubVerdict
    """
    evidence = {**ev, **(contact or {})}
    signs = _signs(ev)
    reasons = [s[1] for s in signs]
    if contact is not None:
        if contact["contact_time_s"] > 0:
            why = (f"rotor and stator touch for {contact['contact_time_s']:.4g} s "
                   f"({contact['contact_fraction']:.1%} of the run), "
                   f"{contact['impacts_per_revolution']:.3g} impacts per revolution")  # fmt: skip
            return RubVerdict("yes", (why, *reasons), evidence)
        why = "no contact in the simulation"
        if _no_stations(contact):
            why = "the scenario has no contact (no stator to rub)"
        return RubVerdict("no", (why, *reasons), evidence)
    kinds = {s[0] for s in signs}
    if ("proximity" in kinds and len(kinds) >= 2) or {"backward", "subharmonic"} <= kinds:
        return RubVerdict("yes", tuple(reasons), evidence)
    if kinds:
        return RubVerdict("possible", tuple(reasons), evidence)
    return RubVerdict("no", ("no proximity, backward whirl or sub-/super-harmonic sign",), evidence)


def _no_stations(contact: dict) -> bool:
    """Whether simulation contact data come from a run without any contact station."""
    return contact.get("contact_stations", 1) == 0


def _dataset_contact(ds) -> tuple[dict, float | None, tuple[float, float]]:
    """Contact data of the first contact of a results Dataset, its clearance (m) and centre."""
    t = ds["time"].values
    # streamed files hold no in_contact: it is normal_force > 0
    ic = np.asarray(
        ds["in_contact"].values if "in_contact" in ds else ds["normal_force"].values > 0
    )
    ic = ic[0] if ic.shape[0] else np.zeros(t.size, np.int8)  # (contact, time); no contact: none
    kind = ds["event_kind"].values
    if "event_contact" in ds:
        kind = kind[ds["event_contact"].values == 0]
    dt = float(np.mean(np.diff(t)))
    revs = float((ds["tau"].values[-1] - ds["tau"].values[0]) / (2 * math.pi))
    impacts = int(np.sum(kind > 0))
    n_contacts = ds.sizes.get("contact", 1)
    contact = {"contact_stations": int(n_contacts),
               "contact_time_s": float(ic.sum() * dt), "contact_fraction": float(ic.mean()),
               "impacts": impacts, "impacts_per_revolution": impacts / revs if revs > 0 else 0.0}  # fmt: skip
    clearance, centre = None, (0.0, 0.0)
    if "contacts" in ds.attrs:
        c = json.loads(ds.attrs["contacts"])
        if c:
            clearance, centre = float(c[0]["clearance"]), (c[0]["offset_y"], c[0]["offset_z"])
    elif "parameters" in ds.attrs:
        par = json.loads(ds.attrs["parameters"])
        for key, val in par.items():
            if key.endswith("clearance"):
                clearance = float(val[0] if isinstance(val, list) else val)
    return contact, clearance, centre


def dataset_verdict(ds) -> RubVerdict:
    """Rub verdict of a simulation results Dataset at its (first) contact station (the orbit
    relative to the stator's motion when the stator is flexible).

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`rubrotor.simulate`.

    Returns
    -------
    RubVerdict
    """
    from rubrotor.analysis.orders import spin_from_dataset

    for var in ("v", "w", "normal_force", "event_kind", "time"):
        if var not in ds.variables:
            raise InputError("results", f"no '{var}'", "a rubrotor simulation results Dataset")
    v, w = ds["v"].values[0], ds["w"].values[0]  # the first (contact) station
    if "stator_y" in ds and ds["stator_y"].shape[0]:  # relative to a flexible stator's motion
        v, w = v - ds["stator_y"].values[0], w - ds["stator_z"].values[0]
    contact, clearance, centre = _dataset_contact(ds)
    ev = rub_evidence(spin_from_dataset(ds), v, w, clearance=clearance, centre=centre)
    return rub_verdict(ev, contact)
