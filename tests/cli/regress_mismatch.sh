#!/usr/bin/env bash
# `rtusim regress` catches changes: a copied case with one edited value, one deleted key and one
# added key reports exactly those three mismatches (case, key, expected, got) and exits 1; a bad
# case directory is bad input (exit 2, one line naming the file).
set -uo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0
ok() { pass=$((pass+1)); }
bad() { echo "FAIL $1"; fail=$((fail+1)); }

case=builtin_64_layouts
mkdir -p "$tmp/t" && cp -r "$src/traces/$case" "$tmp/t/"
python3 - "$tmp/t/$case/expected.json" <<'PY'
import json, sys
p = sys.argv[1]
e = json.load(open(p))
assert "l1.misses" in e and "rays.shadow" in e
e["l1.misses"] += 1
del e["rays.shadow"]
e["bogus.key"] = 7
json.dump(e, open(p, "w"), indent=2)
PY
misses=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['l1.misses'])" "$src/traces/$case/expected.json")
shadow=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['rays.shadow'])" "$src/traces/$case/expected.json")
"$rtusim" regress "$tmp/t" > "$tmp/out" 2> "$tmp/err"
rc=$?
[ $rc -eq 1 ] && ok || bad "edited case: exit $rc, want 1"
grep '^MISMATCH' "$tmp/out" | sort > "$tmp/got"
sort > "$tmp/want" <<EOT
MISMATCH $case bogus.key: expected 7, got (absent)
MISMATCH $case l1.misses: expected $((misses + 1)), got $misses
MISMATCH $case rays.shadow: expected (absent), got $shadow
EOT
if diff "$tmp/want" "$tmp/got" > "$tmp/diff"; then ok; else bad "mismatch lines differ:"; cat "$tmp/diff"; fi
grep -qx 'regress: 0 passed, 1 failed' "$tmp/out" && ok || { bad "summary line"; cat "$tmp/out"; }

# A second, untouched case passes beside the failing one; the summary counts both.
cp -r "$src/traces/box_96_layouts" "$tmp/t/"
"$rtusim" regress "$tmp/t" > "$tmp/out2" 2>&1
rc=$?
[ $rc -eq 1 ] && grep -qx 'regress: 1 passed, 1 failed' "$tmp/out2" && ok || { bad "two cases: exit $rc"; cat "$tmp/out2"; }

# expect_bad NAME PATTERN DIR: exit 2 with one stderr line matching PATTERN.
expect_bad() {
  "$rtusim" regress "$3" > /dev/null 2> "$tmp/stderr"
  local rc=$?
  if [ $rc -ne 2 ]; then bad "$1: exit $rc, want 2"; return; fi
  if [ "$(wc -l < "$tmp/stderr")" -ne 1 ]; then bad "$1: not one stderr line"; cat "$tmp/stderr"; return; fi
  grep -qE -- "$2" "$tmp/stderr" && ok || { bad "$1: stderr lacks /$2/"; cat "$tmp/stderr"; }
}
mkdir -p "$tmp/noconf/c1" && cp "$src/traces/$case/expected.json" "$tmp/noconf/c1/"
expect_bad no_config 'noconf/c1/config.toml: missing' "$tmp/noconf"
mkdir -p "$tmp/badjson/c1" && cp "$src/traces/$case/config.toml" "$tmp/badjson/c1/"
printf '{ "l1.misses": 3,\n' > "$tmp/badjson/c1/expected.json"
expect_bad bad_json 'badjson/c1/expected.json: not valid JSON' "$tmp/badjson"
mkdir -p "$tmp/noexp/c1" && cp "$src/traces/$case/config.toml" "$tmp/noexp/c1/"
expect_bad no_expected 'noexp/c1/expected.json: missing' "$tmp/noexp"
mkdir -p "$tmp/empty"
expect_bad no_cases 'empty: no reference cases' "$tmp/empty"
expect_bad no_dir 'nowhere: no such directory' "$tmp/nowhere"

echo "regress_mismatch: $pass passed, $fail failed"
[ $fail -eq 0 ]
