"""Tests of rubrotor.analysis.spectra."""

import numpy as np
import pytest

from rubrotor.analysis.spectra import amplitude_spectrum, full_spectrum, order_spectrum
from rubrotor.errors import InputError


@pytest.mark.parametrize("window", ["hann", "boxcar", "flattop"])
def test_amplitude_spectrum_reads_tone_amplitude(window):
    fs, n = 1000.0, 4000
    t = np.arange(n) / fs
    x = 0.5 + 2.5 * np.cos(2 * np.pi * 50.0 * t + 1.0) + 0.7 * np.sin(2 * np.pi * 120.0 * t)
    spec = amplitude_spectrum(x, fs, window=window)
    assert spec.frequencies[-1] == pytest.approx(fs / 2)
    read = dict(zip(spec.frequencies, spec.amplitudes, strict=True))
    assert read[50.0] == pytest.approx(2.5, rel=1e-12)
    assert read[120.0] == pytest.approx(0.7, rel=1e-12)
    assert read[0.0] == pytest.approx(0.5, rel=1e-12)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_circular_orbit_lands_in_its_half(sign):
    fs, n, radius, f = 1000.0, 2000, 1.3, 37.0
    t = np.arange(n) / fs
    z = radius * np.exp(sign * 2j * np.pi * f * t)
    spec = full_spectrum(z.real, z.imag, fs)
    assert np.all(np.diff(spec.frequencies) > 0)
    k = np.argmax(spec.amplitudes)
    assert spec.frequencies[k] == pytest.approx(sign * f)
    assert spec.amplitudes[k] == pytest.approx(radius, rel=1e-12)
    other = spec.amplitudes[np.sign(spec.frequencies) == -sign]
    assert np.max(other) < 1e-12 * radius


def test_unidirectional_vibration_splits_evenly():
    fs, n = 100.0, 1000
    t = np.arange(n) / fs
    spec = full_spectrum(2.0 * np.cos(2 * np.pi * 5.0 * t), np.zeros(n), fs)
    read = dict(zip(spec.frequencies, spec.amplitudes, strict=True))
    assert read[5.0] == pytest.approx(1.0) and read[-5.0] == pytest.approx(1.0)


def test_order_spectrum_off_bin():
    fs, n, spin = 1000.0, 12345, 23.7  # orders fall between bins
    t = np.arange(n) / fs
    x = (
        1.0 * np.cos(2 * np.pi * spin * t)
        + 0.3 * np.cos(np.pi * spin * t + 0.4)
        + 0.1 * np.cos(2 * np.pi * 3 * spin * t)
    )
    spec = order_spectrum(x, fs, spin)
    amps = dict(zip(np.round(spec.frequencies, 6), spec.amplitudes, strict=True))
    assert amps[1.0] == pytest.approx(1.0, abs=1e-4)
    assert amps[0.5] == pytest.approx(0.3, abs=1e-4)
    assert amps[3.0] == pytest.approx(0.1, abs=1e-4)
    assert amps[2.0] < 1e-4 and amps[round(1 / 3, 6)] < 1e-4


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: amplitude_spectrum([], 10.0), "signal"),
        (lambda: amplitude_spectrum([1.0, np.nan], 10.0), "signal"),
        (lambda: amplitude_spectrum([1.0, 2.0], 0.0), "fs"),
        (lambda: amplitude_spectrum([1.0, 2.0, 3.0], 10.0, window="nope"), "window"),
        (lambda: full_spectrum(np.zeros(8), np.zeros(9), 10.0), "w"),
        (lambda: full_spectrum(np.zeros(8), [np.inf] * 8, 10.0), "w"),
        (lambda: full_spectrum([], np.zeros(8), 10.0), "v"),
        (lambda: order_spectrum(np.zeros(64), 10.0, -1.0), "spin_hz"),
        (lambda: order_spectrum(np.zeros(64), 10.0, 2.0), "orders"),
        (lambda: order_spectrum(np.zeros(64), -10.0, 1.0), "fs"),
    ],
)
def test_bad_input_names_the_field(call, field):
    with pytest.raises(InputError, match=field) as info:
        call()
    assert info.value.field == field
