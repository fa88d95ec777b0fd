"""``analyze``: rub indicators, scalograms and spectra of a results or signal file."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from rubrotor.cli.common import (
    print_json,
    table,
)
from rubrotor.errors import InputError

# ---- analyze / scenarios / reproduce -----------------------------------------------------------
_SIGNAL_EXTENSIONS = (".nc", ".csv", ".npy", ".wav")
_MAX_ANALYSIS_RATE = 2.0e6  # Hz; longer-rate records are low-passed and decimated first


def analyze_args(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "input",
        metavar="FILE",
        help="results.nc from `rubrotor run`, or a signal (.csv, .npy, .wav)",
    )
    parser.add_argument(
        "--out", metavar="DIR", help="output directory (default: the input file's directory)"
    )
    parser.add_argument(
        "--fs", type=float, metavar="HZ", help="sampling frequency (Hz); required for .csv and .npy"
    )
    parser.add_argument(
        "--columns",
        metavar="A[,B]",
        help="column names (CSV header) or 0-based indices: one column, or two "
        "(v,w) for the full spectrum; default the first column",
    )
    parser.add_argument(
        "--spin-hz",
        type=float,
        metavar="HZ",
        help="spin frequency (Hz) for signal files (harmonic ratios)",
    )
    parser.add_argument("--json", action="store_true", help="print the indicators as JSON")


def _read_table(path: Path, ext: str, fs):
    """Channels of a signal file as {name: array}, plus the file's own rate (WAV) or None."""
    if ext == ".npy":
        try:
            data = np.load(path, allow_pickle=False)
        except (OSError, ValueError) as exc:
            raise InputError("input", str(path), f"a readable .npy array ({exc})") from None
        data = np.asarray(data)
        if data.ndim == 1:
            data = data[:, None]
        if data.ndim != 2:
            raise InputError("input", f"array of shape {data.shape}", "a 1-D or 2-D array")
        return {str(i): data[:, i] for i in range(data.shape[1])}, None
    if ext == ".wav":
        from scipy.io import wavfile

        try:
            rate, data = wavfile.read(path)
        except (OSError, ValueError) as exc:
            raise InputError("input", str(path), f"a readable WAV file ({exc})") from None
        data = np.asarray(data, dtype=np.float64)
        if data.ndim == 1:
            data = data[:, None]
        return {str(i): data[:, i] for i in range(data.shape[1])}, float(rate)
    text = path.read_text().splitlines()
    if not text:
        raise InputError("input", str(path), "a CSV file with at least one row")
    first = [c.strip() for c in text[0].split(",")]
    try:
        [float(c) for c in first]
        names = [str(i) for i in range(len(first))]
        skip = 0
    except ValueError:
        names = first
        skip = 1
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=skip, ndmin=2)
    except ValueError as exc:
        raise InputError("input", str(path), f"a CSV file of numbers ({exc})") from None
    if data.shape[1] != len(names):
        raise InputError("input", str(path), "a CSV file with the same number of columns per row")
    out = {n: data[:, i] for i, n in enumerate(names)}
    for i in range(len(names)):  # indices work too
        out.setdefault(str(i), data[:, i])
    return out, None


def _pick_columns(table: dict, spec: str | None) -> list[tuple[str, np.ndarray]]:
    names = list(table)
    if spec is None:
        return [(names[0], table[names[0]])]
    wanted = [c.strip() for c in spec.split(",")]
    if not 1 <= len(wanted) <= 2 or any(not c for c in wanted):
        raise InputError("--columns", spec, "one or two column names or indices, e.g. v,w")
    for c in wanted:
        if c not in table:
            raise InputError("--columns", c, "one of the columns " + ", ".join(names))
    return [(c, table[c]) for c in wanted]


def load_signals(path, *, fs=None, columns=None, spin_hz=None) -> dict:
    """Read the signals ``rubrotor analyze`` works on.

    Parameters
    ----------
    path : path-like
        ``.nc`` results file (the accelerations ``v_ddot``, ``w_ddot`` are analysed, the spin
        speed and natural frequencies come from its attributes and scenario text), or a ``.csv``
        (optional header row), ``.npy`` (1-D or 2-D, columns) or ``.wav`` signal file.
    fs : float, optional
        Sampling frequency (Hz); required for CSV and NPY, optional for WAV (default: its rate).
    columns : str, optional
        ``"A"`` or ``"A,B"``: column names or indices of a signal file.
    spin_hz : float, optional
        Spin frequency (Hz) of a signal file.

    Returns
    -------
    dict
        ``v``, ``w`` (or None), ``fs`` (Hz), ``spin_hz``, ``modes`` ((label, Hz, whirl) list),
        ``unit``, ``names`` (channel names), ``source``.
    """
    import tomllib

    p = Path(path)
    ext = p.suffix.lower()
    if ext not in _SIGNAL_EXTENSIONS:
        raise InputError("input", str(path), "a file ending in " + ", ".join(_SIGNAL_EXTENSIONS))
    if not p.is_file():
        raise InputError("input", str(path), "an existing file")
    if fs is not None and not (math.isfinite(fs) and fs > 0):
        raise InputError("--fs", fs, "a finite sampling frequency > 0 (Hz)")
    if spin_hz is not None and not (math.isfinite(spin_hz) and spin_hz > 0):
        raise InputError("--spin-hz", spin_hz, "a finite spin frequency > 0 (Hz)")
    if ext == ".nc":
        from rubrotor.analysis.overview import mode_entries
        from rubrotor.engine.result import load_dataset
        from rubrotor.errors import ScenarioError
        from rubrotor.linear.verbs import modes
        from rubrotor.scenario.load import scenario_from_dict

        ds = load_dataset(p)
        for var in ("v_dot", "w_dot", "time"):
            if var not in ds.variables:
                raise InputError("input", str(path), f"a rubrotor results file (no '{var}')")
        t = ds["time"].values
        dt = np.diff(t)
        if t.size < 64 or not np.all(dt > 0) or np.ptp(dt) > 1e-6 * np.mean(dt):
            raise InputError(
                "input", str(path), "results saved on a uniform time grid (at least 64 samples)"
            )
        rate = 1.0 / float(np.mean(dt))
        text = ds.attrs.get("scenario", "")
        entries: list = []
        if text:
            try:
                sc = scenario_from_dict(tomllib.loads(text))
                entries = mode_entries(modes(sc, float(ds.attrs["speed_rad_s"])))
            except (tomllib.TOMLDecodeError, ScenarioError):
                entries = []
        v, w = _acceleration_channels(ds)
        for name, x in (("v_ddot", v), ("w_ddot", w)):
            if not np.all(np.isfinite(x)):
                raise InputError("input", f"{path}: {name}", "finite data (no NaN or inf)")
        return {
            "v": v,
            "w": w,
            "fs": rate,
            "spin_hz": float(ds.attrs["speed_hz"]),
            "modes": entries,
            "unit": "m/s^2",
            "names": ["v_ddot", "w_ddot"],
            "source": str(p),
            "scenario_name": ds.attrs.get("scenario_name", ""),
        }
    table, rate = _read_table(p, ext, fs)
    if fs is None:
        if rate is None:
            raise InputError("--fs", None, f"a sampling frequency (Hz) for {ext} files")
        fs = rate
    cols = _pick_columns(table, columns)
    for name, x in cols:
        if x.size < 64:
            raise InputError("input", f"column {name}: {x.size} samples", "at least 64 samples")
        if not np.all(np.isfinite(x)):
            raise InputError("input", f"column {name}", "finite data (no NaN or inf)")
    return {
        "v": cols[0][1],
        "w": cols[1][1] if len(cols) == 2 else None,
        "fs": float(fs),
        "spin_hz": spin_hz,
        "modes": [],
        "unit": "signal unit",
        "names": [c[0] for c in cols],
        "source": str(p),
        "scenario_name": "",
    }


def _acceleration_channels(ds) -> tuple[np.ndarray, np.ndarray]:
    """``v_ddot, w_ddot`` (m/s^2) at the contact station: the first station of a general-engine
    file (derived from the velocities by central differences when streamed without them)."""
    if "v_ddot" in ds.variables:
        v, w = ds["v_ddot"].values, ds["w_ddot"].values
    else:
        t = ds["time"].values
        v = np.gradient(ds["v_dot"].values, t, axis=-1)
        w = np.gradient(ds["w_dot"].values, t, axis=-1)
    return (v[0], w[0]) if v.ndim == 2 else (v, w)


def _indicator_rows(d: dict) -> list[list[str]]:
    rows = [["samples", f"{d['samples']}", ""], ["sampling frequency", f"{d['fs_hz']:.6g}", "Hz"]]
    if d.get("spin_hz"):
        rows.append(["spin frequency", f"{d['spin_hz']:.6g}", "Hz"])
    unit = d["unit"]
    freq = {m["label"]: m["frequency_hz"] for m in d.get("modes", [])}
    for label, e in (d.get("band_energy") or {}).items():
        rows.append([f"band energy {label} ({freq[label]:.0f} Hz)", f"{e:.4g}", f"({unit})^2"])
    for order, r in (d.get("harmonic_ratio") or {}).items():
        kind = "sub" if float(order) < 1 else "super"
        rows.append(
            [f"{kind}-harmonic {float(order):.3g}X / 1X", "inf" if r is None else f"{r:.4g}", ""]
        )
    if d.get("backward_share") is not None:
        rows.append(["backward-whirl share", f"{d['backward_share']:.4f}", ""])
    for i, f in enumerate(d.get("inner_scalogram_peaks_hz", []), 1):
        rows.append([f"inner-scalogram peak {i}", f"{f:.5g}", "Hz"])
    return rows


def analyze_run(args: argparse.Namespace) -> int:
    from rubrotor.analysis.overview import analyze_signal, decimate_to, indicators_dict
    from rubrotor.engine.output import check_output
    from rubrotor.engine.result import atomic_write
    from rubrotor.plotting.figures import analysis_figure

    sig = load_signals(args.input, fs=args.fs, columns=args.columns, spin_hz=args.spin_hz)
    chans = [sig["v"]] + ([sig["w"]] if sig["w"] is not None else [])
    chans, fs = decimate_to(chans, sig["fs"], _MAX_ANALYSIS_RATE)
    spin = sig["spin_hz"]
    if spin is not None and 3 * spin >= fs / 2:
        raise InputError("--spin-hz", spin, f"a spin frequency with 3X below fs/2 = {fs / 2:g} Hz")
    out = Path(args.out) if args.out else Path(args.input).resolve().parent
    if out.exists() and not out.is_dir():
        raise InputError("--out", args.out, "a directory")
    if not args.out:  # the input's folder: checked here (a given --out is checked by main)
        check_output(out, "--out (default: the input file's folder)", folder=True)
    a = analyze_signal(
        chans[0],
        fs,
        w=chans[1] if len(chans) == 2 else None,
        spin_hz=spin,
        modes=sig["modes"],
        unit=sig["unit"],
    )
    d = indicators_dict(a)
    d["source"] = sig["source"]
    d["channels"] = sig["names"]
    name = sig["scenario_name"] or Path(args.input).name
    fig = analysis_figure(
        a, title=f"{name}: {' + i '.join(sig['names'])} (fs = {fs / 1e3:.4g} kHz)"
    )
    atomic_write(out / "analysis.png", lambda tmp: fig.savefig(tmp, format="png", dpi=110))
    atomic_write(out / "indicators.json", lambda tmp: Path(tmp).write_text(json.dumps(d, indent=2)))
    if args.json:
        print_json(d)
    else:
        print(f"{name}: rub indicators of {', '.join(sig['names'])}")
        print(table(["quantity", "value", "unit"], _indicator_rows(d)))
        print(f"wrote {out / 'analysis.png'} and {out / 'indicators.json'}")
    return 0
