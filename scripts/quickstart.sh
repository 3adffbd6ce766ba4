#!/usr/bin/env bash
# Builds dyngen, generates the dynamics of the bundled UR5 arm into gen/ur5, builds that code
# with its own CMakeLists.txt and runs its bit-for-bit check against the runtime. Installs the
# Debian packages this needs first (scripts/install_deps.sh main); the tests are not built.
set -euo pipefail
cd "$(dirname "$0")/.."

start=$SECONDS
scripts/install_deps.sh main
jobs=$(nproc)

echo "== building dyngen in build/ (about a minute on 2 cores the first time)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDYNGEN_BUILD_TESTS=OFF >/dev/null
cmake --build build --target dyngen -j "$jobs" >/dev/null

echo "== build/dyngen examples/ur5.urdf -o gen/ur5 (a second)"
build/dyngen examples/ur5.urdf -o gen/ur5

echo "== building the generated code and its check in gen/ur5/build (about a minute)"
cmake -S gen/ur5 -B gen/ur5/build -Ddyngen_DIR="$PWD/build" >/dev/null
cmake --build gen/ur5/build -j "$jobs" >/dev/null

echo "== bit-for-bit check: generated code vs runtime"
log=gen/ur5/build/ctest.log
if ! ctest --test-dir gen/ur5/build --output-on-failure >"$log" 2>&1; then
  cat "$log"
  exit 1
fi
grep -E "Test +#|tests passed" "$log"

echo
echo "The generated code is in gen/ur5/: ur5_dynamics.hpp (API and array layout),"
echo "ur5_dynamics.cpp (rnea, crba, aba), dyngen_sincos.h (their sin and cos), ur5_model.hpp"
echo "and ur5_check.cpp (the check). Done in $((SECONDS - start)) s."
