set -euo pipefail
# 1. look at the rotor you wrote
rubrotor draw rotor.toml --out rotor.png
# 2. its modes at the scenario's speed, and its critical speeds
rubrotor modes rotor.toml
rubrotor critical rotor.toml
# 3. the Campbell diagram from rest to 600 rad/s
rubrotor campbell rotor.toml --speeds 0:600:61 --out campbell.png
# 4. the linear screening: does the unbalance response reach the seal's clearance?
rubrotor clearance rotor.toml --figure clearance.png
# 5. simulate the rub at 380 rad/s, then ask for the verdict
rubrotor simulate rotor.toml --out run.nc --figure
rubrotor analyze run.nc --out verdict
