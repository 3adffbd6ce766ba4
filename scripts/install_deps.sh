#!/usr/bin/env bash
# Installs the Debian packages dyngen needs to build and test, if any are missing.
set -euo pipefail

packages=(
  g++ make cmake           # toolchain
  libeigen3-dev            # dense linear algebra in the generator and the tests
  liburdfdom-dev           # URDF parsing
  libtinyxml2-dev          # line-numbered XML errors and document order
  libyaml-cpp-dev          # chain specs
  libfmt-dev               # formatting of emitted code
  libcli11-dev             # command line
  libssl-dev               # sha256 of the input in the banner
  libgtest-dev             # tests and generated check harnesses
  nlohmann-json3-dev       # dyngen eval and report: JSON
  libmpfrc++-dev libmpfr-dev libgmp-dev  # the MPFR reference (numerics/, dyngen report)
  libbenchmark-dev         # dyngen report's timings
  gnuplot-nox              # dyngen report's plot
  libmujoco-dev libgl-dev  # peer comparison (tests/peers/mujoco); its CMake config needs OpenGL
  liborocos-kdl-dev libkdl-parser-dev  # peer comparison (tests/peers/kdl)
  valgrind                 # instruction counts (scripts/callgrind.sh)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "installing Debian packages: ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
