#!/usr/bin/env bash
# Builds dyngen with its tests in build/ and runs them all with ctest. Installs the Debian packages
# the tests need first (scripts/install_deps.sh). The build's and ctest's full output go to
# build/build.log and build/ctest.log; the terminal gets progress, every compiler warning and
# error, every failed test with its output, and ctest's summary.
set -euo pipefail
cd "$(dirname "$0")/.."

start=$SECONDS
scripts/install_deps.sh
jobs=$(nproc)

echo "== configuring build/ with the tests"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDYNGEN_BUILD_TESTS=ON >/dev/null

# Runs a command with its output into a log, printing the lines that matter: make's or ctest's
# progress every 10%, compiler warnings and errors, and what ctest says beyond "Passed".
run_logged() {
  local log=$1 step=$2
  shift 2
  local next=10 t0=$SECONDS line percent status
  set +e
  "$@" 2>&1 | {
    while IFS= read -r line; do
      printf '%s\n' "$line" >&3
      percent=""
      if [[ $line =~ ^\[\ *([0-9]+)%\] ]]; then                               # make
        percent=${BASH_REMATCH[1]}
        [[ $line =~ (warning|error): ]] || line=""
      elif [[ $line =~ ^\ *([0-9]+)/([0-9]+)\ Test\ +#[0-9]+:.*\ Passed\ + ]]; then  # ctest
        percent=$((100 * BASH_REMATCH[1] / BASH_REMATCH[2]))
        line=""
      elif [[ $line =~ ^\ *Start\ +[0-9]+: || $line =~ ^(Scanning|Consolidate|Built\ target|dyngen\ ) ]]; then
        line=""
      elif [[ $step == build && ! $line =~ (warning|error|Error|undefined\ reference|\*\*\*) ]]; then
        line=""
      fi
      [ -z "$line" ] || printf '%s\n' "$line"
      if [ -n "$percent" ] && [ "$percent" -ge "$next" ]; then
        echo "  $percent% after $((SECONDS - t0)) s"
        next=$((percent / 10 * 10 + 10))
      fi
    done
  } 3>"$log"
  status=${PIPESTATUS[0]}
  set -e
  return "$status"
}

echo "== building dyngen, the tests and about 110 generated packages (about 10 minutes on 2" \
     "cores the first time; full output in build/build.log)"
if ! run_logged build/build.log build cmake --build build -j "$jobs"; then
  echo "the build failed; its last 40 lines (all of it: build/build.log):"
  tail -n 40 build/build.log
  exit 1
fi
warnings=$(grep -c "warning:" build/build.log || true)
[ "$warnings" -eq 0 ] || echo "$warnings compiler warnings (above; in context: build/build.log)"

echo "== running the tests (about 4 minutes; full output in build/ctest.log)"
status=0
run_logged build/ctest.log test ctest --test-dir build --output-on-failure -j "$jobs" || status=$?
echo "done in $((SECONDS - start)) s"
exit "$status"
