#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# CTest viewer.browser: a short `nbs_model --viewer` run (2 scans, no PNG pictures, 2 threads), then headless
# Chromium (WebGL on SwiftShader, no GPU, no network: the page is opened from file://) screenshots the page at
# #scan=1 and at the last scan, and check_screenshot checks that the object's screen region shows the mesh and that
# the slider (the page reads #scan=K through the slider's input handler) changes the picture; the page's DOM at the
# last scan must report as many faces as nbs_model's final mesh (the face records decode to the same mesh).
# Usage: viewer_test.sh NBS_MODEL CHECK_SCREENSHOT CHROMIUM WORKDIR. Exits 77 (skipped) without Chromium or
# three.js (scripts/install-deps.sh --with-browser, scripts/install-viewer.sh).
set -euo pipefail
model=$1 check=$2 chromium=$3 work=$4
if [[ -z $chromium || $chromium == *NOTFOUND* || ! -x $chromium ]]; then
  echo "SKIP: Chromium not found at configure time (scripts/install-deps.sh --with-browser)"; exit 77
fi
rm -rf "$work" && mkdir -p "$work"
scans=2
"$model" --scans $scans --no-images --threads 2 --viewer --out "$work/out" > "$work/nbs_model.log"
grep '^viewer' "$work/nbs_model.log"
page=$work/out/viewer/index.html
[[ -s $page ]] || { echo "FAIL: $page not written"; exit 1; }
if ! grep -q 'three.js inlined' "$work/nbs_model.log"; then
  echo "SKIP: three.js not installed (scripts/install-viewer.sh); the page was written with the hint"; exit 77
fi
chrome() {  # fragment, what (--screenshot=PNG or --dump-dom)
  # --no-sandbox: CI runs as root; --enable-unsafe-swiftshader --use-angle=swiftshader: WebGL without a GPU;
  # --virtual-time-budget: the page's async work (inflate, module import, first frame) finishes before the shot.
  timeout 40 "$chromium" --headless=new --no-sandbox --disable-gpu --enable-unsafe-swiftshader \
    --use-angle=swiftshader --no-first-run --no-default-browser-check --user-data-dir="$work/profile" \
    --window-size=800,600 --virtual-time-budget=15000 "$2" "file://$page#$1" 2> "$work/chromium.log" ||
    { cat "$work/chromium.log"; echo "FAIL: chromium"; exit 1; }
}
chrome "scan=$scans&cand=0" --dump-dom > "$work/dom.html"
want=$(sed -n 's/^mesh .* \([0-9]*\) triangles.*/\1/p' "$work/nbs_model.log")
got=$(grep -o 'mesh [0-9]* faces' "$work/dom.html" | grep -o '[0-9]*' || true)
echo "faces at scan $scans: page $got, nbs_model $want"
[[ -n $want && $got == "$want" ]] || { echo "FAIL: the page shows ${got:-no} faces, the final mesh has $want"; exit 1; }
for s in "$scans:last" "1:first"; do
  chrome "scan=${s%%:*}&cand=0" --screenshot="$work/${s#*:}.png" > /dev/null
  [[ -s $work/${s#*:}.png ]] || { cat "$work/chromium.log"; echo "FAIL: no screenshot ${s#*:}.png"; exit 1; }
done
# The 3D view is the left 440 of the 800 pixels (the side panel is 360 wide); the object is framed in its middle:
# x 17 %..35 %, y 38 %..65 % of the window. Measured: the mesh fills 32 % of it (0.8 % with #mesh=0),
# scan 1 vs 2 differ in 11 % of it (0 % for the same scan twice).
"$check" "$work/last.png" "$work/first.png" 0.17 0.38 0.35 0.65 0.20 0.05
