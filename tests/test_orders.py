"""Order tracking, cascade, shaft centreline and order-filtered orbits (rubrotor.analysis.orders,
rubrotor.analysis.diagnostics, rubrotor.analysis.measured)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from rubrotor.analysis.diagnostics import cascade, filtered_orbit, keyphasor_marks, shaft_centreline
from rubrotor.analysis.measured import read_csv_table, spin_from_table, time_column
from rubrotor.analysis.orders import (
    block_revolutions,
    spin_from_dataset,
    spin_from_keyphasor,
    spin_from_speed,
    track_orders,
)
from rubrotor.errors import InputError

sys.path.insert(0, str(Path(__file__).parent))
from orders_reference import KNOWN, SLOW_RUNUP, synthetic  # noqa: E402


def test_slow_runup_order_tracking_equals_steady_unbalance_response(tmp_path):
    """1X of a slow contact-free run-up equals the steady unbalance response away from the
    critical speed.

    Reference: :func:`rubrotor.linear.response.unbalance_response`, the frequency-domain solve of
    the full FE rotor at each block's mean speed (an independent route: no time stepping, no
    modal reduction). Measured at ``|Omega / Omega_c - 1| > 0.2``: amplitude within 0.38 %,
    phase within 0.014 rad, complex relative error <= 1.45 % (the run-up's phase lag, largest
    just below the critical; 0.13-0.35 % at 1.5 Omega_c).
    """
    from rubrotor.engine.general import engine_problem
    from rubrotor.engine.simulate import simulate
    from rubrotor.linear.response import unbalance_response
    from rubrotor.scenario.load import load_scenario

    path = tmp_path / "slow.toml"
    path.write_text(SLOW_RUNUP)
    scenario = load_scenario(path)
    ds = simulate(scenario)
    system, _, kw, _ = engine_problem(scenario)
    planes = [(u.position, u.magnitude, u.phase) for u in kw["unbalances"]]
    spin = spin_from_dataset(ds)
    critical = 272.0  # rad/s, first forward critical (damped_modes at 270 rad/s: 271.98)
    for j, probe in enumerate(ds["station"].values):
        track = track_orders(spin, ds["v"].values[j], ds["w"].values[j], orders=[1.0, 2.0])
        sel = (track.time_s > 1.0) & (np.abs(track.speed_rad_s / critical - 1) > 0.2)
        speeds = track.speed_rad_s[sel]
        assert speeds.min() < 150 and speeds.max() > 400 and sel.sum() > 200
        ref = unbalance_response(system, speeds, planes, [probe]).complex_response[:, 0]
        i = track.order_index(1.0)
        for got, want in ((track.y[i, sel], ref[:, 0]), (track.w[i, sel], ref[:, 1])):
            err = np.abs(got - want) / np.abs(want)
            assert err.max() < 0.02
            assert np.abs(np.abs(got) / np.abs(want) - 1).max() < 0.02
            assert np.abs(np.angle(got / want)).max() < 0.02  # rad
        # a linear rotor under unbalance has no 2X: what the Hann blocks read there is the
        # growth of 1X within a block (measured <= 0.13 % of 1X past 140 rad/s)
        late = speeds > 140.0
        two = np.hypot(np.abs(track.y[1, sel]), np.abs(track.w[1, sel]))[late]
        assert np.max(two / np.abs(ref[late, 0])) < 3e-3


def _check_known(track, tol):
    for order, ((ay, py), (az, pz)) in KNOWN.items():
        i = track.order_index(order)
        for got, amp, ph in ((track.y[i], ay, py), (track.w[i], az, pz)):
            assert np.max(np.abs(np.abs(got) / amp - 1)) < tol
            assert np.max(np.abs(np.angle(got * np.exp(-1j * ph)))) < tol


@pytest.mark.parametrize("column", ["speed_rad_s", "rpm", "keyphasor"])
def test_measured_csv_orders_to_1e_3(tmp_path, column):
    """A measured-style CSV (time column, speed in rad/s or rev/min, or a keyphasor) with known
    1X and 2X amplitudes and phases, speed rising 60 -> 180 rad/s at 40 rad/s^2.

    Reference: the amplitudes and phases the signal was built with. Tolerance 1e-3 relative
    (amplitude) and 1e-3 rad (phase); measured errors are below 2e-5 (cubic-spline resampling).
    The keyphasor is ``sin(theta)``, whose rising zero crossing is at ``theta = 0 mod 2 pi``.
    """
    fs = 4000.0
    t = np.arange(int(3.0 * fs)) / fs
    theta = 60.0 * t + 20.0 * t**2
    y, z = synthetic(t, theta)
    speed = 60.0 + 40.0 * t
    col = {"speed_rad_s": speed, "rpm": speed * 60 / (2 * math.pi), "keyphasor": np.sin(theta)}
    data = np.column_stack([t, col[column], y, z])
    path = tmp_path / "probe.csv"
    np.savetxt(path, data, delimiter=",", header=f"time,{column},y,z", comments="")
    table = read_csv_table(path)
    assert time_column(table)[1] == pytest.approx(fs, rel=1e-9)
    spin = spin_from_table(table)
    track = track_orders(spin, table["y"], table["z"], orders=[0.5, 1.0, 2.0])
    assert track.revolutions == 4  # 0.5X needs 2 revolutions, doubled for the Hann window
    _check_known(track, 1e-3)
    sel = np.isfinite(spin.speed)
    want = 60.0 + 40.0 * track.time_s
    assert np.max(np.abs(track.speed_rad_s / want - 1)) < 1e-5
    assert np.max(np.abs(spin.speed[sel] - speed[sel])) < 1e-5 * speed.max()
    assert np.max(np.abs(track.y[0])) < 1e-8  # no 0.5X in the signal


def test_forward_backward_components():
    """A forward circle of radius 10 um at 1X and a backward circle of 3 um at 2X.

    Reference: z = 10e-6 exp(i theta) + 3e-6 exp(-2 i theta), so F(1X) = 10 um, B(1X) = 0,
    F(2X) = 0, B(2X) = 3 um, exactly.
    """
    t = np.arange(8000) / 4000.0
    spin = spin_from_speed(t, np.full(t.size, 100.0))
    orbit = 10e-6 * np.exp(1j * spin.angle) + 3e-6 * np.exp(-2j * spin.angle)
    tr = track_orders(spin, orbit.real, orbit.imag, orders=[1.0, 2.0])
    assert np.allclose(np.abs(tr.forward[0]), 10e-6, rtol=1e-6)
    assert np.allclose(np.abs(tr.backward[1]), 3e-6, rtol=1e-6)
    assert np.abs(tr.backward[0]).max() < 1e-11 and np.abs(tr.forward[1]).max() < 1e-11


def test_centreline_cascade_and_filtered_orbit():
    """Shaft centreline, cascade and 1X-filtered orbit of the synthetic signal of known orders.

    References: the mean position (3, -5) um of the signal; its 1X component
    25 cos(theta + 0.7), 18 cos(theta - 1.2) um; 1X at 100 rad/s in the cascade with the Hann
    amplitude within its scalloping loss (<= 15 %, 2x zero padding: <= 4 %).
    """
    fs = 4000.0
    t = np.arange(int(2.0 * fs)) / fs
    spin = spin_from_speed(t, np.full(t.size, 100.0))
    y, z = synthetic(t, spin.angle)
    cl = shaft_centreline(spin, y, z)
    assert np.allclose(cl.y, 3e-6, rtol=1e-6) and np.allclose(cl.z, -5e-6, rtol=1e-6)
    assert np.allclose(cl.speed_rad_s, 100.0, rtol=1e-9)
    tr = track_orders(spin, y, z, orders=[1.0, 2.0])
    fy, fz = filtered_orbit(spin, tr, 1.0)
    ok = np.isfinite(fy)
    assert ok.sum() > t.size // 2
    assert np.max(np.abs(fy[ok] - 25e-6 * np.cos(spin.angle[ok] + 0.7))) < 1e-3 * 25e-6
    assert np.max(np.abs(fz[ok] - 18e-6 * np.cos(spin.angle[ok] - 1.2))) < 1e-3 * 18e-6
    tm, _, _ = keyphasor_marks(spin, y, z)
    assert np.allclose(np.diff(tm), 2 * math.pi / 100.0, rtol=1e-9)
    c = cascade(spin, y, revolutions=8)
    k = np.argmax(c.amplitude[0])
    assert c.frequency_rad_s[k] == pytest.approx(100.0, rel=0.05)
    assert c.amplitude[0, k] == pytest.approx(25e-6, rel=0.05)
    full = cascade(spin, 4e-6 * np.cos(spin.angle), -4e-6 * np.sin(spin.angle), revolutions=8)
    k = np.argmax(full.amplitude[0])
    assert full.full and full.frequency_rad_s[k] == pytest.approx(-100.0, rel=0.05)


def test_order_tracking_errors_name_the_field():
    """Bad input names the field, the value and what is allowed."""
    t = np.arange(400) / 400.0
    spin = spin_from_speed(t, np.full(t.size, 60.0))
    with pytest.raises(InputError, match="orders"):
        track_orders(spin, np.sin(spin.angle), orders=[0.0])
    with pytest.raises(InputError, match="revolutions"):
        track_orders(spin, np.sin(spin.angle), orders=[0.5], revolutions=3)
    with pytest.raises(InputError, match="Nyquist"):  # 25X of 60 rad/s: 1500 > 400 pi rad/s
        track_orders(spin, np.sin(spin.angle), orders=[25.0])
    with pytest.raises(InputError, match="keyphasor"):
        spin_from_keyphasor(t, np.zeros(t.size))
    with pytest.raises(InputError, match="speed"):
        spin_from_speed(t, -np.ones(t.size))
    assert block_revolutions([1 / 3, 0.5, 2.0]) == 6


def test_diagnostics_figures_draw_the_tracked_data():
    """Each figure draws the numbers of the analysis it is given (read back from its artists).

    References: the track's |Y| (um) on the Bode amplitude axis; the centreline's mean position
    and the clearance circle's radius on the centreline plot; the order lines' slope k in the
    cascade.
    """
    from rubrotor.plotting.diagnostics import (
        bode_figure,
        cascade_figure,
        centreline_figure,
        mark_orders,
        orbit_figure,
        polar_figure,
    )

    fs = 4000.0
    t = np.arange(int(3.0 * fs)) / fs
    spin = spin_from_speed(t, 60.0 + 40.0 * t)
    y, z = synthetic(t, spin.angle)
    tr = track_orders(spin, y, z, orders=[1.0, 2.0])
    fig = bode_figure({0.5: tr}, orders=(1.0,))
    line = fig.axes[0].lines[0]
    assert np.allclose(line.get_ydata(), np.abs(tr.y[0]) * 1e6)
    assert np.allclose(line.get_xdata(), tr.speed_rad_s)
    assert "rev/min" in bode_figure({0.5: tr}, rpm=True).axes[1].get_xlabel()
    # Bently-Nevada phase lag of 25 cos(theta + 0.7): the next positive peak is 2 pi - 0.7 on
    lag = bode_figure({0.5: tr}, orders=(1.0,), phase="lag").axes[1].lines[0].get_ydata()
    assert np.allclose(lag, 360.0 - np.degrees(0.7), atol=0.06)
    pol = polar_figure(tr, order=2.0, direction="z")
    assert np.allclose(pol.axes[0].lines[0].get_ydata(), 4.0, rtol=1e-3)  # 2X z: 4 um
    cl = shaft_centreline(spin, y, z)
    cf = centreline_figure(cl, clearance=50e-6)
    circle = cf.axes[0].lines[0]
    assert np.allclose(np.hypot(circle.get_xdata(), circle.get_ydata()), 50.0)
    assert np.allclose(cf.axes[0].collections[0].get_offsets()[:, 1], 3.0, rtol=1e-6)
    casc = cascade(spin, y, z, revolutions=4)
    order_lines = [ln for ln in cascade_figure(casc).axes[0].lines if ln.get_linestyle() == "--"]
    slopes = sorted(
        {round(float(np.ptp(ln.get_xdata()) / np.ptp(ln.get_ydata())), 9) for ln in order_lines}
    )
    assert slopes == [0.5, 1.0, 2.0, 3.0]
    of = orbit_figure(spin, y, z, tr, at_speed=100.0, revolutions=2, clearance=50e-6)
    assert len(of.axes) == 2 and len(of.axes[1].lines) == 3  # circle, filtered orbit, marks
    from matplotlib.figure import Figure

    ax = Figure().add_subplot()
    ax.set_ylim(1, 100)
    mark_orders(ax, spin.time, spin.speed, orders=(1.0, 2.0))
    two = ax.lines[1]
    assert np.allclose(two.get_ydata(), 2 * spin.speed / (2 * math.pi))  # 2X in Hz
    assert np.allclose(two.get_xdata(), spin.time * 1e3)  # ms


def test_coast_down_tracks_like_a_run_up():
    """A coast-down (180 -> 60 rad/s at -40 rad/s^2) reads the same known orders to 1e-3, with
    speeds falling block by block. Reference: the signal's built-in amplitudes and phases and
    its speed law."""
    fs = 4000.0
    t = np.arange(int(3.0 * fs)) / fs
    spin = spin_from_speed(t, 180.0 - 40.0 * t)
    y, z = synthetic(t, spin.angle)
    track = track_orders(spin, y, z, orders=[1.0, 2.0])
    _check_known(track, 1e-3)
    assert np.all(np.diff(track.speed_rad_s) < 0)
    assert np.allclose(track.speed_rad_s, 180.0 - 40.0 * track.time_s, rtol=1e-6)
    casc = cascade(spin, y, z, revolutions=4)
    assert np.all(np.diff(casc.speed_rad_s) < 0)


def test_constant_speed_run_gives_one_steady_phasor(tmp_path):
    """A constant-speed contact-free run started on its steady state: ``dataset_orders`` gives
    one speed per order and the 1X of the steady unbalance response.

    Reference: :func:`rubrotor.linear.response.unbalance_response` of the full FE rotor at
    200 rad/s. The run keeps 6 modes plus the residual flexibility, exact at steady state:
    measured difference 5.7e-8 (the engine's and the resampling's round-off), tolerance 1e-6.
    2X and 0.5X are absent from a linear response (measured below 1e-12 of 1X).
    """
    from rubrotor.analysis.orders import dataset_orders
    from rubrotor.engine.general import engine_problem
    from rubrotor.engine.simulate import simulate
    from rubrotor.linear.response import unbalance_response
    from rubrotor.scenario.load import load_scenario

    text = SLOW_RUNUP.split("[speed]")[0] + "[speed]\nrad_per_s = 200.0\n"
    text += SLOW_RUNUP.split("step = 6.0")[1].replace("duration = 11.0", "duration = 1.0")
    path = tmp_path / "steady.toml"
    path.write_text(text + '[initial]\nstate = "steady"\n')
    scenario = load_scenario(path)
    ds = simulate(scenario)
    system, _, kw, _ = engine_problem(scenario)
    planes = [(u.position, u.magnitude, u.phase) for u in kw["unbalances"]]
    rows = dataset_orders(ds)
    assert {(r["probe_m"], r["order"]) for r in rows} == {
        (p, k) for p in (0.25, 0.5) for k in (0.5, 1.0, 2.0)
    }
    for r in rows:
        assert r["speed_rad_s"] == pytest.approx([200.0], rel=1e-12)
        resp = unbalance_response(system, [200.0, 201.0], planes, [r["probe_m"]])
        ref = resp.complex_response[0, 0]  # at 200 rad/s
        got = np.array([r["amplitude_y_m"][0] * np.exp(1j * r["phase_y_rad"][0]),
                        r["amplitude_z_m"][0] * np.exp(1j * r["phase_z_rad"][0])])  # fmt: skip
        if r["order"] == 1.0:
            assert np.max(np.abs(got - ref) / np.abs(ref)) < 1e-6
        else:
            assert np.max(np.abs(got)) < 1e-9 * np.abs(ref).max()
