// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The last step of every mesh reader: IndexedMesh::validate(), its InvalidArgument reported as a FileError that
/// names the file.

#include <string>
#include <utility>

#include "nbs/core/error.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs::detail {

/// Returns `mesh` if it is valid; otherwise throws FileError("<path>: <what is wrong>").
[[nodiscard]] inline IndexedMesh finish_mesh(const std::string& path, IndexedMesh&& mesh) {
  try {
    mesh.validate();
  } catch (const InvalidArgument& e) {
    throw FileError(concat(path, ": ", e.what()));
  }
  return std::move(mesh);
}

}  // namespace nbs::detail
