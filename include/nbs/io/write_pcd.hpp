// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// PCD writer (PCL's Point Cloud Data format v0.7, DATA ascii or binary): x y z and normal_x normal_y normal_z as
/// 8-byte floats, colours as PCL's packed `rgb` (TYPE F SIZE 4, bits 0x00RRGGBB), the viewpoint when the cloud has
/// one. read_pcd reads the file back exactly; PCL reads it as a PCLPointCloud2.

#include <bit>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>

#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/io/point_cloud.hpp"

namespace nbs {

enum class PcdFormat { ascii, binary };

/// Writes `cloud` (validated first: InvalidArgument naming the problem) to `path`, atomically (FileError if it
/// cannot be written; `path` is then unchanged). Binary data is little-endian.
inline void write_pcd(const std::string& path, const PointCloud& cloud, PcdFormat format = PcdFormat::binary) {
  cloud.validate();
  static_assert(std::endian::native == std::endian::little, "write_pcd writes little-endian data");
  const bool nrm = cloud.has_normals(), rgb = cloud.has_colors();
  std::ostringstream out;
  out.precision(17);
  out << "# .PCD v0.7 - Point Cloud Data file format (written by nbs)\nVERSION 0.7\nFIELDS x y z"
      << (nrm ? " normal_x normal_y normal_z" : "") << (rgb ? " rgb" : "") << "\nSIZE 8 8 8" << (nrm ? " 8 8 8" : "")
      << (rgb ? " 4" : "") << "\nTYPE F F F" << (nrm ? " F F F" : "") << (rgb ? " F" : "") << "\nCOUNT 1 1 1"
      << (nrm ? " 1 1 1" : "") << (rgb ? " 1" : "") << "\nWIDTH " << cloud.size() << "\nHEIGHT 1\nVIEWPOINT";
  const Pose vp = cloud.viewpoint.value_or(Pose::Identity());
  const Eigen::Quaterniond q(vp.linear());
  out << ' ' << vp.translation().x() << ' ' << vp.translation().y() << ' ' << vp.translation().z() << ' ' << q.w()
      << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << "\nPOINTS " << cloud.size() << "\nDATA "
      << (format == PcdFormat::ascii ? "ascii" : "binary") << '\n';
  const auto packed = [&](std::size_t i) {
    const Rgb& c = cloud.colors[i];
    return (std::uint32_t{c[0]} << 16) | (std::uint32_t{c[1]} << 8) | std::uint32_t{c[2]};
  };
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (format == PcdFormat::ascii) {
      out << cloud.points[i].x() << ' ' << cloud.points[i].y() << ' ' << cloud.points[i].z();
      if (nrm) out << ' ' << cloud.normals[i].x() << ' ' << cloud.normals[i].y() << ' ' << cloud.normals[i].z();
      if (rgb) out << ' ' << packed(i);  // the packed value as an unsigned integer, as PCL writes it
      out << '\n';
      continue;
    }
    out.write(reinterpret_cast<const char*>(cloud.points[i].data()), 24);
    if (nrm) out.write(reinterpret_cast<const char*>(cloud.normals[i].data()), 24);
    if (rgb) {
      const std::uint32_t v = packed(i);
      out.write(reinterpret_cast<const char*>(&v), 4);
    }
  }
  io_detail::write_file_atomic(path, std::move(out).str());
}

}  // namespace nbs
