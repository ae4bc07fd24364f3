#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The main job: installs what is missing, builds nbs_model (Release, tests off) in build/demo and runs it on the
# bundled Stanford bunny: autonomous modeling with the NBS planner (default method SGU_H) until done or 30 scans; mesh,
# voxels, candidates, pictures, report.json and the session viewer out/viewer/index.html (three.js from
# scripts/install-viewer.sh; without it the page says how to get it) go to out/. Extra arguments go to nbs_model
# (e.g. scripts/demo.sh --seed 7 --method C_S --scans 10; see nbs_model --help).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/install-deps.sh
scripts/install-viewer.sh || echo "demo: three.js not installed; out/viewer/index.html will say how to get it" >&2
dir=build/demo
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DNBS_BUILD_TESTS=OFF -DNBS_BUILD_EXAMPLES=ON \
      -DNBS_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$dir" --target nbs_model -j "${NBS_JOBS:-$(nproc)}"
"$dir"/examples/nbs_model --mesh data/meshes/stanford-bunny.obj --size 0.16 --out out --viewer "$@"
