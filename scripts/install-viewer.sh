#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs three.js, pinned, from the npm registry into build/viewer-deps (only if missing), for the session viewer
# of `nbs_model --viewer` (tools/viewer/write_viewer.hpp inlines build/viewer-deps/node_modules/three/build/
# three.module.min.js into out/viewer/index.html, so the page opens offline). Installs Debian's npm first when npm
# is missing. Without three.js the viewer is still written and says how to get it.
# Usage: scripts/install-viewer.sh   (exits non-zero when npm or the registry is not reachable)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
version=0.170.0  # = kThreeVersion in tools/viewer/write_viewer.hpp (r171+ split three.module.js into two files)
prefix=build/viewer-deps
lib=$prefix/node_modules/three/build/three.module.min.js
if [[ -f $lib ]] && grep -q "\"version\": \"$version\"" "$prefix/node_modules/three/package.json"; then
  echo "install-viewer: three.js $version present ($lib)"
  exit 0
fi
command -v npm > /dev/null || scripts/install-deps.sh --with-npm
mkdir -p "$prefix"
npm install --prefix "$prefix" --no-audit --no-fund --no-save --loglevel=error "three@$version"
[[ -f $lib ]] || { echo "install-viewer: $lib missing after npm install" >&2; exit 1; }
echo "install-viewer: three.js $version -> $lib"
