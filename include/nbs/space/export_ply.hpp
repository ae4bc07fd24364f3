#pragma once
/// \file
/// Export of the voxel space as a PLY point set: one vertex per voxel centre with its occupancy probability p and
/// a grey level 255·p (black = free, grey = unknown, white = occupied, as in the thesis figures).

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace nbs {

struct PlyExportSetting {
  /// Also write the never-observed voxels (p = 0.5) inside the space's bounds. Throws if that would exceed
  /// max_voxels.
  bool include_unknown = false;
  std::uint64_t max_voxels = 50'000'000;
};

/// Writes `space` to `path` as binary little-endian PLY (x y z float metres, red green blue uchar, p float).
/// Writes a temporary file next to `path` and renames it into place, so a failed write leaves `path` untouched.
/// Returns the number of voxels written. Throws FileError on I/O failure, InvalidArgument if the voxel count
/// exceeds setting.max_voxels.
template <class B, class M>
std::uint64_t write_voxels_ply(const ProbabilisticVoxelSpace<B, M>& space, const std::filesystem::path& path,
                               const PlyExportSetting& setting = {}) {
  static_assert(std::endian::native == std::endian::little, "PLY writer assumes a little-endian host");
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
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw FileError(detail::concat("write_voxels_ply: cannot open ", tmp.string()));
    out << "ply\nformat binary_little_endian 1.0\ncomment nbs probabilistic voxel space, edge "
        << space.resolution_m() << " m\nelement vertex " << recs.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
           "property uchar blue\nproperty float p\nend_header\n";
    for (const Rec& r : recs) {
      out.write(reinterpret_cast<const char*>(&r.x), 12);
      out.write(reinterpret_cast<const char*>(&r.r), 3);
      out.write(reinterpret_cast<const char*>(&r.p), 4);
    }
    out.flush();
    if (!out) {
      out.close();
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw FileError(detail::concat("write_voxels_ply: write to ", tmp.string(), " failed"));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw FileError(detail::concat("write_voxels_ply: cannot rename to ", path.string()));
  }
  return recs.size();
}

}  // namespace nbs
