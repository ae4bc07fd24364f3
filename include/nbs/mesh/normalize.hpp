// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Places a ground-truth mesh on the pedestal (Sec. 4.7): scaled, centred, standing on z = 0.

#include "nbs/core/error.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

/// Which axis of a mesh file points up. Scanned models often use y (e.g. the Stanford bunny OBJ); nbs uses z.
enum class UpAxis { x, y, z };

/// Rotation mapping the mesh's `up` axis onto world +z (a proper rotation; identity for UpAxis::z).
/// y-up: (x, y, z) ↦ (x, −z, y), a rotation of +90° about x. x-up: (x, y, z) ↦ (−z, y, x), −90° about y.
[[nodiscard]] inline Mat3 up_axis_to_z(UpAxis up) {
  Mat3 r = Mat3::Identity();
  if (up == UpAxis::y) r << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  if (up == UpAxis::x) r << 0, 0, -1, 0, 1, 0, 1, 0, 0;
  return r;
}

/// Normalises `mesh` in place for the simulation (Sec. 4.7): rotates `up_axis` (default z: the mesh is already
/// z-up) onto +z, scales uniformly so that the largest extent of the bounding box is `object_size_m` (metres;
/// default 0.16 m, the benchmark object size), then translates so that the box is centred on x = y = 0 with its
/// bottom (min z) at z = 0, the pedestal top. Only vertices referenced by triangles define the box.
/// Throws InvalidArgument (mesh unchanged) for an invalid mesh or a non-positive size.
inline void normalize_on_pedestal(IndexedMesh& mesh, double object_size_m = 0.16, UpAxis up_axis = UpAxis::z) {
  detail::require_positive("object_size_m", object_size_m);
  mesh.validate();
  const Mat3 r = up_axis_to_z(up_axis);
  for (auto& v : mesh.vertices) v = r * v;
  const Aabb box = mesh.bounds();
  const double scale = object_size_m / box.extent().maxCoeff();  // > 0: validate() ensures a non-zero area
  const Vec3 anchor(box.center().x(), box.center().y(), box.min.z());
  for (auto& v : mesh.vertices) v = scale * (v - anchor);
}

}  // namespace nbs
