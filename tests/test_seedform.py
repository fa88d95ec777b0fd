"""The seed's eq. (1) form (``formulation = "seed-eq1"``) and the linear stability of a contact."""

from __future__ import annotations

import dataclasses
import math
from importlib import resources

import numpy as np
import pytest
from seed import seed_shaft

from rubrotor import Integrator, ModalDamping, load_scenario, simulate
from rubrotor.analysis.spectra import full_spectrum
from rubrotor.core.contact import contact_force, contact_force_jac, pack_contact
from rubrotor.engine.simulate import assemble
from rubrotor.errors import InputError, ScenarioError
from rubrotor.linear.shaft import whirl_frequencies
from rubrotor.linear.stability import contact_stability
from rubrotor.rotors.seed_form import seed_coefficients, two_field_determinant
from rubrotor.rotors.shaft import modal_matrices

SPEED = 11613.8  # rad/s, 1.5 x first forward critical of the seed rotor


def _case(stem="seed_case1", **changes):
    sc = load_scenario(resources.files("rubrotor") / "scenarios" / f"{stem}.toml")
    return sc.with_changes(**changes) if changes else sc


def _signed_hz(sysm):
    return np.sort(sysm.lam.imag) / (2 * math.pi)


@pytest.mark.parametrize("speed", [0.0, SPEED, 3 * SPEED])
def test_free_frequencies_equal_two_field(speed):
    """Seed form and two-field model: the same whirl frequencies (same characteristic equation).

    References: the eigenvalues of the two-field first-order system (``assemble``) and, as a
    third route, the roots of the closed-form characteristic polynomial of
    :func:`rubrotor.linear.shaft.whirl_frequencies`.
    """
    sh = seed_shaft(modes=4)
    two = assemble(sh, speed)
    seed = assemble(dataclasses.replace(sh, formulation="seed-eq1"), speed)
    f2, fs = _signed_hz(two), _signed_hz(seed)
    assert np.max(np.abs(fs - f2) / np.abs(f2)) < 1e-10
    poly = np.sort(np.concatenate([whirl_frequencies(sh, n, speed) for n in range(1, 5)]))
    assert np.max(np.abs(fs * 2 * math.pi - poly) / np.abs(poly)) < 1e-10
    assert np.max(np.abs(seed.lam.real)) < 1e-9 * np.max(np.abs(seed.lam))


def test_coefficients_are_the_two_field_determinant():
    """c4..c0 written from eq. (1) equal det(M s^2 + Omega G s + K) / ((L/2) kappa G A).

    Two routes: term-by-term transcription of eq. (1) and the polynomial determinant of the
    two-field modal matrices (:mod:`rubrotor.rotors.shaft`).
    """
    sh = seed_shaft()
    for n in (1, 2, 3):
        a = seed_coefficients(sh, n, SPEED)
        b = two_field_determinant(sh, n, SPEED)
        assert np.max(np.abs(a - b) / np.abs(a).max()) < 1e-14


def test_damped_seed_form_has_the_damped_two_field_eigenvalues():
    """With modal damping 1 % both forms have the same (complex) eigenvalues; at rest each
    branch is a damped oscillator of ratio 0.01 (``-Re s / |s| = zeta``, closed form)."""
    sh = seed_shaft()
    d = ModalDamping(0.01)
    for speed in (0.0, SPEED):
        a = assemble(sh, speed, d).lam
        b = assemble(dataclasses.replace(sh, formulation="seed-eq1"), speed, d).lam
        a, b = a[np.argsort(a.imag)], b[np.argsort(b.imag)]
        assert np.max(np.abs(a - b) / np.abs(a)) < 1e-10
    rest = assemble(dataclasses.replace(sh, formulation="seed-eq1"), 0.0, d).lam
    assert np.allclose(-rest.real / np.abs(rest), 0.01, rtol=1e-9)


def test_formulation_validation():
    with pytest.raises(InputError, match="shaft.formulation"):
        seed_shaft(formulation="one-field")
    with pytest.raises(ScenarioError, match="shaft.formulation"):
        _case(**{"shaft.formulation": "seed"})
    with pytest.raises(ScenarioError, match="initial.state"):
        _case(**{"initial.state": "moving"})
    # Rayleigh / Euler-Bernoulli: the single equation is the one-field beam, the same system
    sh = seed_shaft(theory="rayleigh")
    a = assemble(sh, SPEED).lam
    b = assemble(dataclasses.replace(sh, formulation="seed-eq1"), SPEED).lam
    assert np.array_equal(a, b)
    with pytest.raises(InputError, match="shaft.theory"):
        seed_coefficients(sh, 1, SPEED)


def test_contact_jacobian_matches_finite_differences():
    """The linearisation uses the engine's contact Jacobian; check it against central
    differences of the contact force itself (second route)."""
    sc = _case()
    c = sc.contact
    cp = pack_contact(
        1, 0, c.stiffness, c.damping, c.clearance, c.friction, 0, 0.05 * sc.speed, 1e-6
    )
    x0 = np.array([c.clearance + 1e-4, 0.0, 0.0, 0.0])
    jac = np.zeros((2, 4))
    contact_force_jac(*x0, cp, jac)
    num = np.zeros((2, 4))
    for k, h in enumerate((1e-9, 1e-9, 1e-6, 1e-6)):
        e = np.zeros(4)
        e[k] = h
        fp, fm = contact_force(*(x0 + e), cp), contact_force(*(x0 - e), cp)
        num[:, k] = [(fp[0] - fm[0]) / (2 * h), (fp[1] - fm[1]) / (2 * h)]
    assert np.allclose(jac, num, rtol=1e-5, atol=1e-6 * np.abs(jac).max())


def test_pressed_contact_destabilises_the_seed_form_only():
    """Linearised pressed contact, mode 1, mu = 0 (model-notes section 6).

    Seed form: the backward mode-1 shear branch (about -20.66 kHz) grows, at a rate
    proportional to ``b_h`` (ratio of the rates at ``b_h' = 1e3`` and ``1e2`` is 10 to 1 %) and
    zero without contact damping; two-field: every eigenvalue has a negative real part. With the
    isotropic linearisation of the notes the rates are twice the radial ones, and those are the
    notes' values (+21.2 and +212 1/s at -20654 Hz, -0.546 1/s); the notes' figures are quoted
    from model-notes.md with their printed precision.
    """
    sc = _case()
    rate = {}
    for bh in (0.0, 1e2, 1e3):
        s = contact_stability(
            sc, 1e-4, formulation="seed-eq1", contact_damping_nd=bh, modes=1, friction=False
        )
        t = contact_stability(
            sc, 1e-4, formulation="two-field", contact_damping_nd=bh, modes=1, friction=False
        )
        rate[bh] = s.max_growth_rate
        if bh > 0:
            assert s.max_growth_rate > 0
            assert -20800 < s.dominant_frequency_hz < -20500  # backward mode-1 shear
            assert t.max_growth_rate < 0
    scale = max(abs(rate[1e2]), abs(rate[1e3]))
    assert abs(rate[0.0]) < 1e-9 * scale
    assert rate[1e3] / rate[1e2] == pytest.approx(10.0, rel=0.01)
    iso = contact_stability(
        sc, 1e-4, formulation="seed-eq1", modes=1, friction=False, linearisation="isotropic"
    )
    iso_t = contact_stability(
        sc, 1e-4, formulation="two-field", modes=1, friction=False, linearisation="isotropic"
    )
    assert iso.max_growth_rate == pytest.approx(21.2, abs=0.05)
    assert iso.dominant_frequency_hz == pytest.approx(-20654, abs=1)
    assert iso_t.max_growth_rate == pytest.approx(-0.546, abs=0.001)
    assert iso.max_growth_rate / rate[1e2] == pytest.approx(2.0, rel=0.02)


def test_seed_form_case1_stronger_unbalance_diverges_backward_shear():
    """Seed form, case 1, unbalance 3e-3 kg m from rest: the run ends partial, and the last
    part's full spectrum of the acceleration peaks at a negative (backward) frequency in the
    19-26 kHz band of the mode-1 shear branch (model-notes section 6)."""
    sc = _case(**{"shaft.formulation": "seed-eq1", "unbalance.magnitude": 3e-3})
    ds = simulate(
        sc, integrator=Integrator(revolutions=30, dtau=1e-3, save_every=4), progress=False
    )
    assert ds.attrs["status"] == "partial" and "diverged" in ds.attrs["status_message"]
    n = ds["time"].size
    last = slice(n - n // 3, n)
    fs = 1.0 / float(ds["time"][1] - ds["time"][0])
    spec = full_spectrum(ds["v_ddot"].values[0, last], ds["w_ddot"].values[0, last], fs)
    peak = spec.frequencies[int(np.argmax(spec.amplitudes))]
    assert -26e3 < peak < -19e3
    # the two-field model with the same input stays bounded
    ok = simulate(
        sc.with_changes(**{"shaft.formulation": "two-field"}),
        integrator=Integrator(revolutions=30, dtau=1e-3, save_every=4),
        progress=False,
    )
    assert ok.attrs["status"] == "complete"


def _steady_radius(sc) -> float:
    """Closed-form steady unbalance orbit radius (m) at the unbalance station: per mode the
    receptance at ``s = i Omega``, ``1/D(s)`` for the seed form, ``[(M s^2 + Omega G s +
    K)^-1]_00`` for the two-field mode (solved here with numpy)."""
    sh, u = sc.shaft, sc.unbalance
    F, s = u.magnitude * sc.speed**2, 1j * sc.speed
    total = 0j
    for n in range(1, sh.modes + 1):
        if sh.formulation == "seed-eq1":
            h = 1 / np.polyval(seed_coefficients(sh, n, sc.speed), s)
        else:
            mm = modal_matrices(sh, n)
            h = np.linalg.inv(mm.M * s**2 + sc.speed * mm.G * s + mm.K)[0, 0]
        total += math.sin(sh.wavenumber(n) * u.position) ** 2 * F * h
    return abs(total)


def test_steady_initial_state_is_the_particular_solution():
    """``initial.state = "steady"`` without contact: the orbit is the exact steady unbalance
    orbit from t = 0 (radius constant, 1X) for both formulations and both engines; reference:
    the closed-form modal receptances of :func:`_steady_radius`. The two formulations have
    different steady orbits (the seed form's receptance has no zeros)."""
    radii = {}
    for form in ("two-field", "seed-eq1"):
        sc = _case("seed_no_contact", **{"shaft.formulation": form, "initial.state": "steady"})
        ref = _steady_radius(sc)
        radii[form] = ref
        for method in ("exponential", "abm"):
            ds = simulate(
                sc,
                integrator=Integrator(revolutions=3, dtau=1e-3, save_every=8, method=method),
                progress=False,
            )
            r = np.hypot(ds["v"].values[0], ds["w"].values[0])
            assert np.max(np.abs(r - ref)) < 1e-6 * ref, (form, method)
    assert abs(radii["two-field"] / radii["seed-eq1"] - 1) > 0.05


def test_coefficients_from_the_dimensionless_form():
    """Third route: the seed's dimensionless eqs. (4)-(5) per mode (complex p' = v' + i w',
    derivatives in tau = Omega t, projected on sin(n pi chi) with weight 2):
    ``c^4 r^4 delta P'''' - 2i r^4 c^4 delta P''' + (c^2 + r^2 c^2 (delta + 1) K^2) P''
    - 2i r^2 c^2 K^2 P' + K^4 P = 2 sin(K a') F'`` with ``K = n pi``; in SI
    ``c_j = d_j E I / (2 L^3 Omega^j)`` (from ``P = L P'``, ``F = F' E I / L^2``)."""
    from rubrotor.rotors.shaft import Dimensionless

    sh = seed_shaft()
    nd = Dimensionless(sh, SPEED)
    r, delta, c = sh.slenderness, sh.shear_parameter, nd.speed_parameter
    for n in (1, 2, 3):
        K = n * math.pi
        d = np.array(
            [
                c**4 * r**4 * delta,
                -2j * r**4 * c**4 * delta,
                c**2 + r**2 * c**2 * (delta + 1) * K**2,
                -2j * r**2 * c**2 * K**2,
                K**4,
            ]
        )
        j = np.arange(4, -1, -1)
        si = d * sh.bending_stiffness / (2 * sh.length**3 * SPEED**j)
        ours = seed_coefficients(sh, n, SPEED)
        assert np.max(np.abs(si - ours) / np.abs(ours)) < 1e-12
