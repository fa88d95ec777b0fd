"""Dry whirl (rubrotor.studies.dry_whirl) against its closed form.

References, all independent of the simulation:

* the steady rolling backward whirl of a Jeffcott rotor in full contact with a rigid or a
  flexible stator, derived in the rubrotor.studies.dry_whirl module docstring: ``omega = -Omega R / |D|``
  with ``|D| = g k_c / (k_c + Re Z)``, and the least friction that holds it
  ``mu_roll = Im Z / Re Z`` (``Z`` the series impedance of rotor and stator);
* the coupled natural frequencies: ``sqrt((k + k_c) / m)`` (rigid stator), the eigenvalues of
  the 2x2 chain (flexible, checked here with ``scipy.linalg.eigh``);
* the orbit is checked to satisfy the equations of motion it came from.

The friction threshold is measured by simulation (general engine, exponential integrator at
``h = 1e-5 s``) started on the rolling orbit: sustained backward whirl above ``mu_roll``, none
just below it (scan points 0.95 and 1.05 of ``mu_roll``).
"""

import numpy as np
import pytest
import scipy.linalg

from rubrotor.engine.parts import Stator
from rubrotor.errors import InputError
from rubrotor.rotors.forces import Contact
from rubrotor.studies.dry_whirl import (
    DryWhirlCase,
    Jeffcott,
    coupled_frequencies,
    relative_system,
    rolling_whirls,
    scan_friction,
    scan_speed,
    whirl_frequency,
)

ROTOR = Jeffcott(10.0, 1e6, 316.0)  # omega_n = 316 rad/s, 5 % damping
CONTACT = Contact(clearance=1e-4, stiffness=1e8, law="linear", radius=0.01, position=0.5,
                  friction_regularization=1e-5)  # fmt: skip
RIGID = DryWhirlCase(ROTOR, CONTACT, 6.0)  # Omega R / g = 600 rad/s
FLEX = DryWhirlCase(ROTOR, CONTACT, 8.0, Stator.isotropic(10.0, 4e6, 632.0))  # 800 rad/s


@pytest.mark.parametrize("case", [RIGID, FLEX], ids=["rigid", "flexible"])
def test_rolling_orbit_satisfies_its_equations(case):
    """The closed-form orbit: rotor ``Z_r A = F``, stator ``Z_s B = -F``, ``|A - B| = g +
    F_n / k_c``, the tangential force ``mu_roll F_n`` and no sliding ``R Omega + omega |D| = 0``."""
    for r in rolling_whirls(case):
        zr = ROTOR.impedance(r.frequency)
        d = r.rotor_amplitude - r.stator_amplitude
        n = d / abs(d)
        force = -r.normal_force * (1 + 1j * r.friction_needed) * n
        assert abs(zr * r.rotor_amplitude - force) < 1e-9 * abs(force)
        if case.stator is not None:
            s = case.stator
            zs = s.stiffness_y - s.mass_y * r.frequency**2 + 1j * s.damping_y * r.frequency
            assert abs(zs * r.stator_amplitude + force) < 1e-9 * abs(force)
        assert abs(abs(d) - (1e-4 + r.normal_force / 1e8)) < 1e-12
        assert abs(case.speed * 0.01 + r.frequency * abs(d)) < 1e-12
        assert r.normal_force > 0 and r.friction_needed > 0


def test_coupled_frequencies():
    """Rigid: ``sqrt((k + k_c)/m)``; flexible: the eigenvalues of the locked 2-mass chain."""
    assert coupled_frequencies(RIGID)[0] == pytest.approx(np.sqrt((1e6 + 1e8) / 10), rel=1e-14)
    kc = 1e8
    k = np.array([[1e6 + kc, -kc], [-kc, 4e6 + kc]])
    w2 = scipy.linalg.eigh(k, np.diag([10.0, 10.0]), eigvals_only=True)
    assert np.allclose(coupled_frequencies(FLEX), np.sqrt(w2), rtol=1e-12)


def test_whirl_frequency_of_an_exact_orbit():
    """A backward circular orbit off the spectral lines: its frequency to 1e-6 (the
    weak forward tone 11 lines away leaks 5e-7 through the Hann side lobes)."""
    t = np.arange(5000) * 2e-5
    z = 1e-4 * np.exp(-1j * 587.123 * t) + 1e-6 * np.exp(1j * 100.0 * t)
    assert whirl_frequency(t, z.real, z.imag) == pytest.approx(-587.123, rel=1e-6)


@pytest.mark.parametrize("case", [RIGID, FLEX], ids=["rigid", "flexible"])
def test_friction_threshold_and_whirl_frequency(case):
    """Simulated threshold brackets ``mu_roll``; the whirl frequency is the rolling one.

    Started on the closed-form orbit, the run at ``0.95 mu_roll`` slips off and leaves the
    stator, the run at ``1.05 mu_roll`` (and at ``2 mu_roll``) keeps whirling backward in full
    contact at ``omega = -Omega R / |D|`` (to 5e-4 at 1.05, where the regularised friction's
    micro-slip ``~ v_r`` is largest; to 2e-4 at 2 mu_roll), inside the band bounded by the
    coupled frequency."""
    roll = rolling_whirls(case)[-1]
    mu = roll.friction_needed
    scan = scan_friction(case, [0.95 * mu, 1.05 * mu, 2 * mu], duration=0.3, start="rolling")
    print("mu_roll", mu, "threshold", scan.threshold, "omega", scan.whirl_frequency,
          "closed form", roll.frequency, "-Omega R/g", scan.rolling_condition[0])  # fmt: skip
    assert list(scan.backward) == [False, True, True]
    assert scan.threshold == pytest.approx(1.05 * mu)
    assert scan.contact_fraction[0] == 0.0
    assert scan.whirl_frequency[1] == pytest.approx(roll.frequency, rel=5e-4)
    assert scan.whirl_frequency[2] == pytest.approx(roll.frequency, rel=2e-4)
    assert scan.gap[2] == pytest.approx(roll.gap, rel=1e-4)
    assert scan.predicted(2) == roll
    bounds = sorted([np.sqrt(ROTOR.stiffness / ROTOR.mass), *coupled_frequencies(case)])
    assert any(lo < -roll.frequency < hi for lo, hi in zip(bounds, bounds[1:], strict=False))


def test_flexible_stator_two_routes():
    """The engine's own flexible stator (kicked start) whirls at the same frequency as the
    stator written into the rotor (:func:`relative_system`, rolling start) and the closed form."""
    roll = rolling_whirls(FLEX)[-1]
    own = scan_friction(FLEX, [0.8], duration=0.3)  # engine Stator, from a kick
    assert own.backward[0]
    assert own.whirl_frequency[0] == pytest.approx(roll.frequency, rel=2e-4)
    assert relative_system(FLEX).n_dof == 4


def test_bad_input_names_the_field():
    """Errors name the field and what is allowed."""
    with pytest.raises(InputError, match="rotor.mass"):
        Jeffcott(0.0, 1e6)
    with pytest.raises(InputError, match="frictions"):
        scan_friction(RIGID, [-0.1])
    with pytest.raises(InputError, match="start"):
        scan_friction(RIGID, [0.1], start="moving")
    with pytest.raises(InputError, match="contact"):
        DryWhirlCase(ROTOR, Contact(clearance=1e-4, stiffness=1e8, radius=0.01), 6.0)


def test_figure_has_units_and_the_closed_form():
    """The figure's axes carry units and its lines include the closed-form rolling frequency."""
    from rubrotor.plotting.dry_whirl import dry_whirl_figure

    fs = scan_friction(RIGID, [0.05, 0.3], duration=0.05)
    ss = scan_speed(RIGID, [6.0, 10.0], 0.3, duration=0.05)
    fig = dry_whirl_figure([fs], [ss], ["rigid"])
    ax1, ax2 = fig.axes
    assert "rad/s" in ax1.get_ylabel() and "rad/s" in ax2.get_xlabel()
    roll = rolling_whirls(RIGID)[-1].frequency
    assert any(np.allclose(ln.get_ydata(), roll) for ln in ax1.get_lines())
    assert ss.speeds.tolist() == [6.0, 10.0] and ss.threshold is None
