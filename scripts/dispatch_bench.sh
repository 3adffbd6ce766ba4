#!/usr/bin/env bash
# The load-time dispatch against the baseline alone (docs/performance.md, "Instruction sets"):
# writes each robot's rnea, crba, aba, minv, rnea_derivatives and aba_derivatives twice into
# build-bench/dispatch/, compiles one copy with -DDYNGEN_NO_DISPATCH and one as a user's build
# does (both -O3 -ffp-contract=off), builds bench/dispatch_bench.cpp over them and runs it
# pinned to CPU 0, writing a table of the medians to bench/results/dispatch.md (OUT to change).
# The baseline copy's kernels are renamed (-Dkernels=kernels_baseline) so that the linker keeps
# each copy's own instantiations. ROBOTS: "name urdf dyngen-options" lines. About 5 minutes on
# 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh bench
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --target dyngen -j "$(nproc)" >/dev/null
dir=build-bench/dispatch
out=${OUT:-bench/results/dispatch.md}
robots=${ROBOTS:-"ur5 tests/models/ur5.urdf
iiwa14 tests/models/iiwa14.urdf
solo12_floating tests/models/solo12.urdf --floating-base
anymal_c_floating tests/models/anymal_c.urdf --floating-base"}
rm -rf "$dir" && mkdir -p "$dir" "$(dirname "$out")"
packages=$dir/packages.hpp
list=""
jobs=()
while read -r name urdf options; do
  [ -n "$name" ] || continue
  for build in baseline dispatch; do
    package=${name}_${build}
    # shellcheck disable=SC2086
    build/dyngen "$urdf" $options --name "$package" -o "$dir/$package" --quiet \
      --algorithms rnea,crba,aba,minv,rnea_derivatives,aba_derivatives 2>/dev/null
    echo "#include \"$package/${package}_dynamics.hpp\"" >>"$packages"
    defines=""
    [ "$build" = baseline ] && defines="-DDYNGEN_NO_DISPATCH -Dkernels=kernels_baseline"
    jobs+=("$dir/$package/${package}_dynamics.cpp $defines")
  done
  list+=" ROBOT(\"$name\", ${name}_baseline, ${name}_dispatch)"
done <<<"$robots"
echo "#define ROBOTS$list" >>"$packages"

echo "== compiling ${#jobs[@]} packages (minutes)"
flags=(-std=c++17 -O3 -ffp-contract=off)
objects=()
running=0
for job in "${jobs[@]}"; do
  read -r source defines <<<"$job"
  # shellcheck disable=SC2086
  g++ "${flags[@]}" $defines -c "$source" -o "$source.o" &
  objects+=("$source.o")
  running=$((running + 1))
  if [ "$running" -ge "$(nproc)" ]; then wait -n; running=$((running - 1)); fi
done
while [ "$running" -gt 0 ]; do wait -n; running=$((running - 1)); done
g++ "${flags[@]}" -I"$dir" bench/dispatch_bench.cpp "${objects[@]}" -lbenchmark -lpthread \
  -o "$dir/dispatch_bench"
taskset -c 0 "$dir/dispatch_bench" --benchmark_repetitions=5 --benchmark_min_time=0.1 \
  --benchmark_report_aggregates_only=true --benchmark_enable_random_interleaving=true \
  --benchmark_out="$dir/dispatch.json" >/dev/null
# medians of the CPU time, ns, and the baseline's over the dispatched build's
python3 - "$dir/dispatch.json" "$out" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))
median = {r["run_name"]: r["cpu_time"] for r in runs["benchmarks"] if r.get("aggregate_name") == "median"}
rows = {}
for name, t in median.items():
    robot, function, build = name.split("/")
    rows.setdefault((robot, function), {})[build] = t
ctx = runs["context"]
lines = ["# The generated code for the baseline alone and as a user's build compiles it", "",
         "`scripts/dispatch_bench.sh`: *baseline* compiled with `-DDYNGEN_NO_DISPATCH`, "
         "*dispatch* as the package's CMake does by default (the loader runs the AVX2 clone "
         "here), both g++ -O3 -ffp-contract=off, in one binary; the bits checked equal. "
         f"{ctx['date']}, {ctx['num_cpus']} CPUs at {ctx['mhz_per_cpu']} MHz, pinned to CPU 0; "
         "medians of 5 repetitions interleaved at random, CPU ns per call.", "",
         "| robot | function | baseline | dispatch | baseline / dispatch |", "|---|---|---:|---:|---:|"]
functions = ["rnea", "crba", "aba", "minv", "rnea_derivatives", "aba_derivatives"]
for (robot, function), t in sorted(rows.items(), key=lambda r: (r[0][0], functions.index(r[0][1]))):
    lines.append(f"| {robot} | {function} | {t['baseline']:.0f} | {t['dispatch']:.0f} | "
                 f"{t['baseline'] / t['dispatch']:.2f} |")
open(sys.argv[2], "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
