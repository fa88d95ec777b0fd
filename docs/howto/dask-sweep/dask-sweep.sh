# How to run a sweep on a Dask cluster: docs/howto/dask-sweep.md (run in CI, on this machine).
set -euo pipefail
# [cluster] a scheduler and two single-threaded workers (on a real cluster: one per node)
PORT=$((20000 + RANDOM % 20000))
dask scheduler --port "$PORT" --no-dashboard > scheduler.log 2>&1 &
SCHEDULER=$!
dask worker "tcp://127.0.0.1:$PORT" --nworkers 2 --nthreads 1 --no-dashboard > workers.log 2>&1 &
WORKERS=$!
trap 'kill $WORKERS $SCHEDULER 2>/dev/null || true' EXIT
# [sweep]
rubrotor sweep seed_case1.toml --vary speed.critical_multiple=1.2:2.4:6 --revolutions 160 \
    --scheduler "tcp://127.0.0.1:$PORT" --out sweep.zarr --figure sweep.png --no-progress
# [end]
