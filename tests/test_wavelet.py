"""Tests of rubrotor.analysis.wavelet against closed forms and an explicit DFT definition."""

import numpy as np
import pytest

from rubrotor.analysis.wavelet import (
    cwt,
    cwt_binned,
    inner_scalogram,
    log_frequencies,
    scale_from_frequency,
    scalogram,
)
from rubrotor.errors import InputError

OMEGA0 = 6.0


def _interior(n, s):
    margin = int(np.ceil(9.0 * s))  # beyond the float64 truncation half-width 8.49 s
    return slice(margin, n - margin)


@pytest.mark.parametrize("order", [0.5, 1.0, 3.0])
@pytest.mark.parametrize("padding", ["symmetric", "periodic", "zero"])
def test_tone_reads_its_amplitude_at_its_scale(order, padding):
    # |W| = A exactly for the non-corrected analytic Morlet; the only departures are the
    # negative-frequency response 2*exp(-2*omega0**2) ~ 1e-31 and the truncation at eps.
    fs, spin, amp, n = 1000.0, 25.0, 1.7, 8000
    f_tone = order * spin
    t = np.arange(n) / fs
    x = amp * np.cos(2 * np.pi * f_tone * t + 0.3)
    freqs = np.sort(np.concatenate([log_frequencies(5.0, 200.0, 40), [f_tone]]))
    res = cwt(x, fs, freqs, dtype=np.complex128, padding=padding)
    j = int(np.searchsorted(freqs, f_tone))
    s = res.metadata["scales"][j]
    inner = _interior(n, s)
    mag = np.abs(res.coefficients[:, inner])
    assert np.max(np.abs(mag[j] - amp)) < 1e-9
    assert np.all(np.argmax(mag, axis=0) == j)
    # the phase follows the tone
    phase = np.angle(res.coefficients[j, inner] * np.exp(-1j * (2 * np.pi * f_tone * t[inner])))
    assert np.allclose(phase, 0.3, atol=1e-9)
    res32 = cwt(x, fs, [f_tone], padding=padding)
    assert res32.coefficients.dtype == np.complex64
    assert np.max(np.abs(np.abs(res32.coefficients[0, inner]) - amp)) < 1e-5 * amp


def test_l2_normalization_and_its_frequency_bias():
    fs, f1, n = 1000.0, 40.0, 6000
    x = np.cos(2 * np.pi * f1 * np.arange(n) / fs)
    freqs = np.linspace(36.0, 44.0, 801)
    w1 = np.abs(cwt(x, fs, freqs, normalization="l1", dtype=np.complex128).coefficients[:, 3000])
    w2 = np.abs(cwt(x, fs, freqs, normalization="l2", dtype=np.complex128).coefficients[:, 3000])
    s = scale_from_frequency(freqs, fs)
    assert np.allclose(w2, w1 * np.sqrt(s) * np.pi**0.25 / np.sqrt(2.0), rtol=1e-12)
    assert freqs[np.argmax(w1)] == pytest.approx(f1, abs=0.01)
    expected = f1 * 2 * OMEGA0 / (OMEGA0 + np.sqrt(OMEGA0**2 + 2))
    assert freqs[np.argmax(w2)] == pytest.approx(expected, abs=0.01)


def _morlet_l1(tau_samples, s):
    """(1/s) * conj(psi(-tau/s)) evaluated so that W[m] = sum_n x[n] kernel(m - n)."""
    return (2.0 / (s * np.sqrt(2 * np.pi))) * np.exp(
        1j * OMEGA0 * tau_samples / s - 0.5 * (tau_samples / s) ** 2
    )


@pytest.mark.parametrize("padding", ["symmetric", "periodic", "zero"])
def test_impulse_response_closed_form(padding):
    # W of A*delta[n - n0] is A * (1/s) conj(psi((n0 - m)/s)) = A*sqrt(2/pi)/s
    # * exp(i*omega0*(m - n0)/s - (m - n0)**2 / (2 s**2)), exact while the band stays below Nyquist.
    fs, n, n0, amp = 1.0, 4001, 2000, 3.0
    x = np.zeros(n)
    x[n0] = amp
    freqs = log_frequencies(0.004, 0.18, 12)
    res = cwt(x, fs, freqs, dtype=np.complex128, padding=padding)
    m = np.arange(n)
    for j, s in enumerate(res.metadata["scales"]):
        exact = amp * _morlet_l1(m - n0, s)
        assert np.max(np.abs(res.coefficients[j] - exact)) < 1e-6 * np.max(np.abs(exact))


def test_gaussian_tone_closed_form():
    # x = A exp(-(n-n0)^2/(2 sig^2)) cos(w1 (n-n0)).  With X(w) = A sig sqrt(2pi)/2 e^{-i w n0}
    # [e^{-sig^2 (w-w1)^2/2} + e^{-sig^2 (w+w1)^2/2}] and Psi_s(w) = 2 e^{-(s w - w0)^2/2},
    # W(m) = (1/2pi) int X Psi_s e^{i w m} dw = sum_+- A sig/sqrt(P) exp((Q + i d)^2/(2P) - R/2)
    # with P = sig^2 + s^2, Q = +-sig^2 w1 + s w0, R = sig^2 w1^2 + w0^2, d = m - n0.
    fs, n, n0, amp, sig, w1 = 1.0, 4096, 2048.3, 1.3, 12.0, 2 * np.pi * 0.05
    k = np.arange(n)
    x = amp * np.exp(-((k - n0) ** 2) / (2 * sig**2)) * np.cos(w1 * (k - n0))
    freqs = log_frequencies(0.02, 0.15, 15)
    res = cwt(x, fs, freqs, dtype=np.complex128)
    d = k - n0
    worst = 0.0
    for j, s in enumerate(res.metadata["scales"]):
        p = sig**2 + s**2
        exact = np.zeros(n, dtype=complex)
        for sign in (1.0, -1.0):
            q = sign * sig**2 * w1 + s * OMEGA0
            r = sig**2 * w1**2 + OMEGA0**2
            exact += amp * sig / np.sqrt(p) * np.exp((q + 1j * d) ** 2 / (2 * p) - r / 2)
        err = np.max(np.abs(res.coefficients[j] - exact))
        assert np.max(np.abs(exact)) > 1e-3 * amp  # every row carries signal
        worst = max(worst, err / np.max(np.abs(exact)))
    assert worst < 1e-6


def test_direct_time_domain_convolution_periodic():
    rng = np.random.default_rng(1)
    n, fs = 257, 50.0
    x = rng.standard_normal(n)
    freqs = np.array([0.6, 1.5, 3.0, 7.0, 10.0])
    res = cwt(x, fs, freqs, dtype=np.complex128, padding="periodic")
    m = np.arange(n)
    for j, s in enumerate(res.metadata["scales"]):
        lag = (m[:, None] - m[None, :]) % n
        kern = sum(_morlet_l1(lag + r * n, s) for r in range(-6, 7))  # circular wrap
        direct = kern @ x
        assert np.max(np.abs(res.coefficients[j] - direct)) < 1e-9 * np.max(np.abs(direct))


def test_symmetric_padding_is_mirror_convolution():
    rng = np.random.default_rng(2)
    n, fs = 200, 10.0
    x = rng.standard_normal(n)
    y = np.concatenate([x, x[::-1]])
    freqs = np.array([0.3, 1.0, 1.8])
    res = cwt(x, fs, freqs, dtype=np.complex128)
    m2 = np.arange(2 * n)
    for j, s in enumerate(res.metadata["scales"]):
        lag = (m2[:n, None] - m2[None, :]) % (2 * n)
        kern = sum(_morlet_l1(lag + r * 2 * n, s) for r in range(-4, 5))
        assert np.allclose(res.coefficients[j], kern @ y, rtol=0, atol=1e-10)


def _explicit(x, fs, freqs, padding, inner, normalization="l1"):
    res = cwt(x, fs, freqs, dtype=np.complex128, padding=padding, normalization=normalization)
    p = np.abs(res.coefficients) ** 2
    n = x.size
    out = []
    for j, c in enumerate(res.coi):
        if inner:
            out.append(np.sum(p[j, c : n - c]) if 2 * c < n else 0.0)
        else:
            out.append(np.sum(p[j]))
    return np.sqrt(np.array(out) / fs)


@pytest.mark.parametrize("padding", ["symmetric", "periodic", "zero"])
@pytest.mark.parametrize("normalization", ["l1", "l2"])
def test_parseval_scalogram_equals_explicit_matrix(padding, normalization):
    rng = np.random.default_rng(3)
    n, fs = 6000, 1000.0
    t = np.arange(n) / fs
    x = 0.7 + rng.standard_normal(n) + 2.0 * np.sin(2 * np.pi * 60.0 * t)
    freqs = log_frequencies(0.3, 480.0, 60)  # includes scales longer than the record
    for inner in (False, True):
        fast = scalogram(x, fs, freqs, inner=inner, padding=padding, normalization=normalization)
        ref = _explicit(x, fs, freqs, padding, inner, normalization)
        nz = ref > 0
        assert np.all(fast[~nz] == 0.0)
        assert np.max(np.abs(fast[nz] / ref[nz] - 1.0)) < 1e-9


def test_inner_scalogram_alias_and_peak():
    fs, n = 500.0, 20000
    t = np.arange(n) / fs
    x = np.cos(2 * np.pi * 20.0 * t) + 0.2 * np.cos(2 * np.pi * 70.0 * t)
    freqs = log_frequencies(5.0, 200.0, 200)
    a = inner_scalogram(x, fs, freqs)
    b = scalogram(x, fs, freqs, inner=True)
    assert np.array_equal(a, b)
    assert freqs[np.argmax(a)] == pytest.approx(20.0, rel=0.02)
    # a tone of amplitude A gives about A * sqrt(T_inner) at its scale (L1)
    j = np.argmin(np.abs(freqs - 20.0))
    c = int(np.ceil(np.sqrt(2) * scale_from_frequency(freqs[j], fs)))
    assert a[j] == pytest.approx(np.sqrt((n - 2 * c) / fs), rel=2e-3)


@pytest.mark.parametrize("statistic", ["max", "rms"])
def test_binned_map_matches_matrix(statistic):
    rng = np.random.default_rng(4)
    n, fs, nb = 5003, 100.0, 17
    x = rng.standard_normal(n)
    freqs = log_frequencies(1.0, 40.0, 9)
    full = np.abs(cwt(x, fs, freqs, dtype=np.complex128).coefficients)
    res = cwt_binned(x, fs, freqs, nb, statistic=statistic, dtype=np.complex128)
    assert res.values.shape == (9, nb)
    for i in range(nb):
        seg = full[:, res.bin_edges[i] : res.bin_edges[i + 1]]
        ref = seg.max(axis=1) if statistic == "max" else np.sqrt(np.mean(seg**2, axis=1))
        assert np.allclose(res.values[:, i], ref, rtol=1e-12)
    assert res.times[0] == pytest.approx(0.5 * (res.bin_edges[1] - 1) / fs)


def test_metadata_and_coi():
    res = cwt(np.ones(100), 100.0, [10.0, 20.0])
    md = res.metadata
    assert md["omega0"] == OMEGA0 and md["padding"] == "symmetric"
    assert md["normalization"] == "l1" and md["padded_length"] == 200
    assert np.allclose(md["scales"], 100.0 * OMEGA0 / (2 * np.pi * np.array([10.0, 20.0])))
    assert res.coi.tolist() == np.ceil(np.sqrt(2) * md["scales"]).astype(int).tolist()
    assert np.allclose(md["bandwidth_hz"], [10.0 / 6, 20.0 / 6])


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"signal": []}, "signal"),
        ({"signal": [1.0, np.nan, 2.0]}, "signal"),
        ({"signal": [1.0, np.inf, 2.0]}, "signal"),
        ({"fs": 0.0}, "fs"),
        ({"fs": -5.0}, "fs"),
        ({"frequencies": [0.0]}, "frequencies"),
        ({"frequencies": [50.0]}, "frequencies"),
        ({"frequencies": [60.0]}, "frequencies"),
        ({"frequencies": []}, "frequencies"),
        ({"padding": "wrap"}, "padding"),
        ({"normalization": "max"}, "normalization"),
        ({"dtype": np.float64}, "dtype"),
        ({"omega0": 1.0}, "omega0"),
    ],
)
def test_bad_input_names_the_field(kwargs, field):
    args = {"signal": np.zeros(64), "fs": 100.0, "frequencies": [10.0]}
    args.update(kwargs)
    sig, fs, fr = args.pop("signal"), args.pop("fs"), args.pop("frequencies")
    with pytest.raises(InputError, match=field) as info:
        cwt(sig, fs, fr, **args)
    assert info.value.field == field
    if "dtype" not in args:
        with pytest.raises(InputError, match=field):
            scalogram(sig, fs, fr, **args)


def test_bad_bins_and_log_frequencies():
    with pytest.raises(InputError, match="n_bins"):
        cwt_binned(np.zeros(10), 10.0, [1.0], 11)
    with pytest.raises(InputError, match="statistic"):
        cwt_binned(np.zeros(10), 10.0, [1.0], 2, statistic="mean")
    with pytest.raises(InputError, match="fmin"):
        log_frequencies(-1.0, 10.0, 3)
    with pytest.raises(InputError, match="fmax"):
        log_frequencies(5.0, 1.0, 3)
    with pytest.raises(InputError, match="count"):
        log_frequencies(1.0, 10.0, 0)


@pytest.mark.parametrize("padding", ["symmetric", "periodic", "zero"])
def test_scalograms_equal_the_two_separate_routes(padding):
    from rubrotor.analysis.wavelet import inner_scalogram, scalogram, scalograms

    rng = np.random.default_rng(3)
    fs = 1000.0
    x = rng.standard_normal(3000) + np.cos(2 * np.pi * 60 * np.arange(3000) / fs)
    f = np.geomspace(3.0, 450.0, 40)
    full, inner = scalograms(x, fs, f, padding=padding)
    # equal up to the rounding of differently batched fallback rows
    np.testing.assert_allclose(full, scalogram(x, fs, f, padding=padding), rtol=1e-12)
    np.testing.assert_allclose(inner, inner_scalogram(x, fs, f, padding=padding), rtol=1e-12)
