"""A general rotor: stepped shaft sections, rigid disks and bearings, built into finite elements.

Description
-----------
:class:`Material`, :class:`Section`, :class:`Disk` and :class:`Bearing` describe the machine;
:class:`Rotor` holds them with the beam theory and the mesh settings, validates the whole
(positions on the rotor, no two disks or two supports at one station, enough supports) and
builds a :class:`rubrotor.rotors.linear.LinearSystem` with :meth:`Rotor.linear_system`.

Assembly
--------
Nodes sit at every section boundary, disk, bearing and extra station (probes, contacts,
forces); each section is then cut into elements no longer than its target length (its
``elements`` count, else ``max_element_length``, else the default of
:meth:`Rotor.default_element_length`). Shaft elements are :func:`rubrotor.rotors.elements.beam_element`; a disk adds
``diag(m, m, Id, Id)`` to the mass and ``Ip [[0, 1], [-1, 0]]`` to the gyroscopic matrix on
``[psi_v, psi_w]`` of its node; a bearing becomes a :class:`rubrotor.rotors.linear.Support` on the
deflections of its node; a ``pinned`` bearing fixes them (exact constraint).

The beam ``theory`` applies to the shaft elements; disks always keep their rotatory inertia,
and ``gyroscopic = False`` removes the gyroscopic moments of shaft and disks alike.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from rubrotor.errors import InputError
from rubrotor.rotors.elements import beam_element
from rubrotor.rotors.linear import (
    EXTRAPOLATIONS,
    INTERPOLATIONS,
    LinearSystem,
    NodalBasis,
    Support,
)
from rubrotor.rotors.scales import check_scales, rotor_scales
from rubrotor.rotors.shaft import (
    SHEAR_COEFFICIENTS,
    THEORIES,
    _finite_positive,
    shear_coefficient_value,
)

__all__ = [
    "Material",
    "Section",
    "Disk",
    "Bearing",
    "PointMass",
    "Rotor",
    "BEARING_KINDS",
    "COEFFICIENTS",
    "DEFAULT_TOLERANCE",
    "DEFAULT_WAVENUMBER",
    "MESH_MATRICES",
]

BEARING_KINDS = ("bearing", "pinned", "seal")
COEFFICIENTS = ("kyy", "kyz", "kzy", "kzz", "cyy", "cyz", "czy", "czz")
DEFAULT_TOLERANCE = 1e-4
"""Relative frequency error the default mesh aims at for the first five frequencies."""
DEFAULT_WAVENUMBER = 11.0
"""``k L`` of the highest bending wave the default mesh resolves (third free-free mode)."""
MESH_MATRICES = 8
"""Dense ``n x n`` float64 matrices a mesh of ``n`` DOFs is budgeted for (see
:meth:`rubrotor.Rotor.check_mesh_size`): measured, the peak memory of assembly plus
:func:`rubrotor.damped_modes` grows as 6.3 such matrices (seal_rub.toml meshed to 2032 and 4024
DOFs: 599 and 1208 MB peak RSS)."""

_TOL = 1e-9  # m: two stations closer than this are one node


def _number(name: str, value, unit: str) -> float:
    """A finite number (any sign) or an InputError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise InputError(name, value, f"a number ({unit})")
    if not math.isfinite(float(value)):
        raise InputError(name, value, f"a finite number ({unit})")
    return float(value)


def _rename(exc: InputError, prefix: str) -> InputError:
    """The same error with its field put under ``prefix`` (``"section[2]"``)."""
    tail = exc.field.rpartition(".")[2]
    return InputError(f"{prefix}.{tail}", exc.value, exc.allowed)


@dataclass(frozen=True)
class Material:
    """An isotropic elastic material.

    Parameters
    ----------
    name : str
        Its name (the key of ``[materials.NAME]`` in a scenario).
    youngs_modulus : float
        ``E`` (Pa).
    density : float
        ``rho`` (kg/m^3).
    shear_modulus : float, optional
        ``G`` (Pa). Give exactly one of ``shear_modulus`` and ``poisson_ratio``.
    poisson_ratio : float, optional
        ``nu`` in (-1, 0.5); then ``G = E / (2 (1 + nu))``.
    """

    name: str
    youngs_modulus: float
    density: float
    shear_modulus: float | None = None
    poisson_ratio: float | None = None

    def __post_init__(self):
        pre = f"materials.{self.name}"
        _finite_positive(f"{pre}.youngs_modulus", self.youngs_modulus, "Pa")
        _finite_positive(f"{pre}.density", self.density, "kg/m^3")
        if (self.shear_modulus is None) == (self.poisson_ratio is None):
            raise InputError(
                f"{pre}.shear_modulus / {pre}.poisson_ratio",
                (self.shear_modulus, self.poisson_ratio),
                "exactly one of the two (the other follows from E)",
            )
        if self.shear_modulus is not None:
            _finite_positive(f"{pre}.shear_modulus", self.shear_modulus, "Pa")
            if not -1 < self.nu < 0.5:
                raise InputError(
                    f"{pre}.shear_modulus",
                    self.shear_modulus,
                    f"a value with E/(2G) - 1 in (-1, 0.5); it gives nu = {self.nu:.4g}",
                )
        else:
            nu = _number(f"{pre}.poisson_ratio", self.poisson_ratio, "dimensionless")
            if not -1 < nu < 0.5:
                raise InputError(f"{pre}.poisson_ratio", nu, "a number in (-1, 0.5)")

    @property
    def G(self) -> float:  # noqa: N802 - the symbol of the field
        """Shear modulus ``G`` (Pa)."""
        if self.shear_modulus is not None:
            return float(self.shear_modulus)
        return self.youngs_modulus / (2 * (1 + self.poisson_ratio))

    @property
    def nu(self) -> float:
        """Poisson's ratio (dimensionless)."""
        if self.poisson_ratio is not None:
            return float(self.poisson_ratio)
        return self.youngs_modulus / (2 * self.shear_modulus) - 1


@dataclass(frozen=True)
class Section:
    """A uniform hollow circular shaft section.

    Parameters
    ----------
    length : float
        Axial length (m).
    diameter : float
        Outer diameter (m).
    material : Material
        Its material.
    bore_diameter : float
        Inner diameter (m), 0 for a solid section.
    elements : int, optional
        Number of elements (at least this many when stations split the section);
        default from the rotor's mesh rule.
    position : float, optional
        Left end (m) of a *sleeve*: a section laid over the shaft from ``position`` to
        ``position + length`` (an impeller hub, a shrunk-on sleeve; ROSS models them as a
        second shaft element on the same nodes). Its element matrices add to those of the
        shaft sections there; it does not extend the rotor. ``None`` (default): a shaft
        section, end to end with the others.
    mass_damping : float
        ``alpha`` (1/s) of the section's proportional damping ``C_e = alpha M_e + beta K_e``
        (ROSS's ``ShaftElement(alpha=...)``); 0 by default.
    stiffness_damping : float
        ``beta`` (s) of the same; 0 by default.
    """

    length: float
    diameter: float
    material: Material
    bore_diameter: float = 0.0
    elements: int | None = None
    position: float | None = None
    mass_damping: float = 0.0
    stiffness_damping: float = 0.0

    def __post_init__(self):
        _finite_positive("section.length", self.length, "m")
        _finite_positive("section.diameter", self.diameter, "m")
        bore = _finite_positive("section.bore_diameter", self.bore_diameter, "m", allow_zero=True)
        if bore >= self.diameter:
            raise InputError(
                "section.bore_diameter", self.bore_diameter, f"< diameter = {self.diameter} m"
            )
        if not isinstance(self.material, Material):
            raise InputError("section.material", self.material, "a Material")
        n = self.elements
        if n is not None and (isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 10000):
            raise InputError("section.elements", n, "an integer in 1..10000")
        if self.position is not None:
            _number("section.position", self.position, "m")
        for name, unit in (("mass_damping", "1/s"), ("stiffness_damping", "s")):
            v = _number(f"section.{name}", getattr(self, name), unit)
            if v < 0:
                raise InputError(f"section.{name}", v, f"a number >= 0 ({unit})")


@dataclass(frozen=True)
class Disk:
    """A rigid disk (impeller, wheel, coupling) at one axial station.

    Parameters
    ----------
    position : float
        Axial position (m from the left end of the rotor).
    mass : float
        Mass (kg), ``>= 0``.
    polar_inertia : float
        Polar moment of inertia ``Ip`` (kg m^2), ``>= 0``.
    diametral_inertia : float
        Diametral (transverse) moment of inertia ``Id`` (kg m^2), ``>= 0``.
    width : float
        Axial width (m), only used to reject overlapping disks; 0 for a lumped disk.
    name : str
        Label.
    """

    position: float
    mass: float
    polar_inertia: float = 0.0
    diametral_inertia: float = 0.0
    width: float = 0.0
    name: str = ""

    def __post_init__(self):
        _number("disk.position", self.position, "m")
        _finite_positive("disk.mass", self.mass, "kg", allow_zero=True)
        _finite_positive("disk.polar_inertia", self.polar_inertia, "kg m^2", allow_zero=True)
        _finite_positive(
            "disk.diametral_inertia", self.diametral_inertia, "kg m^2", allow_zero=True
        )
        _finite_positive("disk.width", self.width, "m", allow_zero=True)

    @classmethod
    def from_geometry(
        cls,
        position: float,
        outer_diameter: float,
        width: float,
        material: Material,
        bore_diameter: float = 0.0,
        name: str = "",
    ) -> Disk:
        """A uniform annular disk: ``m = rho pi (D^2 - d^2) b / 4``, ``Ip = m (D^2 + d^2) / 8``,
        ``Id = Ip / 2 + m b^2 / 12`` (diameters ``D``, ``d`` and width ``b`` in m).

        Examples
        --------
        >>> steel = Material("steel", 211e9, 7810, poisson_ratio=0.3)
        >>> d = Disk.from_geometry(0.5, outer_diameter=0.3, width=0.05, material=steel)
        >>> round(d.mass, 3), round(d.polar_inertia, 5)
        (27.603, 0.31053)
        """
        outer = _finite_positive("disk.outer_diameter", outer_diameter, "m")
        b = _finite_positive("disk.width", width, "m")
        bore = _finite_positive("disk.bore_diameter", bore_diameter, "m", allow_zero=True)
        if bore >= outer:
            raise InputError("disk.bore_diameter", bore_diameter, f"< outer_diameter = {outer} m")
        m = material.density * math.pi * (outer**2 - bore**2) / 4 * b
        ip = m * (outer**2 + bore**2) / 8
        return cls(position, m, ip, ip / 2 + m * b**2 / 12, width=b, name=name)


@dataclass(frozen=True)
class Bearing:
    """A bearing or seal: 2x2 stiffness and damping at one station, or a pinned support.

    Parameters
    ----------
    position : float
        Axial position (m from the left end).
    kyy, kyz, kzy, kzz : float or sequence of float
        Stiffness (N/m): force along ``y`` per ``w`` is ``-kyz w``, etc. Direct terms ``>= 0``.
    cyy, cyz, czy, czz : float or sequence of float
        Damping (N s/m). Direct terms ``>= 0``.
    speeds : sequence of float, optional
        Spin speeds (rad/s, increasing) at which sequence-valued coefficients are tabulated;
        coefficients are interpolated linearly between them and held outside.
    kind : {"bearing", "pinned", "seal"}
        ``"pinned"``: both deflections are exactly zero (no coefficients allowed). ``"seal"``:
        coefficients like a bearing's, but no static load in API 617's check (ROSS's
        ``SealElement``).
    name : str
        Label.
    fail_time : float, optional
        Time (s) from which the bearing no longer holds the rotor (a magnetic bearing losing
        levitation); honoured by free-spin runs (:mod:`rubrotor.engine.spin`).
    frequencies : sequence of float, optional
        Whirl (excitation) frequencies (rad/s, increasing) at which the sequence-valued
        coefficients are tabulated instead of ``speeds`` (a magnetic bearing's controller, a
        squeeze-film damper: ROSS's ``frequency=`` tables). Direct coefficients of such a table
        may be negative (an AMB's controller gives negative damping at low frequency).
    interpolation : {"linear", "pchip"}
        Between table points (see :class:`rubrotor.rotors.linear.Support`).
    extrapolation : {"hold", "linear"}
        Outside the table (see :class:`rubrotor.rotors.linear.Support`).
    myy, myz, mzz : float
        Bearing mass (kg), a constant symmetric 2x2 added to the mass matrix on the bearing's
        deflections (``[[myy, myz], [myz, mzz]]``, relative ones when linked).
    link : str, optional
        Name of a :class:`~rubrotor.rotors.fe.PointMass` (a bearing housing): the bearing acts between the shaft
        and that mass instead of the ground.
    on : str, optional
        Name of a :class:`~rubrotor.rotors.fe.PointMass`: the bearing acts between that mass and the ground (the
        housing's support); ``position`` is then the mass's station.
    """

    position: float
    kyy: float | Sequence[float] = 0.0
    kyz: float | Sequence[float] = 0.0
    kzy: float | Sequence[float] = 0.0
    kzz: float | Sequence[float] = 0.0
    cyy: float | Sequence[float] = 0.0
    cyz: float | Sequence[float] = 0.0
    czy: float | Sequence[float] = 0.0
    czz: float | Sequence[float] = 0.0
    speeds: Sequence[float] | None = None
    kind: str = "bearing"
    name: str = ""
    fail_time: float | None = None
    frequencies: Sequence[float] | None = None
    interpolation: str = "linear"
    extrapolation: str = "hold"
    myy: float = 0.0
    myz: float = 0.0
    mzz: float = 0.0
    link: str | None = None
    on: str | None = None
    _table: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        _number("bearing.position", self.position, "m")
        if self.fail_time is not None:
            _finite_positive("bearing.fail_time", self.fail_time, "s", allow_zero=True)
            if self.kind == "pinned":
                raise InputError("bearing.fail_time", self.fail_time, 'none with kind = "pinned"')
        if self.kind not in BEARING_KINDS:
            raise InputError(
                "bearing.kind", self.kind, " or ".join(f'"{k}"' for k in BEARING_KINDS)
            )
        if self.speeds is not None and self.frequencies is not None:
            raise InputError(
                "bearing.frequencies", self.frequencies, "none with speeds (one table axis)"
            )
        if self.interpolation not in INTERPOLATIONS:
            raise InputError("bearing.interpolation", self.interpolation, " or ".join(
                f'"{i}"' for i in INTERPOLATIONS))  # fmt: skip
        if self.extrapolation not in EXTRAPOLATIONS:
            raise InputError("bearing.extrapolation", self.extrapolation, " or ".join(
                f'"{i}"' for i in EXTRAPOLATIONS))  # fmt: skip
        for nm in ("myy", "myz", "mzz"):
            v = _number(f"bearing.{nm}", getattr(self, nm), "kg")
            if nm != "myz" and v < 0:
                raise InputError(f"bearing.{nm}", v, "a mass >= 0 (kg)")
        if self.link is not None and self.on is not None:
            raise InputError("bearing.link", self.link, "none with on (a bearing joins two bodies)")
        speeds = self._speeds()
        table = {c: self._column(c, speeds) for c in COEFFICIENTS}
        for c in COEFFICIENTS:  # store tables as tuples: comparable and hashable
            if np.ndim(getattr(self, c)) == 1:
                object.__setattr__(self, c, tuple(float(v) for v in table[c]))
        if speeds is not None and self.frequencies is None:
            object.__setattr__(self, "speeds", tuple(float(v) for v in speeds))
        if self.kind == "pinned":
            for c, col in table.items():
                if np.any(col != 0):
                    raise InputError(f"bearing.{c}", getattr(self, c), 'none with kind = "pinned"')
        k = np.stack([[table["kyy"], table["kyz"]], [table["kzy"], table["kzz"]]]).transpose(
            2, 0, 1
        )
        c = np.stack([[table["cyy"], table["cyz"]], [table["czy"], table["czz"]]]).transpose(
            2, 0, 1
        )
        object.__setattr__(self, "_table", (speeds, k, c))

    @property
    def axis(self) -> str:
        """``"frequency"`` for a table against whirl frequency, else ``"speed"``."""
        return "frequency" if self.frequencies is not None else "speed"

    def _speeds(self) -> np.ndarray | None:
        key = "frequencies" if self.frequencies is not None else "speeds"
        given = getattr(self, key)
        if given is None:
            return None
        if isinstance(given, str | bytes) or np.ndim(given) != 1:
            raise InputError(f"bearing.{key}", given, f"a list of {key} (rad/s)")
        s = np.array([_number(f"bearing.{key}", v, "rad/s") for v in given])
        if len(s) < 1 or np.any(s < 0) or np.any(np.diff(s) <= 0):
            raise InputError(
                f"bearing.{key}", given, f"a non-empty list of increasing {key} >= 0 (rad/s)"
            )
        if self.frequencies is not None:
            object.__setattr__(self, "frequencies", tuple(float(v) for v in s))
        return s

    def _column(self, name: str, speeds: np.ndarray | None) -> np.ndarray:
        value = getattr(self, name)
        unit = "N/m" if name[0] == "k" else "N s/m"
        n = 1 if speeds is None else len(speeds)
        if not isinstance(value, str) and np.ndim(value) == 1:
            if speeds is None or len(value) != n:
                raise InputError(
                    f"bearing.{name}", value, f"a number, or a list of {n} values with speeds"
                )
            col = np.array([_number(f"bearing.{name}", v, unit) for v in value])
        else:
            col = np.full(n, _number(f"bearing.{name}", value, unit))
        if name[1] == name[2] and self.frequencies is None and np.any(col < 0):
            raise InputError(f"bearing.{name}", value, f"values >= 0 ({unit})")
        return col

    @property
    def holds(self) -> bool:
        """True if it holds the rotor in both directions (pinned, or ``kyy, kzz > 0``)."""
        _, k, _ = self._table
        return self.kind == "pinned" or bool(np.all(k[:, 0, 0] > 0) and np.all(k[:, 1, 1] > 0))

    @property
    def mass_matrix(self) -> np.ndarray:
        """The bearing mass ``[[myy, myz], [myz, mzz]]`` (kg)."""
        return np.array([[self.myy, self.myz], [self.myz, self.mzz]], float)

    def support(self, node: int, name: str, dofs=None, link=None) -> Support:
        """This bearing as a :class:`rubrotor.rotors.linear.Support` on node ``node`` (or on
        the DOFs ``dofs``, linked to the DOFs ``link``)."""
        speeds, k, c = self._table
        return Support(
            dofs=tuple(dofs) if dofs is not None else (4 * node, 4 * node + 1),
            k=k,
            c=c,
            speeds=speeds,
            position=float(self.position),
            name=name,
            interpolation=self.interpolation,
            extrapolation=self.extrapolation,
            link=tuple(link) if link is not None else None,
            axis=self.axis,
            kind="seal" if self.kind == "seal" else "bearing",
        )


@dataclass(frozen=True)
class PointMass:
    """A lumped mass with its own two lateral DOFs (a bearing housing, a pedestal).

    It is joined to the rotor and the ground by bearings (``Bearing(link=name)`` between the
    shaft and it, ``Bearing(on=name)`` between it and the ground), as ROSS's ``PointMass``.

    Parameters
    ----------
    name : str
        Label the bearings refer to.
    position : float
        Axial station (m) it sits at (for labels and plots: it adds no shaft node).
    mass_y, mass_z : float
        Mass (kg) along ``y`` and ``z``.
    """

    name: str
    position: float
    mass_y: float
    mass_z: float

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise InputError("point_mass.name", self.name, "a non-empty label")
        _number("point_mass.position", self.position, "m")
        for nm in ("mass_y", "mass_z"):
            _finite_positive(f"point_mass.{nm}", getattr(self, nm), "kg", allow_zero=True)


@dataclass(frozen=True)
class Rotor:
    """A general rotor: shaft sections end to end, disks and bearings.

    Parameters
    ----------
    sections : sequence of Section
        From the left end (``x = 0``) to the right end, end to end.
    disks : sequence of Disk
        Rigid disks; positions in ``[0, L]``, two disks never at one station (nor overlapping
        when they have a width).
    bearings : sequence of Bearing
        Bearings, seals and pinned supports; positions in ``[0, L]``, one per station. At
        least two of them, at different stations, must hold the rotor (pinned, or
        ``kyy > 0`` and ``kzz > 0``): a rotor without supports is rejected.
    theory : {"timoshenko", "rayleigh", "euler-bernoulli"}
        Beam theory of the shaft elements.
    gyroscopic : bool
        Include gyroscopic moments (shaft and disks).
    shear_coefficient : {"cowper", "hutchinson", "seed"} or float
        See :func:`rubrotor.rotors.shaft.shear_coefficient_value` (per section: its bore ratio).
    max_element_length : float, optional
        Longest element (m) for sections without ``elements``; default
        :meth:`default_element_length` of each section.
    stations : sequence of float
        Extra node positions (m), e.g. probes.
    point_masses : sequence of PointMass
        Lumped masses with their own DOFs (bearing housings), joined by bearings with
        ``link`` / ``on``; their ``[v, w]`` DOFs follow the nodal ones, in this order.
    mass_damping, stiffness_damping : float
        Rotor-wide proportional damping ``C = alpha M + beta K`` (``alpha`` in 1/s, ``beta``
        in s) on the shaft, sleeves, disks and point masses (not the bearings), as ROSS's
        ``Rotor(alpha=, beta=)``; 0 by default.

    Sections with a ``position`` are sleeves laid over the shaft (see :class:`Section`); the
    shaft is the others, end to end.

    Examples
    --------
    >>> steel = Material("steel", 211e9, 7810, poisson_ratio=0.3)
    >>> rotor = Rotor([Section(1.0, 0.05, steel)],
    ...               bearings=[Bearing(0.0, kind="pinned"), Bearing(1.0, kind="pinned")])
    >>> system = rotor.linear_system()
    >>> len(rotor.nodes()), system.n_dof
    (53, 208)
    """

    sections: Sequence[Section]
    disks: Sequence[Disk] = ()
    bearings: Sequence[Bearing] = ()
    theory: str = "timoshenko"
    gyroscopic: bool = True
    shear_coefficient: str | float = "cowper"
    max_element_length: float | None = None
    stations: Sequence[float] = ()
    point_masses: Sequence[PointMass] = ()
    mass_damping: float = 0.0
    stiffness_damping: float = 0.0

    def __post_init__(self):
        for name, unit in (("mass_damping", "1/s"), ("stiffness_damping", "s")):
            if _number(f"rotor.{name}", getattr(self, name), unit) < 0:
                raise InputError(f"rotor.{name}", getattr(self, name), f"a number >= 0 ({unit})")
        for name in ("sections", "disks", "bearings", "stations", "point_masses"):
            object.__setattr__(self, name, tuple(getattr(self, name)))
        if not self.shaft_sections:
            raise InputError("section", (), "at least one shaft section (without position)")
        self._check_point_masses()
        for name, kind in (("sections", Section), ("disks", Disk)):
            for i, item in enumerate(getattr(self, name)):
                if not isinstance(item, kind):
                    raise InputError(f"{name[:-1]}[{i + 1}]", item, f"a {kind.__name__}")
        for i, item in enumerate(self.bearings):  # a Bearing or another support term
            if not all(hasattr(item, a) for a in ("support", "position", "kind", "holds")):
                raise InputError(f"bearing[{i + 1}]", item, "a Bearing or a support term "
                                 "(rubrotor.forces.supports)")  # fmt: skip
        if self.theory not in THEORIES:
            raise InputError("rotor.theory", self.theory, " or ".join(f'"{t}"' for t in THEORIES))
        if not isinstance(self.gyroscopic, bool):
            raise InputError("rotor.gyroscopic", self.gyroscopic, "true or false")
        coef = self.shear_coefficient
        if isinstance(coef, str) and coef not in SHEAR_COEFFICIENTS:
            allowed = " or ".join(f'"{c}"' for c in SHEAR_COEFFICIENTS) + " or a number > 0"
            raise InputError("rotor.shear_coefficient", coef, allowed)
        for sec in self.sections:
            self._kappa_of(sec)
        if self.max_element_length is not None:
            _finite_positive("rotor.max_element_length", self.max_element_length, "m")
        self._check_positions()
        self._check_supports()

    # ---- geometry --------------------------------------------------------------------------
    @property
    def shaft_sections(self) -> tuple[Section, ...]:
        """The sections end to end (without the sleeves)."""
        return tuple(s for s in self.sections if s.position is None)

    @property
    def sleeves(self) -> tuple[Section, ...]:
        """The sections laid over the shaft (with a ``position``)."""
        return tuple(s for s in self.sections if s.position is not None)

    @property
    def length(self) -> float:
        """Total length ``L`` (m)."""
        return float(self.boundaries[-1])

    @property
    def boundaries(self) -> np.ndarray:
        """Section boundaries (m), from 0 to ``L`` (shaft sections only)."""
        return np.concatenate([[0.0], np.cumsum([s.length for s in self.shaft_sections])])

    def _check_point_masses(self) -> None:
        names = [p.name for p in self.point_masses]
        for i, p in enumerate(self.point_masses):
            if not isinstance(p, PointMass):
                raise InputError(f"point_mass[{i + 1}]", p, "a PointMass")
            if names.index(p.name) != i:
                raise InputError(f"point_mass[{i + 1}].name", p.name, "a name not used before")
        for i, b in enumerate(self.bearings):
            for key in ("link", "on"):
                ref = getattr(b, key, None)
                if ref is not None and ref not in names:
                    raise InputError(f"bearing[{i + 1}].{key}", ref, "the name of a point_mass: "
                                     + (", ".join(names) or "none defined"))  # fmt: skip

    @property
    def mass(self) -> float:
        """Total mass of shaft and disks (kg)."""
        shaft = sum(
            s.material.density * math.pi * (s.diameter**2 - s.bore_diameter**2) / 4 * s.length
            for s in self.sections
        )
        return float(shaft + sum(d.mass for d in self.disks))

    def _kappa(self, i: int) -> float:
        return self._kappa_of(self.shaft_sections[i])

    def _kappa_of(self, s: Section) -> float:
        try:
            return shear_coefficient_value(
                self.shear_coefficient, s.material.nu, s.bore_diameter / s.diameter
            )
        except InputError as exc:
            raise InputError("rotor.shear_coefficient", exc.value, exc.allowed) from None

    def _check_positions(self):
        length = self.length
        shaft_bearings = tuple(b for b in self.bearings if b.on is None)
        groups = (("disk", self.disks), ("bearing", shaft_bearings))
        for kind, items in groups:
            for i, item in enumerate(items):
                if not -_TOL <= item.position <= length + _TOL:
                    raise InputError(
                        f"{kind}[{i + 1}].position", item.position, f"in [0, {length:g}] m"
                    )
            order = sorted(range(len(items)), key=lambda j: items[j].position)
            for a, b in zip(order, order[1:], strict=False):
                gap = items[b].position - items[a].position
                reach = (getattr(items[a], "width", 0) + getattr(items[b], "width", 0)) / 2
                if gap <= max(_TOL, reach - _TOL):
                    raise InputError(
                        f"{kind}[{b + 1}].position",
                        items[b].position,
                        f"a station apart from {kind}[{a + 1}] at {items[a].position:g} m "
                        f"(no two {kind}s overlap; merge them into one)",
                    )
        for i, sec in enumerate(self.sections):
            if sec.position is not None and not (
                -_TOL <= sec.position and sec.position + sec.length <= length + _TOL
            ):
                raise InputError(f"section[{i + 1}].position", sec.position,
                                 f"a sleeve inside [0, {length:g}] m")  # fmt: skip
        for x in self.stations:
            if not -_TOL <= _number("stations", x, "m") <= length + _TOL:
                raise InputError("stations", x, f"positions in [0, {length:g}] m")

    def _check_supports(self):
        held = {round(b.position / _TOL) for b in self.bearings if b.holds and b.on is None}
        if len(held) < 2:
            raise InputError(
                "bearing",
                len(self.bearings),
                'supports at two or more stations that hold the rotor (kind = "pinned", or '
                "kyy > 0 and kzz > 0); a rotor without supports has rigid-body modes",
            )

    # ---- mesh ------------------------------------------------------------------------------
    def default_element_length(self, index: int) -> float:
        """Default element length (m) of section ``index``, from a measured error model.

        The relative error of a bending frequency of wavenumber ``k`` on elements of length
        ``h`` is about ``(k h)^4 / 1440 + (k h)^2 s / 24`` with ``s = b / (1 + b)`` the shear
        share of the strain energy, ``b = (k r0)^2 delta`` (``r0`` radius of gyration,
        ``delta = E / (kappa G)``; second term for Timoshenko elements only, which converge as
        ``h^2`` once ``h`` is below the diameter; both constants fitted on pinned uniform
        shafts, see docs/model.md). The mesh keeps it below
        :data:`rubrotor.rotors.fe.DEFAULT_TOLERANCE` for the bending wave of frequency ``c (11/L)^2``, where
        ``c = r0 sqrt(E/rho)`` is the length-weighted mean over the sections; in section ``i``
        that wave has ``k = sqrt(omega / c_i)``.

        Parameters
        ----------
        index : int
            Section index (0 = leftmost).

        Returns
        -------
        float
            Element length (m).
        """

        def wave_constant(s: Section) -> float:
            r0 = math.sqrt(s.diameter**2 + s.bore_diameter**2) / 4
            return r0 * math.sqrt(s.material.youngs_modulus / s.material.density)

        shaft = self.shaft_sections
        s = shaft[index]
        mean_c = sum(wave_constant(t) * t.length for t in shaft) / self.length
        omega = mean_c * (DEFAULT_WAVENUMBER / self.length) ** 2
        k = math.sqrt(omega / wave_constant(s))
        a = 0.0
        if self.theory == "timoshenko":
            r0 = math.sqrt(s.diameter**2 + s.bore_diameter**2) / 4
            delta = s.material.youngs_modulus / (self._kappa(index) * s.material.G)
            b = (k * r0) ** 2 * delta
            a = b / (1 + b) / 24
        # x = (k h)^2 solves x^2 / 1440 + a x = tol
        x = 720 * (-a + math.sqrt(a * a + DEFAULT_TOLERANCE / 360))
        return math.sqrt(x) / k

    def nodes(self, stations: Sequence[float] = ()) -> np.ndarray:
        """Node positions (m): section boundaries, disks, bearings, stations, then the mesh.

        Parameters
        ----------
        stations : sequence of float
            Extra positions (m) that must be nodes (added to ``self.stations``).

        Returns
        -------
        ndarray
            Increasing positions (m), from 0 to ``L``.
        """
        self.check_mesh_size(len(stations))
        bounds = self.boundaries
        points = [*bounds, *(d.position for d in self.disks)]
        points += [b.position for b in self.bearings] + [*self.stations, *stations]
        points += [x for v in self.sleeves for x in (v.position, v.position + v.length)]
        for x in stations:
            if not -_TOL <= _number("stations", x, "m") <= self.length + _TOL:
                raise InputError("stations", x, f"positions in [0, {self.length:g}] m")
        points = np.clip(np.sort(np.asarray(points, float)), 0.0, self.length)
        keep = np.concatenate([[True], np.diff(points) > _TOL])
        points = points[keep]
        out = [0.0]
        shaft = self.shaft_sections
        for i, (s, a, b) in enumerate(zip(shaft, bounds[:-1], bounds[1:], strict=True)):
            if s.elements:
                h = s.length / s.elements
            else:
                h = self.max_element_length or self.default_element_length(i)
            inner = points[(points > a + _TOL) & (points < b - _TOL)]
            for x0, x1 in zip([a, *inner], [*inner, b], strict=True):
                n = max(1, math.ceil((x1 - x0) / h - 1e-9))
                out += list(np.linspace(x0, x1, n + 1)[1:])
        return np.array(out)

    def check_mesh_size(self, extra_nodes: int = 0) -> None:
        """Refuse, before meshing, a mesh whose dense matrices would not fit in memory.

        The element count is estimated per section (``elements``, else ``ceil(length / h)``)
        plus one per extra node. The finite-element system keeps four dense ``n x n`` matrices
        of float64 (``n = 4 (elements + 1)`` DOFs) and its analyses factor or diagonalise them
        (a reduction's dense eigenproblem, the damped modes' ``2n`` state space): the estimate
        is :data:`rubrotor.rotors.fe.MESH_MATRICES` such matrices, ``8 MESH_MATRICES n^2`` bytes, against 80 % of
        the memory available now.

        Parameters
        ----------
        extra_nodes : int
            Nodes added by stations (each may split an element).

        Raises
        ------
        InputError
            Naming the key that makes the finest part of the mesh (``section[i].elements`` or
            ``rotor.max_element_length``), its value, the element count and the memory.
        """
        from rubrotor._memory import available_memory

        total, worst, key, value = extra_nodes + len(self.disks) + len(self.bearings), -1, "", None
        for i, s in enumerate(self.shaft_sections):
            if s.elements:
                n, k, v = s.elements, f"section[{i + 1}].elements", s.elements
            elif self.max_element_length:
                n = math.ceil(s.length / self.max_element_length)
                k, v = "rotor.max_element_length", self.max_element_length
            else:
                n = math.ceil(s.length / self.default_element_length(i))
                k, v = f"section[{i + 1}].elements", None
            total += n
            if n > worst:
                worst, key, value = n, k, v
        dof = 4 * (total + 1)
        need, avail = 8.0 * MESH_MATRICES * dof**2, available_memory()
        if need > 0.8 * avail:
            fewer = "larger" if key == "rotor.max_element_length" else "fewer"
            why = ""
            if value is None:  # the default mesh: its element length follows the diameters
                i, s = max(enumerate(self.shaft_sections), key=lambda t: t[1].diameter)
                why = (f" (the default mesh refines with the diameters: the largest is "
                       f"section[{i + 1}].diameter = {s.diameter:g} m)")
            raise InputError(
                key, value, f"a mesh that fits in memory (about {total} elements, {dof} DOFs: "
                f"{need / 2**30:.3g} GiB of dense matrices, {avail / 2**30:.3g} GiB available); "
                f"give {fewer} {key.split('.')[-1]}{why}"
            )  # fmt: skip

    # ---- assembly --------------------------------------------------------------------------
    def _element(self, s: Section, h: float):
        """The beam element of section (or sleeve) ``s`` of length ``h`` (m)."""
        return beam_element(
            h,
            s.material.youngs_modulus,
            s.material.G,
            s.material.density,
            s.diameter,
            s.bore_diameter,
            self._kappa_of(s),
            self.theory,
            self.gyroscopic,
        )

    def _assemble_shaft(self, x: np.ndarray, n: int) -> tuple[np.ndarray, ...]:
        """``M, K, C, G`` (``n x n``) of the shaft elements and sleeves on the nodes ``x`` (m)."""
        M, K, C, G = (np.zeros((n, n)) for _ in range(4))
        bounds = self.boundaries
        shaft = self.shaft_sections
        for e in range(len(x) - 1):
            mid = 0.5 * (x[e] + x[e + 1])
            i = min(int(np.searchsorted(bounds, mid)) - 1, len(shaft) - 1)
            on = [shaft[i]] + [v for v in self.sleeves
                               if v.position < mid < v.position + v.length]  # fmt: skip
            sl = slice(4 * e, 4 * e + 8)
            for s in on:
                el = self._element(s, x[e + 1] - x[e])
                M[sl, sl] += el.M
                K[sl, sl] += el.K
                G[sl, sl] += el.G
                if s.mass_damping or s.stiffness_damping:
                    C[sl, sl] += s.mass_damping * el.M + s.stiffness_damping * el.K
        return M, K, C, G

    def _supports(self, basis: NodalBasis, M: np.ndarray) -> tuple[list, list]:
        """The bearings as supports (their mass added to ``M``) and the pinned DOFs."""
        extra = {p.name: 4 * len(basis.nodes) + 2 * j for j, p in enumerate(self.point_masses)}
        supports, fixed = [], []
        for i, b in enumerate(self.bearings):
            if b.on is not None:
                node, dofs = None, (extra[b.on], extra[b.on] + 1)
            else:
                node = basis.node_at(b.position)
                dofs = (4 * node, 4 * node + 1)
            if b.kind == "pinned":
                fixed += list(dofs)
                continue
            link = (extra[b.link], extra[b.link] + 1) if b.link is not None else None
            sup = b.support(node, b.name or f"bearing {i + 1}", dofs=dofs, link=link)
            if np.any(b.mass_matrix):
                ix = np.ix_(sup.all_dofs, sup.all_dofs)
                M[ix] += sup.block(b.mass_matrix)
            supports.append(sup)
        return supports, fixed

    def linear_system(self, stations: Sequence[float] = ()) -> LinearSystem:
        """The finite-element model of this rotor.

        Parameters
        ----------
        stations : sequence of float
            Extra node positions (m), e.g. probe, contact and force stations.

        Returns
        -------
        LinearSystem
            ``M``, ``K``, ``G`` assembled (sleeves, disks, point masses and bearing masses
            included), ``C`` the sections' proportional damping (zero unless given), bearings
            as supports, pinned DOFs fixed, a :class:`rubrotor.rotors.linear.NodalBasis` on the
            nodes (the point masses' ``[v, w]`` after the nodal DOFs).
        """
        x = self.nodes(stations)
        n = 4 * len(x) + 2 * len(self.point_masses)
        M, K, C, G = self._assemble_shaft(x, n)
        basis = NodalBasis(x, extra=2 * len(self.point_masses))
        for d in self.disks:
            j = 4 * basis.node_at(d.position)
            M[j : j + 4, j : j + 4] += np.diag(
                [d.mass, d.mass, d.diametral_inertia, d.diametral_inertia]
            )
            if self.gyroscopic:
                G[j + 2, j + 3] += d.polar_inertia
                G[j + 3, j + 2] -= d.polar_inertia
        for j, p in enumerate(self.point_masses):
            k = 4 * len(x) + 2 * j
            M[k, k] += p.mass_y
            M[k + 1, k + 1] += p.mass_z
        if self.mass_damping or self.stiffness_damping:
            C += self.mass_damping * M + self.stiffness_damping * K
        supports, fixed = self._supports(basis, M)
        labels = tuple(f"{q}@{xi:.6g}" for xi in x for q in ("v", "w", "psi_v", "psi_w"))
        labels += tuple(f"{q}@{p.name}" for p in self.point_masses for q in ("v", "w"))
        masses = self._masses(x)
        scales = rotor_scales(self, x, M, K)
        check_scales(scales)
        return LinearSystem(
            M=M,
            K=K,
            C=C,
            G=G,
            basis=basis,
            supports=tuple(supports),
            fixed=tuple(fixed),
            dof_labels=labels,
            name="fe",
            scales=scales,
            masses=masses,
        )

    def _masses(self, x: np.ndarray) -> tuple:
        """``(left, right, mass)`` of each element (sections and sleeves, m, m, kg) and lumped
        mass (disks, point masses: ``(mx + my) / 2`` as ROSS), for API 617's overhung mass."""
        out = []
        bounds, shaft = self.boundaries, self.shaft_sections
        for e in range(len(x) - 1):
            mid = 0.5 * (x[e] + x[e + 1])
            i = min(int(np.searchsorted(bounds, mid)) - 1, len(shaft) - 1)
            on = [shaft[i]] + [v for v in self.sleeves
                               if v.position < mid < v.position + v.length]  # fmt: skip
            m = sum(s.material.density * math.pi * (s.diameter**2 - s.bore_diameter**2) / 4
                    for s in on) * (x[e + 1] - x[e])  # fmt: skip
            out.append((float(x[e]), float(x[e + 1]), float(m)))
        out += [(d.position, d.position, d.mass) for d in self.disks]
        out += [(p.position, p.position, 0.5 * (p.mass_y + p.mass_z)) for p in self.point_masses]
        return tuple(out)
