"""ROSS peer models for the rubrotor benchmarks.

This module builds the *same* physical rotors as rubrotor in ROSS
(``ross-rotordynamics``, finite-element rotordynamics) so that the two codes can
be compared on natural frequencies, Campbell-diagram cost and rub-impact
simulation cost.  ROSS is only *called* here; none of its code is copied.

Nothing heavy happens at import time and ``ross`` is imported lazily inside the
functions, so this module imports fine on a machine without ROSS.

Functions
---------
build_ross_shaft
    Uniform solid simply supported Timoshenko shaft (no disk) in ROSS.
ross_bending_frequencies
    First ``n`` bending whirl frequencies (forward and backward, Hz) at a speed,
    identified among ROSS's lateral/axial/torsional modes.
ross_campbell_seconds
    Wall time of ``Rotor.run_campbell`` (median over repetitions, warm-up and
    ROSS's per-rotor ``run_modal`` cache excluded) and its result.
build_ross_rub_model, ross_rub_seconds_per_revolution
    ROSS's own rubbing fault model (``Rotor.run_rubbing``) at midspan and its
    wall time per simulated revolution, with the midspan orbit.
quartic_reference_frequencies
    VALIDATION AID ONLY: closed-form whirl frequencies of the simply supported
    Timoshenko rotor, used to check that the ROSS model is the intended one.

Notes on ROSS 2.3.0 behaviour that matter here (see benchmarks/README.md):

* ROSS shaft elements have 6 DOF per node (x, y, z, alpha, beta, theta), so its
  modal output mixes bending, axial and torsional modes.  With translational
  supports only, axial and torsional rigid-body modes exist; ROSS filters
  eigenvalues with ``|lambda| <= 0.1`` so they do not appear, but the first
  torsional (~3.9 kHz) and axial (~6.5 kHz) elastic modes fall between the
  bending modes of the seed rotor.  Bending modes are selected with
  ``Shape.mode_type == "Lateral"``.
* ROSS's own whirl label (``Shape.whirl``) is "Mixed" whenever any node orbit
  (including the nearly motionless support nodes or a node of the mode shape)
  has the "wrong" sign, so it is unreliable for modes 2 and 3.  We classify the
  whirl from the whole eigenvector instead: with nodal complex amplitudes X, Y
  of an eigenvalue ``i*w`` (w > 0), the forward (co-rotating with the spin,
  x -> y) circular component is ``sum |X + iY|^2`` and the backward one is
  ``sum |X - iY|^2``.
* ``Rotor.run_modal`` is memoised per rotor instance (methodtools lru_cache);
  timings clear that cache before each repetition.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import statistics
import time
import warnings

import numpy as np

__all__ = [
    "DEFAULT_SUPPORT_STIFFNESS",
    "SEED_ROTOR",
    "build_ross_rub_model",
    "build_ross_shaft",
    "cowper_shear_coefficient_solid",
    "quartic_reference_frequencies",
    "ross_bending_frequencies",
    "ross_campbell_seconds",
    "ross_rub_seconds_per_revolution",
    "ross_version",
]

#: Seed rotor of the benchmarks (SI units): uniform solid aluminium shaft.
SEED_ROTOR = {
    "length": 0.4,
    "diameter": 0.1,
    "youngs_modulus": 71e9,
    "shear_modulus": 26.2e9,
    "density": 2660.0,
}

#: Translational stiffness (N/m) of the end "bearings" emulating pinned supports.
#: 1e13 / 1e14 / 1e15 / 1e16 change the 3rd bending frequency (40 elements) by
#: 3.5e-5 / 3.5e-6 / 3.5e-7 relative, so 1e15 is converged to < 1e-6.
DEFAULT_SUPPORT_STIFFNESS = 1e15


def ross_version() -> str:
    """Installed ROSS version (imports ROSS)."""
    rs = _import_ross()
    return getattr(rs, "__version__", "unknown")


def _import_ross():
    """Import ROSS quietly.

    ROSS 2.3 imports ``ccp``, whose CoolProp/REFPROP probe prints a screenful of
    "could not load REFPROP" text from native code on import; it is harmless, so
    file descriptors 1 and 2 are muted while importing.
    """
    import sys

    if "ross" in sys.modules:
        return sys.modules["ross"]
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import ross as rs
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (*saved, devnull):
            os.close(fd)
    return rs


@contextlib.contextmanager
def _quiet():
    """Silence ROSS's prints ("Running direct method") and its warnings."""
    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


# ---------------------------------------------------------------------------
# Validation aid: closed-form simply supported Timoshenko rotor
# ---------------------------------------------------------------------------


def cowper_shear_coefficient_solid(youngs_modulus: float, shear_modulus: float) -> float:
    """Cowper's shear coefficient of a solid circle, kappa = 6(1+nu)/(7+6nu).

    nu = E/(2G) - 1, which is also what ROSS's ``Material`` derives from E and G_s.
    """
    nu = youngs_modulus / (2.0 * shear_modulus) - 1.0
    return 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)


def quartic_reference_frequencies(
    length,
    diameter,
    youngs_modulus,
    shear_modulus,
    density,
    speed_rad_s,
    n_modes=3,
    shear_coefficient=None,
):
    """VALIDATION AID ONLY -- not a rubrotor implementation.

    Whirl frequencies of mode n = 1..n_modes of the uniform, simply supported,
    solid Timoshenko rotor: the four real roots w (rad/s, w > 0 forward, w < 0
    backward) of

        (rhoA w^2 - kGA k^2)(rhoI w^2 - Omega rho Ip w - EI k^2 - kGA) - (kGA k)^2 = 0

    with k = n pi / L.  Returns a dict of arrays in Hz: ``forward_hz``,
    ``backward_hz`` (bending branch, |w| ascending) and ``shear_forward_hz``,
    ``shear_backward_hz`` (the high shear branch).
    """
    if shear_coefficient is None:
        shear_coefficient = cowper_shear_coefficient_solid(youngs_modulus, shear_modulus)
    area = math.pi * diameter**2 / 4.0
    inertia = math.pi * diameter**4 / 64.0
    polar = 2.0 * inertia
    kga = shear_coefficient * shear_modulus * area
    ei = youngs_modulus * inertia
    out = {
        k: np.empty(n_modes)
        for k in ("forward_hz", "backward_hz", "shear_forward_hz", "shear_backward_hz")
    }
    for i, n in enumerate(range(1, n_modes + 1)):
        k = n * math.pi / length
        p1 = np.polynomial.Polynomial([-kga * k**2, 0.0, density * area])
        p2 = np.polynomial.Polynomial(
            [-ei * k**2 - kga, -speed_rad_s * density * polar, density * inertia]
        )
        roots = (p1 * p2 - (kga * k) ** 2).roots()
        roots = np.sort(roots.real[np.abs(roots.imag) <= 1e-9 * np.abs(roots).max()])
        if roots.size != 4:
            raise RuntimeError(f"expected 4 real roots for n={n}, got {roots}")
        pos, neg = roots[roots > 0], -roots[roots < 0]
        out["forward_hz"][i], out["shear_forward_hz"][i] = np.sort(pos) / (2 * math.pi)
        out["backward_hz"][i], out["shear_backward_hz"][i] = np.sort(neg) / (2 * math.pi)
    return out


# ---------------------------------------------------------------------------
# ROSS model of the seed shaft
# ---------------------------------------------------------------------------


def _ross_material(rs, youngs_modulus, shear_modulus, density):
    # Exactly E and G_s given; ROSS derives Poisson = E/(2 G_s) - 1 from them and
    # uses it in Cowper's kappa.
    return rs.Material(name="rubrotor_seed", rho=density, E=youngs_modulus, G_s=shear_modulus)


def build_ross_shaft(
    length,
    diameter,
    youngs_modulus,
    shear_modulus,
    density,
    n_elements=40,
    support_stiffness=DEFAULT_SUPPORT_STIFFNESS,
    *,
    alpha=0.0,
    beta=0.0,
    gyroscopic=True,
):
    """Uniform solid simply supported Timoshenko shaft as a ``ross.Rotor``.

    ``n_elements`` equal Timoshenko ``ShaftElement`` s (shear effects, rotary
    inertia and gyroscopic terms on, Cowper shear coefficient); "pinned" ends are
    ``BearingElement`` s at the two end nodes with ``kxx = kyy =
    support_stiffness`` (N/m), no cross-coupling, no damping, no axial stiffness
    and no rotational stiffness (ROSS bearings have none).  ``alpha`` (1/s) and
    ``beta`` (s) are ROSS's element proportional damping, C_e = alpha M_e +
    beta K_e (shaft elements only).  SI units throughout.
    """
    rs = _import_ross()
    material = _ross_material(rs, youngs_modulus, shear_modulus, density)
    le = length / n_elements
    with _quiet():
        shaft = [
            rs.ShaftElement(
                L=le,
                idl=0.0,
                odl=diameter,
                material=material,
                shear_effects=True,
                rotary_inertia=True,
                gyroscopic=gyroscopic,
                shear_method_calc="cowper",
                alpha=alpha,
                beta=beta,
            )
            for _ in range(n_elements)
        ]
        bearings = [
            rs.BearingElement(n=0, kxx=support_stiffness, cxx=0.0),
            rs.BearingElement(n=n_elements, kxx=support_stiffness, cxx=0.0),
        ]
        return rs.Rotor(shaft_elements=shaft, bearing_elements=bearings)


def _whirl_forward_fraction(shape_vector, number_dof):
    """Forward share of the lateral motion of one eigenvector (0..1)."""
    x = shape_vector[0::number_dof]
    y = shape_vector[1::number_dof]
    fwd = np.sum(np.abs(x + 1j * y) ** 2)
    bwd = np.sum(np.abs(x - 1j * y) ** 2)
    return float(fwd / (fwd + bwd))


def _lateral_modes(rotor, speed_rad_s, n_lateral):
    """(freq_hz, forward_fraction, mode_index) of the lowest lateral modes."""
    num_modes = 2 * (n_lateral + 6)
    while True:
        with _quiet():
            modal = rotor.run_modal(speed=speed_rad_s, num_modes=num_modes)
        picked = []
        for j, shape in enumerate(modal.shapes):
            if shape.mode_type != "Lateral":
                continue
            picked.append(
                (
                    modal.wd[j] / (2 * math.pi),
                    _whirl_forward_fraction(modal.modes[:, j], modal.number_dof),
                    j,
                )
            )
        if len(picked) >= n_lateral or num_modes >= rotor.ndof:
            break
        num_modes *= 2
    if len(picked) < n_lateral:
        raise RuntimeError(f"ROSS returned only {len(picked)} lateral modes")
    picked.sort(key=lambda p: p[0])
    return picked[:n_lateral], modal


def ross_bending_frequencies(rotor, speed_rad_s, n_modes=3):
    """First ``n_modes`` bending whirl frequencies of a ROSS rotor at a speed.

    Runs ``rotor.run_modal(speed)``, keeps ROSS's "Lateral" modes (dropping its
    axial and torsional ones), sorts them by damped frequency and takes the lowest
    ``2 n_modes``.  For a simply supported isotropic shaft these are the backward
    and forward whirl of each bending order n (B_n <= F_n < B_{n+1} on the seed
    rotor over the benchmark speed range); within each consecutive pair the mode
    with the larger forward circular component (see module notes) is forward.
    At zero speed the pair is degenerate and the split is arbitrary but the two
    frequencies coincide.

    Returns a dict with arrays ``forward_hz`` and ``backward_hz`` (Hz, length
    n_modes), ``forward_fraction`` (n_modes x 2: fraction of forward whirl of the
    forward and backward mode, ~1 and ~0 when spinning) and ``ross_whirl``
    (ROSS's own labels, for information).
    """
    picked, modal = _lateral_modes(rotor, speed_rad_s, 2 * n_modes)
    whirl = modal.whirl_direction()
    fwd = np.empty(n_modes)
    bwd = np.empty(n_modes)
    frac = np.empty((n_modes, 2))
    labels = []
    for i in range(n_modes):
        a, b = picked[2 * i], picked[2 * i + 1]
        f, bk = (a, b) if a[1] > b[1] else (b, a)
        if speed_rad_s != 0 and not (f[1] > 0.5 > bk[1]):
            warnings.warn(
                f"bending pair {i + 1} at {speed_rad_s} rad/s is not a clean "
                f"forward/backward pair (forward fractions {f[1]:.3f}, {bk[1]:.3f})",
                RuntimeWarning,
                stacklevel=2,
            )
        fwd[i], bwd[i] = f[0], bk[0]
        frac[i] = f[1], bk[1]
        labels.append((str(whirl[f[2]]), str(whirl[bk[2]])))
    return {
        "forward_hz": fwd,
        "backward_hz": bwd,
        "forward_fraction": frac,
        "ross_whirl": labels,
        "speed_rad_s": float(speed_rad_s),
    }


def _campbell_frequency_count(rotor, speeds, n_modes):
    """How many ROSS Campbell frequencies cover the first n bending pairs.

    ROSS's Campbell keeps the lowest ``frequencies`` modes of all types; on the
    seed rotor torsional/axial modes sit between the bending ones, so 6 (the
    ROSS default) is not enough for 3 bending pairs.  We count, at the highest
    speed, the rank of the last of the first 2 n_modes lateral modes.
    """
    picked, _ = _lateral_modes(rotor, float(np.max(speeds)), 2 * n_modes)
    needed = max(p[2] for p in picked) + 1
    picked0, _ = _lateral_modes(rotor, float(np.min(speeds)), 2 * n_modes)
    return max(needed, max(p[2] for p in picked0) + 1)


def ross_campbell_seconds(rotor, speeds, repeats=3, n_modes=3, frequencies=None):
    """Wall time of ROSS's ``rotor.run_campbell(speeds)``.

    ``frequencies`` (number of modes ROSS tracks) defaults to the smallest count
    that contains the first ``n_modes`` bending pairs (8 for the seed rotor up to 12000 rad/s).
    One warm-up call on 3 speeds is excluded; before every call the per-rotor
    ``run_modal`` cache is cleared so each repetition does the full work.

    Returns ``(median_seconds, campbell_result, info)`` where ``info`` has all
    repetition times, ``frequencies`` and the number of speeds.
    """
    speeds = np.asarray(speeds, dtype=float)
    if frequencies is None:
        frequencies = _campbell_frequency_count(rotor, speeds, n_modes)
    with _quiet():
        rotor.run_modal.cache_clear()
        rotor.run_campbell(speeds[:3].copy(), frequencies=frequencies)  # warm-up
    times = []
    result = None
    for _ in range(repeats):
        rotor.run_modal.cache_clear()
        with _quiet():
            t0 = time.perf_counter()
            result = rotor.run_campbell(speeds, frequencies=frequencies)
            times.append(time.perf_counter() - t0)
    rotor.run_modal.cache_clear()
    info = {"times_s": times, "frequencies": frequencies, "n_speeds": int(speeds.size)}
    return statistics.median(times), result, info


# ---------------------------------------------------------------------------
# Rub-impact with ROSS's rubbing fault
# ---------------------------------------------------------------------------


def _rayleigh_for_two_modes(zeta, w1, w2):
    """alpha (1/s), beta (s) giving damping ratio zeta at w1 and w2 (rad/s)."""
    alpha = 2.0 * zeta * w1 * w2 / (w1 + w2)
    beta = 2.0 * zeta / (w1 + w2)
    return alpha, beta


def build_ross_rub_model(
    length=SEED_ROTOR["length"],
    diameter=SEED_ROTOR["diameter"],
    youngs_modulus=SEED_ROTOR["youngs_modulus"],
    shear_modulus=SEED_ROTOR["shear_modulus"],
    density=SEED_ROTOR["density"],
    n_elements=20,
    clearance=20e-6,
    contact_stiffness=1e8,
    contact_damping=0.0,
    friction=0.1,
    unbalance_magnitude=1e-4,
    unbalance_phase=0.0,
    damping_ratio=0.02,
    support_stiffness=DEFAULT_SUPPORT_STIFFNESS,
    contact_node=None,
):
    """Seed shaft with ROSS's rubbing fault at midspan (a description, not run).

    Returns a dict with the ROSS ``rotor`` and the keyword arguments of
    ``rotor.run_rubbing`` except ``speed`` and ``t``.  SI units: clearance (m,
    radial), contact_stiffness (N/m, linear penalty), contact_damping (N s/m),
    friction (Coulomb coefficient), unbalance_magnitude (kg m) applied at the
    contact node (midspan by default, ``n_elements`` must be even).

    Structural damping: ROSS has no modal damping for shaft elements, so Rayleigh
    element damping C = alpha M + beta K is used with ``damping_ratio`` at the
    first and third bending frequencies (closed-form values at rest); modes in
    between have slightly less, modes above more.

    ROSS's rubbing force (ross/faults/rubbing.py, 2.3.0) acts on the *left node*
    of shaft element ``n``, so ``n = contact_node`` puts it at that node.  With
    radial displacement r = |(x, y)| >= clearance:
      normal  F_k = -k (r - clearance) (x, y)/r           (linear penalty)
      damping F_c = -c (xdot, ydot)                       (whole velocity, not
                                                           only its radial part)
      friction F_f = mu * (|F_k + F_c|_x, |F_k + F_c|_y) with signs (-, +) if
                 v = xdot cos(phi) - ydot sin(phi) + Omega R > 0, (+, -) if < 0
    i.e. the friction force is built component-wise in the fixed x/y axes rather
    than tangentially to the contact; with torque=False no torque is applied.
    The contact force is evaluated once per time step from the state at the start
    of the step (explicit), while the linear part is implicit Newmark
    (gamma=1/2, beta=1/4).
    """
    if contact_node is None:
        if n_elements % 2:
            raise ValueError("n_elements must be even for a midspan contact node")
        contact_node = n_elements // 2
    ref = quartic_reference_frequencies(
        length, diameter, youngs_modulus, shear_modulus, density, 0.0, n_modes=3
    )
    w1, w3 = 2 * math.pi * ref["forward_hz"][0], 2 * math.pi * ref["forward_hz"][2]
    alpha, beta = _rayleigh_for_two_modes(damping_ratio, w1, w3) if damping_ratio else (0, 0)
    rotor = build_ross_shaft(
        length,
        diameter,
        youngs_modulus,
        shear_modulus,
        density,
        n_elements=n_elements,
        support_stiffness=support_stiffness,
        alpha=alpha,
        beta=beta,
    )
    rub_kwargs = {
        "n": contact_node,
        "distance": clearance,
        "contact_stiffness": contact_stiffness,
        "contact_damping": contact_damping,
        "friction_coeff": friction,
        "node": [contact_node],
        "unbalance_magnitude": [unbalance_magnitude],
        "unbalance_phase": [unbalance_phase],
        "torque": False,
    }
    return {
        "rotor": rotor,
        "rub_kwargs": rub_kwargs,
        "contact_node": contact_node,
        "alpha": alpha,
        "beta": beta,
    }


def ross_rub_seconds_per_revolution(
    model=None,
    speed_rad_s=11614.0,
    n_revolutions=10,
    steps_per_revolution=256,
    repeats=1,
    model_reduction=None,
    **model_kwargs,
):
    """Time ROSS's ``rotor.run_rubbing`` and return seconds per revolution.

    ``model`` comes from :func:`build_ross_rub_model` (built from
    ``model_kwargs`` if omitted).  The rotor starts at rest and spins at constant
    ``speed_rad_s`` (default 11614 rad/s = 1.5 x the first forward critical of the
    seed rotor) for ``n_revolutions``, with a fixed step of one
    ``steps_per_revolution``-th of a revolution (ROSS's Newmark uses exactly the
    time array it is given; it has no adaptive step).  ``model_reduction`` is
    passed to ROSS (e.g. ``{"num_modes": 12}`` for its pseudo-modal method);
    ``None`` is ROSS's direct method on the full FE model.

    Returns a dict: ``seconds_per_revolution`` (median over ``repeats``),
    ``times_s``, ``n_steps`` (time steps integrated), ``dt``, ``t`` (s), and the
    midspan orbit ``x``, ``y`` (m) plus ``contact_force`` (n_steps, 2) (N, x/y
    force ROSS applied at the contact node).
    """
    if model is None:
        model = build_ross_rub_model(**model_kwargs)
    elif model_kwargs:
        raise TypeError("give either model or model keyword arguments, not both")
    _import_ross()
    from ross.faults.rubbing import Rubbing

    rotor = model["rotor"]
    period = 2 * math.pi / speed_rad_s
    n_steps = int(n_revolutions * steps_per_revolution)
    dt = period / steps_per_revolution
    t = np.arange(n_steps + 1) * dt
    extra = {} if model_reduction is None else {"model_reduction": dict(model_reduction)}

    kw = dict(model["rub_kwargs"])
    fault_args = {
        k: kw.pop(k)
        for k in (
            "n",
            "distance",
            "contact_stiffness",
            "contact_damping",
            "friction_coeff",
            "torque",
        )
    }
    run_args = {
        "node": kw.pop("node"),
        "unb_magnitude": kw.pop("unbalance_magnitude"),
        "unb_phase": kw.pop("unbalance_phase"),
    }

    def run_once(t_arr):
        # Exactly what ``Rotor.run_rubbing`` does (Rubbing(...).run(...)), but
        # keeping the fault object so its applied contact forces can be read.
        with _quiet():
            fault = Rubbing(rotor, **fault_args)
            out = fault.run(
                speed=speed_rad_s, t=t_arr, **run_args, **{k: dict(v) for k, v in extra.items()}
            )
        return fault, out

    run_once(t[:8].copy())  # warm-up: numba compilation of ROSS's Newmark kernel
    times = []
    res = fault = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        fault, res = run_once(t)
        times.append(time.perf_counter() - t0)
    node = model["contact_node"]
    ndof = rotor.number_dof
    x = np.asarray(res.yout[:, ndof * node + 0])
    y = np.asarray(res.yout[:, ndof * node + 1])
    med = statistics.median(times)
    return {
        "seconds_per_revolution": med / n_revolutions,
        "times_s": times,
        "n_steps": n_steps,
        "dt": dt,
        "n_revolutions": n_revolutions,
        "steps_per_revolution": steps_per_revolution,
        "t": t,
        "x": x,
        "y": y,
        "contact_force": np.asarray(fault.forces[[ndof * node, ndof * node + 1], :]).T,
        "ndof": int(rotor.ndof),
        "model_reduction": model_reduction,
    }
