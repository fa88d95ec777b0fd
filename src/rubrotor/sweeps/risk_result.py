"""The result of a risk analysis (:class:`RiskResult`) and the Wilson score interval."""

from __future__ import annotations

import json
import sys
import time
from dataclasses import dataclass, field

import numpy as np

__all__ = ["RiskResult", "wilson_interval"]


def wilson_interval(k, n: int, confidence: float = 0.95) -> tuple[np.ndarray, np.ndarray]:
    """Wilson score interval of a binomial proportion ``k / n`` (module docstring).

    Examples
    --------
    >>> lo, hi = wilson_interval(0, 10)
    >>> float(lo), round(float(hi), 4)
    (0.0, 0.2775)
    """
    from scipy.stats import norm

    z = norm.ppf(0.5 + confidence / 2)
    p = np.asarray(k, float) / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return np.maximum(centre - half, 0.0), np.minimum(centre + half, 1.0)


@dataclass(frozen=True)
class RiskResult:
    """The probability of rub against speed, with what drives it.

    Attributes
    ----------
    method : str
        ``"linear"`` or ``"time"``.
    speeds : ndarray, shape (S,)
        Spin speeds (rad/s).
    samples : int
        ``N``.
    rubs : ndarray, shape (S,)
        Samples that rub at each speed.
    probability, lower, upper : ndarray, shape (S,)
        ``rubs / N`` and its Wilson interval at ``confidence`` (1).
    confidence : float
        Level of the intervals.
    keys : tuple of str
        The varied scenario keys.
    distributions : tuple of str
        Their distributions as written.
    seed : int
        Seed of the samples.
    sampler : str
        ``"sobol"``, ``"lhs"`` or ``"random"``.
    rub_anywhere : float
        Fraction of samples that rub at some speed.
    sobol : dict or None
        Sobol' indices (first, total and intervals per key) of the output "rubs at some speed"
        (``"rub"``) and of the smallest margin over the speeds (``"margin"``, m).
    time_stats : dict or None
        Time method: per speed, the runs simulated and those that diverged, quantiles of the
        peak normal force (N) and of the contact fraction (1) over the simulated runs, and the
        count of each regime label.
    store : str or None
        The zarr store with every sample's inputs and outputs.
    """

    method: str
    speeds: np.ndarray
    samples: int
    rubs: np.ndarray
    probability: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    confidence: float
    keys: tuple
    distributions: tuple
    seed: int
    sampler: str
    rub_anywhere: float
    sobol: dict | None = None
    time_stats: dict | None = None
    store: str | None = None
    units: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The JSON form printed by ``rubrotor risk --json`` (SI units in the key names)."""
        return {
            "method": self.method,
            "samples": self.samples,
            "seed": self.seed,
            "sampler": self.sampler,
            "confidence": self.confidence,
            "vary": [
                {"key": k, "distribution": d, "unit": self.units.get(k, "1")}
                for k, d in zip(self.keys, self.distributions, strict=True)
            ],  # fmt: skip
            "speed_rad_s": self.speeds.tolist(),
            "rubs": self.rubs.astype(int).tolist(),
            "probability": self.probability.tolist(),
            "probability_lower": self.lower.tolist(),
            "probability_upper": self.upper.tolist(),
            "rub_anywhere": self.rub_anywhere,
            "sobol": self.sobol,
            "time": self.time_stats,
            "store": self.store,
        }

    def to_dataset(self):
        """The result as an xarray Dataset (dimension ``speed``; attrs hold the definition)."""
        import xarray as xr

        sp = ("speed", self.speeds, {"units": "rad/s", "long_name": "spin speed"})
        data = {
            "rubs": ("speed", self.rubs, {"units": "1", "long_name": "samples that rub"}),
            "probability": ("speed", self.probability, {"units": "1", "long_name": "P(rub)"}),
            "probability_lower": ("speed", self.lower, {"units": "1",
                                  "long_name": f"Wilson {self.confidence:g} lower bound"}),
            "probability_upper": ("speed", self.upper, {"units": "1",
                                  "long_name": f"Wilson {self.confidence:g} upper bound"}),
        }  # fmt: skip
        if self.sobol is not None:
            for out in ("rub", "margin"):
                s = self.sobol[out]
                for what in ("first", "total"):
                    data[f"sobol_{what}_{out}"] = ("key", np.array([s[k][what] for k in self.keys],
                                                   float), {"units": "1"})  # fmt: skip
        attrs = {k: json.dumps(v) if isinstance(v, dict | list) or v is None else v
                 for k, v in self.to_dict().items()
                 if k not in ("speed_rad_s", "rubs", "probability", "probability_lower",
                              "probability_upper")}  # fmt: skip
        return xr.Dataset(data, coords={"speed": sp, "key": ("key", list(self.keys))},
                          attrs=attrs)  # fmt: skip


def progress_line(enabled: bool, done: int, total: int, t0: float) -> None:
    if enabled:
        print(f"\rrubrotor risk: {done}/{total} chunks, {time.perf_counter() - t0:.0f} s",
              end="" if done < total else "\n", file=sys.stderr)  # fmt: skip
