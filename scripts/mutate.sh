#!/usr/bin/env bash
# Mutation testing (issue 40): applies each mutation kept in tests/mutations/ (one patch per
# mutation, a small plausible bug in the model) alone to a scratch clone of HEAD, rebuilds, runs
# the tests with CI=true, and reports which mutations the tests catch (some test fails) and by
# which tests. A tool for us, not part of CI.
#
# usage: scripts/mutate.sh [--all] [--scratch DIR] [MUTATION...]
#   MUTATION     names of tests/mutations/*.patch (default: every one)
#   (default)    per mutation, the tests its "# tests:" line names (a ctest -R regex): the ones
#                meant to catch it, in seconds; the table says "subset"
#   --all        the whole suite per mutation (about 3 minutes each on 2 cores)
#   --scratch    the scratch clone (default: rtusim-mutate beside this checkout, so that its
#                ../shared/scenes is this one's); an existing one is reset
#                to this checkout's HEAD and its build reused, so a rerun builds incrementally
# The subsets are built without the RTL (-DRTUSIM_BUILD_RTL=OFF: no mutation touches it, and
# the Verilator builds are most of a full build); --all builds it. Before the mutations, the
# same tests must pass on the unmutated clone, else a "caught" would mean nothing. The table
# (markdown) goes to stdout and to SCRATCH/mutations.md.
set -uo pipefail
src=$(git -C "$(dirname "$0")/.." rev-parse --show-toplevel)
scratch=$(dirname "$src")/rtusim-mutate
all=false
names=()
while [ $# -gt 0 ]; do
  case $1 in
    --all) all=true ;;
    --scratch) scratch=$2; shift ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) names+=("$1") ;;
  esac
  shift
done
if [ ${#names[@]} -eq 0 ]; then
  for p in "$src"/tests/mutations/*.patch; do names+=("$(basename "$p" .patch)"); done
fi
for n in "${names[@]}"; do
  [ -f "$src/tests/mutations/$n.patch" ] || { echo "mutate: no tests/mutations/$n.patch" >&2; exit 2; }
done
export CI=true RTUSIM_SCENES=${RTUSIM_SCENES:-$src/../shared/scenes}
log=$scratch/logs
build=$scratch/build

# The scratch clone at this checkout's HEAD (committed state: commit what you want mutated).
if [ ! -d "$scratch/.git" ]; then
  git init -q "$scratch" || exit 1
fi
git -C "$scratch" fetch -q "$src" HEAD && git -C "$scratch" checkout -q --force FETCH_HEAD &&
  git -C "$scratch" clean -qfd -e build -e logs -e mutations.md || exit 1
mkdir -p "$log"
echo "mutate: scratch clone $scratch at $(git -C "$scratch" rev-parse --short HEAD)" >&2

rtl=$($all && echo ON || echo OFF)  # the whole suite has RTL tests (cli.rtl_tier among them)
rebuild() {
  cmake -S "$scratch" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRTUSIM_BUILD_RTL=$rtl \
    > "$log/configure.txt" 2>&1 || return 1
  nice -n 10 cmake --build "$build" -j2 > "$1" 2>&1
}

# The tests one mutation runs: its "# tests:" regex, or everything.
regex_of() { sed -n 's/^# tests: //p' "$src/tests/mutations/$1.patch"; }
run_tests() {  # regex ("" = all), log file; prints the failed tests, one a line
  local args=(--timeout 600 -j2)
  [ -n "$1" ] && args+=(-R "$1")
  (cd "$build" && nice -n 10 ctest "${args[@]}" > "$2" 2>&1)
  sed -n '/The following tests FAILED/,$p' "$2" | sed -n 's/^[[:space:]]*[0-9]* - \([^ ]*\) .*/\1/p'
  grep -q "No tests were found" "$2" && echo "(no tests matched)"
}

echo "mutate: building the unmutated clone" >&2
rebuild "$log/build_base.txt" || { echo "mutate: the unmutated clone does not build: $log/build_base.txt" >&2; exit 1; }
base_regex=""
if ! $all; then
  for n in "${names[@]}"; do base_regex+="${base_regex:+|}$(regex_of "$n")"; done
fi
echo "mutate: baseline tests" >&2
base_failed=$(run_tests "$base_regex" "$log/tests_base.txt")
if [ -n "$base_failed" ]; then
  echo "mutate: tests fail without any mutation (see $log/tests_base.txt):" >&2
  echo "$base_failed" >&2
  exit 1
fi

table="| mutation | tests run | caught | by |
|---|---|---|---|"
caught=0
for n in "${names[@]}"; do
  patch=$src/tests/mutations/$n.patch
  what=$(sed -n 's/^# mutation: //p' "$patch")
  regex=""; $all || regex=$(regex_of "$n")
  scope=$($all && echo "all" || echo "subset: \`${regex//|/\\|}\`")  # | escaped for the table
  git -C "$scratch" checkout -q -- . && git -C "$scratch" apply "$patch" ||
    { echo "mutate: $n does not apply" >&2; table+=$'\n'"| $what | $scope | does not apply | |"; continue; }
  echo "mutate: $n: building" >&2
  if ! rebuild "$log/build_$n.txt"; then
    table+=$'\n'"| $what | $scope | does not build | $log/build_$n.txt |"
  else
    echo "mutate: $n: testing" >&2
    failed=$(run_tests "$regex" "$log/tests_$n.txt" | tr '\n' ' ' | sed 's/ $//')
    if [ -n "$failed" ] && [ "$failed" != "(no tests matched)" ]; then
      caught=$((caught+1))
      table+=$'\n'"| $what | $scope | **caught** | ${failed// /, } |"
    else
      table+=$'\n'"| $what | $scope | not caught | |"
    fi
  fi
  git -C "$scratch" checkout -q -- .
done
table+=$'\n\n'"$caught of ${#names[@]} mutations caught (clone at $(git -C "$scratch" rev-parse --short HEAD), $(date -u '+%Y-%m-%d %H:%M UTC'))."
echo "$table" | tee "$scratch/mutations.md"
[ "$caught" -eq "${#names[@]}" ]
