// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The page of the session viewer (tools/viewer/write_viewer.hpp fills in @NBS_META@ — the JSON table of the
/// session —, @NBS_DATA@ — the zlib-compressed binary buffer, base64 — and @NBS_THREE@ — three.module.min.js, or
/// nothing). Plain HTML + JS, no network: three.js is imported from a blob: URL made of the inlined text, the
/// buffer is inflated by the browser's DecompressionStream. `#scan=K` in the URL (and hashchange) sets the slider
/// and runs its input handler; `#...&truth=1&cand=0` sets the toggles the same way.

#include <string_view>

namespace nbs::tools::viewer {

inline constexpr std::string_view kViewerHtml = R"nbsviewer(<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>nbs session viewer</title>
<style>
  html, body { margin: 0; height: 100%; background: #1b1f24; color: #d8dde3; font: 13px/1.4 sans-serif; }
  #view { position: absolute; left: 0; top: 0; bottom: 0; right: 360px; overflow: hidden; }
  #view canvas { display: block; }
  #side { position: absolute; right: 0; top: 0; bottom: 0; width: 360px; padding: 8px; overflow-y: auto;
          box-sizing: border-box; overflow-x: hidden;
          background: #262b32; border-left: 1px solid #3a414b; }
  h1 { font-size: 15px; margin: 0 0 6px; }
  #slider { width: 100%; }
  .row { display: flex; flex-wrap: wrap; gap: 2px 12px; margin: 6px 0; }
  #msg { position: absolute; left: 20px; top: 20px; right: 20px; color: #ffb86b; font-size: 15px;
         white-space: pre-wrap; }
  #info, #status { font-family: monospace; font-size: 12px; white-space: pre-wrap; }
  svg text { fill: #c5ccd4; font: 10px sans-serif; }
  .legend span { display: inline-block; width: 10px; height: 3px; vertical-align: middle; margin: 0 3px 0 8px; }
</style>
</head>
<body>
<div id="view"><div id="msg"></div></div>
<div id="side">
  <h1>nbs session viewer</h1>
  <div id="title"></div>
  <div class="row"><label for="slider">scan</label><b id="scanlabel"></b></div>
  <input id="slider" type="range" min="1" max="1" step="1" value="1">
  <div class="row">
    <label><input type="checkbox" id="mesh" checked> mesh</label>
    <label><input type="checkbox" id="paths" checked> executed paths</label>
    <label><input type="checkbox" id="cand" checked> next candidates</label>
    <label><input type="checkbox" id="truth"> ground truth</label>
    <label><input type="checkbox" id="occ"> occupied voxels</label>
    <label><input type="checkbox" id="unk"> unknown voxels</label>
    <label><input type="checkbox" id="box" checked> unknown area</label>
    <label id="armrow"><input type="checkbox" id="arm" checked> arm at the scan's start, transfer (--robot)</label>
  </div>
  <svg id="plot" width="340" height="190"></svg>
  <div class="legend" id="legend"></div>
  <div id="info"></div>
  <div id="status"></div>
  <p style="color:#8b949e">Drag: rotate, shift/right drag: pan, wheel: zoom. Candidates: scored before the next
  scan on this model, red (low) → green (high) utility, the chosen one blue (Fig. 4.16). Voxels: final space.</p>
</div>
<script id="nbs-meta" type="application/json">@NBS_META@</script>
<script id="nbs-data" type="application/octet-stream">@NBS_DATA@</script>
<script id="nbs-three" type="text/plain">@NBS_THREE@</script>
<script type="module">
const $ = (id) => document.getElementById(id);
const meta = JSON.parse($('nbs-meta').textContent);
if (!meta.arms) $('armrow').style.display = 'none';  // a run without --robot
const series = (meta.report && meta.report.series) || {};
const N = meta.scans;
const msg = (t) => { $('msg').textContent = t; };
window.addEventListener('error', (e) => msg('viewer error: ' + e.message));
$('slider').max = N;
$('slider').value = N;
$('title').textContent = (meta.report.method || '') + ', ' + N + ' scans' +
    (meta.report.final ? ', stop: ' + meta.report.final.stop : '');

// ---- the per-scan figures (SVG, no library) ------------------------------------------------------------------
const plotSeries = [
  { key: 'c_m', label: 'ĉ_m', color: '#4ea1ff' }, { key: 'd_m', label: 'd̄_m', color: '#f2c94c' },
  { key: 'c_a', label: 'c_a', color: '#6fcf97' }, { key: 'l_s_m', label: 'l_s / max', color: '#eb5757', scaled: true },
];
const P = { w: 340, h: 190, l: 30, r: 8, t: 8, b: 22 };
const px = (k) => P.l + (N > 1 ? (k - 1) / (N - 1) : 0.5) * (P.w - P.l - P.r);
const py = (v) => P.t + (1 - Math.max(0, Math.min(1, v))) * (P.h - P.t - P.b);
function drawPlot() {
  const svg = $('plot');
  const el = (tag, attrs, text) => {
    const e = document.createElementNS('http://www.w3.org/2000/svg', tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    if (text !== undefined) e.textContent = text;
    svg.appendChild(e);
    return e;
  };
  for (const v of [0, 0.25, 0.5, 0.75, 1]) {
    el('line', { x1: P.l, x2: P.w - P.r, y1: py(v), y2: py(v), stroke: '#3a414b' });
    el('text', { x: 2, y: py(v) + 3 }, v.toFixed(2));
  }
  for (let k = 1; k <= N; k += Math.max(1, Math.ceil(N / 10))) el('text', { x: px(k) - 3, y: P.h - 6 }, k);
  for (const s of plotSeries) {
    const v = series[s.key];
    if (!v) continue;
    const max = s.scaled ? Math.max(...v.map(Number)) || 1 : 1;
    s.max = max;
    el('polyline', { fill: 'none', stroke: s.color, 'stroke-width': 2,
                     points: v.map((y, i) => px(i + 1) + ',' + py(y / max)).join(' ') });
  }
  $('legend').innerHTML = plotSeries.filter((s) => series[s.key]).map((s) =>
      '<span style="background:' + s.color + '"></span>' + s.label +
      (s.scaled ? ' (max ' + s.max.toFixed(2) + ' m)' : '')).join('');
  plotCursor = el('line', { x1: 0, x2: 0, y1: P.t, y2: P.h - P.b, stroke: '#ffffff', 'stroke-dasharray': '3 2' });
  svg.addEventListener('click', (e) => {
    const r = svg.getBoundingClientRect();
    const k = Math.round(1 + (e.clientX - r.left - P.l) / (P.w - P.l - P.r) * (N - 1));
    setSlider(Math.max(1, Math.min(N, k)));
  });
}
let plotCursor = null;
drawPlot();

function figures(k) {
  const at = (key, f) => (series[key] ? f(series[key][k - 1]) : '–');
  return 'scan ' + k + ' (' + at('mode', String) + ')  points ' + at('points', String) +
      '\nĉ_m ' + at('c_m', (v) => v.toFixed(3)) + '  d̄_m ' + at('d_m', (v) => v.toFixed(3)) +
      '  c_a ' + at('c_a', (v) => (100 * v).toFixed(2) + ' %') + '  l_s ' + at('l_s_m', (v) => v.toFixed(3) + ' m');
}

// ---- the session buffer ---------------------------------------------------------------------------------------
async function inflate(b64) {
  const s = atob(b64.trim());
  const u = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) u[i] = s.charCodeAt(i);
  const stream = new Blob([u]).stream().pipeThrough(new DecompressionStream('deflate'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}
const buf = await inflate($('nbs-data').textContent);
const arrays = { u8: Uint8Array, u16: Uint16Array, u32: Uint32Array, i32: Int32Array, f32: Float32Array };
const get = (name) => {
  const t = meta.buffers[name];
  return t ? new arrays[t.type](buf.buffer, t.offset, t.count) : null;
};
const B = meta.box;
const dequantise = (q) => {
  const out = new Float32Array(q.length);
  for (let i = 0; i < q.length; ++i) {
    const a = i % 3;
    out[i] = B.min[a] + (q[i] / 65535) * (B.max[a] - B.min[a]);
  }
  return out;
};
// mesh_position: per axis the difference to the previous vertex (mod 2^16); mesh_index: per face a - previous a,
// b - a, c - a (docs/internals.md, "The session viewer")
const undelta = (q) => { for (let i = 3; i < q.length; ++i) q[i] = (q[i] + q[i - 3]) & 0xffff; return q; };
const faceFirst = get('face_first'), faceLast = get('face_last');
const meshIndex = (() => {
  const d = get('mesh_index'), out = new Uint32Array(d.length);
  let a = 0;
  for (let i = 0; i < d.length; i += 3) { a += d[i]; out[i] = a; out[i + 1] = a + d[i + 1]; out[i + 2] = a + d[i + 2]; }
  return out;
})();

// ---- three.js -------------------------------------------------------------------------------------------------
let setScan = (k) => {  // replaced below once three.js is loaded
  $('scanlabel').textContent = k + ' / ' + N;
  $('info').textContent = figures(k);
};
const threeSrc = $('nbs-three').textContent;
let THREE = null;
if (threeSrc.trim().length === 0) {
  msg('The 3D view needs three.js, which was not found when this page was written:\n' + meta.three_hint +
      '\n(the per-scan figures on the right work without it)');
} else {
  THREE = await import(URL.createObjectURL(new Blob([threeSrc], { type: 'text/javascript' })));
}

if (THREE) {
  const view = $('view');
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(view.clientWidth, view.clientHeight);
  renderer.setClearColor(0x1b1f24);
  view.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(40, view.clientWidth / view.clientHeight, 0.005, 50);
  camera.up.set(0, 0, 1);
  scene.add(camera);
  scene.add(new THREE.AmbientLight(0xffffff, 0.7));
  const sun = new THREE.DirectionalLight(0xffffff, 2.2);
  sun.position.set(0.3, 0.6, 1);
  camera.add(sun);
  const U = meta.unknown_area;
  const target = new THREE.Vector3((U.min[0] + U.max[0]) / 2, (U.min[1] + U.max[1]) / 2, (U.min[2] + U.max[2]) / 2);
  const radius = 0.5 * Math.hypot(U.max[0] - U.min[0], U.max[1] - U.min[1], U.max[2] - U.min[2]);
  const orbit = { az: -2.1, el: 0.45, dist: 2.4 * radius / Math.sin(THREE.MathUtils.degToRad(20)) };
  const place = () => {
    const c = Math.cos(orbit.el);
    camera.position.set(target.x + orbit.dist * c * Math.cos(orbit.az), target.y + orbit.dist * c * Math.sin(orbit.az),
                        target.z + orbit.dist * Math.sin(orbit.el));
    camera.lookAt(target);
  };
  let pending = false;
  const render = () => {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => { pending = false; place(); renderer.render(scene, camera); });
  };

  // pedestal grid (z = 0), unknown area
  const grid = new THREE.GridHelper(1.0, 20, 0x59616b, 0x3a414b);
  grid.rotation.x = Math.PI / 2;
  grid.position.set(target.x, target.y, 0);
  scene.add(grid);
  const unknownBox = new THREE.Box3(new THREE.Vector3(...U.min), new THREE.Vector3(...U.max));
  const boxHelper = new THREE.Box3Helper(unknownBox, 0x6b7480);
  scene.add(boxHelper);

  // the model: every face record, the index rebuilt per scan from [first, last]
  const geom = new THREE.BufferGeometry();
  geom.setAttribute('position', new THREE.BufferAttribute(dequantise(undelta(get('mesh_position'))), 3));
  const mesh = new THREE.Mesh(geom, new THREE.MeshStandardMaterial({ color: 0xd9c7a3, roughness: 0.85,
                                                                     metalness: 0.0, side: THREE.DoubleSide }));
  scene.add(mesh);

  // ground truth (decimated)
  const truth = new THREE.Group();
  if (meta.buffers.truth_position) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(dequantise(get('truth_position')), 3));
    g.setIndex(new THREE.BufferAttribute(get('truth_index'), 1));
    truth.add(new THREE.Mesh(g, new THREE.MeshBasicMaterial({ color: 0x56d364, wireframe: true, transparent: true,
                                                              opacity: 0.35 })));
  }
  scene.add(truth);

  // voxels (final space): occupied p >= 0.7, unknown p = 0.5 (never observed)
  const occ = new THREE.Group(), unk = new THREE.Group();
  if (meta.voxels) {
    const v = meta.voxels, p = get('voxel_p');
    const o = [], u = [];
    for (let i = 0; i < p.length; ++i) {
      const x = i % v.size[0], y = Math.floor(i / v.size[0]) % v.size[1], z = Math.floor(i / (v.size[0] * v.size[1]));
      const list = p[i] >= 179 ? o : p[i] === 128 ? u : null;
      if (list) list.push(v.origin[0] + x * v.edge_m, v.origin[1] + y * v.edge_m, v.origin[2] + z * v.edge_m);
    }
    const points = (arr, color, opacity) => {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(arr), 3));
      return new THREE.Points(g, new THREE.PointsMaterial({ color, size: 0.7 * v.edge_m, transparent: opacity < 1,
                                                            opacity, depthWrite: opacity >= 1 }));
    };
    occ.add(points(o, 0xff7b54, 1));
    unk.add(points(u, 0x7aa2f7, 0.35));
  }
  scene.add(occ, unk);

  // executed paths: a line start → end and an arrow head; the sensor's viewing direction at the start (thin)
  const pathGroups = [];
  const path = get('path');
  for (let i = 0; i < N; ++i) {
    const s = new THREE.Vector3(path[9 * i], path[9 * i + 1], path[9 * i + 2]);
    const e = new THREE.Vector3(path[9 * i + 3], path[9 * i + 4], path[9 * i + 5]);
    const z = new THREE.Vector3(path[9 * i + 6], path[9 * i + 7], path[9 * i + 8]);
    const g = new THREE.Group();
    const d = e.clone().sub(s);
    const len = Math.max(d.length(), 1e-4);
    const arrow = new THREE.ArrowHelper(d.normalize(), s, len, 0xffffff, Math.min(0.03, 0.4 * len), 0.012);
    g.add(arrow);
    const look = new THREE.BufferGeometry().setFromPoints([s, s.clone().addScaledVector(z, 0.05)]);
    g.add(new THREE.Line(look, new THREE.LineBasicMaterial({ color: 0x9aa4ae })));
    g.userData.arrow = arrow;
    pathGroups.push(g);
    scene.add(g);
  }

  // candidates per step (scored before scan `step.scan` on the model of scan - 1)
  const cseg = get('cand_segment'), crgb = get('cand_rgb');
  const stepGroups = new Map();
  for (const st of meta.steps) {
    const g = new THREE.Group();
    const pos = [], col = [];
    for (let i = 0; i < st.count; ++i) {
      if (i === st.chosen) continue;
      const j = st.first + i;
      pos.push(...cseg.slice(6 * j, 6 * j + 6));
      const c = [crgb[3 * j] / 255, crgb[3 * j + 1] / 255, crgb[3 * j + 2] / 255];
      col.push(...c, ...c);
    }
    const lg = new THREE.BufferGeometry();
    lg.setAttribute('position', new THREE.BufferAttribute(new Float32Array(pos), 3));
    lg.setAttribute('color', new THREE.BufferAttribute(new Float32Array(col), 3));
    g.add(new THREE.LineSegments(lg, new THREE.LineBasicMaterial({ vertexColors: true })));
    const j = st.first + st.chosen;
    const s = new THREE.Vector3(cseg[6 * j], cseg[6 * j + 1], cseg[6 * j + 2]);
    const d = new THREE.Vector3(cseg[6 * j + 3], cseg[6 * j + 4], cseg[6 * j + 5]).sub(s);
    const len = Math.max(d.length(), 1e-4);
    g.add(new THREE.ArrowHelper(d.normalize(), s, len, 0x005aff, Math.min(0.035, 0.4 * len), 0.016));
    g.visible = false;
    stepGroups.set(st.scan, g);
    scene.add(g);
  }

  // --robot: the arm at the start of scan `a.scan` (its collision shapes) and the sensor's transfer path to it
  const armGroups = new Map();
  if (meta.arms) {
    const ap = get('arm_position'), ai = get('arm_index'), at = get('arm_transfer');
    for (const a of meta.arms) {
      const g = new THREE.Group();
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.BufferAttribute(ap.slice(3 * a.vfirst, 3 * (a.vfirst + a.vcount)), 3));
      geo.setIndex(new THREE.BufferAttribute(ai.slice(a.ifirst, a.ifirst + a.icount), 1));
      geo.computeVertexNormals();
      g.add(new THREE.Mesh(geo, new THREE.MeshStandardMaterial({ color: 0xe19655, roughness: 0.6, metalness: 0.1,
                                                                 flatShading: true })));
      if (a.tcount > 1) {
        const lg = new THREE.BufferGeometry();
        lg.setAttribute('position', new THREE.BufferAttribute(at.slice(3 * a.tfirst, 3 * (a.tfirst + a.tcount)), 3));
        g.add(new THREE.Line(lg, new THREE.LineBasicMaterial({ color: 0xe040c0 })));
      }
      g.visible = false;
      armGroups.set(a.scan, g);
      scene.add(g);
    }
  }

  const show = (id) => $(id).checked;
  let current = N;
  setScan = (k) => {
    current = k;
    $('scanlabel').textContent = k + ' / ' + N;
    const idx = [];
    for (let f = 0; f < faceFirst.length && faceFirst[f] <= k; ++f)
      if (faceLast[f] >= k) idx.push(meshIndex[3 * f], meshIndex[3 * f + 1], meshIndex[3 * f + 2]);
    geom.setIndex(new THREE.BufferAttribute(new Uint32Array(idx), 1));
    geom.computeVertexNormals();
    mesh.visible = show('mesh');
    pathGroups.forEach((g, i) => {
      g.visible = show('paths') && i < k;
      g.userData.arrow.setColor(i === k - 1 ? 0xffd166 : 0xffffff);
    });
    for (const [scan, g] of stepGroups) g.visible = show('cand') && scan === k + 1;
    for (const [scan, g] of armGroups) g.visible = show('arm') && scan === k;
    truth.visible = show('truth');
    occ.visible = show('occ');
    unk.visible = show('unk');
    boxHelper.visible = show('box');
    const st = meta.steps.find((s) => s.scan === k + 1);
    $('info').textContent = figures(k) + '\nmesh ' + idx.length / 3 + ' faces' +
        (st ? '\nnext: ' + st.count + ' candidates scored, chosen utility ' +
              get('cand_utility')[st.first + st.chosen].toPrecision(4) : '\nno further scan');
    document.body.dataset.scan = k;
    render();
  };
  for (const id of ['mesh', 'paths', 'cand', 'truth', 'occ', 'unk', 'box', 'arm'])
    $(id).addEventListener('change', () => setScan(current));

  // orbit: drag rotates, shift/right drag pans, wheel zooms
  const el = renderer.domElement;
  el.addEventListener('contextmenu', (e) => e.preventDefault());
  let drag = null;
  el.addEventListener('pointerdown', (e) => { drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 };
                                              el.setPointerCapture(e.pointerId); });
  el.addEventListener('pointerup', () => { drag = null; });
  el.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    if (drag.pan) {
      const s = orbit.dist * 0.0015;
      const right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
      const up = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 1);
      target.addScaledVector(right, -dx * s).addScaledVector(up, dy * s);
    } else {
      orbit.az -= dx * 0.008;
      orbit.el = Math.max(-1.5, Math.min(1.5, orbit.el + dy * 0.008));
    }
    render();
  });
  el.addEventListener('wheel', (e) => { e.preventDefault(); orbit.dist *= Math.exp(e.deltaY * 0.001); render(); },
                      { passive: false });
  window.addEventListener('resize', () => {
    camera.aspect = view.clientWidth / view.clientHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(view.clientWidth, view.clientHeight);
    render();
  });
}

// ---- slider and URL: #scan=K&truth=1 runs the same handlers as the controls --------------------------------------
function setSlider(k) {
  $('slider').value = k;
  $('slider').dispatchEvent(new Event('input'));
}
$('slider').addEventListener('input', () => {
  const k = Number($('slider').value);
  if (plotCursor) { plotCursor.setAttribute('x1', px(k)); plotCursor.setAttribute('x2', px(k)); }
  setScan(k);
});
function fromHash() {
  const h = new URLSearchParams(location.hash.slice(1));
  for (const id of ['mesh', 'paths', 'cand', 'truth', 'occ', 'unk', 'box', 'arm'])
    if (h.has(id)) $(id).checked = h.get(id) !== '0';
  const k = Number(h.get('scan'));
  setSlider(Number.isInteger(k) && k >= 1 ? Math.min(k, N) : Number($('slider').value));
}
window.addEventListener('hashchange', fromHash);
fromHash();
document.title = 'nbs session viewer — ready';
</script>
</body>
</html>
)nbsviewer";

}  // namespace nbs::tools::viewer
