"""Two contact stations at once on the general engine, against a full-DOF SciPy reference.

Rotor: the finite-element rotor of tests/test_engine.py (two disks, anisotropic cross-coupled
bearings, gravity, two unbalance planes). Contacts: a seal at 0.5 m (Hertz law with
Hunt-Crossley damping against a rigid stator offset by 40 um) and the disk at 0.33 m (linear
spring, no dashpot, against a flexible, anisotropic, offset stator), both with friction. The
Newton solve covers both contacts together whenever both touch.

Reference: tests/engine_reference.py (solve_ivp DOP853 on ``M q'' + D q' + K q = f`` on every
DOF, no modal reduction, the same contact laws on the relative displacement, rtol 1e-11,
atol 1e-14). Both laws start from zero force at the onset (no contact dashpot jump); the fixed
step still converges at first order (fitted slopes 1.00-1.01, also without friction and with a
rigid stator: the onset/separation steps of the kernel are first order), so tight agreement
comes from the adaptive steps (rtol 1e-8: 1e-7 relative).
"""

import sys
from pathlib import Path

import numpy as np
import pytest

from rubrotor.engine.driver import simulate_general
from rubrotor.engine.parts import RubStation, Run, Stator
from rubrotor.rotors.forces import Contact, Unbalance

sys.path.insert(0, str(Path(__file__).parent))
from engine_reference import reference_run, two_disk_rotor  # noqa: E402

GRAVITY = (-9.81, 0.0)
SPEED = 300.0  # rad/s
DURATION = 0.04  # s


def two_contact_case():
    """FE rotor with a seal (Hertz, rigid offset stator) and a disk (linear, flexible stator)."""
    rotor = two_disk_rotor()
    disk = Contact(clearance=1e-4, stiffness=2e7, damping=0.0, friction=0.2, position=0.33,
                   law="linear", radius=0.1)  # fmt: skip
    seal = Contact(clearance=8e-5, stiffness=5e9, damping=0.5, friction=0.1, position=0.5,
                   law="hertz", radius=0.03)  # fmt: skip
    stations = [
        RubStation(disk, offset_y=-1e-4, offset_z=5e-5, stator=Stator(20, 25, 5e6, 6e6, 500, 500)),
        RubStation(seal, offset_y=-4e-5, offset_z=0.0),
    ]
    unb = [Unbalance(2e-4, 0.33, 0.0), Unbalance(1e-4, 0.67, 1.0)]
    return rotor.linear_system(), stations, unb


@pytest.fixture(scope="module")
def reference():
    system, stations, unb = two_contact_case()
    run = Run(speed=SPEED, duration=DURATION, step=1e-4, initial="rest")
    t, rot, sta, _ = reference_run(system, run, stations, unb, gravity=GRAVITY,
                                   rtol=1e-10, atol=1e-14)  # fmt: skip
    return t, rot, sta


def _run(step, **kw):
    system, stations, unb = two_contact_case()
    run = Run(speed=SPEED, duration=DURATION, step=step, save_every=round(1e-4 / step),
              initial="rest", **kw)  # fmt: skip
    return simulate_general(system, run, stations, unb, gravity=GRAVITY, progress=False)


def _errors(res, ref):
    """Relative max errors: rotor at each contact (2), then the flexible stator."""
    t, rot, sta = ref
    n = min(len(t), res.channels.shape[1])
    ch = res.channels
    e = []
    for i in range(2):
        d = np.abs(ch[4 * i : 4 * i + 2, :n] - rot[i, :, :n]).max()
        e.append(d / np.abs(rot[i, :, :n]).max())
    s = np.abs(ch[8:10, :n] - sta[0, :, :n]).max() / np.abs(sta[0, :, :n]).max()
    return e + [s]


def test_two_contacts_match_full_dof_scipy(reference):
    """Both contacts rub (onsets at each), and the error at each station and on the stator
    falls with the step at the measured first order (fitted slope > 0.9) to below 1e-3 at
    h = 2.5e-6 s (printed: 1.1e-4 and 1.3e-4 at the contacts, 7.3e-4 on the stator)."""
    steps = [1e-5, 5e-6, 2.5e-6]
    runs = [_run(h) for h in steps]
    for r in runs:
        assert r.status == "complete", r.message
    ev = runs[-1].events
    onsets = [int(np.sum(ev[:, 1] == i + 1)) for i in range(2)]
    assert min(onsets) >= 2, onsets  # both stations really touch
    errs = np.array([_errors(r, reference) for r in runs])
    slopes = [np.polyfit(np.log(steps), np.log(errs[:, k]), 1)[0] for k in range(3)]
    print("onsets", onsets, "errors", errs.tolist(), "slopes", slopes)
    assert min(slopes) > 0.9
    assert errs[-1].max() < 1e-3


def test_two_contacts_adaptive_meets_tolerance(reference):
    """Adaptive steps (rtol 1e-8) agree with the reference to 1e-6 at both contacts and on the
    stator (printed: 1.1e-7, 1.3e-7, 4.4e-7)."""
    res = _run(1e-4, rtol=1e-8, atol=1e-13)
    assert res.status == "complete", res.message
    errs = _errors(res, reference)
    print("adaptive errors", errs, "steps", res.stats["accepted_steps"])
    assert max(errs) < 1e-6
