// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The collision model (nbs/workspace/collision_model.hpp) as an `octomap::OcTree` and as an OctoMap file (`.bt`
/// binary, `.ot` full) for FCL / MoveIt-style consumers. Only the model's voxels become leaves (occupied); all other
/// space is unknown to the tree (no free leaves), which such consumers treat as collision-free. Export a model
/// built with CollisionModelSetting::remove_inner = false: a hollow model leaves the obstacles' interiors unknown (a
/// body entirely inside an obstacle would not collide), and full interiors prune into large leaves anyway.

#include <octomap/OcTree.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "nbs/core/error.hpp"
#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/octomap/octree_backend.hpp"
#include "nbs/workspace/collision_model.hpp"

namespace nbs::octomap {

/// Tree of the model (same resolution): one occupied leaf (log-odds of 0.971, OctoMap's default upper clamping)
/// per voxel, inner nodes updated, pruned (8 occupied siblings merge into one leaf). Throws InvalidArgument if the
/// resolution is not positive or a voxel lies outside OctoMap's key range (±2^15 voxels), naming it.
[[nodiscard]] inline std::unique_ptr<::octomap::OcTree> to_collision_octree(const CollisionModel& model) {
  detail::require_positive("to_collision_octree: resolution_m", model.resolution_m);
  auto tree = std::make_unique<::octomap::OcTree>(model.resolution_m);
  const float occ = LogOddsModel::logodds(0.971);
  for (const VoxelKey& k : model.voxels) {
    const auto o = to_octree_key(k);
    detail::require(o.has_value(), "to_collision_octree: voxel (", k.x, ", ", k.y, ", ", k.z,
                    ") is outside OctoMap's key range [-32768, 32767]");
    tree->setNodeValue(*o, occ, true);
  }
  tree->updateInnerOccupancy();
  tree->prune();
  return tree;
}

/// Writes the model's tree to `path`: `.bt` → OctoMap binary (occupancy bits, writeBinary), `.ot` → full tree
/// (log-odds, write); the extension is compared case-insensitively. The file is written to `<path>.tmp` beside it
/// and renamed into place, so `path` is never half-written. Throws InvalidArgument (nothing written) for another
/// extension or a model to_collision_octree rejects, FileError naming the file if it cannot be written.
inline void write_collision_octree(const CollisionModel& model, const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  detail::require(ext == ".bt" || ext == ".ot", "write_collision_octree: ", path.string(),
                  ": extension must be .bt (binary) or .ot (full), got '", ext, "'");
  const auto tree = to_collision_octree(model);
  std::ostringstream bytes(std::ios::binary);
  const bool ok = ext == ".bt" ? tree->writeBinary(bytes) : tree->write(bytes);
  if (!ok) throw FileError(detail::concat(path.string(), ": OctoMap could not serialise the tree"));
  io_detail::write_file_atomic(path.string(), bytes.view());
}

}  // namespace nbs::octomap
