// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Wavefront OBJ reader (tinyobjloader, double precision; materials are ignored).

#include <tiny_obj_loader.h>

#include <sstream>
#include <string>
#include <vector>

#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/io/detail/finish_mesh.hpp"
#include "nbs/io/detail/obj_check.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

/// Reads the vertices and faces of an OBJ file; polygons are triangulated by tinyobjloader, all groups are
/// merged, normals/texture coordinates/materials are ignored. Throws FileError naming the file and the problem
/// and, for text errors, the line (cannot open, a coordinate that is not a finite number, a face index that is not
/// an integer or out of range, no triangle). Nothing is returned on failure.
[[nodiscard]] inline IndexedMesh read_obj(const std::string& path);

/// read_obj of a file's contents held in memory: `bytes` is the whole file, `path` names it in the messages.
/// The same checks and errors as read_obj.
[[nodiscard]] inline IndexedMesh read_obj_bytes(const std::string& path, std::string bytes) {
  io_detail::check_obj_text(path, bytes);
  std::istringstream text(std::move(bytes));
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &text, /*readMatFn=*/nullptr,
                                   /*triangulate=*/true);
  if (!ok) throw FileError(detail::concat(path, ": not a readable OBJ file: ", err));
  IndexedMesh mesh;
  const std::size_t nv = attrib.vertices.size() / 3;
  mesh.vertices.reserve(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const Vec3 v(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    if (!v.allFinite()) throw FileError(detail::concat(path, ": vertex ", i + 1, " is not finite"));
    mesh.vertices.push_back(v);
  }
  for (const auto& shape : shapes) {
    std::size_t offset = 0;
    for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      const std::size_t n = shape.mesh.num_face_vertices[f];
      if (n != 3)
        throw FileError(detail::concat(path, ": shape '", shape.name, "' face ", f, " has ", n,
                                       " vertices after triangulation"));
      IndexedMesh::Triangle t{};
      for (std::size_t k = 0; k < 3; ++k) {
        const int idx = shape.mesh.indices[offset + k].vertex_index;
        if (idx < 0 || static_cast<std::size_t>(idx) >= nv)
          throw FileError(detail::concat(path, ": shape '", shape.name, "' face ", f, " refers to vertex ", idx,
                                         " but the file has ", nv, " vertices"));
        t[k] = static_cast<std::uint32_t>(idx);
      }
      mesh.triangles.push_back(t);
      offset += n;
    }
  }
  return detail::finish_mesh(path, std::move(mesh));
}

inline IndexedMesh read_obj(const std::string& path) { return read_obj_bytes(path, io_detail::read_file_bytes(path)); }

}  // namespace nbs
