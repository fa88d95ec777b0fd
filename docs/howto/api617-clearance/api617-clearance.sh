# How to check API 617 clearances: the commands of docs/howto/api617-clearance.md (run in CI).
set -euo pipefail
# [default]
rubrotor clearance seal_rub.toml --figure clearance.png
# [range]
rubrotor clearance seal_rub.toml --min-speed 400 --max-speed 628.3 --probe 0.05@45 \
    --probe 1.25@45 --json > clearance.json
# [level1]
rubrotor level1 seal_rub.toml --qa 2e5 --figure level1.png
# [end]
