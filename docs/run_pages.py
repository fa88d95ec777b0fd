"""Run the commands of the tutorial and how-to pages, so that a page cannot drift from the code.

Each page that teaches commands keeps them in a script beside it (``docs/tutorials/first-rotor/
first-rotor.sh``, ``docs/howto/api617-clearance/api617-clearance.sh``, ...) and shows them with
``literalinclude``: what the reader sees is what runs here. Every script runs under ``bash -e``
in a fresh copy of its folder, with ``rubrotor`` on the PATH (this Python's ``-m rubrotor``);
the figures it writes are copied to ``docs/_pages/NAME/`` for the site to show, with its output
in ``docs/_pages/NAME/output.txt``. A failing command fails the run (exit status 1) and prints the
script's output.

A page that passed leaves ``docs/_pages/NAME/passed`` holding a digest of its folder's files;
``--stale`` runs only the pages without one or whose folder changed since. The Sphinx build
(``docs/conf.py``) runs those itself, so that the README's one docs command builds the site in a
fresh clone; ``RUBROTOR_DOCS_PAGES=all`` makes it run every page (what CI does), ``skip`` none.

Usage::

    python docs/run_pages.py            # every page
    python docs/run_pages.py --stale    # the pages not run since their folder last changed
    python docs/run_pages.py first-rotor api617-clearance
"""

from __future__ import annotations

import hashlib
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

DOCS = Path(__file__).resolve().parent
OUT = DOCS / "_pages"
KEPT = ("*.png", "*.svg", "*.html", "*.json")


def scripts() -> dict[str, Path]:
    """Page name -> its script: every ``docs/{tutorials,howto}/NAME/NAME.sh``."""
    found = {}
    for section in ("tutorials", "howto"):
        for script in sorted((DOCS / section).glob("*/*.sh")):
            if script.stem == script.parent.name:
                found[script.stem] = script
    return found


def digest(script: Path) -> str:
    """SHA-256 of the page folder's files (their paths and contents)."""
    h = hashlib.sha256()
    for f in sorted(p for p in script.parent.rglob("*") if p.is_file()):
        h.update(f.relative_to(script.parent).as_posix().encode() + b"\0" + f.read_bytes())
    return h.hexdigest()


def stale(name: str, script: Path) -> bool:
    """True when the page has not passed since its folder last changed."""
    stamp = OUT / name / "passed"
    return not stamp.exists() or stamp.read_text().strip() != digest(script)


def run(name: str, script: Path, timeout: float = 1800.0) -> bool:
    """Run one page's script in a copy of its folder; keep its figures; True when it passed."""
    with tempfile.TemporaryDirectory(prefix=f"page-{name}-") as tmp:
        work = Path(tmp) / name
        shutil.copytree(script.parent, work)
        bin_dir = Path(tmp) / "bin"
        bin_dir.mkdir()
        shim = bin_dir / "rubrotor"
        shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m rubrotor "$@"\n')
        shim.chmod(0o755)
        env = dict(os.environ, PATH=f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}",
                   MPLBACKEND="Agg")  # fmt: skip
        start = time.perf_counter()
        proc = subprocess.Popen(["bash", "-e", script.name], cwd=work, env=env, text=True,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                start_new_session=True)  # fmt: skip
        try:
            output, _ = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:  # stop the script and every command it started
            os.killpg(proc.pid, signal.SIGKILL)
            output, _ = proc.communicate()
            output += f"\n(timed out after {timeout:.0f} s)\n"
        took = time.perf_counter() - start
        dest = OUT / name
        shutil.rmtree(dest, ignore_errors=True)
        dest.mkdir(parents=True)
        (dest / "output.txt").write_text(output)
        for pattern in KEPT:
            for f in work.rglob(pattern):
                shutil.copy2(f, dest / f.relative_to(work).as_posix().replace("/", "-"))
    if proc.returncode == 0:
        (dest / "passed").write_text(digest(script) + "\n")
    status = "ok" if proc.returncode == 0 else f"FAILED (exit {proc.returncode})"
    print(f"{name}: {status} in {took:.0f} s", flush=True)
    if proc.returncode != 0:
        print(output[-6000:])
    return proc.returncode == 0


def main(argv: list[str]) -> int:
    found = scripts()
    if argv == ["--stale"]:
        argv = [n for n, s in found.items() if stale(n, s)]
        if not argv:
            return 0
    names = argv or list(found)
    unknown = [n for n in names if n not in found]
    if unknown:
        print(f"unknown page(s) {unknown}; pages: {', '.join(found)}", file=sys.stderr)
        return 2
    results = [run(n, found[n]) for n in names]
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
