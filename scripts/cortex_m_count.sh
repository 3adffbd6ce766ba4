#!/usr/bin/env bash
# Instructions, flash and stack per call of generated functions on a Cortex-M4F and a Cortex-M7
# under qemu: each call is built alone (tests/firmware/count_harness.cpp, -O2, no C library,
# unused sections dropped) and run once with qemu's one-instruction translation blocks and
# execution log; the instructions executed between its two markers are counted (the call's own
# set-up included, a handful), its flash is what the call adds to the image (code and constants,
# against the image without the call), its stack what it overwrote below the call site.
#
#   scripts/cortex_m_count.sh ROBOT.urdf [SCALAR [dyngen options...]]
#
# e.g. scripts/cortex_m_count.sh examples/ur5.urdf float. Needs build/dyngen,
# gcc-arm-none-eabi and qemu-system-arm (scripts/install_deps.sh test).
set -euo pipefail
cd "$(dirname "$0")/.."
urdf=$1
scalar=${2:-float}
shift $(($# < 2 ? $# : 2))
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
build/dyngen "$urdf" -o "$work/gen" --name robot --scalar "$scalar" --quiet "$@" \
  --algorithms rnea,crba,aba 2>/dev/null
common="-O2 -ffp-contract=off -fno-fast-math -ffreestanding -ffunction-sections -fdata-sections"
printf '%-4s %-6s %-5s %24s %24s %24s\n' cpu scalar "" "rnea" "crba" "aba"
printf '%-4s %-6s %-5s %24s %24s %24s\n' "" "" "" "instr / flash / stack" \
  "instr / flash / stack" "instr / flash / stack"
for cpu in m4f m7; do
  case $cpu in
    m4f) flags="-mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard -mthumb" machine=mps2-an386 ;;
    m7) flags="-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb" machine=mps2-an500 ;;
  esac
  arm-none-eabi-gcc $flags $common -std=c99 -c examples/firmware/startup.c -o "$work/startup.o"
  arm-none-eabi-g++ $flags $common -std=c++17 -fno-exceptions -fno-rtti -I"$work/gen" \
    -c "$work/gen/robot_dynamics.cpp" -o "$work/dynamics.o"
  counts=()
  baseline=""
  for call in "static_cast<void>(0)" "rnea(q, v, a, out)" "crba(q, M)" "aba(q, v, tau, out)"; do
    arm-none-eabi-g++ $flags $common -std=c++17 -fno-exceptions -fno-rtti -I"$work/gen" \
      '-DDYNGEN_HEADER="robot_dynamics.hpp"' -DDYNGEN_NAMESPACE=robot -DSCALAR="$scalar" \
      "-DCALL=$([ "$call" = "static_cast<void>(0)" ] && echo "$call" || echo "robot::$call")" \
      -c tests/firmware/count_harness.cpp -o "$work/harness.o"
    arm-none-eabi-g++ $flags -nostdlib -Wl,--gc-sections -T examples/firmware/cortex_m.ld \
      "$work/startup.o" "$work/harness.o" "$work/dynamics.o" -lgcc -o "$work/count.elf"
    flash=$(arm-none-eabi-size -A "$work/count.elf" | awk '$1 == ".text" || $1 == ".data" {s += $2} END {print s}')
    if [ -z "$baseline" ]; then
      baseline=$flash
      continue
    fi
    begin=$(arm-none-eabi-nm "$work/count.elf" | awk '/ marker_begin$/ {print $1}')
    end=$(arm-none-eabi-nm "$work/count.elf" | awk '/ marker_end$/ {print $1}')
    timeout 300 qemu-system-arm -machine $machine -nographic -monitor none -serial none \
      -semihosting-config enable=on,target=native -singlestep -d exec,nochain \
      -D "$work/trace.log" -kernel "$work/count.elf" >"$work/out.txt" 2>&1
    instructions=$(awk -v b="/$begin/" -v e="/$end/" \
      'index($0, b) {on = 1; next} index($0, e) {on = 0} on {n++} END {print n + 0}' \
      "$work/trace.log")
    stack=$(awk '/^stack / {print $2}' "$work/out.txt")
    counts+=("$instructions / $((flash - baseline)) / $stack")
  done
  printf '%-4s %-6s %-5s %24s %24s %24s\n' $cpu "$scalar" "" "${counts[@]}"
done
