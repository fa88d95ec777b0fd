"""The API design checks: ``clearance`` (API 617 close-clearance check of every contact) and
``level1`` (API 684 Level I stability)."""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys

from rubrotor.cli.common import add_scenario, load_scenario, parse_speeds, print_json, table
from rubrotor.cli.response import (
    figure_path,
    on_rotor,
    parse_stiffness,
    speed_or_default,
    write_figure,
)
from rubrotor.errors import InputError, ScenarioError


def _options(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument("--max-speed", type=float, metavar="RAD_PER_S",
                        help="maximum continuous speed (rad/s); default the scenario's speed")  # fmt: skip
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument("--figure", metavar="FILE.png", help="also write a figure (.png/.pdf/.svg)")


def _probe(text: str) -> tuple[float, float | None]:
    """``X`` or ``X@DEG``: a probe at X m, along DEG degrees from +y towards +z."""
    pos, _, deg = text.partition("@")
    try:
        return float(pos), (math.radians(float(deg)) if deg else None)
    except ValueError:
        raise InputError(
            "--probe", text, "X (m) or X@ANGLE (m, degrees from +y towards +z)"
        ) from None


# ---- clearance ---------------------------------------------------------------------------------
def clearance_args(parser: argparse.ArgumentParser) -> None:
    _options(parser)
    parser.add_argument("--min-speed", type=float, metavar="RAD_PER_S",
                        help="minimum allowable speed (rad/s); default 0.7 x the maximum")  # fmt: skip
    parser.add_argument("--speeds", metavar="START:STOP:COUNT",
                        help="response speeds (rad/s); default 0 to 1.25 x the maximum, 251")  # fmt: skip
    parser.add_argument("--probe", type=_probe, action="append", metavar="X[@DEG]",
                        help="vibration probe (m, optional angle); default each bearing, major axis")  # fmt: skip
    parser.add_argument("--mode", type=int, default=0, help="forward mode placing the unbalance, counted from 0 (0: the first "
                        "forward mode, 1: the second, ...; default 0)")
    parser.add_argument("--no-cap", action="store_true", help="no cap of 6 on the scale factor")
    parser.add_argument("--trip-speed", type=float, metavar="RAD_PER_S",
                        help="trip speed (rad/s) of the critical speeds' clearance check; "
                        "default 1.05 x the maximum")  # fmt: skip


def _print_criticals(res) -> None:
    """The critical speeds of API 617 (response peaks at the probes) with their verdicts."""
    top = max(res.trip_speed, 1.25 * res.max_speed)
    print(f"API 617 critical speeds up to {top:.5g} rad/s (response peaks at the probes, AF by "
          f"the half-power method >= 2.5; clearances checked up to the trip speed "
          f"{res.trip_speed:.5g} rad/s):")  # fmt: skip
    if not res.criticals:
        print("  none: no response peak with AF >= 2.5")
        return
    rows = [[f"{c.speed_rad_s:.5g}", f"{c.whirl} ({c.mode_whirl} mode)", str(c.probe + 1),
             f"{c.amplification_factor:.3g}", f"{100 * c.required_margin:.3g}",
             f"{100 * c.actual_margin:.3g}",
             ", ".join(f"{m * 1e6:.4g}" for m in c.clearance_margins) or "-", c.verdict]
            for c in res.criticals]  # fmt: skip
    print(table(["N_c (rad/s)", "whirl at probe", "probe", "AF", "SM req (%)", "SM (%)",
                 "clearance margin (µm)", "verdict"], rows))  # fmt: skip


def clearance_run(args: argparse.Namespace) -> int:
    import numpy as np

    from rubrotor.linear.api617 import clearance_check
    from rubrotor.linear.front import with_criticals
    from rubrotor.linear.verbs import linear_system
    from rubrotor.plotting.response import clearance_figure

    out = figure_path(args.figure)
    scenario = load_scenario(args.scenario)
    nmc = speed_or_default(args.max_speed, scenario.speed, "--max-speed")
    nma = speed_or_default(args.min_speed, 0.7 * nmc, "--min-speed")
    if not 0 < nmc or nma > nmc:
        raise InputError("--min-speed", nma, f"a speed in [0, {nmc:g}] rad/s (maximum > 0)")
    speeds = parse_speeds(args.speeds) if args.speeds else np.linspace(0.0, 1.25 * nmc, 251)
    if not scenario.contacts:
        raise ScenarioError("contact", None, "a [contact] or [[contact]] table: the clearances")
    gaps = [(f"contact {i + 1} at {c.position:g} m", c.position, c.clearance)
            for i, c in enumerate(scenario.contacts)]  # fmt: skip
    system = linear_system(scenario, [p for p, _ in args.probe or []])
    probes = args.probe or [(s.position, None) for s in system.supports]
    on_rotor(scenario, [p for p, _ in probes], "--probe")
    res = clearance_check(system, speeds, nma, nmc, probes, gaps, args.mode,
                          scale_factor_cap=None if args.no_cap else 6.0)  # fmt: skip
    trip = speed_or_default(args.trip_speed, 1.05 * nmc, "--trip-speed")
    if trip < nmc:
        raise InputError("--trip-speed", args.trip_speed, f"a speed >= {nmc:g} rad/s (N_mc)")
    res = with_criticals(res, system, probes, gaps, trip)
    d = res.to_dict()
    if args.json:
        print_json(d)
    else:
        print(
            f"{scenario.name}: API 617 close-clearance check, N_ma {nma:.5g} .. N_mc {nmc:.5g} rad/s"
        )
        if res.mode is not None:
            md = res.mode
            af = md["amplification_factor"]
            print(f"mode: forward mode {md['forward_index']} at {md['frequency_rad_s']:.6g} rad/s "
                  f"({md['whirl']}), damping ratio {md['damping_ratio']:.4g}, AF "
                  f"{'-' if af is None else f'{af:.3g}'}, separation margin "
                  f"{100 * md['separation_margin']:.3g} %")  # fmt: skip
        print("unbalance: " + ", ".join(f"{m * 1e6:.4g} g mm at {p:g} m, {f:.3g} rad"
                                         for p, m, f in res.planes))  # fmt: skip
        print(f"A_vl {res.vibration_limit * 1e6:.4g} µm pk-pk, A_max {res.max_probe_amplitude * 1e6:.4g}"
              f" µm pk-pk, scale factor {res.scale_factor:.4g}")  # fmt: skip
        rows = [[c["name"], f"{c['diametral_clearance_m'] * 1e6:.4g}",
                 f"{c['max_scaled_response_m_pp'] * 1e6:.4g}", f"{c['worst_speed_rad_s']:.5g}",
                 f"{c['margin_m'] * 1e6:.4g}", c["verdict"]] for c in d["clearances"]]  # fmt: skip
        print(table(["clearance", "2c (µm)", "scaled (µm pp)", "at (rad/s)", "margin (µm)",
                     "verdict"], rows))  # fmt: skip
        _print_criticals(res)
    for c in d["clearances"]:
        if c["touching_speeds_rad_s"]:
            s = c["touching_speeds_rad_s"]
            print(f"rubrotor: note: the scaled orbit at {c['name']} reaches its clearance at "
                  f"{s[0]:.5g}-{s[-1]:.5g} rad/s: simulate the rub there (set [speed] rad_per_s = "
                  f"{c['worst_speed_rad_s']:.5g} and run `rubrotor simulate`)", file=sys.stderr)  # fmt: skip
    write_figure(clearance_figure(res, f"API 617 clearance check: {scenario.name}"), out, args.json)
    return 0


# ---- level1 ------------------------------------------------------------------------------------
def _stage(text: str) -> tuple[float, float, float, float]:
    allowed = "POWER_W,DIAMETER_M,WIDTH_M[,DENSITY_RATIO] with positive numbers"
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise InputError("--stage", text, allowed) from None
    if len(vals) not in (3, 4) or not all(v > 0 and math.isfinite(v) for v in vals):
        raise InputError("--stage", text, allowed)
    return tuple(vals) if len(vals) == 4 else (*vals, 1.0)


def level1_args(parser: argparse.ArgumentParser) -> None:
    _options(parser)
    parser.add_argument("--at", type=float, metavar="X",
                        help="station of the cross-coupling (m); default mid-span between the "
                        "outermost bearings, or the heaviest overhung disk (the stage) of an "
                        "overhung rotor")  # fmt: skip
    parser.add_argument("--stiffness", metavar="START:STOP:COUNT",
                        help="cross-coupled stiffness (N/m, log-spaced); default 1e4:1e9:41")  # fmt: skip
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--qa", type=float, metavar="N_PER_M", help="anticipated cross-coupling")
    group.add_argument("--stage", type=_stage, action="append", metavar="P,D,H[,RATIO]",
                       help="a compressor stage for Q_A (W, m, m, discharge/suction density)")  # fmt: skip


def _station(scenario) -> tuple[float, str]:
    from rubrotor.linear.front import level1_station
    from rubrotor.modelling import model_of

    return level1_station(model_of(scenario))


def level1_run(args: argparse.Namespace) -> int:
    import numpy as np

    from rubrotor.linear.api684 import anticipated_cross_coupling, level1
    from rubrotor.linear.verbs import linear_system
    from rubrotor.plotting.response import level1_figure

    out = figure_path(args.figure)
    q = parse_stiffness(args.stiffness) if args.stiffness else None
    scenario = load_scenario(args.scenario)
    speed = speed_or_default(args.max_speed, scenario.speed, "--max-speed")
    at, location = (args.at, "given") if args.at is not None else _station(scenario)
    on_rotor(scenario, [at], "--at")
    system = linear_system(scenario, (at,))
    qa = args.qa
    if args.stage:
        p, d, h, r = zip(*args.stage, strict=True)
        qa = anticipated_cross_coupling(p, speed, d, h, r)
    if qa is not None and not (math.isfinite(qa) and qa > 0):
        raise InputError("--qa", qa, "a cross-coupled stiffness > 0 (N/m)")
    try:
        res = dataclasses.replace(level1(system, speed, at, q, qa), location=location)
    except InputError as exc:
        if exc.field != "stiffness":
            raise
        raise InputError("--stiffness", args.stiffness or "1e4:1e9:41", exc.allowed) from None
    if args.json:
        print_json(res.to_dict())
    else:
        print(
            f"{scenario.name}: API 684 Level I at {speed:.5g} rad/s, cross-coupling at x = {at:g} m "
            f"({location})"
        )
        pick = np.unique(np.linspace(0, res.stiffness.size - 1, 9).round().astype(int))
        print(table(["Q (N/m)", "log dec", "frequency (Hz)"],
                    [[f"{res.stiffness[i]:.3g}", f"{res.log_dec[i]:.4g}", f"{res.frequency_hz[i]:.4g}"]
                     for i in pick]))  # fmt: skip
        q0 = f"{res.q0:.4g} N/m" if res.q0 is not None else "above the range"
        print(f"Q0 (log dec 0): {q0}")
        if qa is not None:
            print(f"Q_A {qa:.4g} N/m: log dec {res.log_dec_at_qa:.4g}, verdict: {res.verdict}")
    write_figure(level1_figure(res, f"API 684 Level I: {scenario.name}"), out, args.json)
    return 0
