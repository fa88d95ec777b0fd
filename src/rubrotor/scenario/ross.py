"""A ROSS rotor as scenario tables: ``rubrotor import-ross`` and :meth:`rubrotor.Scenario.from_ross`.

The rotor comes as a ROSS ``Rotor`` object (ROSS 2.3 or 3.x installed) or as the file ROSS's
``Rotor.save`` wrote (read without ROSS, :func:`rubrotor.rotors.ross_model.read_ross_file`).
Each ROSS element becomes a scenario table that every verb reads:

* each shaft element: a ``[[section]]`` of one element (``elements = 1``) with its length,
  diameters and material; a second element on the same nodes (ROSS's way to add an impeller
  hub's or a sleeve's mass) a sleeve ``[[section]]`` with ``position``; ROSS's element damping
  ``alpha``, ``beta`` as ``mass_damping``, ``stiffness_damping``; the materials as
  ``[materials.NAME]`` with ``shear_modulus`` (ROSS's ``G_s``); the beam switches
  (``shear_effects``, ``rotary_inertia``, ``gyroscopic``, ``shear_method_calc``) as
  ``[rotor] theory, gyroscopic, shear_coefficient`` (they must be the same for every element);
* disks: ``[[disk]]`` of mass, ``Id`` and ``Ip`` at their node (several on one node summed);
* bearings and seals: ``[[bearing]]`` with their tables (``speeds`` or ``frequencies``),
  ``interpolation`` as ROSS's, ``extrapolation = "linear"`` (ROSS 3.x's end slope), bearing
  mass ``myy, myz, mzz``; linked to a housing: ``link``; a housing's support: ``on``;
* point masses: ``[[point_mass]]`` (at the station of the shaft node their housing joins);
* axes: ROSS's ``x, y`` (lateral, ``y`` up in its static analysis) are rubrotor's ``y, z``, its
  axial ``z`` rubrotor's ``x``; gravity as ROSS's ``run_static`` applies it, along its ``-y``:
  ``[gravity] z = -9.8065`` (m/s^2), so the rotor sags along rubrotor's ``-z``.

Refused, naming the element: tapered shaft elements, beam switches that differ between
elements, rotor-wide damping (``Rotor(alpha=, beta=)``, modal damping), a speed-dependent or
skew bearing mass, motors and elements coupling the lateral DOFs with the axial or torsional
ones. The scenario's linear system equals :func:`rubrotor.rotors.ross.from_ross` of the same
rotor (same nodes; element matrices equal to rounding, see tests/test_ross_import.py).
"""

from __future__ import annotations

import numpy as np

from rubrotor.errors import InputError
from rubrotor.rotors.ross_model import RossModel, read_ross_file, ross_model

__all__ = ["ross_scenario_dict", "ross_mapping", "ROSS_GRAVITY"]

ROSS_GRAVITY = 9.8065
"""Gravity (m/s^2) of ROSS's ``run_static``, along ROSS's ``-y``: the imported scenario's
``[gravity] z = -9.8065`` (ROSS's ``x, y`` are rubrotor's ``y, z``)."""

_THEORY = {(True, True): "timoshenko", (False, True): "rayleigh", (False, False): "euler-bernoulli"}
_OURS = {"kyy": (0, 0), "kyz": (0, 1), "kzy": (1, 0), "kzz": (1, 1)}


def _uniform(model: RossModel, key: str):
    values = {e[key] for e in model.shafts}
    if len(values) > 1:
        raise InputError(
            f"ShaftElement.{key}",
            sorted(map(str, values)),
            "the same value for every shaft element (one rotor-wide setting)",
        )
    return values.pop()


def _rotor_table(model: RossModel) -> dict:
    switches = (_uniform(model, "shear_effects"), _uniform(model, "rotary_inertia"))
    if switches not in _THEORY:
        raise InputError(
            "ShaftElement.shear_effects",
            switches,
            "shear effects only together with rotary inertia (Timoshenko)",
        )
    shear = _uniform(model, "shear_method_calc")
    if shear not in ("cowper", "hutchinson"):
        raise InputError("ShaftElement.shear_method_calc", shear, '"cowper" or "hutchinson"')
    out = {"theory": _THEORY[switches], "gyroscopic": bool(_uniform(model, "gyroscopic")),
           "shear_coefficient": shear}  # fmt: skip
    alpha, beta = model.damping
    if alpha:
        out["mass_damping"] = alpha
    if beta:
        out["stiffness_damping"] = beta
    return out


def _materials(model: RossModel) -> tuple[dict, dict]:
    """``[materials.NAME]`` tables and the name of each ``(E, G_s, rho)``."""
    tables, names = {}, {}
    for e in model.shafts:
        m = e["material"]
        key = (m["E"], m["G_s"], m["rho"])
        if key in names:
            continue
        name, i = m["name"] or "material", 2
        while name in tables:
            name, i = f"{m['name']}_{i}", i + 1
        tables[name] = {"youngs_modulus": m["E"], "shear_modulus": m["G_s"], "density": m["rho"]}
        names[key] = name
    return tables, names


def _sections(model: RossModel, nodes: np.ndarray, names: dict) -> list:
    out, seen = [], {}
    for e in model.shafts:
        tag = e.get("tag", "")
        if e["idl"] != e["idr"] or e["odl"] != e["odr"]:
            raise InputError(
                f"ShaftElement {tag!r}",
                (e["odl"], e["odr"], e["idl"], e["idr"]),
                "a cylindrical element (tapered elements are not mapped)",
            )
        n = int(e["n"])
        m = e["material"]
        sec = {"length": float(e["L"]), "diameter": float(e["odl"]),
               "bore_diameter": float(e["idl"]), "material": names[(m["E"], m["G_s"], m["rho"])],
               "elements": 1}  # fmt: skip
        if n in seen:
            if float(e["L"]) != seen[n]:
                raise InputError(
                    f"ShaftElement {tag!r}.L",
                    e["L"],
                    f"{seen[n]} m, the length of the element on the same nodes",
                )
            sec["position"] = float(nodes[n])
        seen.setdefault(n, float(e["L"]))
        for ours, theirs in (("mass_damping", "alpha"), ("stiffness_damping", "beta")):
            if float(e.get(theirs) or 0.0) and not any(model.damping):  # ROSS: global wins
                sec[ours] = float(e[theirs])
        out.append((n, "position" in sec, sec))
    out.sort(key=lambda t: (t[1], t[0]))  # the shaft left to right, then the sleeves
    return [sec for _, _, sec in out]


def _disks(model: RossModel, nodes: np.ndarray) -> list:
    by_node: dict = {}
    for d in model.disks:
        n = int(d["n"])
        acc = by_node.setdefault(
            n,
            {
                "position": float(nodes[n]),
                "mass": 0.0,
                "polar_inertia": 0.0,
                "diametral_inertia": 0.0,
                "names": [],
            },
        )
        acc["mass"] += float(d["m"])
        acc["polar_inertia"] += float(d["Ip"])
        acc["diametral_inertia"] += float(d["Id"])
        acc["names"].append(str(d.get("tag", "")))
    out = []
    for n in sorted(by_node):
        acc = by_node[n]
        acc["name"] = " + ".join(t for t in acc.pop("names") if t)
        out.append(acc)
    return out


def _housings(model: RossModel, nodes: np.ndarray) -> dict:
    """``{ROSS node: (name, station)}`` of the point masses (station: the shaft node their
    housing chain joins)."""
    links = {s.n_link: s.n for s in model.supports if s.n_link is not None}
    out = {}
    for p in model.point_masses:
        n, seen = int(p["n"]), set()
        while n >= len(nodes):
            if n in seen or n not in links:
                raise InputError(
                    f"PointMass {p['tag']!r}",
                    p["n"],
                    "a point mass joined to the shaft by a bearing's n_link",
                )
            seen.add(n)
            n = links[n]
        out[int(p["n"])] = (str(p["tag"]), float(nodes[n]))
    return out


def _bearing(s, nodes: np.ndarray, housings: dict) -> dict:
    b: dict = {"name": s.name}
    if s.seal:
        b["kind"] = "seal"
    if s.n < len(nodes):
        b["position"] = float(nodes[s.n])
    elif s.n in housings and s.n_link is None:
        b["on"], b["position"] = housings[s.n]
    else:
        raise InputError(f"bearing {s.name!r}.n", s.n, "a shaft node or a point mass's node")
    if s.n_link is not None:
        if s.n_link not in housings or s.n >= len(nodes):
            raise InputError(
                f"bearing {s.name!r}.n_link",
                s.n_link,
                "the node of a point mass, from a shaft node",
            )
        b["link"] = housings[s.n_link][0]
    for prefix, table in (("k", s.k), ("c", s.c)):
        for ours, (i, j) in _OURS.items():
            col = [float(v) for v in table[:, i, j]]
            b[prefix + ours[1:]] = col if s.axis is not None else col[0]
    if s.axis is not None:
        b["speeds" if s.kind == "speed" else "frequencies"] = [float(v) for v in s.axis]
        b["interpolation"] = "pchip" if s.interpolation == "pchip" and s.axis.size > 2 else "linear"
        b["extrapolation"] = "linear"
    for ours, (i, j) in (("myy", (0, 0)), ("myz", (0, 1)), ("mzz", (1, 1))):
        if s.mass[i, j]:
            b[ours] = float(s.mass[i, j])
    return b


def ross_scenario_dict(model: RossModel, speed: float = 0.0, name: str = "ross_rotor") -> dict:
    """The scenario mapping (the parsed TOML) of a ROSS rotor.

    Parameters
    ----------
    model : RossModel
        From :func:`rubrotor.rotors.ross_model.read_ross_file` or
        :func:`~rubrotor.rotors.ross_model.ross_model`.
    speed : float
        ``[speed] rad_per_s`` (rad/s) of the scenario.
    name : str
        ``[meta] name``.

    Returns
    -------
    dict
        ``meta``, ``materials``, ``section``, ``disk``, ``bearing``, ``point_mass``, ``rotor``,
        ``speed`` and ``gravity`` tables.
    """
    nodes = model.nodes_pos
    materials, names = _materials(model)
    housings = _housings(model, nodes)
    out = {
        "meta": {"name": name, "description": f"Imported from ROSS {model.version}".strip()},
        "materials": materials,
        "section": _sections(model, nodes, names),
    }
    disks = _disks(model, nodes)
    if disks:
        out["disk"] = disks
    out["bearing"] = [_bearing(s, nodes, housings) for s in model.supports]
    if housings:
        masses = {int(p["n"]): p for p in model.point_masses}
        out["point_mass"] = [{"name": nm, "position": x, "mass_y": float(masses[n]["mx"]),
                              "mass_z": float(masses[n]["my"])}
                             for n, (nm, x) in housings.items()]  # fmt: skip
    out["rotor"] = _rotor_table(model)
    out["speed"] = {"rad_per_s": float(speed)}
    # ROSS's x, y are our y, z; its run_static pulls along its -y with g = 9.8065 m/s^2
    out["gravity"] = {"y": 0.0, "z": -ROSS_GRAVITY}
    return out


def ross_mapping(rotor, speed: float = 0.0, name: str | None = None, speeds=None) -> dict:
    """The scenario mapping of a ROSS rotor (object or saved file); what
    :meth:`rubrotor.Scenario.from_ross` builds its scenario of.

    Parameters
    ----------
    rotor : ross.Rotor or str or Path
        A ROSS rotor (ROSS installed), or the ``.toml``/``.json`` file its ``Rotor.save``
        wrote (read without ROSS).
    speed : float
        Spin speed (rad/s) of the scenario's ``[speed]``.
    name : str, optional
        ``[meta] name`` (default the file stem, or ``"ross_rotor"``).
    speeds : array_like, optional
        With a ROSS object: speeds (rad/s) at which to read its speed tables from ROSS's own
        interpolant (ROSS 2.3's smoothing splines; see :func:`rubrotor.rotors.ross.from_ross`).

    Returns
    -------
    dict
    """
    from pathlib import Path

    if isinstance(rotor, str | Path):
        model = read_ross_file(rotor)
        name = name or Path(rotor).stem
    else:
        model = ross_model(rotor, speeds)
    return ross_scenario_dict(model, speed, name or "ross_rotor")
