# How to run a rotor in fluid-film bearings with rub: the commands of
# docs/howto/film-bearings.md (run in CI).
set -euo pipefail
# [bearings]
rubrotor bearings oil_whip_rub.toml --speeds 200:1400:7 --figure films.png
# [threshold]
rubrotor critical oil_whip_rub.toml
# [simulate]
rubrotor simulate oil_whip_rub.toml --out whip.nc --figure
rubrotor analyze whip.nc --out whip
# [end]
