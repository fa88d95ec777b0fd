"""``from_ross``: a ROSS rotor imported into rubrotor keeps ROSS's matrices and modes.

References are ROSS itself (an independent code): its global matrices ``M(f)``, ``K(f)``,
``C(f)``, ``G()`` after the documented DOF mapping, and its ``run_modal`` damped natural
frequencies. Skipped when ROSS is not installed (``pip install "rubrotor[ross]"``).
"""

import contextlib
import io
import os
import warnings

import numpy as np
import pytest
import scipy.linalg as sl

with warnings.catch_warnings():  # ROSS's import warns about REFPROP (its ccp dependency)
    warnings.simplefilter("ignore")
    if os.environ.get("RUBROTOR_REQUIRE_ROSS"):  # CI's ROSS step: a missing ROSS is a failure
        import ross
    else:
        ross = pytest.importorskip("ross")

from rubrotor.rotors.ross import from_ross, ross_dof_map  # noqa: E402

pytestmark = pytest.mark.filterwarnings("ignore")


def _anisotropic_rotor():
    """Hand-built ROSS rotor: 12 hollow steel elements, 2 disks, anisotropic cross-coupled
    bearings with speed tables (4 points: ROSS's spline passes through them)."""
    steel = ross.Material(name="steel_ix", rho=7810, E=211e9, Poisson=0.3)
    shaft = [
        ross.ShaftElement(L=0.1, idl=0.01, odl=0.05 if i < 6 else 0.04, material=steel, n=i)
        for i in range(12)
    ]
    disks = [
        ross.DiskElement(n=4, m=8.0, Id=0.03, Ip=0.06),
        ross.DiskElement(n=9, m=5.0, Id=0.02, Ip=0.035),
    ]
    f = np.array([0.0, 300.0, 600.0, 900.0])
    bearings = [
        ross.BearingElement(
            n=n,
            frequency=f,
            kxx=2e7 + 1e4 * f,
            kyy=4e7 + 2e4 * f,
            kxy=3e6 + 5e3 * f,
            kyx=-2e6 - 5e3 * f,
            cxx=1e3 + f,
            cyy=2e3 + f,
            cxy=50.0 + 0 * f,
            cyx=-40.0 + 0 * f,
        )
        for n in (0, 12)
    ]
    return ross.Rotor(shaft, disks, bearings)


@pytest.fixture(scope="module", params=["rotor_example", "anisotropic"])
def rotor(request):
    with contextlib.redirect_stdout(io.StringIO()):
        return ross.rotor_example() if request.param == "rotor_example" else _anisotropic_rotor()


def _ross_on_ours(rotor, a):
    idx, sign = ross_dof_map(len(rotor.nodes_pos), rotor.number_dof)
    return sign[:, None] * a[np.ix_(idx, idx)] * sign[None, :]


@pytest.mark.parametrize("speed", [0.0, 300.0, 600.0])
def test_matrices_equal_ross_after_mapping(rotor, speed):
    """``M, C + speed G, K`` at a table speed equal ROSS's after ``T^T (.) T`` (to round-off)."""
    ours = from_ross(rotor).matrices(speed)
    pairs = [
        (ours.M, rotor.M(speed)),
        (ours.K, rotor.K(speed)),
        (ours.C, rotor.C(speed)),
        (ours.G, rotor.G()),
    ]
    for mine, theirs in pairs:
        ref = _ross_on_ours(rotor, np.asarray(theirs, float))
        assert np.abs(mine - ref).max() <= 1e-12 * np.abs(ref).max()


def test_gyroscopic_convention(rotor):
    """ROSS's gyroscopic matrix maps onto ours: ``+Ip`` at ``(psi_v, psi_w)`` (spin y -> z)."""
    g = from_ross(rotor).G
    blocks = np.array([g[4 * i + 2, 4 * i + 3] for i in range(len(rotor.nodes_pos))])
    assert np.all(blocks >= 0.0) and blocks.max() > 0.0
    assert np.allclose(g, -g.T, rtol=0, atol=1e-15 * np.abs(g).max())


@pytest.mark.parametrize("speed", [0.0, 600.0])
def test_damped_frequencies_equal_run_modal(rotor, speed):
    """Every lateral eigenvalue of ROSS's ``run_modal`` (eigenvector with lateral content), the
    lowest 12, equals ours to 1e-6 relative, and we find no other mode below the 12th."""
    with contextlib.redirect_stdout(io.StringIO()):
        modal = rotor.run_modal(speed, num_modes=30)
    idx, _ = ross_dof_map(len(rotor.nodes_pos), rotor.number_dof)
    vec = np.asarray(modal.evectors)[: rotor.ndof]
    lateral = np.linalg.norm(vec[idx], axis=0) > 1e-6 * np.linalg.norm(vec, axis=0)
    wd = np.asarray(modal.evalues).imag[lateral]
    wd = np.sort(wd[wd > 1e-3])
    wd = wd[:12]  # the lowest 12 lateral modes (ROSS's sparse solver blurs the top ones)
    assert len(wd) == 12
    a, _ = from_ross(rotor).matrices(speed).first_order()
    lam = sl.eigvals(a)
    ours = np.sort(lam.imag[lam.imag > 1e-3])
    ours = ours[ours <= wd[-1] * (1 + 1e-6)]
    assert len(ours) == len(wd)
    assert np.max(np.abs(ours - wd) / wd) <= 1e-6


# ---- same rotor, same mesh: our element builder against ROSS's elements -----------------------
ROSS_THEORY = {
    "timoshenko": dict(shear_effects=True, rotary_inertia=True, gyroscopic=True),
    "rayleigh": dict(shear_effects=False, rotary_inertia=True, gyroscopic=True),
    "euler-bernoulli": dict(shear_effects=False, rotary_inertia=False, gyroscopic=False),
}
TABLE = np.array([0.0, 300.0, 600.0, 900.0])  # rad/s
BEARING = dict(  # ours (y, z) = ROSS (x, y)
    kyy=2e7 + 1e4 * TABLE,
    kzz=4e7 + 2e4 * TABLE,
    kyz=3e6 + 5e3 * TABLE,
    kzy=-2e6 - 5e3 * TABLE,
    cyy=1e3 + TABLE,
    czz=2e3 + TABLE,
    cyz=50.0 + 0 * TABLE,
    czy=-40.0 + 0 * TABLE,
)


def _same_mesh_pair(theory):
    """The rotor of :func:`_anisotropic_rotor` with the beam ``theory``, built in ROSS and, from
    the same description, with :class:`rubrotor.rotors.fe.Rotor` (two sections of 6 elements)."""
    from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section

    steel = ross.Material(name="steel_same_mesh", rho=7810, E=211e9, Poisson=0.3)
    shaft = [
        ross.ShaftElement(
            L=0.1, idl=0.01, odl=0.05 if i < 6 else 0.04, material=steel, **ROSS_THEORY[theory]
        )
        for i in range(12)
    ]
    disks = [
        ross.DiskElement(n=4, m=8.0, Id=0.03, Ip=0.06),
        ross.DiskElement(n=9, m=5.0, Id=0.02, Ip=0.035),
    ]
    names = {"kyy": "kxx", "kzz": "kyy", "kyz": "kxy", "kzy": "kyx"}
    names |= {"c" + k[1:]: "c" + v[1:] for k, v in names.items()}
    brg = {names[k]: v for k, v in BEARING.items()}
    bearings = [ross.BearingElement(n=n, frequency=TABLE, **brg) for n in (0, 12)]
    with contextlib.redirect_stdout(io.StringIO()):
        theirs = ross.Rotor(shaft, disks, bearings)
    mat = Material("steel", 211e9, 7810, poisson_ratio=0.3)
    ours = Rotor(
        [Section(0.6, 0.05, mat, 0.01, elements=6), Section(0.6, 0.04, mat, 0.01, elements=6)],
        disks=[Disk(0.4, 8.0, 0.06, 0.03), Disk(0.9, 5.0, 0.035, 0.02)],
        bearings=[Bearing(x, speeds=TABLE, **BEARING) for x in (0.0, 1.2)],
        theory=theory,
        shear_coefficient="cowper",
    )
    return ours.linear_system(), theirs


@pytest.mark.parametrize("theory", list(ROSS_THEORY))
def test_same_mesh_elements_equal_ross(theory):
    """Same nodes, material, Cowper shear coefficient (hollow-section form in both) and beam
    theory (ROSS's ``shear_effects``/``rotary_inertia``/``gyroscopic`` switches): our assembled
    ``M``, ``K`` (bearings at each table speed), ``G`` equal ROSS's element matrices mapped by
    :func:`from_ross` to 1e-13 of their largest entry (measured <= 8.9e-16), and our damped
    frequencies equal ROSS's ``run_modal`` (lowest 12 lateral modes) to 1e-6 (the issue's goal;
    measured <= 3.7e-10 at 0 and 600 rad/s, ROSS 2.3)."""
    ours, theirs = _same_mesh_pair(theory)
    mapped = from_ross(theirs)
    np.testing.assert_allclose(ours.basis.nodes, mapped.basis.nodes, rtol=0, atol=1e-12)
    for speed in TABLE:
        a, b = ours.matrices(speed), mapped.matrices(speed)
        for mine, ref in ((a.M, b.M), (a.K, b.K), (a.G, b.G), (a.damping, b.damping)):
            assert np.abs(mine - ref).max() <= 1e-13 * max(np.abs(ref).max(), 1e-300)
    for speed in (0.0, 600.0):
        with contextlib.redirect_stdout(io.StringIO()):
            modal = theirs.run_modal(speed, num_modes=30)
        idx, _ = ross_dof_map(len(theirs.nodes_pos), theirs.number_dof)
        vec = np.asarray(modal.evectors)[: theirs.ndof]
        lateral = np.linalg.norm(vec[idx], axis=0) > 1e-6 * np.linalg.norm(vec, axis=0)
        wd = np.asarray(modal.evalues).imag[lateral]
        wd = np.sort(wd[wd > 1e-3])[:12]
        lam = sl.eigvals(ours.matrices(speed).first_order()[0])
        mine = np.sort(lam.imag[lam.imag > 1e-3])[:12]
        assert np.max(np.abs(mine - wd) / wd) <= 1e-6
