"""ROSS rotors as scenarios (``Scenario.from_ross``, ``rubrotor import-ross``) against ROSS.

Reference: :func:`rubrotor.rotors.ross.from_ross`, whose matrices equal ROSS's own
``Rotor.M``, ``K``, ``C``, ``G`` (tests/test_ross_interop.py, tests/test_ross_parity.py), and
ROSS's ``run_static``. For ROSS's example rotors (``rotor_example``,
``rotor_example_with_damping``, ``compressor_example``, ``rotor_example_amb_simple``) and the
parity rotors (housings with bearing mass, a 2-D speed x frequency seal, ``rotor8``): the
scenario, from the ROSS object and from the file ``Rotor.save`` wrote, saved and loaded back,
gives the same linear system as ``from_ross`` to 1e-12 of each matrix's largest entry
(measured <= 9e-15: the compressor's 91 elements summed in another order). Runs where ROSS is
installed (CI's ROSS venvs); skipped otherwise.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

with warnings.catch_warnings():  # ROSS's import warns about REFPROP (its ccp dependency)
    warnings.simplefilter("ignore")
    if os.environ.get("RUBROTOR_REQUIRE_ROSS"):
        import ross
    else:
        ross = pytest.importorskip("ross")

from rubrotor import load_scenario  # noqa: E402
from rubrotor.cli.app import main  # noqa: E402
from rubrotor.rotors.ross import from_ross  # noqa: E402
from rubrotor.scenario.load import Scenario  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
import test_ross_parity as parity  # noqa: E402

pytestmark = pytest.mark.filterwarnings("ignore")
ROSS3 = int(ross.__version__.split(".")[0]) >= 3
TOL = 1e-12


def _quiet(fn, *args, **kwargs):
    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


def _amb():
    from ross.bearings.magnetic.amb_models import rotor_example_amb_simple

    return rotor_example_amb_simple()


ROTORS = {
    "rotor_example": lambda: ross.rotor_example(),
    "rotor_example_with_damping": lambda: ross.rotor_example_with_damping(),
    "compressor_example": lambda: ross.compressor_example(),
    "amb_simple": _amb,
    "housings": parity.housings,
    "seal_2d": parity.seal_2d,
    "rotor8": parity.rotor8,
}


@pytest.fixture(scope="module", params=list(ROTORS))
def rotor(request):
    if request.param in ("amb_simple", "seal_2d") and not ROSS3:
        pytest.skip("magnetic bearings and 2-D tables: ROSS 3.x")
    if request.param == "rotor_example_with_damping" and not hasattr(ross, request.param):
        pytest.skip("not in this ROSS")
    return request.param, _quiet(ROTORS[request.param])


def _speeds(rotor) -> np.ndarray:
    """Where to compare: 0, each table point, between them and beyond (rad/s)."""
    pts = parity._axis_points(rotor)
    mids = 0.5 * (pts[1:] + pts[:-1]) if pts.size > 1 else np.zeros(0)
    return np.unique(np.concatenate([[0.0, 150.0, 3000.0], pts, mids]))


def _worst(a, b, speeds) -> float:
    worst = 0.0
    for w in speeds:
        ma, mb = a.matrices(w), b.matrices(w)
        for nm in "MKCG":
            ref = getattr(mb, nm)
            err = np.abs(getattr(ma, nm) - ref).max() / max(np.abs(ref).max(), 1e-300)
            worst = max(worst, err)
    return worst


def test_scenario_equals_from_ross(rotor, tmp_path):
    """From the object and from ROSS's saved file, through a saved scenario: the same nodes and
    matrices as from_ross at 0, every table point, between them and beyond."""
    name, r = rotor
    pts = parity._axis_points(r)
    old = not ROSS3 and pts.size  # ROSS 2.3's splines: read each element at every table point
    ref = from_ross(r, speeds=pts) if old else from_ross(r)
    saved = tmp_path / f"{name}.toml"
    _quiet(r.save, saved)
    sources = [(r, {"speeds": pts} if old else {})]
    if not old:  # a 2.3 file holds the tables, not ROSS 2.3's splines between them
        sources.append((saved, {}))
    for src, kw in sources:
        sc = Scenario.from_ross(src, **kw)
        back = load_scenario(sc.save(tmp_path / f"{name}_scenario.toml"))
        system = back.rotor.linear_system()
        np.testing.assert_allclose(system.basis.nodes, ref.basis.nodes, rtol=0, atol=1e-12)
        err = _worst(system, ref, _speeds(r))
        print(f"{name} from {type(src).__name__}: {err:.2e}")
        assert err <= TOL


def test_cli_static_equals_run_static(rotor, tmp_path, capsys):
    """import-ross, a ``[gravity]`` of ROSS's run_static (9.8065 m/s^2 along ROSS's -y, our -z),
    then ``rubrotor static --json``: with two bearings the reactions are statically
    determinate, so they equal ROSS's (rigid supports) to 1e-9 of the largest."""
    name, r = rotor
    if name not in ("rotor_example", "rotor_example_with_damping", "compressor_example"):
        pytest.skip("two-bearing example rotors (seals carry no static load in ROSS)")
    saved = tmp_path / f"{name}.toml"
    _quiet(r.save, saved)
    out = tmp_path / "scenario.toml"
    assert main(["import-ross", str(saved), "--out", str(out)]) == 0
    out.write_text(out.read_text() + "\n[gravity]\nz = -9.8065\n")
    capsys.readouterr()
    if name == "compressor_example":
        pytest.skip("the 12 seals share the static load in rubrotor's static verb")
    assert main(["static", str(out), "--json"]) == 0
    mine = json.loads(capsys.readouterr().out)
    _quiet(r.run_static)
    theirs = np.array(list(r.bearing_forces_nodal.values()), float)
    got = np.array([b["force_z_N"] for b in mine["bearings"]], float)
    print(name, got, theirs)
    assert np.abs(got - theirs).max() <= 1e-9 * np.abs(theirs).max()
