#!/usr/bin/env bash
# Builds dyngen_derivatives_bench and times the functions of issue 45's targets (bench/README.md,
# "Against Pinocchio's derivatives"), counts each target row's instructions and level-1
# instruction-cache misses per call under callgrind (as scripts/callgrind_derivatives.sh does),
# then writes bench/results/peer_targets.md (the targets, met or missed, with those measures),
# peer_targets.json (Google Benchmark's output), peer_targets.txt (what the bench printed: its
# operation table) and peer_targets_callgrind.txt (package|function|instructions|misses); the
# operations that body frames cannot remove come from dyngen_work_counts, which it reruns
# (work_counts.md and .json). Extra arguments go to the bench. About 10 minutes once built.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/callgrind.sh

scripts/install_deps.sh bench  # valgrind
callgrind_build dyngen_derivatives_bench
echo "== running (the median of 5 repetitions of at least 0.2 s each, interleaved at random)"
results=bench/results
mkdir -p "$results"
packages='ur5 fixed|iiwa14 fixed|panda fixed|solo12 floating|anymal_c floating|atlas fixed|atlas floating'
functions='rnea|crba|aba|minv|rnea_derivatives|rnea_derivatives_with_M|aba_derivatives'
"$tool" --benchmark_repetitions=5 --benchmark_min_time=0.2 \
  --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true \
  --benchmark_filter="^($packages)/($functions)\$" \
  --benchmark_out="$results/peer_targets.json" --benchmark_out_format=json "$@" \
  | tee "$results/peer_targets.txt"
echo "== counting instructions under callgrind (minutes)"
calls=64  # one call on each of the harness's 64 states
read -r harness_ir harness_i1 <<<"$(callgrind_counts "$scratch" "$tool" --count "ur5 fixed" none $calls)"
: >"$results/peer_targets_callgrind.txt"
while IFS='|' read -r package function; do
  read -r ir i1 <<<"$(callgrind_counts "$scratch" "$tool" --count "$package" "$function" $calls)"
  echo "$package|$function|$(((ir - harness_ir) / calls))|$(((i1 - harness_i1) / calls))" \
    >>"$results/peer_targets_callgrind.txt"
done < <(python3 bench/peer_targets.py --rows)
echo "== counting operations (dyngen_work_counts)"
cmake --build "${BUILD_DIR:-build-bench}" --target dyngen_work_counts -j "$(nproc)"
"${BUILD_DIR:-build-bench}/bench/dyngen_work_counts" "$results" >/dev/null
python3 bench/peer_targets.py "$results/peer_targets.json" "$results/peer_targets.txt" \
  --callgrind "$results/peer_targets_callgrind.txt" --frames "$results/work_counts.json" \
  --out "$results/peer_targets.md"
