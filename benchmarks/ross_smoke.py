"""Smoke run of the ROSS peer models (needs the ``bench`` extra: ROSS installed).

Prints:
* ROSS's first three bending whirl frequencies of the seed shaft (40 Timoshenko
  elements) at 0 and 10000 rad/s against the closed-form quartic (validation
  aid), with relative differences; also with 80 elements, to show ROSS's
  discretisation error;
* the wall time of ROSS's Campbell diagram over 200 speeds in 0..12000 rad/s;
* ROSS's rubbing simulation time per revolution at 11614 rad/s.

Run from the repository root:  python benchmarks/ross_smoke.py [--quick]
(--quick: one Campbell repetition instead of three, fewer rub revolutions)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import ross_peer as rp  # noqa: E402


def frequencies_table(n_elements: int) -> None:
    rotor = rp.build_ross_shaft(**rp.SEED_ROTOR, n_elements=n_elements)
    print(
        f"\nBending whirl frequencies, {n_elements} elements, "
        f"support stiffness {rp.DEFAULT_SUPPORT_STIFFNESS:.0e} N/m"
    )
    print(f"{'speed':>7} {'n':>2} {'dir':>3} {'ROSS Hz':>12} {'quartic Hz':>12} {'rel diff':>10}")
    for speed in (0.0, 10000.0):
        ross = rp.ross_bending_frequencies(rotor, speed, n_modes=3)
        ref = rp.quartic_reference_frequencies(**rp.SEED_ROTOR, speed_rad_s=speed, n_modes=3)
        for key, tag in (("forward_hz", "F"), ("backward_hz", "B")):
            for i in range(3):
                a, b = ross[key][i], ref[key][i]
                print(f"{speed:7.0f} {i + 1:2d} {tag:>3} {a:12.3f} {b:12.3f} {a / b - 1:10.2e}")
        if speed:
            print(
                "        forward share of forward/backward modes:",
                ", ".join(f"{f:.3f}/{b:.3f}" for f, b in ross["forward_fraction"]),
            )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)

    print(f"ROSS {rp.ross_version()}, numpy {np.__version__}")
    kappa = rp.cowper_shear_coefficient_solid(
        rp.SEED_ROTOR["youngs_modulus"], rp.SEED_ROTOR["shear_modulus"]
    )
    rotor = rp.build_ross_shaft(**rp.SEED_ROTOR)
    el = rotor.shaft_elements[0]
    print(
        f"Cowper kappa: ours {kappa:.10f}, ROSS element {el.kappa:.10f} "
        f"(ROSS Poisson {el.material.Poisson:.10f})"
    )
    frequencies_table(40)
    frequencies_table(80)

    speeds = np.linspace(0.0, 12000.0, 200)
    repeats = 1 if args.quick else 3
    med, camp, info = rp.ross_campbell_seconds(rotor, speeds, repeats=repeats)
    print(
        f"\nROSS run_campbell, {info['n_speeds']} speeds 0..12000 rad/s, "
        f"{info['frequencies']} tracked modes (3 bending pairs + axial/torsional in between): "
        f"median {med:.2f} s over {repeats} rep(s) {np.round(info['times_s'], 2).tolist()}"
    )

    n_rev = 4 if args.quick else 10
    model = rp.build_ross_rub_model()
    kw = model["rub_kwargs"]
    print(
        f"\nROSS rubbing: 20 elements ({model['rotor'].ndof} DOF), contact at node "
        f"{model['contact_node']} (midspan), clearance {kw['distance'] * 1e6:.0f} um, "
        f"k_c {kw['contact_stiffness']:.0e} N/m, c_c {kw['contact_damping']} N s/m, "
        f"mu {kw['friction_coeff']}, unbalance {kw['unbalance_magnitude'][0]:.0e} kg m, "
        f"Rayleigh alpha {model['alpha']:.4g} 1/s beta {model['beta']:.4g} s"
    )
    for reduction in (None, {"num_modes": 12}):
        rub = rp.ross_rub_seconds_per_revolution(
            model, speed_rad_s=11614.0, n_revolutions=n_rev, model_reduction=reduction
        )
        r = np.hypot(rub["x"], rub["y"])
        last = r[-rub["steps_per_revolution"] :]
        contact = np.hypot(*rub["contact_force"].T) > 0
        label = "direct (full FE)" if reduction is None else f"pseudo-modal {reduction}"
        print(
            f"  {label}: {rub['seconds_per_revolution'] * 1e3:.1f} ms/revolution "
            f"({rub['n_revolutions']} rev, {rub['n_steps']} Newmark steps, "
            f"dt {rub['dt'] * 1e6:.3f} us = 1/{rub['steps_per_revolution']} rev); "
            f"midspan radius max {r.max() * 1e6:.1f} um, last rev "
            f"{last.min() * 1e6:.1f}..{last.max() * 1e6:.1f} um; "
            f"in contact {contact.mean() * 100:.0f}% of steps"
        )


if __name__ == "__main__":
    main()
