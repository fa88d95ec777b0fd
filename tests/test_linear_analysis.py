"""Linear analyses of any rotor, each against an independent reference (named per test)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg

import rubrotor
from rubrotor.cli import main
from rubrotor.errors import InputError
from rubrotor.linear.campbell import campbell_data
from rubrotor.linear.critical import linear_critical_speeds
from rubrotor.linear.modes import damped_modes
from rubrotor.linear.response import unbalance_response
from rubrotor.linear.shaft import natural_frequencies
from rubrotor.linear.stability import stability_threshold
from rubrotor.rotors.linear import LinearSystem, NodalBasis, Support

SCEN = Path(rubrotor.__file__).parent / "scenarios"


def jeffcott(m=2.0, k=8e4, c=20.0, a=0.0, speeds=(0.0, 1e4)) -> LinearSystem:
    """A rigid-disk Jeffcott rotor: one node, rotations fixed, cross-coupling ``q = a Omega``."""
    s = np.asarray(speeds, float)
    kk = np.array([[[k, a * w], [-a * w, k]] for w in s])
    cc = np.array([[[c, 0.0], [0.0, c]] for _ in s])
    z = np.zeros((4, 4))
    return LinearSystem(
        M=np.diag([m, m, 1.0, 1.0]),
        K=z.copy(),
        C=z.copy(),
        G=z.copy(),
        basis=NodalBasis(np.array([0.0])),
        supports=(Support(dofs=(0, 1), k=kk, c=cc, speeds=s),),
        fixed=(2, 3),
    )


def test_cross_coupled_instability_onset_closed_form():
    """Reference: m z'' + c z' + (k - i q) z = 0 loses stability when q = c sqrt(k/m); with
    q = a Omega the threshold is Omega* = c sqrt(k/m) / a (derived in the module docstring)."""
    m, k, c, a = 2.0, 8e4, 20.0, 0.5
    exact = c * math.sqrt(k / m) / a
    found = stability_threshold(jeffcott(m, k, c, a), max_speed=3 * exact)
    assert found == pytest.approx(exact, rel=1e-8)
    assert stability_threshold(jeffcott(m, k, c, 0.0), max_speed=3 * exact) is None


def test_continuous_shaft_equals_the_polynomial_route():
    """Reference: rubrotor.linear.shaft (roots of the per-mode characteristic polynomial), an
    independent route from the real first-order eigenproblem used here."""
    sc = rubrotor.load_scenario(SCEN / "seed_rotor.toml")
    system = rubrotor.linear_system(sc)
    for speed in (0.0, 10000.0):
        ours = damped_modes(system, speed).modes
        ref = sorted(natural_frequencies(sc.shaft, speed), key=lambda m: m.frequency_hz)
        assert len(ours) == len(ref)
        got = np.array([m.frequency_hz for m in ours])
        want = np.array([m.frequency_hz for m in ref])
        np.testing.assert_allclose(got, want, rtol=1e-10)
        if speed > 0:  # whirl labels agree with the polynomial route's
            assert [m.whirl for m in ours] == [m.whirl for m in ref]
        else:  # isotropic at rest: each frequency twice, one forward and one backward
            assert all(ours[2 * i].frequency_hz == pytest.approx(ours[2 * i + 1].frequency_hz)
                       for i in range(len(ours) // 2))  # fmt: skip
            assert {ours[0].whirl, ours[1].whirl} == {"forward", "backward"}


def test_arnoldi_route_equals_dense_route():
    """Reference: the dense eigenproblem of all 2N eigenvalues (scipy.linalg.eig)."""
    sc = rubrotor.load_scenario(SCEN / "general_rotor.toml")
    system = rubrotor.linear_system(sc)
    for speed in (0.0, 700.0):
        found = damped_modes(system, speed, n=8).modes
        every = damped_modes(system, speed).modes
        few, allm = found[:8], every[:8]
        np.testing.assert_allclose(
            [m.eigenvalue for m in few], [m.eigenvalue for m in allm], rtol=1e-9
        )
        assert [m.whirl for m in few] == [m.whirl for m in allm]
        # after the 8 modes, marked: the overdamped roots of |lambda| up to the 8th mode's
        top = abs(few[-1].eigenvalue) * (1 + 1e-9)
        below = [m.eigenvalue for m in every if m.overdamped and abs(m.eigenvalue) <= top]
        assert all(m.overdamped for m in found[8:]) and not any(m.overdamped for m in few)
        np.testing.assert_allclose([m.eigenvalue for m in found[8:]], below, rtol=1e-9)


def test_centred_jeffcott_disk_frequency_and_critical_speed():
    """Reference: the undamped Jeffcott rotor's frequency sqrt(k/m) for every speed, so its 1X
    critical speed is sqrt(k/m) (forward whirl) and its backward critical does not exist."""
    m, k = 2.0, 8e4
    system = jeffcott(m, k, c=0.0)
    data = campbell_data(system, np.linspace(0, 400, 5), n=2)
    np.testing.assert_allclose(data.frequency_hz, math.sqrt(k / m) / (2 * math.pi), rtol=1e-12)
    crit = linear_critical_speeds(system, 400.0, n=2)
    assert [c.speed_rad_s for c in crit] == pytest.approx([math.sqrt(k / m)] * 2, rel=1e-9)


def _fe_rotor() -> LinearSystem:
    return _fe_rotor_mesh(6)


def _fe_rotor_mesh(elements: int) -> LinearSystem:
    sec = rubrotor.Section(length=0.6, diameter=0.04, material=rubrotor.Material(
        name="steel", youngs_modulus=211e9, poisson_ratio=0.3, density=7810), elements=elements)  # fmt: skip
    bearings = (
        rubrotor.Bearing(position=0.0, kyy=3e6, kzz=5e6, kyz=4e5, kzy=-2e5, cyy=400.0, czz=600.0),
        rubrotor.Bearing(position=0.6, kyy=3e6, kzz=5e6, cyy=400.0, czz=600.0),
    )
    disk = rubrotor.Disk(position=0.3, mass=4.0, polar_inertia=0.02, diametral_inertia=0.011)
    return rubrotor.Rotor(sections=(sec,), disks=(disk,), bearings=bearings).linear_system(())


def test_unbalance_response_is_the_steady_state_of_the_time_integration():
    """References: (1) the first-order form solved as (i W I - A) x = b, a second algebraic
    route; (2) SciPy DOP853 (rtol 1e-11) integrating the equations of motion from the predicted
    state for three periods stays on the predicted orbit."""
    system = _fe_rotor()
    w, me, ph, x_u = 500.0, 1e-4, 0.7, 0.3
    resp = unbalance_response(system, [w, w + 1.0], [(x_u, me, ph)], [0.3, 0.15])
    mx = system.matrices(w)
    a, minv = mx.first_order()
    n = system.n_dof
    fc = system.force_map(x_u) @ np.array([1.0, -1j]) * me * w * w * np.exp(1j * ph)
    x = np.linalg.solve(1j * w * np.eye(2 * n) - a, np.concatenate([np.zeros(n), minv @ fc]))
    v_route2 = system.output_rows(0.3) @ x[:n]
    np.testing.assert_allclose(resp.complex_response[0, 0], v_route2, rtol=1e-9)

    def rhs(t, y):
        return a @ y + np.concatenate([np.zeros(n), minv @ np.real(fc * np.exp(1j * w * t))])

    period = 2 * math.pi / w
    sol = scipy.integrate.solve_ivp(
        rhs, (0, 3 * period), np.real(x), method="DOP853", rtol=1e-11, atol=1e-16,
        t_eval=np.linspace(0, 3 * period, 31),
    )  # fmt: skip
    rows = system.output_rows(0.3)
    sim = rows @ sol.y[:n]
    pred = np.real(resp.complex_response[0, 0][:, None] * np.exp(1j * w * sol.t))
    assert np.max(np.abs(sim - pred)) < 1e-7 * np.max(np.abs(pred))
    assert resp.major[0, 0] >= resp.amplitude[0, 0].max() - 1e-18


def test_general_rotor_modes_json(capsys):
    """``rubrotor modes --json`` prints the schema of the issue for a general rotor."""
    assert main(["modes", str(SCEN / "general_rotor.toml"), "--speed", "300", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["speed_rad_s"] == 300.0
    modes = out["modes"]
    assert [m["index"] for m in modes] == list(range(1, len(modes) + 1))
    # ranked by |lambda| (ROSS's wn), the overdamped roots after the oscillating modes
    over = [m["overdamped"] for m in modes]
    assert over == sorted(over) and not over[0]
    for part in (False, True):
        wn = [m["natural_frequency_hz"] for m in modes if m["overdamped"] is part]
        assert wn == sorted(wn)
    for m in modes:
        assert set(m) == {"index", "frequency_hz", "natural_frequency_hz", "damping_ratio",
                          "log_dec", "whirl", "overdamped"}  # fmt: skip
        assert m["whirl"] in ("forward", "backward", "mixed")
        if m["log_dec"] is None:  # a real root: no oscillation, no log dec
            assert m["overdamped"] and m["frequency_hz"] == 0.0
            continue
        assert m["log_dec"] == pytest.approx(
            2 * math.pi * m["damping_ratio"] / math.sqrt(1 - m["damping_ratio"] ** 2), rel=1e-9
        )
        assert m["natural_frequency_hz"] == pytest.approx(
            m["frequency_hz"] / math.sqrt(1 - m["damping_ratio"] ** 2), rel=1e-9
        )


def test_bad_inputs_name_the_field():
    system = jeffcott()
    with pytest.raises(InputError, match="speed"):
        damped_modes(system, -1.0)
    with pytest.raises(InputError, match="speeds"):
        campbell_data(system, [1.0])
    with pytest.raises(InputError, match="position"):
        unbalance_response(_fe_rotor(), [10.0, 20.0], [(0.3, 1e-4, 0.0)], [2.0])
    with pytest.raises(InputError, match="rotor"):
        rubrotor.linear_system("not a rotor")


class _Pivot:
    """Rigid rotor pivoting at ``x = 0``: the deflection at ``x`` is ``x [psi_v, psi_w]``."""

    length = 0.5

    def rows(self, position: float) -> np.ndarray:
        return float(position) * np.eye(2)


def test_gyroscopic_anisotropic_rigid_rotor_frequencies_and_whirl():
    """Rigid rotor tilting about a pivot (diametral inertia ``Id``, polar ``Ip``, tilt stiffness
    ``ky != kz``): ``Id psi_v'' + Omega Ip psi_w' + ky psi_v = 0``,
    ``Id psi_w'' - Omega Ip psi_v' + kz psi_w = 0``. With ``psi = (a, b) exp(i w t)`` the
    characteristic equation, derived by hand, is ``(ky - Id w^2)(kz - Id w^2) = w^2 Omega^2 Ip^2``,
    a quadratic in ``w^2``. The first row gives ``b/a = i (ky - Id w^2) / (w Omega Ip)``: the
    lower root (below both ``ky/Id`` and ``kz/Id``) has ``b = i r a``, ``r > 0``, an orbit turning
    from ``+v`` towards ``-w``: backward; the upper root (above both) is forward."""
    i_d, i_p, ky, kz = 0.02, 0.03, 4e4, 9e4
    system = LinearSystem(
        M=np.diag([i_d, i_d]),
        K=np.diag([ky, kz]),
        C=np.zeros((2, 2)),
        G=i_p * np.array([[0.0, 1.0], [-1.0, 0.0]]),
        basis=_Pivot(),
    )
    for speed in (50.0, 800.0, 5000.0):
        b = i_d * (ky + kz) + (speed * i_p) ** 2
        disc = math.sqrt(b * b - 4 * i_d**2 * ky * kz)
        ref = np.sqrt([(b - disc) / (2 * i_d**2), (b + disc) / (2 * i_d**2)]) / (2 * math.pi)
        modes = damped_modes(system, speed).modes
        np.testing.assert_allclose([m.frequency_hz for m in modes], ref, rtol=1e-12)
        assert [m.whirl for m in modes] == ["backward", "forward"]


def test_anisotropic_jeffcott_unbalance_orbit_is_backward_between_the_split_criticals():
    """Undamped Jeffcott rotor on anisotropic supports with unbalance ``m e``: by hand,
    ``m v'' + ky v = m e W^2 cos W t`` and ``m w'' + kz w = m e W^2 sin W t`` give
    ``v = A cos W t``, ``w = B sin W t`` with ``A = m e W^2 / (ky - m W^2)``,
    ``B = m e W^2 / (kz - m W^2)``; the orbit turns backward exactly where ``A B < 0``, between
    ``sqrt(ky/m)`` and ``sqrt(kz/m)`` (the classic split-critical result)."""
    m, ky, kz, me = 2.0, 8e4, 1.8e5, 1e-4
    z = np.zeros((4, 4))
    system = LinearSystem(
        M=np.diag([m, m, 1.0, 1.0]),
        K=z.copy(),
        C=z.copy(),
        G=z.copy(),
        basis=NodalBasis(np.array([0.0])),
        supports=(Support(dofs=(0, 1), k=np.diag([ky, kz])[None], c=np.zeros((1, 2, 2))),),
        fixed=(2, 3),
    )
    speeds = np.linspace(51.0, 501.0, 91)
    resp = unbalance_response(system, speeds, [(0.0, me, 0.0)], [0.0])
    a = me * speeds**2 / (ky - m * speeds**2)
    b = me * speeds**2 / (kz - m * speeds**2)
    vw = resp.complex_response[:, 0, :]
    np.testing.assert_allclose(vw[:, 0], a, rtol=1e-12, atol=0)
    np.testing.assert_allclose(vw[:, 1], -1j * b, rtol=1e-12, atol=0)
    np.testing.assert_allclose(resp.major[:, 0], np.maximum(abs(a), abs(b)), rtol=1e-12)
    # orbit direction from the complex response: Im(conj(V) W) > 0 is backward
    backward = np.imag(np.conj(vw[:, 0]) * vw[:, 1]) > 0
    between = (speeds > math.sqrt(ky / m)) & (speeds < math.sqrt(kz / m))
    assert between.any() and (~between).any()
    np.testing.assert_array_equal(backward, between)
    with pytest.raises(InputError, match="speeds"):  # undamped resonance: no steady state
        unbalance_response(system, [math.sqrt(ky / m)], [(0.0, me, 0.0)], [0.0])


def _rotor_with_speed_table(elements: int) -> LinearSystem:
    """The test rotor with its left bearing tabulated against speed (cross-coupling growing)."""
    sec = rubrotor.Section(length=0.6, diameter=0.04, material=rubrotor.Material(
        name="steel", youngs_modulus=211e9, poisson_ratio=0.3, density=7810), elements=elements)  # fmt: skip
    left = rubrotor.Bearing(
        position=0.0, speeds=(0.0, 1000.0, 4000.0), kyy=(3e6, 4e6, 6e6), kzz=5e6,
        kyz=(0.0, 4e5, 9e5), kzy=(0.0, -4e5, -9e5), cyy=400.0, czz=(600.0, 500.0, 450.0),
    )  # fmt: skip
    right = rubrotor.Bearing(position=0.6, kyy=3e6, kzz=5e6, cyy=400.0, czz=600.0)
    disk = rubrotor.Disk(position=0.3, mass=4.0, polar_inertia=0.02, diametral_inertia=0.011)
    return rubrotor.Rotor(sections=(sec,), disks=(disk,), bearings=(left, right)).linear_system(())


@pytest.mark.parametrize("elements", [30, 2])
def test_banded_unbalance_solve_equals_the_dense_solve(elements):
    """The compiled banded LU sweep (supports interpolated per speed, partial pivoting) against
    NumPy's dense LAPACK solve of ``system.matrices(speed)`` at every speed (reference: the full
    matrices assembled by the other route, ``Support.coefficients`` for the tables). Equal to
    1e-10 (both are backward-stable LU solves; they differ by cond * eps, measured ~1e-12).
    30 elements: a narrow band (really banded); 2 elements: the band is the whole matrix. The
    speeds include ones just off resonances and one above the last table speed (held)."""
    from rubrotor.core.banded import OK, unbalance_sweep
    from rubrotor.linear.band import _band_parts

    system = _rotor_with_speed_table(elements)
    n = system.n_dof
    b = system.force_map(0.3) @ np.array([1.0, -1j]) * 1e-4
    speeds = np.array([50.0, 400.0, 700.0, 2500.0, 3000.0, 5000.0])
    parts = _band_parts(system, speeds)
    if elements == 30:
        assert 2 * parts.kl + parts.ku + 1 < n // 4
    q, status, _ = unbalance_sweep(parts, speeds, b, np.eye(n, dtype=complex))
    assert status == OK
    for i, w in enumerate(speeds):
        mx = system.matrices(w)
        dyn = mx.K - w * w * mx.M + 1j * w * (mx.C + w * mx.G)
        ref = np.linalg.solve(dyn, b * w * w)
        assert np.abs(q[i] - ref).max() <= 1e-10 * np.abs(ref).max()


def test_band_lu_pivots():
    """A banded matrix with a zero leading diagonal entry needs row exchanges; the compiled
    band LU must solve it as NumPy's dense LU does (reference), and report a singular one."""
    from rubrotor.core.banded import OK, SINGULAR, band_factor, band_solve

    rng = np.random.default_rng(3)
    n, kl, ku = 12, 2, 3
    a = np.zeros((n, n), complex)
    for k in range(-kl, ku + 1):
        a += np.diag(rng.normal(size=n - abs(k)) + 1j * rng.normal(size=n - abs(k)), k)
    a[0, 0] = a[5, 5] = 0.0
    ab = np.zeros((2 * kl + ku + 1, n), complex)
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            ab[kl + ku + i - j, j] = a[i, j]
    ab = np.ascontiguousarray(ab.T)  # the kernels keep a matrix column contiguous
    ipiv = np.empty(n, np.int64)
    assert band_factor(ab, kl, ku, ipiv) == OK
    assert np.any(ipiv != np.arange(n))
    x = rng.normal(size=n) + 0j
    ref = np.linalg.solve(a, x)
    band_solve(ab, kl, ku, ipiv, x)
    np.testing.assert_allclose(x, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    sing = np.zeros((n, 2 * kl + ku + 1), complex)
    assert band_factor(sing, kl, ku, ipiv) == SINGULAR


@pytest.mark.parametrize("elements", [40, 3])
def test_campbell_equals_the_dense_eigen_solve(elements):
    """``campbell_data`` (projection starts + Newton on the banded quadratic eigenproblem)
    against the dense route: ``scipy.linalg.eig`` of the full first-order matrix at every speed
    (reference, nothing reduced), on the rotor with a speed-tabulated cross-coupled bearing,
    from rest (repeated frequencies: whirl from the circular combinations) to 5000 rad/s.
    Frequencies and log decs agree to 1e-9 relative (measured ~1e-11), whirl labels exactly.
    3 elements: the basis is all DOFs; 40 elements: a real reduction."""
    system = _rotor_with_speed_table(elements)
    speeds = np.linspace(0.0, 5000.0, 26)
    data = campbell_data(system, speeds, n=6)
    for i, w in enumerate(speeds):
        mx = system.matrices(w)
        lam = scipy.linalg.eigvals(mx.first_order()[0])
        lam = np.sort_complex(lam[lam.imag > 0])
        lam = lam[np.argsort(lam.imag)][:6]
        np.testing.assert_allclose(data.frequency_hz[i], lam.imag / (2 * np.pi), rtol=1e-9)
        log_dec = -2 * np.pi * lam.real / lam.imag
        np.testing.assert_allclose(data.log_dec[i], log_dec, rtol=1e-7, atol=1e-9)
        ranked = damped_modes(system, float(w), n=6).modes  # by |lambda|: sort by frequency
        ref = [md.whirl for md in sorted(ranked, key=lambda md: md.frequency_hz)]
        assert list(data.whirl[i]) == ref


def test_critically_damped_pair_is_not_a_mode():
    """The shipped general rotor's damped bearings give a critically damped eigenvalue pair
    (double real ``lam ~ -1878 1/s``) that rounding splits into ``-1878 +- 1e-3 i``: it must not
    appear as a zero-frequency mode, so that the ARPACK route (n given) and the dense route
    (all modes; reference) list the same modes in the same order at the speed where it
    appeared, and the critical speeds are the same on every call."""
    sc = rubrotor.load_scenario(SCEN / "general_rotor.toml")
    system = rubrotor.linear_system(sc)
    w = 378.76574661847303
    sparse = damped_modes(system, w, n=4).modes
    dense = damped_modes(system, w).modes[:4]
    assert min(m.frequency_hz for m in dense) > 1.0
    np.testing.assert_allclose(
        [m.frequency_hz for m in sparse], [m.frequency_hz for m in dense], rtol=1e-9
    )
    assert [m.whirl for m in sparse] == [m.whirl for m in dense]


def test_newton_modal_route_equals_the_dense_eigen_solve():
    """``damped_modes(n=...)`` on a large banded rotor takes the Campbell route at one speed
    (Krylov Ritz basis, Newton on the banded quadratic eigenproblem). Reference: the dense route
    of the same function with all modes (``scipy.linalg.eig`` of the full first-order matrix).
    40 elements (164 free DOFs, above the Krylov size), a speed-tabulated cross-coupled
    bearing, at rest (pairs of equal frequencies) and spinning: eigenvalues to 1e-9 relative
    (measured ~1e-11), whirl labels exactly, shapes (unit largest deflection, up to a unit
    factor) to 1e-6 (the dense eigenvectors' own accuracy, measured ~1e-9)."""
    from rubrotor.linear.band import _KRYLOV_SIZE
    from rubrotor.linear.modes import _newton_eig

    system = _rotor_with_speed_table(40)
    assert system.n_dof > _KRYLOV_SIZE
    for speed in (0.0, 2500.0):
        assert _newton_eig(system, speed, 8) is not None  # the route under test ran
        found = damped_modes(system, speed, n=8).modes
        every = damped_modes(system, speed).modes
        few, allm = found[:8], every[:8]
        np.testing.assert_allclose(
            [m.eigenvalue for m in few], [m.eigenvalue for m in allm], rtol=1e-9
        )
        assert [m.whirl for m in few] == [m.whirl for m in allm]
        # after the 8 modes, marked: the overdamped roots of |lambda| up to the 8th mode's
        top = abs(few[-1].eigenvalue) * (1 + 1e-9)
        below = [m.eigenvalue for m in every if m.overdamped and abs(m.eigenvalue) <= top]
        assert all(m.overdamped for m in found[8:]) and not any(m.overdamped for m in few)
        np.testing.assert_allclose([m.eigenvalue for m in found[8:]], below, rtol=1e-9)
        for a, b in zip(few, allm, strict=True):  # equal up to a unit factor (two stations
            phase = np.vdot(a.shape, b.shape)  # may tie for the largest deflection)
            np.testing.assert_allclose(a.shape * phase / abs(phase), b.shape, atol=1e-6)


def test_eigenvalues_then_null_vectors_equal_the_dense_eigen_solve():
    """``damped_modes(n=...)`` on a small dense rotor: LAPACK eigenvalues without vectors, then
    one null vector of the quadratic pencil per mode. Reference: the dense route of the same
    function with all modes (``scipy.linalg.eig`` of the first-order matrix with eigenvectors).
    8 elements (36 free DOFs), speed-tabulated cross-coupled bearing, at rest and spinning:
    eigenvalues to 1e-9 relative, whirl labels exactly, shapes (unit largest deflection, up to
    a unit factor) to 1e-6 (the dense eigenvectors' own accuracy). An isotropic Jeffcott rotor at
    rest (a double eigenvalue) must not take the route (``None``) and still equal the dense
    route, with one forward and one backward circular mode (the limit of a slow spin)."""
    from rubrotor.linear.modes import _eigvals_then_vectors

    system = _rotor_with_speed_table(8)
    for speed in (0.0, 2500.0):
        mx = system.matrices(speed)
        assert _eigvals_then_vectors(mx, mx.first_order()[0], 8) is not None  # route ran
        found = damped_modes(system, speed, n=8).modes
        every = damped_modes(system, speed).modes
        few, allm = found[:8], every[:8]
        np.testing.assert_allclose(
            [m.eigenvalue for m in few], [m.eigenvalue for m in allm], rtol=1e-9
        )
        assert [m.whirl for m in few] == [m.whirl for m in allm]
        # after the 8 modes, marked: the overdamped roots of |lambda| up to the 8th mode's
        top = abs(few[-1].eigenvalue) * (1 + 1e-9)
        below = [m.eigenvalue for m in every if m.overdamped and abs(m.eigenvalue) <= top]
        assert all(m.overdamped for m in found[8:]) and not any(m.overdamped for m in few)
        np.testing.assert_allclose([m.eigenvalue for m in found[8:]], below, rtol=1e-9)
        for a, b in zip(few, allm, strict=True):
            phase = np.vdot(a.shape, b.shape)
            np.testing.assert_allclose(a.shape * phase / abs(phase), b.shape, atol=1e-6)
    jeff = jeffcott()
    mx = jeff.matrices(0.0)
    assert _eigvals_then_vectors(mx, mx.first_order()[0], 2) is None
    few, allm = damped_modes(jeff, 0.0, n=2).modes, damped_modes(jeff, 0.0).modes
    assert [m.whirl for m in few] == [m.whirl for m in allm]
    assert sorted(m.whirl for m in few) == ["backward", "forward"]  # one circular mode of each


def test_compiled_band_matmul_and_ritz_vectors():
    """``band_matmul`` against NumPy's dense product of the same matrix (reference), and
    ``ritz_vectors`` against the definition of a null vector: at an eigenvalue of a small
    quadratic problem (from ``scipy.linalg.eig`` of its companion form, reference) the residual
    ``|T(lam) y|`` is at rounding level relative to ``|T|``; equal eigenvalues get independent
    vectors."""
    from rubrotor.core.banded import band_matmul, ritz_vectors
    from rubrotor.linear.band import _to_band

    rng = np.random.default_rng(7)
    n, kl, ku = 30, 3, 2
    a = sum(np.diag(rng.normal(size=n - abs(k)), k) for k in range(-kl, ku + 1))
    x = rng.normal(size=(n, 4))
    out = np.empty_like(x)
    band_matmul(_to_band(a, kl, ku), ku, x, out)
    np.testing.assert_allclose(out, a @ x, rtol=1e-13, atol=1e-13)

    m = 5
    mass = np.diag(rng.uniform(1, 2, m))
    damp = rng.normal(size=(1, m, m)) * 0.1
    stiff = (lambda q: q @ q.T + m * np.eye(m))(rng.normal(size=(m, m)))[None]
    comp = np.block([[np.zeros((m, m)), np.eye(m)], [-np.linalg.solve(mass, stiff[0]),
                     -np.linalg.solve(mass, damp[0])]])  # fmt: skip
    lam = scipy.linalg.eigvals(comp)[None, :3]
    y = ritz_vectors(mass, damp, stiff, lam)
    for j in range(3):
        t = lam[0, j] ** 2 * mass + lam[0, j] * damp[0] + stiff[0]
        assert np.linalg.norm(t @ y[0, j]) <= 1e-10 * np.linalg.norm(t)
    # a double eigenvalue (T(lam) = 0 exactly): two independent unit vectors
    y2 = ritz_vectors(np.eye(2), np.zeros((1, 2, 2)), 4.0 * np.eye(2)[None], np.array([[2j, 2j]]))
    assert abs(np.vdot(y2[0, 0], y2[0, 1])) < 0.99
