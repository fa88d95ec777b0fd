"""Linear verbs: ``modes``, ``critical``, ``campbell`` and ``stability`` (a pressed contact)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

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
from rubrotor.modelling import model_of


# ---- modes -------------------------------------------------------------------------------------
def modes_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument(
        "--speed",
        metavar="SPEED",
        help="spin speed, rad/s or a unit after the number (12000rpm, 200hz); default: the "
        "scenario's speed",
    )
    parser.add_argument(
        "--station",
        type=float,
        metavar="M",
        help="refer modal masses and stiffnesses to this axial position (m); default: where "
        "each mode deflects most",
    )
    parser.add_argument(
        "--order",
        choices=("ross", "natural"),
        default="ross",
        help="general rotors: modes selected and ordered as ROSS 3.1's run_modal (default: "
        "the 4n nearest 1/s, positive damped frequencies first by damped frequency) or by "
        "undamped natural frequency |lambda| (natural)",
    )
    parser.add_argument(
        "--number",
        type=int,
        metavar="N",
        help="general rotors: keep N modes (ROSS's run_modal with num_modes = 2 N); default "
        "20 in the table, all in JSON",
    )
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")


def _modal_masses(scenario, speed: float, station: float | None, out: dict | None) -> None:
    """Modal masses (kg) and stiffnesses (N/m): into ``out`` (JSON) or printed as a table."""
    from rubrotor.linear.modal_mass import NORMALISATION, modal_masses

    mm = modal_masses(scenario, speed, station, n=12)
    if out is not None:
        out["modal_mass_normalisation"] = NORMALISATION
        out["modal_masses"] = [m.to_dict() for m in mm]
        return
    print(f"\nmodal masses and stiffnesses ({NORMALISATION})")
    rows = [[str(m.index), f"{m.frequency_hz:.2f}", f"{m.station:.4g}", f"{m.modal_mass:.4g}",
             f"{m.modal_stiffness:.4g}", f"{round(math.degrees(m.direction)) % 180}"] for m in mm]  # fmt: skip
    heads = ["mode", "undamped (Hz)", "station x (m)", "modal mass (kg)", "stiffness (N/m)",
             "direction (deg from y)"]  # fmt: skip
    print(table(heads, rows))


def modes_run(args: argparse.Namespace) -> int:
    from rubrotor.linear.verbs import modes
    from rubrotor.units import parse_speed

    scenario = load_scenario(args.scenario)
    speed = scenario.speed if args.speed is None else parse_speed(args.speed, "--speed")
    if not math.isfinite(speed) or speed < 0:
        raise InputError("--speed", args.speed, "a finite spin speed >= 0 (rad/s)")
    if model_of(scenario).linear == "matrix":
        if args.number is not None and args.number < 1:
            raise InputError("--number", args.number, "a number of modes >= 1")
        count = args.number if args.number is not None else (None if args.json else 20)
        return _general_modes(scenario, speed, args.json, args.station, args.order, count)
    result = modes(scenario, speed)
    if args.json:
        out = {
            "speed_rad_s": speed,
            "modes": [
                {"n": m.n, "branch": m.branch, "whirl": m.whirl, "frequency_hz": m.frequency_hz}
                for m in result
            ],
        }
        _modal_masses(scenario, speed, args.station, out)
        print_json(out)
        return 0
    print(f"{scenario.name}: whirl frequencies at {speed:.6g} rad/s ({speed / TWO_PI:.6g} Hz)")
    rows = [
        [str(m.n), m.branch, m.whirl, f"{m.frequency_hz:.2f}", f"{m.frequency_rad_s:.2f}"]
        for m in result
    ]
    print(table(["n", "branch", "whirl", "frequency (Hz)", "frequency (rad/s)"], rows))
    _modal_masses(scenario, speed, args.station, None)
    return 0


def _general_modes(
    scenario,
    speed: float,
    as_json: bool,
    station: float | None,
    order: str = "ross",
    count: int | None = 20,
) -> int:
    """Damped modes of a general rotor and modal masses: JSON, or tables."""
    from rubrotor.linear.verbs import damped_modes

    result = damped_modes(scenario, speed, count, order)
    if as_json:
        out = result.to_dict()
        _modal_masses(scenario, speed, station, out)
        print_json(out)
        return 0
    print(
        f"{scenario.name}: damped modes at {speed:.6g} rad/s ({speed / TWO_PI:.6g} Hz), "
        + (
            "ordered as ROSS 3.1 (by damped frequency)"
            if order == "ross"
            else "ranked by undamped natural frequency |lambda|"
        )  # fmt: skip
    )
    rows = [
        [
            str(m.index),
            f"{m.frequency_hz:.3f}",
            f"{m.natural_frequency_hz:.3f}",
            f"{m.damping_ratio:.4g}",
            f"{m.log_dec:.4g}",
            m.whirl + (" (overdamped)" if m.overdamped else ""),
        ]
        for m in result.modes  # 20 modes (natural: then the overdamped roots up to the 20th)
    ]
    head = ["mode", "frequency (Hz)", "natural (Hz)", "damping ratio", "log dec", "whirl"]
    print(table(head, rows))
    _modal_masses(scenario, speed, station, None)
    return 0


def _general_critical(scenario, as_json: bool, max_speed: float | None) -> int:
    """Critical speeds (1X crossings) and the stability threshold of a general rotor."""
    from rubrotor.linear.critical import CRITICALLY_DAMPED, linear_critical_speeds
    from rubrotor.linear.stability import ZETA_ROUNDOFF, is_undamped, stability_threshold
    from rubrotor.linear.verbs import linear_system

    top = max_speed if max_speed is not None else max(3.0 * scenario.speed, 100.0)
    system = linear_system(scenario)
    crit = linear_critical_speeds(system, top, n=8)
    threshold = stability_threshold(system, top, n=8)
    undamped = threshold is None and is_undamped(system, (0.0, 0.5 * top, top), n=8)
    if as_json:
        print_json(
            {
                "max_speed_rad_s": top,
                "critical_speeds": [c.to_dict() for c in crit],
                "critically_damped_above": CRITICALLY_DAMPED,
                "stability_threshold_rad_s": threshold,
                "undamped": undamped,
            }
        )
        return 0
    print(f"{scenario.name}: critical speeds up to {top:.6g} rad/s (damped frequency = spin)")
    rows = [
        [
            str(c.index),
            c.whirl,
            f"{c.speed_rad_s:.2f}",
            f"{c.speed_rpm:.0f}",
            f"{c.damping_ratio:.3g}",
        ]
        + (["critically damped"] if c.critically_damped else [""])
        for c in crit
    ]
    print(table(["mode", "whirl", "speed (rad/s)", "speed (rpm)", "damping ratio", ""], rows))
    if any(c.critically_damped for c in crit):
        print(
            f"critically damped: damping ratio > {CRITICALLY_DAMPED:g} (API 684: amplification "
            "factor < 2.5), no resonance peak to keep a separation margin from"
        )
    if undamped:
        print(f"stability threshold: none, the rotor is undamped (every damping ratio within "
              f"+-{ZETA_ROUNDOFF:g}, the eigensolver's round-off, up to {top:.6g} rad/s)")
    else:
        print("stability threshold: "
              + (f"{threshold:.6g} rad/s" if threshold is not None
                 else f"none up to {top:.6g} rad/s"))  # fmt: skip
    return 0


# ---- critical ----------------------------------------------------------------------------------
def critical_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument(
        "--max-speed",
        type=float,
        metavar="RAD_PER_S",
        help="general rotors: search up to this speed (default 3 x the scenario's speed)",
    )


def critical_run(args: argparse.Namespace) -> int:
    from rubrotor.linear.verbs import critical_speeds

    scenario = load_scenario(args.scenario)
    if model_of(scenario).linear == "matrix":
        if args.max_speed is not None and not (
            math.isfinite(args.max_speed) and args.max_speed > 0
        ):
            raise InputError("--max-speed", args.max_speed, "a finite speed > 0 (rad/s)")
        return _general_critical(scenario, args.json, args.max_speed)
    result = critical_speeds(scenario)
    if args.json:
        print_json(
            {
                "critical_speeds": [
                    {"n": c.n, "branch": c.branch, "whirl": c.whirl, "speed_rad_s": c.speed_rad_s}
                    for c in result
                ]
            }
        )
        return 0
    print(f"{scenario.name}: critical speeds (whirl frequency = spin)")
    rows = [
        [
            str(c.n),
            c.branch,
            c.whirl,
            f"{c.speed_rad_s:.2f}",
            f"{c.speed_hz:.2f}",
            f"{c.speed_hz * 60:.0f}",
        ]
        for c in result
    ]
    print(table(["n", "branch", "whirl", "speed (rad/s)", "speed (Hz)", "speed (rpm)"], rows))
    return 0


# ---- campbell ----------------------------------------------------------------------------------


def campbell_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument(
        "--speeds",
        required=True,
        metavar="START:STOP:COUNT",
        help="spin speeds, rad/s or a unit after a number: 0:60000:200, 0:12000rpm:61",
    )
    parser.add_argument("--out", metavar="FILE.png",
                        help="figure file to write (.png/.pdf/.svg; .html: interactive, general "
                        "rotor, needs the 'interactive' extra); no figure without it")  # fmt: skip
    parser.add_argument(
        "--json", action="store_true", help="print the diagram data as JSON on stdout"
    )
    parser.add_argument("--run-range", metavar="MIN:MAX",
                        help="minimum operating and maximum continuous speed (rad/s), shaded with "
                        "the API 684 separation margins; default 0.7 x the scenario's speed to "
                        "its speed (general rotor)")  # fmt: skip


def run_range(text: str | None, speed: float) -> tuple[float, float]:
    """``MIN:MAX`` (rad/s) of ``--run-range``, or ``(0.7 speed, speed)``; an InputError naming
    the flag unless ``0 <= MIN <= MAX`` are finite numbers."""
    if text is None:
        return 0.7 * speed, speed
    try:
        lo, hi = (float(v) for v in text.split(":"))
    except ValueError:
        raise InputError("--run-range", text, "MIN:MAX in rad/s, e.g. 400:630") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo <= hi):
        raise InputError("--run-range", text, "finite speeds 0 <= MIN <= MAX (rad/s)")
    return lo, hi


def campbell_run(args: argparse.Namespace) -> int:
    from rubrotor.linear.shaft import campbell

    speeds = parse_speeds(args.speeds)
    if args.out is None and not args.json:
        raise InputError("--out", None, "a figure file (--out FILE.png), --json, or both")
    out = None if args.out is None else Path(args.out)
    fmt = None if out is None else out.suffix.lstrip(".").lower()
    if out is not None and fmt not in ("png", "pdf", "svg", "html"):
        raise InputError("--out", args.out, "a file name ending in .png, .pdf, .svg or .html")
    scenario = load_scenario(args.scenario)
    model = model_of(scenario)
    if model.linear == "matrix":
        band = run_range(args.run_range, scenario.speed)
        return _general_campbell(scenario, speeds, out, args.json, band)
    if fmt == "html":
        raise InputError("--out", args.out, "a .png, .pdf or .svg file for a [shaft] scenario")
    shaft = model.require_shaft("the Campbell diagram")
    if out is not None:  # the figure only when asked for: drawing it costs more than the solve
        from rubrotor.plotting.linear import campbell_figure

        save_atomic(campbell_figure(shaft, speeds, operating_speed=scenario.speed), out)
    if args.json:
        data = campbell(shaft, speeds)
        curves = []
        for i, n in enumerate(data["n"]):
            for j, (branch, whirl) in enumerate(data["labels"]):
                curves.append(
                    {
                        "n": int(n),
                        "branch": branch,
                        "whirl": whirl,
                        "frequency_hz": data["frequency_hz"][:, i, j].tolist(),
                    }
                )
        print_json(
            {
                "speed_rad_s": data["speed_rad_s"].tolist(),
                "operating_speed_rad_s": scenario.speed,
                "modes": curves,
                "figure": None if out is None else str(out),
            }
        )
    else:
        print(f"wrote {out}")
    return 0


def _general_campbell(scenario, speeds, out: Path | None, as_json: bool, band) -> int:
    """Campbell diagram with stability (log dec in colour) of a general rotor; an interactive
    HTML page when ``out`` ends in .html, no figure when ``out`` is None."""
    from rubrotor.linear.campbell import campbell_data
    from rubrotor.linear.critical import linear_critical_speeds
    from rubrotor.linear.verbs import linear_system

    system = linear_system(scenario)
    data = campbell_data(system, speeds, n=8)
    # the critical speeds are marked on the figure only (JSON alone: not searched)
    crit = linear_critical_speeds(system, float(speeds[-1]), n=8) if out and speeds[-1] > 0 else []
    title = f"Campbell diagram: {scenario.name}"
    if out is None:  # no figure asked for (--json alone)
        pass
    elif out.suffix.lower() == ".html":
        from rubrotor.plotting.interactive import campbell_html, write_html

        write_html(campbell_html(data, crit, scenario.speed, title, band), out)
    else:
        from rubrotor.plotting.linear import campbell_stability_figure

        save_atomic(campbell_stability_figure(data, crit, scenario.speed, title, band), out)
    if as_json:
        print_json({**data.to_dict(), "figure": None if out is None else str(out)})
    else:
        print(f"wrote {out}")
    return 0


# ---- stability of a pressed contact ----------------------------------------------------------
def stability_args(parser: argparse.ArgumentParser) -> None:
    add_scenario(parser)
    parser.add_argument(
        "--indentation", type=float, required=True, metavar="M", help="static indentation (m)"
    )
    parser.add_argument(
        "--bh-nd", type=float, metavar="BH", help="contact damping b_h' (default: the scenario's)"
    )
    parser.add_argument(
        "--formulation",
        choices=("both", "two-field", "seed-eq1"),
        default="both",
        help="shaft formulation(s) (default both)",
    )
    parser.add_argument("--modes", type=int, metavar="N", help="shaft modes (default: scenario's)")
    parser.add_argument("--no-friction", action="store_true", help="set mu = 0")
    parser.add_argument(
        "--linearisation", choices=("radial", "isotropic"), default="radial", help="contact model"
    )
    parser.add_argument("--top", type=int, default=6, help="eigenvalues listed per formulation")
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")


def stability_run(args: argparse.Namespace) -> int:
    from rubrotor.linear.stability import contact_stability

    scenario = load_scenario(args.scenario)
    if args.modes is not None and not 1 <= args.modes <= 200:
        raise InputError("--modes", args.modes, "an integer in 1..200")
    forms = ("two-field", "seed-eq1") if args.formulation == "both" else (args.formulation,)
    if model_of(scenario).linear == "matrix":
        forms = ("general",)  # the finite-element rotor: one formulation
    res = [
        contact_stability(
            scenario,
            args.indentation,
            formulation=f,
            contact_damping_nd=args.bh_nd,
            modes=args.modes,
            friction=not args.no_friction,
            linearisation=args.linearisation,
        )
        for f in forms
    ]
    if args.json:
        print_json({"speed_rad_s": scenario.speed, "results": [r.as_dict() for r in res]})
        return 0
    r0 = res[0]
    print(
        f"{scenario.name}: pressed contact, indentation {r0.indentation:.4g} m, F_n0 "
        f"{r0.normal_force:.4g} N, radial stiffness {r0.radial_stiffness:.4g} N/m, damping "
        f"{r0.radial_damping:.4g} N s/m"
        + (", the first [[contact]] table of the finite-element rotor" if r0.formulation ==
           "general" else f" (b_h = {r0.contact_damping:.4g} s/m), {args.linearisation} "
           "linearisation")
    )  # fmt: skip
    rows = [
        [
            r.formulation,
            f"{e.real:+.4g}",
            f"{e.imag / TWO_PI:+.2f}",
            r.verdict(e),
        ]
        for r in res
        for e in r.eigenvalues[: max(args.top, 1)]
    ]
    print(table(["formulation", "growth rate (1/s)", "whirl frequency (Hz)", ""], rows))
    tols = ", ".join(f"{r.formulation} {r.growth_tolerance:.2g}" for r in res)
    print(f"neutral: |growth rate| below round-off, 1e-10 x the largest |eigenvalue| ({tols} 1/s)")
    return 0
