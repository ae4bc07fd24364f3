#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The main job: installs what is missing, builds nbs_model (Release, tests off) in build/demo and runs it on the
# bundled Stanford bunny: autonomous modeling with the NBS planner (method C_H) until done or 30 scans; mesh,
# voxels, candidates, pictures and report.json go to out/. Extra arguments go to nbs_model
# (e.g. scripts/demo.sh --seed 7 --method C_S --scans 10; see nbs_model --help).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/install-deps.sh
dir=build/demo
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DNBS_BUILD_TESTS=OFF -DNBS_BUILD_EXAMPLES=ON \
      -DNBS_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$dir" --target nbs_model -j "${NBS_JOBS:-$(nproc)}"
"$dir"/examples/nbs_model --mesh data/meshes/stanford-bunny.obj --size 0.16 --out out "$@"
