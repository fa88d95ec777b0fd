"""
Thermal rub: the Newkirk spiral
===============================

The shipped ``thermal_rub.toml`` is a stepped steel rotor with two disks on damped bearings.
A labyrinth seal between the disks (30 um clearance) rubs lightly under the unbalance response.
The friction power heats the rotor at the high spot, and the rotor bows towards it
(:mod:`rubrotor.studies.thermal`, derived on the "Thermal rub" page of the guide). The
linearised slow dynamics give the growth rate and the spiral period against speed: the spiral
grows below the first forward critical and is damped above it. A slow-time run at the
scenario's 270 rad/s then shows the 1X vector of the seal and both disks spiralling out over
hours of machine time, until the run stops as a runaway. The same rotor with a stiffer seal
(2 MN/m), a hot spot that trails the high spot by 80 degrees and 1 um of bow per watt has an
unstable steady bow too, but its rub is lost over part of every turn and the spiral settles
into a limit cycle.
"""

from importlib import resources

import numpy as np

from rubrotor.linear.critical import linear_critical_speeds
from rubrotor.linear.verbs import linear_system
from rubrotor.plotting.thermal import growth_figure, spiral_figure
from rubrotor.scenario.load import load_scenario, scenario_from_dict, scenario_to_dict
from rubrotor.studies.thermal import ThermalModel, growth_against_speed, slow_run

scenario = load_scenario(resources.files("rubrotor") / "scenarios" / "thermal_rub.toml")
crit = [c.speed_rad_s for c in linear_critical_speeds(linear_system(scenario), 450.0, n=4)
        if c.whirl == "forward"]  # fmt: skip
speeds = np.linspace(230.0, 420.0, 9)
lin = growth_against_speed(scenario, speeds, steps=512)
fig_growth = growth_figure(speeds, [r.growth_rate for r in lin],
                           [r.spiral_period for r in lin], crit)  # fmt: skip
for w, r in zip(speeds, lin, strict=True):
    print(f"{w:6.1f} rad/s: growth {r.growth_rate * 3600:+.3f} 1/h, "
          f"period {r.spiral_period / 60:.1f} min")  # fmt: skip

run = slow_run(ThermalModel(scenario, steps=512), 5 * 3600.0, samples=80)
print("slow run:", run.attrs["status"], "at", round(float(run.time[-1]) / 3600, 2), "h")
fig_spiral = spiral_figure(run)

spec = scenario_to_dict(scenario)
spec["contact"][0]["stiffness"] = 2e6  # N/m
spec["thermal"].update(hot_spot_lag=1.4, bow_per_heat=1e-6)  # rad, m/W
cycling = ThermalModel(scenario_from_dict(spec), steps=256)
steady = cycling.steady()
print(f"steady bow {abs(steady.bow[0]) * 1e6:.1f} um, growth {steady.growth_rate * 3600:+.2f} 1/h")
cycle = slow_run(cycling, 1.5 * 3600.0, samples=120, rtol=1e-6)
fig_cycle = spiral_figure(cycle)
