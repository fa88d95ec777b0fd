"""A general rotor's plant at any constant speed without rebuilding its reduction.

Continuation in a speed key asks for the stroboscopic map at a new speed several times per
branch point. Rebuilding the plant there (:func:`rubrotor.engine.driver.build_plant`, a dense
eigen-decomposition of the ``2 n`` first-order matrix and three ``n x n`` inverses) cost about
0.3-0.5 s per speed on ``seal_rub.toml`` (284 DOFs), 95 % of a branch point. Only the
speed-dependent parts change with the speed: the gyroscopic term ``Omega G``, the supports'
tabulated coefficients, the unbalance forcing and the contact's sliding speed.
:class:`SpeedFamily` updates exactly those, in about 6 ms (CPU) per speed:

* modes: the ``keep + EXTRA_MODES`` lowest modes are followed on a fixed basis
  (:class:`rubrotor.engine.reduce.SpeedBasis`: those modes at an anchor speed, real and
  imaginary parts, with the static responses at the support DOFs), one ``r x r`` real
  eigen-decomposition (``r = 48`` here) per speed, each followed mode picked by its overlap with
  the anchor's; one Newton step on the full quadratic eigenproblem (banded LU, right and left
  vectors from one factorisation, :func:`rubrotor.core.banded.newton_pairs`) then makes them
  exact; the ``keep`` lowest ``|lam|`` are kept, as the dense reduction keeps them. Beyond
  :data:`ANCHOR_SPAN` from every anchor a new anchor is built from the modes followed there
  (or densely when farther than twice the span). Measured on ``seal_rub.toml`` from 600 to
  800 rad/s: eigenvalues and contact rows equal the dense rebuild's to 4e-10;
* static flexibility at the contact stations and the static deflection: exact, by the
  Sherman-Morrison-Woodbury update of ``K^-1`` for the support coefficients' change (only the
  support DOFs' entries of ``K`` depend on speed);
* the residual flexibility of the dropped modes at the stations, ``K^-1 + Re(sum V U / lam)``,
  from those two (a small difference of two large flexibilities: it carries ~4e-8 of
  rounding, as the dense route's does);
* the steady unbalance response: exact, one banded complex LU of the dynamic stiffness;
* the stators (speed-independent) are the first plant's.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.linalg

from rubrotor.engine.driver import Plant
from rubrotor.engine.reduce import Modes, speed_basis
from rubrotor.errors import InputError

ANCHOR_SPAN = 0.03
"""Largest relative distance (dimensionless) from the anchor speed a basis serves."""
EXTRA_MODES = 4
"""Modes followed in the basis beyond the plant's kept ones (stored modes): at each speed the
``keep`` lowest ``|lam|`` of them are kept, as the dense reduction keeps the lowest at each
speed (on ``seal_rub.toml`` the 16th and 17th swap near 617.8 rad/s)."""
NEWTON_STEPS = 1
"""Newton steps per followed mode (:func:`rubrotor.core.banded.newton_pairs`): the projection's
eigenvalue is within ~1e-7 of the true one (relative), so one step leaves ~1e-14 (quadratic
convergence) and its vectors the error of one inverse iteration with that shift (measured: the
plants equal the dense rebuild's to 1e-10)."""
NEWTON_START = 1e-5
"""Largest relative eigenvalue change the refinement accepts (a larger one means the projection
did not start Newton close to the mode it follows)."""


class SpeedFamily:
    """Plants of one general rotor at constant speeds (see the module docstring).

    Parameters
    ----------
    system : rubrotor.rotors.linear.LinearSystem
        The rotor.
    run : rubrotor.engine.parts.Run
        Its run settings (modes kept, probes); the speed is replaced per plant.
    kw : dict
        ``stations``, ``unbalances``, ``loads``, ``gravity`` (as :func:`build_plant`).
    plant : Plant
        The dense plant at ``run.speed`` (stator parts, contact laws, positions).

    Attributes
    ----------
    usable : bool
        Whether the rotor allows it: symmetric mass, stiffness and damping, skew gyroscopic
        matrix, as many sub- as super-diagonals (the left eigenproblem is solved on the same
        banded factors, transposed), supports to the ground (none linked to a housing).
        Otherwise :meth:`GeneralMap.at_speed` rebuilds the plant.
    anchors : list of rubrotor.engine.reduce.SpeedBasis
        The bases built so far.
    """

    def __init__(self, system, run, kw, plant: Plant):
        from rubrotor.engine.parts import static_load_vector, unbalance_phasor
        from rubrotor.linear.band import _band_parts

        self.system, self.run, self.base = system, run, plant
        self.problem = (system, run, kw)
        self.keep = plant.n_rotor
        n = system.n_dof
        pos = np.full(len(system.M), -1)
        pos[system.free] = np.arange(n)
        self._sup = [(s, pos[list(s.dofs)]) for s in system.supports]
        self.sdofs = np.unique(np.concatenate([d[d >= 0] for _, d in self._sup] or [[]])).astype(
            int
        )
        self.speed0 = float(run.speed)
        sm = system.matrices(self.speed0)
        self.M = sm.M
        self.minv = np.linalg.inv(sm.M)
        self.Bmat = plant.Bmat
        positions = plant.stations
        self.orow = np.vstack([system.output_rows(x) for x in positions])
        self.parts = _band_parts(system, np.array([self.speed0]))
        f = np.ix_(system.free, system.free)
        # the left problem reuses the bands transposed: M, K, C symmetric (G skew), kl = ku
        self.usable = (
            self.parts.kl == self.parts.ku
            and all(np.array_equal(a[f], a[f].T) for a in (system.M, system.K, system.C))
            and np.array_equal(system.G[f], -system.G[f].T)
            and all(getattr(sup, "link", None) is None for sup in system.supports)
            and not plant.supports  # film rows and their linearisation change with the speed
        )
        b1 = np.zeros(n, complex)
        for u in kw["unbalances"]:
            b1 += unbalance_phasor(u, 1.0) * (system.force_map(u.position) @ np.array([1, -1j]))
        self.b1 = b1
        f_s = static_load_vector(system, tuple(kw["loads"]), kw["gravity"])
        E = np.zeros((n, self.sdofs.size))
        E[self.sdofs, np.arange(self.sdofs.size)] = 1.0
        lu = scipy.linalg.lu_factor(sm.K)
        self._X = scipy.linalg.lu_solve(lu, np.column_stack([self.Bmat, f_s]))  # K0^-1 [B, f]
        self._Y = scipy.linalg.lu_solve(lu, E)  # K0^-1 E_s
        self.offs = np.array([[s.offset_y, s.offset_z] for s in kw["stations"]]).ravel()
        self.radii = np.array([s.contact.radius for s in kw["stations"]])
        self.anchors: list = []

    def _supports(self, speed: float, ref: float):
        """Support coefficient changes ``(dK, dC)`` (p, p) from ``ref`` to ``speed`` (rad/s)."""
        p = self.sdofs.size
        dK, dC = np.zeros((p, p)), np.zeros((p, p))
        for s, d in self._sup:
            k1, c1 = s.coefficients(speed)
            k0, c0 = s.coefficients(ref)
            for i in range(2):
                for j in range(2):
                    if d[i] < 0 or d[j] < 0:
                        continue
                    a, b = np.searchsorted(self.sdofs, d[i]), np.searchsorted(self.sdofs, d[j])
                    dK[a, b] += k1[i, j] - k0[i, j]
                    dC[a, b] += c1[i, j] - c0[i, j]
        return dK, dC

    def _anchor(self, speed: float):
        """The basis serving ``speed`` (rad/s): the nearest anchor within :data:`ANCHOR_SPAN`;
        else a new anchor at ``speed`` built from the modes followed there from the nearest
        anchor (within twice the span), or from the dense eigen-decomposition."""
        near = min(self.anchors, key=lambda b: abs(speed - b.speed0), default=None)
        dist = np.inf if near is None else abs(speed - near.speed0) / near.speed0
        if dist <= ANCHOR_SPAN:
            return near
        sm = self.system.matrices(speed)
        count = self.keep + EXTRA_MODES
        if dist <= 2 * ANCHOR_SPAN:
            lam, phi, _, psi, _ = self._followed(near, speed)
            basis = speed_basis(sm, count, self.sdofs, (lam, phi.T, psi), self.minv)
        else:
            basis = speed_basis(sm, count, self.sdofs, minv=self.minv)
        self.anchors.append(basis)
        return basis

    def _static(self, speed: float):
        """``K(speed)^-1 [B, f_s]`` (m/N; m) by Woodbury from the first speed's ``K``."""
        dK, _ = self._supports(speed, self.speed0)
        if not np.any(dK):
            return self._X
        s = self.sdofs
        inner = np.eye(s.size) + dK @ self._Y[s]
        return self._X - self._Y @ np.linalg.solve(inner, dK @ self._X[s])

    def _particular(self, speed: float) -> np.ndarray:
        """Steady unbalance response (m, rad; complex amplitude) at ``speed`` (rad/s): one
        banded LU of ``K - Omega^2 M + i Omega D`` (supports at ``speed`` included)."""
        from rubrotor.core.banded import OK, _assemble, band_factor, band_solve

        if not np.any(self.b1):
            return np.zeros(self.b1.size, complex)
        parts = self._parts(speed)[0]
        n, kl, ku = self.b1.size, parts.kl, parts.ku
        ab = np.empty((n, 2 * kl + ku + 1), complex)
        ipiv = np.empty(n, np.int64)
        _assemble(parts, 0, speed, 1j * speed, ab)
        if band_factor(ab, kl, ku, ipiv) != OK:
            raise InputError("speed", speed, "a speed off an undamped critical speed")
        x = self.b1 * speed**2
        band_solve(ab, kl, ku, ipiv, x)
        return x

    def _mass(self, u: np.ndarray) -> np.ndarray:
        """``u M`` (rows ``u``, complex) on the mass band (``M`` real and symmetric)."""
        from rubrotor.core.banded import band_matmul

        out_r, out_i = np.empty((u.shape[1], u.shape[0])), np.empty((u.shape[1], u.shape[0]))
        band_matmul(self.parts.m, self.parts.ku, np.ascontiguousarray(u.real.T), out_r)
        band_matmul(self.parts.m, self.parts.ku, np.ascontiguousarray(u.imag.T), out_i)
        return (out_r + 1j * out_i).T

    def _parts(self, speed: float):
        """Band parts with the supports at ``speed`` (rad/s), and their transpose."""
        from rubrotor.linear.band import _support_values

        _, _, k, c = _support_values(self.system, np.array([speed]))
        parts = self.parts._replace(sup_k=k, sup_c=c)
        return parts, parts._replace(g=-parts.g, sup_row=parts.sup_col, sup_col=parts.sup_row)

    def _followed(self, basis, speed: float):
        """Every mode ``basis`` follows, at ``speed`` (rad/s), exact: ``(lam, phi, u, psi,
        cond)`` with right displacement vectors ``phi`` (k, n), left rows ``u`` (k, n) scaled
        so that ``u (2 lam M + D) phi = 1`` and first-order left vectors ``psi`` (k, 2 n).

        The projection on the anchor's basis follows the modes (eigenvalues to ~1e-7, vectors
        to ~1e-4 at 2 % from the anchor); one Newton step on the full quadratic eigenproblem
        (right vectors, ``T(lam) phi = 0``, and left ones, ``u T(lam) = 0``, on the transposed
        problem) makes them exact to rounding. With that scaling of ``u`` the first-order left
        vector is ``[u (lam M + D), u M]`` and the modal input row is ``U = u``.
        """
        from rubrotor.core.banded import _derivative_apply, newton_pairs

        dK, dC = self._supports(speed, basis.speed0)
        lam0, Vq0, U0, _, cond = basis.modes(dK, dC, speed)
        n = self.M.shape[0]
        w = np.where(lam0.imag == 0.0, 1.0, 2.0)
        parts, parts_t = self._parts(speed)
        phi, u = np.ascontiguousarray((Vq0 / w[None, :]).T), np.ascontiguousarray(U0)
        lam = lam0
        for _ in range(NEWTON_STEPS):
            lam = newton_pairs(parts, parts_t, speed, lam, phi, u)
        if not np.all(np.abs(lam - lam0) <= NEWTON_START * np.abs(lam0)):
            raise InputError("speed", speed, "a speed where the rotor's modes can be followed "
                             "(Newton moved a followed mode too far)")  # fmt: skip
        lam = np.where(lam0.imag == 0.0, lam.real + 0j, lam)
        dphi, du = np.empty(n, complex), np.empty(n, complex)
        psi = np.empty((lam.size, 2 * n), complex)
        for j in range(lam.size):
            _derivative_apply(parts, 0, speed, lam[j], phi[j], dphi)
            u[j] /= u[j] @ dphi
            _derivative_apply(parts_t, 0, speed, lam[j], u[j], du)
            psi[j, :n] = du
        um = self._mass(u)
        psi[:, :n] -= lam[:, None] * um
        psi[:, n:] = um
        return lam, phi, u, psi, cond

    def rotor_modes(self, speed: float) -> tuple[Modes, np.ndarray]:
        """Kept rotor modes at ``speed`` (rad/s) and the static deflection ``q_s`` (m, rad).

        The ``keep`` lowest ``|lam|`` of the followed modes (:meth:`_followed`), as the dense
        reduction keeps them. ``Rq``, ``Rv`` of the returned :class:`Modes` are exact on forces
        at the contact stations (``Rq B B^T``; nodal stations have ``B^T B = I``); ``Kinv`` is
        None.
        """
        basis = self._anchor(speed)
        lam, phi, u, psi, cond = self._followed(basis, speed)
        low = np.argsort(np.abs(lam), kind="stable")[: self.keep]
        lam, phi, u, psi = lam[low], phi[low], u[low], psi[low]
        Vq = phi.T * np.where(lam.imag == 0.0, 1.0, 2.0)[None, :]
        st = self._static(speed)
        m = self.Bmat.shape[1]
        ub = u @ self.Bmat
        RqB = st[:, :m] + np.real((Vq / lam[None, :]) @ ub)
        RvB = np.real(Vq @ ub)
        modes = Modes(lam, Vq, u, RqB @ self.Bmat.T, RvB @ self.Bmat.T, None, cond,
                      basis.R.shape[1], psi)  # fmt: skip
        return modes, st[:, m]

    def plant(self, speed: float) -> Plant:
        """The plant at ``speed`` (rad/s), as :func:`build_plant` would give it (dense)."""
        speed = float(speed)
        base, B, orow = self.base, self.Bmat, self.orow
        modes, q_s = self.rotor_modes(speed)
        nsr = self.keep
        lam = np.concatenate([modes.lam, base.lam[nsr:]])
        beta = base.beta.copy()
        beta[:nsr] = modes.U @ B
        Cd = base.contacts.Cd.copy()
        Cd[:, :nsr] = B.T @ modes.Vq
        RqB, RvB = modes.Rq @ B, modes.Rv @ B
        Q = self._particular(speed)
        Pu = B.T @ Q
        cp = base.contacts.cp.copy()
        cp[:, 7] = self.radii * speed
        contacts = base.contacts._replace(
            Cd=np.ascontiguousarray(Cd), Cv=np.ascontiguousarray(Cd * lam[None, :]),
            Rd=B.T @ RqB, Rv=B.T @ RvB, Pu=Pu, Pv=1j * speed * Pu, d0=B.T @ q_s - self.offs,
            cp=cp,
        )  # fmt: skip
        Od = base.outputs.Od.copy()
        Od[:, :nsr] = orow @ modes.Vq
        outputs = base.outputs._replace(
            Od=Od, Ov=Od * lam[None, :], ORd=orow @ RqB, ORv=orow @ RvB, OPu=orow @ Q,
            OPv=1j * speed * (orow @ Q), Od0=orow @ q_s,
        )  # fmt: skip
        return dataclasses.replace(
            base, lam=lam, beta=beta, contacts=contacts, outputs=outputs,
            y0=np.zeros(lam.size, complex), rotor=modes, q_static=q_s, q_unbalance=Q,
            speed=speed,
        )  # fmt: skip
