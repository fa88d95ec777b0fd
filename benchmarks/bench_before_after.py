"""``rubrotor.simulate`` on shipped scenarios, this tree against an older source tree, paired.

Run: ``python benchmarks/bench_before_after.py --old-src DIR [--pairs 3] [--scenarios a,b]``
with ``DIR`` the ``src`` folder of the old code (``git archive COMMIT | tar -x -C X``, then
``X/src``). Each side runs in fresh processes, interleaved A B A B, with its own warm numba cache
(``NUMBA_CACHE_DIR`` per side under the system's temporary folder); each process compiles and
warms up first, then times ``rubrotor.simulate`` three times (median). Printed per scenario and
pair: seconds of each, their ratio (new / old) and the largest difference of the two codes'
saved displacements (m), so equal speed is measured at equal results; the process CPU time of
the same runs beside the wall time (on a loaded machine the CPU ratio is the steadier one).
Prints, never asserts.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, sys, time
import numpy as np
import rubrotor
from pathlib import Path
sc = rubrotor.load_scenario(Path(rubrotor.__file__).parent / "scenarios" / (sys.argv[2] + ".toml"))
ds = rubrotor.simulate(sc)  # compile + warm up
times, cpu = [], []
for _ in range(3):
    t0, c0 = time.perf_counter(), time.process_time()
    ds = rubrotor.simulate(sc)
    times.append(time.perf_counter() - t0); cpu.append(time.process_time() - c0)
np.save(sys.argv[1], np.stack([ds["v"].values.ravel(), ds["w"].values.ravel()]))
print(json.dumps({"median_s": sorted(times)[1], "median_cpu_s": sorted(cpu)[1]}))
"""


def _run(src: Path, cache: Path, scenario: str, out: Path) -> dict:
    # one BLAS thread: on a loaded machine OpenBLAS's spinning threads dominate (seal_rub's
    # reduction took 0.05 s of CPU with one thread, 0.5-3 s with two, in either code)
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache), OPENBLAS_NUM_THREADS="1")
    res = subprocess.run([sys.executable, "-c", CHILD, str(out), scenario], env=env,
                         capture_output=True, text=True, check=True)  # fmt: skip
    return json.loads(res.stdout.strip().splitlines()[-1])


def main() -> None:
    import numpy as np

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old-src", required=True, type=Path)
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--scenarios", default="seal_rub,seed_case1")
    args = ap.parse_args()
    tmp = Path(tempfile.gettempdir())
    sides = {"old": args.old_src, "new": ROOT / "src"}
    for scenario in args.scenarios.split(","):
        ratios, cratios = [], []
        for k in range(args.pairs):
            t = {}
            order = list(sides.items()) if k % 2 == 0 else list(sides.items())[::-1]
            for side, src in order:  # alternate who goes first (a loaded machine drifts)
                t[side] = _run(src, tmp / f"bench-cache-{side}", scenario, tmp / f"ba-{side}.npy")
            diff = float(np.max(np.abs(np.load(tmp / "ba-new.npy") - np.load(tmp / "ba-old.npy"))))
            ratios.append(t["new"]["median_s"] / t["old"]["median_s"])
            cratios.append(t["new"]["median_cpu_s"] / t["old"]["median_cpu_s"])
            print(f"{scenario} pair {k + 1}: wall old {t['old']['median_s']:.3f} s, new "
                  f"{t['new']['median_s']:.3f} s, ratio {ratios[-1]:.3f}; CPU old "
                  f"{t['old']['median_cpu_s']:.3f} s, new {t['new']['median_cpu_s']:.3f} s, ratio "
                  f"{cratios[-1]:.3f}; max |new - old| {diff:.2e} m", flush=True)  # fmt: skip
        print(f"{scenario}: median ratio new/old wall {statistics.median(ratios):.3f}, CPU "
              f"{statistics.median(cratios):.3f}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
