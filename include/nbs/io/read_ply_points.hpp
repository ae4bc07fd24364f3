// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Strict PLY point-cloud reader: the `vertex` element's x y z, with nx ny nz and red green blue when present
/// (write_ply_points' output reads back exactly). Faces, other elements and properties are skipped.

#include <array>
#include <cmath>
#include <string>
#include <string_view>

#include "nbs/io/point_cloud.hpp"
#include "nbs/io/read_ply.hpp"

namespace nbs {

/// Reads the points of a PLY file (`bytes` the whole file, `path` naming it in the messages). Normals are read when
/// the vertex element has all of nx ny nz, colours when it has all of red green blue (each an integer in
/// [0, 255]). Throws FileError naming the file and the element, record or line and the value for what read_ply
/// rejects in the header and the data (malformed or truncated files, non-finite coordinates), for only some of
/// nx ny nz or red green blue, a non-finite normal, a colour that is not an integer in [0, 255], and a file
/// without points. A mesh file gives its vertices.
[[nodiscard]] inline PointCloud read_ply_points_bytes(const std::string& path, const std::string& bytes) {
  static constexpr std::array<std::string_view, 6> kExtras = {"nx", "ny", "nz", "red", "green", "blue"};
  io_detail::PlyContents c = io_detail::parse_ply(path, bytes, kExtras);
  const auto group = [&](std::size_t first, const char* what) {
    const int n = c.has_extra[first] + c.has_extra[first + 1] + c.has_extra[first + 2];
    if (n != 0 && n != 3)
      throw FileError(detail::concat(path, ": element 'vertex' has only some of the ", what, " properties ",
                                     kExtras[first], " ", kExtras[first + 1], " ", kExtras[first + 2]));
    return n == 3;
  };
  const bool normals = group(0, "normal");
  std::vector<Rgb> colors = io_detail::ply_vertex_colors(path, c, 3, kExtras.size());
  if (c.vertices.empty()) throw FileError(detail::concat(path, ": the point cloud has no points"));
  PointCloud cloud;
  cloud.points = std::move(c.vertices);
  const std::size_t n = cloud.points.size();
  if (normals) cloud.normals.resize(n);
  cloud.colors = std::move(colors);
  for (std::size_t i = 0; i < n; ++i) {
    const double* e = &c.extras[i * kExtras.size()];
    if (normals) {
      cloud.normals[i] = Vec3(e[0], e[1], e[2]);
      if (!cloud.normals[i].allFinite())
        throw FileError(detail::concat(path, ": element 'vertex' record ", i, ": non-finite normal (",
                                       cloud.normals[i].transpose(), ")"));
    }
  }
  return cloud;
}

/// read_ply_points_bytes of the file at `path` (FileError if it cannot be read).
[[nodiscard]] inline PointCloud read_ply_points(const std::string& path) {
  return read_ply_points_bytes(path, io_detail::read_file_bytes(path));
}

}  // namespace nbs
