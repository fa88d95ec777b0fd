"""Seed case 1 at default settings through the front door, against the first landing (cc537d9).

Run: ``python benchmarks/bench_seed_vs_first_landing.py [--pairs 5] [--old-venv DIR]``.

The first landing (commit cc537d9) is installed once into its own venv (``git archive cc537d9``
unpacked and ``pip install``-ed; ``--old-venv`` reuses it), then both codes run seed case 1 at its
default settings (adaptive steps, 200 revolutions; ``--settings file``: the scenario file's
fixed step over 300 revolutions) in fresh processes, interleaved A B A B.
Each process compiles and warms up first, then times ``rubrotor.simulate`` three times (median).
Printed per pair: seconds per simulated revolution of each and their ratio (ours / old), and the
largest difference of the two codes' orbits at the contact station (m), so equal speed is
measured at equal results. Prints, never asserts.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

OLD = "cc537d9"
ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, sys, time
import numpy as np
import rubrotor
from pathlib import Path
sc = rubrotor.load_scenario(Path(rubrotor.__file__).parent / "scenarios" / "seed_case1.toml")
kw = {"integrator": rubrotor.Integrator(revolutions=200)} if sys.argv[2] == "adaptive" else {}
ds = rubrotor.simulate(sc, **kw)  # compile + warm up
times = []
for _ in range(3):
    t0 = time.perf_counter(); ds = rubrotor.simulate(sc, **kw); times.append(time.perf_counter() - t0)
revs = float(ds["time"].values[-1]) * sc.speed / (2 * np.pi)
np.save(sys.argv[1], np.stack([ds["time"].values, ds["v"].values.ravel()[: ds.sizes["time"]],
                               ds["w"].values.ravel()[: ds.sizes["time"]]]))
print(json.dumps({"s_per_rev": sorted(times)[1] / revs, "revolutions": revs}))
"""


def old_venv(path: Path | None) -> Path:
    """A venv with the first landing installed (made once)."""
    venv = path or Path(tempfile.gettempdir()) / f"rubrotor-{OLD}-venv"
    py = venv / "bin" / "python"
    if not py.exists():
        src = Path(tempfile.mkdtemp()) / "src"
        src.mkdir()
        archive = subprocess.run(
            ["git", "-C", str(ROOT), "archive", OLD], capture_output=True, check=True
        )
        subprocess.run(["tar", "-x", "-C", str(src)], input=archive.stdout, check=True)
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
        subprocess.run([str(py), "-m", "pip", "install", "--quiet", str(src)], check=True)
    return py


def run(python: str, out: Path, settings: str) -> dict:
    env = {"OPENBLAS_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"}
    cwd = tempfile.mkdtemp()  # not the checkout: the old venv must import its own rubrotor
    res = subprocess.run(
        [python, "-c", CHILD, str(out), settings], capture_output=True, text=True, cwd=cwd, env=env
    )
    if res.returncode:
        raise SystemExit(res.stderr)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--pairs", type=int, default=5)
    ap.add_argument("--old-venv", type=Path)
    ap.add_argument(
        "--settings",
        choices=("adaptive", "file"),
        default="adaptive",
        help="adaptive: Integrator(revolutions=200), the engine's defaults (the issue's case); "
        "file: the scenario file's fixed d(tau) = 0.001 over 300 revolutions",
    )
    args = ap.parse_args()
    old_py = str(old_venv(args.old_venv))
    tmp = Path(tempfile.mkdtemp())
    ratios = []
    print("pair  ours s/rev   old s/rev   ours/old   max |orbit difference| (m)")
    for i in range(args.pairs):
        a = run(sys.executable, tmp / "new.npy", args.settings)
        b = run(old_py, tmp / "old.npy", args.settings)
        new, old = (__import__("numpy").load(tmp / f) for f in ("new.npy", "old.npy"))
        diff = float(abs(new[1:] - old[1:]).max()) if new.shape == old.shape else float("nan")
        ratios.append(a["s_per_rev"] / b["s_per_rev"])
        print(
            f"{i:4d}  {a['s_per_rev']:.3e}   {b['s_per_rev']:.3e}   {ratios[-1]:8.3f}   {diff:.2e}"
        )
    print(
        f"median ours/old: {statistics.median(ratios):.3f} over {len(ratios)} pairs "
        f"(goal <= 1.0; min {min(ratios):.3f}, max {max(ratios):.3f})"
    )


if __name__ == "__main__":
    main()
