"""Continuation of the one-mode rotor's rub branches: rubrotor against pyHarm.

The same rotor in both codes: one Euler-Bernoulli mode (modal mass ``m``, stiffness ``k``,
damping ``c = 2 zeta sqrt(k m)``, mode shape 1 at midspan), unbalance ``u = m_e e`` at midspan,
a radial penalty contact ``f = -k_c (r - g)_+ (e_r + mu e_t)`` with friction ``mu`` opposing the
forward spin, and for the partial rub a constant side load. rubrotor continues by shooting
(fixed-step exponential map prepared once per key value, monodromy from the map's variational
equations, Floquet multipliers at every point; optionally Richardson-extrapolated points);
pyHarm (``pyharm-os``, optional group ``pyharm``) by harmonic balance with its arc-length
corrector. pyHarm ships no rotor-stator contact with friction, so :class:`RadialPenaltyContact`
below adds one through pyHarm's documented plugin route (a subclass of its node-to-node element
base, registered by ``Maestro({"plugin": [...]})``), evaluated by alternating frequency/time
(AFT) with its analytic Jacobian; the side load is its ``GOForcing`` on harmonic 0.

1. Full annular rub (``one_mode_annular_rub.toml``, friction sign unsmoothed as in pyHarm's
   element), speed from 1.8 down to 1.2 x the first critical speed: down the no-contact orbit
   to contact onset (a non-smooth turning point), back up the unstable rub branch to its fold
   and down the stable rub branch. Accuracy of every point: its relative distance (in
   ``(r, W)`` scaled by the point) to the closed-form curve ``[(k - m W^2) r + k_c (r - g)]^2
   + [c W r + mu k_c (r - g)]^2 = (u W^2)^2`` (or the linear response without contact). The
   orbit is a circle, so its contact force is a pure first harmonic and harmonic balance with
   one harmonic is exact: pyHarm's error is its solver tolerance. rubrotor's default route here
   is the synchronous one (circles as equilibria of the rotating frame,
   :mod:`rubrotor.orbits.synchronous`), exact to rounding; the shooting rows (``method="shooting"``)
   carry the time-stepping error (second order, fourth with Richardson).
2. Partial rub (``one_mode_partial_rub.toml``, one impact per revolution), period-1 branch from
   1.9 to 2.05 x critical (below its period doubling): harmonic balance is not exact; pyHarm's
   harmonic count is raised (5 .. 40) to reach rubrotor's error. Accuracy of every point: the
   relative error of its largest radius against shooting at 16384 steps per revolution at that
   speed (itself checked against 32768).

Time per point: wall time from one accepted point to the next (interleaved repeats in one
process, per point the median over the repeats; numba/jax compilation excluded by a warm-up).
Printed per row: mean (total / points), median and worst point; the location of bifurcations
and contact onset, which only rubrotor does, is reported apart. Per pair: the mean ratio and
the every-point ratio ``our worst point / pyHarm's best point`` (below 1: each of our points
cost less than each of pyHarm's), with whether our largest error is at most pyHarm's.

Run (pyHarm lives in its own venv, which sees the system site packages), from a scratch
directory (pyHarm writes ``.pyHarm/`` into the working directory):
``OPENBLAS_NUM_THREADS=1 PYTHONPATH=src /work/venvs/pyharm/bin/python
benchmarks/bench_continuation_vs_pyharm.py [REPEATS] [annular,partial]``.
"""

from __future__ import annotations

import functools
import logging
import math
import sys
import time
from importlib import resources

import numpy as np
import scipy.optimize

from rubrotor.orbits import continuation, shooting
from rubrotor.orbits.continuation import continue_orbit
from rubrotor.rotors.shaft import modal_matrices
from rubrotor.scenario import load_scenario

VERBOSE = False
_REGISTERED: list = []
KEY = "speed.critical_multiple"
START, STOP = 1.8, 1.2  # x first critical speed


# ---- the one-mode model and its closed form --------------------------------------------------
def one_mode(sc) -> dict:
    """Modal mass (kg), stiffness (N/m), damping (N s/m), unbalance (kg m), contact of ``sc``."""
    mm = modal_matrices(sc.shaft, 1)
    m, k = float(mm.M[0, 0].real), float(mm.K[0, 0].real)
    return dict(
        m=m, k=k, c=2 * sc.damping.ratios[0] * math.sqrt(k * m), u=sc.unbalance.magnitude,
        kc=sc.contact.stiffness, mu=sc.contact.friction, g=sc.contact.clearance,
        crit=sc.with_changes(**{KEY: 1.0}).speed,
        fy=sc.load.force_y if sc.load is not None else 0.0,
    )  # fmt: skip


def balance(p: dict, r, w):
    """Amplitude equation residual (N^2) and its gradient in ``(r, w)`` at radius r (m), w (rad/s)."""
    kc = np.where(r > p["g"], p["kc"], 0.0)
    radial = (p["k"] - p["m"] * w * w) * r + kc * (r - p["g"])
    tang = p["c"] * w * r + p["mu"] * kc * (r - p["g"])
    f = radial**2 + tang**2 - (p["u"] * w * w) ** 2
    df_dr = 2 * radial * (p["k"] - p["m"] * w * w + kc) + 2 * tang * (p["c"] * w + p["mu"] * kc)
    df_dw = -4 * radial * p["m"] * w * r + 2 * tang * p["c"] * r - 4 * p["u"] ** 2 * w**3
    return f, df_dr, df_dw


def curve_error(p: dict, r, w):
    """Relative distance of points (r m, w rad/s) to the closed-form curve (dimensionless)."""
    f, fr, fw = balance(p, np.asarray(r, float), np.asarray(w, float))
    return np.abs(f) / np.hypot(fr * r, fw * w)


def closed_form_turns(p: dict) -> tuple[float, float]:
    """Contact onset and the rub branch's fold (rad/s) of the closed form."""

    def free(w):
        return p["u"] * w * w / abs(p["k"] - p["m"] * w * w + 1j * p["c"] * w) - p["g"]

    wn = math.sqrt(p["k"] / p["m"])
    onset = scipy.optimize.brentq(free, wn, 3 * wn, xtol=1e-14)

    def top_speed(r):  # largest W with a rub orbit of radius r: a quartic in W
        a, b = (p["k"] + p["kc"]) * r - p["kc"] * p["g"], p["m"] * r
        d = p["mu"] * p["kc"] * (r - p["g"])
        roots = np.roots([b * b - p["u"] ** 2, 0, (p["c"] * r) ** 2 - 2 * a * b,
                          2 * p["c"] * r * d, a * a + d * d])  # fmt: skip
        real = [x.real for x in roots if abs(x.imag) < 1e-9 * abs(x) and x.real > 0]
        return max(real, default=0.0)

    grid = p["g"] * np.linspace(1.001, 20.0, 2000)
    i = int(np.argmax([top_speed(r) for r in grid]))
    res = scipy.optimize.minimize_scalar(lambda r: -top_speed(r), bounds=(grid[i - 1], grid[i + 1]),
                                         method="bounded", options={"xatol": 1e-15})  # fmt: skip
    return onset, -res.fun


def turning_points(w) -> list[float]:
    """Speeds where a sampled branch reverses (vertex of the parabola through the 3 points)."""
    w = np.asarray(w, float)
    out = []
    for i in np.flatnonzero(np.diff(np.sign(np.diff(w))) != 0) + 1:
        s = np.array([-1.0, 0.0, 1.0])
        a, b, c = np.polyfit(s, w[i - 1 : i + 2], 2)
        out.append(float(c - b * b / (4 * a)) if a != 0 else float(w[i]))
    return out


# ---- rubrotor ----------------------------------------------------------------------------------
def _stamps(module, name: str, accepted=lambda self, out: True):
    """Wrap ``module.name`` to record ``perf_counter()`` after each call that ``accepted``."""
    orig = getattr(module, name)
    stamps: list = []

    @functools.wraps(orig)
    def wrapped(*args, **kwargs):
        out = orig(*args, **kwargs)
        if accepted(args[0] if args else None, out):
            stamps.append(time.perf_counter())
        return out

    setattr(module, name, wrapped)
    return stamps, lambda: setattr(module, name, orig)


def per_point(t0: float, stamps: list) -> np.ndarray:
    """Wall time (s) of each branch point: from the previous point (or the start) to it."""
    return np.diff(np.concatenate([[t0], stamps]))


def run_ours(
    sc,
    p: dict,
    steps: int,
    richardson: bool,
    span,
    points: int = 200,
    ds_max=0.2,
    method: str = "shooting",
):
    """rubrotor's branch: speeds (rad/s), largest radii (m), folds (rad/s), per-point times (s)
    and which points' intervals hold the location of a bifurcation or of contact onset."""
    stamps, restore = _stamps(continuation, "_point")
    located, restores = [], []
    for name in ("_locate", "_locate_turn", "_onset"):
        got, undo = _stamps(continuation, name, lambda self, out: out is not None)
        located.append(got)
        restores.append(undo)
    t0 = time.perf_counter()
    try:
        branch = continue_orbit(sc, KEY, *span, steps=steps, points=points, ds_max=ds_max,
                                richardson=richardson, method=method)  # fmt: skip
    finally:
        for undo in (restore, *restores):
            undo()
    w = np.array([q.value for q in branch.points]) * p["crit"]
    r = np.array([q.max_radius_m for q in branch.points])
    folds = sorted(b.value * p["crit"] for b in branch.bifurcations if b.type == "fold")
    edges = np.concatenate([[t0], stamps])
    at = np.searchsorted(edges, np.concatenate(located)) - 1  # interval of each location
    mask = np.zeros(len(stamps), bool)
    mask[np.clip(at, 0, len(stamps) - 1)] = True
    return w, r, folds, np.diff(edges), mask


# ---- pyHarm ------------------------------------------------------------------------------------
@functools.cache
def pyharm_contact_class():
    """A radial penalty contact with Coulomb friction as a pyHarm node-to-node element."""
    from pyHarm.Elements.NodeToNodeElements.NodeToNodeElement import NodeToNodeElement

    class RadialPenaltyContact(NodeToNodeElement):
        """``R = k (r - g)_+ (e_r + mu s e_t)`` on the two directions of ``dirs`` (AFT).

        ``g`` gap (m), ``k`` penalty stiffness (N/m), ``mu`` friction coefficient, ``s`` = +1
        for spin in the direction from the first to the second direction of ``dirs``.
        """

        factory_keyword = "RadialPenaltyContact"

        def __post_init__(self):
            self.g, self.k = float(self.data["g"]), float(self.data["k"])
            self.mu, self.s = float(self.data["mu"]), float(self.data.get("s", 1.0))

        def __flag_update__(self):
            self.flag_nonlinear = True
            self.flag_AFT = True

        def adim(self, lc, wc):
            self.g, self.k = self.g / lc, self.k * lc
            self.flag_adim = True

        def _time(self, xg):
            sel = self.Pslave - self.Pmaster
            proj = [self.Pdir[i] @ sel for i in range(2)]
            x = xg[self.indices]
            return proj, [(pr @ x) @ self.D["ft"] for pr in proj]

        def evalResidual(self, xg, om):
            proj, (u, v) = self._time(xg)
            r = np.hypot(u, v)
            a = self.k * np.clip(1.0 - self.g / np.maximum(r, 1e-300), 0.0, None)  # pen / r
            fx, fy = a * (u - self.mu * self.s * v), a * (v + self.mu * self.s * u)
            self.R = proj[0].T @ (fx @ self.D["tf"]) + proj[1].T @ (fy @ self.D["tf"])
            return self.R

        def evalJacobian(self, xg, om):
            proj, (u, v) = self._time(xg)
            r = np.maximum(np.hypot(u, v), 1e-100)
            on = r > self.g
            a = np.where(on, self.k * (1.0 - self.g / r), 0.0)
            b = np.where(on, self.k * self.g / r**3, 0.0)  # d(pen / r) / dx = b x
            ms = self.mu * self.s
            tx, ty = u - ms * v, v + ms * u
            d = {(0, 0): a + tx * b * u, (0, 1): -ms * a + tx * b * v,
                 (1, 0): ms * a + ty * b * u, (1, 1): a + ty * b * v}  # fmt: skip
            ft, tf = self.D["ft"], self.D["tf"]
            n = len(self.indices)
            self.J = np.zeros((n, n))
            for (i, j), dij in d.items():
                self.J += proj[i].T @ ((ft * dij) @ tf).T @ proj[j]
            self.dJdom = np.zeros((n, 1))
            return self.J, self.dJdom

        def __str__(self):
            return f"RadialPenaltyContact(g={self.g}, k={self.k}, mu={self.mu})"

    return RadialPenaltyContact


def pyharm_input(p: dict, crit: float, nh: int, nti: int, ds: float, tol: float, span) -> dict:
    eye = np.eye(2)
    load = {"side_load": {"type": "GOForcing", "connect": {"rotor": [0]}, "dirs": [0],
                          "amp": p["fy"], "ho": 0, "dto": 0}} if p["fy"] else {}  # fmt: skip
    lo, hi = sorted(span)
    return {
        "plugin": [] if _REGISTERED else [pyharm_contact_class()],
        "system": {"type": "Base", "nh": nh, "nti": nti,
                   "adim": {"status": True, "lc": p["g"], "wc": crit}},
        "substructures": {"rotor": {"matrix": {"M": p["m"] * eye, "K": p["k"] * eye,
                                               "C": p["c"] * eye}, "ndofs": 2}},
        "connectors": {
            "unbalance_x": {"type": "GOForcing", "connect": {"rotor": [0]}, "dirs": [0],
                            "amp": p["u"], "ho": 1, "dto": 2, "phi": 0.0},
            "unbalance_y": {"type": "GOForcing", "connect": {"rotor": [0]}, "dirs": [1],
                            "amp": p["u"], "ho": 1, "dto": 2, "phi": math.pi / 2},
            "stator": {"type": "RadialPenaltyContact", "connect": {"rotor": [0]}, "dirs": [0, 1],
                       "g": p["g"], "k": p["kc"], "mu": p["mu"], "s": 1.0},
            **load,
        },
        "analysis": {"branch": {
            "study": "frf", "puls_inf": lo * crit, "puls_sup": hi * crit,
            "sign_ds": -1 if span[1] < span[0] else 1, "ds0": ds, "ds_max": ds, "ds_min": 1e-8,
            "predictor": "tangent", "corrector": "arc_length", "solver": "NewtonRaphson",
            "solver_options": {"tol_residual": tol, "tol_delta_x": tol, "max_iter": 50},
            "stopper": "bounds", "verbose": VERBOSE,
        }},
    }  # fmt: skip


def run_pyharm(p: dict, crit: float, nh: int, nti: int, ds: float, tol: float, span):
    """pyHarm's branch: accepted points' speeds (rad/s), largest radii (m), per-point times (s).

    The radius is the largest of the harmonic series on 4096 instants per revolution (what
    the series represents, not only its ``nti`` AFT samples).
    """
    import pyHarm
    from pyHarm.Analysis.FRF_NonLinear import FRF_NonLinear
    from pyHarm.DynamicOperator import compute_DFT

    if not VERBOSE:
        logging.disable(logging.WARNING)  # pyHarm's banner and per-point log lines
    stamps, restore = _stamps(FRF_NonLinear, "makeStep",
                              lambda self, out: self.SolList[-1].flag_accepted)  # fmt: skip
    t0 = time.perf_counter()
    try:
        maestro = pyHarm.Maestro(pyharm_input(p, crit, nh, nti, ds, tol, span))
        _REGISTERED.append(True)  # the factory keeps the plugin: register it once
        maestro.operate()
    finally:
        restore()
        logging.disable(logging.NOTSET)
    edf = maestro.system.expl_dofs
    dft = compute_DFT(4096, nh)["ft"]
    ix = edf[(edf["sub"] == "rotor") & (edf["dof_num"] == 0)].index.to_numpy()
    iy = edf[(edf["sub"] == "rotor") & (edf["dof_num"] == 1)].index.to_numpy()
    sols = [s for s in maestro.nls["branch"].SolList if s.flag_accepted]
    w = np.array([s.x[-1] for s in sols]) * crit
    r = np.array([np.max(np.hypot(s.x[ix] @ dft, s.x[iy] @ dft)) for s in sols]) * p["g"]
    # per-point times from the second accepted point on (the first is solved before any step)
    return w, r, per_point(t0, stamps)


def _measure(rows: dict, repeats: int) -> dict:
    """Run every row ``repeats`` times, interleaved; medians over the repeats.

    ``rows[label]() -> (w, r, turns, per_point_times, located)``; returns ``label -> (total s,
    w, r, turns, per-point times, located)`` with the median total and, per point, the median
    of that point's time over the repeats (both codes are deterministic, so the points are the
    same in every repeat; the median removes the scheduler's pauses on the shared cores, which
    would otherwise decide the worst point).
    """
    runs: dict = {label: [] for label in rows}
    for _ in range(repeats):
        for label, run in rows.items():
            t0 = time.perf_counter()
            out = run()
            runs[label].append((time.perf_counter() - t0, *out))
    res = {}
    for label, got in runs.items():
        mid = sorted(got, key=lambda x: x[0])[len(got) // 2]
        pps = [g[4] for g in got if g[4].shape == mid[4].shape]
        res[label] = (*mid[:4], np.median(np.stack(pps), axis=0), mid[5])
    return res


def _line(label: str, total: float, w, err, pp, mask) -> str:
    """One row: points, mean / best / median / worst time per point (ms), error max / median.

    ``worst`` leaves out the first point (setup and first solve) and the points during which
    a bifurcation or contact onset was located (``mask``; their worst is given apart).
    """
    plain = pp[1:][~mask[1:]]
    loc = f", worst with a location {1e3 * pp[mask].max():.1f}" if mask.any() else ""
    return (f"{label}: {len(w)} points, {1e3 * total / len(w):.2f} ms/point mean (best "
            f"{1e3 * plain.min():.2f}, median {1e3 * np.median(pp):.2f}, worst "
            f"{1e3 * plain.max():.2f}{loc}); "
            f"error max {err.max():.1e}, median {np.median(err):.1e}")  # fmt: skip


ROUNDING = 1e-14
"""Errors below this are rounding of the points themselves, so their order says nothing about
the method: the synchronous route's points, whose rotating-frame residual is ~1e-16, are 1.7e-15
off the curve also when the distance is evaluated in 40 digits (mpmath); pyHarm's measure
1.0e-15 to 1.7e-15."""


def _ratios(res: dict, errors: dict, ours: list, theirs: list) -> None:
    """Time ratios ours / pyHarm: mean per point and the every-point one, with accuracy verdict.

    Every point: ``max over our points / min over pyHarm's points`` of the time per point
    (the first point of each, which holds the setup and the first solve, and our points that
    located a bifurcation or contact onset, which pyHarm does not do, left out): below 1 means
    each of those points of ours cost less than any of pyHarm's.
    """
    for a in ours:
        for b in theirs:
            ta, tb = res[a], res[b]
            mean = (ta[0] / len(ta[1])) / (tb[0] / len(tb[1]))
            every = ta[4][1:][~ta[5][1:]].max() / tb[4][1:].min()
            ea, eb = errors[a].max(), errors[b].max()
            if max(ea, eb) < ROUNDING:
                acc = f"equal accuracy: both at rounding ({ea:.1e} vs {eb:.1e})"
            else:
                acc = "equal-or-better accuracy" if ea <= eb else (
                    f"LESS accurate ({ea:.0e} vs {eb:.0e})")  # fmt: skip
            ok = "faster on every point" if every < 1 else "NOT faster on every point"
            print(f"  {a} / {b}: mean {mean:.2f}, every point (max/min) {every:.2f} -> {ok}, "
                  f"{acc}")  # fmt: skip


def annular(repeats: int) -> None:
    """The full annular rub (a circular orbit: harmonic balance with one harmonic is exact)."""
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / "one_mode_annular_rub.toml")
    # pyHarm's contact (and the closed form) has the exact Coulomb sign; rubrotor's default
    # smoothing (s = v / sqrt(v^2 + v_r^2)) shifts this curve by ~1e-13: the same law here
    sc = sc.with_changes(**{"contact.friction_regularization": 1e-9})
    p = one_mode(sc)
    exact = closed_form_turns(p)
    print(f"== full annular rub, {START} -> {STOP} x critical ==\nclosed form: contact onset "
          f"{exact[0] / p['crit']:.12f}, fold {exact[1] / p['crit']:.12f} x critical "
          f"({p['crit']:.3f} rad/s)")  # fmt: skip
    span = (START, STOP)
    sync = "rubrotor synchronous (rotating-frame equilibria, the default route here)"
    rows = {sync: functools.partial(run_ours, sc, p, 256, False, span, method="synchronous")}
    rows.update({f"rubrotor shooting {n} steps/rev{' + Richardson ' + str(2 * n) if rich else ''}":
                 functools.partial(run_ours, sc, p, n, rich, span)
                 for n, rich in ((256, False), (1024, False), (128, True), (256, True))})  # fmt: skip
    ours = list(rows)
    for nh, ds in ((1, 0.15), (1, 0.05), (3, 0.15)):
        rows[f"pyHarm nh={nh} ds={ds}"] = pyharm_row(p, nh, ds, span)
    res = _measure(rows, repeats)
    errors = {}
    for label, (total, w, r, turns, pp, mask) in res.items():
        errors[label] = curve_error(p, r, w)
        print(_line(label, total, w, errors[label], pp, mask))
        terr = [f"{abs(t - x) / x:.1e}" for t, x in zip(sorted(turns), exact, strict=False)]
        print(f"    turning points (x critical): {[round(t / p['crit'], 9) for t in turns]}; "
              f"errors {terr}")  # fmt: skip
    print("time per point, rubrotor / pyHarm:")
    _ratios(res, errors, ours, [k for k in res if k not in ours])


def pyharm_row(p: dict, nh: int, ds: float, span):
    """A row running pyHarm with ``nh`` harmonics (``16 (2 nh + 1)`` AFT instants), step ``ds``;
    its turning points from the parabola through three points around each turn."""

    def run():
        w, r, pp = run_pyharm(p, p["crit"], nh, 16 * (2 * nh + 1), ds, 1e-10, span)
        return w, r, turning_points(w), pp, np.zeros(pp.size, bool)

    return run


def reference_radii(sc, p: dict, w, guesses, steps: int) -> np.ndarray:
    """Largest radii (m) of the period-1 orbits at speeds ``w`` (rad/s) by shooting at ``steps``.

    ``guesses``: ``(speed rad/s, RotorState)`` pairs of a coarser branch; each orbit starts
    from the nearest one's state.
    """
    ws = np.array([g[0] for g in guesses])
    out = []
    for wi in w:
        sci = sc.with_changes(**{KEY: float(wi / p["crit"])})
        orb = shooting.shoot(sci, guesses[int(np.argmin(np.abs(ws - wi)))][1], steps=steps)
        out.append(shooting._Map(sci, 1, steps).run(shooting.state_vector(orb.state))[2])
    return np.array(out)


PARTIAL_SPAN = (1.9, 2.05)
"""Period-1 partial rub of ``one_mode_partial_rub.toml`` (x critical), up to just below its
period doubling at 2.0575."""
REFERENCE_STEPS = 16384


def partial(repeats: int) -> None:
    """The partial rub (one impact per revolution): harmonic balance is no longer exact."""
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / "one_mode_partial_rub.toml")
    p = one_mode(sc)
    span = PARTIAL_SPAN
    print(f"== partial rub (side load {p['fy']:g} N), {span[0]} -> {span[1]} x critical ==")
    rows = {f"rubrotor {n} steps/rev{' + Richardson ' + str(2 * n) if rich else ''}":
            functools.partial(run_ours, sc, p, n, rich, span, ds_max=0.01)
            for n, rich in ((256, False), (1024, False), (2048, False), (4096, False),
                            (1024, True))}  # fmt: skip
    ours = list(rows)
    for nh in PARTIAL_HARMONICS:
        rows[f"pyHarm nh={nh} ds={PARTIAL_DS}"] = pyharm_row(p, nh, PARTIAL_DS, span)
    res = _measure(rows, repeats)
    guide = continue_orbit(sc, KEY, *span, steps=1024, points=400, ds_max=0.01)
    guesses = [(q.value * p["crit"], q.state) for q in guide.points]
    errors = {}
    for label, (total, w, r, _, pp, mask) in res.items():
        ref = reference_radii(sc, p, w, guesses, REFERENCE_STEPS)
        errors[label] = np.abs(r - ref) / ref
        print(_line(label, total, w, errors[label], pp, mask))
    w_chk = np.array([guesses[0][0], guesses[len(guesses) // 2][0], guesses[-1][0]])
    a = reference_radii(sc, p, w_chk, guesses, REFERENCE_STEPS)
    b = reference_radii(sc, p, w_chk, guesses, 2 * REFERENCE_STEPS)
    print(
        f"  (errors against shooting at {REFERENCE_STEPS} steps/rev, itself within "
        f"{np.max(np.abs(a - b) / b):.1e} of {2 * REFERENCE_STEPS} steps/rev)"
    )
    print("time per point, rubrotor / pyHarm:")
    _ratios(res, errors, ours, [k for k in res if k not in ours])


PARTIAL_HARMONICS = (5, 10, 20, 40)
PARTIAL_DS = 0.005


def main(repeats: int = 3, cases: str = "annular,partial") -> None:
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / "one_mode_annular_rub.toml")
    p = one_mode(sc)
    run_ours(sc, p, 64, True, (START, STOP), points=3)
    run_ours(sc, p, 64, False, (START, STOP), points=3, method="synchronous")
    run_pyharm(p, p["crit"], 1, 64, 0.5, 1e-10, (START, STOP))  # warm-up: numba / jax
    if "annular" in cases:
        annular(repeats)
    if "partial" in cases:
        partial(repeats)


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]), *sys.argv[2:3])
