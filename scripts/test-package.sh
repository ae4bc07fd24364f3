#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The installed package, as a downstream user meets it. Usage: scripts/test-package.sh <configured build dir> [jobs]
#   1. installs the build into a prefix, then moves the prefix (the package must be relocatable) and checks that no
#      installed CMake or pkg-config file names the build tree, the source tree or the prefix, and that no exported
#      target holds an absolute path (dependencies by imported target only);
#   2. find_package(nbs REQUIRED COMPONENTS embree octomap fcl ompl png kdl): builds tests/downstream, which links and runs
#      every adapter (each check has a known answer);
#   3. a required component that is unknown, and one whose dependency is missing (octomap hidden by
#      CMAKE_DISABLE_FIND_PACKAGE_octomap, which also takes fcl; libpng and urdfdom hidden likewise), fail naming the
#      component and the reason; the same as OPTIONAL_COMPONENTS configures and says which one is missing;
#   1b. runs the installed tools from the moved prefix (nbs_model loads the installed demo mesh);
#   4. pkg-config: compiles and runs tests/downstream/main.cpp (core only: -DNBS_DOWNSTREAM_PKGCONFIG includes the core
#      check's headers and one header of each library nbs.pc requires, not the umbrella) with
#      `pkg-config --cflags --libs nbs`.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
build=${1:?usage: scripts/test-package.sh <configured build dir> [jobs]}
jobs=${2:-$(nproc)}
work=$root/build/test-package
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/first" >/dev/null
mv "$work/first" "$work/prefix"
prefix=$work/prefix
if grep -rlE "$root|$work/first|$(cd "$build" && pwd)" "$prefix/share" >/dev/null; then
  echo "test-package: installed files name the build: $(grep -rlE "$root|$work/first" "$prefix/share" | tr '\n' ' ')" >&2
  exit 1
fi
# Dependencies must be named by their imported targets, not by absolute paths of this machine's files.
if grep -nE 'INTERFACE_[A-Z_]+ "[^"]*(^|;|")/' "$prefix"/share/cmake/nbs/*Targets.cmake; then
  echo "test-package: an exported target holds an absolute path (above)" >&2
  exit 1
fi
echo "relocatable: OK (installed, moved, no installed file names the build, source or first prefix)"

# The installed tools run from the moved prefix; nbs_model finds its demo mesh in <prefix>/share/nbs, not the source.
"$prefix/bin/nbs_plan" --help >/dev/null
if [[ -x $prefix/bin/nbs_model ]]; then
  "$prefix/bin/nbs_model" --scans 1 --no-images --out "$work/model" >"$work/model.log"
  if ! grep -qF "object  $prefix/share/nbs/meshes/stanford-bunny.obj:" "$work/model.log"; then
    echo "test-package: the installed nbs_model did not load the installed mesh:" >&2
    head -3 "$work/model.log" >&2
    exit 1
  fi
fi
[[ ! -e $prefix/bin/nbs_eval ]] || "$prefix/bin/nbs_eval" --help >/dev/null
echo "installed tools: OK ($(ls "$prefix/bin" | tr '\n' ' '))"

cmake -S tests/downstream -B "$work/all" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/all" -j "$jobs" >/dev/null
"$work/all/nbs_downstream"

expect_failure() {  # name, text the configure output must contain, cmake args...
  local name=$1 text=$2; shift 2
  if cmake -S tests/downstream -B "$work/$name" -DCMAKE_PREFIX_PATH="$prefix" "$@" >"$work/$name.log" 2>&1; then
    echo "test-package: $name: configuring succeeded, it must fail" >&2; exit 1
  fi
  # CMake wraps the reason given by the package: compare with whitespace squeezed.
  if ! tr -s ' \n' ' ' <"$work/$name.log" | grep -qF "$text"; then
    echo "test-package: $name: the error does not say \"$text\":" >&2; cat "$work/$name.log" >&2; exit 1
  fi
  echo "$name: fails as it must (\"$text\")"
}
expect_failure unknown_component "required component 'bogus' is not available: nbs has no such component" \
  "-DNBS_DOWNSTREAM_COMPONENTS=octomap;bogus"
expect_failure missing_dependency \
  "required component 'fcl' is not available: it needs the octomap component, which is not available: its dependency, package 'octomap'" \
  "-DNBS_DOWNSTREAM_COMPONENTS=fcl" -DCMAKE_DISABLE_FIND_PACKAGE_octomap=TRUE
expect_failure missing_libpng \
  "required component 'png' is not available: its dependency, package 'PNG' 1.6, was not found" \
  "-DNBS_DOWNSTREAM_COMPONENTS=png" -DCMAKE_DISABLE_FIND_PACKAGE_PNG=TRUE
expect_failure missing_urdfdom \
  "required component 'kdl' is not available: its dependency, package 'urdfdom', was not found" \
  "-DNBS_DOWNSTREAM_COMPONENTS=kdl" -DCMAKE_DISABLE_FIND_PACKAGE_urdfdom=TRUE
cmake -S tests/downstream -B "$work/optional" -DCMAKE_PREFIX_PATH="$prefix" -DNBS_DOWNSTREAM_COMPONENTS=embree \
  -DNBS_DOWNSTREAM_OPTIONAL=bogus >"$work/optional.log" 2>&1
grep -qF "nbs: optional component 'bogus' is not available" "$work/optional.log"
echo "optional_component: configures and reports the missing one"

export PKG_CONFIG_PATH=$prefix/share/pkgconfig
# shellcheck disable=SC2046
g++ -std=c++20 -O1 -DNBS_DOWNSTREAM_PKGCONFIG tests/downstream/main.cpp -o "$work/nbs_pkgconfig" $(pkg-config --cflags --libs nbs)
"$work/nbs_pkgconfig" | sed 's/^/pkg-config: /'
echo "PACKAGE OK"
