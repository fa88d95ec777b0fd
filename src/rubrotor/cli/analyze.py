"""``analyze``: rub indicators, scalograms and spectra of a results or signal file."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from rubrotor.cli.common import (
    print_json,
    table,
)
from rubrotor.errors import InputError

if TYPE_CHECKING:  # annotations only: numpy is imported when a verb runs, not at --help
    import numpy as np

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
        "--fs",
        type=float,
        metavar="HZ",
        help="sampling frequency (Hz); required for .npy and for a .csv without a time column",
    )
    parser.add_argument(
        "--columns",
        metavar="A[,B]",
        help="column names (CSV header) or 0-based indices: one column, or two "
        "(v,w) for the full spectrum; default the first column that is not time, speed, rpm "
        "or keyphasor",
    )
    parser.add_argument(
        "--spin-hz",
        type=float,
        metavar="HZ",
        help="spin frequency (Hz) for signal files (harmonic ratios)",
    )
    parser.add_argument(
        "--clearance",
        type=float,
        metavar="M",
        help="radial clearance at the probe (m), for the rub verdict of a signal file",
    )
    parser.add_argument(
        "--orders",
        metavar="K[,K...]",
        default="0.5,1,2",
        help="orders of the spin speed to track (default 0.5,1,2)",
    )
    parser.add_argument(
        "--rpm", action="store_true", help="speed axes of the order figures in rev/min"
    )
    parser.add_argument("--json", action="store_true", help="print the indicators as JSON")
    parser.add_argument("--svg", action="store_true",
                        help="also write every figure as SVG beside its PNG")  # fmt: skip
    parser.add_argument("--html", action="store_true",
                        help="also write cascade.html, interactive (run-ups; needs the "
                        "'interactive' extra)")  # fmt: skip


def _read_table(path: Path, ext: str, fs):
    """Channels of a signal file as {name: array}, plus the file's own rate (WAV) or None."""
    import numpy as np

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
    from rubrotor.analysis.measured import read_csv_table

    return read_csv_table(path), None


def _pick_columns(table: dict, spec: str | None) -> list[tuple[str, np.ndarray]]:
    from rubrotor.analysis.measured import AUXILIARY_NAMES

    names = list(table)
    if spec is None:
        named = [n for n in names if not n.isdigit()]
        first = next((n for n in named if n.lower() not in AUXILIARY_NAMES), names[0])
        return [(first, table[first])]
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
        angle, speed and natural frequencies come from the file), or a ``.csv`` (optional header
        row; a ``time`` column gives the sampling frequency, a ``speed_rad_s``/``rpm`` or
        ``keyphasor`` column the spin angle, see :mod:`rubrotor.analysis.measured`), ``.npy``
        (1-D or 2-D, columns) or ``.wav`` signal file.
    fs : float, optional
        Sampling frequency (Hz); required for NPY and for a CSV without a time column, optional
        for WAV (default: its rate).
    columns : str, optional
        ``"A"`` or ``"A,B"``: column names or indices of a signal file.
    spin_hz : float, optional
        Spin frequency (Hz) of a signal file without a speed or keyphasor column.

    Returns
    -------
    dict
        ``v``, ``w`` (or None), ``fs`` (Hz), ``spin_hz`` (None for a varying speed), ``modes``
        ((label, Hz, whirl) list), ``unit``, ``names`` (channel names), ``source``, ``spin``
        (:class:`~rubrotor.analysis.orders.SpinAngle` or None), ``speed_range_rad_s``
        ((min, max) or None), ``dataset`` (the results Dataset of a ``.nc``, else None).
    """
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
        return _results_signals(p)
    return _file_signals(p, ext, fs, columns, spin_hz)


def _speed_range(spin) -> tuple[float, float] | None:
    if spin is None:
        return None
    sp = spin.speed[spin.valid]
    return float(sp.min()), float(sp.max())


def _varying(rng) -> bool:
    return rng is not None and rng[1] - rng[0] > 1e-6 * rng[1]


def _results_signals(p: Path) -> dict:
    """The signals of a results file (see :func:`load_signals`)."""
    import tomllib

    import numpy as np

    from rubrotor.analysis.orders import spin_from_dataset
    from rubrotor.analysis.overview import mode_entries
    from rubrotor.engine.result import load_dataset
    from rubrotor.errors import ScenarioError
    from rubrotor.linear.verbs import modes
    from rubrotor.scenario.load import scenario_from_dict

    ds = load_dataset(p)
    for var in ("v_dot", "w_dot", "time"):
        if var not in ds.variables:
            raise InputError("input", str(p), f"a rubrotor results file (no '{var}')")
    t = ds["time"].values
    dt = np.diff(t)
    if t.size < 64 or not np.all(dt > 0) or np.ptp(dt) > 1e-6 * np.mean(dt):
        raise InputError("input", str(p), "results saved on a uniform time grid (at least 64 samples)")  # fmt: skip
    spin = spin_from_dataset(ds)
    rng = _speed_range(spin)
    text = ds.attrs.get("scenario", "")
    entries: list = []
    if text:
        try:
            sc = scenario_from_dict(tomllib.loads(text))
            found = modes(sc, float(ds.attrs["speed_rad_s"]))
            # the shaft's closed-form whirl lines; a general rotor's damped modes are not drawn
            entries = mode_entries(found) if isinstance(found, list) else []
        except (tomllib.TOMLDecodeError, ScenarioError):
            entries = []
    v, w = _acceleration_channels(ds)
    for name, x in (("v_ddot", v), ("w_ddot", w)):
        if not np.all(np.isfinite(x)):
            raise InputError("input", f"{p}: {name}", "finite data (no NaN or inf)")
    return {
        "v": v, "w": w, "fs": 1.0 / float(np.mean(dt)),
        "spin_hz": None if _varying(rng) else float(ds.attrs["speed_hz"]),
        "modes": entries, "unit": "m/s^2", "names": ["v_ddot", "w_ddot"], "source": str(p),
        "scenario_name": ds.attrs.get("scenario_name", ""), "spin": spin,
        "speed_range_rad_s": rng, "dataset": ds, "at": _first_station(ds),
    }  # fmt: skip


def _first_station(ds) -> str | None:
    """``"x = 0.75 m"``: where the results file's first station (the analysed one) is."""
    if "station" not in ds.coords or ds["station"].size == 0:
        return None
    return f"x = {float(ds['station'].values[0]):.4g} m"


def _file_signals(p: Path, ext: str, fs, columns, spin_hz) -> dict:
    """The signals of a CSV, NPY or WAV file (see :func:`load_signals`)."""
    import numpy as np

    from rubrotor.analysis.measured import spin_from_table, time_column
    from rubrotor.analysis.orders import spin_from_speed

    table, rate = _read_table(p, ext, fs)
    tc = time_column(table) if ext == ".csv" else None
    if tc is not None:
        if fs is not None and abs(fs / tc[1] - 1) > 1e-6:
            raise InputError("--fs", fs, f"the rate of the time column {tc[0]} ({tc[1]:.9g} Hz) or no --fs")  # fmt: skip
        fs = tc[1]
    if fs is None:
        if rate is None:
            raise InputError("--fs", None, f"a sampling frequency (Hz) for {ext} files without a time column")  # fmt: skip
        fs = rate
    cols = _pick_columns(table, columns)
    for name, x in cols:
        if x.size < 64:
            raise InputError("input", f"column {name}: {x.size} samples", "at least 64 samples")
        if not np.all(np.isfinite(x)):
            raise InputError("input", f"column {name}", "finite data (no NaN or inf)")
    spin = spin_from_table(table, fs) if ext == ".csv" else None
    if spin is None and spin_hz is not None:
        t = table[tc[0]] if tc is not None else np.arange(cols[0][1].size) / fs
        spin = spin_from_speed(t, np.full(t.size, 2 * math.pi * spin_hz))
    rng = _speed_range(spin)
    if spin_hz is None and rng is not None and not _varying(rng):
        spin_hz = rng[0] / (2 * math.pi)
    return {
        "v": cols[0][1], "w": cols[1][1] if len(cols) == 2 else None, "fs": float(fs),
        "spin_hz": None if _varying(rng) else spin_hz, "modes": [], "unit": "signal unit",
        "names": [c[0] for c in cols], "source": str(p), "scenario_name": "", "spin": spin,
        "speed_range_rad_s": rng, "dataset": None,
    }  # fmt: skip


def _acceleration_channels(ds) -> tuple[np.ndarray, np.ndarray]:
    """``v_ddot, w_ddot`` (m/s^2) at the contact station: the first station of a results
    file (derived from the velocities by central differences when streamed without them)."""
    import numpy as np

    if "v_ddot" in ds.variables:
        v, w = ds["v_ddot"].values, ds["w_ddot"].values
    else:
        t = ds["time"].values
        v = np.gradient(ds["v_dot"].values, t, axis=-1)
        w = np.gradient(ds["w_dot"].values, t, axis=-1)
    return v[0], w[0]


def _indicator_rows(d: dict) -> list[list[str]]:
    rows = [["samples", f"{d['samples']}", ""], ["sampling frequency", f"{d['fs_hz']:.6g}", "Hz"]]
    if d.get("spin_hz"):
        rows.append(["spin frequency", f"{d['spin_hz']:.6g}", "Hz"])
    rng = d.get("speed_range_rad_s")
    if rng and rng[1] > rng[0] * (1 + 1e-6):
        rows.append(["spin speed range", f"{rng[0]:.6g} - {rng[1]:.6g}", "rad/s"])
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


def _parse_orders(text: str) -> tuple[float, ...]:
    from rubrotor.analysis.orders import block_revolutions

    try:
        orders = tuple(float(x) for x in text.split(","))
    except ValueError:
        raise InputError("--orders", text, "orders separated by commas, e.g. 0.5,1,2") from None
    try:
        block_revolutions(orders)
    except InputError as exc:
        raise InputError("--orders", text, exc.allowed) from None
    return orders


def _signal_orders(sig: dict, orders) -> tuple[list[dict], dict]:
    """Order rows and order tracks ({probe: track}) of a signal file with a spin angle."""
    import numpy as np

    from rubrotor.analysis.orders import track_orders

    tr = track_orders(sig["spin"], sig["v"], sig["w"], orders=orders)
    rows = []
    for i, k in enumerate(tr.orders):
        row = {"probe_m": None, "order": float(k), "channels": sig["names"],
               "speed_rad_s": tr.speed_rad_s.tolist(),
               "amplitude_y_m": np.abs(tr.y[i]).tolist(), "phase_y_rad": np.angle(tr.y[i]).tolist()}  # fmt: skip
        if tr.w is not None:
            row |= {"amplitude_z_m": np.abs(tr.w[i]).tolist(),
                    "phase_z_rad": np.angle(tr.w[i]).tolist(),
                    "forward_m": np.abs(tr.forward[i]).tolist(),
                    "backward_m": np.abs(tr.backward[i]).tolist()}  # fmt: skip
        rows.append(row)
    return rows, {" + i ".join(sig["names"]): tr}


def _orders_and_verdict(sig: dict, orders, clearance) -> tuple[dict, dict]:
    """``orders`` rows and the ``rub`` verdict of the analysed file, and the tracks drawn."""
    from rubrotor.analysis.verdict import dataset_verdict, rub_evidence, rub_verdict

    ds, spin = sig["dataset"], sig["spin"]
    if spin is None:
        why = "no spin speed: give --spin-hz, or a speed_rad_s, rpm or keyphasor column"
        return {"orders": [], "rub": {"rub": "unknown", "reasons": [why], "evidence": {}}}, {}
    try:
        rows, tracks = (
            _dataset_orders(ds, orders) if ds is not None else _signal_orders(sig, orders)
        )
    except InputError as exc:  # a record shorter than one block of the orders
        note = f"no orders: {exc.field} = {exc.value} ({exc.allowed})"
        rows, tracks = [], {}
    else:
        note = None
    if ds is not None:
        verdict = dataset_verdict(ds)
    else:
        verdict = rub_verdict(rub_evidence(spin, sig["v"], sig["w"], clearance=clearance))
    out = {"orders": rows, "rub": verdict.as_dict()}
    return (out | {"orders_note": note} if note else out), tracks


def _dataset_orders(ds, orders) -> tuple[list[dict], dict]:
    """Order rows of a results Dataset and, for a run with varying speed, the tracks drawn."""
    import numpy as np

    from rubrotor.analysis.orders import dataset_orders, spin_from_dataset, track_orders

    rows = dataset_orders(ds, orders)
    sp = spin_from_dataset(ds)
    if np.ptp(sp.speed) <= 1e-6 * np.max(sp.speed):
        return rows, {}
    v, w = ds["v"].values, ds["w"].values  # (station, time)
    return rows, {float(x): track_orders(sp, v[j], w[j], orders=orders)
                  for j, x in enumerate(ds["station"].values)}  # fmt: skip


def _order_figures(sig: dict, tracks: dict, args: argparse.Namespace, out: Path) -> list[Path]:
    """``orders.png`` (transient Bode of 1X) and ``cascade.png`` of a run with varying speed."""
    import numpy as np

    from rubrotor.analysis.diagnostics import cascade
    from rubrotor.plotting.diagnostics import bode_figure, cascade_figure

    if not tracks or not _varying(sig["speed_range_rad_s"]):
        return []
    ds = sig["dataset"]
    if ds is not None:
        y, z = ds["v"].values[0], ds["w"].values[0]
        label = "displacement at the first station"
    else:
        y, z = sig["v"], sig["w"]
        label = " + i ".join(sig["names"])
    name = sig["scenario_name"] or Path(args.input).name
    first = next(iter(tracks.values()))
    ks = tuple(k for k in (1.0,) if np.any(np.abs(first.orders - k) < 1e-9)) or (
        float(first.orders[0]),
    )
    figs = {"orders.png": bode_figure(tracks, orders=ks, rpm=args.rpm, title=f"{name}: tracked {ks[0]:g}X")}  # fmt: skip
    try:  # 8 revolutions or more: two spectra of 4
        casc = cascade(sig["spin"], y, z, revolutions=4)
    except InputError:
        casc = None
    paths = []
    if casc is not None and casc.speed_rad_s.size >= 2:
        figs["cascade.png"] = cascade_figure(casc, rpm=args.rpm, title=f"{name}: cascade of the {label}")  # fmt: skip
        if getattr(args, "html", False):
            from rubrotor.plotting.interactive import cascade_html, write_html

            write_html(
                cascade_html(casc, title=f"{name}: cascade of the {label}"), out / "cascade.html"
            )
            paths.append(out / "cascade.html")
    for fname, fig in figs.items():
        paths += save_figure(fig, out / fname, getattr(args, "svg", False))
    return paths


def save_figure(fig, path: Path, svg: bool) -> list[Path]:
    """Write ``fig`` to ``path`` (PNG) and, with ``svg``, beside it as SVG; the paths written."""
    from rubrotor.engine.result import atomic_write

    atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=110))
    if not svg:
        return [path]
    atomic_write(path.with_suffix(".svg"), lambda tmp: fig.savefig(tmp, format="svg"))
    return [path, path.with_suffix(".svg")]


def _runup_warning(sig: dict) -> None:
    rng = sig["speed_range_rad_s"]
    if _varying(rng):
        print(f"rubrotor: warning: the speed varies from {rng[0]:.6g} to {rng[1]:.6g} rad/s: "
              "no single spin frequency; orders are tracked against the run's speed (\"orders\")",
              file=sys.stderr)  # fmt: skip


def _verdict_line(rub: dict) -> str:
    return f"rub: {rub['rub']}" + (": " + "; ".join(rub["reasons"]) if rub["reasons"] else "")


def analyze_run(args: argparse.Namespace) -> int:
    from rubrotor.analysis.overview import analyze_signal, decimate_to, indicators_dict
    from rubrotor.engine.output import check_output
    from rubrotor.engine.result import atomic_write
    from rubrotor.plotting.signals import analysis_figure

    orders = _parse_orders(args.orders)  # bad options fail before the analysis
    c = args.clearance
    if c is not None and not (math.isfinite(c) and c > 0):
        raise InputError("--clearance", c, "a radial clearance > 0 (m)")
    sig = load_signals(args.input, fs=args.fs, columns=args.columns, spin_hz=args.spin_hz)
    if sig["dataset"] is not None and c is not None:
        raise InputError("--clearance", c, "only with a signal file (a results file has its clearance)")  # fmt: skip
    _runup_warning(sig)
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
    rng = sig["speed_range_rad_s"]
    d["speed_range_rad_s"] = None if rng is None else list(rng)
    extra, tracks = _orders_and_verdict(sig, orders, c)
    d |= extra
    name = sig["scenario_name"] or Path(args.input).name
    at = f" at {sig['at']}" if sig.get("at") else ""  # the station the channels were taken at
    fig = analysis_figure(
        a, title=f"{name}: {' + i '.join(sig['names'])}{at} (fs = {fs / 1e3:.4g} kHz)"
    )
    if _varying(rng):  # the orders follow the run's speed on the map
        from rubrotor.plotting.diagnostics import mark_orders

        sp = sig["spin"]
        sl = sp.valid
        mark_orders(fig.axes[0], sp.time[sl] - sp.time[0], sp.speed[sl])
    figures = save_figure(fig, out / "analysis.png", getattr(args, "svg", False))
    atomic_write(out / "indicators.json", lambda tmp: Path(tmp).write_text(json.dumps(d, indent=2)))
    written = [
        *figures,
        *_order_figures(sig, tracks, args, out),
        out / "indicators.json",
    ]
    if args.json:
        print_json(d)
    else:
        print(f"{name}: rub indicators of {', '.join(sig['names'])}")
        print(table(["quantity", "value", "unit"], _indicator_rows(d)))
        print(_verdict_line(d["rub"]))
        print("wrote " + ", ".join(str(p) for p in written))
    return 0
