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

scripts/install_deps.sh
build=${BUILD_DIR:-build-bench}
filter=${1:-.}
results=${2:-bench/results}
calls=100  # callgrind counts exactly; more calls only average over more of the 16 states
start=$SECONDS

echo "== configuring $build and building dyngen_call_counts (minutes the first time)"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DDYNGEN_BUILD_BENCH=ON >/dev/null
cmake --build "$build" --target dyngen_call_counts -j "$(nproc)"
tool=$build/bench/dyngen_call_counts

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# instructions and level-1 instruction-cache misses collected inside dyngen_measured_call over
# CALLS calls; LD_BIND_NOW resolves every symbol at start-up, so that no first call pays the
# dynamic linker. The simulated caches are this machine's level 1 (32 KB, 8 ways, 64-byte lines),
# given rather than detected, so that the counts do not depend on what valgrind recognises.
count() {
  LD_BIND_NOW=1 valgrind --tool=callgrind --collect-atstart=no \
    --cache-sim=yes --I1=32768,8,64 --D1=32768,8,64 --LL=1048576,16,64 \
    --toggle-collect=dyngen_measured_call --callgrind-out-file="$scratch/out" \
    "$tool" "$@" >/dev/null 2>"$scratch/log" || { cat "$scratch/log" >&2; exit 1; }
  # summary: Ir Dr Dw I1mr D1mr D1mw ILmr DLmr DLmw
  grep -qx 'events: Ir Dr Dw I1mr D1mr D1mw ILmr DLmr DLmw' "$scratch/out" ||
    { echo "callgrind.sh: unexpected events in callgrind's output" >&2; exit 1; }
  read -r ir _ _ i1_misses _ < <(sed -n 's/^summary: //p' "$scratch/out")
  echo "$* $ir $i1_misses" >>"$scratch/counts"
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
