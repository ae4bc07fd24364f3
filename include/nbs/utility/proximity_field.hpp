// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// ProximityField: for unobserved voxels near the observed surface, the distance d(x) to the nearest occupied voxel
/// (voxel centres, metres), up to d_max. Used by the proximity-count and Vasquez-Gomez terms (peer_terms.hpp).
///
/// Adapter note: the reference implementation of Delmerico et al. (2018) stores d(x) in the map while integrating,
/// marking voxels behind each measured end point along the beam up to d_max. nbs's space does not keep that, so
/// the field is derived from the current space instead: every unobserved voxel whose centre lies within d_max of an
/// occupied voxel's centre (Euclidean). Unobserved voxels next to an observed surface are those behind or beside
/// it, so both readings mark the same region up to its shape.

#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs {

/// Read-only after `build`; concurrent const calls are safe.
class ProximityField {
public:
  ProximityField() = default;

  /// Builds the field of `space` (a ProbabilisticVoxelSpace or anything with resolution_m(), for_each(f(key,
  /// state)), observed(key) and model().occupied(state)). d_max_m > 0 and at most 16 voxels.
  template <class Space>
  [[nodiscard]] static ProximityField build(const Space& space, double d_max_m) {
    detail::require_positive("ProximityField d_max_m", d_max_m);
    const double l = space.resolution_m();
    const int r = static_cast<int>(std::floor(d_max_m / l));
    detail::require(r <= 16, "ProximityField: d_max_m (", d_max_m, ") must be at most 16 voxels (", 16 * l, ")");
    ProximityField f;
    f.d_max_m_ = d_max_m;
    struct Offset {
      int dx, dy, dz;
      float d;
    };
    std::vector<Offset> offsets;
    for (int dz = -r; dz <= r; ++dz)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const double d = l * std::sqrt(double(dx * dx + dy * dy + dz * dz));
          if ((dx | dy | dz) != 0 && d <= d_max_m) offsets.push_back({dx, dy, dz, static_cast<float>(d)});
        }
    space.for_each([&](const VoxelKey& k, const auto& state) {
      if (!space.model().occupied(state)) return;
      for (const Offset& o : offsets) {
        const VoxelKey n{k.x + o.dx, k.y + o.dy, k.z + o.dz};
        if (!n.valid() || space.observed(n)) continue;
        auto [it, inserted] = f.distance_.try_emplace(n.pack(), o.d);
        if (!inserted && o.d < it->second) it->second = o.d;
      }
    });
    return f;
  }

  /// d(x) in metres, or a negative value if x is not in the field (observed, or farther than d_max).
  [[nodiscard]] double distance_m(const VoxelKey& k) const {
    const auto it = distance_.find(k.pack());
    return it == distance_.end() ? -1.0 : static_cast<double>(it->second);
  }
  [[nodiscard]] double d_max_m() const { return d_max_m_; }
  [[nodiscard]] std::size_t size() const { return distance_.size(); }

private:
  double d_max_m_ = 0.0;
  std::unordered_map<std::uint64_t, float> distance_;
};

}  // namespace nbs
