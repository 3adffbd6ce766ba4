#!/usr/bin/env bash
# How much the generated code's speed depends on which physical pages hold it (bench/README.md,
# "Placement"): builds dyngen_bench, dyngen_batch_bench, dyngen_derivatives_bench and
# move_text.so in build-bench/, runs bench/placement.py over COPIES copies of each (default 10;
# about 16 minutes in all) and writes bench/results/placement_scalar.md (the generated scalar
# code of issue 16's table, and the snapped code of its two arms with rounded rotations),
# placement_batch.md (scalar, d4 and f8 code of issue 17's rows) and placement_derivatives.md
# (issue 13's ratios: rnea, aba, their derivatives and finite differences of aba on its four
# robots). Linux only.
set -euo pipefail
cd "$(dirname "$0")/.."

copies=${1:-10}
scripts/install_deps.sh bench
cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DDYNGEN_BUILD_BENCH=ON >/dev/null
echo "== building the benchmarks (minutes on a fresh build)"
cmake --build build-bench --target dyngen_bench dyngen_batch_bench dyngen_derivatives_bench \
  dyngen_move_text -j "$(nproc)"

mkdir -p bench/results
bin=build-bench/bench
python3 bench/placement.py --binary "$bin/dyngen_bench" --move-text "$bin/libdyngen_move_text.so" \
  --copies "$copies" --out bench/results/placement_scalar.md \
  --filter '^(ur5|iiwa14|panda|solo12|solo12_floating|anymal_c_floating|romeo|atlas|atlas_floating)/(rnea|crba|aba)/generated$|^(iiwa14|panda)/(rnea|crba|aba)/snapped$'
python3 bench/placement.py --binary "$bin/dyngen_batch_bench" \
  --move-text "$bin/libdyngen_move_text.so" --copies "$copies" \
  --out bench/results/placement_batch.md \
  --filter '^(ur5_fixed|solo12_floating|atlas_floating)/(rnea|crba|aba)/(scalar_double|batch_d4|batch_f8)$'
python3 bench/placement.py --binary "$bin/dyngen_derivatives_bench" \
  --move-text "$bin/libdyngen_move_text.so" --copies "$copies" \
  --out bench/results/placement_derivatives.md \
  --filter '^(ur5 fixed|iiwa14 fixed|solo12 floating|atlas floating)/(rnea|aba|rnea_derivatives|aba_derivatives|aba_finite_differences)$'
