"""Same rotor, same mesh: rubrotor's finite-element builder against ROSS's own elements.

Run: ``PYTHONPATH=src /work/venvs/ross23/bin/python benchmarks/bench_fe_vs_ross_elements.py``
(any venv with ``pip install "rubrotor[ross]"``; ROSS 2.3 and 3.x both work).

Each rotor is described once (sections cut into elements, disks, bearings) and built twice:
with :class:`rubrotor.rotors.fe.Rotor` (Nelson-McVaugh Timoshenko element, ``rubrotor.rotors.elements``)
and with ROSS's ``ShaftElement``/``DiskElement``/``BearingElement`` on the same nodes, the same
material and the same shear-coefficient rule. ROSS's global matrices are brought onto our DOFs
with :func:`rubrotor.from_ross` (its DOF mapping is tested separately in
``tests/test_ross_interop.py``). Printed per rotor and beam theory:

* the largest entry-wise difference of ``M``, ``K`` (bearings at the speed included) and ``G``,
  relative to the largest entry of each matrix;
* the largest relative difference of the lowest 12 damped frequencies at 0 and at the top
  speed: (a) ours against the same eigensolver on ROSS's matrices (element differences only),
  (b) ours against ROSS's ``run_modal`` (elements and eigensolvers).

The ROSS switches for the beam theories: Timoshenko = ``shear_effects``, ``rotary_inertia``,
``gyroscopic`` all on (ROSS's default); Rayleigh = ``shear_effects=False``; Euler-Bernoulli =
all three off (disks keep their gyroscopic moments in both codes).

A last block compares the ``"hutchinson"`` shear coefficient, where the two codes use
different formulas (see the printed note), and shows that passing ROSS's number reproduces ROSS.
"""

from __future__ import annotations

import contextlib
import io
import os
import warnings

import numpy as np
import scipy.linalg as sl


def _import_ross_quietly():
    """Import ROSS with file descriptors 1 and 2 on /dev/null: its ``ccp`` dependency prints a
    screenful of "could not load REFPROP" from native code (harmless)."""
    saved = os.dup(1), os.dup(2)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import ross
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (*saved, devnull):
            os.close(fd)
    return ross


ross = _import_ross_quietly()

from rubrotor.rotors.fe import Bearing, Disk, Material, Rotor, Section  # noqa: E402
from rubrotor.rotors.ross import from_ross  # noqa: E402
from rubrotor.rotors.shaft import shear_coefficient_value  # noqa: E402

warnings.simplefilter("ignore")

THEORIES = {
    "timoshenko": dict(shear_effects=True, rotary_inertia=True, gyroscopic=True),
    "rayleigh": dict(shear_effects=False, rotary_inertia=True, gyroscopic=True),
    "euler-bernoulli": dict(shear_effects=False, rotary_inertia=False, gyroscopic=False),
}
BEARING_KEYS = {"kyy": "kxx", "kyz": "kxy", "kzy": "kyx", "kzz": "kyy"}
BEARING_KEYS |= {"c" + k[1:]: "c" + v[1:] for k, v in BEARING_KEYS.items()}


def example_description():
    """``ross.rotor_example()`` as documented by ROSS: 6 solid steel elements of 0.25 m, two
    geometric disks at nodes 2 and 4, bearings ``kxx = 1e6``, ``kyy = 0.8e6`` N/m at the ends."""
    disk = dict(outer_diameter=0.28, width=0.07, bore_diameter=0.05)
    return dict(
        name="ross.rotor_example()",
        material=dict(youngs_modulus=211e9, density=7810, shear_modulus=81.2e9),
        sections=[(1.5, 0.05, 0.0, 6)],
        disks=[(0.5, disk), (1.0, disk)],
        bearings=[(x, dict(kyy=1e6, kzz=0.8e6)) for x in (0.0, 1.5)],
        top_speed=600.0,
    )


def stepped_description():
    """12 hollow steel elements (0.05/0.04 m outer, 0.01 m bore), two disks, anisotropic
    cross-coupled damped bearings (the rotor of ``tests/test_ross_interop.py``, constant)."""
    b = dict(kyy=2e7, kzz=4e7, kyz=3e6, kzy=-2e6, cyy=1e3, czz=2e3, cyz=50.0, czy=-40.0)
    return dict(
        name="stepped, 12 el.",
        material=dict(youngs_modulus=211e9, density=7810, poisson_ratio=0.3),
        sections=[(0.6, 0.05, 0.01, 6), (0.6, 0.04, 0.01, 6)],
        disks=[(0.4, (8.0, 0.06, 0.03)), (0.9, (5.0, 0.035, 0.02))],
        bearings=[(x, b) for x in (0.0, 1.2)],
        top_speed=900.0,
    )


def rotor60_description():
    """The 60-element rotor of ``bench_linear_vs_ross.py``: 1.2 m hollow steel (0.06/0.01 m),
    disks at 0.4 and 0.8 m, anisotropic cross-coupled bearings at 0.04 and 1.16 m."""
    b = dict(kyy=3e7, kzz=6e7, kyz=5e6, kzy=-5e6, cyy=2e3, czz=3e3)
    return dict(
        name="60 el., 2 disks",
        material=dict(youngs_modulus=211e9, density=7810, poisson_ratio=0.3),
        sections=[(1.2, 0.06, 0.01, 60)],
        disks=[(0.4, (10.0, 0.1, 0.05)), (0.8, (7.0, 0.07, 0.04))],
        bearings=[(x, b) for x in (0.04, 1.16)],
        top_speed=2000.0,
    )


def build_ours(desc, theory, shear_coefficient="cowper"):
    """The description as a rubrotor :class:`~rubrotor.rotors.fe.Rotor`."""
    mat = Material("steel", **desc["material"])
    sections = [
        Section(L, od, mat, bore_diameter=i, elements=n) for L, od, i, n in desc["sections"]
    ]
    disks = []
    for x, d in desc["disks"]:
        if isinstance(d, dict):
            disks.append(Disk.from_geometry(x, material=mat, **d))
        else:
            m, ip, id_ = d
            disks.append(Disk(x, m, polar_inertia=ip, diametral_inertia=id_))
    bearings = [Bearing(x, **k) for x, k in desc["bearings"]]
    return Rotor(sections, disks, bearings, theory=theory, shear_coefficient=shear_coefficient)


def build_ross(desc, theory, shear_method_calc="cowper"):
    """The description as a ROSS rotor on the same nodes."""
    m = desc["material"]
    extra = {"G_s": m["shear_modulus"]} if "shear_modulus" in m else {"Poisson": m["poisson_ratio"]}
    mat = ross.Material(name="steel_same_mesh", rho=m["density"], E=m["youngs_modulus"], **extra)
    shaft, nodes = [], [0.0]
    for length, od, bore, n in desc["sections"]:
        for _ in range(n):
            shaft.append(
                ross.ShaftElement(
                    L=length / n,
                    idl=bore,
                    odl=od,
                    material=mat,
                    shear_method_calc=shear_method_calc,
                    **THEORIES[theory],
                )
            )
            nodes.append(nodes[-1] + length / n)

    def node(x):
        return int(np.argmin(np.abs(np.array(nodes) - x)))

    disks = []
    for x, d in desc["disks"]:
        if isinstance(d, dict):
            disks.append(
                ross.DiskElement.from_geometry(
                    n=node(x),
                    material=mat,
                    width=d["width"],
                    i_d=d["bore_diameter"],
                    o_d=d["outer_diameter"],
                )
            )
        else:
            disks.append(ross.DiskElement(n=node(x), m=d[0], Ip=d[1], Id=d[2]))
    bearings = [
        ross.BearingElement(
            n=node(x), **({"cxx": 0.0} | {BEARING_KEYS[k]: v for k, v in b.items()})
        )
        for x, b in desc["bearings"]
    ]
    with contextlib.redirect_stdout(io.StringIO()):
        return ross.Rotor(shaft, disks, bearings)


def relative_difference(a, b):
    """Largest ``|a - b|`` relative to the largest ``|b|``."""
    return float(np.abs(a - b).max() / np.abs(b).max())


def eig_frequencies(matrices, count=12):
    """Lowest ``count`` damped frequencies (rad/s), dense ``eigvals`` of the first-order form."""
    lam = sl.eigvals(matrices.first_order()[0])
    return np.sort(lam.imag[lam.imag > 1e-3])[:count]


def ross_frequencies(rotor, speed, count=12):
    """Lowest ``count`` lateral damped frequencies (rad/s) of ROSS's ``run_modal``."""
    with contextlib.redirect_stdout(io.StringIO()):
        modal = rotor.run_modal(speed, num_modes=2 * count + 16)
    vec = np.asarray(modal.evectors)[: rotor.ndof]
    n = rotor.number_dof
    lateral_rows = np.sort(np.r_[np.arange(0, rotor.ndof, n), np.arange(1, rotor.ndof, n)])
    lateral = np.linalg.norm(vec[lateral_rows], axis=0) > 1e-6 * np.linalg.norm(vec, axis=0)
    wd = np.asarray(modal.evalues).imag[lateral]
    return np.sort(wd[wd > 1e-3])[:count]


def compare(desc, theory, shear=("cowper", "cowper")):
    """Differences of one rotor in one theory (dict of floats)."""
    ours_rotor = build_ours(desc, theory, shear[0])
    ross_rotor = build_ross(desc, theory, shear[1])
    ours, theirs = ours_rotor.linear_system(), from_ross(ross_rotor)
    np.testing.assert_allclose(ours.basis.nodes, theirs.basis.nodes, rtol=0, atol=1e-12)
    out = {}
    for speed in (0.0, desc["top_speed"]):
        a, b = ours.matrices(speed), theirs.matrices(speed)
        out["M"] = relative_difference(a.M, b.M)
        out["K"] = max(out.get("K", 0.0), relative_difference(a.K, b.K))
        out["G"] = relative_difference(a.G, b.G) if np.any(b.G) else 0.0
        fa = eig_frequencies(a)
        out[f"same solver @{speed:g}"] = float(np.max(np.abs(fa - eig_frequencies(b)) / fa))
        fr = ross_frequencies(ross_rotor, speed)
        out[f"run_modal @{speed:g}"] = float(np.max(np.abs(fa[: len(fr)] - fr) / fr))
    return out


def hutchinson_note(desc):
    """Shear coefficient of the rotor's (solid) elements: ours, Hutchinson (2001) and ROSS's."""
    m = desc["material"]
    nu = m["youngs_modulus"] / (2 * m["shear_modulus"]) - 1
    paper = 6 * (1 + nu) ** 2 / (7 + 12 * nu + 4 * nu**2)
    theirs = build_ross(desc, "timoshenko", "hutchinson").shaft_elements[0].kappa
    return nu, shear_coefficient_value("hutchinson", nu), paper, float(theirs)


def main():
    print(f"ROSS {ross.__version__}; relative differences, ours vs ROSS on the same mesh")
    with contextlib.redirect_stdout(io.StringIO()):
        shipped = ross.rotor_example()
    rebuilt = build_ross(example_description(), "timoshenko")
    check = max(
        relative_difference(getattr(rebuilt, k)(0.0), getattr(shipped, k)(0.0)) for k in "MK"
    )
    print(
        f"(our description of rotor_example rebuilt in ROSS vs ross.rotor_example(): {check:.1e})"
    )
    head = ["M", "K", "G", "same solver @0", "same solver @top", "run_modal @0", "run_modal @top"]
    print(f"{'rotor':24s} {'theory':16s} " + " ".join(f"{h:>16s}" for h in head))
    for desc in (example_description(), stepped_description(), rotor60_description()):
        for theory in THEORIES:
            d = compare(desc, theory)
            top = f"{desc['top_speed']:g}"
            vals = [d[k.replace("top", top)] for k in head]
            print(f"{desc['name']:24s} {theory:16s} " + " ".join(f"{v:16.2e}" for v in vals))
    desc = example_description()
    nu, ours, paper, theirs = hutchinson_note(desc)
    print(
        f"\nHutchinson shear coefficient of rotor_example's solid elements (nu = {nu:.6f}): "
        f"rubrotor {ours:.6f}, Hutchinson (2001) 6(1+nu)^2/(7+12nu+4nu^2) = {paper:.6f}, "
        f"ROSS {theirs:.6f} (ROSS's formula has (1+nu) where the paper has (1+nu)^2)"
    )
    mismatch = compare(desc, "timoshenko", ("hutchinson", "hutchinson"))
    matched = compare(desc, "timoshenko", (theirs, "hutchinson"))
    print(
        f"rotor_example, 'hutchinson' in both: K differs by {mismatch['K']:.2e}, frequencies by "
        f"{mismatch['same solver @0']:.2e}; ours given ROSS's kappa: K {matched['K']:.2e}, "
        f"frequencies {matched['same solver @0']:.2e}"
    )


if __name__ == "__main__":
    main()
