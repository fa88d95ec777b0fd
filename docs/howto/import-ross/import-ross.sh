# How to import a ROSS rotor: the commands of docs/howto/import-ross.md (run in CI).
set -euo pipefail
# [import]
rubrotor import-ross ross_rotor.toml --out compressor.toml --rpm 3000
# [check]
rubrotor draw compressor.toml --out compressor.png
rubrotor critical compressor.toml
# [end]
