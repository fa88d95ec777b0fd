# How to find the rub of a seal: the commands of docs/howto/seal-rub.md (run in CI).
set -euo pipefail
# [modes]
rubrotor modes rotor.toml
rubrotor critical rotor.toml
# [stability]
rubrotor stability rotor.toml --indentation 5e-6
# [runup]
rubrotor simulate runup.toml --out runup.nc --figure
# [end]
