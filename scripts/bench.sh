#!/usr/bin/env bash
# Builds and runs the benchmarks (bench/README.md) and writes bench/results/: benchmarks.md
# (the table), benchmarks.json (Google Benchmark's raw output), benchmarks.gp and
# benchmarks.svg (the plot). Extra arguments go to dyngen_bench, for instance
# --benchmark_filter=ur5 or --benchmark_min_time=0.5.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh
jobs=$(nproc)
results=bench/results
start=$SECONDS

echo "== configuring build-bench"
cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DDYNGEN_BUILD_BENCH=ON >/dev/null
echo "== building dyngen and the generated code of every benchmarked robot (minutes)"
cmake --build build-bench --target dyngen_bench -j "$jobs"

# Repetitions interleaved at random, so that a burst of load from a neighbour on a shared
# machine spreads over many benchmarks instead of falling on a few.
echo "== running the benchmarks (minutes; the median of 3 repetitions of at least 0.1 s each)"
mkdir -p "$results"
build-bench/bench/dyngen_bench --benchmark_repetitions=3 --benchmark_min_time=0.1 \
  --benchmark_enable_random_interleaving=true \
  --benchmark_out="$results/benchmarks.json" --benchmark_out_format=json "$@" "$results"

echo "== drawing the plot"
(cd "$results" && gnuplot benchmarks.gp)
echo "wrote $results/benchmarks.md, benchmarks.json, benchmarks.gp and benchmarks.svg" \
     "in $((SECONDS - start)) s"
