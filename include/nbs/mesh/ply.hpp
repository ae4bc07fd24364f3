#pragma once
/// \file
/// PLY export of a mesh: vertices (double x y z), normals (double nx ny nz), faces (list uchar uint).

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include "nbs/core/error.hpp"
#include "nbs/mesh/conversion.hpp"

namespace nbs {

/// Writes `mesh` (an IndexedMesh; normals written when present, else zero) as PLY, binary little-endian unless
/// `ascii`. Throws InvalidArgument if the mesh is invalid, FileError if the file cannot be written.
inline void write_mesh_ply(const std::string& path, const IndexedMesh& mesh, bool ascii = false) {
  mesh.validate();
  std::ofstream out(path, std::ios::binary);
  if (!out) throw FileError(detail::concat(path, ": cannot open file for writing"));
  out.precision(17);
  out << "ply\nformat " << (ascii ? "ascii" : "binary_little_endian") << " 1.0\ncomment written by nbs mesh\n"
      << "element vertex " << mesh.vertices.size() << "\n"
      << "property double x\nproperty double y\nproperty double z\n"
      << "property double nx\nproperty double ny\nproperty double nz\n"
      << "element face " << mesh.triangles.size() << "\nproperty list uchar uint vertex_indices\nend_header\n";
  auto put = [&](const auto& value) {  // little-endian raw bytes (every platform nbs supports is little-endian)
    static_assert(std::endian::native == std::endian::little);
    char b[sizeof(value)];
    std::memcpy(b, &value, sizeof(value));
    out.write(b, sizeof(value));
  };
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& p = mesh.vertices[i];
    const Vec3 n = mesh.normals.empty() ? Vec3::Zero() : mesh.normals[i];
    if (ascii) {
      out << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << n.x() << ' ' << n.y() << ' ' << n.z() << '\n';
    } else {
      for (int k = 0; k < 3; ++k) put(p[k]);
      for (int k = 0; k < 3; ++k) put(n[k]);
    }
  }
  for (const auto& t : mesh.triangles) {
    if (ascii) {
      out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    } else {
      put(std::uint8_t{3});
      for (std::uint32_t i : t) put(i);
    }
  }
  out.close();
  if (!out) throw FileError(detail::concat(path, ": write failed"));
}

/// Writes any EdgeMesh (its triangulated part, see to_indexed_mesh) as PLY.
template <EdgeMesh M>
void write_mesh_ply(const std::string& path, const M& mesh, bool ascii = false) {
  write_mesh_ply(path, to_indexed_mesh(mesh), ascii);
}

}  // namespace nbs
