"""Named structures the compiled engine kernels read (:mod:`rubrotor.core.engine`).

They live outside ``rubrotor.core`` (which imports only numpy and numba); numba reads any
named tuple of arrays by field name.
"""

from collections import namedtuple

__all__ = ["Steps", "Contacts", "Outputs", "Drive", "Control", "Plan", "State", "Span", "Sink"]

Steps = namedtuple(
    "Steps", ["E", "G0", "G1", "BT", "CdE", "CvE", "CdG0b", "CvG0b", "Sd", "Sv", "rot", "h"]
)
"""Per level ``l`` (step ``h_l = h_0 / 2^l``): ``E`` (L, ns) ``e^{lam h}``; ``G0, G1`` (L, ns)
``h (phi1 - phi2)`` and ``h phi2`` (s); ``BT`` (m, ns) the modal input ``beta`` transposed; ``CdE, CvE`` (L, m, ns) contact rows times ``E``;
``CdG0b, CvG0b`` (L, m, m) real contact response to ``F_n``; ``Sd, Sv`` (L, m, m) real
sensitivities to ``F_{n+1}``; ``rot`` (L,) ``e^{i Omega h}``; ``h`` (L,) steps (s)."""

Contacts = namedtuple("Contacts", ["Cd", "Cv", "Rd", "Rv", "Pu", "Pv", "d0", "cp", "max_disp"])
"""``Cd, Cv`` (m, ns) rows of relative displacement/velocity; ``Rd, Rv`` (m, m) residual
feed-through; ``Pu, Pv`` (m,) unbalance phasors (``Re(Pu z)``); ``d0`` (m,) static relative
displacement (m) minus stator offset; ``cp`` (nc, 10) packed laws; ``max_disp`` (m) divergence."""

Outputs = namedtuple("Outputs", ["Od", "Ov", "ORd", "ORv", "OPu", "OPv", "Od0", "Sd", "Sv", "flex"])
"""Output station rows (2 S, ns), their residual (2 S, m), unbalance phasors and static parts
(2 S,); stator rows ``Sd, Sv`` (m, ns); ``flex`` (nc,) 1.0 for a flexible stator."""

Drive = namedtuple("Drive", ["lam", "Bp", "Bm", "omega0", "alpha", "on"])
"""Unbalance as an input at a varying speed ``Omega = omega0 + alpha t`` (rad/s, rad/s^2):
``Bp = U b / 2``, ``Bm = U conj(b) / 2`` (ns,) with ``b`` the complex unbalance load per unit
``Omega^2`` (kg m); ``lam`` (ns,) the modes; ``on`` 1.0 to use it."""

Control = namedtuple("Control", ["on", "rtol", "atol", "a_f", "errc"])
"""Adaptive step control: ``on`` (1.0 adaptive), ``rtol`` (1), ``atol`` (m), ``a_f`` the
direct contact acceleration per N (m/(s^2 N)), ``errc`` (L,) displacement per N of a
zero- against first-order hold at each level (m/N)."""

Plan = namedtuple(
    "Plan",
    ["lam", "BT", "Wd", "Wv", "Ca", "EH", "H", "J", "hmin", "tol_x", "have", "tab", "order",
     "tab4"],
)  # fmt: skip
"""The adaptive kernel's plan (:mod:`rubrotor.core.engine_adaptive`): modes ``lam`` (ns,)
(1/s), ``BT`` (m, ns) modal input transposed, ``Wd, Wv`` (m, m, ns) ``Cd_rj beta_jc`` and
``Cv_rj beta_jc``, ``Ca`` (m, ns) ``|Cd_rj lam_j^2|`` (look-ahead bound), ``EH`` (ns,)
``e^{lam H}``, ``H`` the output spacing (s), ``J`` the finest level (``hmin = H / 2^J``, s),
``tol_x`` (m) the gap at which an onset counts as located, ``have`` (L,) int flags and ``tab``
the per-level coefficient tables ``(E, G0, G1, CdE, CvE, Q0d, Q0v, Sd, Sv)`` filled on first use
(row ``L - 1`` for a non-dyadic step); ``order`` 2 (force held linear over a contact step) or
4 (quadratic, collocation at ``0, h/2, h``) and ``tab4`` its tables ``(E, Em, W, CdE, CvE,
CdEm, CvEm, P0d, P0v, S2d, S2v)`` (:func:`rubrotor.core.engine_adaptive._fill4`)."""

State = namedtuple("State", ["y", "F", "Fp", "dprev", "clock", "istate", "stats"])
"""The engine kernels' state, updated in place: ``y`` (ns,) complex modal coordinates, ``F``,
``Fp`` (m,) current and previous contact forces (N), ``dprev`` (nc,) last radial displacements
(m), ``clock`` the fixed-step kernel's ``[z]`` unbalance phasor or the adaptive kernel's ``T_*``
slots (time s, previous step s, level, counters), ``istate`` the ``I_*`` counters and status,
``stats`` the fixed-step kernel's ``[h_prev]`` (s)."""

Span = namedtuple("Span", ["n_samples", "save_every", "offset", "omega", "t0"])
"""What one kernel call covers: ``n_samples`` to write from column ``offset``, every
``save_every`` steps, at spin ``omega`` (rad/s), the run starting at ``t0`` (s)."""

Sink = namedtuple("Sink", ["out", "ys", "events"])
"""Where the kernels write: samples ``out`` (channels, samples), modal states ``ys`` (samples,
ns; empty when not kept) and contact events ``events`` (cap, 2)."""


def span(n_samples, save_every, offset, omega, t0=0.0) -> Span:
    """A :class:`Span` with the scalar types the kernels are compiled for (int, float)."""
    return Span(int(n_samples), int(save_every), int(offset), float(omega), float(t0))
