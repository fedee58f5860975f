#!/usr/bin/env bash
# Installs the Debian packages glassmap needs (quiet and quick when all are present),
# then configures and builds in build/ (or $GLASSMAP_BUILD_DIR).
# Extra arguments are passed to CMake's configure step, e.g. -DGLASSMAP_SANITIZE=ON.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${GLASSMAP_BUILD_DIR:-$here/build}

packages=(
  build-essential cmake pkg-config git
  libcgal-dev libeigen3-dev libgdal-dev gdal-bin libboost-graph-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libcairo2-dev
  nlohmann-json3-dev libyaml-cpp-dev libtbb-dev zlib1g-dev libzstd-dev liblz4-dev libsqlite3-dev
  pybind11-dev python3-dev python3-numpy python3-pytest
  python3 python3-matplotlib python3-yaml clang libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S "$here" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build_dir" -j "$jobs"
