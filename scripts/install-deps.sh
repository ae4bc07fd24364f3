#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs every Debian package nbs uses (idempotent: only what is missing; sudo only when not root).
# Usage: scripts/install-deps.sh [--with-plots] [--with-fuzz] [--with-docs] [--with-browser] [--with-npm]
#                                [--with-bench-incumbents]
#   --with-plots             adds python3-matplotlib for benchmarks/plots
#   --with-fuzz              adds clang and libFuzzer for scripts/fuzz.sh (and scripts/test.sh's ASan build)
#   --with-docs              adds doxygen and graphviz for scripts/docs.sh
#   --with-browser           adds chromium for the session viewer's browser test (tests/viewer)
#   --with-npm               adds npm for scripts/install-viewer.sh (three.js)
#   --with-bench-incumbents  adds the benchmark-only incumbents (scripts/bench.sh passes it): Open3D and PCL for
#                            bench_registration. Neither the library nor its tests need them (scripts/test.sh does
#                            not pass it); each bench builds without them.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libnanoflann-dev libtinyobjloader-dev catch2 libbenchmark-dev
  libembree-dev liboctomap-dev libfcl-dev libpng-dev nlohmann-json3-dev libcli11-dev
  libompl-dev libboost-serialization-dev libboost-filesystem-dev libboost-system-dev libode-dev
  liborocos-kdl-dev liburdfdom-dev
)
for arg in "$@"; do
  case $arg in
    --with-plots) packages+=(python3-matplotlib python3-numpy) ;;
    --with-fuzz) packages+=(clang libclang-rt-dev) ;;
    --with-docs) packages+=(doxygen graphviz) ;;
    --with-browser) packages+=(chromium) ;;
    --with-npm) packages+=(npm) ;;
    --with-bench-incumbents) packages+=(libopen3d-dev libpcl-dev) ;;
    *) echo "install-deps: unknown option '$arg'" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
