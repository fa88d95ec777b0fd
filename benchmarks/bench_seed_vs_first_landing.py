"""Seed case 1 at default settings through the front door, against the first landing (cc537d9).

Run: ``python benchmarks/bench_seed_vs_first_landing.py [--pairs 5] [--settings adaptive|file]``
(``--old-venv DIR``: a venv with the first landing installed instead).

The first landing's ``src`` (commit cc537d9) is unpacked once into the temporary folder
(``git archive``) and imported through ``PYTHONPATH`` with the same Python and packages as this
checkout's ``src``; both codes run seed case 1 at its default settings (adaptive steps, 200
revolutions; ``--settings file``: the scenario file's fixed step over 300 revolutions) in fresh
processes, interleaved (who goes first alternates), pinned to one core (``--cpu``), one BLAS
thread, each side with its own numba cache. Each process compiles and warms up first, then
times ``rubrotor.simulate`` 15 times (3 with ``file``): the median CPU time of the process and
the median wall time. Printed per pair: CPU seconds per simulated revolution of each and their
ratio (ours / old), the wall ratio, and the largest difference of the two codes' orbits at the
contact station (m), so equal speed is measured at equal results; then the median of the paired
ratios. Prints, never asserts.
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

import numpy as np

OLD = "cc537d9"
ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, os, sys, time
import numpy as np
os.sched_setaffinity(0, {int(sys.argv[3])})
import rubrotor
from pathlib import Path
sc = rubrotor.load_scenario(Path(rubrotor.__file__).parent / "scenarios" / "seed_case1.toml")
kw = {"integrator": rubrotor.Integrator(revolutions=200)} if sys.argv[2] == "adaptive" else {}
ds = rubrotor.simulate(sc, **kw)  # compile + warm up
times, cpu = [], []
for _ in range(15 if kw else 3):
    t0, c0 = time.perf_counter(), time.process_time()
    ds = rubrotor.simulate(sc, **kw)
    times.append(time.perf_counter() - t0); cpu.append(time.process_time() - c0)
revs = float(ds["time"].values[-1]) * sc.speed / (2 * np.pi)
np.save(sys.argv[1], np.stack([ds["time"].values, ds["v"].values.ravel()[: ds.sizes["time"]],
                               ds["w"].values.ravel()[: ds.sizes["time"]]]))
print(json.dumps({"s_per_rev": float(np.median(cpu)) / revs, "wall_per_rev": float(np.median(times)) / revs,
                  "revolutions": revs}))
"""


def old_src() -> Path:
    """The first landing's ``src`` (``git archive``), unpacked once into the temporary folder."""
    dest = Path(tempfile.gettempdir()) / f"rubrotor-src-{OLD}"
    if not (dest / "src" / "rubrotor").exists():
        dest.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(
            ["git", "-C", str(ROOT), "archive", OLD, "src"], capture_output=True, check=True
        )
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive.stdout, check=True)
    return dest / "src"


def run(python: str, src: Path | None, out: Path, settings: str, cpu: int) -> dict:
    """One fresh process of ``python`` importing rubrotor from ``src`` (None: its own install)."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    env.pop("PYTHONPATH", None)
    side = "installed" if src is None else src.parent.name
    env["NUMBA_CACHE_DIR"] = str(Path(tempfile.gettempdir()) / f"bench-seed-cache-{side}")
    if src is not None:
        env["PYTHONPATH"] = str(src)
    cwd = tempfile.mkdtemp()  # not the checkout: each side must import its own rubrotor
    res = subprocess.run(
        [python, "-c", CHILD, str(out), settings, str(cpu)],
        capture_output=True, text=True, cwd=cwd, env=env,
    )  # fmt: skip
    if res.returncode:
        raise SystemExit(res.stderr)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--pairs", type=int, default=5)
    ap.add_argument("--old-venv", type=Path, help="a venv with cc537d9 installed (default: its "
                    "src unpacked and imported with this Python)")  # fmt: skip
    ap.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)),
                    help="core both children are pinned to (default: the last one)")  # fmt: skip
    ap.add_argument(
        "--settings",
        choices=("adaptive", "file"),
        default="adaptive",
        help="adaptive: Integrator(revolutions=200), the engine's defaults (the issue's case); "
        "file: the scenario file's fixed d(tau) = 0.001 over 300 revolutions",
    )
    args = ap.parse_args()
    if args.old_venv:
        old = (str(args.old_venv / "bin" / "python"), None)
    else:
        old = (sys.executable, old_src())
    ours = (sys.executable, ROOT / "src")
    tmp = Path(tempfile.mkdtemp())
    ratios, wratios = [], []
    print(f"load average {os.getloadavg()[0]:.1f}; CPU s per simulated revolution (median of the "
          "process's calls)")  # fmt: skip
    print(
        "pair  ours s/rev   old s/rev   ours/old CPU   ours/old wall   max |orbit difference| (m)"
    )
    for i in range(args.pairs):
        first, second = ("new", "old") if i % 2 == 0 else ("old", "new")
        r = {}
        for side in (first, second):  # alternate who goes first (a loaded machine drifts)
            py, src = ours if side == "new" else old
            r[side] = run(py, src, tmp / f"{side}.npy", args.settings, args.cpu)
        a, b = r["new"], r["old"]
        new, old_ = (np.load(tmp / f) for f in ("new.npy", "old.npy"))
        diff = float(abs(new[1:] - old_[1:]).max()) if new.shape == old_.shape else float("nan")
        ratios.append(a["s_per_rev"] / b["s_per_rev"])
        wratios.append(a["wall_per_rev"] / b["wall_per_rev"])
        print(
            f"{i:4d}  {a['s_per_rev']:.3e}   {b['s_per_rev']:.3e}   {ratios[-1]:12.3f}   "
            f"{wratios[-1]:13.3f}   {diff:.2e}",
            flush=True,
        )
    print(
        f"median ours/old CPU: {statistics.median(ratios):.3f} over {len(ratios)} pairs "
        f"(goal <= 1.03; min {min(ratios):.3f}, max {max(ratios):.3f}); wall "
        f"{statistics.median(wratios):.3f}"
    )


if __name__ == "__main__":
    main()
