"""Tests of rubrotor.analysis.indicators."""

import numpy as np
import pytest

from rubrotor.analysis.indicators import backward_whirl_share, band_energies, rub_indicators
from rubrotor.errors import InputError

FS, SPIN, N = 2000.0, 25.0, 40000
T = np.arange(N) / FS
MODES = [("1F", 180.0, "forward"), ("1B", 150.0, "backward"), ("2F", 420.0, "forward")]


def test_subharmonic_ratio():
    v = (
        np.cos(2 * np.pi * SPIN * T)
        + 0.35 * np.cos(np.pi * SPIN * T + 0.2)
        + 0.05 * np.cos(2 * np.pi * 2 * SPIN * T)
    )
    ind = rub_indicators(v, FS, SPIN)
    assert ind.harmonic_ratio[0.5] == pytest.approx(0.35, abs=1e-5)
    assert ind.harmonic_ratio[2.0] == pytest.approx(0.05, abs=1e-5)
    assert ind.harmonic_ratio[1 / 3] < 1e-5 and ind.harmonic_ratio[3.0] < 1e-5
    assert ind.backward_share is None and ind.band_ratio is None
    assert ind.scalogram_peaks_hz[0] == pytest.approx(SPIN, rel=0.03)
    assert ind.scalogram_peaks_hz[1] == pytest.approx(SPIN / 2, rel=0.03)


def test_forward_orbit_has_no_backward_share():
    z = 1e-4 * np.exp(2j * np.pi * SPIN * T) + 2e-5 * np.exp(2j * np.pi * 180.0 * T)
    assert backward_whirl_share(z.real, z.imag, FS) < 1e-20
    ind = rub_indicators(z.real, FS, SPIN, MODES, w=z.imag)
    assert ind.backward_share < 1e-20
    assert ind.band_energy["1F"] == pytest.approx(4e-10, rel=1e-9)  # R**2 of the 180 Hz whirl
    assert ind.band_energy["1B"] < 1e-30
    zb = np.conj(z)
    assert backward_whirl_share(zb.real, zb.imag, FS) == pytest.approx(1.0, abs=1e-15)


def test_band_energy_by_whirl_and_baseline_ratio():
    base = (
        1e-4 * np.exp(2j * np.pi * SPIN * T)
        + 1e-6 * np.exp(-2j * np.pi * 150.0 * T)
        + 1e-6 * np.exp(2j * np.pi * 180.0 * T)
    )
    rub = base + 3e-6 * np.exp(-2j * np.pi * 150.0 * T)
    ind = rub_indicators(rub.real, FS, SPIN, MODES, w=rub.imag, baseline=(base.real, base.imag))
    assert ind.band_energy["1B"] == pytest.approx(16e-12, rel=1e-9)
    assert ind.band_ratio["1B"] == pytest.approx(16.0, rel=1e-9)
    assert ind.band_ratio["1F"] == pytest.approx(1.0, rel=1e-9)
    assert ind.band_energy["2F"] < 1e-25  # empty band: only rounding noise
    assert 0.0 < ind.backward_share < 0.01


def test_one_sided_band_energy_of_real_tone():
    x = 2.0 * np.cos(2 * np.pi * 180.0 * T)
    e = band_energies(x, FS, MODES)
    assert e["1F"] == pytest.approx(2.0, rel=1e-9)  # A**2 / 2


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: rub_indicators([], FS, SPIN), "v"),
        (lambda: rub_indicators(np.ones(100), 0.0, SPIN), "fs"),
        (lambda: rub_indicators(np.ones(100), FS, -1.0), "spin_hz"),
        (lambda: rub_indicators(np.ones(100), FS, SPIN, w=np.ones(99)), "w"),
        (lambda: rub_indicators(np.ones(100), FS, SPIN, [("a", 1.0, "sideways")]), "modes"),
        (lambda: rub_indicators(np.ones(100), FS, SPIN, [("a", 1e4, "forward")]), "modes"),
        (lambda: backward_whirl_share(np.ones(4), [1.0, np.nan, 1.0, 1.0], FS), "w"),
        (
            lambda: rub_indicators(np.ones(100), FS, SPIN, band_halfwidth_hz=-1.0),
            "band_halfwidth_hz",
        ),
        (
            lambda: rub_indicators(np.ones(100), FS, SPIN, baseline=(np.ones(100), np.ones(100))),
            "baseline",
        ),
    ],
)
def test_bad_input_names_the_field(call, field):
    with pytest.raises(InputError, match=field) as info:
        call()
    assert info.value.field == field
