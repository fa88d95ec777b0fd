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

import json
import math
import zlib

import numpy as np

from rubrotor.errors import ScenarioError

__all__ = [
    "physical_state", "snapshot", "resume", "fingerprint", "check_fingerprint", "finite_state", "flatten",
    "unflatten", "layout", "checksum", "read_restart",
]  # fmt: skip

CONTACT_KEYS = ("position", "clearance", "radius", "offset_y", "offset_z", "law", "stiffness",
                "damping", "friction", "friction_sign", "friction_regularization", "stator")
"""The contact parameters a restart file must share with the scenario (those a file keeps)."""

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
        offsets (m), law, stiffness, damping, friction, friction sign and regularization (the
        contact force's parameters) and stator (kg, N/m, N s/m, or ``None``).
    """
    sm = system.matrices(speed)
    contacts = []
    for s in stations:
        c = s.contact
        st = s.stator
        contacts.append({
            "position": c.position, "clearance": c.clearance, "radius": c.radius,
            "offset_y": s.offset_y, "offset_z": s.offset_z, "law": c.law,
            "stiffness": c.stiffness, "damping": c.damping, "friction": c.friction,
            "friction_sign": c.friction_sign,
            "friction_regularization": c.friction_regularization,
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
    if a is None or b is None or isinstance(a, str) or isinstance(b, str):
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
        for key in CONTACT_KEYS:
            if key not in a or key not in b:  # a file written before the key was kept
                continue
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
        "checksum": 1,
    }


def checksum(vec: np.ndarray) -> float:
    """CRC-32 of the little-endian float64 bytes of ``vec`` (an integer below 2^32, exact as a
    float): the last component of :func:`flatten`'s vector, so that a changed byte is seen."""
    return float(zlib.crc32(np.asarray(vec, "<f8").tobytes()))


def flatten(snap: dict) -> np.ndarray:
    """A snapshot (without ``time_s``) as one float vector: ``x``, the stator states, ``F``,
    ``Fp``, ``dprev``, ``hp``, ``level`` (SI; the layout is :func:`layout`), then the
    :func:`checksum` of those."""
    parts = [snap["x"]] + [u for u in snap["stators"] if u is not None]
    parts += [snap["F"], snap["Fp"], snap["dprev"], [snap["hp"], snap["level"]]]
    vec = np.concatenate([np.asarray(p, float) for p in parts])
    return np.append(vec, checksum(vec))


def intact(vec: np.ndarray, lay: dict) -> bool:
    """Whether ``vec`` matches its :func:`checksum` (always, for a layout without one: files
    written before it was added)."""
    if not lay.get("checksum"):
        return True
    vec = np.asarray(vec, float)
    return checksum(vec[:-1]) == vec[-1]


def unflatten(vec: np.ndarray, lay: dict, time_s: float) -> dict:
    """Inverse of :func:`flatten` for the layout ``lay``; ``time_s`` (s) added.

    Raises
    ------
    ValueError
        When the vector does not have the layout's length (:func:`intact` checks its checksum).
    """
    vec = np.asarray(vec, float)
    try:
        size = lay["x"] + sum(lay["stators"]) + lay["F"] + lay["Fp"] + lay["dprev"] + 2
    except (KeyError, TypeError):
        raise ValueError("its restart_vector layout attribute is incomplete") from None
    if vec.shape != (size + lay.get("checksum", 0),):
        raise ValueError(f"its restart_vector has {vec.size} components, its layout {size}")
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


def read_restart(ds, path: str, scenario, system, speed: float):
    """State ``x`` (``[q, q']`` on the free DOFs), start time (s) and restart state of an open
    results file, checked against the scenario's model.

    Every way a file can fail to be a restart of this model is refused naming
    ``initial.path``, or the contact key that differs (:func:`check_fingerprint`): not written
    by the general engine, missing attributes, stopped before its first chunk, another speed,
    another model (a file without a fingerprint: its stored scenario's rotor and contact tables
    compared with this one's), a negative or non-finite restart time, a restart vector whose
    checksum does not match, a state that is not finite.
    """
    at = ds.attrs

    def refuse(allowed):
        raise ScenarioError("initial.path", path, allowed)

    has_rows = "restart_vector" in ds and ds.sizes.get("checkpoint", 0) > 0
    if "restart_vector" not in ds and "final_state" not in at:
        refuse("a results file written by the general engine (this one has no restart state)")
    if "restart_vector" in ds and not has_rows and "final_state" not in at:
        refuse("a results file with a restart state: this one stopped before its first chunk "
               "completed (nothing to continue from; run it again)")
    if "speed_end_rad_s" in at:
        refuse("a constant-speed results file")
    try:
        stored_speed = float(at["speed_rad_s"])
    except (KeyError, TypeError, ValueError):
        refuse("a results file with its speed_rad_s attribute (this one has none: damaged?)")
    if not math.isclose(stored_speed, speed, rel_tol=1e-12):
        refuse(f"a results file run at {speed:g} rad/s")
    stations = scenario.engine.stations
    if "model_fingerprint" in at:
        try:
            stored = json.loads(at["model_fingerprint"])
        except ValueError:
            refuse("a results file whose model_fingerprint attribute is readable JSON")
        check_fingerprint(stored, fingerprint(system, stations, speed), path)
    else:
        _same_tables(at.get("scenario", ""), getattr(scenario, "source", ""), path)
    if has_rows:
        x, end, snap = _last_row(ds, path)
    else:  # a file of an earlier version: the rotor state only
        if at.get("status") != "complete":
            refuse("a complete results file (this one has no restart state)")
        try:
            x = np.array(json.loads(at["final_state"]), float)
            end = float(at.get("end_time_s", float(at.get("start_time_s", 0.0))
                               + float(ds["time"].values[-1])))  # fmt: skip
        except (KeyError, ValueError, IndexError, TypeError):
            refuse("a results file whose final_state and time are readable")
        snap = None
        if not np.all(np.isfinite(x)):
            refuse("a results file whose kept state is finite")
    if not (math.isfinite(end) and end >= 0):
        refuse(f"a results file whose restart time is finite and >= 0 s (it has {end!r})")
    n = system.n_dof
    if x.shape != (2 * n,):
        refuse(f"a results file of this rotor ({2 * n} states)")
    return x, end, snap


def _last_row(ds, path: str):
    """``x``, time (s) and snapshot of the last restart row, its layout and checksum checked."""
    try:
        lay = json.loads(ds["restart_vector"].attrs["layout"])
        t_last = float(ds["restart_time"].values[-1])
        snap = unflatten(ds["restart_vector"].values[-1], lay, t_last)
    except (KeyError, ValueError, TypeError) as exc:
        why = exc if isinstance(exc, ValueError) else f"no {exc} attribute"
        raise ScenarioError("initial.path", path, f"a results file with an intact restart "
                            f"state ({why})") from None  # fmt: skip
    if not finite_state(snap):
        raise ScenarioError("initial.path", path, "a results file whose kept state is finite")
    if not intact(ds["restart_vector"].values[-1], lay):
        raise ScenarioError("initial.path", path, "a results file with an intact restart state "
                            "(its restart_vector does not match its checksum: changed after "
                            "it was written)")  # fmt: skip
    return np.array(snap["x"], float), t_last, snap


ROTOR_TABLES = ("materials", "shaft", "section", "disk", "bearing", "support", "contact",
                "stator")  # fmt: skip
"""Tables of a scenario that make its model (compared for files without a fingerprint)."""


def _same_tables(stored: str, now: str, path: str) -> None:
    """Refuse a file without a fingerprint whose stored scenario's rotor or contact tables
    differ from the scenario's (or that stores no scenario to compare)."""
    import tomllib

    try:
        a, b = tomllib.loads(stored), tomllib.loads(now)
    except (tomllib.TOMLDecodeError, TypeError):
        a, b = None, None
    if not stored or a is None:
        raise ScenarioError("initial.path", path, "a results file that says which model it "
                            "belongs to (this one has neither a model_fingerprint nor its "
                            "scenario)")  # fmt: skip
    for key in ROTOR_TABLES:
        if a.get(key) != b.get(key):
            raise ScenarioError("initial.path", path, f"a results file of this model: its "
                                f"scenario's [{key}] differs from this one's (the state belongs "
                                "to that model)")  # fmt: skip
