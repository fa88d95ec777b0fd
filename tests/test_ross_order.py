"""``damped_modes(order="ross")``: modes selected and ordered as ROSS 3.1's ``run_modal``.

Reference: closed forms on uncoupled single-DOF oscillators ``m x'' + c x' + k x = 0`` per
direction: ``lambda = -zeta wn + i wn sqrt(1 - zeta^2)``, ``wn = sqrt(k / m)``,
``zeta = c / (2 sqrt(k m))``. ROSS 3.1's rule (``Rotor._index``): positive damped frequencies
first, by damped frequency, then ``|lambda|``; real roots after them. The comparison with ROSS
itself, mode by mode on its example rotors, is in tests/test_ross_import_ross.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubrotor.errors import InputError
from rubrotor.linear.modes import damped_modes
from rubrotor.rotors.linear import LinearSystem, NodalBasis


def _oscillators(wn, zeta) -> LinearSystem:
    """Uncoupled oscillators of 1 kg, one per (wn rad/s, zeta), on the v DOFs of as many
    nodes (the other DOFs stiff and light, far above)."""
    n = len(wn)
    size = 4 * n
    m = np.full(size, 1e-6)
    k = np.full(size, 1e9)
    c = np.zeros(size)
    for i, (w, z) in enumerate(zip(wn, zeta, strict=True)):
        m[4 * i], k[4 * i], c[4 * i] = 1.0, w**2, 2 * z * w
    return LinearSystem(M=np.diag(m), K=np.diag(k), C=np.diag(c), G=np.zeros((size, size)),
                        basis=NodalBasis(np.arange(n, dtype=float)))  # fmt: skip


def test_ross_order_by_damped_frequency_natural_by_modulus():
    """A heavily damped mode (wn 100 rad/s, zeta 0.9: wd 43.6 rad/s) and a light one (wn 60,
    zeta 0.01): ROSS's order puts the first one first (lower wd), ``|lambda|`` order the
    second; the eigenvalues equal the closed forms to 1e-12."""
    wn, zeta = np.array([60.0, 100.0, 150.0]), np.array([0.01, 0.9, 0.05])
    system = _oscillators(wn, zeta)
    lam = -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2)
    ross = [m.eigenvalue for m in damped_modes(system, 0.0, n=3, order="ross").modes]
    natural = [m.eigenvalue for m in damped_modes(system, 0.0, n=3, order="natural").modes]
    np.testing.assert_allclose(ross, lam[[1, 0, 2]], rtol=1e-12)
    np.testing.assert_allclose(natural, lam[[0, 1, 2]], rtol=1e-12)
    default = [m.eigenvalue for m in damped_modes(system, 0.0, n=3).modes]
    np.testing.assert_allclose(default, natural, rtol=0)  # the default: by |lambda|


def test_overdamped_roots_after_the_oscillating_modes():
    """An overdamped oscillator (zeta 3: two real roots) and two light ones: ROSS's order lists
    the oscillating modes first, by damped frequency (the two, then the stiff filler DOFs'),
    then the real roots by ``|lambda|``."""
    wn, zeta = np.array([50.0, 80.0, 120.0]), np.array([3.0, 0.02, 0.02])
    system = _oscillators(wn, zeta)
    modes = damped_modes(system, 0.0, order="ross").modes
    lam = np.array([m.eigenvalue for m in modes])
    osc = -zeta[1:] * wn[1:] + 1j * wn[1:] * np.sqrt(1 - zeta[1:] ** 2)
    real = np.sort(np.abs(np.roots([1.0, 2 * zeta[0] * wn[0], wn[0] ** 2])))
    np.testing.assert_allclose(lam[:2], osc, rtol=1e-12)
    over = [i for i, m in enumerate(modes) if m.overdamped]
    assert min(over) > max(i for i, m in enumerate(modes) if not m.overdamped)
    np.testing.assert_allclose(np.abs(lam[over[:2]]), real, rtol=1e-10)


def test_order_refused_by_name():
    with pytest.raises(InputError, match="order"):
        damped_modes(_oscillators([10.0], [0.1]), 0.0, order="wd")


def test_cli_modes_default_is_ross_order(tmp_path, capsys):
    """``rubrotor modes --json`` lists a general rotor's modes in ROSS's order: the
    oscillating modes by damped frequency, then the overdamped ones; ``--order natural`` by
    ``|lambda|``."""
    import json
    from importlib import resources

    from rubrotor.cli import main

    path = str(resources.files("rubrotor") / "scenarios" / "general_rotor.toml")
    assert main(["modes", path, "--speed", "300", "--json"]) == 0
    modes = json.loads(capsys.readouterr().out)["modes"]
    over = [m["overdamped"] for m in modes]
    assert over == sorted(over)
    wd = [m["frequency_hz"] for m in modes if not m["overdamped"]]
    assert wd == sorted(wd)
    assert main(["modes", path, "--speed", "300", "--json", "--order", "natural"]) == 0
    natural = json.loads(capsys.readouterr().out)["modes"]
    assert sorted(m["frequency_hz"] for m in natural) == pytest.approx(
        sorted(m["frequency_hz"] for m in modes), rel=1e-9
    )
