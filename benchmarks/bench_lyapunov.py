"""Cost of the largest Lyapunov exponent per sweep point, relative to a plain sweep point.

A sweep point (:func:`rubrotor.sweeps.sweep.simulate_point`) runs the adaptive exponential integrator
over ``R`` revolutions (``T`` discarded) and reduces the run to metrics. With ``lyapunov=True``
it also runs :func:`rubrotor.orbits.lyapunov.lyapunov_exponents` from the point's final state over the
``K = R - T`` kept revolutions, 512 fixed steps per revolution, one tangent vector propagated
by the exact derivative of the step. Both are timed side by side in this process (medians of
REPEATS), after a warm-up that compiles the kernels (compilation time printed separately), on:

* the seed rotor (3 Timoshenko modes, 12 complex state coordinates), seed case 1 with 2e-3 kg m
  unbalance, 2 % damping and a 1e5 N side load at 1.5 x critical: a periodic impacting rub;
* the one-mode Euler-Bernoulli rotor of the follow-sweep tests in full annular rub.

Also printed: the exponent estimate alone with 1 and with 4 tangent vectors (spectrum cost).
Then the convergence table of the largest exponent with the averaging length (100 .. 1600
revolutions, 256 .. 1024 steps per revolution) on a chaotic partial rub
(``one_mode_chaotic_rub.toml``, positive) and a period-1 partial rub (``one_mode_partial_rub.toml``,
negative). Run: ``PYTHONPATH=src python benchmarks/bench_lyapunov.py [REPEATS]``. Timings are never asserted.
"""

from __future__ import annotations

import statistics
import sys
import time
from importlib import resources


def _median_time(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def _cases():
    from rubrotor.scenario import load_scenario, scenario_from_dict

    seed = load_scenario(resources.files("rubrotor") / "scenarios" / "seed_case1.toml")
    seed = seed.with_changes(
        **{
            "unbalance.magnitude": 2e-3,
            "damping.ratio": 0.02,
            "load.force_y": 1e5,
            "speed.critical_multiple": 1.5,
        }
    )
    spec = {
        "meta": {"name": "one_mode"},
        "shaft": {
            "length": 0.4, "diameter": 0.1, "youngs_modulus": 71e9, "density": 2660,
            "poisson_ratio": 0.33, "theory": "euler-bernoulli", "modes": 1,
        },
        "speed": {"critical_multiple": 1.3},
        "unbalance": {"magnitude": 2e-4},
        "contact": {
            "law": "linear", "clearance": 1e-4, "stiffness": 5e8, "damping": 0.0,
            "friction": 0.01,
        },
        "damping": {"ratio": 0.05},
    }  # fmt: skip
    return [
        ("seed rotor, periodic impacting rub", seed),
        ("one mode, full annular rub", scenario_from_dict(spec)),
    ]


def main() -> None:
    from rubrotor.orbits.lyapunov import lyapunov_exponents
    from rubrotor.sweeps.sweep import simulate_point

    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    T, R, N = 100, 300, 128  # the sweep defaults: 100 discarded, 200 kept, 128 samples/rev
    t0 = time.perf_counter()
    for _, sc in _cases():
        simulate_point(sc, 2, 4, N, lyapunov=True)
        lyapunov_exponents(sc, count=4, revolutions=1)
    print(f"warm-up (numba compilation or cache load): {time.perf_counter() - t0:.2f} s")
    print(
        f"sweep point: {R} revolutions ({T} discarded), {N} samples/rev; exponent over {R - T} rev"
    )
    for name, sc in _cases():
        plain = _median_time(lambda sc=sc: simulate_point(sc, T, R, N), repeats)
        with_l = _median_time(lambda sc=sc: simulate_point(sc, T, R, N, lyapunov=True), repeats)
        one = _median_time(lambda sc=sc: lyapunov_exponents(sc, revolutions=R - T), repeats)
        four = _median_time(
            lambda sc=sc: lyapunov_exponents(sc, count=4, revolutions=R - T), repeats
        )
        print(f"{name}:")
        print(f"  plain point            {plain * 1e3:9.1f} ms")
        print(f"  point with exponent    {with_l * 1e3:9.1f} ms   ratio {with_l / plain:.2f}")
        print(f"  exponent alone (1 vec) {one * 1e3:9.1f} ms   ratio to plain {one / plain:.2f}")
        print(f"  4 exponents (4 vecs)   {four * 1e3:9.1f} ms   ratio to 1 vec {four / one:.2f}")


def convergence() -> None:
    """Largest exponent per revolution vs averaging length: chaotic and periodic partial rub."""
    from rubrotor.orbits.lyapunov import lyapunov_exponents
    from rubrotor.scenario import load_scenario

    where = resources.files("rubrotor") / "scenarios"
    chaotic = load_scenario(where / "one_mode_chaotic_rub.toml")
    periodic = load_scenario(where / "one_mode_partial_rub.toml")  # period-1 at 2.0 x critical
    print("largest exponent per revolution vs revolutions averaged (300 discarded):")
    for name, sc in (("chaotic partial rub", chaotic), ("period-1 partial rub", periodic)):
        for spr in (256, 512, 1024):
            row = [
                lyapunov_exponents(
                    sc, revolutions=n, transient_revolutions=300, steps_per_revolution=spr
                ).per_revolution[0]
                for n in (100, 200, 400, 800, 1600)
            ]
            cells = " ".join(f"{v:+.4f}" for v in row)
            print(f"  {name:22s} {spr:5d} steps/rev, 100..1600 rev: {cells}")


if __name__ == "__main__":
    main()
    convergence()
