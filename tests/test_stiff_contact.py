"""Very stiff contact: right forces, or a run stopped partial with a message (issue 21).

On seal_rub.toml the reported peak normal force grew as ``k^2`` beyond ``contact.stiffness =
1e16`` N/m (6.95e6 N at 1e17, 6.9e8 N at 1e18) although the applied force had converged: the
normal force was the law at Newton's previous iterate, and the Newton tolerance ``1e-13 k g``
grew with ``k`` until it accepted unconverged forces. References, independent of the kernel's
bookkeeping:

* the contact law evaluated by hand at the saved state (rotor and stator displacements and
  velocities at the seal): ``F_n = k eps + c eps'`` must equal the saved normal force;
* the rigid limit: the peak force must converge as ``k`` grows (the penetration vanishes).
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from test_mangled_scenarios import _dump

import rubrotor

SEAL = Path(str(resources.files("rubrotor") / "scenarios" / "seal_rub.toml"))


def _run(tmp_path, k: float, revolutions: float = 40):
    doc = tomllib.loads(SEAL.read_text())
    doc["simulation"]["revolutions"] = revolutions
    doc["contact"][0]["stiffness"] = k
    path = tmp_path / f"k{k:g}.toml"
    path.write_text(_dump(doc))
    return rubrotor.simulate(rubrotor.load_scenario(path), progress=False), doc["contact"][0]


@pytest.mark.parametrize("k", [2e8, 1e14])
def test_saved_normal_force_is_the_law_at_the_saved_state(k, tmp_path):
    """At 1e14 N/m the saved force was 1.2 N rms off the law at the saved state (the samples
    pressed in: ``k eps > 1 N``)."""
    ds, c = _run(tmp_path, k)
    assert ds.attrs["status"] == "complete"
    v, w = ds["v"].values[0], ds["w"].values[0]
    vd, wd = ds["v_dot"].values[0], ds["w_dot"].values[0]
    ry = v - ds["stator_y"].values[0] - c["offset_y"]
    rz = w - ds["stator_z"].values[0] - c["offset_z"]
    ryd = vd - ds["stator_y_dot"].values[0]
    rzd = wd - ds["stator_z_dot"].values[0]
    d = np.hypot(ry, rz)
    law = c["stiffness"] * (d - c["clearance"]) + c["damping"] * (ry * ryd + rz * rzd) / d
    law = np.maximum(law, 0.0)  # a contact separating faster than its damping pulls: no force
    fn = ds["normal_force"].values[0]
    # pressed in (k eps > 1 N): not the grazing closures, where by design the force is a part
    # of the law's (complementarity at eps = 0, 0 <= F_n <= c eps')
    touching = c["stiffness"] * (d - c["clearance"]) > 1.0
    assert touching.sum() > 1000
    np.testing.assert_allclose(fn[touching], law[touching], rtol=1e-6, atol=1e-3)
    applied = np.hypot(ds["force_y"].values[0], ds["force_z"].values[0])
    np.testing.assert_allclose(applied[touching], fn[touching] * np.hypot(1, c["friction"]),
                               rtol=1e-3)  # fmt: skip


def test_peak_force_converges_to_the_rigid_limit(tmp_path):
    """Peaks at 1e15, 1e16 and 1e18 N/m agree to 1e-4 (they were 5935, 5954, 6.9e8 N; now
    5935.30, 5935.08, 5935.05). Five revolutions hold the peak (t = 0.036 s); over 40, the
    stiffer runs may stop partial later, at a contact the step cannot resolve."""
    peaks = {}
    for k in (1e15, 1e16, 1e18):
        ds, _ = _run(tmp_path, k, revolutions=5)
        assert ds.attrs["status"] == "complete", ds.attrs["status_message"]
        peaks[k] = float(ds["normal_force"].max())
    assert peaks[1e16] == pytest.approx(peaks[1e15], rel=1e-4)
    assert peaks[1e18] == pytest.approx(peaks[1e15], rel=1e-4)


def test_unresolvable_stiffness_stops_partial_naming_it(tmp_path):
    """At 1e30 N/m the run completed with a 6.95e32 N peak; it now stops partial, the message
    naming the stiffness and the step, and every saved force is finite and physical."""
    ds, _ = _run(tmp_path, 1e30)
    assert ds.attrs["status"] == "partial"
    msg = ds.attrs["status_message"]
    assert "contact[1].stiffness" in msg and "simulation.dt" in msg
    fn = ds["normal_force"].values
    assert np.all(np.isfinite(fn)) and fn.max() < 1e4
