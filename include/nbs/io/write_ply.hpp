// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// PLY writers for point clouds (optional normals and colours) and indexed triangle meshes (on PlyWriter: the
/// file appears complete or not at all).

#include <cstdint>
#include <span>
#include <string>

#include "nbs/io/color.hpp"
#include "nbs/io/detail/ply_header.hpp"
#include "nbs/io/ply_writer.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

/// Writes a point cloud: `vertex` element with double x y z, plus nx ny nz if `normals` is non-empty and
/// uchar red green blue if `colors` is non-empty (each must then have points.size() entries).
/// Throws InvalidArgument on size mismatch, FileError if the file cannot be written.
inline void write_ply_points(const std::string& path, std::span<const Vec3> points, std::span<const Vec3> normals = {},
                             std::span<const Rgb> colors = {}, PlyFormat format = PlyFormat::binary_little_endian) {
  detail::require(normals.empty() || normals.size() == points.size(), "write_ply_points: ", normals.size(),
                  " normals for ", points.size(), " points");
  detail::require(colors.empty() || colors.size() == points.size(), "write_ply_points: ", colors.size(),
                  " colours for ", points.size(), " points");
  PlyWriter w(path, format);
  w.comment("written by nbs");
  w.element("vertex", points.size());
  for (const char* name : {"x", "y", "z"}) w.property(PlyType::f64, name);
  if (!normals.empty())
    for (const char* name : {"nx", "ny", "nz"}) w.property(PlyType::f64, name);
  if (!colors.empty())
    for (const char* name : {"red", "green", "blue"}) w.property(PlyType::u8, name);
  w.end_header();
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) w.value(points[i][k]);
    if (!normals.empty())
      for (int k = 0; k < 3; ++k) w.value(normals[i][k]);
    if (!colors.empty())
      for (std::uint8_t c : colors[i]) w.value(c);
    w.end_record();
  }
  w.finish();
}

/// Writes an indexed triangle mesh (double x y z, uchar red green blue if the mesh has colours; faces as
/// `list uchar uint vertex_indices`).
/// Throws InvalidArgument if the mesh violates its invariants, FileError if the file cannot be written.
inline void write_ply(const std::string& path, const IndexedMesh& mesh,
                      PlyFormat format = PlyFormat::binary_little_endian) {
  mesh.validate();
  PlyWriter w(path, format);
  w.comment("written by nbs");
  w.element("vertex", mesh.vertices.size());
  for (const char* name : {"x", "y", "z"}) w.property(PlyType::f64, name);
  if (!mesh.colors.empty())
    for (const char* name : {"red", "green", "blue"}) w.property(PlyType::u8, name);
  w.element("face", mesh.triangles.size());
  w.list_property(PlyType::u8, PlyType::u32, "vertex_indices");
  w.end_header();
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) w.value(mesh.vertices[i][k]);
    if (!mesh.colors.empty())
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

}  // namespace nbs
