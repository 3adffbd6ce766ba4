#!/usr/bin/env bash
# Installs the Debian 12 packages that a job needs, if any are missing (with sudo when not root).
#
#   scripts/install_deps.sh            everything the tests need (scripts/test.sh)
#   scripts/install_deps.sh main       building dyngen, generating code, building and checking it
#                                      (scripts/quickstart.sh)
#   scripts/install_deps.sh report     main, and what dyngen report needs
#   scripts/install_deps.sh package    main, and what cpack -G DEB needs
#   scripts/install_deps.sh python     main, and what a package's Python module (--python) needs
#   scripts/install_deps.sh bench      the tests' packages and valgrind (scripts/bench.sh,
#                                      scripts/callgrind.sh)
#   scripts/install_deps.sh fuzz       main, and clang with libFuzzer (scripts/fuzz.sh)
#
# Several jobs may be named at once. --print lists the packages and installs nothing.
set -euo pipefail

main=(
  g++ make cmake           # toolchain
  libeigen3-dev            # dense linear algebra in the generator and the tests
  liburdfdom-dev           # URDF parsing
  libtinyxml2-dev          # line-numbered XML errors and document order
  libyaml-cpp-dev          # chain specs
  libfmt-dev               # formatting of emitted code
  libcli11-dev             # command line
  libssl-dev               # sha256 of the input in the banner
  nlohmann-json3-dev       # dyngen eval and report: JSON
  libmpfrc++-dev libmpfr-dev libgmp-dev  # the MPFR reference (numerics/): generation's estimates
  libgtest-dev             # the generated package's check, and the tests
  libmujoco-dev libgl-dev  # MJCF, read by MuJoCo's compiler; its CMake config needs OpenGL
)
report=(
  libbenchmark-dev         # dyngen report's timings
  gnuplot-nox              # dyngen report's plot
)
firmware=(
  gcc-arm-none-eabi qemu-system-arm  # tests/firmware: Cortex-M builds run under qemu
)
python=(
  pybind11-dev python3-dev python3-numpy  # the generated Python module (--python)
  python3-pip python3-setuptools          # pip install of a package with --python
  python3-pytest python3-matplotlib       # its tests, and examples/python's plot
  python3-torch                           # the PyTorch functions (--torch)
)
dispatch=(
  qemu-user  # tests/generated: one binary's AVX2 and baseline paths, on emulated processors
)
peers=(
  liborocos-kdl-dev libkdl-parser-dev  # tests/peers/kdl
)

print=false
jobs=()
for arg in "$@"; do
  case $arg in
    --print) print=true ;;
    main | report | package | python | test | bench | fuzz) jobs+=("$arg") ;;
    *) echo "install_deps.sh: unknown job '$arg' (main, report, package, python, test, bench, fuzz)" >&2
       exit 1 ;;
  esac
done
[ ${#jobs[@]} -gt 0 ] || jobs=(test)

packages=("${main[@]}")
for job in "${jobs[@]}"; do
  case $job in
    report) packages+=("${report[@]}") ;;
    package) packages+=(dpkg-dev file) ;;  # CPack's dependency scan: dpkg-shlibdeps and file
    python) packages+=("${python[@]}") ;;
    test) packages+=("${report[@]}" "${peers[@]}" "${firmware[@]}" "${dispatch[@]}" "${python[@]}") ;;
    bench) packages+=("${report[@]}" "${peers[@]}" "${firmware[@]}" "${dispatch[@]}" "${python[@]}"
                      valgrind) ;;
    fuzz) packages+=(clang libclang-rt-dev) ;;
  esac
done
# each package once
mapfile -t packages < <(printf '%s\n' "${packages[@]}" | awk '!seen[$0]++')

if $print; then
  echo "${packages[*]}"
  exit 0
fi

if ! command -v dpkg-query >/dev/null; then
  echo "install_deps.sh: not a Debian system; install these packages' equivalents yourself:" >&2
  echo "  ${packages[*]}" >&2
  exit 0
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -gt 0 ] || exit 0

command="apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if ! command -v sudo >/dev/null; then
    echo "${#missing[@]} Debian packages are missing, and installing them needs root. As root, run:" >&2
    echo "  $command" >&2
    exit 1
  fi
  sudo=sudo
fi

echo "== installing ${#missing[@]} Debian packages (a few minutes on a new machine): ${missing[*]}"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
export DEBIAN_FRONTEND=noninteractive
# apt's progress and notes go to the log, which is shown only if it fails
if ! { $sudo apt-get update -q && $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"; } \
     >"$log" 2>&1; then
  cat "$log" >&2
  echo "install_deps.sh: installing failed; the command was:" >&2
  echo "  ${sudo:+sudo }$command" >&2
  exit 1
fi
