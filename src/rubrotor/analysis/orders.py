r"""Order tracking of run-ups, coast-downs and steady runs: computed order tracking.

The method is *computed order tracking* (Potter 1990; Fyfe and Munck 1997), the digital
counterpart of sampling synchronously with a once-per-revolution keyphasor as machinery
monitoring systems do: each signal is resampled
at equal increments of the spin angle ``theta`` (``samples_per_rev`` per revolution, cubic
spline through the time samples), cut into blocks of a whole number of revolutions starting at
the keyphasor (``theta`` a multiple of ``2 pi``), Hann windowed and Fourier-analysed per
block. An order ``k`` (any positive real with ``k * revolutions`` an integer: 0.5, 1, 2, 1/3,
...) is then a bin of the block, with no leakage from the other orders whatever the speed: the
block spans an exact number of periods of every tracked order, twice the fewest needed, so the
Hann window's leakage stops at the neighbouring bins, which are no tracked order. It is exact
for a steady run and, for a run-up, reads the window-weighted mean phasor over the block (two
revolutions for integer orders, four with 0.5X). A component that is no order of the spin (a
free whirl at a natural frequency, excited by impacts) is read into every tracked order within
the Hann main lobe, ``2 / revolutions`` orders on either side: on a run with rub, a large 0.5X
may be such a whirl; take longer blocks (``revolutions``) to separate them. We chose it
over the Vold-Kalman filter because it needs no bandwidth parameter, its phase reference is
the keyphasor exactly as on a machine, and its error is the resampling error alone
(``O((k Omega dt)^4)`` for the cubic spline: below 1e-6 at 100 samples per period).

Conventions (SI; phases in rad):

* A tracked order ``k`` of a signal ``y`` has the complex amplitude ``Y`` with
  ``y(t) ~ Re(Y exp(i k theta(t)))`` over the block, ``theta`` the spin angle from the run
  (the keyphasor fires at ``theta = 0 mod 2 pi``). Amplitude ``|Y|`` (zero-to-peak) and phase
  ``arg Y``; the Bently-Nevada phase lag is ``-arg Y`` (mod ``2 pi``). For a linear rotor this
  equals :func:`rubrotor.linear.response.unbalance_response`'s ``Re(Q exp(i Omega t))``.
* The orbit ``z = y + i w`` splits into a forward and a backward circle per order,
  ``z ~ F exp(i k theta) + B exp(-i k theta)`` with ``F = (Y + i W)/2`` and
  ``B = (conj(Y) + i conj(W))/2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from rubrotor.errors import InputError

__all__ = [
    "SpinAngle",
    "OrderTrack",
    "spin_from_dataset",
    "spin_from_speed",
    "spin_from_keyphasor",
    "track_orders",
    "block_revolutions",
    "dataset_orders",
    "DEFAULT_TRACKED",
]

DEFAULT_TRACKED = (0.5, 1.0, 2.0)
"""Orders tracked by default: the half-order rub subharmonic, 1X and 2X."""

_TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class SpinAngle:
    """Spin angle and speed of a record at its sample times.

    Attributes
    ----------
    time : numpy.ndarray
        Sample times (s), increasing.
    angle : numpy.ndarray
        Spin angle (rad); the keyphasor is at multiples of ``2 pi``. NaN outside the span it is
        known on (before the first and after the last keyphasor pulse).
    speed : numpy.ndarray
        Spin speed (rad/s), NaN where ``angle`` is.
    """

    time: np.ndarray
    angle: np.ndarray
    speed: np.ndarray

    @property
    def valid(self) -> slice:
        """The samples where the angle is known (one contiguous slice)."""
        ok = np.flatnonzero(np.isfinite(self.angle))
        return slice(int(ok[0]), int(ok[-1]) + 1) if ok.size else slice(0, 0)


def _times(time) -> np.ndarray:
    t = np.asarray(time, dtype=np.float64)
    if t.ndim != 1 or t.size < 4 or not np.all(np.isfinite(t)):
        raise InputError(
            "time", f"array of shape {t.shape}", "a finite 1-D array of >= 4 times (s)"
        )
    if not np.all(np.diff(t) > 0):
        raise InputError("time", "non-increasing times", "strictly increasing sample times (s)")
    return t


def spin_from_speed(time, speed, *, angle0: float = 0.0) -> SpinAngle:
    """Spin angle from a sampled speed (a tachometer or the run's speed column).

    The angle is the cumulative trapezoidal integral of the speed, exact for a speed linear
    between samples (a linear run-up or a speed table).

    Parameters
    ----------
    time : array_like, shape (n,)
        Sample times (s), strictly increasing.
    speed : array_like, shape (n,)
        Spin speed (rad/s), > 0.
    angle0 : float
        Spin angle at the first sample (rad).

    Returns
    -------
    SpinAngle
    """
    from scipy.integrate import cumulative_trapezoid

    t = _times(time)
    om = np.asarray(speed, dtype=np.float64)
    if om.shape != t.shape or not np.all(np.isfinite(om)) or np.any(om <= 0):
        raise InputError("speed", f"array of shape {om.shape}",
                         f"finite speeds > 0 (rad/s), one per time ({t.size})")  # fmt: skip
    angle = angle0 + cumulative_trapezoid(om, t, initial=0.0)
    return SpinAngle(t, angle, om)


def spin_from_keyphasor(time, pulses, *, threshold: float | None = None) -> SpinAngle:
    """Spin angle from a once-per-revolution keyphasor signal.

    Each rising crossing of ``threshold`` (time by linear interpolation between samples) marks
    ``theta = 2 pi j``; between marks the angle is the not-a-knot cubic spline through them
    (exact for a constant angular acceleration), and the speed its derivative.

    Parameters
    ----------
    time : array_like, shape (n,)
        Sample times (s), strictly increasing.
    pulses : array_like, shape (n,)
        Keyphasor signal (any unit): one pulse (or notch edge) per revolution.
    threshold : float, optional
        Crossing level (unit of ``pulses``); default midway between its minimum and maximum.

    Returns
    -------
    SpinAngle
        NaN before the first and after the last mark.
    """
    from scipy.interpolate import CubicSpline

    t = _times(time)
    p = np.asarray(pulses, dtype=np.float64)
    if p.shape != t.shape or not np.all(np.isfinite(p)):
        raise InputError("keyphasor", f"array of shape {p.shape}", f"finite values, one per time ({t.size})")  # fmt: skip
    level = 0.5 * (p.min() + p.max()) if threshold is None else float(threshold)
    i = np.flatnonzero((p[:-1] < level) & (p[1:] >= level))
    if i.size < 4:
        raise InputError("keyphasor", f"{i.size} pulses", "at least 4 once-per-revolution pulses")
    marks = t[i] + (level - p[i]) / (p[i + 1] - p[i]) * (t[i + 1] - t[i])
    spline = CubicSpline(marks, _TWO_PI * np.arange(marks.size))
    inside = (t >= marks[0]) & (t <= marks[-1])
    angle = np.full(t.shape, np.nan)
    speed = np.full(t.shape, np.nan)
    angle[inside] = spline(t[inside])
    speed[inside] = spline(t[inside], 1)
    return SpinAngle(t, angle, speed)


def spin_from_dataset(ds) -> SpinAngle:
    """Spin angle and speed of a rubrotor results Dataset.

    The angle is the Dataset's ``tau`` coordinate (rad), the exact integral of the run's speed
    profile (constant, linear run-up or coast-down, table); the speed is its derivative by
    second-order differences, exact for a piecewise-linear speed (rad/s).

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`rubrotor.simulate`.

    Returns
    -------
    SpinAngle
    """
    if "tau" not in ds.coords and "tau" not in ds.variables:
        raise InputError("results", "no 'tau'", "a rubrotor results Dataset with a spin angle")
    t = _times(ds["time"].values)
    angle = np.asarray(ds["tau"].values, dtype=np.float64)
    speed = np.gradient(angle, t, edge_order=2)
    if np.any(speed <= 0):
        raise InputError("results", "spin speed <= 0", "a run with positive spin speed")
    return SpinAngle(t, angle, speed)


@dataclass(frozen=True)
class OrderTrack:
    """Tracked orders of one probe (one or two directions).

    Attributes
    ----------
    orders : numpy.ndarray, shape (n_orders,)
        Orders (multiples of the spin speed).
    speed_rad_s : numpy.ndarray, shape (n_blocks,)
        Spin speed at each block's middle angle, the centre of its window (rad/s).
    time_s : numpy.ndarray, shape (n_blocks,)
        Time at each block's middle angle (s).
    y : numpy.ndarray, complex, shape (n_orders, n_blocks)
        Complex amplitude ``Y`` of the first direction (unit of the signal, e.g. m).
    w : numpy.ndarray or None
        Same for the second direction (z), None for a single channel.
    revolutions : int
        Revolutions per block.
    window : str
        Block window, ``"hann"`` or ``"rect"``.
    """

    orders: np.ndarray
    speed_rad_s: np.ndarray
    time_s: np.ndarray
    y: np.ndarray
    w: np.ndarray | None
    revolutions: int
    window: str = "hann"

    @property
    def forward(self) -> np.ndarray:
        """Forward-whirl phasor ``F = (Y + i W)/2`` per order and block (signal unit)."""
        return 0.5 * (self.y + 1j * self.w)

    @property
    def backward(self) -> np.ndarray:
        """Backward-whirl phasor ``B = (conj Y + i conj W)/2`` per order and block."""
        return 0.5 * (np.conj(self.y) + 1j * np.conj(self.w))

    def order_index(self, order: float) -> int:
        """Row of ``order`` in the arrays (exact match within 1e-9)."""
        hit = np.flatnonzero(np.abs(self.orders - order) < 1e-9)
        if not hit.size:
            raise InputError("order", order, f"one of the tracked orders {self.orders.tolist()}")
        return int(hit[0])


def _orders(orders) -> np.ndarray:
    o = np.atleast_1d(np.asarray(orders, dtype=np.float64))
    if o.ndim != 1 or o.size == 0 or not np.all(np.isfinite(o)) or np.any(o <= 0):
        raise InputError("orders", orders, "one or more finite orders > 0 (e.g. 0.5, 1, 2)")
    return o


def block_revolutions(orders) -> int:
    """Fewest whole revolutions in which every order completes whole periods.

    Parameters
    ----------
    orders : sequence of float
        Orders, each a fraction with denominator at most 64 (0.5, 1/3, 2, ...).

    Returns
    -------
    int
        The least common multiple of the orders' denominators.
    """
    den = 1
    for o in _orders(orders):
        f = Fraction(float(o)).limit_denominator(64)
        if abs(float(f) - o) > 1e-9:
            raise InputError("orders", float(o), "fractions with a denominator <= 64 (e.g. 1/3)")
        den = den * f.denominator // math.gcd(den, f.denominator)
    return den


def _per_rev(spin: SpinAngle, samples_per_rev: int | None) -> int:
    sl = spin.valid
    dt = np.diff(spin.time[sl])
    most = float(np.max(_TWO_PI / (spin.speed[sl][1:] * dt)))
    if samples_per_rev is None:
        return int(min(4096, max(64, 2 ** math.ceil(math.log2(most)))))
    if not (isinstance(samples_per_rev, int | np.integer) and samples_per_rev >= 8):
        raise InputError("samples_per_rev", samples_per_rev, "an integer >= 8")
    return int(samples_per_rev)


def _revolutions(spin: SpinAngle) -> tuple[int, int]:
    """First keyphasor revolution index inside the record and the whole revolutions after it."""
    a = spin.angle[spin.valid]
    r0 = math.ceil(a[0] / _TWO_PI - 1e-12)
    r1 = math.floor(a[-1] / _TWO_PI + 1e-12)
    if r1 - r0 < 1:
        raise InputError("record", f"{(a[-1] - a[0]) / _TWO_PI:.3g} revolutions",
                         "at least one whole revolution between keyphasor marks")  # fmt: skip
    return r0, r1 - r0


def _rev_sums(spin: SpinAngle, chans: list, m: int, ext: np.ndarray):
    """Per-revolution DFT sums ``sum_n c(theta_n) exp(-i k theta_n)`` on the absolute angle.

    Each channel is resampled at ``m`` equal angle steps per revolution (cubic splines: the time
    at an angle, then the signal at that time), revolution by revolution in chunks, so memory
    stays bounded on long records.

    Returns
    -------
    r0 : int
        Revolution index of the first keyphasor mark.
    sums : list of numpy.ndarray, complex, shape (n_rev, n_ext)
        One per channel.
    time_at : callable
        Time (s) at spin angles (rad), the spline of the record's angle.
    """
    from scipy.interpolate import CubicSpline

    sl = spin.valid
    t, a = spin.time[sl], spin.angle[sl]
    time_at = CubicSpline(a, t)
    splines = [CubicSpline(t, c[sl]) for c in chans]
    r0, n_rev = _revolutions(spin)
    kern = np.exp(-1j * np.outer(_TWO_PI * np.arange(m) / m, ext))  # (m, n_ext)
    sums = [np.empty((n_rev, ext.size), complex) for _ in chans]
    chunk = max(1, (1 << 20) // m)
    for ra in range(0, n_rev, chunk):
        rb = min(n_rev, ra + chunk)
        revs = r0 + np.arange(ra, rb)
        tg = time_at(_TWO_PI * (revs[:, None] + np.arange(m) / m)).ravel()
        rot = np.exp(-1j * np.outer(_TWO_PI * revs, ext))  # (revs, n_ext)
        for out, spl in zip(sums, splines, strict=True):
            out[ra:rb] = spl(tg).reshape(rb - ra, m) @ kern * rot
    return r0, sums, time_at


def track_orders(spin: SpinAngle, y, w=None, *, orders=DEFAULT_TRACKED, revolutions=None,
                 samples_per_rev=None, step: int = 1, window: str = "hann") -> OrderTrack:  # fmt: skip
    """Amplitude and phase of orders of the spin speed, block by block (computed order tracking).

    Parameters
    ----------
    spin : SpinAngle
        Spin angle and speed at the samples (:func:`spin_from_dataset`, :func:`spin_from_speed`,
        :func:`spin_from_keyphasor`).
    y : array_like, shape (n,)
        Signal along the first direction (any unit, e.g. m), sampled at ``spin.time``.
    w : array_like, shape (n,), optional
        Signal along the second direction (same unit): gives forward and backward components.
    orders : sequence of float
        Orders to track (> 0; default 0.5, 1, 2).
    revolutions : int, optional
        Revolutions per block; default the fewest that hold whole periods of every order
        (:func:`block_revolutions`: 1 for integer orders, 2 with 0.5X), doubled for Hann.
    samples_per_rev : int, optional
        Angle samples per revolution; default the next power of two at or above the record's
        largest time samples per revolution (64 to 4096).
    step : int
        Revolutions between block starts (1: one block per revolution, overlapping when
        ``revolutions > 1``).
    window : {"hann", "rect"}
        Block window. Both read a steady order exactly (the block holds whole periods of every
        order, and Hann's leakage reaches only the neighbouring ``1/revolutions`` orders); on a
        run-up Hann keeps the growth of 1X within a block out of 2X and 0.5X (the rectangular
        window leaks 0.4 % of 1X into 2X on the slow run-up of the tests, Hann 0.1 %).

    Returns
    -------
    OrderTrack
    """
    o = _orders(orders)
    if window not in ("hann", "rect"):
        raise InputError("window", window, '"hann" or "rect" (rectangular)')
    need = block_revolutions(o) * (2 if window == "hann" else 1)
    b = need if revolutions is None else int(revolutions)
    if b < 1 or b % need:
        raise InputError("revolutions", revolutions, f"a positive multiple of {need} for orders {o.tolist()}")  # fmt: skip
    if not (isinstance(step, int | np.integer) and step >= 1):
        raise InputError("step", step, "an integer >= 1 (revolutions)")
    chans = [np.asarray(y, dtype=np.float64)] + ([] if w is None else [np.asarray(w, float)])
    for name, c in zip(("y", "w"), chans, strict=False):
        if c.shape != spin.time.shape or not np.all(np.isfinite(c[spin.valid])):
            raise InputError(name, f"array of shape {c.shape}", f"finite samples at the {spin.time.size} times")  # fmt: skip
    sl = spin.valid
    nyquist = math.pi / float(np.max(np.diff(spin.time[sl])))  # rad/s
    top = float(np.max(spin.speed[sl]))
    if o.max() * top >= nyquist:
        raise InputError("orders", o.max(), f"orders whose frequency at the top speed {top:.6g} rad/s "
                         f"stays below the Nyquist frequency {nyquist:.6g} rad/s")  # fmt: skip
    m = _per_rev(spin, samples_per_rev)
    if o.max() >= m / 2:
        raise InputError("orders", o.max(), f"orders below samples_per_rev / 2 = {m / 2:g}")
    ext = o if window == "rect" else np.concatenate([o, o - 1.0 / b, o + 1.0 / b])
    r0, sums, time_at = _rev_sums(spin, chans, m, ext)
    n_rev = sums[0].shape[0]
    if n_rev < b:
        raise InputError("record", f"{n_rev} whole revolutions", f"at least {b} (one block)")
    starts = np.arange(0, n_rev - b + 1, step)
    phasors = [_block_phasors(c, o, ext, m, r0, b, starts, window) for c in sums]
    mid = time_at(_TWO_PI * (r0 + starts) + math.pi * b)
    speed = np.interp(mid, spin.time[sl], spin.speed[sl])
    return OrderTrack(o, speed, mid, phasors[0], phasors[1] if len(phasors) == 2 else None, b,
                      window)  # fmt: skip


def _block_phasors(part, o, ext, m: int, r0: int, b: int, starts, window: str) -> np.ndarray:
    """Phasors ``Y`` (n_orders, n_blocks) from one channel's per-revolution sums ``part``.

    The per-revolution DFT sums on the absolute angle (:func:`_rev_sums`, orders ``ext``) are
    summed over each block's revolutions (cumulative sums). The Hann window is applied in the
    frequency domain: its block DFT at bin ``K`` is ``(R_K - (R_{K-1} + R_{K+1}) / 2) / 2`` of
    the rectangular DFTs ``R`` in the block's own angle, i.e. orders ``k`` and ``k -+ 1/b``.
    """
    csum = np.vstack([np.zeros(ext.size), np.cumsum(part, axis=0)])
    g = (csum[starts + b] - csum[starts]).T  # global-angle sums (n_ext, n_blocks)
    n = b * m
    if window == "rect":
        return g * (2.0 / n)
    k = o.size
    start = _TWO_PI * (r0 + starts)  # block start angles (rad)
    local = g * np.exp(1j * np.outer(ext, start))
    hann = 0.5 * local[:k] - 0.25 * (local[k : 2 * k] + local[2 * k :])
    return hann * np.exp(-1j * np.outer(o, start)) * (4.0 / n)


def _steady_block(spin: SpinAngle, y, w, orders) -> OrderTrack:
    """One block over the last half of a constant-speed record (whole revolutions)."""
    sl = spin.valid
    a = spin.angle[sl]
    need = 2 * block_revolutions(orders)
    revs = math.floor((a[-1] - a[0]) / _TWO_PI / 2 / need) * need
    if revs < need:
        return track_orders(spin, y, w, orders=orders)
    start = _TWO_PI * (math.floor(a[-1] / _TWO_PI + 1e-12) - revs) - 1e-9
    cut = np.flatnonzero(spin.angle >= start - _TWO_PI)[0]  # one revolution of margin
    part = SpinAngle(spin.time[cut:], spin.angle[cut:], spin.speed[cut:])
    wc = None if w is None else np.asarray(w, float)[cut:]
    tr = track_orders(part, np.asarray(y, float)[cut:], wc, orders=orders, revolutions=revs)
    return tr if tr.speed_rad_s.size == 1 else _last(tr)


def _last(tr: OrderTrack) -> OrderTrack:
    from dataclasses import replace

    w = None if tr.w is None else tr.w[:, -1:]
    return replace(tr, speed_rad_s=tr.speed_rad_s[-1:], time_s=tr.time_s[-1:], y=tr.y[:, -1:], w=w)


def dataset_orders(ds, orders=DEFAULT_TRACKED) -> list[dict]:
    """Tracked orders of every station of a results Dataset, as JSON-able rows.

    A run-up, coast-down or speed table is tracked block by block (:func:`track_orders`); a
    constant-speed run gives one block, the last half of its whole revolutions (past the start
    transient), so one speed.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`rubrotor.simulate` (every station of its ``station`` dimension).
    orders : sequence of float
        Orders to track (default 0.5, 1, 2).

    Returns
    -------
    list of dict
        One row per station and order: ``probe_m``, ``order``, ``speed_rad_s`` (list),
        ``amplitude_y_m``, ``phase_y_rad``, ``amplitude_z_m``, ``phase_z_rad`` (lists; phase of
        ``Re(Y exp(i k theta))`` from the keyphasor), ``forward_m``, ``backward_m`` (lists).
    """
    spin = spin_from_dataset(ds)
    steady = bool(np.ptp(spin.speed) <= 1e-9 * np.max(spin.speed))
    rows = []
    for probe, y, w in _station_orbits(ds):
        if steady:
            tr = _steady_block(spin, y, w, orders)
        else:
            tr = track_orders(spin, y, w, orders=orders)
        for i, k in enumerate(tr.orders):
            rows.append({
                "probe_m": probe, "order": float(k), "speed_rad_s": tr.speed_rad_s.tolist(),
                "amplitude_y_m": np.abs(tr.y[i]).tolist(), "phase_y_rad": np.angle(tr.y[i]).tolist(),
                "amplitude_z_m": np.abs(tr.w[i]).tolist(), "phase_z_rad": np.angle(tr.w[i]).tolist(),
                "forward_m": np.abs(tr.forward[i]).tolist(),
                "backward_m": np.abs(tr.backward[i]).tolist(),
            })  # fmt: skip
    return rows


def _station_orbits(ds):
    """``(position m, v, w)`` of every station of a results Dataset (m)."""
    v, w = ds["v"].values, ds["w"].values  # (station, time)
    return [(float(x), v[j], w[j]) for j, x in enumerate(ds["station"].values)]
