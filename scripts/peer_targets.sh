#!/usr/bin/env bash
# Builds dyngen_derivatives_bench and times the functions of issue 45's targets (bench/README.md,
# "Against Pinocchio's derivatives"), then writes bench/results/peer_targets.md (the targets, met
# or missed), peer_targets.json (Google Benchmark's output) and peer_targets.txt (what the bench
# printed: its operation table). Extra arguments go to the bench.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh bench
echo "== configuring build-bench"
cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DDYNGEN_BUILD_BENCH=ON >/dev/null
echo "== building dyngen and the derivative packages (minutes)"
cmake --build build-bench --target dyngen_derivatives_bench -j "$(nproc)"
echo "== running (the median of 5 repetitions of at least 0.2 s each, interleaved at random)"
results=bench/results
mkdir -p "$results"
packages='ur5 fixed|iiwa14 fixed|panda fixed|solo12 floating|anymal_c floating|atlas fixed|atlas floating'
functions='rnea|crba|aba|minv|rnea_derivatives|rnea_derivatives_with_M|aba_derivatives'
build-bench/bench/dyngen_derivatives_bench --benchmark_repetitions=5 --benchmark_min_time=0.2 \
  --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true \
  --benchmark_filter="^($packages)/($functions)\$" \
  --benchmark_out="$results/peer_targets.json" --benchmark_out_format=json "$@" \
  | tee "$results/peer_targets.txt"
python3 bench/peer_targets.py "$results/peer_targets.json" "$results/peer_targets.txt" \
  --out "$results/peer_targets.md"
