// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Export of the voxel space as a PLY point set: one vertex per voxel centre with its occupancy probability p and
/// a grey level 255·p (black = free, grey = unknown, white = occupied, as in the thesis figures).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/io/ply_writer.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace nbs {

struct PlyExportSetting {
  /// Also write the never-observed voxels (p = 0.5) inside the space's bounds. Throws if that would exceed
  /// max_voxels.
  bool include_unknown = false;
  std::uint64_t max_voxels = 50'000'000;
};

/// Writes `space` to `path` as binary little-endian PLY (x y z float metres, red green blue uchar, p float).
/// Writes a temporary file next to `path` and renames it into place (PlyWriter), so a failed write leaves `path`
/// untouched.
/// Returns the number of voxels written. Throws FileError on I/O failure, InvalidArgument if the voxel count
/// exceeds setting.max_voxels.
template <class B, class M>
std::uint64_t write_voxels_ply(const ProbabilisticVoxelSpace<B, M>& space, const std::filesystem::path& path,
                               const PlyExportSetting& setting = {}) {
  struct Rec {
    float x, y, z;
    std::uint8_t r, g, b;
    float p;
  };
  std::vector<Rec> recs;
  const auto add = [&](const VoxelKey& k, double p) {
    const Vec3 c = space.grid().center(k);
    const auto grey = static_cast<std::uint8_t>(std::lround(std::clamp(p, 0.0, 1.0) * 255.0));
    recs.push_back({static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()), grey, grey,
                    grey, static_cast<float>(p)});
  };
  if (setting.include_unknown) {
    const KeyBox kb = space.bounds_keys();
    detail::require(kb.volume() <= setting.max_voxels, "write_voxels_ply: ", kb.volume(),
                    " voxels in the bounds exceed max_voxels = ", setting.max_voxels);
    for (std::int32_t z = kb.min.z; z <= kb.max.z; ++z)
      for (std::int32_t y = kb.min.y; y <= kb.max.y; ++y)
        for (std::int32_t x = kb.min.x; x <= kb.max.x; ++x) add({x, y, z}, space.probability(VoxelKey{x, y, z}));
  } else {
    detail::require(observed_count(space.backend()) <= setting.max_voxels, "write_voxels_ply: too many voxels");
    space.for_each([&](const VoxelKey& k, const auto& s) { add(k, space.model().probability(s)); });
  }
  std::ostringstream comment;  // the edge length with the stream's default 6 significant digits
  comment << "nbs probabilistic voxel space, edge " << space.resolution_m() << " m";
  PlyWriter w(path, PlyFormat::binary_little_endian);
  w.comment(comment.str());
  w.element("vertex", recs.size());
  for (const char* name : {"x", "y", "z"}) w.property(PlyType::f32, name);
  for (const char* name : {"red", "green", "blue"}) w.property(PlyType::u8, name);
  w.property(PlyType::f32, "p");
  w.end_header();
  for (const Rec& r : recs) {
    w.value(r.x), w.value(r.y), w.value(r.z);
    w.value(r.r), w.value(r.g), w.value(r.b);
    w.value(r.p);
    w.end_record();
  }
  w.finish();
  return recs.size();
}

}  // namespace nbs
