"""Guards of a free-spin run (:mod:`rubrotor.engine.spin`): what makes it resolvable, and the
chunked driver loop that keeps it interruptible.

A free-spin run is integrated by an explicit error-controlled Dormand-Prince 5(4) pair, whose
step is bounded by its stability limit, about ``3.3 / lambda`` for the largest rate ``lambda``
(1/s) of the right-hand side. :func:`stiff_terms` estimates that rate term by term from the
scenario's values (contact stiffness and damping through the modal rows ``Pc``, the spin and
ring drags, the friction's coupling ``mu N / v_r`` through the radii and inertias), so that a
run needing more than ``max_steps`` steps is refused before it starts, naming the key of its
stiffest term, and a run that becomes so stiff while it runs stops partial with the same
diagnosis. :func:`run_chunks` calls the compiled kernel a few hundred samples at a time, checks
every saved sample finite, prints a progress line and turns Ctrl-C into a partial result.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from rubrotor.core.status import DIVERGED, MAX_STEPS, OK
from rubrotor.errors import InputError

__all__ = ["stiff_terms", "stiffest", "check_samples", "run_chunks", "STABILITY", "STEPS_PER_SAMPLE"]

STABILITY = 3.3
"""Dormand-Prince 5(4): a step ``h`` is stable when ``h lambda <= 3.3`` (real or imaginary
``lambda``; the boundary of its stability region, Hairer and Wanner, vol. 1, IV.2)."""

STEPS_PER_SAMPLE = 1000
"""Steps a free-spin run may take per saved sample (the shipped touchdown_drop takes 3)."""

MEMORY_SHARE = 0.5
"""A run's saved samples may take at most this share of the available memory."""


def stiff_terms(J, drag, Pc, cp, radius, ring, normal, why=()) -> list[tuple]:
    """Rates (1/s) of the right-hand side's terms: ``(rate, key, value, what)`` per term.

    ``key`` is the scenario key the term's rate departs most by (for the friction's coupling,
    the one of friction, radius, ring radius and inertia, or the normal force's source ``why``
    that is furthest from a usual value), ``value`` its value and ``what`` the term in words.

    Parameters
    ----------
    J, drag : float
        Rotor polar inertia (kg m^2) and spin drag (N m s).
    Pc : ndarray (2 n_c, r)
        Modal rows of the contacts (1/sqrt(kg)).
    cp : ndarray (n_c, 10)
        Packed contact laws (:func:`rubrotor.core.contact.pack_contact`).
    radius : ndarray (n_c,)
        Rotor radii at the contacts (m).
    ring : ndarray (n_c, 3)
        ``[inertia kg m^2, drag N m s, bore radius m]`` per contact (inertia 0: fixed stator).
    normal : ndarray (n_c,)
        Normal force (N) the contacts carry (an estimate before the run, the largest of the last
        samples during it).
    why : tuple, optional
        ``(key, value)`` of what sets the normal force, if one does (the unbalance).
    """
    with np.errstate(all="ignore"):
        terms = [(drag / J, "speed.drag", drag, f"the spin drag (drag / J, J = {J:.3g} kg m^2)")]
        for i in range(cp.shape[0]):
            terms += _contact_terms(i, J, Pc, cp[i], radius[i], ring[i], normal[i], why)
    return [(r if math.isfinite(r) else math.inf, *rest) for r, *rest in terms]


def _contact_terms(i, J, Pc, cp, radius, ring, normal, why) -> list[tuple]:
    key = f"contact[{i + 1}]"
    pc2 = max(float(Pc[2 * i] @ Pc[2 * i]), float(Pc[2 * i + 1] @ Pc[2 * i + 1]))
    k, c, mu, vr = cp[2], cp[3], cp[5], max(cp[8], 1e-300)
    n = max(float(normal), 0.0)
    if cp[1] == 0.0:  # Hertz: dF/d(eps) = 1.5 k^(2/3) N^(1/3), damping k eps^1.5 c = N c
        k_eff, c_eff = 1.5 * k ** (2 / 3) * n ** (1 / 3), n * c
    else:
        k_eff, c_eff = k, c
    g = mu * n / vr  # d(friction force)/d(sliding speed), N s/m
    what = (f"the friction's coupling mu N / v_r of {key} (friction = {mu:.3g}, normal force "
            f"~{n:.3g} N, friction_regularization = {vr:.3g} m/s)")  # fmt: skip
    # factors of the coupling's rate: (key, value, a usual value, exponent)
    source = (*why, 1e3, 1) if why else (f"{key}.stiffness", k, 1e8, 1)
    usual = [(f"{key}.friction", mu, 0.3, 1), (source[0], n, *source[2:], source[1])]
    terms = [
        (math.sqrt(k_eff * pc2), f"{key}.stiffness", float(k), "the contact stiffness"),
        (c_eff * pc2, f"{key}.damping", float(c), "the contact damping"),
        (g * pc2, *_culprit(usual), what),
        (g * radius**2 / J, *_culprit(usual + [(f"{key}.radius", radius, 0.05, 2)]),
         what + f" on the spin through radius = {radius:.3g} m"),
    ]  # fmt: skip
    if ring[0] > 0:
        terms.append((ring[1] / ring[0], *_culprit([(f"{key}.ring_drag", ring[1], 1e-3, 1),
                      (f"{key}.ring_inertia", ring[0], 1e-3, -1)]),
                      f"the ring's drag / inertia ({ring[1]:.3g} N m s / {ring[0]:.3g} kg m^2)"))
        terms.append((g * ring[2] ** 2 / ring[0],
                      *_culprit(usual + [(f"{key}.ring_radius", ring[2], 0.05, 2),
                                         (f"{key}.ring_inertia", ring[0], 1e-3, -1)]),
                      what + f" on the ring through ring_radius = {ring[2]:.3g} m and "
                      f"ring_inertia = {ring[0]:.3g} kg m^2"))  # fmt: skip
    return terms


def _culprit(factors) -> tuple[str, float]:
    """The (key, value) of the factor furthest above its usual value (in its exponent)."""
    def departure(f):
        _, value, usual, power, *_ = f
        return power * math.log10(max(abs(value), 1e-300) / usual)

    worst = max(factors, key=departure)
    return worst[0], float(worst[-1] if len(worst) > 4 else worst[1])


def stiffest(terms) -> tuple:
    """The term of largest rate (see :func:`stiff_terms`)."""
    return max(terms, key=lambda t: t[0])


def estimated_normal(f0, Pc, unb, speed, nc) -> tuple[np.ndarray, str]:
    """A normal force (N) per contact before the run: the constant loads' share at the contact
    (the modal force ``f0`` through ``Pc``, at least its largest component) plus every unbalance
    force ``m e Omega^2``; and ``(key, value)`` of the unbalance when it sets it (else ``()``)."""
    with np.errstate(all="ignore"):
        unbalance = float(np.sum(unb[:, 0])) * speed**2 if unb.size else 0.0
    normal = np.empty(nc)
    for i in range(nc):
        static = float(np.hypot(Pc[2 * i] @ f0, Pc[2 * i + 1] @ f0)) if Pc.size else 0.0
        normal[i] = static / max(float(Pc[2 * i] @ Pc[2 * i]), 1e-300) + unbalance
    why = (("unbalance.magnitude", float(np.sum(unb[:, 0])))
           if unbalance > 0.5 * float(np.max(normal, initial=0.0)) else ())  # fmt: skip
    return normal, why


def refuse_unresolvable(terms, duration: float, max_steps: int) -> None:
    """Raise ``InputError`` naming the stiffest term's key when the run would need more
    than ``max_steps`` stable steps over ``duration`` (s)."""
    rate, key, value, what = stiffest(terms)
    need = duration * rate / STABILITY
    if need <= max_steps:
        return
    raise InputError(key, value,
                     f"a run the explicit stepper can resolve: {what} has a rate of {rate:.3g} "
                     f"1/s, which needs steps of {STABILITY / rate:.3g} s, about {need:.3g} "
                     f"steps for {duration:.3g} s (at most {max_steps:.3g})")  # fmt: skip


def check_samples(n: float, channels: int, keys: tuple[str, str], values: tuple) -> int:
    """The number of saved samples, refused (naming ``keys``) when not finite or when they cannot
    fit in half the available memory.

    Parameters
    ----------
    n : float
        Samples asked for (``duration / spacing + 1``).
    channels : int
        Values saved per sample (8 bytes each).
    keys : (str, str)
        Names of the length (``simulation.duration``) and sample (``simulation.sample_rate``)
        keys, the first named when its value is the larger departure.
    values : (float, float)
        Their values (s, Hz).
    """
    from rubrotor.engine.stream import _available_memory

    avail = MEMORY_SHARE * _available_memory()
    need = n * 8.0 * channels
    if math.isfinite(need) and need <= avail:
        return int(n)
    duration, rate = float(f"{values[0]:.12g}"), float(f"{values[1]:.12g}")
    # which key is the larger departure from a usual run (1 s at 1e4 Hz)
    key = keys[0] if (duration / 1.0) >= (rate / 1e4) else keys[1]
    value = duration if key == keys[0] else rate
    raise InputError(key, value, f"a run whose saved samples fit in memory: {n:.3g} samples of "
                     f"{channels} values need {need / 2**30:.3g} GiB, {avail / 2**30:.3g} GiB "
                     f"available; shorten {keys[0]} or lower {keys[1]}")  # fmt: skip


def run_chunks(kernel, x0, t_out, args, ctrl, rows: int, show, diagnose):
    """Run ``kernel`` over ``t_out`` a chunk of samples at a time.

    Between chunks: every saved value checked finite, a progress line (``show``), Ctrl-C caught,
    the remaining steps projected from the last chunk's step rate (a run that would exceed
    ``ctrl[2]`` steps stops). The kernel hands its last step size back in ``ctrl[1]``, so the
    chunked run takes exactly the steps of one call.

    Returns
    -------
    out : ndarray (rows, m)
        Saved samples (m of them).
    counts : (int, int)
        Accepted and rejected steps.
    reason : str
        ``""`` when complete, else why and where the run stopped.
    """
    n = t_out.size
    out = np.empty((rows, n))
    ist = np.zeros(4, np.int64)
    ctrl = ctrl.copy()
    max_steps = int(ctrl[2])
    acc = rej = 0
    m, chunk, reason = 1, 64, ""
    x = np.ascontiguousarray(x0, float)
    t0 = time.perf_counter()
    try:
        while m < n:
            stop = min(n, m + chunk)
            buf = np.zeros((rows, stop - m + 1))
            ctrl[2] = max_steps - acc - rej
            tic = time.perf_counter()
            kernel(x, t_out[m - 1 : stop], *args, ctrl, (buf, ist))
            got = int(ist[3])
            acc, rej = acc + int(ist[1]), rej + int(ist[2])
            bad = ~np.all(np.isfinite(buf[:, :got]), axis=0)
            if bad.any():
                got = int(np.argmax(bad))
                ist[0] = DIVERGED
            if m == 1:
                out[:, 0] = buf[:, 0]
            out[:, m : m + got - 1] = buf[:, 1:got]
            m += max(got - 1, 0)
            x = out[: x.size, m - 1].copy()
            if ist[0] != OK:
                reason = diagnose(int(ist[0]), out[:, :m], t_out[m - 1], ctrl[1])
                break
            steps = int(ist[1]) + int(ist[2])
            left = steps * (t_out[-1] - t_out[m - 1]) / max(t_out[m - 1] - t_out[m - got], 1e-300)
            if m < n and acc + rej + left > max_steps:
                reason = diagnose(MAX_STEPS, out[:, :m], t_out[m - 1], ctrl[1], acc + rej + left)
                break
            wall = time.perf_counter() - tic
            chunk = int(min(max(chunk * min(4.0, 0.25 / max(wall, 1e-3)), 16), 1 << 16))
            el = time.perf_counter() - t0
            if show and el > 2.0:
                frac = (m - 1) / (n - 1)
                print(f"\rrubrotor: {100 * frac:5.1f} % (t = {t_out[m - 1]:.4g} s) {el:.0f} s, "
                      f"~{el / max(frac, 1e-9) - el:.0f} s left", end="", file=sys.stderr)  # fmt: skip
    except KeyboardInterrupt:
        reason = f"interrupted by the user at t = {t_out[m - 1]:.6g} s; data up to there kept"
    if show and time.perf_counter() - t0 > 2.0:
        print(file=sys.stderr)
    return out[:, :m], (acc, rej), reason
