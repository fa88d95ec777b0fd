"""Fluid-film supports as ``[[bearing]]`` types: static equilibrium, coefficients, oil whirl.

References, each independent of the code under test:
- Ocvirk's short bearing (Ocvirk 1952; Childs 1993, ch. 3): with the pi-film (half-Sommerfeld),
  the load a journal carries at eccentricity ratio ``eps`` is
  ``W = mu Omega R L^3 / (4 c^2) * eps / (1 - eps^2)^2 * sqrt(pi^2 (1 - eps^2) + 16 eps^2)`` and
  its attitude angle ``tan(phi) = pi sqrt(1 - eps^2) / (4 eps)``; ``eps`` is solved here from
  ``W`` with ``brentq`` (xtol 1e-15).
- The closed-form short-bearing coefficients (Friswell, Penny, Garvey, Lees 2010, *Dynamics of
  Rotating Machines*, sec. 5.5.2): ``K = W/c [a_ij]``, ``C = W/(c Omega) [b_ij]`` in their frame
  of ``u`` across the load line and ``v`` along it, the load acting along ``-v``, written out
  below. With gravity along ``-y`` and spin from ``y`` to ``z`` that frame is ``y = -v``,
  ``z = u`` (``T = [[0, -1], [1, 0]]``, ``K_yz = T K_uv T^T``); any other axis assignment
  differs by O(1), not by the 1e-6 asserted.
- Central differences of the film force (step ``1e-5 c`` and ``1e-5 c Omega``), against the
  coefficients ``bearings`` reports.
- Oil whirl: the rotor made rigid (E = 1e16 Pa: its bending stiffness 1.2e12 N/m against
  ~1e7 N/m of film), its translation (mass ``m`` on two equal bearings: 4x4) and tilt (inertia
  about the centre, bearings at ``+-a``: 4x4 with the gyroscopic coupling) assembled here from the
  closed-form coefficients at the Ocvirk equilibrium; the threshold is where the largest real
  part of their eigenvalues crosses zero (``brentq``).
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg
import scipy.optimize

import rubrotor
from rubrotor.errors import InputError, ScenarioError
from rubrotor.forces.supports import support_term
from rubrotor.modelling import Model

G = 9.80665
D, LB, CR, MU = 0.05, 0.02, 5e-5, 0.02  # journal diameter, length, clearance (m), Pa s
R = D / 2

TOML = """
[meta]
name = "journal_rotor"
[speed]
rad_per_s = {speed!r}
[gravity]
y = -9.80665
z = 0.0
[materials.steel]
youngs_modulus = {E!r}
poisson_ratio = 0.3
density = 7810.0
[[section]]
length = 0.5
diameter = 0.05
material = "steel"
elements = 4
[[disk]]
position = 0.25
mass = 10.0
polar_inertia = 0.05
diametral_inertia = 0.03
[[bearing]]
position = 0.0
type = "short_journal"
name = "left"
diameter = {D!r}
length = {LB!r}
radial_clearance = {CR!r}
viscosity = {MU!r}
[[bearing]]
position = 0.5
type = "short_journal"
name = "right"
diameter = {D!r}
length = {LB!r}
radial_clearance = {CR!r}
viscosity = {MU!r}
{extra}
"""


def _write(tmp_path, speed=300.0, E=2.11e11, extra="", name="journal.toml"):
    path = tmp_path / name
    path.write_text(TOML.format(speed=float(speed), E=E, D=D, LB=LB, CR=CR, MU=MU, extra=extra))
    return path


def _ocvirk_load(eps, omega):
    """Ocvirk's load capacity (N) at ``eps`` and spin ``omega`` (module docstring)."""
    return (MU * omega * R * LB**3 / (4 * CR**2) * eps / (1 - eps**2) ** 2
            * math.sqrt(math.pi**2 * (1 - eps**2) + 16 * eps**2))  # fmt: skip


def _ocvirk(w, omega):
    eps = scipy.optimize.brentq(lambda e: _ocvirk_load(e, omega) - w, 1e-12, 1 - 1e-12,
                                xtol=1e-15, rtol=1e-15)  # fmt: skip
    return eps, math.atan2(math.pi * math.sqrt(1 - eps**2), 4 * eps)


def _closed_form(eps, w, omega):
    """Friswell et al. (2010) sec. 5.5.2: K (N/m), C (N s/m) in their frame (u, v)."""
    e2 = eps * eps
    s = math.sqrt(1 - e2)
    pi2 = math.pi**2
    h0 = 1 / (pi2 * (1 - e2) + 16 * e2) ** 1.5
    a = np.array([
        [4 * h0 * (pi2 * (2 - e2) + 16 * e2),
         h0 * math.pi * (pi2 * (1 - e2) ** 2 - 16 * e2 * e2) / (eps * s)],
        [-h0 * math.pi * (pi2 * (1 - e2) * (1 + 2 * e2) + 32 * e2 * (1 + e2)) / (eps * s),
         4 * h0 * (pi2 * (1 + 2 * e2) + 32 * e2 * (1 + e2) / (1 - e2))],
    ])  # fmt: skip
    b = np.array([
        [2 * h0 * math.pi * s * (pi2 * (1 + 2 * e2) - 16 * e2) / eps,
         -8 * h0 * (pi2 * (1 + 2 * e2) - 16 * e2)],
        [-8 * h0 * (pi2 * (1 + 2 * e2) - 16 * e2),
         2 * h0 * math.pi * (pi2 * (1 - e2) ** 2 + 48 * e2) / (eps * s)],
    ])  # fmt: skip
    return w / CR * a, w / (CR * omega) * b


def _half_weight(path):
    rotor = rubrotor.load_scenario(path).rotor
    return 0.5 * rotor.mass * G  # two bearings, symmetric: statics gives each half


@pytest.mark.parametrize("speed", [80.0, 300.0, 2000.0])
def test_static_equals_ocvirk_through_static_and_bearings(tmp_path, speed):
    path = _write(tmp_path, speed)
    eps_ref, phi_ref = _ocvirk(_half_weight(path), speed)
    res = rubrotor.static(path)
    films = [b for b in res.bearings if b.eccentricity_ratio is not None]
    assert len(films) == 2
    for b in films:
        assert b.eccentricity_ratio == pytest.approx(eps_ref, rel=1e-8)
        assert b.attitude_angle_rad == pytest.approx(phi_ref, rel=1e-8)
    rows = rubrotor.bearings(path, [speed]).to_dict()["bearings"]
    assert [r["name"] for r in rows] == ["left", "right"]
    for r in rows:
        assert r["eccentricity_ratio"] == pytest.approx(eps_ref, rel=1e-8)
        assert r["attitude_angle_rad"] == pytest.approx(phi_ref, rel=1e-8)
        assert r["speed_rad_s"] == speed


def test_coefficients_equal_closed_form_and_central_differences(tmp_path):
    path = _write(tmp_path)
    w = _half_weight(path)
    for speed in (100.0, 300.0, 1500.0):
        eps, _ = _ocvirk(w, speed)
        k_uv, c_uv = _closed_form(eps, w, speed)
        t = np.array([[0.0, -1.0], [1.0, 0.0]])
        k_ref, c_ref = t @ k_uv @ t.T, t @ c_uv @ t.T
        (st,) = [s for s in Model.of(path).support_linearisation(speed) if s.name == "left"]
        row = next(r for r in rubrotor.bearings(path, [speed]).to_dict()["bearings"]
                   if r["name"] == "left")  # fmt: skip
        k = np.array([[row["kyy"], row["kyz"]], [row["kzy"], row["kzz"]]])
        c = np.array([[row["cyy"], row["cyz"]], [row["czy"], row["czz"]]])
        np.testing.assert_allclose(k, st.K0, rtol=0, atol=0)
        scale_k, scale_c = np.abs(k_ref).max(), np.abs(c_ref).max()
        assert np.abs(k - k_ref).max() <= 1e-6 * scale_k
        assert np.abs(c - c_ref).max() <= 1e-6 * scale_c
        # central differences of the film force about the static position
        term, p0 = st.term, st.p0
        hq, hv = 1e-5 * CR, 1e-5 * CR * speed
        k_fd, c_fd = np.zeros((2, 2)), np.zeros((2, 2))
        for j in range(2):
            dp = np.zeros(2)
            dp[j] = hq
            k_fd[:, j] = -(term.force(p0 + dp, (0, 0), speed) - term.force(p0 - dp, (0, 0), speed)) / (2 * hq)
            dv = np.zeros(2)
            dv[j] = hv
            c_fd[:, j] = -(term.force(p0, dv, speed) - term.force(p0, -dv, speed)) / (2 * hv)
        assert np.abs(k - k_fd).max() <= 1e-6 * scale_k
        assert np.abs(c - c_fd).max() <= 1e-6 * scale_c


def _rigid_threshold(m, i_d, i_p, a, w, top):
    """Oil-whirl threshold (rad/s) and whirl frequency (rad/s) of a rigid rotor (module docstring)."""

    def blocks(omega):
        eps, _ = _ocvirk(w, omega)
        k, c = _closed_form(eps, w, omega)  # in (u, v): eigenvalues invariant under T
        trans = np.block([[np.zeros((2, 2)), np.eye(2)], [-2 * k / m, -2 * c / m]])
        gyro = omega * i_p * np.array([[0.0, 1.0], [-1.0, 0.0]])
        tilt = np.block([[np.zeros((2, 2)), np.eye(2)],
                         [-2 * a * a * k / i_d, -(2 * a * a * c + gyro) / i_d]])  # fmt: skip
        return np.concatenate([scipy.linalg.eigvals(trans), scipy.linalg.eigvals(tilt)])

    def growth(omega):
        return blocks(omega).real.max()

    grid = np.linspace(50.0, top, 120)
    vals = [growth(x) for x in grid]
    i = next(j for j, v in enumerate(vals) if v > 0)
    th = scipy.optimize.brentq(growth, grid[i - 1], grid[i], xtol=1e-10, rtol=1e-13)
    lam = blocks(th)
    return th, abs(lam[np.argmax(lam.real)].imag)


def test_oil_whirl_threshold_equals_rigid_rotor_characteristic_matrix(tmp_path):
    from rubrotor.linear.modes import _modes
    from rubrotor.linear.stability import stability_threshold

    path = _write(tmp_path, E=1e16)
    sc = rubrotor.load_scenario(path)
    rotor = sc.rotor
    m_s = 7810.0 * math.pi * 0.05**2 / 4 * 0.5
    m = m_s + 10.0
    i_d = 0.03 + m_s * (0.5**2 / 12 + 0.025**2 / 4)  # disk + shaft (slender rod + rotary inertia)
    i_p = 0.05 + m_s * 0.025**2 / 2
    assert rotor.mass == pytest.approx(m, rel=1e-12)
    th_ref, whirl_ref = _rigid_threshold(m, i_d, i_p, 0.25, 0.5 * m * G, 20000.0)
    system = Model.of(path).linear_system()
    th = stability_threshold(system, 20000.0, n=4, points=60, min_speed=50.0)
    # rigid to ~K_film / K_shaft = 1e-5: the thresholds agree to that order
    assert th == pytest.approx(th_ref, rel=1e-4)
    modes = _modes(system, th, 4, natural=False).modes
    crossing = min(modes, key=lambda md: abs(md.damping_ratio))
    whirl = 2 * math.pi * crossing.frequency_hz
    assert whirl == pytest.approx(whirl_ref, rel=1e-4)
    assert whirl / th == pytest.approx(0.5, abs=0.02)  # the whirl ratio near one half


def test_every_linear_verb_runs_with_films(tmp_path):
    path = _write(tmp_path, extra='[[unbalance]]\nposition = 0.25\nmagnitude = 1e-4\n')
    sc = rubrotor.load_scenario(path)
    assert rubrotor.modes(sc, n=4).modes
    assert rubrotor.campbell(sc, "100:1000:4", n=4) is not None
    env = {"PYTHONPATH": str(__import__("pathlib").Path(rubrotor.__file__).parents[1])}
    out = subprocess.run([sys.executable, "-m", "rubrotor", "bearings", str(path), "--speeds",
                          "100:400:3", "--json"], capture_output=True, text=True, env=env,
                         check=True)  # fmt: skip
    rows = json.loads(out.stdout)["bearings"]
    assert len(rows) == 6
    assert set(rows[0]) >= {"name", "speed_rad_s", "eccentricity_ratio", "attitude_angle_rad",
                            "kyy", "kyz", "kzy", "kzz", "cyy", "cyz", "czy", "czz"}  # fmt: skip


@pytest.mark.parametrize(
    ("key", "value", "match"),
    [
        ("radial_clearance", -1e-4, r"bearing\[1\]\.radial_clearance"),
        ("viscosity", 0.0, r"bearing\[1\]\.viscosity"),
        ("length", 0.3, r"bearing\[1\]\.length"),
        ("cavitation", '"bogus"', r"bearing\[1\]\.cavitation"),
        ("viscosity", "nan", r"bearing\[1\]\.viscosity"),
    ],
)
def test_bad_film_keys_are_refused_by_name(tmp_path, key, value, match):
    text = TOML.format(speed=300.0, E=2.11e11, D=D, LB=LB, CR=CR, MU=MU, extra="")
    first = text.index("[[bearing]]")
    head, tail = text[:first], text[first:]
    lines = tail.split("\n")
    for i, line in enumerate(lines):
        if line.startswith(f"{key} ="):
            lines[i] = f"{key} = {value}"
            break
    else:
        lines.insert(2, f"{key} = {value}")
    path = tmp_path / "bad.toml"
    path.write_text(head + "\n".join(lines))
    with pytest.raises((InputError, ScenarioError), match=match):
        rubrotor.load_scenario(path)


def test_zero_speed_and_no_load_are_refused(tmp_path):
    path = _write(tmp_path)
    with pytest.raises(InputError, match="speed = 0"):
        rubrotor.bearings(path, [0.0])
    text = path.read_text().replace("y = -9.80665", "y = 0.0")
    (tmp_path / "noload.toml").write_text(text)
    with pytest.raises(InputError, match="gravity"):
        rubrotor.bearings(tmp_path / "noload.toml", [300.0])


def test_squeeze_film_linearisation():
    """A centred damper: the spring alone holds it, and its pi-film damping is half the full
    film's ``pi mu R L^3 / c^3`` (Childs 1993, eq. 3.x; San Andres 2010)."""
    row = {"type": "squeeze_film", "position": 0.1, "diameter": 0.1, "length": 0.02,
           "radial_clearance": 1e-4, "viscosity": 0.02, "centering_stiffness": 1e6}  # fmt: skip
    damper = support_term(row)
    k, c = damper.linearise((0.0, 0.0))
    full = math.pi * 0.02 * 0.05 * 0.02**3 / 1e-4**3
    np.testing.assert_allclose(k, 1e6 * np.eye(2), rtol=1e-15)
    np.testing.assert_allclose(c, 0.5 * full * np.eye(2), rtol=1e-12, atol=1e-9 * full)
    with pytest.raises(InputError, match="bearing.centering_stiffness"):
        support_term(dict(row, centering_stiffness=-1.0))
    assert support_term(damper.table_entry()) == damper  # the table it writes builds it back


def test_support_linearisation_on_the_engines_mesh(tmp_path):
    """What the engine reads (``Model.support_linearisation`` on its own mesh, built with
    ``only=True``): the same static position and coefficients as the verbs' mesh (two bearings:
    statically determinate), and ``K0``, ``C0`` inside that system's matrices at the speed."""
    path = _write(tmp_path)
    model = Model.of(path)
    engine_system = model.linear_system((0.25,), only=True)
    speed = 400.0
    on_engine = model.support_linearisation(speed, engine_system)
    on_verbs = model.support_linearisation(speed)
    for a, b in zip(on_engine, on_verbs, strict=True):
        np.testing.assert_allclose(a.p0, b.p0, rtol=1e-9)
        np.testing.assert_allclose(a.K0, b.K0, rtol=1e-9)
        assert a.film == b.film and a.term.spins
    mx = engine_system.matrices(speed)
    free = list(engine_system.free)
    for st in on_engine:
        i = [free.index(d) for d in st.dofs]
        bare = engine_system.K[np.ix_(st.dofs, st.dofs)]
        np.testing.assert_allclose(mx.K[np.ix_(i, i)] - bare, st.K0, rtol=1e-12)
        np.testing.assert_allclose(mx.C[np.ix_(i, i)], st.C0, rtol=1e-12)


def test_three_bearings_statically_indeterminate_balance(tmp_path):
    """Three journals on a flexible shaft, the disk off centre: the static solution shares the
    load by the shaft's flexibility; whatever the share, the film forces balance the weight
    and its moment (statics, 1e-9), and the lateral (cross-coupled) forces sum to zero."""
    extra = ('[[bearing]]\nposition = 0.25\ntype = "short_journal"\nname = "middle"\n'
             f"diameter = {D!r}\nlength = {LB!r}\nradial_clearance = {CR!r}\nviscosity = {MU!r}\n")  # fmt: skip
    path = _write(tmp_path, extra=extra)
    path.write_text(path.read_text().replace("[[disk]]\nposition = 0.25", "[[disk]]\nposition = 0.3"))
    sc = rubrotor.load_scenario(path)
    res = rubrotor.static(sc)
    m_s = sc.rotor.mass - 10.0
    weight = sc.rotor.mass * G
    moment = (m_s * 0.25 + 10.0 * 0.3) * G  # about x = 0
    fy = np.array([b.force_y for b in res.bearings])
    fz = np.array([b.force_z for b in res.bearings])
    x = np.array([b.position for b in res.bearings])
    assert fy.sum() == pytest.approx(weight, rel=1e-9)
    assert (x * fy).sum() == pytest.approx(moment, rel=1e-9)
    assert abs(fz.sum()) <= 1e-9 * weight and np.abs(fz).max() > 1e-3 * weight
    assert len({round(v, 6) for v in fy}) == 3  # a share set by the shaft, not by symmetry
