"""Cold start: each verb's first and second call on a fresh install, and the import time.

Every case runs ``rubrotor VERB ...`` on a shipped scenario in a fresh Python process, twice:

* **first call**: an empty numba cache directory (``NUMBA_CACHE_DIR`` pointing at a new
  temporary folder), as after ``pip install rubrotor``: every kernel the verb uses compiles;
* **second call**: a new process on the cache the first call left (what every later call costs).

For each call it prints the whole-process wall time and CPU time (user + system of the child),
their difference and the numba compile time (CPU seconds of the compiling thread), split per
kernel (numba's own ``numba:compile`` events, exclusive of the kernels compiled inside it), so
one sees where a first call goes. On a busy machine wall times stretch with the load; the CPU
columns (and their difference, the cost of the first call) hold.
``import rubrotor`` and ``rubrotor --help`` are timed the same way (median of ``--reps`` fresh
processes, warm file-system cache).

Usage::

    python benchmarks/bench_cold_start.py                   # every verb, the table
    python benchmarks/bench_cold_start.py --verbs modes,critical --kernels 8
    python benchmarks/bench_cold_start.py --json cold.json  # the raw numbers as well
    python benchmarks/bench_cold_start.py --src /tmp/main/src   # another checkout's package

Each case gets its own empty cache: a verb's first call is measured as if it were the first
thing the user ran. Wall times on a shared machine drift; CPU time is the steadier figure.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SRC = HERE.parent / "src"

LINEAR = ("modes", "critical", "campbell", "static", "response", "unbalance", "ucs", "shapes",
          "clearance", "level1")
"""The linear verbs: goal, first call within 5 s of the second."""

NONLINEAR = ("simulate", "continue", "analyze")
"""The time-domain verbs: goal, first call within 15 s of the second."""


def cases(tmp: Path) -> list[tuple[str, str, list[str]]]:
    """``(label, verb, argv)`` for every verb on a shipped scenario (the README's commands)."""
    s = _scenarios()
    out = tmp / "out"
    return [
        ("modes", "modes", ["modes", f"{s}/general_rotor.toml", "--speed", "300", "--json"]),
        ("critical", "critical", ["critical", f"{s}/general_rotor.toml"]),
        ("campbell", "campbell", ["campbell", f"{s}/general_rotor.toml", "--speeds",
                                  "0:1500:100", "--out", f"{out}-campbell.png"]),
        ("static", "static", ["static", f"{s}/general_rotor.toml", "--json"]),
        ("response", "response", ["response", f"{s}/general_rotor.toml", "--at", "0.45",
                                  "--frequencies", "0:3000:300", "--kind", "forward", "--json"]),
        ("unbalance", "unbalance", ["unbalance", f"{s}/seal_rub.toml", "--speeds", "10:1500:300",
                                    "--probe", "0.75", "--json"]),
        ("ucs", "ucs", ["ucs", f"{s}/general_rotor.toml", "--json"]),
        ("shapes", "shapes", ["shapes", f"{s}/general_rotor.toml", "--speed", "300", "--json"]),
        ("clearance", "clearance", ["clearance", f"{s}/seal_rub.toml", "--json"]),
        ("level1", "level1", ["level1", f"{s}/seal_rub.toml", "--stage", "2e6,0.3,0.015,1.4",
                              "--json"]),
        ("modes seed", "modes", ["modes", f"{s}/seed_rotor.toml", "--speed", "0"]),
        ("critical seed", "critical", ["critical", f"{s}/seed_rotor.toml"]),
        ("simulate seed_case1", "simulate", ["simulate", f"{s}/seed_case1.toml",
                                             "--out", f"{out}-case1/"]),
        ("simulate seal_rub", "simulate", ["simulate", f"{s}/seal_rub.toml",
                                           "--out", f"{out}-seal.nc"]),
        ("simulate runup_rub", "simulate", ["simulate", f"{s}/runup_rub.toml",
                                            "--out", f"{out}-runup.nc"]),
        ("continue partial", "continue", [
            "continue", f"{s}/one_mode_partial_rub.toml",
            "--vary", "speed.critical_multiple=2.03:2.11", "--switch", "period-doubling",
            "--out", f"{out}-branch.nc", "--json"]),
        ("analyze case1", "analyze", ["analyze", f"{out}-case1/results.nc", "--json"]),
        ("analyze runup", "analyze", ["analyze", f"{out}-runup.nc", "--json"]),
    ]


def _scenarios() -> str:
    return str(SRC / "rubrotor" / "scenarios")


# ---------------------------------------------------------------- the child: one call, measured


def _child(report: str, argv: list[str]) -> int:
    """Run ``rubrotor ARGV`` in this process and write its compile times to ``report``."""
    try:
        from rubrotor.cli import _one_blas_thread

        _one_blas_thread()  # as the `rubrotor` command does, before numba imports NumPy
    except ImportError:  # an older package (--src): its command line sets no thread count
        pass
    from numba.core import event

    rows: list[dict] = []
    stack: list[list[float]] = []  # [start, nested seconds]

    class Listener(event.Listener):
        def on_start(self, ev):
            stack.append([time.thread_time(), 0.0])

        def on_end(self, ev):
            start, nested = stack.pop()
            total = time.thread_time() - start  # CPU seconds of the compiling thread
            if stack:
                stack[-1][1] += total
            disp = ev.data["dispatcher"]
            fn = disp.py_func
            rows.append({"kernel": f"{fn.__module__}.{fn.__qualname__}",
                         "signature": str(ev.data["args"]),
                         "inclusive": total, "exclusive": total - nested})

    t0 = time.perf_counter()
    with event.install_listener("numba:compile", Listener()):
        from rubrotor.cli import main  # the console script's entry point (as `rubrotor`)

        t_import = time.perf_counter() - t0
        status = main(argv)
    wall = time.perf_counter() - t0
    Path(report).write_text(json.dumps({"status": status, "wall_in_process": wall,
                                        "import": t_import, "compiles": rows}))
    return 0


# --------------------------------------------------------------- the parent: processes, the table


def _run(cmd: list[str], env: dict) -> tuple[float, float, int, str]:
    """Wall and CPU seconds (user + system) of one child process, its status and stderr tail."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    err = proc.stderr.read().decode(errors="replace") if proc.stderr else ""
    proc.stderr.close()
    return wall, usage.ru_utime + usage.ru_stime, os.waitstatus_to_exitcode(status), err[-400:]


def _env(src: Path, cache: Path | None) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(src)
    env.pop("NUMBA_DISABLE_JIT", None)
    if cache is not None:
        env["NUMBA_CACHE_DIR"] = str(cache)
    env.setdefault("MPLBACKEND", "Agg")
    return env


def call(src: Path, cache: Path, argv: list[str], tmp: Path) -> dict:
    """One measured ``rubrotor ARGV`` process on numba cache ``cache``."""
    report = tmp / f"report-{time.monotonic_ns()}.json"
    cmd = [sys.executable, str(Path(__file__).resolve()), "--child", str(report), "--", *argv]
    wall, cpu, status, err = _run(cmd, _env(src, cache))
    data = json.loads(report.read_text()) if report.exists() else {"compiles": []}
    compile_s = sum(r["exclusive"] for r in data["compiles"])
    return {"wall": wall, "cpu": cpu, "status": data.get("status", status), "stderr": err,
            "compile": compile_s, "import": data.get("import"), "compiles": data["compiles"]}


def import_times(src: Path, reps: int) -> dict:
    """Median wall and CPU seconds of ``import rubrotor`` and ``rubrotor --help``."""
    out = {}
    env = _env(src, None)
    for label, cmd in (("import rubrotor", ["-c", "import rubrotor"]),
                       ("rubrotor --help", ["-m", "rubrotor", "--help"]),
                       ("python (bare)", ["-c", "pass"])):
        runs = [_run([sys.executable, *cmd], env) for _ in range(reps)]
        out[label] = {"wall": statistics.median(r[0] for r in runs),
                      "cpu": statistics.median(r[1] for r in runs),
                      "status": max(r[2] for r in runs)}
    return out


def _kernel_table(rows: list[dict], top: int) -> list[str]:
    """The ``top`` kernels by exclusive compile time, summed over their specialisations."""
    per: dict[str, list[float]] = {}
    for r in rows:
        per.setdefault(r["kernel"].removeprefix("rubrotor."), []).append(r["exclusive"])
    lines = []
    for name, ts in sorted(per.items(), key=lambda kv: -sum(kv[1]))[:top]:
        lines.append(f"      {sum(ts):6.2f} s  {len(ts)} sig  {name}")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--verbs", help="comma-separated case labels or verbs (default all)")
    parser.add_argument("--kernels", type=int, default=6,
                        help="kernels listed per case, by compile time (default 6; 0: none)")
    parser.add_argument("--reps", type=int, default=5, help="import timing repetitions")
    parser.add_argument("--src", type=Path, default=SRC, help="the package's src folder")
    parser.add_argument("--json", type=Path, help="write the raw numbers here")
    parser.add_argument("--no-import", action="store_true", help="skip the import timing")
    parser.add_argument("rest", nargs="*", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        return _child(args.child, args.rest)

    results: dict = {"src": str(args.src), "load": os.getloadavg(), "cases": {}}
    if not args.no_import:
        results["import"] = import_times(args.src, args.reps)
        for label, r in results["import"].items():
            print(f"{label:18s} wall {r['wall']:6.2f} s  cpu {r['cpu']:6.2f} s", flush=True)
    with tempfile.TemporaryDirectory(prefix="rubrotor-cold-") as tmpdir:
        tmp = Path(tmpdir)
        todo = cases(tmp)
        if args.verbs:
            want = set(args.verbs.split(","))
            todo = [c for c in todo if c[0] in want or c[1] in want
                    or (c[1] == "analyze" and "analyze" in want)]
        # analyze reads the results the simulate cases write: run those first (warm) if skipped
        needed = {c[2][1] for c in todo if c[1] == "analyze"}
        if needed:
            warm = tmp / "cache-warm"
            for label, verb, cargv in cases(tmp):
                if verb == "simulate" and any(cargv[-1].rstrip("/") in n for n in needed):
                    if not any(c[0] == label for c in todo):
                        call(args.src, warm, cargv, tmp)
        print(f"\n{'case':22s} {'first wall':>10s} {'cpu':>7s} {'compile':>8s} | "
              f"{'second wall':>11s} {'cpu':>7s} | {'diff wall':>9s} {'cpu':>7s}  goal (diff)",
              flush=True)
        for label, verb, cargv in todo:
            cache = tmp / f"cache-{label.replace(' ', '_')}"
            cache.mkdir()
            first = call(args.src, cache, cargv, tmp)
            second = call(args.src, cache, cargv, tmp)
            goal = 5.0 if verb in LINEAR else 15.0
            diff = first["wall"] - second["wall"]
            dcpu = first["cpu"] - second["cpu"]
            ok = "ok" if min(diff, dcpu) <= goal else f"> {goal:g} s"
            bad = "" if first["status"] == 0 and second["status"] == 0 else (
                f"  EXIT {first['status']}/{second['status']}: {first['stderr'] or second['stderr']}")
            print(f"{label:22s} {first['wall']:9.2f}s {first['cpu']:6.2f}s {first['compile']:7.2f}s"
                  f" | {second['wall']:10.2f}s {second['cpu']:6.2f}s | {diff:8.2f}s {dcpu:6.2f}s  {ok}{bad}",
                  flush=True)
            if args.kernels:
                print("\n".join(_kernel_table(first["compiles"], args.kernels)), flush=True)
            if second["compile"] > 0.05:
                print(f"      second call still compiled {second['compile']:.2f} s:", flush=True)
                print("\n".join(_kernel_table(second["compiles"], args.kernels or 3)), flush=True)
            results["cases"][label] = {"first": first, "second": second}
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
