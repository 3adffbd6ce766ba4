# Sourced by scripts/callgrind.sh and scripts/callgrind_derivatives.sh, from the project's root.
#
# callgrind_build TARGET: installs what is missing, configures BUILD_DIR (default build-bench,
# shared with scripts/bench.sh) for the benchmarks and builds TARGET there; sets tool to it and
# scratch to a directory removed on exit.
callgrind_build() {
  scripts/install_deps.sh
  local build=${BUILD_DIR:-build-bench}
  echo "== configuring $build and building $1 (minutes the first time)"
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DDYNGEN_BUILD_BENCH=ON >/dev/null
  cmake --build "$build" --target "$1" -j "$(nproc)"
  tool=$build/bench/$1
  scratch=$(mktemp -d)
  trap 'rm -rf "$scratch"' EXIT
}

# callgrind_counts SCRATCH COMMAND...: prints "IR I1_MISSES", the instructions and level-1
# instruction-cache misses collected inside dyngen_measured_call while COMMAND runs. LD_BIND_NOW
# resolves every symbol at start-up, so that no first call pays the dynamic linker. The simulated
# caches are this machine's level 1 (32 KB, 8 ways, 64-byte lines), given rather than detected,
# so that the counts do not depend on what valgrind recognises.
callgrind_counts() {
  local scratch=$1
  shift
  LD_BIND_NOW=1 valgrind --tool=callgrind --collect-atstart=no \
    --cache-sim=yes --I1=32768,8,64 --D1=32768,8,64 --LL=1048576,16,64 \
    --toggle-collect=dyngen_measured_call --callgrind-out-file="$scratch/out" \
    "$@" >/dev/null 2>"$scratch/log" || { cat "$scratch/log" >&2; exit 1; }
  # summary: Ir Dr Dw I1mr D1mr D1mw ILmr DLmr DLmw
  grep -qx 'events: Ir Dr Dw I1mr D1mr D1mw ILmr DLmr DLmw' "$scratch/out" ||
    { echo "$(basename "$0"): unexpected events in callgrind's output" >&2; exit 1; }
  local ir i1
  read -r ir _ _ i1 _ < <(sed -n 's/^summary: //p' "$scratch/out")
  echo "$ir $i1"
}
