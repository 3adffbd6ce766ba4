#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer in build-fuzz/ and runs each for SECONDS (default 60), starting from
# the checked-in corpus. New inputs collect in build-fuzz/tests/fuzz/corpus_TARGET; a crash is
# written to build-fuzz/tests/fuzz/ as crash-* and the run fails (tests/fuzz/README.md).
#
#   scripts/fuzz.sh            every target for 60 s
#   scripts/fuzz.sh 600 urdf   the urdf target for 10 minutes
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
filter=${2:-}
scripts/install_deps.sh fuzz python
echo "== configuring build-fuzz with clang (tests off, fuzz targets on)"
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DDYNGEN_BUILD_TESTS=OFF -DDYNGEN_BUILD_FUZZ=ON -DDYNGEN_FUZZ_SECONDS="$seconds" >/dev/null
echo "== building the fuzz targets (a few minutes the first time)"
cmake --build build-fuzz -j "$(nproc)"
echo "== fuzzing each target for $seconds s"
(cd build-fuzz/tests/fuzz && ctest --output-on-failure -R "fuzz\.${filter}.*\.run")
