#!/usr/bin/env bash
# Installs the Debian 12 packages stsim needs, only those that are missing, so a second run is instant.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config ccache
  libeigen3-dev libyaml-cpp-dev libboost1.74-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  sumo sumo-tools
  libfcl-dev
  liburdfdom-dev  # URDF robots for the arm model (models/arm/src/urdf.cpp)
  python3-matplotlib openmpi-bin libopenmpi-dev
  xvfb xauth  # a virtual X display for the sumo-gui test (xvfb-run needs xauth, only recommended)
  clang libclang-rt-14-dev  # libFuzzer for fuzz/ (clang's fuzzer runtime is in the compiler-rt dev package)
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest  # the Python module stsim
  file  # cpack -G DEB finds the ELF files for dpkg-shlibdeps with it
  chromium nodejs  # the pool page in a real browser (tests/models/pool/pool_page_test.js, headless over a pipe)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}" >&2
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo_cmd apt-get update -qq
  $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
