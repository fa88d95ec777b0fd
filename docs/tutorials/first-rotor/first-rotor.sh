# The tutorial's commands, run in CI by docs/run_pages.py from a copy of this folder.
set -euo pipefail
# [draw]
rubrotor draw rotor.toml --out rotor.png
# [modes]
rubrotor modes rotor.toml
rubrotor critical rotor.toml
# [campbell]
rubrotor campbell rotor.toml --speeds 0:600:61 --run-range 300:340 --out campbell.png
# [unbalance]
rubrotor unbalance rotor.toml --speeds 0:600:121 --probe 0.5 --probe 0.3 --figure bode.png
# [clearance]
rubrotor clearance rotor.toml --figure clearance.png
# [simulate]
rubrotor simulate rotor.toml --out run.nc --figure
# [analyze]
rubrotor analyze run.nc --out verdict
# [end]
