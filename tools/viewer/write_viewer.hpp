// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The interactive session viewer of `nbs_model --viewer` (tool code, not part of the nbs library): a
/// `SessionRecorder` collects the mesh after each scan, the executed scan paths and the scored candidates of each
/// step; `write_viewer` writes one self-contained `DIR/index.html` (three.js inlined, the session as a
/// zlib-compressed binary buffer, base64) that opens offline from file://. Data format: docs/internals.md
/// ("The session viewer"); the page: tools/viewer/viewer_html.hpp.

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "nbs/core/detail/cell_key.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/core/types.hpp"
#include "nbs/io/color.hpp"
#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/mesh/mesh_concept.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

#include "viewer/viewer_html.hpp"

namespace nbs::tools::viewer {

/// The three.js release the viewer is written for (scripts/install-viewer.sh installs exactly this one; r171 and
/// later split three.module.js into two files, which the inlining below does not handle).
inline constexpr std::string_view kThreeVersion = "0.170.0";

/// How to get three.js, printed by nbs_model and shown by the page when the library was not found.
[[nodiscard]] inline std::string three_hint() {
  return "three.js " + std::string(kThreeVersion) +
         " not found: run scripts/install-viewer.sh (npm install --prefix build/viewer-deps three@" +
         std::string(kThreeVersion) + ") and rerun with --viewer, or set NBS_THREE_JS to a three.module.min.js";
}

#ifndef NBS_VIEWER_DEPS_DIR  // tools/CMakeLists.txt: <source tree>/build/viewer-deps
#define NBS_VIEWER_DEPS_DIR "build/viewer-deps"
#endif

/// three.module.min.js: $NBS_THREE_JS if set, else the copy scripts/install-viewer.sh installs under
/// `deps_dir` (build/viewer-deps of the source tree). std::nullopt if neither file exists.
[[nodiscard]] inline std::optional<std::filesystem::path> find_three_js(
    const std::filesystem::path& deps_dir = NBS_VIEWER_DEPS_DIR) {
  if (const char* env = std::getenv("NBS_THREE_JS"); env != nullptr && *env != '\0') {
    if (std::filesystem::is_regular_file(env)) return std::filesystem::path(env);
    return std::nullopt;
  }
  const auto p = deps_dir / "node_modules" / "three" / "build" / "three.module.min.js";
  if (std::filesystem::is_regular_file(p)) return p;
  return std::nullopt;
}

/// Collects a modeling session scan by scan. Faces are kept as records (a, b, c, first scan, last scan): a face
/// of the StreamingMesh may be replaced by a later scan, so each appearance of a face is one record, open while the
/// face exists. Vertex ids are the StreamingMesh's (it only appends vertices).
class SessionRecorder {
 public:
  /// Call after the scan along `path` was integrated into `mesh` (scans are counted from 1). `mesh` only appends
  /// vertices (vertex ids stay), as StreamingMesh does.
  template <EdgeMesh M>
  void add_scan(const M& mesh, const LinearScanPath& path) {
    ++scans_;
    paths_.push_back(path);
    std::vector<char> seen(faces_.size(), 0);
    mesh.for_each_face([&](const MeshFace& f) {
      const Key k = canonical(f.a, f.b, f.c);
      const auto [it, fresh] = open_.try_emplace(k, static_cast<std::uint32_t>(faces_.size()));
      if (fresh) {
        faces_.push_back({k, static_cast<std::uint16_t>(scans_), kOpen});
        seen.push_back(1);
      } else {
        seen[it->second] = 1;
      }
    });
    for (auto it = open_.begin(); it != open_.end();) {
      if (seen[it->second] == 0) {
        faces_[it->second].last = static_cast<std::uint16_t>(scans_ - 1);
        it = open_.erase(it);
      } else {
        ++it;
      }
    }
    positions_.resize(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) positions_[v] = mesh.position(static_cast<VertexId>(v));
  }

  /// The candidate set scored before scan `scan` (paths[chosen] was executed), with its utilities (Fig. 4.16).
  void add_candidates(int scan, std::span<const LinearScanPath> paths, std::span<const double> utility,
                      std::size_t chosen = 0) {
    steps_.push_back({scan, std::vector<LinearScanPath>(paths.begin(), paths.end()),
                      std::vector<double>(utility.begin(), utility.end()), chosen});
  }

  /// --robot (issue 19 item 5): the arm at the start of scan `scan` (`arm`: its collision shapes as triangles, world
  /// frame, robot/shape_mesh.hpp) and the sensor's path along the transfer to that start (world, metres; empty for
  /// none). The page shows it with the scan.
  void add_arm(int scan, const IndexedMesh& arm, std::span<const Vec3> transfer) {
    arms_.push_back({scan, arm, std::vector<Vec3>(transfer.begin(), transfer.end())});
  }

  [[nodiscard]] int scans() const { return scans_; }

  /// What `write_viewer` adds next to the recorded session.
  struct Extras {
    Aabb unknown_area;                                  ///< the unknown area box (Sec. 4.1)
    const IndexedMesh* truth = nullptr;                 ///< the object's ground truth, decimated to ~truth_faces
    std::size_t truth_faces = 20000;
    const ProbabilisticVoxelSpace<>* space = nullptr;   ///< final voxel space (p of every voxel in its bounds)
    std::uint64_t max_voxels = 4'000'000;               ///< left out above this many voxels in the bounds
    nlohmann::ordered_json report;                      ///< report.json of the run (the per-scan series)
  };

  /// Writes `path` (index.html; parent directory created) atomically. `three_js`: three.module.min.js to inline,
  /// or std::nullopt (the page then shows three_hint()). Returns the file size in bytes.
  std::uintmax_t write(const std::filesystem::path& path, const Extras& extras,
                       const std::optional<std::filesystem::path>& three_js) const;

 private:
  struct Key {
    std::uint32_t a, b, c;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = k.a * 0x9E3779B97F4A7C15ULL;
      h ^= (h >> 29) + k.b * 0xBF58476D1CE4E5B9ULL;
      h ^= (h >> 31) + k.c * 0x94D049BB133111EBULL;
      return static_cast<std::size_t>(h ^ (h >> 32));
    }
  };
  struct FaceRecord {
    Key v;
    std::uint16_t first, last;
  };
  struct Step {
    int scan;
    std::vector<LinearScanPath> paths;
    std::vector<double> utility;
    std::size_t chosen;
  };
  struct Arm {
    int scan;
    IndexedMesh mesh;
    std::vector<Vec3> transfer;
  };
  static constexpr std::uint16_t kOpen = 0xFFFF;

  /// The face with its smallest vertex first, orientation kept.
  static Key canonical(VertexId a, VertexId b, VertexId c) {
    if (b < a && b < c) return {b, c, a};
    if (c < a && c < b) return {c, a, b};
    return {a, b, c};
  }

  int scans_ = 0;
  std::vector<FaceRecord> faces_;
  std::unordered_map<Key, std::uint32_t, KeyHash> open_;
  std::vector<Vec3> positions_;
  std::vector<LinearScanPath> paths_;
  std::vector<Step> steps_;
  std::vector<Arm> arms_;
};

namespace detail {

/// Little binary buffer with named, 4-byte aligned sections described in a JSON table.
struct Blob {
  std::string bytes;
  nlohmann::ordered_json table = nlohmann::ordered_json::object();

  template <class T>
  void add(const std::string& name, const std::vector<T>& v, const char* type) {
    while (bytes.size() % 4 != 0) bytes.push_back('\0');
    table[name] = {{"type", type}, {"offset", bytes.size()}, {"count", v.size()}};
    bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
};

[[nodiscard]] inline std::string zlib_compress(const std::string& in) {
  uLongf n = compressBound(static_cast<uLong>(in.size()));
  std::string out(n, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(in.data()),
                static_cast<uLong>(in.size()), 6) != Z_OK)  // level 9: 1 % smaller, 10x slower (4.7 s, demo)
    throw Error("viewer: zlib compression failed");
  out.resize(n);
  return out;
}

[[nodiscard]] inline std::string base64(std::string_view in) {
  static constexpr char k[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const auto n = (std::uint32_t(std::uint8_t(in[i])) << 16) | (std::uint32_t(std::uint8_t(in[i + 1])) << 8) |
                   std::uint8_t(in[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out.push_back(k[(n >> s) & 63]);
  }
  if (i < in.size()) {
    std::uint32_t n = std::uint32_t(std::uint8_t(in[i])) << 16;
    if (i + 1 < in.size()) n |= std::uint32_t(std::uint8_t(in[i + 1])) << 8;
    out.push_back(k[(n >> 18) & 63]);
    out.push_back(k[(n >> 12) & 63]);
    out.push_back(i + 1 < in.size() ? k[(n >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

/// Quantises positions to 16 bit per axis in `box` (q = round((p - min) / extent · 65535)).
[[nodiscard]] inline std::uint16_t quantise(double x, double lo, double extent) {
  const double q = extent > 0 ? std::round((x - lo) / extent * 65535.0) : 0.0;
  return static_cast<std::uint16_t>(std::clamp(q, 0.0, 65535.0));
}

/// Vertex-clustering decimation of `mesh` on a grid of cell `cell_m` (a cluster's vertex is its mean; faces whose
/// three clusters differ are kept, duplicates removed). Throws InvalidArgument if a vertex lies more than 2²⁰ cells
/// from the mesh's minimum (or is not finite).
[[nodiscard]] inline IndexedMesh decimate(const IndexedMesh& mesh, double cell_m) {
  struct Acc {
    Vec3 sum = Vec3::Zero();
    int n = 0;
    std::uint32_t id = 0;
  };
  std::unordered_map<std::uint64_t, Acc> cells;
  const Aabb b = mesh.bounds();
  std::vector<std::uint64_t> cell_of(mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const std::uint64_t key = nbs::detail::pack_cell_key_checked((mesh.vertices[v] - b.min) / cell_m, "viewer decimation");
    cell_of[v] = key;
    Acc& a = cells[key];
    a.sum += mesh.vertices[v];
    ++a.n;
  }
  IndexedMesh out;
  std::vector<std::uint64_t> keys;
  keys.reserve(cells.size());
  for (const auto& [key, a] : cells) keys.push_back(key);
  std::sort(keys.begin(), keys.end());  // deterministic numbering
  for (std::uint64_t key : keys) {
    Acc& a = cells[key];
    a.id = static_cast<std::uint32_t>(out.vertices.size());
    out.vertices.push_back(a.sum / a.n);
  }
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (const auto& t : mesh.triangles) {
    std::array<std::uint32_t, 3> r{cells[cell_of[t[0]]].id, cells[cell_of[t[1]]].id, cells[cell_of[t[2]]].id};
    if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;
    std::rotate(r.begin(), std::min_element(r.begin(), r.end()), r.end());
    tris.push_back(r);
  }
  std::sort(tris.begin(), tris.end());
  tris.erase(std::unique(tris.begin(), tris.end()), tris.end());
  for (const auto& r : tris) out.triangles.push_back({r[0], r[1], r[2]});
  return out;
}

/// `text` with every "</" written as "<\/" (safe inside a <script> element; same JSON value).
[[nodiscard]] inline std::string script_safe(std::string text) {
  for (std::size_t i = 0; (i = text.find("</", i)) != std::string::npos; i += 3) text.replace(i, 2, "<\\/");
  return text;
}

inline void replace_once(std::string& s, std::string_view what, std::string_view with) {
  const std::size_t i = s.find(what);
  if (i == std::string::npos) throw Error("viewer: template has no " + std::string(what));
  s.replace(i, what.size(), with);
}

}  // namespace detail

inline std::uintmax_t SessionRecorder::write(const std::filesystem::path& path, const Extras& ex,
                                             const std::optional<std::filesystem::path>& three_js) const {
  // The quantisation box: the unknown area, the model's vertices and the ground truth.
  Aabb box = ex.unknown_area;
  std::vector<std::uint32_t> remap(positions_.size(), 0xFFFFFFFFu);
  for (const FaceRecord& f : faces_)
    for (std::uint32_t v : {f.v.a, f.v.b, f.v.c}) remap[v] = 0;
  std::vector<Vec3> used;
  for (std::size_t v = 0; v < positions_.size(); ++v)
    if (remap[v] == 0) {
      remap[v] = static_cast<std::uint32_t>(used.size());
      used.push_back(positions_[v]);
      box.extend(positions_[v]);
    }
  std::optional<IndexedMesh> truth;
  if (ex.truth != nullptr && !ex.truth->triangles.empty()) {
    const double diag = ex.truth->bounds().extent().norm();
    double cell = diag / 400.0;  // coarsen until at most truth_faces faces remain
    truth = detail::decimate(*ex.truth, cell);
    while (truth->triangles.size() > ex.truth_faces) truth = detail::decimate(*ex.truth, cell *= 1.3);
    for (const Vec3& p : truth->vertices) box.extend(p);
  }
  for (const LinearScanPath& p : paths_) box.extend(p.start().position()), box.extend(p.end_position());
  const Vec3 ext = box.extent();
  const auto q3 = [&](std::vector<std::uint16_t>& out, const Vec3& p) {
    for (int a = 0; a < 3; ++a) out.push_back(detail::quantise(p[a], box.min[a], ext[a]));
  };

  detail::Blob blob;
  nlohmann::ordered_json meta;
  meta["format"] = "nbs-session-viewer 1";
  meta["scans"] = scans_;
  meta["box"] = {{"min", {box.min.x(), box.min.y(), box.min.z()}}, {"max", {box.max.x(), box.max.y(), box.max.z()}}};
  meta["unknown_area"] = {{"min", {ex.unknown_area.min.x(), ex.unknown_area.min.y(), ex.unknown_area.min.z()}},
                          {"max", {ex.unknown_area.max.x(), ex.unknown_area.max.y(), ex.unknown_area.max.z()}}};
  {  // the mesh: vertices (16-bit, each axis as the difference to the previous vertex modulo 2^16), faces sorted
     // by (first scan, smallest vertex, next vertex) as (a - previous face's a, b - a, c - a), each face alive in
     // the scans [first, last]; deltas let zlib find the repetition (the demo's buffer: 1.5 MB -> 1.0 MB)
    std::vector<std::uint16_t> pos;
    pos.reserve(3 * used.size());
    for (const Vec3& p : used) q3(pos, p);
    for (std::size_t i = pos.size(); i-- > 3;) pos[i] = static_cast<std::uint16_t>(pos[i] - pos[i - 3]);
    std::vector<std::array<std::uint32_t, 5>> recs;  // first, a, b, c, last (a the smallest after remapping)
    recs.reserve(faces_.size());
    for (const FaceRecord& f : faces_) {
      std::array<std::uint32_t, 3> t{remap[f.v.a], remap[f.v.b], remap[f.v.c]};
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());  // keeps the orientation
      recs.push_back({f.first, t[0], t[1], t[2], f.last == kOpen ? static_cast<std::uint32_t>(scans_) : f.last});
    }
    std::sort(recs.begin(), recs.end());
    std::vector<std::int32_t> idx;
    std::vector<std::uint16_t> first, last;
    idx.reserve(3 * recs.size());
    std::int64_t prev = 0;
    for (const auto& r : recs) {
      idx.insert(idx.end(), {static_cast<std::int32_t>(r[1] - prev), static_cast<std::int32_t>(r[2] - r[1]),
                             static_cast<std::int32_t>(r[3] - r[1])});
      prev = r[1];
      first.push_back(static_cast<std::uint16_t>(r[0]));
      last.push_back(static_cast<std::uint16_t>(r[4]));
    }
    blob.add("mesh_position", pos, "u16");
    blob.add("mesh_index", idx, "i32");
    blob.add("face_first", first, "u16");
    blob.add("face_last", last, "u16");
  }
  {  // executed paths (start, end, sensor axes at the start), float32 metres
    std::vector<float> seg;
    for (const LinearScanPath& p : paths_) {
      const Pose s = p.start().pose();
      for (const Vec3& v : {p.start().position(), p.end_position(), Vec3(s.linear().col(2))})
        for (int a = 0; a < 3; ++a) seg.push_back(static_cast<float>(v[a]));
    }
    blob.add("path", seg, "f32");
  }
  {  // candidates per step: segments, utility, colour (Fig. 4.16, io/color.hpp), chosen index
    std::vector<float> seg, util;
    std::vector<std::uint8_t> rgb;
    nlohmann::ordered_json steps = nlohmann::ordered_json::array();
    for (const Step& st : steps_) {
      const std::vector<double> u01 = normalize_utilities(st.utility);
      steps.push_back({{"scan", st.scan}, {"first", util.size()}, {"count", st.paths.size()}, {"chosen", st.chosen}});
      for (std::size_t i = 0; i < st.paths.size(); ++i) {
        for (const Vec3& v : {st.paths[i].start().position(), st.paths[i].end_position()})
          for (int a = 0; a < 3; ++a) seg.push_back(static_cast<float>(v[a]));
        util.push_back(static_cast<float>(st.utility[i]));
        const Rgb c = utility_color(u01[i]);
        rgb.insert(rgb.end(), {c[0], c[1], c[2]});
      }
    }
    blob.add("cand_segment", seg, "f32");
    blob.add("cand_utility", util, "f32");
    blob.add("cand_rgb", rgb, "u8");
    meta["steps"] = steps;
  }
  if (!arms_.empty()) {  // --robot: per scan the arm's triangles and the transfer polyline, float32 metres
    std::vector<float> pos, transfer;
    std::vector<std::uint32_t> idx;
    nlohmann::ordered_json arms = nlohmann::ordered_json::array();
    const auto put = [](std::vector<float>& out, const Vec3& v) {
      for (int a = 0; a < 3; ++a) out.push_back(static_cast<float>(v[a]));
    };
    for (const Arm& a : arms_) {
      arms.push_back({{"scan", a.scan}, {"vfirst", pos.size() / 3}, {"vcount", a.mesh.vertices.size()},
                      {"ifirst", idx.size()}, {"icount", 3 * a.mesh.triangles.size()},
                      {"tfirst", transfer.size() / 3}, {"tcount", a.transfer.size()}});
      for (const Vec3& v : a.mesh.vertices) put(pos, v);
      for (const auto& t : a.mesh.triangles) idx.insert(idx.end(), {t[0], t[1], t[2]});  // per arm from 0
      for (const Vec3& v : a.transfer) put(transfer, v);
    }
    blob.add("arm_position", pos, "f32");
    blob.add("arm_index", idx, "u32");
    blob.add("arm_transfer", transfer, "f32");
    meta["arms"] = arms;
  }
  if (truth) {
    std::vector<std::uint16_t> pos;
    for (const Vec3& p : truth->vertices) q3(pos, p);
    std::vector<std::uint32_t> idx;
    for (const auto& t : truth->triangles) idx.insert(idx.end(), {t[0], t[1], t[2]});
    blob.add("truth_position", pos, "u16");
    blob.add("truth_index", idx, "u32");
  }
  if (ex.space != nullptr) {  // p of every voxel in the space's bounds, 0..255, x fastest
    const KeyBox kb = ex.space->bounds_keys();
    if (!kb.empty() && kb.volume() <= ex.max_voxels) {
      std::vector<std::uint8_t> p;
      p.reserve(kb.volume());
      for (std::int32_t z = kb.min.z; z <= kb.max.z; ++z)
        for (std::int32_t y = kb.min.y; y <= kb.max.y; ++y)
          for (std::int32_t x = kb.min.x; x <= kb.max.x; ++x)
            p.push_back(static_cast<std::uint8_t>(
                std::lround(255.0 * std::clamp(ex.space->probability(VoxelKey{x, y, z}), 0.0, 1.0))));
      blob.add("voxel_p", p, "u8");
      const Vec3 c0 = ex.space->grid().center(kb.min);
      meta["voxels"] = {{"origin", {c0.x(), c0.y(), c0.z()}},
                        {"size", {kb.max.x - kb.min.x + 1, kb.max.y - kb.min.y + 1, kb.max.z - kb.min.z + 1}},
                        {"edge_m", ex.space->resolution_m()}};
    }
  }
  meta["buffers"] = blob.table;
  meta["report"] = ex.report;
  meta["three_hint"] = three_hint();

  std::string html(kViewerHtml);
  detail::replace_once(html, "@NBS_META@", detail::script_safe(meta.dump()));
  detail::replace_once(html, "@NBS_DATA@", detail::base64(detail::zlib_compress(blob.bytes)));
  std::string three;
  if (three_js) {
    three = io_detail::read_file_bytes(three_js->string());
    if (three.find("</script") != std::string::npos || three.find("<!--") != std::string::npos)
      throw Error(three_js->string() + ": cannot be inlined (holds </script or <!--)");
  }
  detail::replace_once(html, "@NBS_THREE@", three);
  std::filesystem::create_directories(path.parent_path());
  io_detail::write_file_atomic(path.string(), html);
  return html.size();
}

/// nbs_model's call: writes `out_dir`/viewer/index.html with three.js if it is found and prints one line (the
/// file and its size), or the hint how to get three.js.
inline void write_viewer(const SessionRecorder& rec, const std::filesystem::path& out_dir,
                         const SessionRecorder::Extras& extras) {
  const auto three = find_three_js();
  const auto path = out_dir / "viewer" / "index.html";
  const std::uintmax_t bytes = rec.write(path, extras, three);
  std::printf("viewer  %s (%.2f MB%s)\n", path.string().c_str(), double(bytes) / 1e6,
              three ? ", three.js inlined; opens offline" : "");
  if (!three) std::printf("viewer  %s\n", three_hint().c_str());
}

}  // namespace nbs::tools::viewer
