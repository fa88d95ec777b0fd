"""Time simulation of the rotor under unbalance with rotor-stator contact.

:func:`~rubrotor.simulation.simulate_system` is the array-level entry point (shaft, speed, forces, integrator); it
assembles and diagonalises the modal system, runs a compiled kernel from :mod:`rubrotor.core`
in chunks (progress and Ctrl-C are handled between chunks, never per step) and returns a
:class:`SimulationResult`. :func:`rubrotor.results.to_dataset` turns that into an xarray Dataset.
"""

from __future__ import annotations

import math
import sys
import time as _time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from rubrotor.core.contact import pack_contact
from rubrotor.core.integrate import STATUS, abm_fixed, expo_adaptive, expo_fixed, n_channels
from rubrotor.errors import InputError
from rubrotor.forces import Contact, ModalDamping, RadialLoad, Unbalance
from rubrotor.integrator import Integrator
from rubrotor.model import Shaft, modal_matrices

__all__ = [
    "ModalSystem",
    "RotorState",
    "SimulationResult",
    "assemble",
    "simulate_system",
    "simulate_scenario",
    "simulate",
    "converge",
    "phi_functions",
]

ADAPTIVE_LEVELS = 21
INITIAL_STATES = ("rest", "steady")
EVENT_BUFFER = 200_000


def phi_functions(z: np.ndarray, third: bool = False):
    """``phi1 = (e^z - 1)/z``, ``phi2 = (e^z - 1 - z)/z^2`` (and ``phi3 = (e^z - 1 - z - z^2/2)/z^3``).

    Accurate for small ``|z|`` (Taylor series below 0.25, the recurrence
    ``phi_{k+1} = (phi_k - 1/k!)/z`` above).

    Parameters
    ----------
    z : ndarray, complex
        Arguments (dimensionless).
    third : bool
        Also return ``phi3``.

    Returns
    -------
    phi1, phi2[, phi3] : ndarray, complex

    Examples
    --------
    >>> p1, p2 = phi_functions(np.array([1e-12 + 0j, 1.0 + 0j]))
    >>> bool(np.allclose(p1, [1.0, np.e - 1])), bool(np.allclose(p2, [0.5, np.e - 2]))
    (True, True)
    """
    z = np.asarray(z, dtype=complex)
    small = np.abs(z) < 0.25
    out = [np.empty_like(z) for _ in range(3)]
    zs = z[small]
    # Taylor series: phi_k(z) = sum_j z^j / (j + k)!
    term = np.ones_like(zs)
    acc = [np.zeros_like(zs) for _ in range(3)]
    for j in range(0, 20):
        for k in range(3):
            acc[k] = acc[k] + term / math.factorial(j + k + 1)
        term = term * zs
    zl = z[~small]
    big = [(np.exp(zl) - 1) / zl]
    big.append((big[0] - 1) / zl)
    big.append((big[1] - 0.5) / zl)
    for k in range(3):
        out[k][small] = acc[k]
        out[k][~small] = big[k]
    return (out[0], out[1], out[2]) if third else (out[0], out[1])


def _block_diag(blocks: list[np.ndarray]) -> np.ndarray:
    """Block-diagonal matrix of square blocks (cheaper than scipy's for a few small blocks)."""
    n = sum(b.shape[0] for b in blocks)
    out = np.zeros((n, n), dtype=np.result_type(*blocks))
    o = 0
    for b in blocks:
        k = b.shape[0]
        out[o : o + k, o : o + k] = b
        o += k
    return out


def _damping_matrix(M: np.ndarray, K: np.ndarray, zeta: float) -> np.ndarray:
    """``C = M Phi diag(2 zeta omega) Phi^T M`` from the non-rotating modes of ``(K, M)``."""
    if zeta == 0.0:
        return np.zeros_like(M)
    w2, phi = scipy.linalg.eigh(K, M)
    return M @ phi @ np.diag(2 * zeta * np.sqrt(w2)) @ phi.T @ M


@dataclass
class ModalSystem:
    """The rotor in diagonal (eigen) coordinates of its first-order modal system.

    Physical state ``x = [q_1; q_1'; q_2; q_2'; ...]`` (complex, ``q_n = [P_n, Psi_n]`` or
    ``[P_n]``) is ``x = V y``; ``y' = lam y + beta(a) F`` for a point force ``F`` (N) at ``a``.
    """

    shaft: Shaft
    speed: float
    lam: np.ndarray
    V: np.ndarray
    Vinv: np.ndarray
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    q_index: np.ndarray  # indices of q in x
    qd_index: np.ndarray  # indices of q' in x
    defl_index: np.ndarray  # index in x of the deflection P_n of each mode
    wavenumbers: np.ndarray
    cond: float = field(default=1.0)

    def force_input(self, position: float) -> np.ndarray:
        """``beta`` (eigen-coordinates per N) of a point force at ``position`` (m)."""
        b = np.zeros(self.V.shape[0], complex)
        mdiag = np.diag(self.M)
        for n_i, xi in enumerate(self.defl_index):
            vel = self.qd_index[np.searchsorted(self.q_index, xi)]
            b[vel] = (
                math.sin(self.wavenumbers[n_i] * position)
                / mdiag[np.searchsorted(self.q_index, xi)]
            )
        return self.Vinv @ b

    def displacement_row(self, position: float) -> np.ndarray:
        """Row mapping ``y`` to the complex deflection ``v + i w`` (m) at ``position`` (m)."""
        r = np.zeros(self.V.shape[0], complex)
        for n_i, xi in enumerate(self.defl_index):
            r[xi] = math.sin(self.wavenumbers[n_i] * position)
        return r @ self.V

    def velocity_row(self, position: float) -> np.ndarray:
        """Row mapping ``y`` to the complex velocity (m/s) at ``position`` (m)."""
        r = np.zeros(self.V.shape[0], complex)
        for n_i, xi in enumerate(self.defl_index):
            vel = self.qd_index[np.searchsorted(self.q_index, xi)]
            r[vel] = math.sin(self.wavenumbers[n_i] * position)
        return r @ self.V

    def energy(self, y: np.ndarray) -> float:
        """Kinetic plus strain energy (J) of the physical state ``V y``."""
        x = self.V @ y
        q = x[self.q_index]
        qd = x[self.qd_index]
        return 0.5 * float(np.real(qd.conj() @ self.M @ qd) + np.real(q.conj() @ self.K @ q))


def assemble(shaft: Shaft, speed: float, damping: ModalDamping | None = None) -> ModalSystem:
    """Assemble and diagonalise the first-order modal system at spin ``speed`` (rad/s).

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    speed : float
        Spin speed ``Omega`` (rad/s).
    damping : ModalDamping, optional
        Modal damping ratios; none by default.

    Returns
    -------
    ModalSystem
        Or a :class:`rubrotor.seedform.SeedModalSystem` (same interface) for a Timoshenko shaft
        with ``formulation = "seed-eq1"``.
    """
    if shaft.formulation == "seed-eq1" and shaft.theory == "timoshenko":
        from rubrotor.seedform import assemble_seed

        return assemble_seed(shaft, speed, damping)
    damping = damping or ModalDamping()
    blocks_a, blocks_m, blocks_k, blocks_c = [], [], [], []
    q_idx, qd_idx, defl = [], [], []
    off = 0
    for n in range(1, shaft.modes + 1):
        mm = modal_matrices(shaft, n)
        m = mm.size
        c = _damping_matrix(mm.M, mm.K, damping.ratio(n))
        minv = np.linalg.inv(mm.M)
        a = np.zeros((2 * m, 2 * m), complex)
        a[:m, m:] = np.eye(m)
        a[m:, :m] = -minv @ mm.K
        a[m:, m:] = -minv @ (c + speed * mm.G)
        blocks_a.append(a)
        blocks_m.append(mm.M)
        blocks_k.append(mm.K)
        blocks_c.append(c)
        q_idx.extend(range(off, off + m))
        qd_idx.extend(range(off + m, off + 2 * m))
        defl.append(off)
        off += 2 * m
    ns = sum(a.shape[0] for a in blocks_a)
    lam = np.empty(ns, complex)
    V = np.zeros((ns, ns), complex)
    Vinv = np.zeros((ns, ns), complex)
    cond = 1.0
    o = 0
    for a in blocks_a:
        k = a.shape[0]
        lam_b, v = np.linalg.eig(a)
        v = v / np.linalg.norm(v, axis=0)
        vinv = np.linalg.inv(v)
        cond = max(cond, np.abs(v).sum(axis=0).max() * np.abs(vinv).sum(axis=0).max())  # 1-norm
        lam[o : o + k] = lam_b
        V[o : o + k, o : o + k] = v
        Vinv[o : o + k, o : o + k] = vinv
        o += k
    if cond > 1e12:
        raise InputError(
            "speed", speed, "a speed where the modal system is diagonalisable (move it slightly)"
        )
    q_index = np.array(q_idx)
    order = np.argsort(q_index)
    return ModalSystem(
        shaft=shaft,
        speed=speed,
        lam=lam,
        V=V,
        Vinv=Vinv,
        M=_block_diag(blocks_m),
        K=_block_diag(blocks_k),
        C=_block_diag(blocks_c),
        q_index=q_index[order],
        qd_index=np.array(qd_idx)[order],
        defl_index=np.array(defl),
        wavenumbers=np.array([shaft.wavenumber(n) for n in range(1, shaft.modes + 1)]),
        cond=cond,
    )


@dataclass(frozen=True)
class RotorState:
    """A physical state of the rotor, to start a simulation from (and returned at its end).

    Carried in physical modal coordinates, not in the eigen-coordinates of one speed, so that a
    state can start a run at another speed, clearance, unbalance ... (the eigen-basis and the
    particular solution of the new run are applied to it by :func:`~rubrotor.simulation.simulate_system`).

    Attributes
    ----------
    q : ndarray, complex, shape (n,)
        Generalised coordinates ``q = [P_1, (Psi_1), P_2, ...]`` in the order of
        ``rubrotor.simulation.ModalSystem.q_index``: modal deflections ``v + i w`` (m) and, for Timoshenko
        shafts, modal rotations (rad).
    qd : ndarray, complex, shape (n,)
        Their time derivatives (m/s, rad/s).
    phase : float
        Angle of the unbalance at this state, ``Omega t`` reduced to ``[-pi, pi]`` (rad); 0 (to
        rounding) at the end of a run of a whole number of revolutions.
    """

    q: np.ndarray
    qd: np.ndarray
    phase: float = 0.0


@dataclass
class SimulationResult:
    """Raw simulation output (SI units); see :func:`rubrotor.results.to_dataset`.

    Attributes
    ----------
    time : ndarray
        Sample times (s).
    stations : ndarray
        Axial positions (m) of the output stations; station 0 is the contact station (midspan
        without contact), the others are probes.
    channels : ndarray, shape (6 S + 2, T)
        Per station v, w (m), v', w' (m/s), v'', w'' (m/s^2); then normal force (N), friction
        force along the tangent (N).
    status : str
        ``"complete"`` or ``"partial"``.
    message : str
        Why a partial run stopped.
    stats : dict
        Integrator statistics.
    events : ndarray
        Contact onset (+t) and separation (-t) times (s).
    final_state : RotorState or None
        The state at the last sample (``None`` when the run did not complete).
    work : dict
        Work (J) of each force over the run when energy tracking was on.
    """

    time: np.ndarray
    stations: np.ndarray
    channels: np.ndarray
    status: str
    message: str
    stats: dict
    events: np.ndarray
    work: dict
    speed: float
    unbalance_force: complex
    unbalance_position: float
    final_state: RotorState | None = None


def _start_coordinates(sysm: ModalSystem, start: RotorState, load) -> np.ndarray:
    """Unshifted eigen-coordinates ``y = V^-1 x`` of a start state, turned to unbalance phase 0.

    The run starts with the unbalance at angle 0. A state taken at unbalance angle ``phi`` is
    turned by ``exp(-i phi)`` (every complex coordinate): the isotropic rotor, the annular
    stator and the rotating unbalance are invariant under that rotation, so the turned state
    continues the same motion seen in a frame turned by ``-phi``. A constant radial load breaks
    the symmetry, so with a load the state must be taken at angle 0 (whole revolutions).
    """
    n = sysm.q_index.size
    q = np.asarray(start.q, dtype=complex)
    qd = np.asarray(start.qd, dtype=complex)
    if q.shape != (n,) or qd.shape != (n,) or not np.all(np.isfinite(q) & np.isfinite(qd)):
        raise InputError("start", f"q, qd of shapes {q.shape}, {qd.shape}", f"finite ({n},) arrays")
    turn = complex(math.cos(start.phase), -math.sin(start.phase))
    has_load = load is not None and (load.force_y != 0 or load.force_z != 0)
    if abs(turn - 1) > 1e-6:
        if has_load:
            raise InputError(
                "start.phase", start.phase, "0 (a state after whole revolutions) with a load"
            )
        q, qd = q * turn, qd * turn
    x = np.zeros(sysm.V.shape[0], complex)
    x[sysm.q_index] = q
    x[sysm.qd_index] = qd
    return sysm.Vinv @ x


def _state_of(sysm: ModalSystem, y_full: np.ndarray, phase: float) -> RotorState:
    """The physical state of unshifted eigen-coordinates ``y_full``."""
    x = sysm.V @ y_full
    return RotorState(
        q=x[sysm.q_index].copy(),
        qd=x[sysm.qd_index].copy(),
        phase=math.remainder(phase, 2 * math.pi),
    )


def _start_force(y: np.ndarray, cp: np.ndarray, orows) -> complex:
    """Contact force (N) of the start state (the held force of the first exponential step)."""
    from rubrotor.core.contact import contact_force

    rows_d, rows_v, _, _, part_u, part_l, vel_z = orows[:7]
    P = complex(rows_d[0] @ y + part_u[0] + part_l[0])
    V = complex(rows_v[0] @ y + vel_z[0])
    fy, fz, _, _ = contact_force(P.real, P.imag, V.real, V.imag, cp)
    return complex(fy, fz)


def contact_parameters(shaft: Shaft, speed: float, contact: Contact | None) -> np.ndarray:
    """The packed contact law the kernels take (:data:`rubrotor.core.contact.CP_FIELDS`).

    Parameters
    ----------
    shaft : Shaft
        The rotor (its radius is the default contact radius, m).
    speed : float
        Spin speed (rad/s); the surface speed is ``radius * speed`` (m/s).
    contact : Contact or None
        The contact; None packs an inactive law.

    Returns
    -------
    ndarray
    """
    if contact is None:
        return pack_contact(0, 0, 1.0, 0.0, 1.0, 0.0, 0, 0.0, 1.0)
    radius = contact.radius if contact.radius is not None else shaft.diameter / 2
    return pack_contact(
        1,
        contact.law_code,
        contact.stiffness,
        contact.damping,
        contact.clearance,
        contact.friction,
        contact.sign_code,
        radius * speed,
        contact.friction_regularization,
    )


def _available_memory() -> int:
    """Bytes of memory available to this process (MemAvailable; 8 GiB when unknown)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 8 << 30


def _check_output_size(nbytes: int, integrator: Integrator) -> None:
    """Refuse, before it starts, a run whose saved samples cannot fit in half the free memory."""
    limit = _available_memory() // 2
    if nbytes > limit:
        raise InputError(
            "simulation.revolutions",
            integrator.revolutions,
            f"a run whose saved samples fit in memory: this one needs {nbytes / 2**30:.3g} GiB "
            f"(limit {limit / 2**30:.3g} GiB); lower simulation.revolutions, or save fewer "
            "samples with simulation.save_every / simulation.output_dtau, or a larger "
            "simulation.dtau",
        )


def _check_station(name: str, x: float, length: float) -> float:
    if not (0 < x < length):
        raise InputError(name, x, f"an axial position in (0, {length:g}) m")
    return float(x)


def simulate_system(
    shaft: Shaft,
    speed: float,
    integrator: Integrator,
    unbalance: Unbalance | None = None,
    contact: Contact | None = None,
    load: RadialLoad | None = None,
    damping: ModalDamping | None = None,
    *,
    track_energy: bool = False,
    progress: bool | None = None,
    chunk_samples: int = 1 << 15,
    initial: str = "rest",
    start: RotorState | None = None,
) -> SimulationResult:
    """Simulate the rotor from rest, from its steady no-contact orbit or from a given state.

    Parameters
    ----------
    shaft : Shaft
        The rotor.
    speed : float
        Constant spin speed ``Omega`` (rad/s), > 0.
    integrator : Integrator
        Method, steps, length of the run and what to save.
    unbalance : Unbalance, optional
        Rotating unbalance; none by default.
    contact : Contact, optional
        Stator contact; none by default (free rotor).
    load : RadialLoad, optional
        Constant radial load; none by default.
    damping : ModalDamping, optional
        Modal damping ratios; 0 by default (as in the seed).
    track_energy : bool
        Accumulate the work of every force (exponential fixed-step only), for energy checks.
    progress : bool, optional
        Print progress to stderr on runs longer than a few seconds (default: when stderr is a
        terminal).
    chunk_samples : int
        Samples computed per compiled call.
    initial : {"rest", "steady"}
        Initial state: at rest and undeflected (default), or on the steady no-contact orbit
        (the particular solution of unbalance and load, exact in the modal model). Ignored
        when ``start`` is given.
    start : RotorState, optional
        Start from this physical state (e.g. the ``final_state`` of a run at a neighbouring
        parameter value); see :class:`RotorState` for the unbalance angle.

    Returns
    -------
    SimulationResult
        With ``final_state`` (:class:`RotorState`) when the run completed.
    """
    if initial not in INITIAL_STATES:
        raise InputError("initial.state", initial, " or ".join(f'"{x}"' for x in INITIAL_STATES))
    if track_energy and shaft.formulation == "seed-eq1" and shaft.theory == "timoshenko":
        raise InputError(
            "track_energy", True, 'shaft.formulation = "two-field" (the seed form has no energy)'
        )
    if (
        isinstance(speed, bool)
        or not isinstance(speed, int | float)
        or not (speed > 0 and math.isfinite(speed))
    ):
        raise InputError("speed", speed, "a finite spin speed > 0 (rad/s)")
    speed = float(speed)
    L = shaft.length
    unbalance = unbalance or Unbalance(0.0)
    a_u = _check_station(
        "unbalance.position", unbalance.position if unbalance.position is not None else L / 2, L
    )
    a_c = L / 2
    if contact is not None:
        a_c = _check_station(
            "contact.position", contact.position if contact.position is not None else L / 2, L
        )
    a_l = L / 2
    if load is not None and load.position is not None:
        a_l = _check_station("load.position", load.position, L)
    probes = [_check_station("simulation.probes", p, L) for p in integrator.probes]
    stations = np.array([a_c, *probes])

    sysm = assemble(shaft, speed, damping)
    lam = sysm.lam
    ns = lam.size
    beta_c = sysm.force_input(a_c)
    beta_u = sysm.force_input(a_u)
    beta_l = sysm.force_input(a_l)
    fu0 = (
        unbalance.magnitude
        * speed**2
        * complex(math.cos(unbalance.phase), math.sin(unbalance.phase))
    )
    fl = complex(load.force_y, load.force_z) if load is not None else 0j

    rows_d = np.array([sysm.displacement_row(x) for x in stations])
    rows_v = np.array([sysm.velocity_row(x) for x in stations])
    rows_a = rows_v * lam[None, :]
    acc_fc = rows_v @ beta_c
    cdc = np.ascontiguousarray(rows_d[0])
    cvc = np.ascontiguousarray(rows_v[0])

    cp = contact_parameters(shaft, speed, contact)
    gap = contact.clearance if contact is not None else None
    max_disp = integrator.max_displacement
    if max_disp is None:
        max_disp = 1000 * gap if gap is not None else 0.1 * L

    t_total = integrator.total_time(speed)
    method = integrator.method
    h_fixed = integrator.step_seconds(speed)
    events = np.zeros(EVENT_BUFFER)
    stats: dict = {
        "method": method,
        "order": integrator.order,
        "modes": shaft.modes,
        "eig_cond": sysm.cond,
    }
    work = np.zeros(5)

    if method == "exponential":
        res = 1j * speed - lam
        if np.min(np.abs(res) / np.abs(lam)) < 1e-9 and unbalance.magnitude > 0:
            raise InputError(
                "speed",
                speed,
                "a speed that is not exactly an undamped critical speed (add damping or move it)",
            )
        y_u = beta_u * fu0 / res
        y_l = -beta_l * fl / lam
        part_u = rows_d @ y_u
        part_l = rows_d @ y_l
        vel_z = 1j * speed * part_u
        acc_z = -(speed**2) * part_u
        # shifted coordinates: -(particular solution) is rest, 0 is the steady orbit
        y = -(y_u + y_l) if initial == "rest" else np.zeros(ns, complex)
    else:
        part_u = np.zeros(len(stations), complex)
        part_l = np.zeros(len(stations), complex)
        vel_z = np.zeros(len(stations), complex)
        acc_z = rows_v @ beta_u * fu0
        y = np.zeros(ns, complex)
        if initial == "steady":
            y = beta_u * fu0 / (1j * speed - lam) - beta_l * fl / lam
    acc_c = rows_v @ beta_l * fl if method == "abm" else np.zeros(len(stations), complex)
    orows = tuple(
        np.ascontiguousarray(a, dtype=complex)
        for a in (rows_d, rows_v, rows_a, acc_fc, part_u, part_l, vel_z, acc_z, acc_c)
    )
    f_start = 0j
    if start is not None:
        y = _start_coordinates(sysm, start, load)
        if method == "exponential":
            y = y - (y_u + y_l)
        f_start = _start_force(y, cp, orows)

    if h_fixed is not None:
        n_steps = int(round(t_total / h_fixed))
        if n_steps < 1:
            raise InputError(
                "simulation.dtau", integrator.dtau or integrator.dt, "a step shorter than the run"
            )
        n_samples = n_steps // integrator.save_every
        sample_dt = h_fixed * integrator.save_every
    else:
        H = integrator.output_spacing(speed)
        n_samples = int(round(t_total / H))
        sample_dt = H
    if n_samples < 1:
        raise InputError(
            "simulation.revolutions", integrator.revolutions, "a run long enough for one sample"
        )

    _check_output_size(n_channels(len(stations)) * (n_samples + 1) * 8, integrator)
    out = np.empty((n_channels(len(stations)), n_samples + 1))
    istate = np.zeros(5, np.int64)
    cstate = np.array([f_start, 1 + 0j, 0j])

    def write0():
        from rubrotor.core.integrate import _write_sample

        _write_sample(out, 0, y, 1 + 0j, f_start, cp, orows)

    write0()

    if method == "exponential" and h_fixed is not None:
        h = h_fixed
        E = np.exp(lam * h)
        p1, p2 = phi_functions(lam * h)
        G0 = (h * p1 - h * p2) * beta_c
        G1 = h * p2 * beta_c
        sd = complex(cdc @ G1)
        sv = complex(cvc @ G1)
        if track_energy:
            wv = sysm.V[sysm.qd_index, :]
            wz = wv @ y_u  # y_u is a full state: its q-dot rows are velocities
            cmat = sysm.C
            vel_u_row = sysm.velocity_row(a_u)
            vel_u_z = 1j * speed * complex(sysm.displacement_row(a_u) @ y_u)
            vel_l_row = sysm.velocity_row(a_l)
            vel_l_z = complex(vel_l_row @ y_u)
            e0 = sysm.energy(y + y_u + y_l)
        else:
            wv = np.zeros((0, ns), complex)
            wz = np.zeros(0, complex)
            cmat = np.zeros((0, 0))
            vel_u_row = np.zeros(ns, complex)
            vel_u_z = 0j
            vel_l_row = np.zeros(ns, complex)
            vel_l_z = 0j
        etrack = (
            wv,
            wz,
            cmat,
            vel_u_row,
            complex(vel_u_z),
            complex(fu0),
            vel_l_row,
            complex(vel_l_z),
            complex(fl),
        )

        def run_chunk(offset, count):
            return expo_fixed(
                y, cstate, istate, count, integrator.save_every, out, offset,
                E, G0, G1, sd, sv, cdc, cvc, cp,
                orows,
                speed, h, max_disp,
                track_energy, etrack, work,
                events,
            )  # fmt: skip

        stats["step_s"] = h
    elif method == "exponential":
        if track_energy:
            raise InputError("track_energy", True, "a fixed step (dtau or dt) for energy tracking")
        levels = ADAPTIVE_LEVELS
        hs = H / 2.0 ** np.arange(levels)
        E = np.exp(np.outer(hs, lam))
        p1, p2, p3 = phi_functions(np.outer(hs, lam), third=True)
        G0 = (hs[:, None] * (p1 - p2)) * beta_c[None, :]
        # quadratic hold through F_{k-1}, F_k, F_{k+1} at equal steps
        Q1 = (hs[:, None] * (0.5 * p2 + p3)) * beta_c[None, :]
        Q0 = (hs[:, None] * (p1 - 2 * p3)) * beta_c[None, :]
        Qm = (hs[:, None] * (p3 - 0.5 * p2)) * beta_c[None, :]
        sdq = np.ascontiguousarray(Q1 @ cdc)
        svq = np.ascontiguousarray(Q1 @ cvc)
        cdQ0, cvQ0 = Q0 @ cdc, Q0 @ cvc
        cdQm, cvQm = Qm @ cdc, Qm @ cvc
        G1 = (hs[:, None] * p2) * beta_c[None, :]
        sd = np.ascontiguousarray(G1 @ cdc)
        sv = np.ascontiguousarray(G1 @ cvc)
        errc = np.abs(G0 @ cdc)
        rot = np.exp(1j * speed * hs)
        cdE = np.ascontiguousarray(E * cdc[None, :])
        cvE = np.ascontiguousarray(E * cvc[None, :])
        cdG0 = np.ascontiguousarray(G0 @ cdc)
        cvG0 = np.ascontiguousarray(G0 @ cvc)
        stat_arr = np.zeros(3, np.int64)
        istate[3] = 0

        def run_chunk(offset, count):
            return expo_adaptive(
                y, cstate, istate, count, out, offset,
                E, G0, G1, cdE, cvE, cdG0, cvG0, sd, sv, errc, rot, cdc, cvc, cp,
                Q0, Qm, Q1, cdQ0, cvQ0, cdQm, cvQm, sdq, svq,
                orows,
                speed, H, max_disp, integrator.rtol, integrator.atol,
                events, stat_arr,
            )  # fmt: skip

        stats["output_spacing_s"] = H
        stats["min_step_s"] = hs[-1]
    else:
        h = h_fixed
        hist = np.zeros((4, ns), complex)

        def run_chunk(offset, count):
            return abm_fixed(
                y, hist, istate, count, integrator.save_every, out, offset,
                lam, beta_c, beta_u, beta_l, fu0, fl, cdc, cvc, cp,
                orows,
                speed, h, max_disp, events,
            )  # fmt: skip

        stats["step_s"] = h

    show = sys.stderr.isatty() if progress is None else progress
    t0 = _time.perf_counter()
    done = 0
    message = ""
    interrupted = False
    try:
        while done < n_samples:
            count = min(chunk_samples, n_samples - done)
            wrote = run_chunk(1 + done, count)
            done += wrote
            if istate[2] != 0:
                break
            el = _time.perf_counter() - t0
            if show and el > 2.0:
                frac = done / n_samples
                print(
                    f"\rrubrotor: {100 * frac:5.1f} % ({done * sample_dt * speed / (2 * math.pi):.0f} rev)"
                    f" {el:.0f} s, ~{el / max(frac, 1e-9) - el:.0f} s left",
                    end="",
                    file=sys.stderr,
                )
    except KeyboardInterrupt:
        interrupted = True
    if show and _time.perf_counter() - t0 > 2.0:
        print(file=sys.stderr)
    stats["wall_s"] = _time.perf_counter() - t0
    n_out = 1 + done
    status = "complete"
    if istate[2] != 0 or interrupted:
        status = "partial"
        t_stop = done * sample_dt
        if interrupted:
            message = f"interrupted by the user after t = {t_stop:.6g} s"
        elif istate[2] == 1:
            message = (
                f"diverged: contact-point displacement exceeded {max_disp:.3g} m "
                f"at t = {t_stop + sample_dt:.6g} s; data up to t = {t_stop:.6g} s kept"
            )
        else:
            message = f"{STATUS[int(istate[2])]} at t = {t_stop + sample_dt:.6g} s; data up to t = {t_stop:.6g} s kept"
    if method == "exponential" and h_fixed is None:
        stats.update(
            accepted_steps=int(stat_arr[0]),
            rejected_steps=int(stat_arr[1]),
            newton_iterations=int(stat_arr[2]),
        )
    else:
        stats["steps"] = int(istate[0])
    final_state = None
    if status == "complete":
        t_end = done * sample_dt
        y_full = y + y_u * cstate[1] + y_l if method == "exponential" else y
        final_state = _state_of(sysm, y_full, speed * t_end)
    n_ev = min(int(istate[1]), EVENT_BUFFER)
    stats["contact_events"] = int(istate[1])
    work_d: dict = {}
    if track_energy and method == "exponential" and h_fixed is not None:
        e1 = sysm.energy(y + y_u * cstate[1] + y_l)
        p_end = out[0, n_out - 1] + 1j * out[1, n_out - 1]
        u_c = 0.0
        if contact is not None:
            eps = abs(p_end) - contact.clearance
            if eps > 0:
                u_c = (
                    0.4 * contact.stiffness * eps**2.5
                    if contact.law == "hertz"
                    else 0.5 * contact.stiffness * eps**2
                )
        work_d = {
            "mechanical_energy_start_J": e0,
            "mechanical_energy_end_J": e1,
            "contact_potential_end_J": u_c,
            "work_unbalance_J": work[0],
            "work_load_J": work[1],
            "work_contact_J": work[2],
            "dissipated_modal_damping_J": work[3],
            "work_friction_J": work[4],
            # elastic contact work is minus the potential change (zero at the start)
            "dissipated_contact_damping_J": -(work[2] - work[4]) - u_c,
        }
    return SimulationResult(
        time=np.arange(n_out) * sample_dt,
        stations=stations,
        channels=out[:, :n_out],
        status=status,
        message=message,
        stats=stats,
        events=events[:n_ev].copy(),
        work=work_d,
        speed=speed,
        unbalance_force=fu0,
        unbalance_position=a_u,
        final_state=final_state,
    )


# units of resolved object fields that are not scenario keys (see rubrotor.scenario.KEY_UNITS)
_FIELD_UNITS = {"shaft.kappa": "1", "unbalance.phase": "rad"}


def scenario_parameters(scenario) -> dict:
    """Every parameter of a scenario as ``{"section.key": [value, unit]}`` (SI), for provenance.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The scenario.

    Returns
    -------
    dict
    """
    import dataclasses

    from rubrotor.scenario import key_unit

    def unit(key, value=0.0):
        if isinstance(value, bool) or not isinstance(value, int | float | tuple):
            return ""  # names, flags and switches have no unit
        return _FIELD_UNITS.get(key) or key_unit(key)

    out: dict = {}
    sh = scenario.shaft
    for f in dataclasses.fields(sh):
        if f.init:
            val = getattr(sh, f.name)
            out[f"shaft.{f.name}"] = [val, unit(f"shaft.{f.name}", val)]
    out["shaft.shear_modulus"] = [sh.G, "Pa"]
    out["shaft.poisson_ratio"] = [sh.nu, "1"]
    out["shaft.kappa"] = [sh.kappa, "1"]
    out["speed.rad_per_s"] = [scenario.speed, "rad/s"]
    out["initial.state"] = [getattr(scenario, "initial", "rest"), ""]
    for sec in ("unbalance", "load", "contact", "damping", "simulation"):
        obj = getattr(scenario, sec, None)
        if obj is None:
            continue
        for f in dataclasses.fields(obj):
            key = f"{sec}.{f.name}"
            u = unit(key, getattr(obj, f.name))
            if sec == "contact" and f.name == "stiffness":
                u = "N/m^1.5" if obj.law == "hertz" else "N/m"
            if sec == "contact" and f.name == "damping":
                u = "s/m" if obj.law == "hertz" else "N s/m"
            out[key] = [getattr(obj, f.name), u]
    return out


def simulate_scenario(scenario, integrator: Integrator, **kwargs) -> SimulationResult:
    """:func:`~rubrotor.simulation.simulate_system` on the parts of a scenario (raw arrays, no Dataset).

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        Shaft, speed (rad/s), unbalance, contact, load and damping.
    integrator : Integrator
        How to integrate.
    **kwargs
        ``track_energy``, ``progress``, ``chunk_samples`` of :func:`~rubrotor.simulation.simulate_system`.

    Returns
    -------
    SimulationResult
    """
    return simulate_system(
        scenario.shaft,
        scenario.speed,
        integrator,
        scenario.unbalance,
        scenario.contact,
        scenario.load,
        scenario.damping,
        **({"initial": getattr(scenario, "initial", "rest")} | kwargs),
    )


def simulate(
    scenario,
    *,
    integrator: Integrator | None = None,
    progress: bool | None = None,
    track_energy: bool = False,
):
    """Simulate a scenario and return the results Dataset.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        Shaft, speed, unbalance, load, contact, damping and ``[simulation]`` settings.
    integrator : Integrator, optional
        Overrides the scenario's ``[simulation]`` section.
    progress : bool, optional
        Print progress on long runs (default: when stderr is a terminal).
    track_energy : bool
        Accumulate the work of every force (fixed-step exponential only).

    Returns
    -------
    xarray.Dataset
        See :func:`rubrotor.results.to_dataset`; ``attrs["status"]`` is ``"complete"`` or
        ``"partial"`` (then ``attrs["status_message"]`` says why and where it stopped).
    """
    from rubrotor.results import to_dataset

    if getattr(scenario, "engine", None) is not None:  # general rotor or general-engine keys
        from rubrotor.simulate_engine import simulate_engine

        if track_energy:
            raise InputError("track_energy", True, "False with the general engine")
        return simulate_engine(scenario, integrator=integrator, progress=progress)
    scenario.require_shaft("time simulation")
    integ = integrator or scenario.simulation
    if integ is None:
        raise InputError("simulation", None, "a [simulation] section (revolutions or duration)")
    res = simulate_scenario(scenario, integ, track_energy=track_energy, progress=progress)
    params = scenario_parameters(scenario)
    if integrator is not None:
        import dataclasses

        for f in dataclasses.fields(integrator):
            params[f"simulation.{f.name}"] = [getattr(integrator, f.name), ""]
    return to_dataset(res, params, getattr(scenario, "source", ""), getattr(scenario, "name", ""))


def converge(
    scenario,
    *,
    dtau: float | None = None,
    halvings: int = 4,
    max_modes: int | None = None,
    revolutions: float | None = None,
    method: str | None = None,
) -> list[dict]:
    """The seed's step and mode convergence procedure.

    Runs the scenario with fixed steps ``dtau, dtau/2, ..., dtau/2^halvings`` (all saved at the
    spacing ``dtau``) with the scenario's modes, then with ``1 .. max_modes`` modes at ``dtau``,
    and reports the difference between successive runs: ``max |P_a - P_b|`` over the run (m) and
    relative to ``max |P_b|``, where ``P = v + i w`` at the contact station.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The scenario; its ``[simulation]`` section gives the method and length unless overridden.
    dtau : float, optional
        Base step (rad of spin); default the scenario's ``dtau`` or 0.001 (the seed's value).
    halvings : int
        Number of step halvings (the seed used 4: down to ``dtau/16``).
    max_modes : int, optional
        Largest mode count compared; default the scenario's.
    revolutions : float, optional
        Length of each run (rev); default the scenario's.
    method : {"exponential", "abm"}, optional
        Integrator; default the scenario's.

    Returns
    -------
    list of dict
        One row per compared pair: ``{"study": "step"|"modes", "a": ..., "b": ..., "max_diff_m": ...,
        "rel_diff": ..., "wall_s": ...}``.
    """
    import dataclasses

    scenario.require_seed_engine("the convergence study")
    base = scenario.simulation or Integrator(revolutions=revolutions or 20)
    dtau = dtau or base.dtau or 1e-3
    revs = revolutions or base.revolutions or base.duration * scenario.speed / (2 * math.pi)
    method = method or base.method
    max_modes = max_modes or scenario.shaft.modes

    def run(shaft, k):
        integ = Integrator(revolutions=revs, method=method, dtau=dtau / 2**k, save_every=2**k)
        t0 = _time.perf_counter()
        r = simulate_system(
            shaft,
            scenario.speed,
            integ,
            scenario.unbalance,
            scenario.contact,
            scenario.load,
            scenario.damping,
            progress=False,
        )
        return r.channels[0] + 1j * r.channels[1], _time.perf_counter() - t0, r.status

    def compare(study, runs):
        """Rows comparing each run of ``runs = [(label, shaft, k), ...]`` with the previous one."""
        rows, prev = [], None
        for label, shaft, k in runs:
            p, wall, status = run(shaft, k)
            if prev is not None:
                n = min(len(p), len(prev[1]))
                diff = float(np.max(np.abs(p[:n] - prev[1][:n])))
                rows.append(
                    {
                        "study": study,
                        "a": prev[0],
                        "b": label,
                        "max_diff_m": diff,
                        "rel_diff": diff / float(np.max(np.abs(p[:n]))),
                        "wall_s": wall,
                        "status": status,
                    }
                )
            prev = (label, p)
        return rows

    steps = [(f"dtau/{2**k}", scenario.shaft, k) for k in range(halvings + 1)]
    modes = [
        (f"{m} modes", dataclasses.replace(scenario.shaft, modes=m), 0)
        for m in range(1, max_modes + 1)
    ]
    rows = compare("step", steps) + compare("modes", modes)
    return rows
