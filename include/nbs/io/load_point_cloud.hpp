// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Loads a point cloud from PLY or PCD, chosen by the file's content.

#include <string>

#include "nbs/io/read_pcd.hpp"
#include "nbs/io/read_ply_points.hpp"

namespace nbs {

/// Loads `path` as a PLY cloud (read_ply_points) if the file starts with the PLY magic line, as PCD (read_pcd,
/// with `pcd_options`) if its name ends in .pcd (any case) or its first line is a PCD comment or keyword;
/// otherwise throws FileError. Points are returned as stored (metres are not assumed).
[[nodiscard]] inline PointCloud load_point_cloud(const std::string& path, const PcdReadOptions& pcd_options = {}) {
  const std::string bytes = io_detail::read_file_bytes(path);
  if (bytes.starts_with("ply\n") || bytes.starts_with("ply\r")) return read_ply_points_bytes(path, bytes);
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : std::string();
  for (char& c : ext) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  if (ext == ".pcd" || bytes.starts_with("# .PCD") || bytes.starts_with("VERSION") || bytes.starts_with("FIELDS"))
    return read_pcd_bytes(path, bytes, pcd_options);
  throw FileError(detail::concat(path, ": unknown point-cloud format (expected a PLY or a PCD file)"));
}

}  // namespace nbs
