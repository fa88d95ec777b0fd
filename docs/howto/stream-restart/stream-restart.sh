# How to stream a long run and restart it: docs/howto/stream-restart.md (run in CI).
set -euo pipefail
# [start] 5000 revolutions: more samples than fit in memory at once, so the run streams
rubrotor simulate seal_rub.toml --revolutions 5000 --out long.nc > long.log 2>&1 &
RUN=$!
# [stop] stop it as a scheduler or Ctrl-C would: it finishes its chunk and exits with status 1
until [ -s long.nc ] || ! kill -0 "$RUN" 2>/dev/null; do sleep 1; done  # streaming has begun
sleep 3  # (in real life: hours later, or when the batch system says time is up)
kill -TERM "$RUN" 2>/dev/null || echo "the run had already finished"
wait "$RUN" || echo "stopped with status $?"
python -c "import xarray as xr; a = xr.open_dataset('long.nc').attrs; print(a['status'], a['end_time_s'])"
# [restart] continue from the file's last restart state
sed 's/^state = "static".*/state = "file"\npath = "long.nc"/' \
    "$(python -c 'from rubrotor.scenario.load import find_scenario; print(find_scenario("seal_rub.toml"))')" > resume.toml
rubrotor simulate resume.toml --revolutions 20 --out resumed.nc
# [end]
