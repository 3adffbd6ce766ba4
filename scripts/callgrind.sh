#!/usr/bin/env bash
# Instructions and instruction-cache misses per call (bench/README.md, "Work counts and
# instruction counts"): builds dyngen_call_counts (with it the generated code of every package
# dyngen_bench times), runs each function of each package under valgrind --tool=callgrind with its
# cache simulation and writes callgrind.md and callgrind.json.
#
#   scripts/callgrind.sh                        every package: generated, snapped, unrolled, runtime and
#                                               hand-written code, into bench/results
#   scripts/callgrind.sh '^(ur5|panda)' DIR     the packages whose names match an extended regex,
#                                               into DIR
#
# BUILD_DIR chooses the build directory (default build-bench, shared with scripts/bench.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/callgrind.sh

filter=${1:-.}
results=${2:-bench/results}
calls=100  # callgrind counts exactly; more calls only average over more of the 16 states
start=$SECONDS

callgrind_build dyngen_call_counts

# CALLS calls of a function: its instructions and level-1 instruction-cache misses
count() {
  local counts
  counts=$(callgrind_counts "$scratch" "$tool" "$@")
  echo "$* $counts" >>"$scratch/counts"
}

packages=()
while read -r line; do
  [[ ${line%% *} =~ $filter ]] && packages+=("$line")
done < <("$tool" --list)
[ ${#packages[@]} -gt 0 ] || { echo "no package matches '$filter'" >&2; exit 1; }
echo "== counting ${#packages[@]} packages under callgrind"
read -r first _ <<<"${packages[0]}"
count "$first" none rnea "$calls"
for line in "${packages[@]}"; do
  read -r package implementations <<<"$line"
  echo "  $package"
  for implementation in $implementations; do
    for algorithm in rnea crba aba; do
      count "$package" "$implementation" "$algorithm" "$calls"
    done
  done
done

echo "== writing $results/callgrind.md and callgrind.json"
"$tool" --report "$scratch/counts" "$results" >/dev/null
echo "done in $((SECONDS - start)) s"
