"""Continuation of the one-mode rotor's full-annular-rub branch: rubrotor against pyHarm.

The same rotor in both codes: one Euler-Bernoulli mode of ``one_mode_annular_rub.toml``
(modal mass ``m``, stiffness ``k``, damping ``c = 2 zeta sqrt(k m)``, mode shape 1 at midspan),
unbalance ``u = m_e e`` at midspan, a radial penalty contact ``f = -k_c (r - g)_+ (e_r + mu e_t)``
with friction ``mu`` opposing the forward spin. rubrotor continues it by shooting (fixed-step
exponential map, finite-difference monodromy, Floquet multipliers at every point); pyHarm
(``pyharm-os``, optional group ``pyharm``) by harmonic balance with its arc-length corrector.
pyHarm ships no rotor-stator contact with friction, so :class:`RadialPenaltyContact` below adds
one through pyHarm's documented plugin route (a subclass of its node-to-node element base,
registered by ``Maestro({"plugin": [...]})``), evaluated by alternating frequency/time (AFT)
with its analytic Jacobian.

Both continue the speed from 1.8 down to 1.2 x the first critical speed: down the no-contact
orbit to contact onset (a non-smooth turning point), back up the unstable rub branch to its
fold and down the stable rub branch. Accuracy of every branch point: its relative distance
(in ``(r, W)`` scaled by the point) to the closed-form curve ``[(k - m W^2) r + k_c (r - g)]^2 +
[c W r + mu k_c (r - g)]^2 = (u W^2)^2`` (or the linear response without contact). The
synchronous orbit is a circle, so its contact force is a pure first harmonic and harmonic
balance with one harmonic is exact for it: pyHarm's error is its solver tolerance, whatever
the harmonic count; rubrotor's is the second-order error of the time-stepping map, which
falls with the steps per revolution.

Run (pyHarm lives in its own venv, which sees the system site packages):
``OPENBLAS_NUM_THREADS=1 PYTHONPATH=src /work/venvs/pyharm/bin/python
benchmarks/bench_continuation_vs_pyharm.py [REPEATS]``. Prints, per configuration, the median
wall time per branch point (interleaved repeats, one process, numba/jax compilation excluded by
a warm-up), the ratio, the largest and median errors and the turning points each finds
against the closed form's.
"""

from __future__ import annotations

import functools
import logging
import math
import statistics
import sys
import time
from importlib import resources

import numpy as np
import scipy.optimize

from rubrotor.continuation import continue_orbit
from rubrotor.model import modal_matrices
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
def run_ours(sc, p: dict, steps: int, points: int = 200):
    """rubrotor's branch: speeds (rad/s), largest radii (m) and located folds (rad/s)."""
    branch = continue_orbit(sc, KEY, START, STOP, steps=steps, points=points)
    w = np.array([q.value for q in branch.points]) * p["crit"]
    r = np.array([q.max_radius_m for q in branch.points])
    folds = sorted(b.value * p["crit"] for b in branch.bifurcations if b.type == "fold")
    return w, r, folds


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


def pyharm_input(p: dict, crit: float, nh: int, nti: int, ds: float, tol: float) -> dict:
    eye = np.eye(2)
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
        },
        "analysis": {"branch": {
            "study": "frf", "puls_inf": STOP * crit, "puls_sup": START * crit,
            "sign_ds": -1, "ds0": ds, "ds_max": ds, "ds_min": 1e-8,
            "predictor": "tangent", "corrector": "arc_length", "solver": "NewtonRaphson",
            "solver_options": {"tol_residual": tol, "tol_delta_x": tol, "max_iter": 50},
            "stopper": "bounds", "verbose": VERBOSE,
        }},
    }  # fmt: skip


def run_pyharm(p: dict, crit: float, nh: int, nti: int, ds: float, tol: float):
    """pyHarm's branch: accepted points' speeds (rad/s) and largest radii (m)."""
    import pyHarm
    from pyHarm.DynamicOperator import compute_DFT

    if not VERBOSE:
        logging.disable(logging.WARNING)  # pyHarm's banner and per-point log lines
    try:
        maestro = pyHarm.Maestro(pyharm_input(p, crit, nh, nti, ds, tol))
        _REGISTERED.append(True)  # the factory keeps the plugin: register it once
        maestro.operate()
    finally:
        logging.disable(logging.NOTSET)
    edf = maestro.system.expl_dofs
    dft = compute_DFT(nti, nh)["ft"]
    ix = edf[(edf["sub"] == "rotor") & (edf["dof_num"] == 0)].index.to_numpy()
    iy = edf[(edf["sub"] == "rotor") & (edf["dof_num"] == 1)].index.to_numpy()
    sols = [s for s in maestro.nls["branch"].SolList if s.flag_accepted]
    w = np.array([s.x[-1] for s in sols]) * crit
    r = np.array([np.max(np.hypot(s.x[ix] @ dft, s.x[iy] @ dft)) for s in sols]) * p["g"]
    return w, r


def _report(name: str, seconds: float, w, r, turns, p: dict, exact) -> float:
    e = curve_error(p, r, w)
    per = seconds / len(w)
    crit = p["crit"]
    print(f"{name}: {len(w)} points, {seconds:.2f} s, {1e3 * per:.2f} ms per branch point; "
          f"error max {e.max():.1e}, median {np.median(e):.1e}")  # fmt: skip
    print(
        f"    turning points (x critical): {[round(t / crit, 9) for t in turns]}; "
        f"errors {[f'{abs(t - x) / x:.1e}' for t, x in zip(sorted(turns), exact, strict=False)]}"
    )
    return per


def main(repeats: int = 3) -> None:
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / "one_mode_annular_rub.toml")
    p = one_mode(sc)
    exact = closed_form_turns(p)
    print(f"closed form: contact onset {exact[0] / p['crit']:.12f}, fold "
          f"{exact[1] / p['crit']:.12f} x critical ({p['crit']:.3f} rad/s)")  # fmt: skip
    ours = {steps: [] for steps in (256, 1024)}
    theirs = {(nh, ds): [] for nh, ds in ((1, 0.15), (1, 0.05), (3, 0.15))}
    run_ours(sc, p, 256, points=3)
    run_pyharm(p, p["crit"], 1, 64, 0.5, 1e-10)  # warm-up: numba / jax compilation
    out = {}
    for _ in range(repeats):
        for steps, times in ours.items():
            t0 = time.perf_counter()
            out[steps] = run_ours(sc, p, steps)
            times.append(time.perf_counter() - t0)
        for (nh, ds), times in theirs.items():
            t0 = time.perf_counter()
            out[nh, ds] = run_pyharm(p, p["crit"], nh, 16 * (2 * nh + 1), ds, 1e-10)
            times.append(time.perf_counter() - t0)
    per = {}
    for steps, times in ours.items():
        w, r, folds = out[steps]
        per[steps] = _report(f"rubrotor shooting, {steps} steps/rev", statistics.median(times),
                             w, r, folds, p, exact)  # fmt: skip
    for (nh, ds), times in theirs.items():
        w, r = out[nh, ds]
        per[nh, ds] = _report(f"pyHarm HBM, {nh} harmonic(s), ds {ds}", statistics.median(times),
                              w, r, turning_points(w), p, exact)  # fmt: skip
    for steps in ours:
        for key in theirs:
            print(f"time per point, rubrotor {steps} steps / pyHarm nh={key[0]} ds={key[1]}: "
                  f"{per[steps] / per[key]:.1f}")  # fmt: skip


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))
