# How to track the orders of a measured run-up: docs/howto/order-tracking.md (run in CI).
set -euo pipefail
# [make-record] a stand-in for a measured record: simulate a run-up and write its probe as CSV
rubrotor simulate runup_rub.toml --out runup.nc
python - <<'PY'
import numpy as np
import xarray as xr

ds = xr.open_dataset("runup.nc")
t, y, z = ds["time"].values, ds["v"].values[0], ds["w"].values[0]
rpm = np.gradient(ds["angle"].values, t) * 60 / (2 * np.pi) if "angle" in ds else None
if rpm is None:
    rpm = np.interp(t, [t[0], t[-1]], [150 * 30 / np.pi, 450 * 30 / np.pi])
np.savetxt("probe.csv", np.column_stack([t, y, z, rpm]), delimiter=",",
           header="time,y,z,rpm", comments="", fmt="%.9g")
PY
# [analyze]
rubrotor analyze probe.csv --columns y,z --orders 0.5,1,2 --clearance 150e-6 --html --svg --out orders
# [end]
