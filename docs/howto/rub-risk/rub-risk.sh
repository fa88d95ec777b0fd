# How to estimate the probability of rub: docs/howto/rub-risk.md (run in CI, on this machine).
set -euo pipefail
# [linear]
rubrotor risk seal_rub.toml --samples 4000 --speeds 600:1500:100 \
    --vary "contact.clearance=normal(40e-6,4e-6)" \
    --vary "contact.offset_y=normal(-25e-6,5e-6)" \
    --vary "unbalance[1].magnitude=uniform(3e-4,7e-4)" \
    --sobol --out risk --no-progress > table.txt
tail -4 table.txt
# [time]
rubrotor risk one_mode_partial_rub.toml --samples 8 --method time --revolutions 30 \
    --transient 10 --vary "contact.clearance=uniform(2e-5,3e-4)" --out time --no-progress \
    --no-figure --json > time.json
# [end]
