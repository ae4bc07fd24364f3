// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Strict PLY reader (ascii, binary little/big endian) for triangle meshes: `vertex` (x, y, z), `face`
/// (polygons, fan-triangulated) and `tristrips` (−1 restarts a strip) elements, and vertex colours (uchar or any
/// integer-valued red green blue in [0, 255]) when present; other elements and properties are skipped.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/io/detail/finish_mesh.hpp"
#include "nbs/io/detail/ply_body.hpp"
#include "nbs/io/detail/ply_header.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

namespace io_detail {

/// Index list property of a `face` / `tristrips` element ("vertex_indices" or "vertex_index"). Throws if absent
/// or not an integer list.
[[nodiscard]] inline int index_list_property(const std::string& path, const PlyElement& e) {
  int k = e.find("vertex_indices");
  if (k < 0) k = e.find("vertex_index");
  auto fail = [&](const char* msg) {
    throw FileError(detail::concat(path, ": line ", e.header_line, ": element '", e.name, "' ", msg));
  };
  if (k < 0) fail("has no 'vertex_indices' list property");
  const auto& p = e.properties[static_cast<std::size_t>(k)];
  if (!p.is_list) fail("property 'vertex_indices' must be a list");
  if (!ply_type_is_integer(p.type)) fail("property 'vertex_indices' must have an integer item type");
  return k;
}

/// Appends the triangles of one strip, alternating the winding; drops degenerate (stitching) triangles.
inline void append_strip(const std::vector<std::uint32_t>& s, std::vector<IndexedMesh::Triangle>& out) {
  for (std::size_t k = 0; k + 2 < s.size(); ++k) {
    const IndexedMesh::Triangle t = k % 2 == 0 ? IndexedMesh::Triangle{s[k], s[k + 1], s[k + 2]}
                                               : IndexedMesh::Triangle{s[k + 1], s[k], s[k + 2]};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) out.push_back(t);
  }
}

/// What parse_ply reads from a PLY file: the `vertex` element's x y z, per vertex the values of the requested extra
/// scalar properties, and the triangles of the `face` / `tristrips` elements (indices in range; not yet validated as
/// a mesh).
struct PlyContents {
  std::vector<Vec3> vertices;
  std::vector<IndexedMesh::Triangle> triangles;
  std::vector<double> extras;  ///< vertices.size() × extra names, row-major; 0 where has_extra is false
  std::vector<bool> has_extra; ///< per extra name: the vertex element has it
};

/// Parses `bytes` (a whole PLY file, named `path` in the messages). `extra_names` are vertex properties to read
/// besides x y z; each one the file has must be a scalar. Throws FileError as documented at read_ply.
[[nodiscard]] inline PlyContents parse_ply(const std::string& path, const std::string& bytes,
                                           std::span<const std::string_view> extra_names = {}) {
  const PlyHeader header = parse_ply_header(path, bytes);
  std::uint64_t vertex_count = 0;
  for (const auto& e : header.elements)
    if (e.name == "vertex") vertex_count = e.count;
  if (vertex_count > std::numeric_limits<std::uint32_t>::max())
    throw FileError(detail::concat(path, ": ", vertex_count, " vertices exceed the 32-bit index range"));

  PlyContents out;
  out.has_extra.assign(extra_names.size(), false);
  const std::size_t n_extra = extra_names.size();
  PlyBodyReader in(path, bytes, header);
  std::vector<std::uint32_t> list;
  std::vector<double> extra(n_extra, 0.0);
  for (const auto& e : header.elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face", is_strip = e.name == "tristrips";
    int xyz[3] = {-1, -1, -1};
    std::vector<int> extra_at(n_extra, -1);  // property index of each extra name
    if (is_vertex) {
      const char* names[3] = {"x", "y", "z"};
      for (int a = 0; a < 3; ++a) {
        xyz[a] = e.find(names[a]);
        if (xyz[a] < 0 || e.properties[static_cast<std::size_t>(xyz[a])].is_list)
          throw FileError(detail::concat(path, ": line ", e.header_line, ": element 'vertex' needs a scalar property '",
                                         names[a], "'"));
      }
      for (std::size_t j = 0; j < n_extra; ++j) {
        extra_at[j] = e.find(extra_names[j]);
        if (extra_at[j] >= 0 && e.properties[static_cast<std::size_t>(extra_at[j])].is_list)
          throw FileError(detail::concat(path, ": line ", e.header_line, ": vertex property '", extra_names[j],
                                         "' must be a scalar"));
        out.has_extra[j] = extra_at[j] >= 0;
      }
    }
    const int index_prop = is_face || is_strip ? index_list_property(path, e) : -1;
    // Reject absurd counts before allocating: every record takes at least this many bytes.
    const std::size_t min_record =
        header.format == PlyFormat::ascii ? 2 * e.properties.size() : e.min_binary_size();
    if (min_record > 0 && e.count > (in.remaining() + 1) / min_record)
      throw FileError(detail::concat(path, ": element '", e.name, "' declares ", e.count, " records but only ",
                                     in.remaining(), " bytes follow (truncated?)"));
    if (is_vertex) {
      out.vertices.reserve(static_cast<std::size_t>(e.count));
      out.extras.reserve(static_cast<std::size_t>(e.count) * n_extra);
    }

    for (std::uint64_t r = 0; r < e.count; ++r) {
      in.begin_record(e, r);
      Vec3 v = Vec3::Zero();
      std::fill(extra.begin(), extra.end(), 0.0);
      list.clear();
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& p = e.properties[k];
        if (!p.is_list) {
          const double x = in.read_real(p.type, p.name);
          for (int a = 0; a < 3; ++a)
            if (static_cast<int>(k) == xyz[a]) v[a] = x;
          for (std::size_t j = 0; j < n_extra; ++j)
            if (static_cast<int>(k) == extra_at[j]) extra[j] = x;
          continue;
        }
        const std::int64_t n = in.read_int(p.count_type, p.name + " count");
        if (n < 0) in.fail(p.name, ": negative list length ", n);
        if (static_cast<int>(k) != index_prop) {
          in.skip(p.type, static_cast<std::uint64_t>(n), p.name);
          continue;
        }
        for (std::int64_t i = 0; i < n; ++i) {
          const std::int64_t idx = in.read_int(p.type, p.name);
          if (is_strip && idx == -1) {
            list.push_back(std::numeric_limits<std::uint32_t>::max());  // restart marker
            continue;
          }
          if (idx < 0 || static_cast<std::uint64_t>(idx) >= vertex_count)
            in.fail("vertex index ", idx, " out of range [0, ", vertex_count, ")");
          list.push_back(static_cast<std::uint32_t>(idx));
        }
        if (is_face && n < 3) in.fail("a face needs at least 3 vertices, got ", n);
      }
      in.end_record();
      if (is_vertex) {
        if (!v.allFinite()) in.fail("non-finite coordinate (", v.transpose(), ")");
        out.vertices.push_back(v);
        out.extras.insert(out.extras.end(), extra.begin(), extra.end());
      } else if (is_face) {
        for (std::size_t i = 1; i + 1 < list.size(); ++i) out.triangles.push_back({list[0], list[i], list[i + 1]});
      } else if (is_strip) {
        std::vector<std::uint32_t> strip;
        for (std::uint32_t idx : list) {
          if (idx == std::numeric_limits<std::uint32_t>::max()) {
            append_strip(strip, out.triangles);
            strip.clear();
          } else {
            strip.push_back(idx);
          }
        }
        append_strip(strip, out.triangles);
      }
    }
  }
  in.finish();
  return out;
}

/// The vertex colours of parsed PLY contents whose extras `first`, `first + 1`, `first + 2` (of `stride` per vertex)
/// are red, green, blue: empty if the vertex element has none of them. Throws FileError if it has only some, or a
/// value is not an integer in [0, 255].
[[nodiscard]] inline std::vector<Rgb> ply_vertex_colors(const std::string& path, const PlyContents& c,
                                                        std::size_t first, std::size_t stride) {
  const int n = c.has_extra[first] + c.has_extra[first + 1] + c.has_extra[first + 2];
  if (n == 0) return {};
  if (n != 3)
    throw FileError(detail::concat(path, ": element 'vertex' has only some of the colour properties red green blue"));
  static constexpr const char* kNames[3] = {"red", "green", "blue"};
  std::vector<Rgb> colors(c.vertices.size());
  for (std::size_t i = 0; i < colors.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      const double v = c.extras[i * stride + first + k];
      if (!(v >= 0.0 && v <= 255.0 && std::floor(v) == v))
        throw FileError(detail::concat(path, ": element 'vertex' record ", i, ": colour ", kNames[k], " = ", v,
                                       " is not an integer in [0, 255]"));
      colors[i][k] = static_cast<std::uint8_t>(v);
    }
  return colors;
}

}  // namespace io_detail

/// Reads a triangle mesh from a PLY file (metres are not assumed: coordinates are copied as stored).
/// Faces with n ≥ 3 vertices become n − 2 triangles (v0, v_i, v_i+1); `tristrips` lists become strips with
/// alternating winding, −1 starting a new strip. Throws FileError naming the file, the line or element record
/// and the problem for: a bad or truncated header, an unknown type, wrong property types (x/y/z lists, non-integer
/// indices), truncated or surplus data, non-finite coordinates, faces with < 3 vertices, indices out of range,
/// no triangle at all, only some of red green blue or a colour that is not an integer in [0, 255]. Nothing is returned on failure.
[[nodiscard]] inline IndexedMesh read_ply(const std::string& path);

/// read_ply of a file's contents held in memory: `bytes` is the whole file, `path` names it in the messages.
/// The same checks and errors as read_ply.
[[nodiscard]] inline IndexedMesh read_ply_bytes(const std::string& path, const std::string& bytes) {
  static constexpr std::array<std::string_view, 3> kColors = {"red", "green", "blue"};
  io_detail::PlyContents c = io_detail::parse_ply(path, bytes, kColors);
  if (c.triangles.empty() && !c.vertices.empty())
    throw FileError(detail::concat(path, ": ", c.vertices.size(),
                                   " vertices and no faces: a point cloud, not a mesh (read it with read_ply_points or "
                                   "load_point_cloud)"));
  IndexedMesh mesh;
  mesh.colors = io_detail::ply_vertex_colors(path, c, 0, kColors.size());
  mesh.vertices = std::move(c.vertices);
  mesh.triangles = std::move(c.triangles);
  return detail::finish_mesh(path, std::move(mesh));
}

inline IndexedMesh read_ply(const std::string& path) { return read_ply_bytes(path, io_detail::read_file_bytes(path)); }

}  // namespace nbs
