"""The ARPACK + Petrov-Galerkin route of the modal reduction against the dense route.

Reference: :func:`rubrotor.engine.reduce.reduce_matrices`, the dense eigen-decomposition of the
full first-order matrix (a second numerical route: LAPACK ``geev`` on all ``2 n`` eigenvalues
instead of ARPACK on a few), whose residual and run results are tested against full-DOF SciPy
runs in tests/test_engine.py.
"""

import numpy as np
import pytest

from rubrotor.engine import reduce as red
from rubrotor.engine.driver import simulate_general
from rubrotor.engine.parts import RubStation, Run, Stator
from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section
from rubrotor.rotors.forces import Contact, Unbalance

STEEL = Material("steel", 211e9, 7810, poisson_ratio=0.3)
SPEED = 400.0  # rad/s


def rotor_case():
    """30-element rotor, two disks, anisotropic cross-coupled bearings, rub at a disk."""
    rotor = Rotor(
        [Section(1.5, 0.05, STEEL, elements=30)],
        disks=[Disk(0.5, 15.0, 0.1, 0.05), Disk(1.0, 10.0, 0.08, 0.04)],
        bearings=[
            Bearing(0.0, kyy=5e6, kzz=7e6, kyz=1e6, kzy=-8e5, cyy=500, czz=600),
            Bearing(1.5, kyy=6e6, kzz=5e6, kyz=5e5, kzy=-5e5, cyy=500, czz=500),
        ],
    )
    con = Contact(clearance=1e-4, stiffness=5e7, damping=300, friction=0.2, position=0.5,
                  law="linear", radius=0.12)  # fmt: skip
    st = [RubStation(con, offset_y=-5e-5, stator=Stator(30, 30, 2e7, 2e7, 800, 800))]
    return rotor.linear_system(), st, [Unbalance(5e-4, 0.5), Unbalance(3e-4, 1.0, 1.0)]


@pytest.mark.parametrize("keep", [4, 10])
def test_arpack_route_equals_dense_route(keep):
    """A few modes of a 124-DOF rotor by ARPACK and the projection: the same eigenvalues, the
    same modal input and output at the contact station, the same residual feed-through there
    and the same modal projection of a state as the dense route, to rounding."""
    system, st, _ = rotor_case()
    sm = system.matrices(SPEED)
    B = system.force_map(st[0].contact.position)
    assert red.partial_route(sm.M.shape[0], keep, None, B)
    dense = red.reduce_matrices(sm.M, sm.damping, sm.K, keep)
    auto = red.reduce_auto(sm.M, sm.damping, sm.K, keep, fmap=B)
    assert auto.n_total < sm.M.shape[0]  # the projected route was taken (size r < n)
    np.testing.assert_allclose(auto.lam, dense.lam, rtol=1e-9)

    def rel(a, b):
        return np.max(np.abs(a - b)) / np.max(np.abs(b))

    assert rel(B.T @ auto.Vq @ auto.U @ B, B.T @ dense.Vq @ dense.U @ B) < 1e-8
    assert rel(B.T @ auto.Rq @ B, B.T @ dense.Rq @ B) < 1e-6  # K^-1 minus the kept modes
    assert rel(B.T @ auto.Rv @ B, B.T @ dense.Rv @ B) < 1e-8
    x = np.random.default_rng(3).standard_normal(2 * sm.M.shape[0])
    assert rel(B.T @ np.real(auto.Vq @ auto.project(x)),
               B.T @ np.real(dense.Vq @ dense.project(x))) < 1e-8  # fmt: skip


def test_arpack_route_run_equals_dense_route_run(monkeypatch):
    """A rubbing run (flexible offset stator, friction, gravity, two unbalances, 8 modes) built
    on the ARPACK route gives the dense route's samples to 1e-7 of the orbit."""
    system, st, unb = rotor_case()
    run = Run(speed=SPEED, duration=0.05, step=2e-5, save_every=5, modes=8, initial="rest")
    auto = simulate_general(system, run, st, unb, gravity=(-9.81, 0.0), progress=False)
    monkeypatch.setattr(red, "partial_route", lambda *a: False)
    dense = simulate_general(system, run, st, unb, gravity=(-9.81, 0.0), progress=False)
    assert dense.stats["modes_total"] > auto.stats["modes_total"]  # the two routes ran
    assert auto.stats["contact_events"] > 0
    x, ref = auto.channels[:2], dense.channels[:2]
    print("ARPACK vs dense route", np.max(np.abs(x - ref)) / np.max(np.abs(ref)))
    assert np.max(np.abs(x - ref)) / np.max(np.abs(ref)) < 1e-7
