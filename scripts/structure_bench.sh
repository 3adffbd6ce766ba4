#!/usr/bin/env bash
# The code structures side by side (docs/performance.md, "Code structure"): writes each robot's
# rnea, crba, aba, frame_accelerations and centroidal with --structure unrolled, shared, lanes
# and auto into build-bench/structure/, builds bench/structure_bench.cpp over them with the
# generated code's flags (-O3 -ffp-contract=off, EXTRA_FLAGS added, e.g. -mavx2) and runs it,
# pinned to CPU 0, writing a table of the medians to bench/results/structure/lanes.md (OUT to
# change). ROBOTS: "name urdf dyngen-options" lines; default solo12, anymal_c and atlas on a
# floating base. About 5 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh bench
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --target dyngen -j "$(nproc)" >/dev/null
dir=build-bench/structure
out=${OUT:-bench/results/structure/lanes.md}
robots=${ROBOTS:-"solo12_floating tests/models/solo12.urdf --floating-base
anymal_c_floating tests/models/anymal_c.urdf --floating-base
atlas_floating tests/models/atlas.urdf --floating-base"}
rm -rf "$dir" && mkdir -p "$dir" "$(dirname "$out")"
packages=$dir/packages.hpp
list=""
objects=()
while read -r name urdf options; do
  [ -n "$name" ] || continue
  names=()
  for structure in unrolled shared lanes auto; do
    package=${name}_${structure}
    # shellcheck disable=SC2086
    build/dyngen "$urdf" $options --structure "$structure" --name "$package" -o "$dir/$package" \
      --algorithms rnea,crba,aba,frame_accelerations,centroidal --quiet 2>/dev/null
    echo "#include \"$package/${package}_dynamics.hpp\"" >>"$packages"
    objects+=("$dir/$package/${package}_dynamics.cpp")
    names+=("$package")
  done
  list+=" ROBOT(\"$name\", ${names[0]}, ${names[1]}, ${names[2]}, ${names[3]})"
done <<<"$robots"
echo "#define ROBOTS$list" >>"$packages"

echo "== compiling ${#objects[@]} packages (minutes)"
flags=(-std=c++17 -O3 -ffp-contract=off ${EXTRA_FLAGS:-})
printf '%s\n' "${objects[@]}" |
  xargs -P "$(nproc)" -I{} g++ "${flags[@]}" -c {} -o {}.o
g++ "${flags[@]}" -I"$dir" bench/structure_bench.cpp "${objects[@]/%/.o}" -lbenchmark \
  -lpthread -o "$dir/structure_bench"
taskset -c 0 "$dir/structure_bench" --benchmark_repetitions=5 --benchmark_min_time=0.1 \
  --benchmark_report_aggregates_only=true --benchmark_enable_random_interleaving=true \
  --benchmark_out="$dir/structure.json" >/dev/null
# medians of the CPU time, ns, and each structure's over lanes'
python3 - "$dir/structure.json" "$out" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))
median = {r["run_name"]: r["cpu_time"] for r in runs["benchmarks"] if r.get("aggregate_name") == "median"}
structures = ["unrolled", "shared", "lanes", "auto"]
rows = {}
for name, t in median.items():
    robot, function, structure = name.split("/")
    rows.setdefault((robot, function), {})[structure] = t
ctx = runs["context"]
lines = [f"{ctx['date']}, {ctx['num_cpus']} CPUs at {ctx['mhz_per_cpu']} MHz, pinned to CPU 0; "
         "medians of 5 repetitions, CPU ns per call", "",
         "| robot | function | " + " | ".join(structures) + " | unrolled / lanes | shared / lanes |",
         "|---|---|" + "---:|" * (len(structures) + 2)]
for (robot, function), t in rows.items():
    lines.append(f"| {robot} | {function} | " + " | ".join(f"{t[s]:.0f}" for s in structures) +
                 f" | {t['unrolled'] / t['lanes']:.2f} | {t['shared'] / t['lanes']:.2f} |")
open(sys.argv[2], "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
