// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// A triangle mesh moved rigidly (a model placed in a scene, turned over, or brought into another frame).

#include "nbs/core/types.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

/// A copy of `mesh` moved by `T` (vertices T·v, normals R·n; triangles and colours unchanged). Throws
/// InvalidArgument if T is not finite and rigid.
[[nodiscard]] inline IndexedMesh transformed_mesh(const IndexedMesh& mesh, const Pose& T) {
  validate_pose(T, "transformed_mesh: T");
  IndexedMesh out = mesh;
  for (Vec3& v : out.vertices) v = T * v;
  for (Vec3& n : out.normals) n = T.linear() * n;
  return out;
}

}  // namespace nbs
