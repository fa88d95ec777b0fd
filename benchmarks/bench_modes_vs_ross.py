"""Benchmark: rubrotor modal analysis vs ROSS (accuracy and Campbell-diagram cost).

Prints, for the seed shaft (benchmarks/ross_peer.py SEED_ROTOR):
* relative differences ours vs ROSS of the first three bending whirl frequencies
  (forward and backward) at 0 and 10000 rad/s (goal <= 0.1 %);
* wall time of a 200-speed Campbell diagram (0..12000 rad/s), ours vs ROSS, and
  the ratio (goal: ours >= 100x faster).  Medians of repetitions, warm-up
  excluded.

ROSS is a finite-element model: its frequencies carry a discretization error that falls as
h^2. The script therefore also runs ROSS with twice the elements and prints the Richardson
extrapolation (4 f_2n - f_n) / 3, which should meet the exact continuous model of rubrotor.

Run from the repository root:  python benchmarks/bench_modes_vs_ross.py [--repeats N]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import ross_peer as rp  # noqa: E402

SPEEDS_CHECK = (0.0, 10000.0)
CAMPBELL_SPEEDS = np.linspace(0.0, 12000.0, 200)
N_MODES = 3


def _ours():
    """Return (label, natural_frequencies(speed) -> dict, campbell(speeds) -> obj) of rubrotor."""
    from rubrotor.linear.shaft import campbell as our_campbell
    from rubrotor.linear.shaft import natural_frequencies
    from rubrotor.rotors.shaft import Shaft

    s = rp.SEED_ROTOR
    shaft = Shaft(
        length=s["length"],
        diameter=s["diameter"],
        youngs_modulus=s["youngs_modulus"],
        shear_modulus=s["shear_modulus"],
        density=s["density"],
        shear_coefficient="cowper",
        modes=N_MODES,
    )

    def natural(speed):
        modes = [m for m in natural_frequencies(shaft, speed) if m.branch == "bending"]
        return {
            "forward_hz": np.array([m.frequency_hz for m in modes if m.whirl == "forward"]),
            "backward_hz": np.array([m.frequency_hz for m in modes if m.whirl == "backward"]),
        }

    def campbell(speeds):
        return our_campbell(shaft, speeds)

    return "rubrotor.linear.shaft (exact two-field modal Timoshenko, Cowper)", natural, campbell


def _median_time(fn, repeats):
    fn()  # warm-up (JIT, caches), excluded
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="ROSS Campbell repetitions")
    parser.add_argument("--our-repeats", type=int, default=20)
    parser.add_argument("--n-elements", type=int, default=40, help="ROSS shaft elements")
    args = parser.parse_args(argv)

    label, natural, campbell = _ours()
    print(f"ours: {label}")
    print(
        f"ROSS {rp.ross_version()}: {args.n_elements} Timoshenko elements, "
        f"pinned ends = {rp.DEFAULT_SUPPORT_STIFFNESS:.0e} N/m bearings"
    )
    rotor = rp.build_ross_shaft(**rp.SEED_ROTOR, n_elements=args.n_elements)

    rotor2 = rp.build_ross_shaft(**rp.SEED_ROTOR, n_elements=2 * args.n_elements)
    worst = 0.0
    worst_x = 0.0
    print(
        f"\n{'speed':>7} {'n':>2} {'dir':>3} {'ours Hz':>12} {'ROSS Hz':>12} {'rel diff':>10}"
        f" {'ROSS 2n':>12} {'rel diff':>10} {'Richardson':>10}"
    )
    for speed in SPEEDS_CHECK:
        ours = natural(speed)
        ross = rp.ross_bending_frequencies(rotor, speed, n_modes=N_MODES)
        ross2 = rp.ross_bending_frequencies(rotor2, speed, n_modes=N_MODES)
        for key, tag in (("forward_hz", "F"), ("backward_hz", "B")):
            for i in range(N_MODES):
                a, b, b2 = float(ours[key][i]), float(ross[key][i]), float(ross2[key][i])
                rich = (4 * b2 - b) / 3
                rel = a / b - 1.0
                worst = max(worst, abs(rel))
                worst_x = max(worst_x, abs(a / rich - 1))
                print(
                    f"{speed:7.0f} {i + 1:2d} {tag:>3} {a:12.3f} {b:12.3f} {rel:10.2e}"
                    f" {b2:12.3f} {a / b2 - 1:10.2e} {a / rich - 1:10.2e}"
                )
    print(
        f"max |rel diff| vs ROSS {args.n_elements} elements = {worst:.2e}  "
        f"(goal <= 1e-3: {'PASS' if worst <= 1e-3 else 'FAIL'})"
    )
    print(f"max |rel diff| vs ROSS Richardson-extrapolated to h -> 0 = {worst_x:.2e}")

    t_ours, ours_times = _median_time(lambda: campbell(CAMPBELL_SPEEDS), args.our_repeats)
    t_ross, _, info = rp.ross_campbell_seconds(rotor, CAMPBELL_SPEEDS, repeats=args.repeats)
    ratio = t_ross / t_ours
    print(f"\nCampbell diagram, {CAMPBELL_SPEEDS.size} speeds 0..12000 rad/s")
    print(f"  ours: median {t_ours * 1e3:.3f} ms over {args.our_repeats} reps")
    print(
        f"  ROSS: median {t_ross:.2f} s over {args.repeats} reps "
        f"({info['frequencies']} tracked modes) {np.round(info['times_s'], 2).tolist()}"
    )
    print(f"  ROSS / ours = {ratio:.0f}x  (goal >= 100x: {'PASS' if ratio >= 100 else 'FAIL'})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
