#!/usr/bin/env bash
# Rewrites generated/ with the dyngen in build/ (the golden test, tests/generated/CMakeLists.txt,
# compares against it with the same options).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build --target dyngen -j "$(nproc)" >/dev/null
build/dyngen examples/ur5.urdf -o generated/ur5 --quiet --algorithms all --jacobian-frame both --batch 4 2>/dev/null
build/dyngen tests/models/planar5.yaml -o generated/planar5 --quiet
build/dyngen examples/ur5.urdf -o generated/ur5_c --quiet --lang c --scalar float 2>/dev/null
