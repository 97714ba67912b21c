#!/usr/bin/env bash
# The cycle tier runs several layouts in child processes, up to --threads at once: stats.json
# (but its timing keys), image.png and the effective config are byte-identical for 1, 2 and 3
# threads with 3 layouts; a layout that fails in its child fails the run with the message,
# exit status and (absent) outputs of the one-process run.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
common=(--set 'sim.tier="cycle"' --set image.width=24 --set image.height=16 --set l1.size=1024
        --set 'layout.kind=["dfl","odfl","veb"]')

# Stats without the keys that time the run.
strip() {
  python3 - "$1" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(json.dumps({k: v for k, v in s.items() if "seconds" not in k and "per_second" not in k or k.startswith("report.")}, sort_keys=True, indent=1))
PY
}

for t in 1 2 3; do
  d="$tmp/run$t"
  "$rtusim" run "$src/configs/default.toml" "${common[@]}" --threads $t --out "$d" > /dev/null
  strip "$d/stats.json" > "$d/stats.stripped"
  rm "$d/stats.json"
  if [ $t -gt 1 ]; then diff -r "$tmp/run1" "$d" || { echo "run differs: threads=$t" >&2; exit 1; }; fi
done
# The runs really simulated every layout, each its own way.
python3 - "$tmp/run3/stats.stripped" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
for kind in ("dfl", "odfl", "veb"):
    assert s[f"layout.{kind}.sim.cycles"] > 0 and s[f"layout.{kind}.l1.misses"] > 0, kind
assert s["layout.dfl.sim.cycles"] != s["layout.odfl.sim.cycles"]
PY

# A failing layout: odfl's VCD path is a directory, which only its child finds out.
mkdir -p "$tmp/vcd/unit_odfl.vcd"
for t in 1 3; do
  set +e
  "$rtusim" run "$src/configs/default.toml" "${common[@]}" --set "sim.vcd=\"$tmp/vcd/unit.vcd\"" \
    --threads $t --out "$tmp/fail$t" > /dev/null 2> "$tmp/fail$t.err"
  echo $? > "$tmp/fail$t.status"
  set -e
  test ! -e "$tmp/fail$t" || { echo "failed run left outputs (threads=$t)" >&2; exit 1; }
done
test "$(cat "$tmp/fail1.status")" = 2
grep -q "unit_odfl.vcd: is a directory" "$tmp/fail1.err"
cmp "$tmp/fail1.status" "$tmp/fail3.status"
# The same stderr; a sanitizer build's own reports (lines of ==PID== and what follows them, e.g.
# ASan's note on SystemC's coroutine stacks, once per process) are not the run's output.
rtusim_lines() { grep -v -e '^==[0-9]*==' -e '^False positive error reports' -e '^For details see' "$1" || true; }
diff <(rtusim_lines "$tmp/fail1.err") <(rtusim_lines "$tmp/fail3.err")
if ls "$tmp/vcd" | grep -q '\.tmp-'; then echo "a child left a temporary VCD" >&2; exit 1; fi
echo "layout_processes: ok"
