// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// PointCloud: points with optional per-point normals and colours, as the point-cloud readers return them.

#include <cstddef>
#include <optional>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/io/color.hpp"

namespace nbs {

/// Points (metres as stored, frame as the file's), optional normals and 8-bit colours.
/// Invariants (`validate()`): at least one point; every point and normal finite; `normals` and `colors` each empty
/// or of points.size().
struct PointCloud {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;  ///< empty, or one per point (as stored: not normalised)
  std::vector<Rgb> colors;    ///< empty, or one per point
  std::optional<Pose> viewpoint;  ///< the sensor pose in the cloud's frame, when the file states one (PCD VIEWPOINT)
  std::size_t dropped = 0;        ///< points the reader dropped as non-finite (only when asked to, PcdReadOptions)

  [[nodiscard]] std::size_t size() const { return points.size(); }
  [[nodiscard]] bool has_normals() const { return !normals.empty(); }
  [[nodiscard]] bool has_colors() const { return !colors.empty(); }

  /// Throws InvalidArgument naming the first violated invariant and the index.
  void validate() const {
    detail::require(!points.empty(), "point cloud has no points");
    detail::require(normals.empty() || normals.size() == points.size(), "point cloud has ", normals.size(),
                    " normals for ", points.size(), " points");
    detail::require(colors.empty() || colors.size() == points.size(), "point cloud has ", colors.size(),
                    " colours for ", points.size(), " points");
    for (std::size_t i = 0; i < points.size(); ++i)
      detail::require(points[i].allFinite(), "point ", i, " is not finite: (", points[i].transpose(), ")");
    for (std::size_t i = 0; i < normals.size(); ++i)
      detail::require(normals[i].allFinite(), "normal ", i, " is not finite: (", normals[i].transpose(), ")");
  }
};

}  // namespace nbs
