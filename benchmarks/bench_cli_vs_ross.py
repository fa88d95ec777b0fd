"""The command line's cost against ROSS's calls, Python start-up included.

Each verb is timed two ways on ROSS's ``compressor_example`` (imported with ``rubrotor
import-ross`` from the file ROSS saves), beside the ROSS call that does the same analysis:

- **fresh**: a new interpreter per call, caches warm (the second and later runs of a command at
  the terminal; numba's cache and the OS file cache are warm after the first): ours is
  ``rubrotor VERB ...`` (the console script), ROSS's is ``python -c "import ross; r =
  ross.compressor_example(); r.run_...(...)"``;
- **warm**: inside one interpreter, the call repeated after a first one (the library from Python).

The CLI's Campbell diagram solves 8 modes per speed (ROSS's call here: ``frequencies=6``), the
Python calls 6 on both sides.

Each figure is the median of ``--repeats`` interleaved pairs (ours, then ROSS), as wall time and
as the CPU time of the child processes (user + system; read it when the machine is loaded:
``uptime`` is printed). ROSS is optional and is never installed into this interpreter: give the
Python of a venv that has it with ``--ross-python`` (ROSS 2.3 installs on Python 3.11 with
``pip install "ross-rotordynamics==2.3.*" "plotly<7"``). Without it the script says so and times
ours alone, on the shipped ``general_rotor.toml`` (the compressor needs ROSS to be saved).

Usage::

    python benchmarks/bench_cli_vs_ross.py [--ross-python /path/to/venv/bin/python] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
SPEED = 500.0  # rad/s, the modal analysis
CAMPBELL = (0.0, 1100.0, 61)  # rad/s: ROSS's compressor_example over its speed range

# verb -> (our command-line arguments after the scenario, our Python call, ROSS's call); the
# Python calls run with `sc` (our scenario) or `r` (ROSS's rotor) and numpy as `np` in scope.
# ROSS memoises run_modal per rotor (and run_campbell calls it per speed): its cache is cleared
# before each ROSS call, or a repeated call would time a dictionary look-up.
_CLEAR = "(hasattr(r.run_modal, 'cache_clear') and r.run_modal.cache_clear())"
VERBS = {
    "modes": (
        ["--speed", str(SPEED), "--number", "6"],
        f"rubrotor.modes(sc, speed={SPEED}, n=6)",
        f"({_CLEAR}, r.run_modal(speed={SPEED}, num_modes=12))",
    ),
    "campbell": (
        ["--speeds", f"{CAMPBELL[0]:g}:{CAMPBELL[1]:g}:{CAMPBELL[2]}", "--json"],
        f"rubrotor.campbell(sc, np.linspace{CAMPBELL}, n=6)",
        f"({_CLEAR}, r.run_campbell(np.linspace{CAMPBELL}, frequencies=6))",
    ),
}


def _env() -> dict:
    env = dict(os.environ, PYTHONPATH=str(SRC), OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    env.setdefault("NUMBA_NUM_THREADS", "1")
    return env


def _timed(cmd: list[str]) -> tuple[float, float]:
    """Wall and child CPU time (s) of one command, which must succeed."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=_env())
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _warm(python: str, setup: str, call: str, repeats: int) -> tuple[float, float]:
    """Median wall and CPU time (s) of ``call`` in one interpreter, after a first call."""
    code = (
        "import time, statistics, warnings\nwarnings.simplefilter('ignore')\n"
        "import numpy as np\n"
        f"{setup}\n{call}\nw, c = [], []\n"
        f"for _ in range({repeats}):\n"
        "    t0, p0 = time.perf_counter(), time.process_time()\n"
        f"    {call}\n"
        "    w.append(time.perf_counter() - t0); c.append(time.process_time() - p0)\n"
        "print(statistics.median(w), statistics.median(c))\n"
    )
    out = subprocess.run([python, "-c", code], check=True, capture_output=True, text=True,
                         env=_env())  # fmt: skip
    wall, cpu = out.stdout.split()[-2:]
    return float(wall), float(cpu)


def _scenario(ross_python: str | None, folder: Path) -> Path:
    """Our scenario of the compared rotor: ROSS's compressor (saved by ROSS, then
    ``import-ross``), or the shipped general rotor without ROSS."""
    if ross_python is None:
        return SRC / "rubrotor" / "scenarios" / "general_rotor.toml"
    saved = folder / "compressor_ross.toml"
    subprocess.run([ross_python, "-c", "import warnings; warnings.simplefilter('ignore'); "
                    f"import ross; ross.compressor_example().save({str(saved)!r})"],
                   check=True, env=_env())  # fmt: skip
    out = folder / "compressor.toml"
    subprocess.run([sys.executable, "-m", "rubrotor", "import-ross", str(saved), "--out", str(out)],
                   check=True, stdout=subprocess.DEVNULL, env=_env())  # fmt: skip
    return out


def _ours_cli() -> list[str]:
    """The console script when it is this interpreter's, else ``python -m rubrotor``."""
    script = Path(sys.executable).parent / "rubrotor"
    return [str(script)] if script.exists() else [sys.executable, "-m", "rubrotor"]


def _has_ross(python: str | None) -> bool:
    if python is None:
        return False
    probe = subprocess.run([python, "-c", "import ross"], capture_output=True, env=_env())
    return probe.returncode == 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ross-python", help="Python of a venv with ROSS (never this one)")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    ross = args.ross_python if _has_ross(args.ross_python) else None
    if ross is None:
        print("ROSS not found (give --ross-python): timing rubrotor alone on general_rotor.toml")
    print(f"machine: {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}; one BLAS thread")
    with tempfile.TemporaryDirectory() as tmp:
        scenario = _scenario(ross, Path(tmp))
        cli = _ours_cli()
        setup_ours = f"import rubrotor\nsc = rubrotor.load_scenario({str(scenario)!r})"
        setup_ross = "import ross\nr = ross.compressor_example()"
        print("Python start-up alone (fresh, `python -c pass`): "
              f"{statistics.median(_timed([sys.executable, '-c', 'pass'])[0] for _ in range(3)):.3f} s")  # fmt: skip
        print(f"{'call':38s} {'ours wall':>10s} {'ours CPU':>9s} {'ROSS wall':>10s} "
              f"{'ROSS CPU':>9s} {'ratio CPU':>9s}")  # fmt: skip
        rows = [("--help", cli + ["--help"], None)]
        for verb, (flags, _, ross_call) in VERBS.items():
            ross_cmd = None
            if ross:
                ross_cmd = [ross, "-c", f"import warnings; warnings.simplefilter('ignore'); "
                            f"import numpy as np; {setup_ross.replace(chr(10), '; ')}; {ross_call}"]  # fmt: skip
            rows.append((f"{verb} (fresh interpreter)", cli + [verb, str(scenario)] + flags,
                         ross_cmd))  # fmt: skip
        for name, ours_cmd, ross_cmd in rows:
            _timed(ours_cmd)  # the first run fills the caches (not timed)
            ours, theirs = [], []
            for _ in range(args.repeats):
                ours.append(_timed(ours_cmd))
                if ross_cmd:
                    theirs.append(_timed(ross_cmd))
            _row(name, ours, theirs)
        for verb, (_, ours_call, ross_call) in VERBS.items():
            ours = [_warm(sys.executable, setup_ours, ours_call, args.repeats)]
            theirs = [_warm(ross, setup_ross, ross_call, args.repeats)] if ross else []
            _row(f"{verb} (warm, in one interpreter)", ours, theirs)
    return 0


def _row(name: str, ours: list, theirs: list) -> None:
    ow, oc = statistics.median(w for w, _ in ours), statistics.median(c for _, c in ours)
    if theirs:
        tw, tc = statistics.median(w for w, _ in theirs), statistics.median(c for _, c in theirs)
        print(f"{name:38s} {ow:10.3f} {oc:9.3f} {tw:10.3f} {tc:9.3f} {tc / oc:8.1f}x")
    else:
        print(f"{name:38s} {ow:10.3f} {oc:9.3f} {'-':>10s} {'-':>9s} {'-':>9s}")


if __name__ == "__main__":
    sys.exit(main())
