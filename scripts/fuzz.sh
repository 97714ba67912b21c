#!/usr/bin/env bash
# Runs the libFuzzer targets (config, gltf, trace) at once, each for SECONDS on its seed corpus
# under ASan+UBSan, and prints the executions and any finding. New inputs go to a scratch corpus
# (the seeds in tests/fuzz/corpus/ stay as committed); a crash input is saved in the scratch
# directory and fails the script.
#   scripts/fuzz.sh [SECONDS=60] [BUILD_DIR=build-sanitize]
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-60}"
build="${2:-build-sanitize}"
bash scripts/sanitize.sh --build-only "$build"

work="$(mktemp -d "${TMPDIR:-/tmp}/rtusim-fuzz.XXXXXX")"
echo "fuzz: ${secs} s per target, scratch corpus and findings in $work"
declare -A seeds=([config]="config" [gltf]="gltf glb" [trace]="trace")
# The three targets run at once (each is one process, for the same wall time whatever the
# cores); each one's exit status is then read with `wait` on its pid, in order.
declare -A pids
for t in config gltf trace; do
  mkdir -p "$work/$t/corpus" "$work/$t/crashes"
  for s in ${seeds[$t]}; do cp tests/fuzz/corpus/"$s"/* "$work/$t/corpus/"; done
  ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/tests/fuzz/fuzz_$t" -max_total_time="$secs" -rss_limit_mb=2048 -timeout=10 \
      -print_final_stats=1 -artifact_prefix="$work/$t/crashes/" "$work/$t/corpus" \
      >"$work/$t/log.txt" 2>&1 &
  pids[$t]=$!
done
status=0
for t in config gltf trace; do
  log="$work/$t/log.txt"
  if wait "${pids[$t]}"; then
    result="no finding"
  else
    result="FINDING (see $log and $work/$t/crashes/)"
    status=1
  fi
  execs="$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')"
  echo "fuzz_$t: $execs executions, $(ls "$work/$t/corpus" | wc -l) corpus inputs, $result"
done
exit $status
