"""This tree against an older commit, paired: seed case 1, ``seal_rub`` simulate, continuation.

Run (one command, from the checkout)::

    python benchmarks/bench_before_after.py --old 43959d6 [--pairs 5] [--cases seed,seal,cont]

``--old COMMIT`` unpacks that commit's ``src`` (``git archive``) into the system's temporary
folder once; ``--old-src DIR`` takes an unpacked ``src`` folder instead. The cases:

* ``seed``: seed case 1 (``seed_case1.toml``) at its default settings, adaptive steps over 200
  revolutions (``Integrator(revolutions=200)``, the case of issue 36's "no slower"), median of
  15 calls per process; the saved contact-station orbit ``v, w`` (m) compared;
* ``seal``: ``rubrotor.simulate`` of ``seal_rub.toml`` at the scenario's settings, median of 7
  calls per process; the saved displacements ``v, w`` (m) of every station compared;
* ``cont``: continuation of ``seal_rub.toml``'s periodic orbit in ``speed.rad_per_s`` from
  600 rad/s at 128 steps per revolution (as ``bench_continuation_general.py``): marginal cost
  per point, (least time of three 22-point runs - least of three 2-point runs) / 20, so that the
  first orbit's shooting and the setup cancel; the 22 points' key values (rad/s) and states
  compared.

Each side runs in its own fresh process per case and pair, interleaved (who goes first
alternates), pinned to one core (``--cpu``, default the last one) with one BLAS thread and its
own warm numba cache (``NUMBA_CACHE_DIR`` per side; the first pair also compiles, which is
excluded: every process warms up before it times). CPU time of the process (steadier than wall
time on a shared machine) and wall time are printed per pair, then the median of the paired
ratios new / old. Prints, never asserts. Older trees without a case's scenario or API print
"n/a" for it.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, os, sys, time
import numpy as np
out, case, cpu = sys.argv[1], sys.argv[2], int(sys.argv[3])
os.sched_setaffinity(0, {cpu})
import rubrotor
from pathlib import Path

def scenario(name):
    path = Path(rubrotor.__file__).parent / "scenarios" / (name + ".toml")
    if not path.exists():
        print(json.dumps({"na": f"no {name}.toml"})); sys.exit(0)
    return rubrotor.load_scenario(path)

def timed(fn, reps):
    fn()  # compile (first pair) and warm up
    cpu_s, wall_s = [], []
    for _ in range(reps):
        t0, c0 = time.perf_counter(), time.process_time()
        res = fn()
        wall_s.append(time.perf_counter() - t0); cpu_s.append(time.process_time() - c0)
    return res, float(np.median(cpu_s)), float(np.median(wall_s))

if case == "seed":
    sc = scenario("seed_case1")
    kw = {"integrator": rubrotor.Integrator(revolutions=200)}
    ds, c, w = timed(lambda: rubrotor.simulate(sc, **kw), 15)
    n = ds.sizes["time"]
    np.save(out, np.stack([ds["v"].values.ravel()[:n], ds["w"].values.ravel()[:n]]))
    print(json.dumps({"cpu": c, "wall": w, "unit": "per run"}))
elif case == "seal":
    sc = scenario("seal_rub")
    ds, c, w = timed(lambda: rubrotor.simulate(sc), 7)
    np.save(out, np.stack([ds["v"].values.ravel(), ds["w"].values.ravel()]))
    print(json.dumps({"cpu": c, "wall": w, "unit": "per run"}))
else:
    sc = scenario("seal_rub")
    try:
        from rubrotor.orbits.continuation import continue_orbit
    except ImportError:
        print(json.dumps({"na": "no rubrotor.orbits.continuation"})); sys.exit(0)
    def run(points):
        return continue_orbit(sc, "speed.rad_per_s", 600.0, 700.0, points=points, steps=128)
    run(2)  # compile and warm up
    best = {}
    for _ in range(3):
        for points in (2, 22):
            t0, c0 = time.perf_counter(), time.process_time()
            branch = run(points)
            w, c = time.perf_counter() - t0, time.process_time() - c0
            b = best.setdefault(points, [c, w])
            b[0], b[1] = min(b[0], c), min(b[1], w)
    np.save(out, np.stack([np.r_[p.value, np.ravel(p.state)] for p in branch.points]))
    print(json.dumps({"cpu": (best[22][0] - best[2][0]) / 20,
                      "wall": (best[22][1] - best[2][1]) / 20, "unit": "per point"}))
"""

CASES = {
    "seed": "seed case 1, adaptive, 200 rev",
    "seal": "seal_rub simulate",
    "cont": "seal_rub continuation per point",
}


def old_tree(commit: str) -> Path:
    """``src`` of ``commit`` unpacked once into the temporary folder (``git archive``)."""
    full = subprocess.run(["git", "-C", str(ROOT), "rev-parse", commit], capture_output=True,
                          text=True, check=True).stdout.strip()  # fmt: skip
    dest = Path(tempfile.gettempdir()) / f"rubrotor-src-{full[:12]}"
    if not (dest / "src" / "rubrotor").exists():
        dest.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", full, "src"],
                                 capture_output=True, check=True)  # fmt: skip
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive.stdout, check=True)
    return dest / "src"


def _run(src: Path, side: str, case: str, out: Path, cpu: int) -> dict:
    # one BLAS thread: on a loaded machine OpenBLAS's spinning threads dominate (seal_rub's
    # reduction took 0.05 s of CPU with one thread, 0.5-3 s with two, in either code)
    tag = hashlib.sha1(str(src.resolve()).encode()).hexdigest()[:10]
    cache = Path(tempfile.gettempdir()) / f"bench-cache-{side}-{tag}"
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache),
               OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")  # fmt: skip
    res = subprocess.run([sys.executable, "-c", CHILD, str(out), case, str(cpu)], env=env,
                         capture_output=True, text=True, cwd=tempfile.gettempdir())  # fmt: skip
    if res.returncode:
        raise SystemExit(f"{side} {case} failed:\n{res.stderr[-3000:]}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def _difference(case: str, new: Path, old: Path) -> str:
    import numpy as np

    a, b = np.load(new), np.load(old)
    if a.shape != b.shape:
        return f"outputs differ in shape {a.shape} vs {b.shape}"
    if case == "cont":
        dv = float(np.max(np.abs(a[:, 0] - b[:, 0])))
        ds = float(np.max(np.abs(a[:, 1:] - b[:, 1:])) / np.max(np.abs(b[:, 1:])))
        return f"key values equal to {dv:.1e} rad/s, states to {ds:.1e} (relative)"
    return f"max |new - old| {float(np.max(np.abs(a - b))):.2e} m"


def compare(case: str, sides: dict, pairs: int, cpu: int) -> None:
    tmp = Path(tempfile.mkdtemp())
    ratios, wratios = [], []
    for k in range(pairs):
        t = {}
        order = list(sides.items()) if k % 2 == 0 else list(sides.items())[::-1]
        for side, src in order:  # alternate who goes first (a loaded machine drifts)
            t[side] = _run(src, side, case, tmp / f"{side}.npy", cpu)
        if "na" in t["old"] or "na" in t["new"]:
            print(f"{CASES[case]}: n/a ({t['old'].get('na') or t['new'].get('na')})")
            return
        ratios.append(t["new"]["cpu"] / t["old"]["cpu"])
        wratios.append(t["new"]["wall"] / t["old"]["wall"])
        unit = t["new"]["unit"]
        print(f"{CASES[case]} pair {k + 1}: CPU old {t['old']['cpu'] * 1e3:.2f} ms, new "
              f"{t['new']['cpu'] * 1e3:.2f} ms {unit}, ratio {ratios[-1]:.3f}; wall ratio "
              f"{wratios[-1]:.3f}; {_difference(case, tmp / 'new.npy', tmp / 'old.npy')}",
              flush=True)  # fmt: skip
    print(f"{CASES[case]}: median ratio new/old CPU {statistics.median(ratios):.3f} "
          f"(min {min(ratios):.3f}, max {max(ratios):.3f}), wall "
          f"{statistics.median(wratios):.3f} over {pairs} pairs", flush=True)  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    old = ap.add_mutually_exclusive_group(required=True)
    old.add_argument("--old", help="commit to measure against (unpacked with git archive)")
    old.add_argument("--old-src", type=Path, help="an unpacked src folder of the old code")
    ap.add_argument("--pairs", type=int, default=5)
    ap.add_argument("--cases", default="seed,seal,cont", help="comma-separated: seed,seal,cont")
    ap.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)),
                    help="core every child is pinned to (default: the last one)")  # fmt: skip
    args = ap.parse_args()
    sides = {"old": args.old_src or old_tree(args.old), "new": ROOT / "src"}
    print(f"old: {sides['old']}, new: {sides['new']}; load average {os.getloadavg()[0]:.1f}")
    for case in args.cases.split(","):
        if case not in CASES:
            raise SystemExit(f"--cases: {case!r} is not one of {', '.join(CASES)}")
        compare(case, sides, args.pairs, args.cpu)


if __name__ == "__main__":
    main()
