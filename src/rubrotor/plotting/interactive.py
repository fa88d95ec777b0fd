"""Interactive HTML figures (plotly, the optional ``interactive`` extra): the Campbell diagram,
the unbalance response (Bode) and the cascade, as ROSS users know them. Each function returns a
``plotly.graph_objects.Figure``; :func:`write_html` writes it as one self-contained page (plotly.js
inlined: it opens with no network). Hovering shows each point's values with their units.

The CLI writes them when a figure file ends in ``.html``: ``rubrotor campbell ... --out
campbell.html``, ``rubrotor unbalance ... --figure bode.html``; ``rubrotor analyze RUNUP.nc --html`` adds
``cascade.html``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rubrotor.errors import RubrotorError
from rubrotor.linear.critical import CRITICALLY_DAMPED
from rubrotor.plotting.linear import _af_text, amplification_factors, margin_band

__all__ = ["campbell_html", "bode_html", "cascade_html", "write_html", "require_plotly"]

TWO_PI = 2 * math.pi


def require_plotly():
    """The ``plotly.graph_objects`` module, or a RubrotorError saying how to install it."""
    try:
        import plotly.graph_objects as go
    except ImportError:
        raise RubrotorError(
            "interactive (.html) figures need plotly: python -m pip install 'rubrotor[interactive]'"
        ) from None
    return go


def write_html(fig, out: Path) -> None:
    """Write ``fig`` to ``out`` atomically as one page with plotly.js inlined (no network)."""
    from rubrotor.engine.result import atomic_write

    out = Path(out)
    atomic_write(out, lambda tmp: fig.write_html(str(tmp), include_plotlyjs=True, full_html=True))


def _layout(fig, title: str, x: str, y: str) -> None:
    fig.update_layout(title=title, template="plotly_white", hovermode="closest",
                      legend={"orientation": "h", "y": -0.18}, height=600)  # fmt: skip
    fig.update_xaxes(title_text=x, showline=True, mirror=True, linecolor="black")
    fig.update_yaxes(title_text=y, showline=True, mirror=True, linecolor="black")


def campbell_html(data, criticals=(), operating_speed=None, title="Campbell diagram",
                  run_range=None):  # fmt: skip
    """The Campbell diagram of :func:`rubrotor.plotting.linear.campbell_stability_figure`,
    interactive: damped natural frequency (Hz) against spin speed (rad/s), colour the log dec,
    circles forward and triangles backward whirl, the 1X line, critical speeds with their
    amplification factor, the run range and the API 684 separation-margin bands.

    Parameters
    ----------
    data : CampbellData
        From :func:`rubrotor.linear.campbell.campbell_data`.
    criticals : list of LinearCritical
        Critical speeds (rad/s) to mark.
    operating_speed : float, optional
        Spin speed (rad/s) drawn as a vertical line.
    title : str
        Figure title (name the scenario).
    run_range : tuple of float, optional
        Minimum operating and maximum continuous speed (rad/s).

    Returns
    -------
    plotly.graph_objects.Figure
    """
    go = require_plotly()
    fig = go.Figure()
    s = np.repeat(data.speeds[:, None], data.frequency_hz.shape[1], axis=1)
    f, ld = data.frequency_hz, data.log_dec
    fmax = float(np.nanmax(f)) * 1.05
    real = np.isfinite(f) & (f > 1e-9 * fmax)
    backward = np.asarray(data.whirl) == "backward"
    for mask, symbol, name in ((~backward, "circle", "forward whirl"),
                               (backward, "triangle-down", "backward whirl")):  # fmt: skip
        m = real & mask
        fig.add_trace(go.Scatter(
            x=s[m], y=f[m], mode="markers", name=name,
            marker={"symbol": symbol, "size": 7, "color": np.clip(ld[m], -0.1, 1.0),
                    "colorscale": "Plasma", "cmin": -0.1, "cmax": 1.0,
                    "colorbar": {"title": "log dec (1)"} if name == "forward whirl" else None,
                    "line": {"width": 0.5, "color": "black"}},
            customdata=ld[m],
            hovertemplate="%{x:.1f} rad/s<br>%{y:.2f} Hz<br>log dec %{customdata:.3g}",
        ))  # fmt: skip
    fig.add_trace(go.Scatter(x=data.speeds, y=data.speeds / TWO_PI, mode="lines", name="1X",
                             line={"dash": "dot", "color": "black"}))  # fmt: skip
    criticals = [c for c in criticals if not c.damping_ratio > CRITICALLY_DAMPED]
    if criticals:
        cs = [c.speed_rad_s for c in criticals]
        text = [f"{c.speed_rad_s:.0f} rad/s, {c.speed_rad_s * 60 / TWO_PI:.0f} rpm ({c.whirl}), "
                f"AF {_af_text(1 / (2 * c.damping_ratio))}" if c.damping_ratio > 0 else
                f"{c.speed_rad_s:.0f} rad/s ({c.whirl})" for c in criticals]  # fmt: skip
        fig.add_trace(go.Scatter(x=cs, y=[c.harmonic * w / TWO_PI for c, w in zip(criticals, cs, strict=True)],
                                 mode="markers", name="critical speed", text=text,
                                 hovertemplate="%{text}",
                                 marker={"symbol": "diamond", "size": 11, "color": "gold",
                                         "line": {"width": 1, "color": "black"}}))  # fmt: skip
        bands = [margin_band(c.speed_rad_s, c.damping_ratio) for c in criticals]
        for k, (lo, hi) in enumerate(b for b in bands if b[1] > b[0]):
            text = {"annotation_text": "API 684 separation margin: keep the run range out",
                    "annotation_position": "bottom right"} if k == 0 else {}  # fmt: skip
            fig.add_vrect(x0=lo, x1=hi, fillcolor="red", opacity=0.10, line_width=0, **text)
    if run_range is not None:
        fig.add_vrect(x0=run_range[0], x1=run_range[1], fillcolor="grey", opacity=0.15,
                      line_width=0, annotation_text="run range",
                      annotation_position="top left")  # fmt: skip
    if operating_speed:
        fig.add_vline(x=operating_speed, line_dash="dash", line_color="grey",
                      annotation_text=f"operating {operating_speed:.5g} rad/s")  # fmt: skip
    _layout(fig, title, "spin speed (rad/s)", "damped natural frequency (Hz)")
    fig.update_yaxes(range=[0, fmax])
    return fig


def bode_html(resp, probe: int = 0, clearance=None, title: str = "unbalance response"):
    """Bode plot of an unbalance response, interactive: amplitude (µm 0-peak, log) of ``v``,
    ``w`` and the major semi-axis at every probe, and the unwrapped phase (deg) of ``probe``,
    against spin speed (rad/s); peaks labelled with their amplification factor.

    Parameters
    ----------
    resp : UnbalanceResponse
        From :func:`rubrotor.linear.response.unbalance_response`.
    probe : int
        Probe whose ``v``, ``w`` and phase are drawn.
    clearance : float, optional
        Radial clearance (m) drawn on the amplitude.
    title : str
        Figure title (name the scenario).

    Returns
    -------
    plotly.graph_objects.Figure
    """
    go = require_plotly()
    from plotly.subplots import make_subplots

    fig = make_subplots(rows=2, cols=1, shared_xaxes=True, row_heights=[0.62, 0.38],
                        vertical_spacing=0.05)  # fmt: skip
    x = resp.speeds

    def um(a):  # µm, zeros (at rest) left out of the log axis
        a = np.asarray(a, float) * 1e6
        return np.where(a > 0, a, np.nan)

    for c, name, dash, colour in ((0, "v", "solid", "#1f77b4"), (1, "w", "dash", "#ff7f0e")):
        line = {"dash": dash, "color": colour}
        fig.add_trace(go.Scatter(x=x, y=um(resp.amplitude[:, probe, c]), name=f"{name} amplitude",
                                 line=line, legendgroup=name), row=1, col=1)  # fmt: skip
        fig.add_trace(go.Scatter(x=x, y=np.degrees(np.unwrap(resp.phase[:, probe, c])),
                                 name=f"{name} phase", line=line, legendgroup=name), row=2, col=1)  # fmt: skip
    dashes = ("solid", "dashdot", "dot", "longdash")
    for k in range(resp.probes.size):
        fig.add_trace(go.Scatter(x=x, y=um(resp.major[:, k]), line={"color": "black",
                                 "dash": dashes[k % 4]},
                                 name=f"major semi-axis, x = {resp.probes[k]:g} m"), row=1, col=1)  # fmt: skip
    top = float(np.nanmax(um(resp.major)))
    low = max(float(np.nanmin(um(resp.major))), 1e-6 * top)
    for w, peak, af in amplification_factors(x, resp.major[:, probe]):
        label = f"{w:.0f} rad/s, AF {_af_text(af)}" if math.isfinite(af) else f"{w:.0f} rad/s"
        fig.add_annotation(x=w, y=math.log10(peak * 1e6), text=label, row=1, col=1)
    if clearance is not None:
        fig.add_hline(y=clearance * 1e6, line_color="red", line_dash="longdash", row=1, col=1,
                      annotation_text=f"radial clearance {clearance * 1e6:g} µm")  # fmt: skip
    _layout(fig, f"{title}: probe x = {resp.probes[probe]:g} m", "spin speed (rad/s)", "")
    fig.update_yaxes(type="log", title_text="amplitude (µm 0-peak)", row=1, col=1,
                     range=[math.log10(low) - 0.2, math.log10(top) + 0.4])  # fmt: skip
    fig.update_yaxes(title_text="phase, unwrapped (deg)", row=2, col=1)
    fig.update_xaxes(title_text="", row=1, col=1)
    return fig


def cascade_html(casc, orders=(0.5, 1.0, 2.0, 3.0), title: str = "cascade", floor: float = 1e-3):
    """The cascade (waterfall) of a run-up, interactive: amplitude (µm) as colour over frequency
    (Hz; negative = backward whirl in a full-spectrum cascade) and spin speed (rad/s), with the
    forward order lines.

    Parameters
    ----------
    casc : Cascade
        From :func:`rubrotor.analysis.diagnostics.cascade`.
    orders : tuple of float
        Orders drawn as lines (``k`` times the spin frequency).
    title : str
        Figure title (name the scenario and the probe).
    floor : float
        Amplitudes below ``floor`` times the largest are drawn as the floor (log colour).

    Returns
    -------
    plotly.graph_objects.Figure
    """
    go = require_plotly()
    amp = np.asarray(casc.amplitude) * 1e6
    top = float(np.max(amp)) if amp.size else 1.0
    z = np.log10(np.maximum(amp, floor * top))
    f_hz = np.asarray(casc.frequency_rad_s) / TWO_PI
    fig = go.Figure(go.Heatmap(
        x=f_hz, y=casc.speed_rad_s, z=z, colorscale="Greys",
        colorbar={"title": "log10 amplitude (µm)"},
        hovertemplate="%{x:.1f} Hz<br>%{y:.1f} rad/s<br>log10 µm %{z:.2f}<extra></extra>",
    ))  # fmt: skip
    fmax = float(np.max(f_hz))
    for k, dash in zip(orders, ("dot", "solid", "dash", "dashdot", "longdash"), strict=False):
        w = np.asarray(casc.speed_rad_s)
        f = k * w / TWO_PI
        keep = f <= fmax
        fig.add_trace(go.Scatter(x=f[keep], y=w[keep], mode="lines", name=f"{k:g}X",
                                 line={"color": "red", "dash": dash, "width": 1.5}))  # fmt: skip
        if casc.full and k == 1.0:  # backward 1X of a full spectrum
            fig.add_trace(go.Scatter(x=-f[keep], y=w[keep], mode="lines", name="-1X",
                                     line={"color": "blue", "dash": dash, "width": 1.5}))  # fmt: skip
    x_title = "frequency (Hz), negative = backward whirl" if casc.full else "frequency (Hz)"
    _layout(fig, title, x_title, "spin speed (rad/s)")
    reach = 1.2 * max(orders) * float(np.max(casc.speed_rad_s)) / TWO_PI  # Hz: the orders drawn
    fig.update_xaxes(range=[-reach if casc.full else 0.0, reach])
    return fig
