"""Benchmark of rubrotor.analysis.wavelet against PyWavelets and fCWT.

Run from the repository root::

    PYTHONPATH=src python benchmarks/bench_cwt.py [--log2n 20] [--scales 128] [--reps 5]

Each case runs in a fresh subprocess (warm-up, then the median of several repetitions) and
reports its peak memory (``ru_maxrss``) as the increase over the idle interpreter that has
already imported numpy, scipy.fft, rubrotor and the peer library and run the same code path once
on a 16k-sample signal (so compiled code and FFT plans are loaded), i.e. the signal, the output
and every temporary count; the output size and the extra beyond it are printed alongside.  Prints
only; never asserts timings.  Peers are optional (``pip install PyWavelets fcwt``; fcwt needs Debian's
``libfftw3-dev``); a missing peer is reported and skipped.
"""

from __future__ import annotations

import argparse
import json
import math
import resource
import statistics
import subprocess
import sys
import time

import numpy as np

FS = 1.0
OMEGA0 = 6.0
FC = OMEGA0 / (2 * np.pi)
PYWT_NAME = f"cmor2.0-{FC!r}"  # same Gaussian shape as our omega0 = 6 Morlet


def _maxrss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _signal(n: int) -> np.ndarray:
    rng = np.random.default_rng(0)
    t = np.arange(n)
    return (
        rng.standard_normal(n) + np.cos(2 * np.pi * 0.01 * t) + 0.5 * np.cos(2 * np.pi * 0.13 * t)
    )


def _frequencies(n_scales: int) -> np.ndarray:
    return np.geomspace(FS / 2000.0, FS / 4.0, n_scales)


def _time(fn, reps: int) -> tuple[list[float], object]:
    out, result = [], None
    for _ in range(reps):
        result = None  # drop the previous output before the next run
        t0 = time.perf_counter()
        result = fn()
        out.append(time.perf_counter() - t0)
    return out, result


def run_case(case: str, log2n: int, n_scales: int, reps: int) -> dict:
    import scipy.fft  # noqa: F401  (part of the idle baseline)

    sys.path.insert(0, "src")
    import rubrotor.analysis.wavelet  # noqa: F401

    version = ""
    if case == "pywt":
        import pywt

        version = pywt.__version__
    elif case == "fcwt":
        import fcwt  # noqa: F401

    n = 1 << log2n
    x = None  # built after the idle baseline (the jobs read it when they run)
    freqs = _frequencies(n_scales)
    small = _signal(1 << 14)
    if case.startswith("ours"):
        sys.path.insert(0, "src")
        from rubrotor.analysis.wavelet import cwt, cwt_magnitude, scalograms

        padding = case.split(":")[1] if ":" in case else "symmetric"
        if case.startswith("ours_cwt"):

            def job():  # float32 |W| written row by row, no complex matrix
                return cwt_magnitude(x, FS, freqs, padding=padding, workers=2).coefficients

            def warm():
                return cwt_magnitude(small, FS, freqs[freqs > 2e-3], padding=padding, workers=2)
        elif case == "ours_abs_of_complex":

            def job():
                return np.abs(cwt(x, FS, freqs, workers=2).coefficients)

            def warm():
                return cwt(small, FS, freqs[freqs > 2e-3], workers=2)
        elif case == "ours_scalogram_parseval":

            def job():  # both scalograms in one pass over the spectrum
                return scalograms(x, FS, freqs, workers=2)

            def warm():
                return scalograms(small, FS, freqs[freqs > 2e-3], workers=2)
        elif case == "ours_scalogram_matrix":

            def job():
                w = cwt(x, FS, freqs, dtype=np.complex128, workers=2)
                p = np.abs(w.coefficients) ** 2
                full = np.sqrt(p.sum(axis=1) / FS)
                inner = np.sqrt(np.array([p[j, c : n - c].sum() for j, c in enumerate(w.coi)]) / FS)
                return full, inner

            def warm():
                return cwt(small, FS, freqs[freqs > 2e-3], dtype=np.complex128)
        else:
            raise ValueError(case)
    elif case == "pywt":
        scales = pywt.frequency2scale(PYWT_NAME, freqs)

        def job():
            return np.abs(pywt.cwt(x, scales, PYWT_NAME, method="fft")[0])

        def warm():
            return pywt.cwt(small, scales[:8], PYWT_NAME, method="fft")
    elif case == "fcwt":

        def job():
            return np.abs(
                fcwt.cwt(
                    x,
                    2000,
                    float(freqs[0] * 2000),
                    float(freqs[-1] * 2000),
                    n_scales,
                    nthreads=2,
                    scaling="log",
                )[1]
            )

        def warm():
            return fcwt.cwt(
                small,
                2000,
                float(freqs[0] * 2000),
                float(freqs[-1] * 2000),
                8,
                nthreads=2,
                scaling="log",
            )
    else:
        raise ValueError(case)
    warm()
    # idle baseline: interpreter with numpy/scipy/rubrotor/peer imported and the code path warmed
    # up on a 16k-sample signal (compiled kernels loaded); the big signal counts in the peak
    idle = _maxrss_mib()
    x = _signal(n)
    times, result = _time(job, reps)
    out_bytes = sum(
        np.asarray(r).nbytes for r in (result if isinstance(result, tuple) else (result,))
    )
    peak = _maxrss_mib() - idle
    return {
        "case": case,
        "median_s": statistics.median(times),
        "times": times,
        "peak_increase_mib": peak,
        "idle_mib": idle,
        "output_mib": out_bytes / 2**20,
        "extra_mib": peak - out_bytes / 2**20,
        "version": version,
    }


def _subprocess(case, args, reps) -> dict | None:
    cmd = [
        sys.executable,
        __file__,
        "--case",
        case,
        "--log2n",
        str(args.log2n),
        "--scales",
        str(args.scales),
        "--reps",
        str(reps),
    ]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        last = (proc.stderr.strip().splitlines() or ["?"])[-1]
        print(f"  {case}: skipped ({last})")
        return None
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _report(r: dict) -> None:
    label = r["case"] + (f" {r['version']}" if r.get("version") else "")
    print(
        f"  {label:<28s} median of {len(r['times'])}: {r['median_s']:7.3f} s  "
        f"(runs {', '.join(f'{t:.2f}' for t in r['times'])})"
    )
    print(
        f"  {'':<28s} peak +{r['peak_increase_mib']:6.0f} MiB over idle "
        f"({r['idle_mib']:.0f} MiB); output {r['output_mib']:6.0f} MiB, "
        f"extra beyond output {r['extra_mib']:+6.0f} MiB"
    )


def fft_floor(log2n: int, n_scales: int) -> None:
    import scipy.fft as sfft

    n = 1 << log2n
    batch = 8
    a = (np.random.default_rng(1).standard_normal((batch, n)) + 0j).astype(np.complex64)
    sfft.ifft(a, axis=-1, workers=2)
    t = statistics.median(_time(lambda: sfft.ifft(a, axis=-1, workers=2), 5)[0])
    flops = 5.0 * n * math.log2(n)
    rate = flops * batch / t / 1e9
    print(
        f"FFT floor: 5 N log2 N = {flops / 1e6:.0f} MFLOP per length-2^{log2n} transform; "
        f"scipy.fft.ifft complex64 (2 workers) runs at {rate:.1f} GFLOP/s here"
    )
    print(
        f"  -> {n_scales} inverse transforms need >= {n_scales * flops / rate / 1e9:.2f} s "
        "(ours: about one complex FFT of length N per scale, done as cache-sized "
        "FFTs of the folded band, so it can beat this out-of-cache floor)"
    )


def pywt_deviation(log2n: int) -> None:
    try:
        import pywt
    except ImportError:
        print("PyWavelets deviation: skipped (PyWavelets not installed)")
        return
    sys.path.insert(0, "src")
    from rubrotor.analysis.wavelet import cwt

    n = 1 << min(log2n, 16)
    t = np.arange(n)
    print(
        f"PyWavelets {pywt.__version__} '{PYWT_NAME}' vs our exact transform, unit tone at its "
        "own scale, interior samples (our |W| = 1 to 1e-9):"
    )
    for f in (0.002, 0.02, 0.1, 0.25, 0.4):
        x = np.cos(2 * np.pi * f * t)
        ours = np.abs(cwt(x, FS, [f], dtype=np.complex128).coefficients[0])
        for precision in (None, 12):
            if precision is None:
                scale = pywt.frequency2scale(PYWT_NAME, f)
                coef = pywt.cwt(x, [scale], PYWT_NAME, method="fft")[0][0]
            else:
                scale = pywt.frequency2scale(PYWT_NAME, f, precision=precision)
                coef = pywt.cwt(x, [scale], PYWT_NAME, method="fft", precision=precision)[0][0]
            # pywt normalizes by 1/sqrt(scale): a tone reads sqrt(scale)/2 in exact arithmetic
            margin = int(12 * scale)
            ratio = np.abs(coef[margin : n - margin]) / (np.sqrt(scale) / 2)
            ours_i = ours[margin : n - margin]
            dev = np.max(np.abs(ratio / ours_i - 1.0))
            label = "default" if precision is None else f"precision={precision}"
            print(f"  f = {f:5.3f} fs ({label:>12s}): max |pywt row / exact - 1| = {dev:8.2e}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--case")
    ap.add_argument("--log2n", type=int, default=20)
    ap.add_argument("--scales", type=int, default=128)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument(
        "--pywt-reps", type=int, default=1, help="PyWavelets repetitions (slow; 1 by default)"
    )
    args = ap.parse_args()
    if args.case:
        print(json.dumps(run_case(args.case, args.log2n, args.scales, args.reps)))
        return
    n = 1 << args.log2n
    print(
        f"Signal: N = 2^{args.log2n} = {n} samples, {args.scales} log-spaced frequencies "
        f"fs/2000 .. fs/4, omega0 = {OMEGA0}; 2 threads where offered"
    )
    fft_floor(args.log2n, args.scales)
    print(
        "\nFull |W| matrix, float32 output (ours: cwt_magnitude; abs_of_complex: "
        "np.abs(cwt(...)) for reference; peers: np.abs of their complex64 output):"
    )
    reps = max(3, args.reps)
    res = {}
    for case, nrep in (
        ("ours_cwt:symmetric", reps),
        ("ours_cwt:periodic", reps),
        ("ours_abs_of_complex", reps),
        ("pywt", args.pywt_reps),
        ("fcwt", reps),
    ):
        r = _subprocess(case, args, nrep)
        if r:
            _report(r)
            res[case] = r
    if "pywt" in res and len(res["pywt"]["times"]) == 1:
        print("  (PyWavelets timed once: too slow for repetitions; pass --pywt-reps to change)")
    for mine in ("ours_cwt:symmetric", "ours_cwt:periodic", "ours_abs_of_complex"):
        for peer in ("fcwt", "pywt"):
            if mine in res and peer in res:
                ratio = res[peer]["median_s"] / res[mine]["median_s"]
                print(f"  ratio {peer} / {mine}: {ratio:5.2f}x (ours faster when > 1)")
    print("\nScalogram + inner scalogram (float64):")
    for case in ("ours_scalogram_parseval", "ours_scalogram_matrix"):
        r = _subprocess(case, args, max(3, args.reps // 2))
        if r:
            _report(r)
            res[case] = r
    if "ours_scalogram_parseval" in res and "ours_scalogram_matrix" in res:
        a, b = res["ours_scalogram_parseval"], res["ours_scalogram_matrix"]
        print(
            f"  ratio matrix / parseval: {b['median_s'] / a['median_s']:.1f}x faster, peak "
            f"{a['peak_increase_mib']:.0f} MiB vs {b['peak_increase_mib']:.0f} MiB over idle "
            f"(signal {2**args.log2n * 8 / 2**20:.0f} MiB included)"
        )
    print()
    pywt_deviation(args.log2n)


if __name__ == "__main__":
    main()
