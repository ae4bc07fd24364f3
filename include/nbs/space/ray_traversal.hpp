// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Voxels crossed by a segment (exact integer 3D-DDA, see detail/segment_walker.hpp).

#include <type_traits>

#include "nbs/core/error.hpp"
#include "nbs/space/detail/segment_walker.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs {

/// Calls f(key) for every voxel of `grid` crossed by the segment from → to (world metres), in order, from the voxel
/// containing `from` to the voxel containing `to`, both included; each voxel once. End points are quantised to
/// 1/1024 voxel. If f returns bool, false stops the traversal. Returns the number of voxels visited.
/// Throws InvalidArgument if an end point is not finite or outside the grid's key range.
template <class F>
std::size_t traverse_segment(const VoxelGrid& grid, const Vec3& from, const Vec3& to, F&& f) {
  detail::require(grid.key_of(from).has_value(), "traverse_segment: start (", from.transpose(),
                  ") is not finite or outside the key range");
  detail::require(grid.key_of(to).has_value(), "traverse_segment: end (", to.transpose(),
                  ") is not finite or outside the key range");
  detail::SegmentWalker w(from * grid.inverse_resolution(), to * grid.inverse_resolution());
  std::size_t n = 0;
  for (;;) {
    ++n;
    if constexpr (std::is_convertible_v<std::invoke_result_t<F&, const VoxelKey&>, bool>) {
      if (!f(w.key())) return n;
    } else {
      f(w.key());
    }
    if (w.remaining() == 0) return n;
    w.step();
  }
}

}  // namespace nbs
