#!/usr/bin/env bash
# Installs everything emrm needs to build, test and run on Debian 12 (bookworm), as root.
# Idempotent: packages already present are left alone.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config git clang libclang-rt-dev clang-format clang-tidy
  libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libfmt-dev libmuparser-dev
  libgtest-dev libgmock-dev libbenchmark-dev libxml2-dev
  graphviz gnuplot-nox libsqlite3-dev sqlite3 libtbb-dev libboost-dev libnlopt-cxx-dev
  openmpi-bin libopenmpi-dev libcereal-dev
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pandas python3-pytest python3-matplotlib
  chromium fonts-dejavu-core
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
