// SPDX-License-Identifier: BSD-3-Clause
// The session viewer's data format (docs/internals.md, "The session viewer"), decoded here independently of the
// page's JavaScript: after each scan the face records alive in that scan are exactly the mesh's faces (faces that
// are replaced, kept, added and that come back), vertices within half a 16-bit quantisation step, candidates and
// paths as recorded; the page without three.js carries the hint; "</" in the JSON cannot end its script element.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "conformance/indexed_edge_mesh.hpp"
#include "nbs/io/detail/file_bytes.hpp"
#include "nbs_catch.hpp"
#include "viewer/write_viewer.hpp"

namespace {

using Face = std::array<std::uint32_t, 3>;

/// `f` rotated so that its smallest vertex comes first (orientation kept).
Face rotated(Face f) {
  std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  return f;
}

std::string element(const std::string& html, const std::string& id) {
  const std::string open = "<script id=\"" + id + "\"";
  const std::size_t a = html.find('>', html.find(open)) + 1;
  return html.substr(a, html.find("</script>", a) - a);
}

std::string unbase64(const std::string& in) {
  static const std::string k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (char c : in) {
    const std::size_t v = k.find(c);
    if (v == std::string::npos) continue;  // '=' and white space
    acc = (acc << 6) | std::uint32_t(v);
    if ((bits += 6) >= 8) out.push_back(char((acc >> (bits -= 8)) & 0xFF));
  }
  return out;
}

std::string inflate(const std::string& in, std::size_t size) {
  std::string out(size, '\0');
  uLongf n = size;
  REQUIRE(uncompress(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(in.data()),
                     uLong(in.size())) == Z_OK);
  out.resize(n);
  return out;
}

template <class T>
std::vector<T> section(const std::string& buf, const nlohmann::json& table, const std::string& name) {
  const auto& t = table.at(name);
  std::vector<T> v(t.at("count").get<std::size_t>());
  std::memcpy(v.data(), buf.data() + t.at("offset").get<std::size_t>(), v.size() * sizeof(T));
  return v;
}

nbs::LinearScanPath path_at(double x) {
  using nbs::Vec3;
  return nbs::LinearScanPath(nbs::Viewpoint::look_at(Vec3(x, -0.3, 0.2), Vec3(x, 0, 0.05), Vec3::UnitZ()),
                             nbs::Vec3(x + 0.1, -0.3, 0.2));
}

}  // namespace

TEST_CASE("viewer format: face records reproduce the mesh of every scan", "[viewer]") {
  // Six vertices on a 2 x 3 grid; faces change from scan to scan (ids only appended, as in StreamingMesh).
  nbs::IndexedMesh m;
  for (int i = 0; i < 6; ++i) m.vertices.push_back(nbs::Vec3(0.01 * (i % 3), 0.02 * (i / 3), 0.001 * i));
  const std::vector<std::vector<Face>> scans = {
      {{0, 1, 3}},                        // scan 1
      {{1, 4, 3}, {0, 1, 3}, {1, 2, 4}},  // scan 2: two faces added
      {{1, 4, 3}, {3, 0, 4}, {2, 5, 4}},  // scan 3: {0,1,3} and {1,2,4} replaced, one added (written rotated)
      {{0, 1, 3}, {1, 4, 3}, {2, 5, 4}},  // scan 4: {0,1,3} comes back
  };
  nbs::tools::viewer::SessionRecorder rec;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    nbs::IndexedMesh ms = m;
    ms.vertices.resize(s == 0 ? 4 : 6);  // vertices 4 and 5 appear with scan 2
    for (const Face& f : scans[s]) ms.triangles.push_back(f);
    rec.add_scan(nbs::conformance::IndexedEdgeMesh(ms), path_at(0.1 * double(s)));
  }
  const std::vector<nbs::LinearScanPath> cands = {path_at(0.5), path_at(0.6), path_at(0.7)};
  const std::vector<double> utility = {0.9, 0.1, 0.5};
  rec.add_candidates(2, cands, utility, 0);

  const auto dir = std::filesystem::temp_directory_path() / "nbs_test_viewer_format";
  std::filesystem::remove_all(dir);
  nbs::tools::viewer::SessionRecorder::Extras ex;
  ex.unknown_area = nbs::Aabb{nbs::Vec3(-0.05, -0.05, 0.0), nbs::Vec3(0.05, 0.05, 0.1)};
  ex.report = {{"mesh", "</script><b>"}};
  const std::uintmax_t bytes = rec.write(dir / "index.html", ex, std::nullopt);
  const std::string html = nbs::io_detail::read_file_bytes((dir / "index.html").string());
  CHECK(bytes == html.size());
  CHECK(html.find("</script><b>") == std::string::npos);         // escaped as <\/script>
  CHECK(element(html, "nbs-three").empty());                      // no three.js ...
  CHECK(html.find("scripts/install-viewer.sh") != std::string::npos);  // ... and the hint

  const nlohmann::json meta = nlohmann::json::parse(element(html, "nbs-meta"));
  CHECK(meta.at("report").at("mesh") == "</script><b>");
  CHECK(meta.at("scans") == 4);
  const auto& tb = meta.at("buffers");
  std::size_t raw = 0;
  for (const auto& [name, t] : tb.items())  // an upper bound: 4 bytes per element
    raw = std::max<std::size_t>(raw, t.at("offset").get<std::size_t>() + 4 * t.at("count").get<std::size_t>());
  const std::string buf = inflate(unbase64(element(html, "nbs-data")), raw);

  // vertices: per-axis deltas mod 2^16, quantised in meta.box
  auto q = section<std::uint16_t>(buf, tb, "mesh_position");
  REQUIRE(q.size() == 18);
  for (std::size_t i = 3; i < q.size(); ++i) q[i] = std::uint16_t(q[i] + q[i - 3]);
  const auto& bmin = meta.at("box").at("min");
  const auto& bmax = meta.at("box").at("max");
  for (std::size_t v = 0; v < 6; ++v)
    for (int a = 0; a < 3; ++a) {
      const double lo = bmin[a], hi = bmax[a];
      CHECK(std::abs(lo + q[3 * v + a] / 65535.0 * (hi - lo) - m.vertices[v][a]) <= 0.5 * (hi - lo) / 65535.0 + 1e-12);
    }
  // faces: (a - previous a, b - a, c - a), alive in [first, last], sorted by first
  const auto d = section<std::int32_t>(buf, tb, "mesh_index");
  const auto first = section<std::uint16_t>(buf, tb, "face_first");
  const auto last = section<std::uint16_t>(buf, tb, "face_last");
  REQUIRE(d.size() == 3 * first.size());
  CHECK(first.size() == 6);  // {0,1,3} in scans 1-2 and again in 4, {1,4,3}, {1,2,4}, {0,4,3}, {2,5,4}
  CHECK(std::is_sorted(first.begin(), first.end()));
  std::vector<Face> faces;
  std::int64_t a = 0;
  for (std::size_t i = 0; i < d.size(); i += 3) {
    a += d[i];
    faces.push_back({std::uint32_t(a), std::uint32_t(a + d[i + 1]), std::uint32_t(a + d[i + 2])});
  }
  for (std::size_t s = 0; s < scans.size(); ++s) {
    std::multiset<Face> want, got;
    for (const Face& f : scans[s]) want.insert(rotated(f));
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (first[f] <= s + 1 && s + 1 <= last[f]) got.insert(faces[f]);
    INFO("scan " << s + 1);
    CHECK(got == want);
  }
  // paths and candidates as recorded
  const auto path = section<float>(buf, tb, "path");
  REQUIRE(path.size() == 9 * 4);
  CHECK(path[9 * 3 + 0] == Approx(0.3));
  CHECK(path[9 * 3 + 3] == Approx(0.4));
  const auto& step = meta.at("steps").at(0);
  CHECK(step.at("scan") == 2);
  CHECK(step.at("count") == 3);
  CHECK(step.at("chosen") == 0);
  const auto u = section<float>(buf, tb, "cand_utility");
  CHECK(std::vector<double>(u.begin(), u.end()) == std::vector<double>{0.9f, 0.1f, 0.5f});
  const auto rgb = section<std::uint8_t>(buf, tb, "cand_rgb");
  const nbs::Rgb best = nbs::utility_color(1.0), worst = nbs::utility_color(0.0);
  CHECK(std::vector<std::uint8_t>(rgb.begin(), rgb.begin() + 3) == std::vector<std::uint8_t>(best.begin(), best.end()));
  CHECK(std::vector<std::uint8_t>(rgb.begin() + 3, rgb.begin() + 6) ==
        std::vector<std::uint8_t>(worst.begin(), worst.end()));
  CHECK_FALSE(meta.contains("arms"));  // no --robot: no arm section, the session data as before
  CHECK_FALSE(tb.contains("arm_position"));

  // --robot: per scan the arm's triangles and the transfer polyline, float32 as recorded, indices per arm from 0
  nbs::IndexedMesh arm;
  arm.vertices = {nbs::Vec3(0.5, 0.1, 0.2), nbs::Vec3(0.6, 0.1, 0.2), nbs::Vec3(0.5, 0.3, 0.2), nbs::Vec3(0.5, 0.1, 0.7)};
  arm.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const std::vector<nbs::Vec3> transfer = {nbs::Vec3(0.4, 0, 0.5), nbs::Vec3(0.3, 0.1, 0.4), nbs::Vec3(0.2, 0.2, 0.3)};
  rec.add_arm(1, arm, {});
  rec.add_arm(2, arm, transfer);
  rec.write(dir / "index.html", ex, std::nullopt);
  const std::string html2 = nbs::io_detail::read_file_bytes((dir / "index.html").string());
  const nlohmann::json meta2 = nlohmann::json::parse(element(html2, "nbs-meta"));
  const auto& tb2 = meta2.at("buffers");
  std::size_t raw2 = 0;
  for (const auto& [name, t] : tb2.items())
    raw2 = std::max<std::size_t>(raw2, t.at("offset").get<std::size_t>() + 4 * t.at("count").get<std::size_t>());
  const std::string buf2 = inflate(unbase64(element(html2, "nbs-data")), raw2);
  const auto& arms = meta2.at("arms");
  REQUIRE(arms.size() == 2);
  CHECK(arms[0].at("tcount") == 0);
  CHECK(arms[1].at("scan") == 2);
  const auto pos = section<float>(buf2, tb2, "arm_position");
  const auto idx = section<std::uint32_t>(buf2, tb2, "arm_index");
  const auto tr = section<float>(buf2, tb2, "arm_transfer");
  REQUIRE(tr.size() == 9);
  const std::size_t v0 = arms[1].at("vfirst"), i0 = arms[1].at("ifirst"), t0 = arms[1].at("tfirst");
  CHECK(arms[1].at("vcount") == 4);
  CHECK(arms[1].at("icount") == 12);
  for (std::size_t v = 0; v < 4; ++v)
    for (int c = 0; c < 3; ++c) CHECK(pos[3 * (v0 + v) + c] == float(arm.vertices[v][c]));
  for (std::size_t t = 0; t < 4; ++t)
    for (int c = 0; c < 3; ++c) CHECK(idx[i0 + 3 * t + c] == arm.triangles[t][c]);
  for (std::size_t k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) CHECK(tr[3 * (t0 + k) + c] == float(transfer[k][c]));
  std::filesystem::remove_all(dir);
}

TEST_CASE("viewer decimation: clusters per cell, and a vertex beyond the packable cells throws", "[viewer]") {
  nbs::IndexedMesh m;
  m.vertices = {nbs::Vec3(0.0, 0.0, 0.0), nbs::Vec3(0.001, 0.0, 0.0), nbs::Vec3(0.05, 0.0, 0.0),
                nbs::Vec3(0.05, 0.05, 0.0)};
  m.triangles = {{0, 2, 3}, {1, 2, 3}};
  const nbs::IndexedMesh d = nbs::tools::viewer::detail::decimate(m, 0.01);
  CHECK(d.vertices.size() == 3);   // 0 and 1 share a cell
  CHECK(d.triangles.size() == 1);  // the two faces become one
  // 1 km at 0.1 mm cells: 10^7 cells, beyond the 2^20 of the key packing.
  m.vertices.push_back(nbs::Vec3(1000.0, 0.0, 0.0));
  CHECK_THROWS_WITH(nbs::tools::viewer::detail::decimate(m, 1e-4), nbs_test::Contains("viewer decimation"));
}
