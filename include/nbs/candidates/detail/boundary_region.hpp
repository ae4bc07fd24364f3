// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Boundary region V_B (Sec. 4.2.2): region growing from c_b (Eq. 4.4) inside a box in the last sensor frame,
/// and the Eq. (4.11) weights.

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "nbs/candidates/detail/mesh_topology.hpp"
#include "nbs/candidates/quadratic_patch.hpp"
#include "nbs/mesh/boundaries.hpp"

namespace nbs::detail {

/// Axes of a boundary in the last sensor frame S (boundaries.hpp convention): `along` is the sensor axis s of
/// Tab. 4.1 (1 = y for left/right, 0 = x for top/bottom), `trend` the other one, `sign` the step direction of
/// Tab. 4.2 along `trend` (+1 left/top, −1 right/bottom: towards the unknown side).
struct BoundaryAxes {
  int along = 1;
  int trend = 0;
  double sign = 1.0;
};

[[nodiscard]] inline BoundaryAxes boundary_axes(BoundaryType t) {
  switch (t) {
    case BoundaryType::left: return {1, 0, 1.0};
    case BoundaryType::right: return {1, 0, -1.0};
    case BoundaryType::top: return {0, 1, 1.0};
    case BoundaryType::bottom: return {0, 1, -1.0};
  }
  return {};
}

/// Centre vertex c_b, Eq. (4.4): v_b of edge e_{(m+1)/2} (m odd) or e_{m/2} (m even), 1-based. Requires m ≥ 1.
[[nodiscard]] inline VertexId boundary_center_vertex(const Boundary& b) {
  const std::size_t m = b.edges.size();
  const std::size_t k = (m % 2 == 1) ? (m + 1) / 2 : m / 2;
  return b.edges[k - 1][1];
}

/// Axis-aligned box in the sensor frame S.
struct SensorBox {
  Vec3 lo = Vec3::Constant(-std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(std::numeric_limits<double>::infinity());
  [[nodiscard]] bool contains(const Vec3& q) const {
    return (q.array() >= lo.array()).all() && (q.array() <= hi.array()).all();
  }
};

/// The Sec. 4.2.2 box: along s from the first to the last boundary vertex (e_1→v_a, e_m→v_b); along the trend axis
/// from the boundary inwards by `fraction` of the mesh extent `extent_trend_m` in that axis; `tol_m` of slack on the
/// other sides for noise. z unbounded. `q_*` are sensor-frame coordinates.
[[nodiscard]] inline SensorBox boundary_box(const std::vector<Vec3>& q_boundary, const BoundaryAxes& ax,
                                           double extent_trend_m, double fraction, double tol_m) {
  SensorBox box;
  const double a0 = q_boundary.front()[ax.along], a1 = q_boundary.back()[ax.along];
  box.lo[ax.along] = std::min(a0, a1) - tol_m;
  box.hi[ax.along] = std::max(a0, a1) + tol_m;
  double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
  for (const Vec3& q : q_boundary) tmin = std::min(tmin, q[ax.trend]), tmax = std::max(tmax, q[ax.trend]);
  const double inward = fraction * extent_trend_m;
  box.lo[ax.trend] = ax.sign > 0 ? tmin - inward : tmin - tol_m;
  box.hi[ax.trend] = ax.sign > 0 ? tmax + tol_m : tmax + inward;
  return box;
}

/// Breadth-first region growing from `seed` over mesh edges, keeping triangulated vertices whose sensor-frame
/// position T_SW·v lies in `box`. The seed is always included. Deterministic (neighbour order of the topology).
template <EdgeMesh M>
[[nodiscard]] std::vector<VertexId> grow_region(const M& mesh, const MeshTopology& topo, const Pose& t_sw,
                                                VertexId seed, const SensorBox& box) {
  std::vector<VertexId> region{seed};
  std::vector<char> seen(mesh.vertex_count(), 0);
  seen[seed] = 1;
  for (std::size_t i = 0; i < region.size(); ++i) {
    const VertexId v = region[i];
    for (std::uint32_t k = topo.offset[v]; k < topo.offset[v + 1]; ++k) {
      const VertexId w = topo.neighbours[k];
      if (seen[w]) continue;
      seen[w] = 1;
      if (topo.triangulated[w] && box.contains(t_sw * Vec3(mesh.position(w)))) region.push_back(w);
    }
  }
  return region;
}

/// Eq. (4.11) weights of `region` (world positions), with the exact distance to the nearest boundary vertex. The
/// boundary vertices are sorted along the axis of their largest extent and cut into runs of kRun with their boxes;
/// a run is skipped when the squared distance to its box exceeds the best squared distance so far by a relative
/// 1e-9 (far more than the rounding of either sum), so every skipped vertex's computed squared distance is larger
/// than the minimum and the minimum is that of the brute-force scan over all pairs, bit for bit.
template <EdgeMesh M>
[[nodiscard]] std::vector<double> region_weights(const M& mesh, const std::vector<VertexId>& region,
                                                 const std::vector<VertexId>& boundary, double scale_m) {
  constexpr std::size_t kRun = 8;
  std::vector<Vec3> b;
  b.reserve(boundary.size());
  Aabb extent;
  for (VertexId v : boundary) {
    b.push_back(mesh.position(v));
    extent.extend(b.back());
  }
  int axis = 0;
  if (!b.empty()) extent.extent().maxCoeff(&axis);
  std::sort(b.begin(), b.end(), [axis](const Vec3& l, const Vec3& r) { return l[axis] < r[axis]; });
  std::vector<Aabb> runs((b.size() + kRun - 1) / kRun);
  for (std::size_t i = 0; i < b.size(); ++i) runs[i / kRun].extend(b[i]);
  std::vector<double> w;
  w.reserve(region.size());
  if (b.empty()) {  // as the brute-force scan: the distance is infinite (boundary_distance_weight rejects it)
    for (std::size_t i = 0; i < region.size(); ++i)
      w.push_back(boundary_distance_weight(std::numeric_limits<double>::infinity(), scale_m));
    return w;
  }
  for (VertexId v : region) {
    double d2 = std::numeric_limits<double>::infinity();
    const Vec3 p = mesh.position(v);
    const auto scan = [&](std::size_t r) {
      const std::size_t end = std::min(b.size(), (r + 1) * kRun);
      for (std::size_t i = r * kRun; i < end; ++i) d2 = std::min(d2, (b[i] - p).squaredNorm());
    };
    // First the run at p's coordinate along the axis (a good first d2), then every other run not skipped.
    const auto at =
        std::lower_bound(b.begin(), b.end(), p[axis], [axis](const Vec3& q, double c) { return q[axis] < c; });
    const std::size_t first = std::min<std::size_t>(static_cast<std::size_t>(at - b.begin()), b.size() - 1) / kRun;
    scan(first);
    for (std::size_t r = 0; r < runs.size(); ++r) {
      if (r == first) continue;
      const Vec3 gap = (runs[r].min - p).cwiseMax(p - runs[r].max).cwiseMax(0.0);
      if (!(gap.squaredNorm() > d2 * (1.0 + 1e-9))) scan(r);
    }
    w.push_back(boundary_distance_weight(std::sqrt(d2), scale_m));
  }
  return w;
}

}  // namespace nbs::detail
