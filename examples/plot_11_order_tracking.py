"""
Order tracking of a run-up with rub: Bode, polar, cascade, centreline and orbits
=================================================================================

The shipped ``runup_rub.toml``: a 1 m shaft with an 8 kg disk on anisotropic bearings runs up
from 150 to 450 rad/s in 1 s through its first critical speed (about 270 rad/s); near the
critical the unbalance orbit outgrows the 0.3 mm clearance of a catcher ring and rubs.

The analysis reads it as a vibration engineer reads a machine run-up. The spin angle comes from
the run (a measured record gives it from a keyphasor or a speed column, see
:mod:`rubrotor.analysis.measured`); each probe signal is resampled at equal angle steps and
Fourier-analysed over blocks of whole revolutions starting at the keyphasor (computed order
tracking, :func:`rubrotor.analysis.orders.track_orders`), which gives the amplitude and phase of
0.5X, 1X and 2X against speed. ``rubrotor analyze runup.nc`` writes the same numbers
(``"orders"``) and a rub verdict with its evidence.
"""

import json
from pathlib import Path

import rubrotor
from rubrotor.analysis.diagnostics import cascade, shaft_centreline
from rubrotor.analysis.orders import spin_from_dataset, track_orders
from rubrotor.analysis.verdict import dataset_verdict
from rubrotor.plotting.diagnostics import (
    bode_figure,
    cascade_figure,
    centreline_figure,
    orbit_figure,
    polar_figure,
)

scenarios = Path(rubrotor.__file__).parent / "scenarios"
ds = rubrotor.simulate(rubrotor.load_scenario(scenarios / "runup_rub.toml"), progress=False)
spin = spin_from_dataset(ds)
ring = json.loads(ds.attrs["contacts"])[0]  # the catcher ring: clearance and centre
stations = ds["station"].values  # the disk (contact station) first, then the probe
tracks = {
    float(x): track_orders(spin, ds["v"].values[j], ds["w"].values[j], orders=(0.5, 1.0, 2.0))
    for j, x in enumerate(stations)
}
verdict = dataset_verdict(ds)
print(f"rub: {verdict.verdict}")
for reason in verdict.reasons:
    print(" -", reason)

# %%
# Transient Bode plot of 1X at the disk and the quarter-span probe (y solid, z dashed). The
# amplitude rises through the critical and is capped by the ring near 300 um, where the disk
# bounces on it about once per revolution (290-370 rad/s); past 370 rad/s 1X falls, the disk
# hits the ring only in bursts, and the tracked 1X beats with the free whirl the impacts excite
# (its phase no longer follows the unbalance).
bode = bode_figure(tracks, orders=(1.0,), title="runup_rub: tracked 1X")

# %%
# Polar plot of 1X at the disk: the phasor turns through the critical speed (labels in rad/s).
polar = polar_figure(tracks[0.5], order=1.0, direction="y")

# %%
# Full-spectrum cascade of the disk orbit: each spectrum (4 revolutions, Hann) drawn above its
# speed, forward whirl at positive frequencies, backward at negative ones; the dashed lines are
# the orders. Once the disk touches the ring, backward-whirl components (negative frequencies)
# appear, a sign of the rub.
casc = cascade_figure(cascade(spin, ds["v"].values[0], ds["w"].values[0], revolutions=4))

# %%
# Shaft centreline (mean position per revolution) inside the clearance circle: at the ring's
# centre (no gravity, no load) while the whirl is synchronous, wandering past 370 rad/s, where a
# non-synchronous free whirl does not average out over one revolution. Then the orbit at the
# disk unfiltered and 1X-filtered over four revolutions from 300 rad/s, with the keyphasor marks
# (where the shaft is when the keyphasor fires): the unfiltered orbit bounces along the ring.
centre = (ring["offset_y"], ring["offset_z"])
cl = shaft_centreline(spin, ds["v"].values[0], ds["w"].values[0])
centreline = centreline_figure(cl, clearance=ring["clearance"], centre=centre)
orbits = orbit_figure(spin, ds["v"].values[0], ds["w"].values[0], tracks[0.5], at_speed=300.0,
                      clearance=ring["clearance"], centre=centre)  # fmt: skip
