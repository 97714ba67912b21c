#!/usr/bin/env bash
# `rtusim regress` on the real reference cases in traces/: every case passes.
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$rtusim" regress "$src/traces" > "$tmp/out" 2> "$tmp/err"
rc=$?
cat "$tmp/out"
ncases=$(find "$src/traces" -mindepth 2 -maxdepth 2 -name config.toml | wc -l)
if [ $rc -ne 0 ]; then echo "FAIL: regress exit $rc"; cat "$tmp/err"; echo "regress: 0 passed, 1 failed"; exit 1; fi
if ! grep -qx "regress: $ncases passed, 0 failed" "$tmp/out"; then
  echo "FAIL: no 'regress: $ncases passed, 0 failed' line"; echo "regress: 0 passed, 1 failed"; exit 1
fi
echo "regress: 1 passed, 0 failed"
