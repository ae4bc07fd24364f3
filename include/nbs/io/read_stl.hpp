// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// STL reader (binary and ASCII; the usual format of URDF collision meshes) and writer. STL stores unindexed
/// triangles: the reader welds vertices with equal coordinates into one (so shared edges share indices) and
/// ignores the stored facet normals (the winding is kept as stored).

#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <system_error>
#include <tuple>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/io/detail/finish_mesh.hpp"
#include "nbs/io/detail/words.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

/// The two STL encodings.
enum class StlFormat { binary, ascii };

namespace io_detail {

/// Collects STL corners and welds bit-identical ones.
class StlBuilder {
public:
  void add_corner(const Vec3& v) {
    const auto [it, inserted] = index_.try_emplace(std::make_tuple(v.x(), v.y(), v.z()),
                                                   static_cast<std::uint32_t>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(v);
    corner_[n_++ % 3] = it->second;
    if (n_ % 3 == 0) mesh_.triangles.push_back({corner_[0], corner_[1], corner_[2]});
  }
  [[nodiscard]] IndexedMesh take() { return std::move(mesh_); }

private:
  IndexedMesh mesh_;
  std::map<std::tuple<double, double, double>, std::uint32_t> index_;
  std::uint32_t corner_[3] = {0, 0, 0};
  std::size_t n_ = 0;
};

[[nodiscard]] inline float stl_le_float(const char* p) {
  std::uint32_t u = 0;
  for (int i = 3; i >= 0; --i) u = (u << 8) | static_cast<unsigned char>(p[i]);
  return std::bit_cast<float>(u);
}

[[nodiscard]] inline IndexedMesh parse_stl_binary(const std::string& path, const std::string& bytes) {
  std::uint32_t n = 0;
  for (int i = 3; i >= 0; --i) n = (n << 8) | static_cast<unsigned char>(bytes[80 + static_cast<std::size_t>(i)]);
  StlBuilder b;
  for (std::uint32_t t = 0; t < n; ++t) {
    const char* rec = bytes.data() + 84 + 50 * static_cast<std::size_t>(t);
    for (int k = 0; k < 3; ++k) {
      const Vec3 v(stl_le_float(rec + 12 + 12 * k), stl_le_float(rec + 16 + 12 * k), stl_le_float(rec + 20 + 12 * k));
      if (!v.allFinite())
        throw FileError(detail::concat(path, ": binary STL triangle ", t, " corner ", k, " is not finite (",
                                       v.transpose(), ")"));
      b.add_corner(v);
    }
  }
  return b.take();
}

[[nodiscard]] inline IndexedMesh parse_stl_ascii(const std::string& path, std::string_view text) {
  StlBuilder b;
  std::size_t pos = 0, line_no = 0, corners_in_loop = 0;
  bool solid = false, facet = false, loop = false, looped = false, ended = false;  // looped: the facet had its loop
  auto fail = [&](const auto&... msg) {
    throw FileError(detail::concat(path, ": line ", line_no, ": ", msg...));
  };
  while (pos < text.size()) {
    ++line_no;
    const auto w = split_words(next_line(text, pos));
    if (w.empty()) continue;
    if (ended) fail("text after 'endsolid'");
    const std::string_view k = w[0];
    if (!solid) {
      if (k != "solid") fail("an ASCII STL starts with 'solid', got '", k, "'");
      solid = true;
    } else if (k == "facet") {
      if (facet) fail("'facet' inside a facet");
      facet = true;
      looped = false;
    } else if (k == "outer") {
      if (!facet || loop || w.size() < 2 || w[1] != "loop") fail("'outer loop' expected inside a facet");
      if (looped) fail("a facet has a second 'outer loop'");
      loop = true;
      looped = true;
      corners_in_loop = 0;
    } else if (k == "vertex") {
      if (!loop) fail("'vertex' outside 'outer loop'");
      if (w.size() != 4) fail("a vertex needs 3 coordinates, got ", w.size() - 1);
      Vec3 v;
      for (int a = 0; a < 3; ++a) {
        const std::string_view s = w[static_cast<std::size_t>(a) + 1];
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v[a]);
        if (r.ec != std::errc() || r.ptr != s.data() + s.size()) fail("'", s, "' is not a number");
        if (!std::isfinite(v[a])) fail("vertex coordinate '", s, "' is not finite");
      }
      if (++corners_in_loop > 3) fail("a facet has more than 3 vertices");
      b.add_corner(v);
    } else if (k == "endloop") {
      if (!loop) fail("'endloop' without 'outer loop'");
      if (corners_in_loop != 3) fail("a facet has ", corners_in_loop, " vertices, STL needs 3");
      loop = false;
    } else if (k == "endfacet") {
      if (!facet || loop) fail("'endfacet' without a closed 'outer loop'");
      if (!looped) fail("a facet without 'outer loop' (no vertices, STL needs 3)");
      facet = false;
    } else if (k == "endsolid") {
      if (facet) fail("'endsolid' inside a facet");
      ended = true;
    } else {
      fail("unexpected '", k, "' (expected facet, outer loop, vertex, endloop, endfacet or endsolid)");
    }
  }
  if (!solid) fail("empty file");
  if (!ended) throw FileError(detail::concat(path, ": ASCII STL ends without 'endsolid' (truncated?)"));
  return b.take();
}

}  // namespace io_detail

/// Reads an STL file held in memory (`bytes`, named `path` in the messages). Binary if the size is 84 + 50·n for the
/// triangle count n in bytes 80–83 (little endian), else ASCII if it starts with "solid", else an error.
/// Coordinates as stored (no unit conversion). Throws FileError naming the file and the problem (and the line for
/// ASCII): a size that fits neither encoding, a truncated binary file, a non-finite or unparsable coordinate, a
/// facet without exactly one loop of 3 vertices, a missing "endsolid", no triangle of positive area.
[[nodiscard]] inline IndexedMesh read_stl_bytes(const std::string& path, const std::string& bytes) {
  if (bytes.size() >= 84) {
    std::uint64_t n = 0;
    for (int i = 3; i >= 0; --i) n = (n << 8) | static_cast<unsigned char>(bytes[80 + static_cast<std::size_t>(i)]);
    if (bytes.size() == 84 + 50 * n) return detail::finish_mesh(path, io_detail::parse_stl_binary(path, bytes));
  }
  std::size_t start = 0;
  while (start < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[start]))) ++start;
  if (bytes.compare(start, 5, "solid") == 0) {
    try {
      return detail::finish_mesh(path, io_detail::parse_stl_ascii(path, bytes));
    } catch (const FileError&) {
      if (bytes.size() >= 84) {  // a binary file whose 80-byte header starts with "solid" but of the wrong size
        const std::size_t nul = bytes.find('\0');
        if (nul != std::string::npos && nul < 84)
          throw FileError(detail::concat(path, ": binary STL of ", bytes.size(),
                                         " bytes does not match its triangle count (truncated or corrupt)"));
      }
      throw;
    }
  }
  if (bytes.size() < 84)
    throw FileError(detail::concat(path, ": not an STL file: ", bytes.size(),
                                   " bytes, shorter than a binary STL header (84 bytes) and not ASCII ('solid')"));
  std::uint64_t n = 0;
  for (int i = 3; i >= 0; --i) n = (n << 8) | static_cast<unsigned char>(bytes[80 + static_cast<std::size_t>(i)]);
  throw FileError(detail::concat(path, ": binary STL declares ", n, " triangles (", 84 + 50 * n, " bytes) but has ",
                                 bytes.size(), " bytes (truncated or corrupt)"));
}

/// Reads the STL file `path`; see read_stl_bytes. Throws FileError naming the file if it cannot be read.
[[nodiscard]] inline IndexedMesh read_stl(const std::string& path) {
  return read_stl_bytes(path, io_detail::read_file_bytes(path));
}

/// Writes `mesh` as STL (binary: float32, little endian; ASCII: 17 significant digits) to `path` via a temporary
/// file renamed into place. Facet normals are the unit face normals (0 for a zero-area triangle). Throws
/// InvalidArgument for an invalid mesh or (binary) a coordinate beyond float32's range, FileError naming the file if
/// it cannot be written.
inline void write_stl(const std::string& path, const IndexedMesh& mesh, StlFormat format = StlFormat::binary) {
  mesh.validate();
  std::string out;
  const auto normal = [&](std::size_t t) {
    const Vec3 n = mesh.face_normal_scaled(t);
    return n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3(Vec3::Zero());
  };
  if (format == StlFormat::binary) {
    detail::require(mesh.triangles.size() <= 0xffffffffu, "write_stl: ", mesh.triangles.size(),
                    " triangles exceed binary STL's 32-bit count");
    out.assign(80, '\0');
    out.replace(0, 15, "nbs binary STL ");
    const auto put_u32 = [&](std::uint32_t u) {
      for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((u >> (8 * i)) & 0xffu));
    };
    const auto put_vec = [&](const Vec3& v) {
      for (int a = 0; a < 3; ++a) put_u32(std::bit_cast<std::uint32_t>(static_cast<float>(v[a])));
    };
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
      detail::require(mesh.vertices[i].cwiseAbs().maxCoeff() <= std::numeric_limits<float>::max(), "write_stl ",
                      path, ": vertex ", i, " (", mesh.vertices[i].transpose(), ") exceeds binary STL's float32 range");
    put_u32(static_cast<std::uint32_t>(mesh.triangles.size()));
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      put_vec(normal(t));
      for (int k = 0; k < 3; ++k) put_vec(mesh.corner(t, k));
      out.append(2, '\0');
    }
  } else {
    const auto num = [](double x) {
      char buf[32];
      const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, 17);
      return std::string(buf, r.ptr);
    };
    const auto vec = [&](const Vec3& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); };
    out = "solid nbs\n";
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      out += "  facet normal " + vec(normal(t)) + "\n    outer loop\n";
      for (int k = 0; k < 3; ++k) out += "      vertex " + vec(mesh.corner(t, k)) + "\n";
      out += "    endloop\n  endfacet\n";
    }
    out += "endsolid nbs\n";
  }
  io_detail::write_file_atomic(path, out);
}

}  // namespace nbs
