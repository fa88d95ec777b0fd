"""The finite journal bearing with feed grooves (``[[bearing]] type = "finite_journal"``).

References, each independent of the code under test:
- Raimondi, A. A., Boyd, J. (1958). A solution for the finite journal bearing and its
  application to analysis and design. ASLE Transactions 1, parts I-III: the full (360 degree)
  bearing fed at its thickest film with p = 0 there, Swift-Stieber cavitation. Their Sommerfeld
  numbers at L/D = 1, as reproduced in Shigley's Mechanical Engineering Design (ch. 12) and
  transcribed in MathWorks Answers 707318 ("design of journal bearing", ``S_1`` against
  ``h0/c = 1 - eps``): eps 0.1 -> 1.33, 0.2 -> 0.631, 0.4 -> 0.264, 0.6 -> 0.121,
  0.8 -> 0.0446, 0.9 -> 0.0188 (S = 0.0446 at h0/c = 0.2 is also U. C. Jindal's Machine Design,
  example 17-2). Only these cited numbers are asserted.
- Ocvirk's short bearing (L/D -> 0, half-Sommerfeld) and Sommerfeld's long bearing
  (L/D -> infinity, full film) in closed form (as in tests/test_reynolds.py); the model error
  must fall as (L/D)^2 and D/L.
- The separately written cell-centred solver ``rubrotor.forces.reynolds.finite_film`` (load-line
  frame, no grooves): a second discretisation of the same problem.
"""

import math

import numpy as np
import pytest

import rubrotor
from rubrotor.errors import InputError
from rubrotor.forces.finite_journal import FiniteJournal, finite_force
from rubrotor.forces.reynolds import finite_film
from rubrotor.forces.supports import support_term

RB_L_OVER_D_1 = {0.1: 1.33, 0.2: 0.631, 0.4: 0.264, 0.6: 0.121, 0.8: 0.0446, 0.9: 0.0188}


def _somm_att(eps, l_over_d, n_theta, n_z, cavitation="reynolds", grooves=(math.pi,)):
    """S and the attitude angle (rad) with the journal at (eps c, 0): thickest film at pi."""
    f, solves = finite_force(eps, 0.0, 0.0, 0.0, 1.0, 1.0, 2.0 * l_over_d, 1.0, 1.0,
                             cavitation=cavitation, grooves=grooves, n_theta=n_theta,
                             n_z=n_z)  # fmt: skip
    w = math.hypot(*f) / (2.0 * l_over_d)  # per mu omega R L (R/c)^2 with R = c = mu = omega = 1
    load = -f
    att = math.atan2(load[0] * 0.0 - load[1] * eps, load[0] * eps)
    return 1.0 / (math.pi * w), att, solves


@pytest.mark.slow
def test_groove_at_thickest_film_matches_raimondi_boyd_at_l_over_d_1():
    for eps, s_ref in RB_L_OVER_D_1.items():
        s, _, _ = _somm_att(eps, 1.0, 288, 64)
        assert s == pytest.approx(s_ref, rel=0.015), eps


def test_grid_convergence_order_is_two():
    """Successive differences of S fall by about 4 per halving of the grid, with the groove and
    the Reynolds condition (the free boundary costs no order here) and with the full film."""
    for cav in ("reynolds", "full_film"):
        s = [_somm_att(0.6, 1.0, 18 * k, 4 * k, cavitation=cav)[0] for k in (2, 4, 8)]
        d = abs(s[1] - s[0]) / abs(s[2] - s[1])
        assert math.log2(d) == pytest.approx(2.0, abs=0.3), (cav, s)


def test_short_and_long_limits():
    eps = 0.5
    lds = np.array([0.2, 0.1, 0.05])
    err = []
    for ld in lds:
        f, _ = finite_force(eps, 0.0, 0.0, 0.0, 1.0, 1.0, 2.0 * ld, 1.0, 1.0,
                            cavitation="half_sommerfeld", n_theta=288, n_z=64)  # fmt: skip
        lr = 2 * ld  # L / R
        scale = 2.0 * ld  # mu omega R L (R/c)^2
        fr = -(lr**2) * eps**2 / (1 - eps**2) ** 2  # along the eccentricity (+y here)
        ft = lr**2 * math.pi * eps / (4 * (1 - eps**2) ** 1.5)  # 90 deg ahead (+z)
        err.append(abs(f[0] / scale / fr - 1))
        err[-1] = max(err[-1], abs(f[1] / scale / ft - 1))
    slopes = np.diff(np.log(err)) / np.diff(np.log(lds))
    assert err[-1] < 5e-3 and np.all((slopes > 1.7) & (slopes < 2.4)), (err, slopes)
    ft_long = 12 * math.pi * eps / ((2 + eps**2) * math.sqrt(1 - eps**2))
    lds = np.array([2.5, 5.0, 10.0])
    err = []
    for ld in lds:
        f, _ = finite_force(eps, 0.0, 0.0, 0.0, 1.0, 1.0, 2.0 * ld, 1.0, 1.0,
                            cavitation="full_film", n_theta=144, n_z=int(24 * ld))  # fmt: skip
        err.append(abs(f[1] / (2.0 * ld) / ft_long - 1))
    slopes = np.diff(np.log(err)) / np.diff(np.log(lds))
    assert np.all((slopes < -0.8) & (slopes > -1.3)), (err, slopes)


def test_equals_the_cell_centred_solver_without_grooves():
    """Two grids of the same Reynolds problem agree to their discretisation error (both second
    order: 1e-3 at these grids)."""
    for eps in (0.3, 0.7):
        f, _ = finite_force(eps, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, cavitation="reynolds",
                            n_theta=144, n_z=32)  # fmt: skip
        ref = finite_film(eps, 0.5, n_theta=144, n_z=32, cavitation="reynolds")
        # reference frame: its theta from the thickest film, its force per mu omega R L (R/c)^2
        assert math.hypot(*f) == pytest.approx(ref.load, rel=2e-3)
        load = -f
        att = math.atan2(-load[1] * eps, load[0] * eps)
        assert att == pytest.approx(ref.attitude_angle_rad, abs=2e-3)


def test_rotor_on_finite_journals_balances_its_weight(tmp_path):
    toml = """
[meta]
name = "finite_rotor"
[speed]
rad_per_s = 300.0
[gravity]
y = -9.80665
z = 0.0
[materials.steel]
youngs_modulus = 2.11e11
poisson_ratio = 0.3
density = 7810.0
[[section]]
length = 0.5
diameter = 0.05
material = "steel"
elements = 2
[[disk]]
position = 0.25
mass = 10.0
polar_inertia = 0.05
diametral_inertia = 0.03
"""
    for x in (0.0, 0.5):
        toml += f"""[[bearing]]
position = {x}
type = "finite_journal"
diameter = 0.05
length = 0.025
radial_clearance = 5e-5
viscosity = 0.02
groove_angles = [1.5708]
supply_pressure = 1e5
"""
    path = tmp_path / "finite.toml"
    path.write_text(toml)
    sc = rubrotor.load_scenario(path)
    res = rubrotor.static(sc)
    films = [b for b in res.bearings if b.eccentricity_ratio is not None]
    weight = sc.rotor.mass * 9.80665
    assert sum(b.force_y for b in films) == pytest.approx(weight, rel=1e-9)
    assert 0.0 < films[0].eccentricity_ratio < 1.0
    (row, _) = rubrotor.bearings(sc, [300.0]).rows
    term = row.term
    assert np.allclose(term.force(row.p0, (0, 0), 300.0), row.force, rtol=1e-12)


@pytest.mark.parametrize(
    ("key", "value", "match"),
    [
        ("length", 0.5, "L/D"),
        ("viscosity", 0.0, "bearing.viscosity"),
        ("radial_clearance", -1e-5, "bearing.radial_clearance"),
        ("cavitation", "bogus", "bearing.cavitation"),
        ("supply_pressure", -1.0, "bearing.supply_pressure"),
        ("groove_angles", ["x"], "bearing.groove_angles"),
    ],
)
def test_bad_keys_are_refused_by_name(key, value, match):
    row = {"type": "finite_journal", "position": 0.0, "diameter": 0.05, "length": 0.025,
           "radial_clearance": 5e-5, "viscosity": 0.02}  # fmt: skip
    row[key] = value
    with pytest.raises(InputError, match=match):
        support_term(row)


def test_a_valid_table_builds_the_term():
    row = {"type": "finite_journal", "position": 0.1, "diameter": 0.05, "length": 0.025,
           "radial_clearance": 5e-5, "viscosity": 0.02, "groove_angles": [0.0, math.pi],
           "supply_pressure": 2e5}  # fmt: skip
    term = support_term(row)
    assert isinstance(term, FiniteJournal) and term.groove_angles == (0.0, math.pi)
    assert support_term(term.table_entry()) == term
