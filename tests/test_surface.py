"""No traceback on a binary file given to import-ross, nor on a closed pipe (`| head`)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from rubrotor.cli import main

SRC = str(Path(__file__).parents[1] / "src")


def test_import_ross_of_a_binary_file(tmp_path, capsys):
    png = tmp_path / "rotor.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)))
    assert main(["import-ross", str(png), "--out", str(tmp_path / "r.toml")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("rubrotor: error: ROTOR_FILE") and "not UTF-8 text" in err
    assert "byte 0x89 at offset 0" in err


def test_closed_pipe_is_not_a_traceback():
    """``rubrotor modes seal_rub | head -1``: the reader closes the pipe after one line."""
    env = {**os.environ, "PYTHONPATH": SRC}
    proc = subprocess.Popen([sys.executable, "-m", "rubrotor", "modes", "seal_rub"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)  # fmt: skip
    proc.stdout.readline()
    proc.stdout.close()  # as head does
    err = proc.stderr.read().decode()
    proc.stderr.close()
    proc.wait(timeout=600)
    assert "Traceback" not in err and "BrokenPipeError" not in err
    assert proc.returncode in (0, 1)
