// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Surface Edge Explorer (SEE; Border & Gammell, IJRR 2024, arXiv 2207.13684) as a peer candidate generator: a
/// density classification of the measured points (core / frontier / outlier) and one view per frontier point at d_s
/// along the surface normal, sweeping across the frontier edge. nbs's reading of the public description, not SEE's
/// code; what is simplified is listed at SurfaceEdgeExplorer.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

#include "nbs/candidates/candidate_generator.hpp"
#include "nbs/candidates/detail/hole_direction.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"

namespace nbs {

/// SEE's class of a measured point (density with resolution r and neighbour target k).
enum class DensityClass : std::uint8_t {
  core,      ///< at least k other points within r: the surface is observed at the target density here
  frontier,  ///< not core, with at least one core and at least one non-core point within r: the observed edge
  outlier,   ///< neither: sparse, not next to observed surface
};

/// Classifies `points` (metres, any frame): n_i = number of points j ≠ i with ‖p_j − p_i‖ ≤ `radius_m`; core iff
/// n_i ≥ `min_neighbours`; a non-core point is frontier iff its r-ball holds a core and a non-core point, else
/// outlier (SEE's frontier: the border between the fully and the partially observed surface). SEE states the target
/// as a density ρ; here ρ = k / (4/3 π r³). Deterministic (kd-tree, nanoflann). Throws InvalidArgument naming the
/// value for r not finite and > 0, k < 1 or a non-finite point.
[[nodiscard]] inline std::vector<DensityClass> classify_density(std::span<const Vec3> points, double radius_m,
                                                                int min_neighbours);

namespace detail {
/// classify_density over `tree` (built on the points), parameters checked by the caller.
[[nodiscard]] inline std::vector<DensityClass> classify_density(const PointKdTree& tree, double radius_m,
                                                                int min_neighbours) {
  const std::size_t n = tree.size();
  std::vector<DensityClass> cls(n, DensityClass::outlier);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t count = 0;
    tree.for_each_within(tree.points()[i], radius_m, [&](std::size_t, double) { ++count; });
    if (count - 1 >= static_cast<std::size_t>(min_neighbours)) cls[i] = DensityClass::core;  // count includes i
  }
  std::vector<DensityClass> out = cls;
  for (std::size_t i = 0; i < n; ++i) {
    if (cls[i] == DensityClass::core) continue;
    bool core = false, other = false;
    tree.for_each_within(tree.points()[i], radius_m, [&](std::size_t j, double) {
      if (j != i) (cls[j] == DensityClass::core ? core : other) = true;
    });
    if (core && other) out[i] = DensityClass::frontier;
  }
  return out;
}
}  // namespace detail

[[nodiscard]] inline std::vector<DensityClass> classify_density(std::span<const Vec3> points, double radius_m,
                                                                int min_neighbours) {
  detail::require_positive("classify_density: radius_m", radius_m);
  detail::require(min_neighbours >= 1, "classify_density: min_neighbours must be >= 1, got ", min_neighbours);
  for (std::size_t i = 0; i < points.size(); ++i)
    detail::require(points[i].allFinite(), "classify_density: point ", i, " is not finite");
  return detail::classify_density(detail::PointKdTree(std::vector<Vec3>(points.begin(), points.end())), radius_m,
                                  min_neighbours);
}

/// Parameters of the SEE generator. Lengths in metres, angles in radians.
struct SurfaceEdgeSetting {
  /// The measured points (mesh vertices with a normal) are first thinned (thin_points) to pairwise distances
  /// > this, so that the density depends neither on how often nor on how finely a surface was scanned (a grid would
  /// alias: a plane on a cell boundary fills two layers of cells). 2 mm: twice the DLR profiler's profile spacing.
  double spacing_m = 0.002;
  double radius_m = 0.006;   ///< r: SEE's resolution, the radius of the density ball
  /// k: a point is core with at least k other points within r (SEE's ρ = k / (4/3 π r³)). After thinning, a fully
  /// observed plane gives 24 neighbours at r = 3 spacings, its straight edge 14 (measured on a 0.25 × 1 mm sampled
  /// plane): 18 separates them.
  int min_neighbours = 18;
  /// Frontier points within this distance of an earlier one (in point order) share its view (SEE proposes a view per
  /// frontier point; nbs thins them so that Alg. 3 and the selection see tens, not thousands, of views).
  double view_spacing_m = 0.01;
  /// Frontier points within this height above the support plane (the unknown area's bottom) get no view: the
  /// object's contact with the pedestal is an edge no view can observe (Sec. 4.1).
  double support_margin_m = 0.004;
  double path_length_m = 0.0;  ///< line sensors: the sweep's length, centred on the frontier point; 0 = l_b(d_s)
  /// A view whose start lies within `repeat_distance_m` of an earlier scan's start (PlanningContext::scan_starts,
  /// and the last scan's) with s_z within `repeat_angle_rad` of that scan's is not proposed again (SEE does not
  /// repeat a view that failed to observe its frontier point).
  double repeat_distance_m = 0.01;
  double repeat_angle_rad = 15.0 * std::numbers::pi / 180.0;

  /// Throws InvalidArgument naming the field and its value.
  void validate() const {
    detail::require_positive("SurfaceEdge.spacing_m", spacing_m);
    detail::require_positive("SurfaceEdge.radius_m", radius_m);
    detail::require(min_neighbours >= 1, "SurfaceEdge.min_neighbours must be >= 1, got ", min_neighbours);
    detail::require_non_negative("SurfaceEdge.view_spacing_m", view_spacing_m);
    detail::require_non_negative("SurfaceEdge.support_margin_m", support_margin_m);
    detail::require_non_negative("SurfaceEdge.path_length_m", path_length_m);
    detail::require_non_negative("SurfaceEdge.repeat_distance_m", repeat_distance_m);
    detail::require_in_range("SurfaceEdge.repeat_angle_rad", repeat_angle_rad, 0.0, std::numbers::pi);
  }
};

/// Greedy thinning in input order: point i is kept unless a kept point lies within `spacing_m` (inclusive); returns
/// the kept indices, ascending. Kept points are pairwise > spacing_m apart and every point lies within spacing_m of
/// a kept one. Deterministic. Precondition: finite points, spacing_m > 0.
[[nodiscard]] inline std::vector<std::size_t> thin_points(std::span<const Vec3> points, double spacing_m) {
  const detail::PointKdTree tree(std::vector<Vec3>(points.begin(), points.end()));
  std::vector<char> covered(points.size(), 0);
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (covered[i]) continue;
    kept.push_back(i);
    tree.for_each_within(points[i], spacing_m, [&](std::size_t j, double) { covered[j] = 1; });
  }
  return kept;
}

/// SEE's view of one frontier point `p` with unit surface normal `n` (pointing to the sensor side) and outward
/// direction `out` (in the tangent plane, from the observed side across the frontier edge): s_z = −n, s_y = out
/// (the stripe sweeps across the edge, its fan s_x = s_y × s_z along the edge), the path at d_s along n, centred on
/// p with length `length_m` (0 for an area sensor: one viewpoint at p + d_s n). aim = (p, n). Precondition: n unit,
/// out unit and ⊥ n.
[[nodiscard]] inline ScanCandidate surface_edge_view(const Vec3& p, const Vec3& n, const Vec3& out, double d_s,
                                                     double length_m, std::size_t index) {
  const Vec3 s_z = -n, s_y = out, s_x = s_y.cross(s_z);
  ScanCandidate c;
  c.source = CandidateSource::surface_edge;
  c.index = index;
  const Vec3 mid = p + d_s * n, half = 0.5 * length_m * s_y;
  const Viewpoint start = Viewpoint::from_axes(s_x, s_y, s_z, mid - half);
  c.path = length_m > 0.0 ? LinearScanPath(start, mid + half) : LinearScanPath(start);
  c.aim = {p, n};
  c.targets = {{p, n}, {p + 0.5 * half, n}, {p - 0.5 * half, n}};
  return c;
}

/// SEE as a CandidateGenerator (the search of method code SEE; pair it with NearestViewUtility, SEE's selection).
/// Per call: the mesh's vertices with a robust normal, thinned to `spacing_m` (thin_points, vertex order), are
/// classified by classify_density; each frontier point not within `support_margin_m` of the support plane and not
/// within `view_spacing_m` of an earlier proposed one gets surface_edge_view with its vertex normal and the outward
/// direction p − (mean of its r-neighbours), projected ⊥ n. Views that repeat an earlier scan are dropped (see the
/// setting). The candidates replace the planner's candidate set every step (kReplacesCandidateSet): SEE re-derives
/// its frontier from all measurements.
/// Simplified against SEE: the normal is the mesh's (weighted PCA over R_n, oriented to the sensor) instead of a
/// PCA over the r-ball; frontier points are thinned by distance instead of proposing one view each; occluded views
/// are handled by nbs's Alg. 3 (rotations about the aim, else dropped) instead of SEE's view adjustment; the memory
/// of unsuccessful views is the repeat rule (no view is flown twice) instead of SEE's frontier-point bookkeeping.
/// Status: empty_mesh, no_frontier, all_rejected (every frontier view dropped), else ok.
/// Deterministic. Thread-safety: const.
class SurfaceEdgeExplorer : public detail::GeneratorWithSetting<SurfaceEdgeSetting> {
public:
  using GeneratorWithSetting::GeneratorWithSetting;
  /// The planner replaces its candidate set with each call's candidates (search_policy.hpp).
  static constexpr bool kReplacesCandidateSet = true;

  template <EdgeMesh Mesh, VoxelSpace Space>
  [[nodiscard]] CandidateSet generate(const PlanningContext<Mesh, Space>& ctx) const {
    if (auto empty = check_mesh(ctx)) return std::move(*empty);
    const SurfaceEdgeSetting& s = setting_;
    std::vector<Vec3> measured, normals;
    for (VertexId v = 0; v < ctx.mesh.vertex_count(); ++v) {
      const Vec3 n = ctx.mesh.normal(v);
      if (n.squaredNorm() < 0.81) continue;  // no robust normal yet
      measured.push_back(ctx.mesh.position(v));
      normals.push_back(n.normalized());
    }
    struct {
      std::vector<Vec3> points, normals;
      [[nodiscard]] std::size_t size() const { return points.size(); }
    } pts;
    for (const std::size_t i : thin_points(measured, s.spacing_m)) {
      pts.points.push_back(measured[i]);
      pts.normals.push_back(normals[i]);
    }
    const detail::PointKdTree tree(pts.points);
    const std::vector<DensityClass> cls = detail::classify_density(tree, s.radius_m, s.min_neighbours);
    const double d_s = ctx.standoff();
    const double length = ctx.sensor.kind == SensorGeometry::Kind::area
                              ? 0.0
                              : (s.path_length_m > 0.0 ? s.path_length_m : ctx.sensor.baseline_m(d_s));
    const bool support = !ctx.unknown_area.empty();
    const double cos_repeat = std::cos(s.repeat_angle_rad);
    const auto flown = [&](const Pose& v) {
      const auto same = [&](const Pose& t) {
        return (v.translation() - t.translation()).norm() < s.repeat_distance_m &&
               v.linear().col(2).dot(t.linear().col(2)) > cos_repeat;
      };
      return same(ctx.last_sensor) || std::ranges::any_of(ctx.scan_starts, same);
    };
    CandidateSet out;
    std::vector<Vec3> proposed;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (cls[i] != DensityClass::frontier) continue;
      ++out.considered;
      const Vec3& p = pts.points[i];
      if (support && p.z() < ctx.unknown_area.min.z() + s.support_margin_m) {
        ++out.rejected;
        continue;
      }
      const bool near = std::ranges::any_of(proposed, [&](const Vec3& q) { return (q - p).norm() < s.view_spacing_m; });
      if (near) continue;
      const Vec3 n = pts.normals[i];
      Vec3 sum = Vec3::Zero();
      double count = 0.0;
      tree.for_each_within(p, s.radius_m, [&](std::size_t j, double) { sum += pts.points[j], count += 1.0; });
      Vec3 o = p - sum / count;  // count ≥ 1: p itself
      o -= o.dot(n) * n;
      o = o.norm() > 1e-9 ? Vec3(o.normalized()) : detail::any_orthogonal(n);
      ScanCandidate c = surface_edge_view(p, n, o, d_s, length, i);
      if (flown(c.path.start().pose())) {
        ++out.rejected;
        continue;
      }
      proposed.push_back(p);
      out.candidates.push_back(std::move(c));
    }
    out.status = out.considered == 0         ? CandidateStatus::no_frontier
                 : out.candidates.empty() ? CandidateStatus::all_rejected
                                            : CandidateStatus::ok;
    return out;
  }
};

}  // namespace nbs
