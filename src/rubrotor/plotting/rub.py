"""Figure of a general-engine results Dataset (:mod:`rubrotor.engine.general`): orbit at the
first contact relative to its stator, normal forces against time, and the full spectrum (constant
speed) or the per-revolution envelope of the amplitude against speed (run-up or coast-down); with
fluid-film bearings a second row: the journals' orbits in their clearance circles, their
eccentricity ratios and film forces against time."""

from __future__ import annotations

import json
import math

import numpy as np
from matplotlib.figure import Figure

__all__ = ["engine_figure", "per_revolution"]

UM = 1e6  # m -> µm
_LINES = ("-", "--", ":")  # bearings that coincide (a symmetric rotor) stay visible


def _relative(ds, i: int) -> tuple[np.ndarray, np.ndarray, float]:
    """Rotor minus stator centre at contact ``i`` (m) and its clearance (m)."""
    c = json.loads(ds.attrs.get("contacts", "[]"))[i]
    y = ds["v"].values[i] - ds["stator_y"].values[i] - c["offset_y"]
    z = ds["w"].values[i] - ds["stator_z"].values[i] - c["offset_z"]
    return y, z, c["clearance"]


def _orbit(ax, ds) -> None:
    y, z, g = _relative(ds, 0)
    n = y.size
    tail = slice(int(0.75 * n), n)
    ax.plot(z * UM, y * UM, color="0.75", lw=0.5, label="whole record")
    ax.plot(z[tail] * UM, y[tail] * UM, color="C0", lw=0.8, label="last quarter")
    phi = np.linspace(0, 2 * math.pi, 361)
    ax.plot(g * UM * np.cos(phi), g * UM * np.sin(phi), "k--", lw=1, label="clearance")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("z, relative to the stator centre (µm)")
    ax.set_ylabel("y, relative to the stator centre (µm)")
    x0 = float(ds["station"].values[0])
    ax.set_title(f"orbit at the contact, x = {x0:g} m")
    ax.legend(loc="upper right", fontsize=7)


def _forces(ax, ds) -> None:
    t = ds["time"].values
    for i in range(ds.sizes["contact"]):
        x = float(ds["station"].values[i])
        ax.plot(t, ds["normal_force"].values[i], lw=0.7, label=f"contact at x = {x:g} m")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("normal force (N)")
    ax.set_title("contact normal force")
    ax.legend(loc="upper right", fontsize=7)


def _spectrum(ax, ds) -> None:
    y, z, _ = _relative(ds, 0)
    t = ds["time"].values
    half = slice(y.size // 2, y.size)
    sig = (y + 1j * z)[half]
    sig = sig - sig.mean()
    dt = float(np.mean(np.diff(t)))
    win = np.hanning(sig.size)
    amp = np.abs(np.fft.fftshift(np.fft.fft(sig * win))) * 2 / win.sum()
    f = np.fft.fftshift(np.fft.fftfreq(sig.size, dt))
    spin = float(ds.attrs["speed_rad_s"]) / (2 * math.pi)
    keep = np.abs(f) <= 6 * spin
    ax.semilogy(f[keep], amp[keep] * UM, lw=0.8)
    ax.axvline(spin, color="C3", ls=":", lw=1, label=f"+1X = {spin:.4g} Hz (forward)")
    ax.axvline(-spin, color="C2", ls=":", lw=1, label=f"-1X = {-spin:.4g} Hz (backward)")
    ax.legend(loc="upper left", fontsize=7)
    ax.set_xlabel("whirl frequency (Hz; < 0 backward)")
    ax.set_ylabel("amplitude, y + i z (µm)")
    ax.set_title("full spectrum at the contact (second half)")


def _journal_index(ds, j: int) -> int:
    """Station index of bearing ``j``'s journal (the supports' stations come last)."""
    return ds.sizes["station"] - ds.sizes["bearing"] + j


def _journals(ax, ds) -> None:
    """Each fluid-film journal's orbit in its clearance circle (the last quarter)."""
    phi = np.linspace(0, 2 * math.pi, 361)
    n = ds.sizes["time"]
    tail = slice(int(0.75 * n), n)
    for j in range(ds.sizes["bearing"]):
        s = _journal_index(ds, j)
        c = float(ds["bearing_clearance"].values[j])
        y, z = ds["v"].values[s][tail], ds["w"].values[s][tail]
        name = str(ds["bearing_name"].values[j])
        ax.plot(z / c, y / c, lw=0.8, color=f"C{j}", ls=_LINES[j % 3],
                label=f"{name} (c = {c * UM:.3g} µm)")  # fmt: skip
    ax.plot(np.cos(phi), np.sin(phi), "k--", lw=1, label="clearance circle")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("z / radial clearance (1)")
    ax.set_ylabel("y / radial clearance (1)")
    ax.set_title("journal orbits in the bearings (last quarter)")
    ax.legend(loc="upper right", fontsize=7)


def _per_bearing(ax, ds, values, ylabel: str, title: str) -> None:
    """One line per bearing of ``values`` (bearing, time) against time."""
    t = ds["time"].values
    for j in range(ds.sizes["bearing"]):
        ax.plot(t, values[j], lw=0.7, color=f"C{j}", ls=_LINES[j % 3],
                label=str(ds["bearing_name"].values[j]))  # fmt: skip
    ax.set_xlabel("time (s)")
    ax.set_ylabel(ylabel)
    ax.set_title(title)


def _eccentricity(ax, ds) -> None:
    _per_bearing(ax, ds, ds["eccentricity_ratio"].values, "eccentricity ratio (1)",
                 "journal eccentricity")  # fmt: skip
    ax.axhline(1.0, color="k", ls=":", lw=1, label="metal contact")
    ax.legend(loc="lower right", fontsize=7)


def _film_forces(ax, ds) -> None:
    f = np.hypot(ds["film_force_y"].values, ds["film_force_z"].values)
    _per_bearing(ax, ds, f, "film force magnitude (N)", "fluid-film force on each journal")
    ax.legend(loc="upper right", fontsize=7)


def per_revolution(tau: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, ...]:
    """Maximum and minimum of ``values`` over each full revolution of the rotor.

    Parameters
    ----------
    tau : ndarray
        Rotor angle (rad) at each sample, increasing.
    values : ndarray
        One value per sample.

    Returns
    -------
    index : ndarray of int
        First sample of each full revolution.
    vmax, vmin : ndarray
        Largest and smallest value within each revolution (the envelope).
    """
    rev = np.floor((tau - tau[0]) / (2 * math.pi)).astype(int)
    starts = np.flatnonzero(np.diff(rev, prepend=-1))
    if starts.size < 2:
        return starts, values[starts], values[starts]
    starts = starts[:-1]  # the last revolution is incomplete
    stop = np.flatnonzero(rev == rev[starts[-1]])[-1] + 1
    v = values[:stop]
    return starts, np.maximum.reduceat(v, starts), np.minimum.reduceat(v, starts)


def _runup(ax, ds, rpm: bool = False) -> None:
    t, tau = ds["time"].values, ds["tau"].values
    w = np.gradient(tau, t)  # the spin speed of any profile (rad/s)
    for i, x in enumerate(ds["station"].values):
        r = np.hypot(ds["v"].values[i], ds["w"].values[i])
        starts, rmax, rmin = per_revolution(tau, r)
        speed = w[starts] * (30 / math.pi if rpm else 1.0)
        ax.plot(speed, rmax * UM, lw=1.2, color=f"C{i}", label=f"x = {x:g} m, max per rev")
        ax.plot(speed, rmin * UM, lw=0.7, ls="--", color=f"C{i}", label="min per rev")
    g = json.loads(ds.attrs.get("contacts", "[]"))[0]["clearance"]
    ax.axhline(g * UM, color="k", ls=":", lw=1, label="clearance (stator centred, at rest)")
    ax.set_xlabel("spin speed (rev/min)" if rpm else "spin speed (rad/s)")
    ax.set_ylabel("radial displacement |(v, w)| (µm)")
    title = "run-up" if w[-1] > w[0] else "coast-down"
    if np.any(np.diff(w) > 1e-9 * w.max()) and np.any(np.diff(w) < -1e-9 * w.max()):
        title = "speed profile"
    ax.set_title(f"{title}: envelope per revolution")
    ax.legend(loc="best", fontsize=7)


def engine_figure(ds, *, title: str | None = None, rpm: bool = False) -> Figure:
    """Orbit, normal force and spectrum (or amplitude against speed) of an engine run.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`rubrotor.simulate` on a general-engine scenario, with a contact.
    title : str, optional
        Figure title (default: the scenario name and status).
    rpm : bool
        Speed axis of a run-up in rev/min instead of rad/s (the default, as elsewhere).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from rubrotor.errors import InputError

    if ds.sizes.get("contact", 0) == 0 or "contacts" not in ds.attrs:
        raise InputError("results", ds.attrs.get("scenario_name", ""), "a run with a contact")
    films = ds.sizes.get("bearing", 0) > 0
    fig = Figure(figsize=(13, 8.4 if films else 4.2), layout="constrained")
    axes = fig.subplots(2 if films else 1, 3)
    top = axes[0] if films else axes
    _orbit(top[0], ds)
    _forces(top[1], ds)
    if "speed_end_rad_s" in ds.attrs:
        _runup(top[2], ds, rpm)
    else:
        _spectrum(top[2], ds)
    if films:
        _journals(axes[1][0], ds)
        _eccentricity(axes[1][1], ds)
        _film_forces(axes[1][2], ds)
    name = ds.attrs.get("scenario_name", "")
    fig.suptitle(title or f"{name}{_speed_text(ds.attrs)} ({ds.attrs['status']})")
    return fig


def _speed_text(attrs) -> str:
    """The speed for a title (', at 340 rad/s (3247 rpm)' or ', run-up 250-500 rad/s')."""
    lo, hi = attrs.get("speed_rad_s"), attrs.get("speed_end_rad_s")
    if lo is None:
        return ""
    if hi is not None and hi != lo:
        return f", run-up {float(lo):.5g}-{float(hi):.5g} rad/s"
    return f", at {float(lo):.5g} rad/s ({float(lo) * 30 / np.pi:.0f} rpm)"
