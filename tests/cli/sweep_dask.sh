#!/usr/bin/env bash
# The Dask path: `rtusim sweep --scheduler` against a LocalCluster started here gives the same
# results.csv, byte for byte, as the local path. Needs dask.distributed in $RTUSIM_PYTHON (or the
# project's .venv).
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d)
py=${RTUSIM_PYTHON:-$src/.venv/bin/python}
[ -x "$py" ] || py=python3
export RTUSIM_PYTHON=$py
cluster=
cleanup() { [ -n "$cluster" ] && kill "$cluster" 2> /dev/null; wait 2> /dev/null; rm -rf "$tmp"; }
trap cleanup EXIT

cat > "$tmp/spec.toml" <<'TOML'
[image]
width = 32
height = 32
png = false
[sweep]
tracer.max_depth = [1, 3]
layout.kind = ["dfl", "subtree"]
l1.line = [32, 64]
l1.assoc = [2, "full"]
l1.size = [1024, 4096]
[[sweep.group.tier]]
sim.tier = "functional"
[[sweep.group.tier]]
sim.tier = "cycle"
TOML

cat > "$tmp/cluster.py" <<'PY'
import os, sys, time
from distributed import LocalCluster
if __name__ == "__main__":
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None)
    with open(sys.argv[1] + ".tmp", "w") as f:
        f.write(cluster.scheduler_address)
    os.replace(sys.argv[1] + ".tmp", sys.argv[1])
    while True:
        time.sleep(1)
PY
"$py" "$tmp/cluster.py" "$tmp/address" > "$tmp/cluster.log" 2>&1 &
cluster=$!
for _ in $(seq 1 120); do [ -s "$tmp/address" ] && break; sleep 0.5; done
[ -s "$tmp/address" ] || { echo "FAIL no LocalCluster"; cat "$tmp/cluster.log"; exit 1; }

"$rtusim" sweep "$tmp/spec.toml" --out "$tmp/local" --no-plots > /dev/null || { echo "FAIL local sweep"; exit 1; }
"$rtusim" sweep "$tmp/spec.toml" --out "$tmp/dask" --no-plots --scheduler "$(cat "$tmp/address")" \
  > /dev/null || { echo "FAIL dask sweep"; exit 1; }
if ! cmp "$tmp/local/results.csv" "$tmp/dask/results.csv"; then
  echo "FAIL the Dask path differs from the local path"; exit 1
fi
rows=$(($(wc -l < "$tmp/dask/results.csv") - 1))
[ "$rows" -eq 64 ] || { echo "FAIL $rows rows, want 64"; exit 1; }
echo "sweep_dask: the Dask path equals the local path ($rows points)"
