"""A rotor in short journal bearings rubbing on a seal: rubrotor against SciPy DOP853, equal error.

The case is ``oil_whip_rub.toml`` (0.8 m rotor, two Ocvirk short journal bearings, a seal at the
disk) run at 600 rad/s, below its oil-whirl threshold (725 rad/s), with 75 times its unbalance
so that the disk rubs the seal, over ``REVS`` revolutions from its static equilibrium (above the
threshold the whip with rub is chaotic, and two trajectories part whatever the integrator).
The same equations for both: the finite-element model with the whole film force at each
journal, the seal's linear contact law with friction and the unbalance; SciPy integrates all its
DOFs with DOP853 (the right-hand side in NumPy, the force laws from rubrotor's compiled kernels),
rubrotor its modal reduction (the file's ``modes`` plus residual flexibility) with the films as
rows of its implicit step.

1. A reference: DOP853 at rtol 1e-10.
2. rubrotor at the file's step: its error against the reference (disk orbit, max over the run,
   relative to the seal clearance) and its CPU time (after a warm-up run: compilation apart).
3. DOP853 at the loosest rtol of 1e-4, 1e-5, ... whose error is at most rubrotor's, timed.

Prints both errors, both times and the ratio. Run: ``python benchmarks/bench_film_rub.py``
(a few minutes: the reference is slow).
"""

from __future__ import annotations

import pathlib
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

import rubrotor
from rubrotor.core.terms import term_force
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.general import engine_problem
from rubrotor.engine.parts import static_load_vector, unbalance_phasor
from rubrotor.engine.result import to_dataset
from rubrotor.engine.settings import Integrator

REVS = 20
SCENARIO = pathlib.Path(rubrotor.__file__).parent / "scenarios" / "oil_whip_rub.toml"


def _problem():
    text = SCENARIO.read_text().replace("rad_per_s = 1000.0", "rad_per_s = 600.0")
    text = text.replace("magnitude = 2e-5", "magnitude = 1.5e-3")
    text += '\n[initial]\nstate = "static"\n'  # both start in static equilibrium
    sc = _load_text(text)
    integ = Integrator(revolutions=REVS, dt=2e-5, save_every=5, probes=(0.4,))
    system, run, kw, _ = engine_problem(sc, integ)
    return system, run, kw


def _load_text(text):
    import tempfile

    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as f:
        f.write(text)
    return rubrotor.load_scenario(f.name)


def full_model(system, run, kw):
    """The right-hand side on every DOF and the static state (fsolve on the whole forces)."""
    w = run.speed
    sm = system.matrices(w)
    M, D, K = sm.M, sm.damping, sm.K
    n = M.shape[0]
    minv = np.linalg.inv(M)
    f_s = static_load_vector(system, tuple(kw["loads"]), kw["gravity"])
    b_u = sum((unbalance_phasor(u, w) * (system.force_map(u.position) @ np.array([1, -1j]))
               for u in kw["unbalances"]), np.zeros(n, complex))  # fmt: skip
    from rubrotor.forces.contact import pack_row

    contacts = [(system.force_map(s.contact.position), np.array([s.offset_y, s.offset_z]),
                 pack_row(s.contact, s.contact.radius * w)) for s in kw["stations"]]  # fmt: skip
    films = [(system.force_map(b.position), b) for b in kw["supports"]]

    def forces(q, v):
        f = np.zeros(n)
        for B, off, cp in contacts:
            p, u = B.T @ q - off, B.T @ v
            fy, fz, _, _ = term_force(p[0], p[1], u[0], u[1], cp)
            f += B @ np.array([fy, fz])
        for B, b in films:
            p, u = B.T @ q, B.T @ v
            out = b.outputs(p[:, None], u[:, None], w)
            K0, C0 = np.asarray(b.stiffness), np.asarray(b.damping)
            # the linear system holds -K0 p - C0 u of the film: add it back
            f += B @ (np.array([out["film_force_y"][0], out["film_force_z"][0]]) + K0 @ p + C0 @ u)
        return f

    def rhs(t, x):
        q, v = x[:n], x[n:]
        f = f_s + (b_u * np.exp(1j * w * t)).real + forces(q, v) - D @ v - K @ q
        return np.concatenate([v, minv @ f])

    q0 = fsolve(lambda q: K @ q - f_s - forces(q, np.zeros(n)), np.linalg.solve(K, f_s),
                xtol=1e-13)  # fmt: skip
    return rhs, np.concatenate([q0, np.zeros(n)]), system.output_rows(0.4)


def ours(system, run, kw):
    t = time.process_time()
    res = simulate_general(system, run, **kw, progress=False)
    cpu = time.process_time() - t
    ds = to_dataset(res)
    i = int(np.flatnonzero(np.isclose(ds.station.values, 0.4))[0])
    return ds.time.values, np.stack([ds["v"].values[i], ds["w"].values[i]]), cpu


def scipy_run(rhs, x0, rows, t_eval, rtol):
    n = x0.size // 2
    t = time.process_time()
    sol = solve_ivp(rhs, (0.0, t_eval[-1]), x0, method="DOP853", t_eval=t_eval, rtol=rtol,
                    atol=rtol * 1e-6)  # fmt: skip
    cpu = time.process_time() - t
    return rows @ sol.y[:n], cpu, sol.nfev


def main():
    system, run, kw = _problem()
    clearance = kw["stations"][0].contact.clearance
    ours(system, run, kw)  # compile
    t, p, cpu_ours = ours(system, run, kw)
    rhs, x0, rows = full_model(system, run, kw)
    ref, cpu_ref, nfev = scipy_run(rhs, x0, rows, t, 1e-10)
    err_ours = np.max(np.abs(p - ref)) / clearance
    touch = np.max(np.hypot(*ref)) / clearance
    print(f"disk orbit reaches {touch:.2f} clearances (>1: it rubs)")
    print(f"reference DOP853 rtol 1e-10: {cpu_ref:.1f} s CPU, {nfev} evaluations")
    print(f"rubrotor (dt {run.step:g} s): error {err_ours:.2e} of the clearance, "
          f"{cpu_ours:.3f} s CPU")
    for rtol in (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9):
        q, cpu, nfev = scipy_run(rhs, x0, rows, t, rtol)
        err = np.max(np.abs(q - ref)) / clearance
        print(f"DOP853 rtol {rtol:g}: error {err:.2e}, {cpu:.2f} s CPU, {nfev} evaluations")
        if err <= err_ours:
            print(f"at equal error: DOP853 / rubrotor = {cpu / cpu_ours:.0f}x CPU")
            return
    print("DOP853 did not reach rubrotor's error below rtol 1e-9: the ratio is at least "
          f"{cpu / cpu_ours:.0f}x")


if __name__ == "__main__":
    main()
