#pragma once
/// \file
/// PLY writers for point clouds (optional normals and colours) and indexed triangle meshes.

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <span>
#include <string>

#include "nbs/io/color.hpp"
#include "nbs/io/detail/ply_header.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

namespace io_detail {

/// Writes PLY body values in one encoding; coordinates as float64 (`double`) so nothing is lost.
class PlyWriter {
public:
  PlyWriter(const std::string& path, PlyFormat format) : path_(path), format_(format), out_(path, std::ios::binary) {
    if (!out_) throw FileError(detail::concat(path, ": cannot open file for writing"));
    out_.precision(17);
    out_ << "ply\nformat "
         << (format == PlyFormat::ascii                  ? "ascii"
             : format == PlyFormat::binary_little_endian ? "binary_little_endian"
                                                         : "binary_big_endian")
         << " 1.0\ncomment written by nbs\n";
  }
  std::ofstream& header() { return out_; }

  void real(double v) { value(std::bit_cast<std::uint64_t>(v), v); }
  void u8(std::uint8_t v) { value(v, static_cast<unsigned>(v)); }
  void u32(std::uint32_t v) { value(v, v); }
  void end_record() {
    if (format_ == PlyFormat::ascii) out_ << '\n';
    first_ = true;
  }
  void close() {
    out_.close();
    if (!out_) throw FileError(detail::concat(path_, ": write failed"));
  }

private:
  template <class U, class Text>
  void value(U bits, Text text) {
    if (format_ == PlyFormat::ascii) {
      if (!first_) out_ << ' ';
      out_ << text;
      first_ = false;
      return;
    }
    const bool little = format_ == PlyFormat::binary_little_endian;
    char b[sizeof(U)];
    for (std::size_t i = 0; i < sizeof(U); ++i) {
      const std::size_t shift = 8 * (little ? i : sizeof(U) - 1 - i);
      b[i] = static_cast<char>((bits >> shift) & 0xFFu);
    }
    out_.write(b, sizeof(U));
  }

  std::string path_;
  PlyFormat format_;
  std::ofstream out_;
  bool first_ = true;
};

}  // namespace io_detail

/// Writes a point cloud: `vertex` element with double x y z, plus nx ny nz if `normals` is non-empty and
/// uchar red green blue if `colors` is non-empty (each must then have points.size() entries).
/// Throws InvalidArgument on size mismatch, FileError if the file cannot be written.
inline void write_ply_points(const std::string& path, std::span<const Vec3> points, std::span<const Vec3> normals = {},
                             std::span<const Rgb> colors = {}, PlyFormat format = PlyFormat::binary_little_endian) {
  detail::require(normals.empty() || normals.size() == points.size(), "write_ply_points: ", normals.size(),
                  " normals for ", points.size(), " points");
  detail::require(colors.empty() || colors.size() == points.size(), "write_ply_points: ", colors.size(),
                  " colours for ", points.size(), " points");
  io_detail::PlyWriter w(path, format);
  w.header() << "element vertex " << points.size() << "\nproperty double x\nproperty double y\nproperty double z\n";
  if (!normals.empty()) w.header() << "property double nx\nproperty double ny\nproperty double nz\n";
  if (!colors.empty()) w.header() << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  w.header() << "end_header\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) w.real(points[i][k]);
    if (!normals.empty())
      for (int k = 0; k < 3; ++k) w.real(normals[i][k]);
    if (!colors.empty())
      for (std::uint8_t c : colors[i]) w.u8(c);
    w.end_record();
  }
  w.close();
}

/// Writes an indexed triangle mesh (double x y z; faces as `list uchar uint vertex_indices`).
/// Throws InvalidArgument if the mesh violates its invariants, FileError if the file cannot be written.
inline void write_ply(const std::string& path, const IndexedMesh& mesh,
                      PlyFormat format = PlyFormat::binary_little_endian) {
  mesh.validate();
  io_detail::PlyWriter w(path, format);
  w.header() << "element vertex " << mesh.vertices.size()
             << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << mesh.triangles.size()
             << "\nproperty list uchar uint vertex_indices\nend_header\n";
  for (const Vec3& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) w.real(v[k]);
    w.end_record();
  }
  for (const auto& t : mesh.triangles) {
    w.u8(3);
    for (std::uint32_t i : t) w.u32(i);
    w.end_record();
  }
  w.close();
}

}  // namespace nbs
