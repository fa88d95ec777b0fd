"""Which rub indicators separate rub from no rub on a realistic machine, with measurement noise.

The machine: the seed rotor (two-field model, physical friction, case-1 contact: ``k_h' = 1e3``,
``b_h' = 1e2``, ``g = 1.2 mm``) with modal damping, started on its steady no-contact orbit, under
a range of unbalances and static radial loads (a misalignment or fluid force that pushes the
orbit towards the stator). Whether a run rubs is the simulation's ground truth (contact in the
second half of the run). Each response is measured with white Gaussian noise added to every
channel at a stated SNR (``20 log10(rms(signal) / sigma)``, dB) and reduced to one number per
indicator; an indicator's detection margin is ``log10`` of the gap between the two classes,
``max(log10(min R / max N), log10(min N / max R))`` (decades) over all runs and noise
realisations (``R`` rub, ``N`` no rub): positive means a threshold separates them all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["DetectionSettings", "DEFAULT", "LIGHT", "QUICK", "indicators", "run"]


@dataclass(frozen=True)
class DetectionSettings:
    """Machine, class grid, noise and run length of the detection study.

    Attributes
    ----------
    damping : float
        Modal damping ratio (dimensionless).
    unbalance_factors : tuple of float
        Multiples of the shipped unbalance (1.5e-3 kg m).
    loads : tuple of float
        Static radial loads along y (N).
    snr_db : tuple of float
        Signal-to-noise ratios of every measured channel (dB); ``inf``: no noise.
    realisations : int
        Noise realisations per run.
    revolutions : float
        Run length (rev); indicators read the second half.
    samples_per_rev : int
        Output samples per revolution.
    seed : int
        Seed of the noise generator.
    """

    damping: float = 0.01
    unbalance_factors: tuple = (0.75, 1.0, 1.25)
    loads: tuple = (0.0, 5e4, 1e5, 1.5e5, 2e5, 3e5)
    snr_db: tuple = (math.inf, 40.0, 20.0)
    realisations: int = 3
    revolutions: float = 120
    samples_per_rev: int = 64
    seed: int = 20181


DEFAULT = DetectionSettings()
LIGHT = DetectionSettings(unbalance_factors=(1.0,), revolutions=60)
QUICK = DetectionSettings(
    unbalance_factors=(1.0,), loads=(0.0, 2e5), snr_db=(math.inf, 20.0), realisations=2,
    revolutions=30,
)  # fmt: skip

NAMES = (
    ("cwt_band", "CWT band energy, mode-1 shear band / 1X (acceleration)"),
    ("inner_scalogram", "inner scalogram, mode-1 shear band / 1X (acceleration)"),
    ("backward_share", "full-spectrum backward share (displacement orbit)"),
    ("sub_half", "sub-harmonic 1/2X / 1X (displacement v)"),
    ("super_2x", "super-harmonic 2X / 1X (displacement v)"),
    ("super_3x", "super-harmonic 3X / 1X (displacement v)"),
    ("impacts_per_rev", "bursts per revolution of the non-synchronous acceleration"),
)


def _noisy(x: np.ndarray, snr_db: float, rng) -> np.ndarray:
    sigma = math.sqrt(float(np.mean(x**2))) / 10 ** (snr_db / 20)
    return x + rng.normal(0.0, sigma, x.size)


def _bursts_per_rev(a: np.ndarray, fs: float, spin_hz: float) -> float:
    """Onsets per revolution of ``|a - 1X fit|`` above ``median + 6 x 1.4826 MAD``."""
    t = np.arange(a.size) / fs
    e = np.exp(2j * math.pi * spin_hz * t)
    sync = np.vdot(e, a) / a.size * e
    r = np.abs(a - sync)
    med = np.median(r)
    thr = med + 6 * 1.4826 * np.median(np.abs(r - med))
    above = r > thr
    onsets = int(np.sum(above[1:] & ~above[:-1]))
    return onsets / (a.size / fs * spin_hz)


def indicators(v, w, av, aw, fs: float, spin_hz: float, band: tuple) -> dict:
    """The indicators of one measured response (see :data:`NAMES`).

    Parameters
    ----------
    v, w : ndarray
        Displacements (m).
    av, aw : ndarray
        Accelerations (m/s^2).
    fs : float
        Sampling frequency (Hz).
    spin_hz : float
        Spin frequency (Hz).
    band : (float, float)
        Mode-1 shear band (Hz).

    Returns
    -------
    dict of str to float
    """
    from rubrotor.analysis.indicators import backward_whirl_share
    from rubrotor.analysis.spectra import order_spectrum
    from rubrotor.analysis.wavelet import log_frequencies, scalograms

    freqs = np.concatenate([[spin_hz], log_frequencies(band[0], band[1], 5)])
    sc, inner = scalograms(av, fs, freqs)
    orders = (0.5, 1.0, 2.0, 3.0)
    amp = order_spectrum(v, fs, spin_hz, orders=orders).amplitudes
    z = v - v.mean(), w - w.mean()
    return {
        "cwt_band": float(np.sum(sc[1:] ** 2) / sc[0] ** 2),
        "inner_scalogram": float(inner[1:].max() / inner[0]),
        "backward_share": backward_whirl_share(z[0], z[1], fs),
        "sub_half": float(amp[0] / amp[1]),
        "super_2x": float(amp[2] / amp[1]),
        "super_3x": float(amp[3] / amp[1]),
        "impacts_per_rev": _bursts_per_rev(av + 1j * aw, fs, spin_hz),
    }


def _margin(rub: np.ndarray, no: np.ndarray) -> tuple[float, str]:
    """Detection margin (decades) and the direction in which rub moves the indicator."""
    lo = 1e-300
    up = math.log10(max(rub.min(), lo) / max(no.max(), lo))
    down = math.log10(max(no.min(), lo) / max(rub.max(), lo))
    return (up, "higher with rub") if up >= down else (down, "lower with rub")


def run(st: DetectionSettings = DEFAULT) -> dict:
    """Run the detection study.

    Parameters
    ----------
    st : DetectionSettings
        Machine, grid, noise.

    Returns
    -------
    dict
        ``settings``, ``runs`` (per run: unbalance, load, rub, contact fraction),
        ``table`` (per indicator: name, margin in decades, direction, class medians).
    """
    from dataclasses import asdict

    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate
    from rubrotor.studies.seed.claims import band_of, seed_scenarios

    base = seed_scenarios(**{"damping.ratio": st.damping, "initial.state": "steady"})["case1"]
    _entries, band = band_of(base)
    spin_hz = base.speed / (2 * math.pi)
    rng = np.random.default_rng(st.seed)
    integ = Integrator(revolutions=st.revolutions, output_dtau=2 * math.pi / st.samples_per_rev)
    keys = [k for k, _ in NAMES]
    values = {
        snr: {"rub": {k: [] for k in keys}, "no rub": {k: [] for k in keys}} for snr in st.snr_db
    }
    runs = []
    me0 = base.unbalance.magnitude
    for fac in st.unbalance_factors:
        for fy in st.loads:
            sc = base.with_changes(
                **{"unbalance.magnitude": me0 * fac, "load.force_y": fy, "load.force_z": 0.0}
            )
            ds = simulate(sc, integrator=integ, progress=False)
            late = ds["tau"].values >= ds["tau"].values[-1] / 2
            frac = float(np.mean(ds["normal_force"].values.sum(axis=0)[late] > 0))
            cls = "rub" if frac > 0 else "no rub"
            runs.append(
                {"unbalance_kg_m": me0 * fac, "load_N": fy, "contact_fraction": frac, "class": cls}
            )
            fs = 1.0 / float(ds["time"].values[1] - ds["time"].values[0])
            chans = [ds[c].values[0, late] for c in ("v", "w", "v_ddot", "w_ddot")]  # station 0
            for snr in st.snr_db:
                for _ in range(st.realisations if math.isfinite(snr) else 1):
                    noisy = [_noisy(x, snr, rng) if math.isfinite(snr) else x for x in chans]
                    for k, val in indicators(*noisy, fs, spin_hz, band[2:]).items():
                        values[snr][cls][k].append(val)
    table = []
    for key, name in NAMES:
        row: dict = {"indicator": name, "key": key, "snr": {}}
        for snr in st.snr_db:
            r, n = np.array(values[snr]["rub"][key]), np.array(values[snr]["no rub"][key])
            if r.size and n.size:
                m, direction = _margin(r, n)
                row["snr"][_snr_label(snr)] = {
                    "margin_decades": m,
                    "direction": direction,
                    "median_rub": float(np.median(r)),
                    "median_no_rub": float(np.median(n)),
                }
        table.append(row)
    return {"settings": asdict(st), "band_hz": list(band[2:]), "runs": runs, "table": table}


def _snr_label(snr: float) -> str:
    return "no noise" if not math.isfinite(snr) else f"{snr:g} dB"
