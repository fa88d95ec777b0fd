"""Pseudo-arclength continuation of periodic orbits in any scenario key.

Unknowns ``z = (x / s_x, p / s_p)``: the shooting state (see ``rubrotor.orbits.shooting``) and the
continued key's value, scaled by their magnitudes at the start so that the arclength weighs
both alike. Residual ``G(x, p) = P(x; p) - x`` (the stroboscopic map at ``p``, a prepared
:class:`rubrotor.orbits.shooting._Map` per key value; for the speed keys only its speed-dependent
coefficients are rebuilt); ``G_x`` from the map's variational equations (exact, one run),
``G_p`` by central differences in ``p``; tangent = null vector of ``[G_x s_x, G_p s_p]`` (SVD,
oriented along the previous one); predictor ``z + ds t``; corrector = quasi-Newton (Broyden)
on ``[G; t . (z - z_pred)] = 0`` from the previous point's Jacobian, full Newton if that
fails; ``ds`` halves on failure and grows by 1.5 after a quick corrector. On a general rotor,
where a new key value costs a plant (a few ms) and ``G_x`` is one compiled variational run
(1 ms), the corrector is Newton in the state at the predicted key value (``_fixed_key``: two
plants per point with the key's forward difference), and where that fails (near a fold) the
pseudo-arclength chord with the exact ``G_x`` at every iterate. Optionally each point
is Richardson-extrapolated to zero step from the maps of ``N`` and ``2 N`` steps
(``_extrapolate``). A general rotor's map (``rubrotor.orbits.general_map``) has its modes
aligned to the first value's; in a speed key only its speed-dependent parts are updated
(``rubrotor.orbits.speed_family``), in any other key it is rebuilt. Circular orbits of the
axisymmetric rotor are continued on the rotating frame's field instead (``_SyncProblem``).

Bifurcations, between consecutive points, from sign changes of test functions:

* fold: the parameter component of the tangent. At contact onset, where the no-contact and
  rub branches meet in a corner, the branch turns too, and the multipliers jump (the map is
  not smooth there), so other test functions may change sign at the same step: that corner is
  reported once, as ``"contact-onset"`` at the grazing value (``grazing_value``), not as a
  fold next to a Neimark-Sacker point;
* period doubling: the sign of ``det(M + I)`` (a real multiplier crosses -1);
* Neimark-Sacker: the sign of the bialternate product ``prod_{i<j} (mu_i mu_j - 1)`` (a
  complex pair crosses the unit circle);
* branch point: the determinant of the augmented Jacobian ``[G_z; t]``.

Each is located on the arclength from the earlier point (predict, correct, evaluate): a fold
as the extremum of the key value (Brent's bounded search), the others as the root of the test
function's value by bracketing secant (Illinois) steps to :data:`LOCATE_TOL` of arclength.

Step size: with ``ds_max=None`` (the default) the arclength step follows the branch's
turning: after each point ``ds`` is scaled by ``ANGLE_TARGET / angle`` (clipped to 0.5 .. 2,
never grown after a slow corrector), the angle being the one between successive tangents, up
to ``AUTO_DS_MAX`` and to a key change of ``1 / RANGE_STEPS`` of the range (bifurcations
seen only in the multipliers must not share a step); so the step grows where the branch is straight and shrinks at folds,
and the default number of points reaches the end of the range. A given ``ds_max`` keeps the
fixed rule (grow by 1.5 after a quick corrector, up to ``ds_max``). The branch says why it
stopped (``Branch.stopped``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.optimize

from rubrotor.errors import InputError
from rubrotor.modelling import model_of
from rubrotor.orbits.shooting import (
    STEPS_PER_REVOLUTION,
    _Map,
    multipliers_of,
    prepared_map,
    shoot,
    state_vector,
    vector_state,
)
from rubrotor.orbits.synchronous import Field, is_circular, synchronous_orbit, unsupported

BIFURCATIONS = ("fold", "period-doubling", "neimark-sacker", "branch-point", "contact-onset")

STOPS = {
    "range": "reached the end of the range",
    "points": "used its largest number of points",
    "step": "the corrector failed down to the smallest step (1e-8)",
    "met": "met the branch it was born from again",
    "interrupted": "was interrupted by the user (Ctrl-C); the points so far are kept",
}
"""Why a branch ended (``Branch.stopped``) and what that means."""

ANGLE_TARGET = 0.1
"""Angle (rad) between successive tangents the automatic step aims at."""

AUTO_DS_MAX = 5.0
"""Largest automatic arclength step (scaled units)."""

RANGE_STEPS = 20
"""The automatic step moves the key by at most ``1 / RANGE_STEPS`` of the range: bifurcations
that do not bend the branch (period doubling, Neimark-Sacker) show only in the multipliers, and
two of them inside one step would cancel in the sign tests."""


@dataclass(frozen=True)
class BranchPoint:
    """One point of a branch: key value, state, largest radius (m), multipliers, stability."""

    value: float
    state: object
    max_radius_m: float
    multipliers: np.ndarray
    stable: bool


@dataclass(frozen=True)
class Bifurcation:
    """A located bifurcation: ``type`` (one of :data:`BIFURCATIONS`), key ``value``, radius.

    ``max_radius_m`` (m) is interpolated between the two branch points that bracket it, except
    at contact onset (a fold at a grazing value), where it is the clearance.
    """

    type: str
    value: float
    max_radius_m: float = float("nan")


@dataclass(frozen=True)
class Branch:
    """A continued branch of periodic orbits (the result of :func:`rubrotor.orbits.continuation.continue_orbit`).

    Attributes
    ----------
    key : str
        The continued scenario key.
    k : int
        Revolutions per period.
    points : tuple of BranchPoint
    bifurcations : tuple of Bifurcation
    grazings : tuple of float
        Key values where the branch's contact status changes (contact onset: the free orbit
        grazes the stator), located by ``grazing_value``.
    method : str
        ``"shooting"`` or ``"synchronous"`` (rotating-frame equilibria), see
        :func:`rubrotor.orbits.continuation.continue_orbit`.
    stopped : str
        Why the branch ended, a key of ``STOPS``; anything but ``"range"`` (or ``"met"``
        for a switched branch) means it stopped before the end of the asked range.
    """

    key: str
    k: int
    points: tuple
    bifurcations: tuple
    grazings: tuple = ()
    method: str = "shooting"
    stopped: str = "range"

    @property
    def complete(self) -> bool:
        """Whether the branch ended where it should: at the range's end (or, switched, where
        it met its parent branch), not for lack of points or of a converging step."""
        return self.stopped in ("range", "met")

    def summary(self) -> dict:
        """The JSON summary of the CLI (values in the key's units, radii in m)."""
        return {
            "points": [
                {
                    "value": p.value,
                    "max_radius_m": p.max_radius_m,
                    "stable": p.stable,
                    "multipliers_abs_max": float(np.max(np.abs(p.multipliers))),
                }
                for p in self.points
            ],
            "bifurcations": [{"type": b.type, "value": b.value} for b in self.bifurcations],
            "stopped": self.stopped,
            "stopped_because": STOPS[self.stopped],
            "complete": self.complete,
        }

    def dataset(self):
        """The branch as an xarray Dataset (dimension ``point``; states, multipliers, radii)."""
        import xarray as xr

        mu = np.array([p.multipliers for p in self.points])
        states = np.array([state_vector(p.state) for p in self.points])
        return xr.Dataset(
            {
                "value": ("point", [p.value for p in self.points], {"long_name": self.key}),
                "max_radius": ("point", [p.max_radius_m for p in self.points], {"units": "m"}),
                "stable": ("point", np.array([p.stable for p in self.points], np.int8)),
                "multipliers_real": (("point", "multiplier"), mu.real),
                "multipliers_imag": (("point", "multiplier"), mu.imag),
                "state": (("point", "state_component"), states, {"units": "m, m/s"}),
                "bifurcation_value": ("bifurcation", [b.value for b in self.bifurcations]),
                "bifurcation_type": ("bifurcation", [b.type for b in self.bifurcations]),
                "grazing_value": ("grazing", list(self.grazings), {"long_name": "contact onset"}),
            },
            attrs={
                "key": self.key,
                "revolutions_per_period": self.k,
                "method": self.method,
                "stopped": self.stopped,
            },  # fmt: skip
        )


def branches_dataset(branches) -> object:
    """Several branches of one key in one Dataset (e.g. a branch and its period-doubled one).

    The points of all branches follow one another along ``point``; ``branch`` (index into
    ``branches``) and ``revolutions_per_period`` say which branch each point and each
    bifurcation (``bifurcation_branch``) belongs to. With one branch it holds what
    :meth:`Branch.dataset` holds plus those labels.
    """
    import xarray as xr

    parts = [br.dataset() for br in branches]
    data = {}
    for dim in ("point", "bifurcation", "grazing"):
        for name in (n for n in parts[0].data_vars if parts[0][n].dims[0] == dim):
            var = parts[0][name]
            joined = np.concatenate([d[name].values for d in parts])
            data[name] = (var.dims, joined, var.attrs)
    counts = {"point": "points", "bifurcation": "bifurcations", "grazing": "grazings"}
    for dim, field in counts.items():
        label = "branch" if dim == "point" else f"{dim}_branch"
        data[label] = (dim, np.repeat(np.arange(len(branches)),
                                      [len(getattr(br, field)) for br in branches]))  # fmt: skip
    data["revolutions_per_period"] = (
        "point", np.repeat([br.k for br in branches], [len(br.points) for br in branches]),
        {"units": "revolutions"},
    )  # fmt: skip
    attrs = {"key": branches[0].key, "branches": len(branches),
             "methods": ", ".join(br.method for br in branches),
             "stopped": ", ".join(br.stopped for br in branches)}  # fmt: skip
    return xr.Dataset(data, attrs=attrs)


SPEED_KEYS = ("speed.critical_multiple", "speed.rad_per_s", "speed.hz", "speed.rpm")
"""Keys the spin speed is proportional to: continued by ``_Map.at_speed`` (no re-validation
of the scenario, no critical-speed solve, the modal system kept unless gyroscopic)."""


class _Problem:
    """Residual and Jacobian of the continuation in scaled unknowns.

    ``tol``: the corrector's relative tolerance; ``h_rel``: the relative increment of the
    key's central difference. A general rotor's plant at each key value (rebuilt, or updated
    in a speed key) carries ~2e-8 of relative noise from one value to the next (its residual
    flexibility is a small difference of two large ones, measured on ``seal_rub.toml``): there
    the corrector stops at 1e-6 and the key's difference uses 1e-4.
    """

    tol = None  # set below, after CORRECTOR_TOL
    h_rel = 1e-6
    central = True  # central differences in the key (else forward: one map fewer)
    exact_gx = False  # the corrector takes the exact G_x at every iterate (a cheap one)

    def __init__(self, scenario, key, k, steps, sx, sp, richardson=False):
        self.scenario, self.key, self.k, self.steps = scenario, key, k, steps
        self.sx, self.sp, self.richardson = sx, sp, richardson
        self._maps: dict = {}
        self._radius: dict = {}

    def at(self, p):
        """The scenario at key value ``p`` (cached: rebuilding one solves its critical speeds;
        :class:`rubrotor.orbits.points.PointScenarios` solves them once for the unswept shaft)."""
        from rubrotor.orbits.points import PointScenarios

        p = float(p)
        cache = self.__dict__.setdefault("_at", {})
        if "_points" not in self.__dict__:
            self._points = PointScenarios(self.scenario, [self.key])
        if p not in cache:
            if len(cache) > 64:
                cache.clear()
            cache[p] = self._points([p])
        return cache[p]

    def map_at(self, p, steps=None):
        """The prepared map at key value ``p`` (cached; speed keys only rescale the speed).

        ``steps`` (default the problem's) per revolution: Richardson's second map.
        """
        p, steps = float(p), steps or self.steps
        cache = self._maps
        if (p, steps) not in cache:
            if len(cache) > 64:
                cache.clear()
            bases = self.__dict__.setdefault("_bases", {})
            if steps not in bases and self.key in SPEED_KEYS:
                sc = self.at(self.sp)
                bases[steps] = (prepared_map(sc, self.k, steps), sc.speed / self.sp)
            if steps in bases:
                cache[p, steps] = bases[steps][0].at_speed(bases[steps][1] * p)
            elif model_of(self.scenario).maps == "general":  # coordinates aligned with the first
                first = self.__dict__.setdefault("_first", {})
                if steps not in first:
                    first[steps] = prepared_map(self.at(self.sp), self.k, steps)
                cache[p, steps] = prepared_map(self.at(p), self.k, steps, first[steps])
            else:
                cache[p, steps] = prepared_map(self.at(p), self.k, steps)
        return cache[p, steps]

    def residual(self, z, steps=None):
        """Scaled ``G / s_x`` alone (one run of the map)."""
        x, p = self.unscale(z)
        return (self.map_at(p, steps).run(x)[0] - x) / self.sx

    def residual_jacobian(self, z, steps=None):
        """Scaled ``G / s_x`` and its exact scaled ``G_x`` (one variational run of the map)."""
        x, p = self.unscale(z)
        px, jac, _ = self.map_at(p, steps).run(x, True)
        return (px - x) / self.sx, (jac - np.eye(x.size)) * self.sx / self.sx[:, None]

    def unscale(self, z):
        return z[:-1] * self.sx, z[-1] * self.sp

    def evaluate(self, z, steps=None):
        """Scaled ``G / s_x``, its Jacobian in ``z`` and the monodromy matrix at ``z``.

        The monodromy comes from the map's variational equations (one run); the derivative in
        the key by central differences of the map at ``p +- h_rel |p|`` (forward, at
        ``p + h_rel |p|``, where ``central`` is False). The largest radius of the run is kept
        for :meth:`radius`.
        """
        x, p = self.unscale(z)
        px, jac, rmax = self.map_at(p, steps).run(x, True)
        self._radius = {z.tobytes(): rmax}
        h = self.h_rel * abs(p)
        up = self.map_at(p + h, steps).run(x)[0]
        if self.central:
            gp = (up - self.map_at(p - h, steps).run(x)[0]) / (2 * h)
        else:
            gp = (up - px) / h
        gx = (jac - np.eye(x.size)) * self.sx / self.sx[:, None]
        gz = np.column_stack([gx, gp * self.sp / self.sx])
        return (px - x) / self.sx, gz, jac

    def polish(self, z, gz, jac, t):
        """A corrected point refined further where that is cheap (here: as it is)."""
        return z, gz, jac

    def radius(self, z) -> float:
        """Largest contact-station radius (m) of the orbit through ``z`` (kept by evaluate)."""
        got = self._radius.get(z.tobytes())
        if got is None:
            got = self._radius_at(*self.unscale(z))
        return got

    def _radius_at(self, x, p) -> float:
        return self.map_at(p).run(x)[2]


class _SyncProblem(_Problem):
    """The same unknowns with the rotating-frame field as residual (synchronous orbits).

    ``G(x, p) = f(x; p)``, the field of :class:`rubrotor.orbits.synchronous.Field` (per radian of
    spin, in the units of ``x``): its zeros are the circular orbits, exact to rounding. ``G_x``
    is the field's analytic Jacobian ``J``, the monodromy handed to the test functions is
    ``exp(J T)`` (same multipliers, same bifurcation tests), ``G_p`` by central differences.
    No time steps: ``steps`` is ignored and there is nothing to extrapolate.
    """

    def field_at(self, p):
        """The field at key value ``p`` (cached; speed keys only rescale the speed)."""
        p = float(p)
        cache = self.__dict__.setdefault("_fields", {})
        if p not in cache:
            if len(cache) > 64:
                cache.clear()
            if self.key in SPEED_KEYS:
                if "_base_field" not in self.__dict__:
                    sc = self.at(self.sp)
                    self._base_field = (Field(_Map(sc, 1, 16)), sc.speed / self.sp)
                base, ratio = self._base_field
                cache[p] = base.at_speed(ratio * p)
            else:
                cache[p] = Field(_Map(self.at(p), 1, 16))
        return cache[p]

    def residual(self, z, steps=None):
        x, p = self.unscale(z)
        return self.field_at(p).evaluate(x)[0] / self.sx

    def evaluate(self, z, steps=None):
        x, p = self.unscale(z)
        field = self.field_at(p)
        f, jf, radius = field.evaluate(x, True)
        self._radius = {z.tobytes(): radius}
        h = 1e-6 * abs(p)
        gp = (self.field_at(p + h).evaluate(x)[0] - self.field_at(p - h).evaluate(x)[0]) / (2 * h)
        gx = jf * self.sx / self.sx[:, None]
        gz = np.column_stack([gx, gp * self.sp / self.sx])
        return f / self.sx, gz, field.monodromy(jf, self.k)

    def _radius_at(self, x, p) -> float:
        return self.field_at(p).evaluate(x)[2]

    def polish(self, z, gz, jac, t):
        """Newton on ``[G; t . (z - z_0)] = 0`` to rounding (the corrector stops at
        :data:`CORRECTOR_TOL`; a field evaluation costs microseconds, so each point is refined
        until the step is below ``4 eps |z|``, at most three steps)."""
        z0, a = z, np.vstack([gz, t])
        for _ in range(3):
            g = np.concatenate([self.residual(z), [t @ (z - z0)]])
            dz = np.linalg.solve(a, -g)
            z = z + dz
            if np.linalg.norm(dz) <= 4 * np.finfo(float).eps * np.linalg.norm(z):
                break
        _, gz, jac = self.evaluate(z)
        return z, gz, jac


def _tangent(gz, previous):
    t = np.linalg.svd(gz)[2][-1]
    if previous is not None and t @ previous < 0:
        t = -t
    return t


def _fixed_key(prob, z_pred, ds, tol, max_iter=6):
    """Newton in the state alone at the predictor's key value: ``(z, gz, jac, iterations)``
    or None.

    For a problem with a cheap exact ``G_x`` (``prob.exact_gx``: a general rotor, whose map at
    a new key value costs a plant and a monodromy only a compiled run), where the branch is a
    graph over the key the point at the predicted key value is found with that one map: its
    arclength from the last point differs from ``ds`` by the predictor's error, which does not
    matter. Refused (None) when Newton does not converge in ``max_iter`` steps or lands
    farther than ``ds / 2`` from the predictor (near a fold, where the point at that key value
    is far or missing): the pseudo-arclength corrector then takes over.
    """
    n = z_pred.size - 1
    z = z_pred.copy()
    for it in range(1, max_iter + 1):
        try:
            r, gx = prob.residual_jacobian(z)
            dx = np.linalg.solve(gx, -r)
        except (InputError, np.linalg.LinAlgError):
            return None
        z[:n] += dx
        if not np.all(np.isfinite(z)) or np.linalg.norm(z - z_pred) > 0.5 * abs(ds):
            return None
        if np.linalg.norm(dx) < tol * max(1.0, np.linalg.norm(z)):
            try:
                g, gz, jac = prob.evaluate(z)
            except InputError:
                return None
            return (z, gz, jac, it) if np.linalg.norm(g) < tol * np.linalg.norm(z) else None
    return None


def _chord(prob, z_pred, t, gz0, tol=None, max_iter=12, ds=None):
    """Quasi-Newton (Broyden) iterations from the previous point's Jacobian ``gz0``.

    One map run each: the augmented Jacobian ``[G_z; t]`` starts as the previous point's and
    takes Broyden's rank-one update after every step (its last row, the linear arclength
    condition, stays exact), which turns the chord's linear convergence superlinear. Returns
    ``(z, gz, jac, iterations)`` when the step and the scaled residual at the final Jacobian
    evaluation are below ``tol``, else None (the caller then runs full Newton).
    """
    tol = prob.tol if tol is None else tol
    if prob.exact_gx and ds is not None:
        out = _fixed_key(prob, z_pred, ds, tol)
        if out is not None:
            return out
    a = np.vstack([gz0, t])
    z = z_pred.copy()
    g_old = dz = None
    n = z.size - 1
    for it in range(1, max_iter + 1):
        try:
            if prob.exact_gx:
                r, gx = prob.residual_jacobian(z)
            else:
                r = prob.residual(z)
            g = np.concatenate([r, [t @ (z - z_pred)]])
        except InputError:
            return None
        if prob.exact_gx:  # exact G_x; the key's column by the secant along the last step
            if dz is not None and abs(dz[n]) > 1e-3 * np.linalg.norm(dz):
                a[:n, n] = (g[:n] - g_old[:n] - gx @ dz[:n]) / dz[n]
            a[:n, :n] = gx
        elif dz is not None:
            a += np.outer(g - g_old - a @ dz, dz) / (dz @ dz)
        dz = np.linalg.solve(a, -g)
        if prob.exact_gx and np.linalg.norm(dz) < tol * max(1.0, np.linalg.norm(z)):
            # converged: the last Newton step at this key value (its map is prepared), off the
            # arclength plane by less than tol
            z = z.copy()
            z[:n] += np.linalg.solve(gx, -g[:n])
            try:
                g, gz, jac = prob.evaluate(z)
            except InputError:
                return None
            return (z, gz, jac, it) if np.linalg.norm(g) < tol * np.linalg.norm(z) else None
        z = z + dz
        g_old = g
        if not np.all(np.isfinite(z)):
            return None
        scale = max(1.0, np.linalg.norm(z))
        if np.linalg.norm(dz) < tol * scale:
            try:
                g, gz, jac = prob.evaluate(z)
            except InputError:
                return None
            return (z, gz, jac, it) if np.linalg.norm(g) < tol * scale else None
    return None


CORRECTOR_TOL = 1e-11
"""Relative step and scaled residual at which the corrector stops (dimensionless)."""
_Problem.tol = CORRECTOR_TOL


def _correct(prob, z_pred, t, tol=None, max_iter=8):
    """Newton on ``[G; t . (z - z_pred)]``; returns ``(z, gz, jac, iterations)`` or None.

    Converged when both the step and the scaled residual are below ``tol`` (relative): near a
    non-smooth point the difference Jacobian is smeared and Newton only converges linearly, so
    a small step alone does not mean a small error.
    """
    tol = prob.tol if tol is None else tol
    z = z_pred.copy()
    small_step = False
    for it in range(max_iter + 1):
        try:
            g, gz, jac = prob.evaluate(z)
        except InputError:
            return None
        scale = max(1.0, np.linalg.norm(z))
        if small_step and np.linalg.norm(g) < tol * scale:
            return z, gz, jac, it
        if it == max_iter:
            return None
        a = np.vstack([gz, t])
        rhs = -np.concatenate([g, [t @ (z - z_pred)]])
        dz = np.linalg.solve(a, rhs)
        z = z + dz
        if not np.all(np.isfinite(z)):
            return None
        small_step = np.linalg.norm(dz) < tol * scale
    return None


def _tests(gz, t, jac):
    """Test functions: t_p, sign det(M + I), sign prod_{i<j}(mu_i mu_j - 1), sign det [G_z; t].

    A fifth entry is the number of multipliers outside the unit circle (see :func:`_changed`).

    ``det(M + I) = prod (mu_i + 1)`` changes sign exactly when a real multiplier crosses -1
    (a complex pair contributes ``|mu + 1|^2 > 0``, so a pair that meets on the real axis
    outside the circle is no period doubling); the bialternate product
    ``prod_{i<j} (mu_i mu_j - 1)`` vanishes when a complex pair crosses the unit circle
    (``mu conj(mu) = 1``, Neimark-Sacker). Both are symmetric functions of the multipliers of
    a real matrix, hence real and continuous through multiplier collisions.
    """
    mu = np.linalg.eigvals(jac)
    pd = _product_sign(mu + 1)
    i, j = np.triu_indices(mu.size, 1)
    ns = _product_sign(mu[i] * mu[j] - 1)
    out = np.sum(np.abs(mu) > 1)
    return np.array([np.sign(t[-1]), pd, ns, np.sign(np.linalg.det(np.vstack([gz, t]))), out])


def _product_sign(x: np.ndarray) -> float:
    """Sign of the real part of ``prod(x)`` (real for the symmetric functions of :func:`_tests`)
    as the product of ``x / |x|``: the product itself overflows with large multipliers (a
    scenario far off scale) where its sign is still defined."""
    a = np.abs(x)
    if np.any(a == 0):
        return 0.0
    return float(np.sign(np.prod(x / a).real))


def _changed(sig, sig1):
    """Which of :data:`BIFURCATIONS` happened between two signatures.

    A sign change of the bialternate product with no change of the number of multipliers
    outside the unit circle is a neutral saddle (a real pair with ``mu_i mu_j = 1``), not a
    Neimark-Sacker bifurcation.
    """
    hit = sig1[:4] != sig[:4]
    hit[2] &= sig1[4] != sig[4]
    return hit


LOCATE_TOL = 100 * CORRECTOR_TOL
"""Width (scaled arclength, ~ relative key value) to which a test function's root is bracketed.

Tied to the corrector: the corrected points carry a relative error ~ ``CORRECTOR_TOL`` and the
difference derivative in the key one of ``eps / h + h^2 ~ 1e-10`` (the monodromy itself is
exact to rounding), so the test functions are known to ~1e-10 relative; a hundred times the
corrector tolerance is the finest bracket the secant can still order reliably.
"""


def _test_value(prob, z0, t0, s, index):
    """The continuous test function ``index`` at arclength ``s`` from ``z0`` (None: no point).

    1: ``det(M + I)`` (period doubling), 2: the bialternate product ``prod_{i<j}(mu_i mu_j - 1)``
    (Neimark-Sacker), 3: ``det [G_z; t]`` (branch point); returns ``(value, key value)``.
    """
    out = _correct(prob, z0 + s * t0, t0)
    if out is None:
        return None
    z, gz, jac, _ = out
    if index == 3:
        value = np.linalg.det(np.vstack([gz, _tangent(gz, t0)]))
    else:
        mu = np.linalg.eigvals(jac)
        if index == 1:
            value = np.prod(mu + 1).real
        else:
            i, j = np.triu_indices(mu.size, 1)
            value = np.prod(mu[i] * mu[j] - 1).real
    return float(value), float(prob.unscale(z)[1])


def _locate(prob, z0, t0, ds, index):
    """Root of test function ``index`` on the arclength ``[0, ds]`` from ``z0``; returns ``p``.

    Illinois (bracketing secant) iterations on the test function's value, each a corrected
    point on the hyperplane normal to ``t0``, until the bracket is narrower than
    :data:`LOCATE_TOL`; a failed corrector or a secant outside the bracket bisects instead.
    Superlinear on the smooth test functions, so the location no longer depends on where the
    continuation's steps happened to bracket it (that sign bisection stopped on the step).
    """
    ends = [_test_value(prob, z0, t0, s, index) for s in (0.0, ds)]
    if None in ends:
        return float(prob.unscale(z0)[1])
    lo, hi = [0.0, ends[0][0]], [ds, ends[1][0]]
    p_best, side = ends[1][1], 0
    for _ in range(60):
        if abs(hi[0] - lo[0]) < LOCATE_TOL or np.sign(lo[1]) == np.sign(hi[1]):
            break
        s = hi[0] - hi[1] * (hi[0] - lo[0]) / (hi[1] - lo[1])
        if not (min(lo[0], hi[0]) < s < max(lo[0], hi[0])):
            s = 0.5 * (lo[0] + hi[0])
        got = _test_value(prob, z0, t0, s, index)
        if got is None:
            s = 0.5 * (lo[0] + hi[0])
            got = _test_value(prob, z0, t0, s, index)
            if got is None:
                break
        value, p_best = got
        if value == 0.0:
            break
        if np.sign(value) == np.sign(lo[1]):
            lo = [s, value]
            hi[1] *= 0.5 if side == -1 else 1.0  # Illinois: halve the stale end
            side = -1
        else:
            hi = [s, value]
            lo[1] *= 0.5 if side == 1 else 1.0
            side = 1
    return p_best


def _locate_turn(prob, z0, t0, ds, gz0=None, bounds=None):
    """The extremal key value along the arclength in ``[0, ds]`` from ``z0`` (a fold).

    Brent's bounded search of ``p(s)``; also exact at the non-smooth turning point of contact
    onset, where the finite-difference tangent is smeared over the difference increment. Each
    ``p(s)`` by Broyden iterations from ``z0``'s Jacobian ``gz0`` (one map run each), full
    Newton where they fail.
    """
    sign = 1.0 if t0[-1] > 0 else -1.0

    def minus_p(s):
        z = None
        if gz0 is not None:
            try:
                z = _solve_on_plane(prob, z0 + s * t0, t0, np.vstack([gz0, t0]), None,
                                    tol=prob.tol, max_iter=20)  # fmt: skip
            except (InputError, np.linalg.LinAlgError):
                z = None
        if z is None:
            out = _correct(prob, z0 + s * t0, t0, max_iter=20)
            z = None if out is None else out[0]
        return np.inf if z is None else -sign * prob.unscale(z)[1]

    lo, hi = bounds or (0.0, ds)
    res = scipy.optimize.minimize_scalar(
        minus_p, bounds=(lo, hi), method="bounded", options={"xatol": 1e-7 * abs(ds)}
    )
    if bounds is not None and min(res.x - lo, hi - res.x) < 1e-3 * abs(ds):
        return None  # the extremum is not inside the bracket
    return float(-sign * res.fun)


def _richardson_fold(prob, z0, t0, ds, gz0, p_coarse):
    """A fold's key value extrapolated to zero step from its location with ``N`` and ``2 N``.

    The fold of the ``2 N`` map is located the same way (Brent's search of the extremal key
    value on the hyperplanes normal to ``t0``, bracket widened by ``ds / 2`` on each side as
    the fold moves by ``O(h^2)``); with the even error expansion of the scheme ``(4 p_2N -
    p_N) / 3`` is fourth order. If the fine fold is not inside the bracket ``p_coarse`` stays.
    """
    fine = _Problem(prob.scenario, prob.key, prob.k, 2 * prob.steps, prob.sx, prob.sp)
    fine._maps = prob._maps  # cached by (key value, steps): shared
    fine.__dict__["_bases"] = prob.__dict__.setdefault("_bases", {})
    p_fine = _locate_turn(fine, z0, t0, ds, gz0, bounds=(-0.5 * ds, 1.5 * ds))
    return p_coarse if p_fine is None else (4 * p_fine - p_coarse) / 3


def _point(prob, z, jac, gz=None, t=None) -> BranchPoint:
    """The branch point at ``z``; with ``prob.richardson`` extrapolated (``_extrapolate``)."""
    x, p = prob.unscale(z)
    mu = multipliers_of(jac)
    radius = prob.radius(z)
    if prob.richardson:
        z, radius = _extrapolate(prob, z, jac, radius, gz, t)
        x, p = prob.unscale(z)
    state = x.copy() if model_of(prob.scenario).maps == "general" else vector_state(x)
    return BranchPoint(float(p), state, radius, mu, bool(abs(mu[0]) < 1))


def _extrapolate(prob, z, jac, radius, gz=None, t=None):
    """Richardson extrapolation of a branch point (scaled ``z``) and its radius to zero step.

    The exponential scheme with the linear force hold is symmetric (swapping the ends of a
    step and the sign of ``h`` gives the same step, since ``e^z (phi1 - phi2)(-z) = phi2(z)``),
    so on a smooth orbit its error expands in even powers of the step. The point ``z_2`` of
    the branch of the map with twice the steps on the hyperplane through ``z`` normal to the
    tangent ``t`` (default: the same key value) gives ``(4 z_2 - z) / 3`` with an ``O(h^4)``
    error; the hyperplane, not a fixed key value, keeps this regular through folds. ``z_2`` by
    quasi-Newton iterations from ``z`` with ``[G_z; t]`` of the ``steps`` map (within
    ``O(h^2)`` of the fine map's, so each iteration gains about that factor), restarted with
    the fine map's own Jacobian if that fails. Contact onsets and separations inside a step
    break the smooth expansion (partial rub): there the extrapolation is not fourth order.
    """
    n = z.size - 1
    if gz is None or t is None:
        gz = np.column_stack([(jac - np.eye(n)) * prob.sx / prob.sx[:, None], np.zeros(n)])
        t = np.eye(n + 1)[-1]
    fine = 2 * prob.steps
    for a in (gz, None):
        try:
            if a is None:
                a = prob.evaluate(z, fine)[1]
            z2 = _solve_on_plane(prob, z, t, np.vstack([a, t]), fine)
        except InputError:
            continue
        if z2 is not None:
            x2, p2 = prob.unscale(z2)
            r2 = prob.map_at(p2, fine).run(x2)[2]
            return (4 * z2 - z) / 3, (4 * r2 - radius) / 3
    return z, radius


def _solve_on_plane(prob, z0, t, a, steps, tol=1e-12, max_iter=10):
    """``G(z) = 0`` for the map of ``steps`` on ``t . (z - z0) = 0`` by Broyden from ``a``."""
    z, g_old, dz = z0.copy(), None, None
    for _ in range(max_iter):
        g = np.concatenate([prob.residual(z, steps), [t @ (z - z0)]])
        if dz is not None:
            a += np.outer(g - g_old - a @ dz, dz) / (dz @ dz)
        dz = np.linalg.solve(a, -g)
        z, g_old = z + dz, g
        if not np.all(np.isfinite(z)):
            return None
        if np.linalg.norm(dz) <= tol * max(1.0, np.linalg.norm(z)):
            return z
    return None


def _radius(b: Bifurcation, p0: BranchPoint, p1: BranchPoint) -> Bifurcation:
    if np.isfinite(b.max_radius_m):  # known exactly (contact onset: the clearance)
        return b
    w = 0.5 if p1.value == p0.value else (b.value - p0.value) / (p1.value - p0.value)
    r = p0.max_radius_m + min(max(w, 0.0), 1.0) * (p1.max_radius_m - p0.max_radius_m)
    return Bifurcation(b.type, b.value, float(r))


def continue_orbit(scenario, key: str, start: float, stop: float, *, guess=None, k: int = 1,
                   steps: int = STEPS_PER_REVOLUTION, points: int = 200, ds: float = 0.02,
                   ds_max: float | None = None, transient_revolutions: int = 100,
                   richardson: bool = False, method: str = "auto",
                   progress=None) -> Branch:  # fmt: skip
    """Continue a periodic orbit of ``k`` revolutions in ``key`` from ``start`` towards ``stop``.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The base scenario.
    key : str
        Numeric scenario key (``"section.key"``), e.g. ``"speed.critical_multiple"``.
    start, stop : float
        Range of the key (its units); the branch starts at ``start`` and ends where it leaves
        the closed range (its last point corrected onto the bound it crossed) or after
        ``points`` points.
    guess : RotorState, optional
        Guess of the first orbit (default: ``transient_revolutions`` from the steady
        no-contact orbit).
    k, steps
        Revolutions per period and fixed steps per revolution of the map.
    points : int
        Largest number of branch points.
    ds, ds_max : float
        First and largest arclength step (scaled units, dimensionless); ``ds_max=None``
        (default): the step follows the branch's turning (module docstring).
    transient_revolutions : int
        Revolutions from the guess before the first Newton shooting.
    richardson : bool
        Report each point's state and largest radius, and each fold's key value, extrapolated
        to zero step from the maps of ``steps`` and ``2 steps`` per revolution (see
        ``_extrapolate``, ``_richardson_fold``; fourth order on orbits in permanent
        contact or without contact); the multipliers, stability and the other bifurcations
        stay those of the ``steps`` map. Ignored on the synchronous route (exact already).
    method : {"auto", "shooting", "synchronous"}
        ``"shooting"``: the stroboscopic map (any orbit). ``"synchronous"``: circular orbits
        of an axisymmetric rotor without a constant load (no contact or full annular rub) as
        equilibria of the rotating frame, exact to rounding (``rubrotor.orbits.synchronous``);
        refused when the scenario or the start orbit does not allow it. ``"auto"`` (default):
        synchronous when allowed (``k = 1``, no load, the shot start orbit is a circle),
        otherwise shooting.
    progress : callable, optional
        Called after each point as ``progress(n, points, value)`` (count so far, largest
        count, key value).

    Returns
    -------
    Branch
        With ``Branch.stopped`` saying why it ended.
    """
    from rubrotor.scenario.load import as_scenario

    scenario = as_scenario(scenario)
    if not (np.isfinite(start) and np.isfinite(stop)) or start == stop:
        raise InputError("--vary", f"{start}:{stop}", "START:STOP with finite START != STOP")
    if isinstance(points, bool) or not isinstance(points, int) or points < 2:
        raise InputError("points", points, "an integer >= 2")
    sc0 = scenario.with_changes(**{key: float(start)})
    orbit = shoot(sc0, guess, k, steps=steps, transient_revolutions=transient_revolutions)
    if _route(sc0, k, orbit, method) == "synchronous":
        orbit = synchronous_orbit(sc0, orbit.state)
        prob = _problem(scenario, key, k, steps, state_vector(orbit.state), start, _SyncProblem)
    else:
        prob = _problem(scenario, key, k, steps, state_vector(orbit.state), start)
        prob.richardson = bool(richardson)
    z = np.concatenate([state_vector(orbit.state) / prob.sx, [start / abs(start)]])
    g, gz, jac = prob.evaluate(z)
    t = _tangent(gz, None)
    if t[-1] * (stop - start) < 0:
        t = -t
    bounds = (min(start, stop), max(start, stop))
    return _march(prob, z, t, gz, jac, bounds, points, ds, ds_max, progress=progress)


GENERAL_TOL = 1e-6
"""The corrector's tolerance on a general rotor (see :class:`_Problem`)."""

METHODS = ("auto", "shooting", "synchronous")
"""Routes of :func:`rubrotor.orbits.continuation.continue_orbit`."""


def _route(scenario, k, orbit, method) -> str:
    """``"synchronous"`` or ``"shooting"`` for ``method`` at the shot start ``orbit``."""
    if method not in METHODS:
        raise InputError("method", method, " | ".join(METHODS))
    if method == "shooting":
        return method
    general = model_of(scenario).maps == "general"
    why = "a general rotor (not axisymmetric in general)" if general else None
    why = why or unsupported(scenario, k)
    if why is None and not is_circular(scenario, state_vector(orbit.state)):
        why = "a start orbit that is not a circle (partial rub)"
    if why is None:
        return "synchronous"
    if method == "synchronous":
        raise InputError("method", method, f"a scenario and start orbit without {why}; or shooting")
    return "shooting"


def _problem(scenario, key, k, steps, x0, p0, kind=_Problem) -> _Problem:
    """The scaled problem: states by their largest displacement (m) and velocity (a general
    rotor's by its largest modal amplitude and force), key by p0."""
    if model_of(scenario).maps == "general":
        prob = kind(scenario, key, k, steps, np.ones(x0.size), abs(p0))
        prob.sx = prob.map_at(p0)._scales(x0)
        prob.tol, prob.h_rel = GENERAL_TOL, 1e-4
        # each key value costs a plant, a monodromy 1 ms: the key's derivative by a forward
        # difference (its error ~ h ~ 1e-4, that of the central one the plants' noise / h ~
        # 2e-4 alike), and the corrector's G_x exact at every iterate (fewer iterates)
        prob.central, prob.exact_gx = False, True
        return prob
    speed = scenario.with_changes(**{key: float(p0)}).speed
    sx = np.full(x0.size, max(np.max(np.abs(x0[: x0.size // 2])), 1e-12))
    sx[x0.size // 2 :] = sx[0] * speed
    return kind(scenario, key, k, steps, sx, abs(p0))


def _next_ds(ds: float, ds_max: float | None, t, t1, quick: bool, span: float) -> float:
    """The next arclength step: fixed rule with a ``ds_max``, else angle-controlled and moving
    the key by at most ``span / RANGE_STEPS`` (``span``: the range in scaled units)."""
    if ds_max is not None:
        return min(1.5 * ds, ds_max) if quick else ds
    angle = float(np.arccos(np.clip(t @ t1, -1.0, 1.0)))
    factor = float(np.clip(ANGLE_TARGET / max(angle, 1e-12), 0.5, 2.0))
    cap = span / RANGE_STEPS / max(abs(float(t1[-1])), 1e-12)
    return min(ds * (factor if quick else min(factor, 1.0)), AUTO_DS_MAX, cap)


def _found(prob, z, t, ds, gz, hit, onset) -> list:
    """Bifurcations of one step; a contact-onset corner is one event (module docstring)."""
    if hit[0] and onset is not None:  # the corner: a grazing turn
        return [Bifurcation("contact-onset", onset, prob.scenario.contact.clearance)]
    out = []
    for i, name in enumerate(BIFURCATIONS[:4]):
        if hit[i]:
            where = _locate_turn(prob, z, t, ds, gz) if i == 0 else _locate(prob, z, t, ds, i)
            if i == 0 and prob.richardson:
                where = _richardson_fold(prob, z, t, ds, gz, where)
            out.append(Bifurcation(name, where))
    return out


def _march(prob, z, t, gz, jac, bounds, points, ds, ds_max, first=None,
           born_at=None, progress=None) -> Branch:  # fmt: skip
    """Predictor-corrector steps from the converged ``z`` along ``t`` (module docstring).

    ``first`` replaces the first branch point (default: the point at ``z``). ``born_at`` (a
    key value): the branch ends at its first branch point away from that value (a switched
    branch meeting the branch it was born from again).
    """
    lo, hi = bounds
    pts, bifs, grazings = [first or _point(prob, z, jac, gz, t)], [], []
    sig = _tests(gz, t, jac)
    stopped = "points"
    try:
        while len(pts) < points:
            out = _chord(prob, z + ds * t, t, gz, ds=ds)
            chord = out is not None
            if not chord:
                out = _correct(prob, z + ds * t, t)
            if out is None:
                ds *= 0.5
                if ds < 1e-8:
                    stopped = "step"
                    break
                continue
            z1, gz1, jac1, iters = out
            z1, gz1, jac1 = prob.polish(z1, gz1, jac1, t)
            t1 = _tangent(gz1, t)
            sig1 = _tests(gz1, t1, jac1)
            new = _point(prob, z1, jac1, gz1, t1)
            onset = _onset(prob, pts[-1], new)
            found = _found(prob, z, t, ds, gz, _changed(sig, sig1), onset)
            pts.append(new)
            bifs += [_radius(b, pts[-2], pts[-1]) for b in found]
            ds = _next_ds(ds, ds_max, t, t1, iters <= (6 if chord else 3), (hi - lo) / prob.sp)
            z_in, z, t, sig, gz = z, z1, t1, sig1, gz1
            if onset is not None:
                grazings.append(onset)
            if progress is not None:
                progress(len(pts), points, pts[-1].value)
            if not lo <= pts[-1].value <= hi:  # the last point lands on the bound it crossed
                pts[-1:] = _land(prob, z_in, z, hi if pts[-1].value > hi else lo, t)
                bifs = [b for b in bifs if lo <= b.value <= hi]
                grazings = [g for g in grazings if lo <= g <= hi]
                stopped = "range"
                break
            if born_at is not None and _meets_again(bifs, born_at):
                stopped = "met"
                break
    except KeyboardInterrupt:  # Ctrl-C: the points so far are a branch, kept
        stopped = "interrupted"
    method = "synchronous" if isinstance(prob, _SyncProblem) else "shooting"
    return Branch(prob.key, prob.k, tuple(pts), tuple(bifs), tuple(grazings), method, stopped)


def _land(prob, z_in, z_out, value: float, t) -> list:
    """The branch point at key ``value`` (the range's bound) between ``z_in`` (inside the
    range) and ``z_out`` (beyond it): Newton with the key held at ``value``, from the chord's
    point there. A list of that point, or an empty list when Newton fails (the branch then
    ends at its last point inside the range)."""
    p = value / prob.sp
    w = (p - z_in[-1]) / (z_out[-1] - z_in[-1])
    guess = z_in + w * (z_out - z_in)
    guess[-1] = p
    fixed = np.zeros_like(guess)
    fixed[-1] = 1.0
    out = _correct(prob, guess, fixed)
    if out is None:
        return []
    z, gz, jac, _ = out
    return [_point(prob, z, jac, gz, _tangent(gz, t))]


def _meets_again(bifs, born_at: float) -> bool:
    """Whether a branch point was located away from (1e-6 relative) the value ``born_at``."""
    return any(b.type == "branch-point" and abs(b.value - born_at) > 1e-6 * abs(born_at)
               for b in bifs)  # fmt: skip


def _free_radius(scenario, samples: int = 64) -> float:
    """Largest contact-station radius (m) of the steady orbit without contact, to rounding.

    Without contact the steady response to unbalance and a constant load holds the harmonics
    0 and +-1 of the spin only, so ``samples`` points of one revolution give its Fourier
    coefficients exactly and ``|P(theta)|`` is maximised on the trigonometric polynomial.
    """
    from rubrotor.engine.settings import Integrator
    from rubrotor.engine.simulate import simulate_scenario

    # a clearance 1000 times larger keeps the rotor off the stator: deliberate, so its
    # plausibility check (a clearance beyond the radius) is switched off for this scenario
    skip = [*((scenario._spec or {}).get("checks", {}).get("skip", [])), "clearance_vs_radius"]
    free = scenario.with_changes(**{"contact.clearance": 1e3 * scenario.contact.clearance,
                                    "checks.skip": sorted(set(skip))})  # fmt: skip
    integ = Integrator(revolutions=1.0, dtau=2 * np.pi / samples, save_every=1)
    res = simulate_scenario(free, integ, progress=False, initial="steady")
    z = (res.channels[0] + 1j * res.channels[1])[:samples]
    c = np.fft.fft(z) / samples
    n = np.fft.fftfreq(samples, 1.0 / samples)

    def minus_r(theta):
        return -abs(np.sum(c * np.exp(1j * n * theta)))

    j = int(np.argmax(np.abs(z)))
    h = 2 * np.pi / samples
    res = scipy.optimize.minimize_scalar(
        minus_r, bounds=(j * h - h, j * h + h), method="bounded", options={"xatol": 1e-12}
    )
    return -float(res.fun)


def grazing_value(scenario, key: str, free: float, touching: float) -> float:
    """Key value where the free (no-contact) orbit grazes the stator: ``R_free(p) = g``.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The base scenario (with a contact).
    key : str
        The varied key.
    free, touching : float
        Key values where the free orbit's largest radius is below / above the clearance.

    Returns
    -------
    float
        The onset value (the key's units), by Brent's root finding to 4 ulp of the key on
        :func:`_free_radius`, exact to rounding: contact onset along a branch happens where
        the no-contact orbit first touches.
    """
    g = scenario.contact.clearance

    def h(p):
        return _free_radius(scenario.with_changes(**{key: float(p)})) / g - 1.0

    return float(scipy.optimize.brentq(h, free, touching, xtol=1e-15, rtol=8.9e-16))


def _onset(prob, a: BranchPoint, b: BranchPoint) -> float | None:
    """The grazing value between branch points ``a`` and ``b`` if contact starts or ends there.

    The bracket starts at the point without contact and widens (doubling) towards the other
    point until the free orbit touches, then the other way (at the corner where the branch
    turns both points lie on the free side of the onset).
    """
    contact = prob.scenario.contact
    if contact is None or prob.k != 1 or model_of(prob.scenario).maps == "general":
        return None
    g = contact.clearance
    if (a.max_radius_m > g) == (b.max_radius_m > g):
        return None
    free, other = (a, b) if a.max_radius_m <= g else (b, a)
    for step in (other.value - free.value, free.value - other.value):
        for _ in range(8):
            far = free.value + step
            if _free_radius(prob.at(far)) > g:
                return grazing_value(prob.scenario, prob.key, free.value, far)
            step *= 2.0
    return None


def switch_period_doubling(scenario, key: str, branch: Branch, stop: float, *, index: int = 0,
                           steps: int = STEPS_PER_REVOLUTION, points: int = 60, ds: float = 0.02,
                           ds_max: float = 0.2) -> Branch:  # fmt: skip
    """Continue the period-doubled branch (``2 k`` revolutions) born at a period doubling.

    At the period-doubling value ``p*`` of ``branch`` the ``k``-orbit ``x*`` has a multiplier
    -1 with real eigenvector ``v``; for the ``2 k``-revolution map ``x*`` is a pitchfork branch
    point whose new branch leaves along ``(v, 0)`` (the doubled orbit splits as
    ``x* +- a v``, ``a ~ sqrt|p - p*|``). The first predictor is ``z* + ds t0``, ``t0`` the
    part of ``(v, 0)`` orthogonal to the ``k``-branch's tangent (both span the null space of
    the ``2 k`` problem at ``z*``), corrected on the hyperplane normal to ``t0``, which the
    ``k``-branch (also a ``2 k``-orbit) touches only at ``z*``; then the usual pseudo-arclength
    march.

    Parameters
    ----------
    scenario : rubrotor.scenario.Scenario
        The base scenario ``branch`` was continued on.
    key : str
        The continued key (``branch.key``).
    branch : Branch
        A branch with a located ``"period-doubling"`` bifurcation.
    stop : float
        End of the range of the key (its units); the new branch ends when its key value
        leaves the range between ``p*`` and ``stop`` or after ``points`` points.
    index : int
        Which period doubling of ``branch`` (0 = the first).
    steps : int
        Fixed steps per revolution (as for ``branch``).
    points : int
        Largest number of points; the first is the ``k``-orbit at ``p*``.
    ds, ds_max : float
        First and largest arclength step (scaled units, dimensionless).

    Returns
    -------
    Branch
        ``k`` is ``2 branch.k``; the bifurcations found along the new branch, which ends where
        it meets the ``k``-branch again (a branch point away from ``p*``: the next period
        doubling) or leaves the range.
    """
    pds = [b for b in branch.bifurcations if b.type == "period-doubling"]
    if not 0 <= index < len(pds):
        raise InputError("index", index, f"0 .. {len(pds) - 1} (period doublings of the branch)")
    p_star = pds[index].value
    near = min(branch.points, key=lambda q: abs(q.value - p_star))
    orbit = shoot(scenario.with_changes(**{key: p_star}), near.state, branch.k, steps=steps)
    x_star = state_vector(orbit.state)
    jac1 = prepared_map(orbit.scenario, branch.k, steps).run(x_star, True)[1]
    mu, vecs = np.linalg.eig(jac1)
    j = int(np.argmin(np.abs(mu + 1)))
    prob = _problem(scenario, key, 2 * branch.k, steps, x_star, p_star)
    z_star = np.concatenate([x_star / prob.sx, [p_star / prob.sp]])
    # the k-branch through z* also solves the 2k problem: leave along v orthogonally to it
    single = _Problem(scenario, key, branch.k, steps, prob.sx, prob.sp)
    t_single = _tangent(single.evaluate(z_star)[1], None)
    t0 = np.concatenate([np.real(vecs[:, j]) / prob.sx, [0.0]])
    t0 -= (t0 @ t_single) * t_single
    t0 /= np.linalg.norm(t0)
    out = _correct(prob, z_star + ds * t0, t0, max_iter=20)
    if out is None:
        raise InputError("ds", ds, "a smaller first step (no doubled orbit found along v)")
    z, gz, jac, _ = out
    first = _point(prob, z_star, jac1 @ jac1)
    t = _tangent(gz, None)
    p1 = prob.unscale(z)[1]
    if t[-1] * (p1 - p_star) < 0:
        t = -t
    bounds = (
        min(p_star, stop) - 0.5 * abs(stop - p_star),
        max(p_star, stop) + 0.5 * abs(stop - p_star),
    )
    # the doubled orbit closes on the k-branch again at another period doubling (a branch
    # point); beyond it the march would retrace the same orbits shifted by k revolutions, so
    # the branch ends there (a branch point at p* itself is the pitchfork it was born at)
    rest = _march(prob, z, t, gz, jac, bounds, points - 1, ds, ds_max, born_at=p_star)
    return Branch(key, 2 * branch.k, (first, *rest.points), rest.bifurcations,
                  stopped=rest.stopped)  # fmt: skip
