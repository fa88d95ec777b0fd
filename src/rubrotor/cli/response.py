"""Verbs of the static and forced response and of the design maps of any rotor: ``static``,
``response``, ``unbalance``, ``ucs`` and ``shapes`` (the linear verbs a ROSS user expects)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING

from rubrotor.cli.common import (
    TWO_PI,
    add_scenario,
    load_scenario,
    parse_speeds,
    print_json,
    save_atomic,
    table,
)
from rubrotor.errors import InputError

if TYPE_CHECKING:  # annotations only: numpy is imported when a verb runs, not at --help
    import numpy as np

FIGURE_FORMATS = ("png", "pdf", "svg")


def figure_path(text: str | None, flag: str = "--figure", formats=FIGURE_FORMATS) -> Path | None:
    """The figure file of ``flag``: ``None`` when not given; an ``InputError`` naming the
    flag unless it ends in one of ``formats`` (.png, .pdf or .svg) and its directory exists."""
    if text is None:
        return None
    out = Path(text)
    if out.suffix.lstrip(".").lower() not in formats:
        names = ", ".join(f".{f}" for f in formats[:-1]) + f" or .{formats[-1]}"
        raise InputError(flag, text, f"a file name ending in {names}")
    directory = out.parent if str(out.parent) else Path(".")
    if not directory.is_dir():
        raise InputError(flag, text, "a file in an existing directory")
    return out


def speed_or_default(value, default: float, flag: str = "--speed") -> float:
    """``value`` (rad/s, or text with a unit after the number: ``12000rpm``) or ``default``."""
    from rubrotor.units import parse_speed

    speed = (
        default if value is None else parse_speed(value, flag) if isinstance(value, str) else value
    )
    if not (math.isfinite(speed) and speed >= 0):
        raise InputError(flag, value, "a finite spin speed >= 0 (rad/s)")
    return float(speed)


def on_rotor(scenario, values, flag: str) -> list[float]:
    """Stations (m) on the rotor: ``[0, L]`` for a finite-element rotor, ``(0, L)`` for the
    continuous shaft (pinned at its ends); an InputError naming ``flag`` otherwise."""
    from rubrotor.modelling import model_of

    length, closed = model_of(scenario).span()
    lo = 0.0 if closed else 1e-12 * length
    for x in values:
        if not (math.isfinite(x) and lo <= x <= length - lo):
            where = f"[0, {length:g}]" if closed else f"(0, {length:g})"
            raise InputError(flag, x, f"a position on the rotor, in {where} m")
    return [float(x) for x in values]


def _common(parser: argparse.ArgumentParser, speed_help: str | None = None) -> None:
    add_scenario(parser)
    if speed_help:
        parser.add_argument("--speed", metavar="SPEED", help=speed_help)
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument("--figure", metavar="FILE.png", help="also write a figure (.png/.pdf/.svg)")


def write_figure(fig, out: Path | None, as_json: bool) -> None:
    if out is None:
        return
    save_atomic(fig, out)
    if not as_json:
        print(f"wrote {out}")


# ---- static ------------------------------------------------------------------------------------
def static_args(parser: argparse.ArgumentParser) -> None:
    _common(
        parser,
        "spin speed for speed-dependent bearings (rad/s, or a unit after the number: "
        "12000rpm); default the scenario's",
    )


def static_run(args: argparse.Namespace) -> int:
    import numpy as np

    from rubrotor.linear.static import static_analysis
    from rubrotor.plotting.response import static_figure

    out = figure_path(args.figure)
    scenario = load_scenario(args.scenario)
    res = static_analysis(scenario, speed_or_default(args.speed, scenario.speed))
    if args.json:
        print_json(res.to_dict())
    else:
        gy, gz = res.gravity
        i = int(np.argmax(np.hypot(res.deflection[:, 0], res.deflection[:, 1])))
        print(f"{scenario.name}: static deflection under gravity ({gy:g}, {gz:g}) m/s^2 and loads")
        print(
            f"largest deflection {np.hypot(*res.deflection[i]) * 1e6:.4g} µm at x = {res.x[i]:.4g} m"
        )
        rows = [[b.name, f"{b.position:.4g}", f"{b.force_y:.6g}", f"{b.force_z:.6g}"]
                for b in res.bearings]  # fmt: skip
        heads = ["support", "x (m)", "F_y on rotor (N)", "F_z on rotor (N)"]
        if any(b.eccentricity_ratio is not None for b in res.bearings):  # fluid films
            heads += ["eccentricity ratio (1)", "attitude angle (deg)"]
            for row, b in zip(rows, res.bearings, strict=True):
                film = b.eccentricity_ratio is not None
                row += [f"{b.eccentricity_ratio:.6g}" if film else "-",
                        f"{math.degrees(b.attitude_angle_rad) + 0.0:.4g}" if film else "-"]  # fmt: skip
        print(table(heads, rows))
    write_figure(static_figure(res, f"static deflection: {scenario.name}"), out, args.json)
    return 0


# ---- response ----------------------------------------------------------------------------------
def response_args(parser: argparse.ArgumentParser) -> None:
    _common(
        parser, "spin speed (rad/s, or a unit after the number: 12000rpm); default the scenario's"
    )
    parser.add_argument("--at", type=float, required=True, metavar="X", help="force station (m)")
    parser.add_argument("--frequencies", required=True, metavar="START:STOP:COUNT",
                        help="excitation frequencies (rad/s), independent of the spin")  # fmt: skip
    parser.add_argument("--kind", choices=("fixed", "forward", "backward"), default="fixed",
                        help="force fixed in direction, or rotating forward/backward")  # fmt: skip
    parser.add_argument("--force", type=float, default=1.0, metavar="N", help="amplitude (N)")
    parser.add_argument("--direction", type=float, default=0.0, metavar="RAD",
                        help="force angle at t = 0 from +y towards +z (rad)")  # fmt: skip
    parser.add_argument("--probe", type=float, action="append", metavar="X",
                        help="probe position (m), repeatable; default the force station")  # fmt: skip


def response_run(args: argparse.Namespace) -> int:
    import numpy as np

    from rubrotor.linear.response import frequency_response
    from rubrotor.linear.verbs import linear_system
    from rubrotor.plotting.response import frequency_response_figure

    out = figure_path(args.figure)
    freqs = parse_speeds(args.frequencies, "--frequencies")
    scenario = load_scenario(args.scenario)
    on_rotor(scenario, [args.at], "--at")
    probes = on_rotor(scenario, args.probe or [args.at], "--probe")
    system = linear_system(scenario, (args.at, *probes))
    res = frequency_response(system, freqs, args.at, probes, args.kind, args.force,
                             args.direction, speed_or_default(args.speed, scenario.speed))  # fmt: skip
    if args.json:
        print_json(res.to_dict())
    else:
        print(f"{scenario.name}: {args.kind} force {args.force:g} N at x = {args.at:g} m, "
              f"spin {res.speed_rad_s:.6g} rad/s")  # fmt: skip
        rows = []
        for p, x in enumerate(res.probes):
            k = int(np.argmax(res.major[:, p]))
            rows.append([f"{x:.4g}", f"{res.major[k, p] * 1e6:.4g}", f"{freqs[k]:.6g}"])
        print(
            table(["probe x (m)", "peak major semi-axis (µm 0-pk)", "at frequency (rad/s)"], rows)
        )
    write_figure(frequency_response_figure(res), out, args.json)
    return 0


# ---- unbalance ---------------------------------------------------------------------------------
def unbalance_args(parser: argparse.ArgumentParser) -> None:
    _common(parser)
    parser.add_argument("--speeds", required=True, metavar="START:STOP:COUNT",
                        help="spin speeds (rad/s, or 0:12000rpm:61, 5hz:200hz:40)")  # fmt: skip
    parser.add_argument("--probe", type=float, action="append", required=True, metavar="X",
                        help="probe position (m), repeatable; the figure draws every probe's "
                        "major semi-axis, and the phase and polar plot of the first; a figure "
                        "ending in .html is interactive (the 'interactive' extra)")  # fmt: skip


def unbalance_run(args: argparse.Namespace) -> int:
    import numpy as np

    from rubrotor.linear.response import scenario_unbalance_response, unbalance_to_dict
    from rubrotor.plotting.linear import (
        amplification_factors,
        half_power_speeds,
        resonance_speeds,
        unbalance_response_figure,
    )

    out = figure_path(args.figure, formats=(*FIGURE_FORMATS, "html"))
    speeds = parse_speeds(args.speeds)
    scenario = load_scenario(args.scenario)
    res = scenario_unbalance_response(scenario, speeds, on_rotor(scenario, args.probe, "--probe"))
    if not np.all(np.isfinite(res.major)):  # linear in m e Omega^2: only a magnitude overflows
        big = max(scenario.unbalances, key=lambda u: u.magnitude)
        raise InputError("unbalance.magnitude", big.magnitude,
                         f"an unbalance whose force m e Omega^2 at {speeds[-1]:g} rad/s and "
                         "response are finite numbers (kg m)")  # fmt: skip
    if args.json:
        print_json(unbalance_to_dict(res))
    else:
        planes = ", ".join(f"{u.magnitude:g} kg m at {u.position:g} m" for u in scenario.unbalances)
        print(f"{scenario.name}: unbalance response to {planes}")
        rows = []
        for p, x in enumerate(res.probes):
            k = int(np.argmax(res.major[:, p]))
            rows.append([f"{x:.4g}", f"{res.major[k, p] * 1e6:.4g}", f"{speeds[k]:.6g}"])
        print(table(["probe x (m)", "peak major semi-axis (µm 0-pk)", "at speed (rad/s)"], rows))
    if out is not None:  # the figure on a grid refined at the peaks: smooth polar circles
        x = float(res.probes[0])
        gaps = [c.clearance for c in scenario.contacts if abs(c.position - x) <= 1e-9]
        fine = scenario_unbalance_response(
            scenario, resonance_speeds(speeds, res.major[:, 0]), list(res.probes))  # fmt: skip
        peaks = amplification_factors(fine.speeds, fine.major[:, 0])
        finer = half_power_speeds(peaks, speeds[0], speeds[-1])
        if finer.size:  # light damping: speeds evenly in phase through each resonance
            grid = np.unique(np.concatenate([fine.speeds, finer]))
            fine = scenario_unbalance_response(scenario, grid, list(res.probes))
        gap = min(gaps) if gaps else None
        if out.suffix.lower() == ".html":
            from rubrotor.plotting.interactive import bode_html, write_html

            write_html(bode_html(fine, 0, gap, scenario.name), out)
            if not args.json:
                print(f"wrote {out}")
        else:
            write_figure(unbalance_response_figure(fine, 0, gap, scenario.name), out, args.json)
    return 0


# ---- ucs ---------------------------------------------------------------------------------------
def parse_stiffness(text: str) -> np.ndarray:
    """``START:STOP:COUNT`` (N/m) into ``COUNT`` log-spaced stiffness values.

    Examples
    --------
    >>> parse_stiffness("1e6:1e8:3")
    array([1.e+06, 1.e+07, 1.e+08])
    """
    import numpy as np

    allowed = "START:STOP:COUNT with 0 < START < STOP (N/m) and an integer COUNT in 2..10000"
    try:
        start, stop, count = (float(v) for v in text.split(":"))
    except ValueError:
        raise InputError("--stiffness", text, allowed) from None
    if not (0 < start < stop < math.inf) or count != int(count) or not 2 <= count <= 10000:
        raise InputError("--stiffness", text, allowed)
    return np.logspace(math.log10(start), math.log10(stop), int(count))


def ucs_args(parser: argparse.ArgumentParser) -> None:
    _common(parser)
    parser.add_argument("--stiffness", metavar="START:STOP:COUNT",
                        help="support stiffness (N/m, log-spaced); default around the bearings")  # fmt: skip
    parser.add_argument("--modes", type=int, default=4, help="number of modes (default 4)")


def ucs_run(args: argparse.Namespace) -> int:
    import numpy as np

    from rubrotor.linear.ucs import ucs_map
    from rubrotor.linear.verbs import linear_system
    from rubrotor.plotting.linear import ucs_figure

    out = figure_path(args.figure)
    stiffness = None if args.stiffness is None else parse_stiffness(args.stiffness)
    if args.modes < 1:
        raise InputError("--modes", args.modes, "a number of modes >= 1")
    scenario = load_scenario(args.scenario)
    data = ucs_map(linear_system(scenario), stiffness, args.modes)
    if args.json:
        print_json(data.to_dict())
    else:
        print(f"{scenario.name}: undamped critical speeds (rad/s) against support stiffness")
        pick = np.unique(np.linspace(0, data.stiffness.size - 1, 9).round().astype(int))
        rows = [[f"{data.stiffness[i]:.3g}"] + [f"{w:.5g}" for w in data.critical_speeds[i]]
                for i in pick]  # fmt: skip
        heads = ["k (N/m)"] + [f"mode {j + 1}" for j in range(data.critical_speeds.shape[1])]
        print(table(heads, rows))
        cross = [[c["bearing"], c["direction"], str(c["mode"]), f"{c['stiffness_N_m']:.4g}",
                  f"{c['speed_rad_s']:.5g}"] for c in data.crossings()]  # fmt: skip
        if cross:
            print("critical speeds on the bearings (their curve crosses a mode's):")
            print(table(["bearing", "curve", "mode", "k (N/m)", "speed (rad/s)"], cross))
    write_figure(ucs_figure(data, f"undamped critical speed map: {scenario.name}"), out, args.json)
    return 0


# ---- shapes ------------------------------------------------------------------------------------
def shapes_args(parser: argparse.ArgumentParser) -> None:
    _common(
        parser, "spin speed (rad/s, or a unit after the number: 12000rpm); default the scenario's"
    )
    parser.add_argument("--modes", type=int, default=4, help="number of modes (default 4)")


def shapes_run(args: argparse.Namespace) -> int:
    import numpy as np

    from rubrotor.linear.shapes import mode_shapes, node_whirl
    from rubrotor.linear.verbs import linear_system
    from rubrotor.plotting.linear import mode_shapes_3d_figure

    out = figure_path(args.figure)
    if args.modes < 1:
        raise InputError("--modes", args.modes, "a number of modes >= 1")
    scenario = load_scenario(args.scenario)
    speed = speed_or_default(args.speed, scenario.speed)
    shapes = mode_shapes(linear_system(scenario), speed, args.modes)
    if args.json:
        print_json(shapes.to_dict())
    else:
        print(f"{scenario.name}: mode shapes at {speed:.6g} rad/s ({speed / TWO_PI:.6g} Hz)")
        rows = []
        for k, m in enumerate(shapes.modes.modes):
            d = node_whirl(shapes.v[k], shapes.w[k])
            rows.append([str(m.index), f"{m.frequency_hz:.4f}", f"{m.log_dec:.4g}", m.whirl,
                         str(int(np.sum(d == "forward"))), str(int(np.sum(d == "backward")))])  # fmt: skip
        print(table(["mode", "frequency (Hz)", "log dec", "whirl", "fwd nodes", "bwd nodes"], rows))
    write_figure(mode_shapes_3d_figure(shapes), out, args.json)
    return 0
