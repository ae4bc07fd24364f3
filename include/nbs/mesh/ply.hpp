// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// PLY export of a mesh: vertices (double x y z), normals (double nx ny nz), colours when present (uchar red green
/// blue), faces (list uchar uint).

#include <cstdint>
#include <string>

#include "nbs/core/error.hpp"
#include "nbs/io/ply_writer.hpp"
#include "nbs/mesh/conversion.hpp"

namespace nbs {

/// Writes `mesh` (an IndexedMesh; normals written when present, else zero; uchar `red green blue` when it has
/// colours) as PLY, binary little-endian unless `ascii`. The file appears complete or not at all (PlyWriter). Throws InvalidArgument if the mesh is invalid,
/// FileError if the file cannot be written.
inline void write_mesh_ply(const std::string& path, const IndexedMesh& mesh, bool ascii = false) {
  mesh.validate();
  PlyWriter w(path, ascii ? PlyFormat::ascii : PlyFormat::binary_little_endian);
  w.comment("written by nbs mesh");
  w.element("vertex", mesh.vertices.size());
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz"}) w.property(PlyType::f64, name);
  const bool colored = !mesh.colors.empty();
  if (colored)
    for (const char* name : {"red", "green", "blue"}) w.property(PlyType::u8, name);
  w.element("face", mesh.triangles.size());
  w.list_property(PlyType::u8, PlyType::u32, "vertex_indices");
  w.end_header();
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& p = mesh.vertices[i];
    const Vec3 n = mesh.normals.empty() ? Vec3::Zero() : mesh.normals[i];
    for (int k = 0; k < 3; ++k) w.value(p[k]);
    for (int k = 0; k < 3; ++k) w.value(n[k]);
    if (colored)
      for (std::uint8_t c : mesh.colors[i]) w.value(c);
    w.end_record();
  }
  for (const auto& t : mesh.triangles) {
    w.value(std::uint8_t{3});
    for (std::uint32_t i : t) w.value(i);
    w.end_record();
  }
  w.finish();
}

/// Writes any EdgeMesh (its triangulated part, see to_indexed_mesh; a ColoredMesh with its colours) as PLY.
template <EdgeMesh M>
void write_mesh_ply(const std::string& path, const M& mesh, bool ascii = false) {
  write_mesh_ply(path, to_indexed_mesh(mesh), ascii);
}

}  // namespace nbs
