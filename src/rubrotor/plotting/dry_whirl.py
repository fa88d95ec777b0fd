"""Figure of a dry-whirl study (:mod:`rubrotor.studies.dry_whirl`): the friction threshold and the
whirl frequency against spin speed, measured and in closed form. Returns a
:class:`matplotlib.figure.Figure` that is not registered with pyplot.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

__all__ = ["dry_whirl_figure"]


def _branches(case, speeds: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Closed-form rolling frequencies (rad/s) of a
    :class:`~rubrotor.studies.dry_whirl.DryWhirlCase` on a dense speed grid, one curve per band."""
    pts: dict[int, list] = {}
    for w in speeds:
        for i, r in enumerate(case.at_speed(w).rolling_whirls(points=801)):
            pts.setdefault(i, []).append((w, r.frequency))
    return [tuple(np.array(v).T) for v in pts.values()]


def dry_whirl_figure(friction_scans, speed_scans, labels) -> Figure:
    """Two panels: whirl frequency against friction and against spin speed.

    Parameters
    ----------
    friction_scans : sequence of DryWhirlScan
        From :func:`rubrotor.studies.dry_whirl.scan_friction` (one speed each).
    speed_scans : sequence of DryWhirlScan
        From :func:`rubrotor.studies.dry_whirl.scan_speed`, one per friction scan (same case).
    labels : sequence of str
        Legend label of each pair (e.g. "rigid stator").

    Returns
    -------
    matplotlib.figure.Figure
        Left: measured whirl frequency (rad/s; filled markers = sustained backward whirl in
        full contact) against friction, with the closed-form rolling frequency and the friction
        ``mu_roll`` it needs. Right: whirl frequency against spin speed (rad/s) with the rolling
        condition ``-Omega R / g``, the closed-form ``-Omega R / |D|`` and the coupled
        natural frequencies.
    """
    fig = Figure(figsize=(11, 6.2), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    colors = ("tab:blue", "tab:red", "tab:green")
    for k, (fs, ss, lab) in enumerate(zip(friction_scans, speed_scans, labels, strict=True)):
        col = colors[k % len(colors)]
        _friction_panel(ax1, fs, col, lab)
        _speed_panel(ax2, ss, col, lab)
    wn = np.sqrt(friction_scans[0].case.rotor.stiffness / friction_scans[0].case.rotor.mass)
    for ax in (ax1, ax2):
        ax.axhline(-wn, color="0.5", lw=0.8, ls=":")
        ax.grid(alpha=0.3)
        ax.set_ylabel("whirl frequency of D (rad/s, < 0 backward)")
    ax1.text(ax1.get_xlim()[1], -wn, " -omega_n (free decay)", va="bottom", ha="right", fontsize=8)
    ax1.set_xlabel("friction coefficient mu (-)")
    ax2.set_xlabel("spin speed Omega (rad/s)")
    ax1.set_title("friction scan: threshold of backward whirl")
    ax2.set_title("whirl frequency against speed")
    for ax in (ax1, ax2):
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    return fig


def _friction_panel(ax, scan, col: str, lab: str) -> None:
    back = scan.backward
    ax.plot(scan.frictions[back], scan.whirl_frequency[back], "o", color=col,
            label=f"{lab}, Omega = {scan.speeds[0]:g} rad/s: backward whirl")  # fmt: skip
    ax.plot(scan.frictions[~back], scan.whirl_frequency[~back], "o", mfc="none", color=col,
            label=f"{lab}: no sustained contact")  # fmt: skip
    roll = scan.case.rolling_whirls()
    if roll:
        r = roll[-1]
        ax.axhline(r.frequency, color=col, lw=1, label=f"{lab}: -Omega R/|D| = {r.frequency:.1f}")
        ax.axvline(r.friction_needed, color=col, ls="--", lw=1,
                   label=f"{lab}: mu_roll = {r.friction_needed:.3f}")  # fmt: skip
    if scan.threshold is not None:
        ax.plot([scan.threshold], [scan.whirl_frequency[scan.frictions == scan.threshold][0]],
                "*", ms=12, color=col)  # fmt: skip


def _speed_panel(ax, scan, col: str, lab: str) -> None:
    back = scan.backward
    ax.plot(scan.speeds[back], scan.whirl_frequency[back], "o", color=col,
            label=f"{lab}, mu = {scan.frictions[0]:g}: simulated")  # fmt: skip
    ax.plot(scan.speeds[~back], scan.whirl_frequency[~back], "o", mfc="none", color=col)
    dense = np.linspace(scan.speeds[0], scan.speeds[-1], 120)
    for i, (w, f) in enumerate(_branches(scan.case, dense)):
        ax.plot(w, f, "-", color=col, lw=1, label=f"{lab}: -Omega R/|D|" if i == 0 else None)
    for i, fc in enumerate(scan.coupled_frequencies):
        ax.axhline(-fc, color=col, ls="-.", lw=0.8,
                   label=f"{lab}: coupled frequencies" if i == 0 else None)  # fmt: skip
    c = scan.case.contact
    ax.plot(dense, -dense * c.radius / c.clearance, "k--", lw=0.8,
            label="rolling condition -Omega R/g" if col == "tab:blue" else None)  # fmt: skip
