#!/usr/bin/env bash
# Builds dyngen, generates the dynamics of the bundled UR5 arm into gen/ur5, builds that code
# with its own CMakeLists.txt and runs its bit-for-bit check against the runtime.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh
jobs=$(nproc)

echo "== building dyngen (build/)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --target dyngen -j "$jobs" >/dev/null

echo "== dyngen examples/ur5.urdf -o gen/ur5"
build/dyngen examples/ur5.urdf -o gen/ur5 2>/dev/null

echo "== building the generated code and its check (gen/ur5/build)"
cmake -S gen/ur5 -B gen/ur5/build -Ddyngen_DIR="$PWD/build" >/dev/null
cmake --build gen/ur5/build -j "$jobs" >/dev/null

echo "== bit-for-bit check: generated code vs runtime"
ctest --test-dir gen/ur5/build --output-on-failure | grep -E "Test +#|tests passed|failed"

echo
echo "The generated code is in gen/ur5/: ur5_dynamics.hpp (API and array layout),"
echo "ur5_dynamics.cpp (rnea, crba, aba), dyngen_sincos.hpp (their sin and cos), ur5_model.hpp"
echo "and ur5_check.cpp (the check)."
