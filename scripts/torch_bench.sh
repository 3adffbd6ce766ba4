#!/usr/bin/env bash
# PyTorch forward dynamics with gradients against the plain-PyTorch peer (bench/torch_bench.py):
# generates ur5 and solo12 floating with --torch --algorithms aba in double and float, builds
# each with its own CMake for AVX2 into build-torch-bench/, and writes bench/results/torch.md.
# Needs a Release build in build/ (scripts/quickstart.sh or scripts/test.sh makes one).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh python
python=/usr/bin/python3  # Debian's, which has python3-numpy and python3-torch
root=build-torch-bench
cmake --build build --target dyngen -j "$(nproc)" >/dev/null
robots=()
path=""
for entry in "ur5|ur5|tests/models/ur5.urdf||double" "ur5|ur5_float|tests/models/ur5.urdf||float" \
             "solo12 floating|solo12_floating|tests/models/solo12.urdf|--floating-base|double" \
             "solo12 floating|solo12_floating_float|tests/models/solo12.urdf|--floating-base|float"; do
  IFS='|' read -r label name robot options scalar <<<"$entry"
  # shellcheck disable=SC2086
  scripts/build_module.sh "$root" "$name" "$robot" "$python" --torch --algorithms aba --scalar "$scalar" $options
  robots+=("$label=$name=$robot${options:+=floating}")
  path="$path${path:+:}$PWD/$root/$name/build"
done
mkdir -p bench/results
# glibc returns large blocks to the system after each call and maps them anew in the next,
# which the peer's many temporaries pay for more than the timing means to show: keep them
export MALLOC_MMAP_THRESHOLD_=4294967296 MALLOC_TRIM_THRESHOLD_=4294967296 MALLOC_TOP_PAD_=268435456
PYTHONPATH="$path" "$python" bench/torch_bench.py "${robots[@]}" --out bench/results/torch.md
