#!/usr/bin/env bash
# Builds and runs dyngen_contacts_bench (bench/README.md, "Contacts"): contact_dynamics and
# impulse_dynamics beside ABA and contact_dynamics_derivatives beside aba_derivatives, and writes
# bench/results/contacts.md. Extra arguments go to the
# bench, for instance --benchmark_filter=solo12.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh
echo "== configuring build-bench"
cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DDYNGEN_BUILD_BENCH=ON >/dev/null
echo "== building dyngen and the contact packages (minutes)"
cmake --build build-bench --target dyngen_contacts_bench -j "$(nproc)"
echo "== running (the median of 5 repetitions of at least 0.2 s each, interleaved at random)"
mkdir -p bench/results
build-bench/bench/dyngen_contacts_bench --benchmark_repetitions=5 --benchmark_min_time=0.2 \
  --benchmark_enable_random_interleaving=true "$@" bench/results/contacts.md
echo "wrote bench/results/contacts.md"
