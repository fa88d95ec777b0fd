"""Uncertain inputs of a risk analysis: distributions of scenario keys and their quasi-random samples.

A distribution is written as text, ``KEY=DIST`` on the command line:

* ``normal(mean,sd)``: ``sd > 0``;
* ``truncnormal(mean,sd,lo,hi)``: the normal restricted to ``[lo, hi]``, ``lo < hi``;
* ``uniform(lo,hi)``: ``lo < hi``;
* ``lognormal(mu,sigma)``: ``exp(X)`` with ``X`` normal ``(mu, sigma)``, ``sigma > 0``
  (``mu``, ``sigma`` of the logarithm, in log of the key's unit).

Samples: points ``u`` in the unit hypercube ``[0, 1)^d`` from :mod:`scipy.stats.qmc` (scrambled
Sobol', Latin hypercube) or plain pseudo-random numbers, all from one seed, mapped through each
distribution's inverse CDF (``ppf``). Sobol' points are drawn in chunks (the ``i``-th point is
the same however the sequence is chunked), so a long run keeps only one chunk in memory.

The Saltelli design for Sobol' indices uses a ``2 d``-dimensional sequence: its first ``d``
columns are the matrix ``A`` (the samples whose rub the risk counts), its last ``d`` the
matrix ``B``; ``A_B^(i)`` is ``A`` with column ``i`` taken from ``B``.
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError

__all__ = [
    "Distribution",
    "parse_distribution",
    "parse_risk_vary",
    "SAMPLERS",
    "unit_samples",
    "sample_values",
    "check_values",
]

SAMPLERS = ("sobol", "lhs", "random")
"""Sample designs: scrambled Sobol' (default), Latin hypercube, plain pseudo-random."""

_FORMS = {
    "normal": ("mean", "sd"),
    "truncnormal": ("mean", "sd", "lo", "hi"),
    "uniform": ("lo", "hi"),
    "lognormal": ("mu", "sigma"),
}
_TEXT = re.compile(r"^\s*([a-z]+)\s*\((.*)\)\s*$")


@dataclass(frozen=True)
class Distribution:
    """One key's distribution.

    Parameters
    ----------
    kind : {"normal", "truncnormal", "uniform", "lognormal"}
        The family.
    params : tuple of float
        Its parameters in the order of the module docstring, in the key's unit (SI), or of its
        logarithm for ``lognormal``.
    field : str
        The key it belongs to (named in errors).
    """

    kind: str
    params: tuple
    field: str = "vary"

    def __post_init__(self):
        names = _FORMS.get(self.kind)
        if names is None:
            raise InputError(self.field, self.kind, "a distribution " + ", ".join(
                f"{k}({','.join(v)})" for k, v in _FORMS.items()))  # fmt: skip
        p = tuple(float(x) for x in self.params)
        if len(p) != len(names) or not all(math.isfinite(x) for x in p):
            raise InputError(self.field, f"{self.kind}{self.params}",
                             f"{self.kind}({','.join(names)}) with finite numbers")  # fmt: skip
        object.__setattr__(self, "params", p)
        if self.kind in ("normal", "truncnormal") and not p[1] > 0:
            raise InputError(f"{self.field} sd", p[1], "a standard deviation > 0")
        if self.kind == "lognormal" and not p[1] > 0:
            raise InputError(f"{self.field} sigma", p[1], "a log standard deviation > 0")
        lo_hi = p[2:4] if self.kind == "truncnormal" else p if self.kind == "uniform" else None
        if lo_hi is not None and not lo_hi[0] < lo_hi[1]:
            raise InputError(f"{self.field} range", lo_hi, "a non-empty range lo < hi")

    def frozen(self):
        """The :mod:`scipy.stats` frozen distribution."""
        import scipy.stats as st

        p = self.params
        if self.kind == "normal":
            return st.norm(p[0], p[1])
        if self.kind == "truncnormal":
            return st.truncnorm((p[2] - p[0]) / p[1], (p[3] - p[0]) / p[1], loc=p[0], scale=p[1])
        if self.kind == "uniform":
            return st.uniform(p[0], p[1] - p[0])
        return st.lognorm(p[1], scale=math.exp(p[0]))

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """Values (the key's unit) at probabilities ``u`` in ``(0, 1)``."""
        return self.frozen().ppf(u)

    def text(self) -> str:
        """The distribution as written, e.g. ``"normal(4e-05,4e-06)"``."""
        return f"{self.kind}({','.join(repr(x) for x in self.params)})"


def parse_distribution(text: str, field: str = "vary") -> Distribution:
    """Parse ``"normal(4e-5, 4e-6)"`` and the other forms of the module docstring.

    Examples
    --------
    >>> parse_distribution("uniform(1e-4, 3e-4)").params
    (0.0001, 0.0003)
    """
    m = _TEXT.match(str(text))
    if m is None or m.group(1) not in _FORMS:
        raise InputError(field, text, "a distribution " + ", ".join(
            f"{k}({','.join(v)})" for k, v in _FORMS.items()))  # fmt: skip
    try:
        params = tuple(float(x) for x in m.group(2).split(","))
    except ValueError:
        names = _FORMS[m.group(1)]
        raise InputError(field, text, f"{m.group(1)}({','.join(names)}) with numbers") from None
    return Distribution(m.group(1), params, field)


def parse_risk_vary(text: str) -> tuple[str, Distribution]:
    """Split ``"KEY=DIST"`` (the ``--vary`` option of ``rubrotor risk``)."""
    key, sep, dist = str(text).partition("=")
    if not sep or not key.strip():
        raise InputError("--vary", text, "KEY=DIST, e.g. contact.clearance=normal(40e-6,4e-6)")
    return key.strip(), parse_distribution(dist, key.strip())


def unit_samples(sampler: str, dims: int, seed: int, start: int, count: int,
                 total: int) -> np.ndarray:  # fmt: skip
    """Points ``start`` to ``start + count - 1`` of the design of ``total`` points in ``[0, 1)^dims``.

    Sobol' points are computed for the chunk alone (fast-forwarded); Latin hypercube and
    pseudo-random points are drawn for the whole design and sliced (they hold ``total x dims``
    numbers). The same ``(sampler, dims, seed, total)`` gives the same points, chunk by chunk.
    """
    from scipy.stats import qmc

    if sampler == "sobol":
        eng = qmc.Sobol(dims, scramble=True, seed=seed)
        if start:
            eng.fast_forward(int(start))
        with warnings.catch_warnings():  # balance holds for powers of 2; any N is allowed here
            warnings.simplefilter("ignore", UserWarning)
            u = eng.random(count)
    elif sampler == "lhs":
        u = qmc.LatinHypercube(dims, seed=seed).random(total)[start : start + count]
    elif sampler == "random":
        u = np.random.default_rng(seed).random((total, dims))[start : start + count]
    else:
        raise InputError("sampler", sampler, " or ".join(SAMPLERS))
    # ppf(0) is -inf for unbounded families: keep strictly inside (0, 1)
    return np.clip(u, 0.5 / 2**53, 1 - 2.0**-53)


def sample_values(dists, u: np.ndarray) -> np.ndarray:
    """Key values (their units) of unit-cube points ``u`` (n, d) through each ``ppf``."""
    return np.column_stack([dist.ppf(u[:, j]) for j, dist in enumerate(dists)])


def check_values(refs, values: np.ndarray, start: int) -> None:
    """Refuse a sampled value the key does not allow (the distribution reaches outside the
    key's range), naming the key, the value and the sample."""
    from rubrotor.errors import RubrotorError
    from rubrotor.scenario.schema import check_value, key_row

    for j, ref in enumerate(refs):
        col = values[:, j]
        if not np.all(np.isfinite(col)):
            raise InputError(ref.text, float(col[~np.isfinite(col)][0]), "finite samples")
        for i in (int(col.argmin()), int(col.argmax())):
            try:
                check_value(ref.text, float(col[i]), key_row(ref.section, ref.name))
            except RubrotorError as exc:
                raise InputError(ref.text, float(col[i]),
                                 f"{exc.allowed} (sample {start + i}; truncate the distribution"
                                 " with truncnormal(mean,sd,lo,hi))") from None  # fmt: skip
