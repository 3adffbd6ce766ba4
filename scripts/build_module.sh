#!/usr/bin/env bash
# Generates NAME's package from ROBOT with the dyngen options given and builds its Python module
# with the package's own CMake for AVX2 and PYTHON, in ROOT/NAME (for the benchmarks).
#
#   scripts/build_module.sh ROOT NAME ROBOT PYTHON [DYNGEN OPTION...]
set -euo pipefail
root=$1 name=$2 robot=$3 python=$4
shift 4
echo "== $name"
build/dyngen "$robot" -o "$root/$name" --name "$name" --quiet "$@" 2>/dev/null
upper=${name^^}
cmake -S "$root/$name" -B "$root/$name/build" -D"${upper}_BUILD_CHECK=OFF" \
  -D"${upper}_ISA=avx2" -DPython3_EXECUTABLE="$python" >/dev/null
cmake --build "$root/$name/build" -j "$(nproc)" >/dev/null
