#!/usr/bin/env bash
# Output faults: the commit is all-or-nothing (one rename / exchange of the whole directory), a
# directory in the way fails before anything moves, SIGINT/SIGTERM at any moment leaves the
# complete outputs or none (never a staging directory), and a full disk is a clear exit 2.
set -uo pipefail
rtusim=$(realpath "$1"); src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0
bad() { echo "FAIL $*"; fail=$((fail+1)); }
ok() { pass=$((pass+1)); }
D="$src/configs/default.toml"
small=(--set image.width=24 --set image.height=16)
staging() { find "$tmp" -name '.rtusim-staging-*' -o -name '*.tmp-*'; }

# A directory named like an output: exit 2 naming it, the existing directory untouched.
mkdir -p "$tmp/o1/image.png" && echo old > "$tmp/o1/notes.txt"
"$rtusim" run "$D" "${small[@]}" --out "$tmp/o1" > /dev/null 2> "$tmp/err"; rc=$?
if [ $rc -eq 2 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q "o1/image.png: is a directory" "$tmp/err" &&
   [ "$(ls -A "$tmp/o1" | tr '\n' ' ')" = "image.png notes.txt " ] && [ -z "$(staging)" ]; then ok
else bad "commit_blocked: exit $rc, $(cat "$tmp/err"), left: $(ls -A "$tmp/o1") $(staging)"; fi

# Into an existing directory: outputs replaced, the user's other files and folders kept.
mkdir -p "$tmp/o2/sub" && echo mine > "$tmp/o2/notes.txt" && echo stale > "$tmp/o2/stats.json"
"$rtusim" run "$D" "${small[@]}" --out "$tmp/o2" > /dev/null 2>&1; rc=$?
if [ $rc -eq 0 ] && [ "$(cat "$tmp/o2/notes.txt")" = mine ] && [ -d "$tmp/o2/sub" ] &&
   grep -q '"rays.total"' "$tmp/o2/stats.json" && [ -s "$tmp/o2/image.png" ] && [ -z "$(staging)" ]; then ok
else bad "existing_dir: exit $rc, $(ls -A "$tmp/o2")"; fi

# --out . (the working directory): the directory itself stays (same inode), outputs land in it.
mkdir -p "$tmp/here" && echo mine > "$tmp/here/notes.txt"
inode=$(stat -c %i "$tmp/here")
(cd "$tmp/here" && "$rtusim" run "$D" "${small[@]}" --out . > /dev/null 2>&1); rc=$?
if [ $rc -eq 0 ] && [ "$(stat -c %i "$tmp/here")" = "$inode" ] && [ -s "$tmp/here/stats.json" ] &&
   [ "$(cat "$tmp/here/notes.txt")" = mine ] && [ -z "$(staging)" ]; then ok
else bad "out_cwd: exit $rc, $(ls -A "$tmp/here")"; fi

# Full disk (a 1 KiB file-size limit; writes fail with EFBIG): exit 2, one line, nothing left.
(trap '' XFSZ; ulimit -f 1; exec "$rtusim" run "$D" "${small[@]}" --out "$tmp/o3") > /dev/null 2> "$tmp/err"; rc=$?
if [ $rc -eq 2 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q "cannot write" "$tmp/err" &&
   [ ! -e "$tmp/o3" ] && [ -z "$(staging)" ]; then ok
else bad "full_disk: exit $rc, $(cat "$tmp/err"), left: $(ls -A "$tmp") "; fi
(trap '' XFSZ; ulimit -f 1; exec "$rtusim" trace "$D" "${small[@]}" --out "$tmp/t.din") > /dev/null 2> "$tmp/err"; rc=$?
if [ $rc -eq 2 ] && grep -q "cannot write" "$tmp/err" && [ ! -e "$tmp/t.din" ] && [ -z "$(staging)" ]; then ok
else bad "full_disk_trace: exit $rc, $(cat "$tmp/err")"; fi

# Killed at spread-out moments: all or nothing, never a staging directory or temporary file.
# The kills must not all land after the run ended (a 96x96 frame took 0.09 s, so every kill
# from 0.1 s on found a finished run): the frame is 384x384 (about 0.6 s), and per signal some
# kill at 0.1 s or later (the process long started) must stop a running rtusim, which then dies
# of the signal (exit 128 + its number) leaving no output.
complete() { [ -s "$1/stats.json" ] && [ -s "$1/config.toml" ] && [ -s "$1/image.png" ]; }
for sig in INT TERM; do
  signum=$(kill -l "$sig"); interrupted=0; finished=0
  for delay in 0 0.02 0.05 0.1 0.2 0.4 0.8 1.5 3; do
    o="$tmp/k_${sig}_$delay"
    "$rtusim" run "$D" --set image.width=384 --set image.height=384 --out "$o" > /dev/null 2>&1 &
    pid=$!
    sleep "$delay"; kill -s "$sig" "$pid" 2>/dev/null; wait "$pid"; rc=$?
    if { [ ! -e "$o" ] || complete "$o"; } && [ -z "$(staging)" ]; then ok
    else bad "kill_${sig}_$delay: $(ls -A "$o" 2>/dev/null) $(staging)"; fi
    if [ $rc -eq $((128 + signum)) ] && [ ! -e "$o" ] && awk -v d="$delay" 'BEGIN { exit !(d >= 0.1) }'; then
      interrupted=$((interrupted+1))
    fi
    [ $rc -eq 0 ] && complete "$o" && finished=$((finished+1))
  done
  [ $interrupted -ge 1 ] && ok || bad "kill_$sig: no kill at 0.1 s or later stopped a running rtusim"
  echo "kill_$sig: $interrupted runs stopped from 0.1 s on, $finished finished before their kill"
  # The same for a single-file output: stopped while writing, nothing left.
  "$rtusim" trace "$D" --set image.width=384 --set image.height=384 --out "$tmp/k.din" > /dev/null 2>&1 &
  pid=$!; sleep 0.2; kill -s "$sig" "$pid" 2>/dev/null; wait "$pid"; rc=$?
  if [ -z "$(staging)" ] && { [ $rc -eq 0 ] || [ ! -e "$tmp/k.din" ]; }; then ok
  else bad "kill_trace_$sig: exit $rc, $(staging)"; fi
  rm -f "$tmp/k.din"
done

# A run into the directory of an earlier one: the earlier pictures this run does not draw go
# (two layouts' heatmaps and their difference, then one layout and no image), the user's file
# stays; from the working directory itself too (renamed in one by one).
for where in other inside; do
  rm -rf "$tmp/again" && mkdir -p "$tmp/again" && echo mine > "$tmp/again/notes.txt"
  "$rtusim" run "$D" "${small[@]}" --set 'layout.kind=["dfl","odfl"]' --out "$tmp/again" > /dev/null || bad "again: first run"
  if [ "$where" = inside ]; then
    (cd "$tmp/again" && "$rtusim" run "$D" "${small[@]}" --set image.png=false --out . > /dev/null) || bad "again: second run ($where)"
  else
    "$rtusim" run "$D" "${small[@]}" --set image.png=false --out "$tmp/again" > /dev/null || bad "again: second run ($where)"
  fi
  got=$(cd "$tmp/again" && ls | tr '\n' ' ')
  [ "$got" = "config.toml heatmap_dfl.png notes.txt stats.json " ] && ok || bad "again ($where): left $got"
done
# A dangling link in the output directory is kept like any other file.
rm -rf "$tmp/dl" && mkdir -p "$tmp/dl" && ln -s "$tmp/nowhere" "$tmp/dl/zz_link" && ln -s "$tmp/nowhere" "$tmp/dl/image.png"
"$rtusim" run "$D" "${small[@]}" --set image.png=false --out "$tmp/dl" > /dev/null 2> "$tmp/dl.err" && [ -L "$tmp/dl/zz_link" ] \
  && ok || bad "dangling link: $(cat "$tmp/dl.err")"
# config.toml runs again from another directory when the config gave a relative scene path.
python3 "$src/tests/cli/make_bad_inputs.py" "$tmp/rel/scenes" > /dev/null || bad "relative scene: inputs"
printf '[scene]\npath = "scenes/good.glb"\n[camera]\neye = [0.2, 0.2, 2]\ntarget = [0.2, 0.2, 0]\n' > "$tmp/rel/rel.toml"
(cd "$tmp/rel" && "$rtusim" run rel.toml "${small[@]}" --out first > /dev/null) || bad "relative scene: first run"
(cd "$tmp" && "$rtusim" run rel/first/config.toml --out rerun > /dev/null) && cmp -s <(grep -v second "$tmp/rel/first/stats.json") <(grep -v second "$tmp/rerun/stats.json") \
  && ok || bad "relative scene: config.toml does not run again from elsewhere"

# A single output file (trace, hits): written through a symbolic link (the link kept), a FIFO
# (or a device) refused without touching it, and a write failure named by --out, not by the
# temporary file, with nothing left.
t8=(--set image.width=8 --set image.height=8)
mkdir -p "$tmp/one" && echo keep > "$tmp/one/target.bin" && ln -s target.bin "$tmp/one/link.bin"
"$rtusim" trace "$D" "${t8[@]}" --format bin --out "$tmp/one/link.bin" > /dev/null \
  && [ -L "$tmp/one/link.bin" ] && [ "$(head -c 4 "$tmp/one/target.bin")" != keep ] \
  && ok || bad "trace through a symbolic link"
mkfifo "$tmp/one/fifo"
set +e
"$rtusim" hits "$D" "${t8[@]}" --out "$tmp/one/fifo" > /dev/null 2> "$tmp/one/fifo.err"; rc=$?
set -e
[ $rc -eq 2 ] && [ -p "$tmp/one/fifo" ] && grep -q "fifo: exists and is not a regular file" "$tmp/one/fifo.err" \
  && ok || bad "hits onto a FIFO: exit $rc, $(cat "$tmp/one/fifo.err")"
set +e
(trap '' XFSZ; ulimit -f 4; "$rtusim" trace "$D" "${t8[@]}" --out "$tmp/one/big.din" > /dev/null 2> "$tmp/one/big.err"); rc=$?
set -e
[ $rc -eq 2 ] && grep -q "^rtusim: $tmp/one/big.din: cannot write" "$tmp/one/big.err" \
  && [ -z "$(ls "$tmp/one" | grep big.din)" ] && ok || bad "a write failure: exit $rc, $(cat "$tmp/one/big.err")"

echo "output_faults: $pass passed, $fail failed"
[ $fail -eq 0 ]
