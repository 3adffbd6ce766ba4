#!/usr/bin/env bash
# The Python modules' throughput (bench/python_bench.py): generates ur5, solo12 floating and
# atlas floating with --python (rnea, crba, aba), builds each with its own CMake for AVX2 into
# build-python-bench/, and writes bench/results/python.md. Needs a Release build in build/
# (scripts/quickstart.sh or scripts/test.sh makes one).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh python
python=/usr/bin/python3  # Debian's, which has python3-numpy
root=build-python-bench
cmake --build build --target dyngen -j "$(nproc)" >/dev/null
modules=()
path=""
for entry in "ur5|tests/models/ur5.urdf|" "solo12_floating|tests/models/solo12.urdf|--floating-base" \
             "atlas_floating|tests/models/atlas.urdf|--floating-base"; do
  IFS='|' read -r name robot options <<<"$entry"
  # shellcheck disable=SC2086
  scripts/build_module.sh "$root" "$name" "$robot" "$python" --python --algorithms rnea,crba,aba $options
  modules+=("${name}_dynamics")
  path="$path${path:+:}$PWD/$root/$name/build"
done
mkdir -p bench/results
PYTHONPATH="$path" "$python" bench/python_bench.py "${modules[@]}" --out bench/results/python.md
