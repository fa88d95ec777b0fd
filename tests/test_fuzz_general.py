"""Mangled general-rotor scenarios through ``modes``, ``simulate`` and ``continue`` (issue 21).

Property-based, the pattern of tests/test_mangled_scenarios.py extended to the general engine:
hypothesis takes a shipped general-rotor scenario (seal_rub, general_rotor, runup_rub), applies
one mutation a user could make (a key removed, a value scaled by 1e-12 .. 1e12 or negated, or
set to 0, nan, inf, +-1e300, 1e-300) and runs one verb in-process with short settings. Every run
must end with exit status 0, 1 (a partial run, said on stderr) or 2 (one line on stderr, no
traceback); it must not hang (an alarm fails it after 120 s; mutations asking for more than
``MAX_STEPS`` fixed steps are long runs, not hangs, and left out); and a run that exits 0 must hold
no NaN: the modes' frequencies, the simulated displacements and forces, the branch's radii.
"""

from __future__ import annotations

import json
import math
import signal
import tempfile
import tomllib
from pathlib import Path

import numpy as np
import xarray as xr
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from test_mangled_scenarios import SCENARIOS, _dump, _leaves, _table

from rubrotor.cli import main

GENERAL = [p for p in SCENARIOS if p.stem in ("seal_rub", "general_rotor", "runup_rub")]
FACTORS = [1e-12, 1e-6, 1e6, 1e12, -1.0]
VALUES = [0, math.nan, math.inf, 1e300, -1e300, 1e-300]
HANG_S = 120
MAX_STEPS = 2e6  # fixed steps of a simulate example (more is a long run, not a hang)


def _short(doc: dict) -> None:
    """Short runs: one revolution, or 0.02 s of a speed profile."""
    sim = doc.setdefault("simulation", {})
    if "duration" in sim:
        sim["duration"] = min(float(sim["duration"]), 0.02)
    else:
        sim["revolutions"] = 1


def _mutate(value, how):
    if how == "remove":
        return None
    kind, x = how
    if kind == "set":
        return x
    if isinstance(value, bool) or not isinstance(value, int | float | list):
        return x * 1.0  # a number where text was
    if isinstance(value, list):
        return [v * x if isinstance(v, int | float) else v for v in value]
    return value * x


@st.composite
def mangled(draw):
    path = draw(st.sampled_from(GENERAL))
    doc = tomllib.loads(path.read_text())
    _short(doc)
    leaf = draw(st.sampled_from(sorted(_leaves(doc), key=str)))
    how = draw(st.one_of(st.just("remove"), st.tuples(st.just("scale"), st.sampled_from(FACTORS)),
                         st.tuples(st.just("set"), st.sampled_from(VALUES))))  # fmt: skip
    table = _table(doc, leaf)
    new = _mutate(table[leaf[2]], how)
    if new is None:
        del table[leaf[2]]
    else:
        table[leaf[2]] = new
    command = draw(st.sampled_from(["modes", "simulate", "simulate", "continue"]))
    assume(command != "simulate" or _steps(doc) < MAX_STEPS)
    return path.stem, _dump(doc), command


def _steps(doc: dict) -> float:
    """Fixed steps a run asks for (a step scaled down 1e12 is a long run, not a hang)."""
    sim, speed = doc.get("simulation", {}), doc.get("speed", {})
    dt = sim.get("dt")
    if not isinstance(dt, int | float) or isinstance(dt, bool) or not dt > 0:
        return 0.0
    if isinstance(sim.get("duration"), int | float):
        return sim["duration"] / dt
    w = speed.get("rpm", 0) * math.pi / 30 if "rpm" in speed else speed.get("rad_per_s", 1.0)
    revs = sim.get("revolutions", 1)
    try:
        return float(revs) * 2 * math.pi / float(w) / dt
    except (TypeError, ValueError, ZeroDivisionError):
        return 0.0


def _argv(command: str, scenario: Path, out: Path) -> list[str]:
    if command == "modes":
        return ["modes", str(scenario), "--json"]
    if command == "simulate":
        return ["simulate", str(scenario), "--out", str(out / "r.nc"), "--no-progress"]
    return ["continue", str(scenario), "--vary", "speed.rad_per_s=600:601", "--points", "2",
            "--steps", "32", "--out", str(out / "b.nc")]  # fmt: skip


def _no_nan(command: str, out: Path, stdout: str) -> None:
    if command == "modes":
        freqs = [m["frequency_hz"] for m in json.loads(stdout)["modes"]]
        assert freqs and np.all(np.isfinite(freqs)), stdout
        return
    name = "r.nc" if command == "simulate" else "b.nc"
    with xr.open_dataset(out / name) as ds:
        for var in ("v", "w", "normal_force", "max_radius_m"):
            if var in ds:
                assert np.all(np.isfinite(ds[var].values)), var


def _hang(signum, frame):
    raise TimeoutError(f"no answer within {HANG_S} s")


@settings(
    max_examples=30,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(case=mangled())
def test_mangled_general_rotor_never_raises_hangs_or_fakes(case, tmp_path, capsys):
    name, text, command = case
    work = Path(tempfile.mkdtemp(prefix=f"{name}-", dir=tmp_path))
    scenario = work / f"{name}.toml"
    scenario.write_text(text)
    previous = signal.signal(signal.SIGALRM, _hang)
    signal.alarm(HANG_S)
    try:
        status = main(_argv(command, scenario, work))
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    out, err = capsys.readouterr()
    assert status in (0, 1, 2), (status, err)
    if status == 2:
        lines = [ln for ln in err.splitlines() if ln.strip()]
        assert len(lines) == 1 and lines[0].startswith("rubrotor: error:"), err
    if status == 1:
        assert "rubrotor: warning:" in err, err
    if status == 0:
        _no_nan(command, work, out)
