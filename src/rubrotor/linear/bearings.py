"""The fluid-film supports of a rotor at each speed: static position and linearised coefficients.

For each nonlinear support (``short_journal``, ``squeeze_film``, ``finite_journal``) and each spin
speed asked, the rotor's static equilibrium under the scenario's gravity and loads is solved
(:mod:`rubrotor.forces.equilibrium`: Newton on the finite-element static problem with the films'
Jacobians) and the film is linearised there: the journal's eccentricity ratio and attitude angle,
and ``K``, ``C`` (``F ~ F0 - K dq - C dq'``). These are the coefficients every linear verb uses
at that speed (``rubrotor bearings``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubrotor.errors import InputError

__all__ = ["BearingsResult", "bearing_coefficients"]

_KEYS = ("kyy", "kyz", "kzy", "kzz", "cyy", "cyz", "czy", "czz")


@dataclass(frozen=True)
class BearingsResult:
    """The nonlinear supports of a rotor at each speed.

    Attributes
    ----------
    rows : tuple of rubrotor.forces.equilibrium.SupportLinearisation
        One per support and speed, speed by speed, supports in their order: ``p0`` (m),
        ``force`` (N), ``K0`` (N/m), ``C0`` (N s/m), ``eccentricity_ratio`` (1),
        ``attitude_angle_rad`` (rad), ``speed_rad_s`` (rad/s).
    """

    rows: tuple

    def to_dict(self) -> dict:
        """The JSON form printed by ``rubrotor bearings --json``: ``{"bearings": [{"name",
        "position_m", "speed_rad_s", "eccentricity_ratio", "attitude_angle_rad", "y0_m", "z0_m",
        "kyy" ... "kzz" (N/m), "cyy" ... "czz" (N s/m)}]}``."""
        out = []

        def finite(x):  # an attitude without load (a damper's spring carrying nothing): null
            return float(x) if np.isfinite(x) else None

        for r in self.rows:
            item = {"name": r.name, "position_m": r.position, "speed_rad_s": r.speed_rad_s,
                    "eccentricity_ratio": r.eccentricity_ratio,
                    "attitude_angle_rad": finite(r.attitude_angle_rad),
                    "y0_m": float(r.p0[0]), "z0_m": float(r.p0[1])}  # fmt: skip
            mats = np.concatenate([r.K0.ravel(), r.C0.ravel()])
            item.update({k: float(v) for k, v in zip(_KEYS, mats, strict=True)})
            out.append(item)
        return {"bearings": out}


def bearing_coefficients(model, speeds) -> BearingsResult:
    """Every nonlinear support of ``model`` (a :class:`rubrotor.modelling.Model`) at ``speeds``.

    Parameters
    ----------
    model : Model
    speeds : array_like
        Spin speeds (rad/s), finite; > 0 with journal bearings.

    Returns
    -------
    BearingsResult

    Raises
    ------
    InputError
        ``bearing`` when the rotor has no fluid-film support; a speed or load the films cannot
        carry (see :func:`rubrotor.forces.equilibrium.solve_equilibrium`).
    """
    s = np.atleast_1d(np.asarray(speeds, float))
    if s.ndim != 1 or s.size == 0 or not np.all(np.isfinite(s)) or np.any(s < 0):
        raise InputError("speeds", speeds, "finite spin speeds >= 0 (rad/s)")
    system = model.linear_system()
    rows = []
    for w in s:
        rows.extend(model.support_linearisation(float(w), system))
    if not rows:
        raise InputError("bearing", "no fluid film", 'a [[bearing]] of type "short_journal", '
                         '"squeeze_film" or "finite_journal"')  # fmt: skip
    return BearingsResult(tuple(rows))
