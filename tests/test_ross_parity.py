"""ROSS's own test rotors through :func:`rubrotor.rotors.ross.from_ross`, against ROSS's results.

Reference: ROSS itself (``ross-rotordynamics``, an independent code), on rotors built the way
ROSS's test suite and examples build them: a ``rotor8``-style rotor (6 Timoshenko elements, two
disks, bearings tabulated against speed at 50 and 5000 rad/s), ROSS's ``compressor_example``
(91 elements, 56 nodes, 2 bearings and 12 seals tabulated against speed; against frequency in
ROSS 2.3), a rotor with a seal tabulated on a 2-D speed x frequency grid (ROSS 3.x), ROSS's
``rotor_example_amb_simple`` (magnetic bearings, heavy element damping; ROSS 3.x) and a rotor on
bearings linked to housing point masses, with bearing mass (ROSS's ``test_global_index`` rotor).
Compared at table speeds: eigenvalues (damped and undamped natural frequencies), log decs,
critical speeds and their damping ratios, Campbell diagrams and the unbalance response, each
to 1e-6 relative (measured 1e-9 ... 1e-13, printed by ``-s``). Runs where ROSS is installed
(CI's ROSS venvs: 2.3 on Python 3.11, 3.1 on Python 3.13); skipped otherwise.
"""

from __future__ import annotations

import contextlib
import io
import os
import warnings

import numpy as np
import pytest

with warnings.catch_warnings():  # ROSS's import warns about REFPROP (its ccp dependency)
    warnings.simplefilter("ignore")
    if os.environ.get("RUBROTOR_REQUIRE_ROSS"):  # CI's ROSS step: a missing ROSS is a failure
        import ross
    else:
        ross = pytest.importorskip("ross")

from rubrotor.errors import InputError  # noqa: E402
from rubrotor.linear.campbell import campbell_data  # noqa: E402
from rubrotor.linear.critical import linear_critical_speeds  # noqa: E402
from rubrotor.linear.modes import damped_modes  # noqa: E402
from rubrotor.linear.response import unbalance_response  # noqa: E402
from rubrotor.rotors.ross import from_ross, ross_dof_map  # noqa: E402

pytestmark = pytest.mark.filterwarnings("ignore")  # ROSS warns about extrapolated tables

ROSS3 = int(ross.__version__.split(".")[0]) >= 3
needs_ross3 = pytest.mark.skipif(not ROSS3, reason="speed x frequency tables and AMBs: ROSS 3.x")
TOL = 1e-6
STEEL = dict(name="steel_parity", rho=7810, E=211e9, G_s=81.2e9)


def _quiet(fn, *args, **kwargs):
    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


def _table(**kw) -> dict:
    """ROSS's axis keyword: ``speed=`` in 3.x, ``frequency=`` in 2.3 (its only axis)."""
    axis = kw.pop("axis")
    return {**kw, ("speed" if ROSS3 else "frequency"): axis}


def _shaft(n=6, length=0.25, od=0.05):
    steel = ross.Material(**STEEL)
    return [ross.ShaftElement(length, 0.0, od, material=steel) for _ in range(n)], steel


def rotor8():
    """ROSS's ``rotor8`` layout: bearings tabulated at 50 and 5000 rad/s (linear in both codes)."""
    shaft, steel = _shaft()
    disks = [
        ross.DiskElement.from_geometry(n=2, material=steel, width=0.07, i_d=0.05, o_d=0.28),
        ross.DiskElement.from_geometry(n=4, material=steel, width=0.07, i_d=0.05, o_d=0.35),
    ]
    k, c = [1e7, 1.5e7], [1e3, 1.5e3]
    bearings = [
        ross.BearingElement(n, **_table(kxx=k, kyy=k, cxx=c, cyy=c, axis=[50.0, 5000.0]))
        for n in (0, 6)
    ]
    return ross.Rotor(shaft, disks, bearings)


def housings():
    """ROSS's ``test_global_index`` rotor: bearings linked to housing point masses on supports,
    plus bearing mass and an anisotropic cross-coupled support."""
    shaft, steel = _shaft()
    disks = [
        ross.DiskElement.from_geometry(n=2, material=steel, width=0.07, i_d=0.05, o_d=0.28),
        ross.DiskElement.from_geometry(n=4, material=steel, width=0.07, i_d=0.05, o_d=0.28),
    ]
    bearings = [
        ross.BearingElement(0, n_link=7, kxx=1e6, kyy=0.8e6, cxx=50.0, tag="brg0"),
        ross.BearingElement(6, n_link=8, kxx=1e6, kyy=0.8e6, kxy=2e5, kyx=-2e5, cxx=80.0),
        ross.BearingElement(7, kxx=5e6, kyy=4e6, cxx=200.0, mxx=0.4, tag="support0"),
        ross.BearingElement(8, kxx=5e6, kyy=4e6, cxx=200.0, tag="support1"),
    ]
    masses = [ross.PointMass(7, m=1.5), ross.PointMass(8, mx=2.0, my=2.5, mz=2.0)]
    return ross.Rotor(shaft, disks, bearings, masses)


def seal_2d():
    """A seal tabulated on speed x frequency (ROSS 3.x's ``rotor_2d_seal`` test fixture layout)."""
    shaft, steel = _shaft()
    disks = [
        ross.DiskElement.from_geometry(n=2, material=steel, width=0.07, i_d=0.05, o_d=0.28),
        ross.DiskElement.from_geometry(n=4, material=steel, width=0.07, i_d=0.05, o_d=0.35),
    ]
    bearings = [ross.BearingElement(n, kxx=1e6, cxx=100.0) for n in (0, 6)]
    speed = np.array([100.0, 200.0, 300.0, 400.0, 500.0])
    freq = np.array([50.0, 150.0, 250.0, 350.0, 450.0])
    kxy = np.outer(speed, np.ones(5)) * 2e2 + np.outer(np.ones(5), freq) * 1e3
    seal = ross.SealElement(
        3, kxx=1e4, cxx=10.0, kxy=kxy, kyx=-kxy, speed=speed, frequency=freq, tag="seal_2d"
    )
    return ross.Rotor(shaft, disks, bearings + [seal])


def amb_simple():
    from ross.bearings.magnetic.amb_models import rotor_example_amb_simple

    return rotor_example_amb_simple()


def _axis_points(rotor) -> np.ndarray:
    """The union of every bearing's table axes (rad/s): where both codes hold ROSS's values."""
    axes = [getattr(b, nm, None) for b in rotor.bearing_elements for nm in ("speed", "frequency")]
    pts = [np.atleast_1d(np.asarray(a, float)) for a in axes if a is not None and np.size(a) > 1]
    return np.unique(np.concatenate(pts)) if pts else np.zeros(0)


CASES = {  # name: (builder, table speeds to compare at (rad/s), modes)
    "rotor8": (rotor8, [50.0, 5000.0], 6),
    "compressor": (lambda: ross.compressor_example(), None, 6),
    "housings": (housings, [0.0, 400.0, 1500.0], 6),
    "seal_2d": (seal_2d, [100.0, 250.0, 400.0], 6),
}


@pytest.fixture(scope="module", params=list(CASES))
def case(request):
    if request.param == "seal_2d" and not ROSS3:
        pytest.skip("2-D speed x frequency tables exist in ROSS 3.x only")
    build, speeds, n = CASES[request.param]
    rotor = _quiet(build)
    if speeds is None:  # three table points of the compressor's elements
        speeds = _axis_points(rotor)[[0, 3, -1]]
    # ROSS 2.3's smoothing splines: where another element has a table point, read each element
    # there from ROSS (speeds=); ROSS 3.x: each element's own table, PCHIP between as ROSS
    points = _axis_points(rotor)
    system = from_ross(rotor) if ROSS3 or not points.size else from_ross(rotor, speeds=points)
    return request.param, rotor, system, np.asarray(speeds, float), n


def _lateral(rotor, vectors: np.ndarray) -> np.ndarray:
    """Which ROSS eigenvectors are lateral modes (ROSS also has axial and torsional ones)."""
    idx, _ = ross_dof_map(len(rotor.nodes_pos), rotor.number_dof)
    pm = [p.dof_global_index[f"{q}_{p.n}"] for p in rotor.point_mass_elements for q in "xy"]
    keep = np.concatenate([idx, np.array(pm, int)])
    v = vectors[: rotor.ndof]  # mostly lateral: torsional modes move the disks' rims a little
    return np.linalg.norm(v[keep], axis=0) > 0.5 * np.linalg.norm(v, axis=0)


def _ross_modes(rotor, speed: float, lateral: bool = True):
    """ROSS's lateral (or with ``lateral=False`` its axial and torsional) eigenvalues with
    ``Im > 0`` at ``speed`` (all, dense solver)."""
    modal = _quiet(rotor.run_modal, speed, num_modes=2 * rotor.ndof, sparse=False)
    lam, vec = np.asarray(modal.evalues), np.asarray(modal.evectors)
    keep = (_lateral(rotor, vec) == lateral) & (lam.imag > 1e-3)
    return lam[keep]


def test_modes_and_log_decs_equal_ross(case):
    """Each of our ``n`` lowest modes (by ``|lambda|``) is one of ROSS's lateral eigenvalues to
    1e-6 relative, with the same log dec to 1e-6, and ROSS has no other lateral mode below."""
    name, rotor, system, speeds, n = case
    worst_lam = worst_ld = 0.0
    for w in speeds:
        ours = [m for m in damped_modes(system, float(w), n=n).modes if not m.overdamped]
        theirs = _ross_modes(rotor, float(w))
        top = abs(ours[-1].eigenvalue) * (1 + TOL)
        assert np.count_nonzero(np.abs(theirs) <= top) == len(ours)
        for m in ours:
            j = np.argmin(np.abs(theirs - m.eigenvalue))
            worst_lam = max(worst_lam, abs(theirs[j] - m.eigenvalue) / abs(m.eigenvalue))
            ld = -2 * np.pi * theirs[j].real / theirs[j].imag
            worst_ld = max(worst_ld, abs(ld - m.log_dec) / max(1.0, abs(ld)))
    print(f"\n{name}: eigenvalues {worst_lam:.1e}, log decs {worst_ld:.1e}")
    assert worst_lam <= TOL and worst_ld <= TOL


def test_campbell_equals_ross(case):
    """ROSS's ``run_campbell`` (damped frequencies, log decs of its ``n`` lowest modes, tracked
    by MAC) at the table speeds: each lateral point (ROSS's diagram also holds torsional and
    axial modes, told apart by their eigenvectors) is on one of our branches to 1e-6."""
    name, rotor, system, speeds, n = case
    res = _quiet(rotor.run_campbell, speeds, frequencies=n)
    ours = campbell_data(system, speeds, n=n + 4)
    ours_w = 2 * np.pi * ours.frequency_hz
    worst_f = worst_ld = 0.0
    count = 0
    for i in range(len(speeds)):
        other = _ross_modes(rotor, float(speeds[i]), lateral=False).imag
        for wd, ld in zip(np.asarray(res.wd)[i], np.asarray(res.log_dec)[i], strict=True):
            if np.any(np.abs(other - wd) <= TOL * wd):
                continue
            count += 1
            j = np.nanargmin(np.abs(ours_w[i] - wd))
            worst_f = max(worst_f, abs(ours_w[i, j] - wd) / wd)
            worst_ld = max(worst_ld, abs(ours.log_dec[i, j] - ld) / max(1.0, abs(ld)))
    print(f"\n{name}: Campbell frequencies {worst_f:.1e}, log decs {worst_ld:.1e} ({count} pts)")
    assert count >= (n - 2) * len(speeds)
    assert worst_f <= TOL and worst_ld <= TOL


def test_unbalance_response_equals_ross(case):
    """ROSS's ``run_unbalance_response`` (same force: ``m e Omega^2 [1, -i] e^{i phase}`` on
    ``x, y``) at the table speeds: complex ``x, y`` at every shaft node equal ours to 1e-6 of
    the largest amplitude."""
    name, rotor, system, speeds, _ = case
    node = len(rotor.nodes_pos) // 2
    speeds = speeds[speeds > 0]
    res = _quiet(rotor.run_unbalance_response, node, 1e-4, 0.3, speeds)
    theirs = np.asarray(res.forced_resp)
    nodes = np.asarray(rotor.nodes_pos, float)
    ours = unbalance_response(system, speeds, [(nodes[node], 1e-4, 0.3)], list(nodes))
    d = rotor.number_dof
    ref = np.stack([theirs[d * np.arange(len(nodes))], theirs[d * np.arange(len(nodes)) + 1]])
    ref = np.moveaxis(ref, (0, 1, 2), (2, 1, 0))  # (speeds, nodes, [x, y])
    err = np.abs(ours.complex_response - ref).max() / np.abs(ref).max()
    print(f"\n{name}: unbalance response {err:.1e}")
    assert err <= TOL


def test_critical_speeds_equal_ross():
    """``rotor8``: ROSS's ``run_critical_speed`` (secant iteration on its own ``run_modal``,
    here to rtol 1e-10) gives the damped critical speeds and damping ratios of its 4 lowest
    modes; ours (Campbell scan + Brent on the crossing) equal them to 1e-6, and ROSS's own
    modal analysis at each of our critical speeds has a damped frequency equal to it."""
    rotor = _quiet(rotor8)
    system = from_ross(rotor)
    res = _quiet(rotor.run_critical_speed, num_modes=8, rtol=1e-10)
    ross_wd = np.asarray(res.wd())
    ours = linear_critical_speeds(system, 1.2 * ross_wd.max(), n=6)
    speeds = np.array([c.speed_rad_s for c in ours])
    worst = worst_zeta = 0.0
    for w, zeta in zip(ross_wd, np.asarray(res.damping_ratio), strict=True):
        j = np.argmin(np.abs(speeds - w))
        worst = max(worst, abs(speeds[j] - w) / w)
        worst_zeta = max(worst_zeta, abs(ours[j].damping_ratio - zeta))
        assert not ours[j].critically_damped  # zeta about 0.01 here
    for c in ours:
        wd = _ross_modes(rotor, c.speed_rad_s).imag
        assert np.min(np.abs(wd - c.speed_rad_s)) <= 1e-9 * c.speed_rad_s
    print(f"\nrotor8: critical speeds {worst:.1e}, damping ratios {worst_zeta:.1e}")
    assert worst <= TOL and worst_zeta <= TOL


@needs_ross3
def test_amb_modes_ranked_as_ross():
    """ROSS's ``rotor_example_amb_simple`` at 300 rad/s: ROSS's ``run_modal`` (ARPACK, its
    default) lists 183, 183, 334, 339, 1122, 1125 rad/s; our 6 modes ranked by ``|lambda|`` are
    these (damped and undamped frequencies, damping ratios to 1e-6), not the nearly real roots
    of small ``Im`` (0.2-0.7 Hz, ``|lambda|`` about 1e4 rad/s), which come after, marked."""
    rotor = _quiet(amb_simple)
    modal = _quiet(rotor.run_modal, 300.0)
    ours = damped_modes(from_ross(rotor), 300.0, n=6).modes
    osc = [m for m in ours if not m.overdamped]
    assert len(osc) == 6
    lam = np.array([m.eigenvalue for m in osc])
    np.testing.assert_allclose(np.abs(lam), np.asarray(modal.wn)[:6], rtol=TOL)
    np.testing.assert_allclose(lam.imag, np.asarray(modal.wd)[:6], rtol=TOL)
    np.testing.assert_allclose(
        [m.damping_ratio for m in osc], np.asarray(modal.damping_ratio)[:6], rtol=TOL
    )
    every = damped_modes(from_ross(rotor), 300.0).modes
    slow = [m for m in every if 0 < m.frequency_hz < 1.0]  # Im(lambda) of 0.2-0.7 Hz
    assert slow and all(m.overdamped and abs(m.eigenvalue) > 5e3 for m in slow)


def test_pchip_or_linear_between_table_points():
    """Between table points ROSS 3.x interpolates with PCHIP (its default): the default import
    follows it to round-off, ``interpolation="linear"`` does not (both equal at table points).
    ROSS 2.3 (smoothing splines): the default is linear; ``speeds=`` samples ROSS's own spline
    on a finer grid, and there both codes agree exactly."""
    rotor = _quiet(lambda: ross.compressor_example())
    sup = rotor.bearing_elements[0]  # its first bearing, tabulated at 8 speeds
    axis = np.asarray(sup.speed if ROSS3 else sup.frequency, float)  # its own table speeds
    mid = 0.5 * (axis[0] + axis[1])

    def k(system, w):
        s = next(s for s in system.supports if s.name == str(sup.tag))
        return s.coefficients(w)[0]

    ref = np.asarray(sup.K(mid), float)[:2, :2]
    lin = from_ross(rotor, interpolation="linear")
    pchip = from_ross(rotor, interpolation="pchip")
    for w in axis[[1, 4]]:  # table points: equal
        np.testing.assert_allclose(k(lin, w), k(pchip, w), rtol=1e-13)
    gap = np.abs(k(lin, mid) - ref).max() / np.abs(ref).max()
    assert gap > 1e-4  # linear is not ROSS's interpolant
    if ROSS3:
        assert np.abs(k(from_ross(rotor), mid) - ref).max() <= 1e-12 * np.abs(ref).max()
    fine = from_ross(rotor, speeds=[axis[0], mid, axis[1]])
    np.testing.assert_allclose(k(fine, mid), ref, rtol=1e-13, atol=1e-9 * np.abs(ref).max())


def test_unmappable_elements_refused_by_name():
    """A bearing mass tabulated against speed, a skew one and a disk whose mass couples lateral
    and torsional DOFs are refused naming the element (class, tag, node) and the field."""
    shaft, _ = _shaft()
    table = ross.BearingElement(
        6, **_table(kxx=[1e6, 2e6], cxx=[0.0, 0.0], mxx=[1.0, 2.0], axis=[0.0, 100.0]), tag="mb"
    )
    rotor = _quiet(ross.Rotor, shaft, [], [ross.BearingElement(0, kxx=1e6, cxx=0), table])
    with pytest.raises(InputError, match=r"BearingElement 'mb' at node 6\.mxx"):
        from_ross(rotor)
    skew = ross.BearingElement(6, kxx=1e6, cxx=0, mxx=1.0, mxy=0.5, myx=0.0, tag="skew")
    rotor = _quiet(ross.Rotor, shaft, [], [ross.BearingElement(0, kxx=1e6, cxx=0), skew])
    with pytest.raises(InputError, match=r"'skew' at node 6\.mxy"):
        from_ross(rotor)
    with pytest.raises(InputError, match="interpolation"):
        from_ross(rotor8(), interpolation="cubic")
    with pytest.raises(InputError, match="speeds"):
        from_ross(rotor8(), speeds=[])

    class Coupled(ross.DiskElement):  # a disk whose mass couples x with the torsion (a gear's)
        def M(self, *args, **kwargs):
            m = np.array(super().M(*args, **kwargs), float)
            m[0, 5] = m[5, 0] = 1e-3
            return m

    disk = Coupled(n=3, m=5.0, Id=0.02, Ip=0.04, tag="gearish")
    bearings = [ross.BearingElement(n, kxx=1e6, cxx=0) for n in (0, 6)]
    rotor = _quiet(ross.Rotor, shaft, [disk], bearings)
    with pytest.raises(InputError, match=r"Coupled 'gearish' at node 3 .*M couples lateral"):
        from_ross(rotor)  # named: not the shaft element that holds the same two DOFs
