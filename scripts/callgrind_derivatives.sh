#!/usr/bin/env bash
# Instructions and instruction-cache misses per call of the derivatives (bench/README.md,
# "Derivatives in instructions"): builds dyngen_derivatives_bench, runs each of its functions
# under valgrind --tool=callgrind with its cache simulation, as scripts/callgrind.sh does for the
# values, and writes callgrind_derivatives.md: the issue's ratios (rnea_derivatives / rnea,
# aba_derivatives / aba, finite differences / aba_derivatives) in instructions, which do not
# depend on the host or its load, beside the misses that the times add to them.
#
#   scripts/callgrind_derivatives.sh              every package, into bench/results
#   scripts/callgrind_derivatives.sh '^ur5' DIR   the packages whose names match, into DIR
#
# BUILD_DIR chooses the build directory (default build-bench, shared with scripts/bench.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/callgrind.sh

filter=${1:-.}
results=${2:-bench/results}
calls=64  # one call on each of the harness's 64 states
functions="rnea aba rnea_derivatives aba_derivatives aba_finite_differences"
start=$SECONDS

callgrind_build dyngen_derivatives_bench

# CALLS calls of one function of one package: its instructions and level-1 instruction-cache
# misses
count() {
  callgrind_counts "$scratch" "$tool" --count "$1" "$2" "$calls"
}

selected=()
while read -r p; do [[ $p =~ $filter ]] && selected+=("$p"); done < <("$tool" --list)
[ ${#selected[@]} -gt 0 ] || { echo "no package matches '$filter'" >&2; exit 1; }
counts=$(count "${selected[0]}" none)
read -r harness_ir harness_i1 <<<"$counts"
echo "== counting ${#selected[@]} packages under callgrind (the harness: $((harness_ir / calls)) instructions a call)"
: >"$scratch/rows"
for p in "${selected[@]}"; do
  echo "  $p"
  line="$p"
  for f in $functions; do
    counts=$(count "$p" "$f")
    read -r ir i1 <<<"$counts"
    line="$line|$(((ir - harness_ir) / calls))|$(((i1 - harness_i1) / calls))"
  done
  echo "$line" >>"$scratch/rows"
done

mkdir -p "$results"
{
  echo "# The derivatives in instructions"
  echo
  echo "\`scripts/callgrind_derivatives.sh\` (bench/README.md, \"Derivatives in instructions\"): instructions executed per call (callgrind's Ir) and level-1 instruction-cache misses per call in callgrind's simulation of this machine's cache (32 KB, 8 ways, 64-byte lines), for dyngen_derivatives_bench's packages (the generated code at -O3 with -ffp-contract=off), each function called once on each of $calls seeded random states through an out-of-line call; the harness's own $((harness_ir / calls)) instructions a call (an empty call, measured the same way) taken off. *FD* is forward differences of the generated ABA, 2n + 1 calls. The ratios are the issue's, in instructions: the times (placement_derivatives.md) add to them what the misses cost, up to half again for a function whose code outgrows the cache (docs/performance.md, \"Code size and the instruction cache\")."
  echo
  echo "| package | Ir: rnea | aba | rnea_derivatives | aba_derivatives | FD | rnea_derivatives / rnea | aba_derivatives / aba | FD / aba_derivatives | I1 misses: rnea | aba | rnea_derivatives | aba_derivatives |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  awk -F'|' '{
    printf "| %s | %d | %d | %d | %d | %d | %.2f | %.2f | %.2f | %d | %d | %d | %d |\n",
      $1, $2, $4, $6, $8, $10, $6 / $2, $8 / $4, $10 / $8, $3, $5, $7, $9
  }' "$scratch/rows"
} >"$results/callgrind_derivatives.md"
echo "== wrote $results/callgrind_derivatives.md in $((SECONDS - start)) s"
