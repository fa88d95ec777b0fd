"""Restart states of the general engine: what a results file keeps to continue a run exactly.

A run of :func:`rubrotor.engine.driver.simulate_general` takes a :func:`snapshot` of its kernel
state after every completed chunk. A snapshot is physical, not modal (the modal coordinates
depend on how the eigenvectors were normalised, which may differ between machines or
reductions): the rotor state ``x = [q, q']`` on the free DOFs (m, rad; m/s, rad/s), every
flexible stator's ``[u_y, u_z, u_y', u_z']`` (m, m/s), the contact forces of the last two steps
``F``, ``F_prev`` (N), the last radial gaps (m) and the last step (s). :func:`resume` maps it back
onto any plant of the same model, so a continued run takes the same steps as an uninterrupted
one (its unbalance phases advanced by ``Omega t0``; agreement to rounding, see the tests).

A results file stores the snapshot as the variables ``restart_time`` (s) and ``restart_vector``
(:func:`flatten`; its ``layout`` attribute, :func:`layout`, splits it) along a ``checkpoint``
dimension: one row in memory, one per chunk in a streamed file, whose last row is the state
at the end of its last completed chunk.

:func:`fingerprint` sums up the model a state belongs to (DOF count, three fixed bilinear forms
of ``M``, ``C + Omega G + C_s`` and ``K + K_s`` at the run's speed, the contact stations and
their stators); :func:`check_fingerprint` refuses a restart onto another model, naming what
differs.
"""

from __future__ import annotations

import math

import numpy as np

from rubrotor.errors import ScenarioError

__all__ = [
    "physical_state", "snapshot", "resume", "fingerprint", "check_fingerprint", "finite_state", "flatten",
    "unflatten", "layout",
]  # fmt: skip

_REL = 1e-9
"""Relative tolerance of the fingerprint's matrix sums (assembly round-off is ~1e-16)."""


def physical_state(plant, y: np.ndarray, F: np.ndarray, z: complex) -> np.ndarray:
    """Total rotor state ``[q, q']`` (m, rad; m/s, rad/s) on the free DOFs from the modal
    state ``y``, the contact forces ``F`` (N) and the unbalance phasor ``z``."""
    yr = y[: plant.n_rotor]
    fq = plant.Bmat @ F
    Q = plant.q_unbalance * z
    q = np.real(plant.rotor.Vq @ yr) + plant.rotor.Rq @ fq + plant.q_static + Q.real
    qd = np.real(plant.rotor.Vq @ (plant.rotor.lam * yr)) + plant.rotor.Rv @ fq
    return np.concatenate([q, qd + np.real(1j * plant.speed * Q)])


def snapshot(plant, kernel: dict, phasor: complex, time_s: float) -> dict:
    """The physical state of a run (see the module docstring), JSON-able.

    Parameters
    ----------
    plant : rubrotor.engine.driver.Plant
        The plant the kernel state lives on.
    kernel : dict
        Kernel state arrays ``y, F, Fp, dprev, hp`` (and ``tst`` for adaptive steps).
    phasor : complex
        Unbalance phasor ``e^{i Omega t}`` at the state's time.
    time_s : float
        Time of the state (s), from the run's start.

    Returns
    -------
    dict
        ``time_s`` (s), ``x`` (rotor ``[q, q']``), ``stators`` (per contact ``[u_y, u_z, u_y',
        u_z']`` (m, m/s) or ``None`` for a rigid one), ``F``, ``Fp`` (N), ``dprev`` (m), ``hp`` (s)
        and ``level`` (sub-step level of an adaptive run).
    """
    y = kernel["y"]
    o = plant.outputs
    stators = []
    for i, flex in enumerate(o.flex):
        rows = slice(2 * i, 2 * i + 2)
        u = np.concatenate([np.real(o.Sd[rows] @ y), np.real(o.Sv[rows] @ y)]) if flex else None
        stators.append(None if u is None else u.tolist())
    tst = kernel.get("tst")
    hp = float(tst[1]) if tst is not None else float(kernel["hp"][0])
    return {
        "time_s": float(time_s),
        "x": physical_state(plant, y, kernel["F"], phasor).tolist(),
        "stators": stators,
        "F": kernel["F"].tolist(),
        "Fp": kernel["Fp"].tolist(),
        "dprev": kernel["dprev"].tolist(),
        "hp": hp,
        "level": int(tst[2]) if tst is not None else 0,
    }


def resume(plant, kernel: dict, snap: dict, stations) -> None:
    """Set the kernel state from ``snap`` (a :func:`snapshot` of the same model), in place.

    The plant's unbalance phases must already be advanced to the snapshot's time (the new run
    starts at ``t = 0`` with the phasor 1).

    Parameters
    ----------
    plant : rubrotor.engine.driver.Plant
    kernel : dict
        Kernel state arrays, overwritten.
    snap : dict
        The state (SI, see :func:`snapshot`).
    stations : sequence of rubrotor.engine.parts.RubStation
        The plant's contact stations (for their stators' modes).
    """
    from rubrotor.engine.reduce import reduce_matrices

    F = np.asarray(snap["F"], float)
    fq = plant.Bmat @ F
    x = np.asarray(snap["x"], float)
    n = plant.q_static.size
    Q = plant.q_unbalance
    shift = x - np.concatenate([
        plant.q_static + Q.real + plant.rotor.Rq @ fq,
        np.real(1j * plant.speed * Q) + plant.rotor.Rv @ fq,
    ])  # fmt: skip
    y = kernel["y"]
    y[: plant.n_rotor] = plant.rotor.project(shift)
    assert shift.size == 2 * n
    o = plant.n_rotor
    for i, st in enumerate(stations):
        if st.stator is None:
            continue
        sm = reduce_matrices(*st.stator.matrices())
        y[o : o + sm.size] = sm.project(np.asarray(snap["stators"][i], float))
        o += sm.size
    kernel["F"][:] = F
    kernel["Fp"][:] = snap["Fp"]
    kernel["dprev"][:] = snap["dprev"]
    if "tst" in kernel:
        kernel["tst"][1] = snap["hp"]
        kernel["tst"][2] = snap["level"]
    else:
        kernel["hp"][0] = snap["hp"]


def _sums(a: np.ndarray) -> list[float]:
    """Three fixed bilinear forms ``u^T A v`` of a square matrix (a sketch of its entries)."""
    i = np.arange(a.shape[0])
    u = (np.cos(1.3 * i + 0.7), np.sin(0.9 * i + 0.3), np.cos(2.1 * i + 1.1))
    v = (np.sin(1.7 * i + 0.2), np.cos(0.5 * i + 0.9), np.sin(2.9 * i + 0.4))
    return [float(uu @ a @ vv) for uu, vv in zip(u, v, strict=True)]


def fingerprint(system, stations, speed: float) -> dict:
    """What a restart state belongs to (see the module docstring), JSON-able.

    Parameters
    ----------
    system : rubrotor.rotors.linear.LinearSystem
    stations : sequence of rubrotor.engine.parts.RubStation
    speed : float
        Spin speed (rad/s).

    Returns
    -------
    dict
        ``n_dof``; ``mass``, ``damping``, ``stiffness``: three sums each (kg, N s/m, N/m
        weighted); ``contacts``: per station its position (m), clearance (m), radius (m),
        offsets (m), law and stator (kg, N/m, N s/m, or ``None``).
    """
    sm = system.matrices(speed)
    contacts = []
    for s in stations:
        c = s.contact
        st = s.stator
        contacts.append({
            "position": c.position, "clearance": c.clearance, "radius": c.radius,
            "offset_y": s.offset_y, "offset_z": s.offset_z, "law": c.law,
            "stator": None if st is None else [st.mass_y, st.mass_z, st.stiffness_y,
                                               st.stiffness_z, st.damping_y, st.damping_z],
        })  # fmt: skip
    return {
        "n_dof": int(sm.M.shape[0]),
        "mass": _sums(sm.M),
        "damping": _sums(sm.damping),
        "stiffness": _sums(sm.K),
        "contacts": contacts,
    }


def _close(a, b) -> bool:
    if a is None or b is None or isinstance(a, str):
        return a == b
    a, b = np.atleast_1d(np.asarray(a, float)), np.atleast_1d(np.asarray(b, float))
    if a.shape != b.shape:
        return False
    scale = max(float(np.max(np.abs(a), initial=0.0)), float(np.max(np.abs(b), initial=0.0)))
    return bool(np.all(np.abs(a - b) <= _REL * scale))


def check_fingerprint(stored: dict, now: dict, path: str) -> None:
    """Refuse a restart whose file was written for another model, naming what differs.

    Parameters
    ----------
    stored, now : dict
        :func:`fingerprint` of the file's model and of the scenario's.
    path : str
        The results file (for the message).

    Raises
    ------
    ScenarioError
        Naming the contact key (``contact[i].position`` ...) or the rotor matrix that differs.
    """
    cs, cn = stored["contacts"], now["contacts"]
    if len(cs) != len(cn):
        raise ScenarioError("contact", f"{len(cn)} stations",
                            f"{len(cs)} contact stations, as in the restart file initial.path = {path!r}")  # fmt: skip
    for i, (a, b) in enumerate(zip(cs, cn, strict=True)):
        for key in ("position", "clearance", "radius", "offset_y", "offset_z", "law", "stator"):
            if not _close(a[key], b[key]):
                name = (
                    f"contact[{i + 1}].{key}" if key != "stator" else f"contact[{i + 1}].stator_*"
                )
                raise ScenarioError(name, b[key],
                                    f"{a[key]}, as in the restart file initial.path = "
                                    f"{path!r} (the state belongs to that model)")  # fmt: skip
    if stored["n_dof"] != now["n_dof"]:
        raise ScenarioError("initial.path", path,
                            f"a results file of this rotor: it has {stored['n_dof']} DOFs, the "
                            f"scenario's rotor {now['n_dof']} (mesh, probes or supports "
                            "changed)")  # fmt: skip
    for key in ("mass", "damping", "stiffness"):
        if not _close(stored[key], now[key]):
            raise ScenarioError("initial.path", path,
                                f"a results file of this rotor: its {key} matrix differs from "
                                "the scenario's (sections, disks, bearings or speed changed)")  # fmt: skip


def finite_state(snap: dict) -> bool:
    """Whether every number of a snapshot is finite."""
    vals = [snap["x"], snap["F"], snap["Fp"], snap["dprev"], [snap["hp"]]]
    vals += [u for u in snap["stators"] if u is not None]
    return all(math.isfinite(v) for vs in vals for v in vs)


def layout(snap: dict) -> dict:
    """Lengths of the parts of :func:`flatten`'s vector (stored with it)."""
    return {
        "x": len(snap["x"]),
        "stators": [0 if u is None else len(u) for u in snap["stators"]],
        "F": len(snap["F"]),
        "Fp": len(snap["Fp"]),
        "dprev": len(snap["dprev"]),
    }


def flatten(snap: dict) -> np.ndarray:
    """A snapshot (without ``time_s``) as one float vector: ``x``, the stator states, ``F``,
    ``Fp``, ``dprev``, ``hp``, ``level`` (SI; the layout is :func:`layout`)."""
    parts = [snap["x"]] + [u for u in snap["stators"] if u is not None]
    parts += [snap["F"], snap["Fp"], snap["dprev"], [snap["hp"], snap["level"]]]
    return np.concatenate([np.asarray(p, float) for p in parts])


def unflatten(vec: np.ndarray, lay: dict, time_s: float) -> dict:
    """Inverse of :func:`flatten` for the layout ``lay``; ``time_s`` (s) added."""
    vec = np.asarray(vec, float)
    pos = 0

    def take(k: int) -> list:
        nonlocal pos
        pos += k
        return vec[pos - k : pos].tolist()

    x = take(lay["x"])
    stators = [take(k) if k else None for k in lay["stators"]]
    snap = {"time_s": float(time_s), "x": x, "stators": stators, "F": take(lay["F"]),
            "Fp": take(lay["Fp"]), "dprev": take(lay["dprev"])}  # fmt: skip
    hp, level = take(2)
    return {**snap, "hp": hp, "level": int(level)}
