// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Hole Rescan (Sec. 4.4, Alg. 2, Eqs. 4.22–4.23): one scan path per hole (or per group of similar holes), looking
/// along an occlusion-free direction near the hole's PCA normal.

#include <numbers>

#include "nbs/candidates/candidate_generator.hpp"
#include "nbs/candidates/detail/hole_direction.hpp"
#include "nbs/mesh/holes.hpp"

namespace nbs {

/// Choices of the Hole Rescan the thesis leaves open (ours). Lengths in metres, angles in radians.
struct HoleRescanSetting {
  /// Sample only the hemisphere around the PCA normal n_h (Alg. 2 samples "all directions"; with unknown voxels
  /// counting as free, a direction through the object's unseen inside would pass the occlusion test).
  bool front_hemisphere_only = true;
  double start_offset_voxels = 2.0;  ///< occlusion rays start this many voxel edges off c_h (skip the rim's voxels)
  double selection_fraction = 0.2;   ///< the 20 % of Alg. 2
  double merge_distance_m = 0.02;    ///< holes whose centres are closer than this ...
  double merge_angle_rad = 15.0 * std::numbers::pi / 180.0;  ///< ... and whose view directions differ less share a path
  double end_margin = 0.1;           ///< relative margin on each side of the hole, Eqs. 4.22–4.23 (1.1 = 1 + 0.1)
  /// Skip holes whose surface was measured: if a probe ray through c_h along ±n_h (`measured_probe_voxels` voxel
  /// edges each way) meets an occupied voxel, the sensor already saw surface there and the loop is a gap of the
  /// triangulation, not unseen surface; rescanning it adds nothing (our addition: with a noisy stream most border
  /// loops are such gaps, ~950 of them on the bunny after 3 scans, and the thesis's "detect holes once" would
  /// spend the remaining scans on them). Holes smaller than a voxel cannot be told apart and are skipped too.
  bool skip_measured_holes = true;
  double measured_probe_voxels = 1.0;

  void validate() const {
    detail::require_non_negative("HoleRescan.start_offset_voxels", start_offset_voxels);
    detail::require_in_range("HoleRescan.selection_fraction", selection_fraction, 0.0, 1.0);
    detail::require_non_negative("HoleRescan.merge_distance_m", merge_distance_m);
    detail::require_in_range("HoleRescan.merge_angle_rad", merge_angle_rad, 0.0, std::numbers::pi / 2);
    detail::require_in_range("HoleRescan.end_margin", end_margin, 0.0, 10.0);
    detail::require_in_range("HoleRescan.measured_probe_voxels", measured_probe_voxels, 0.0, 100.0);
  }
};

namespace detail {
/// A hole with its chosen view direction n_h (unit, pointing away from the surface to the sensor).
struct HoleView {
  std::size_t index = 0;
  Vec3 center = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
  Vec3 largest = Vec3::Zero();  ///< d_h (not normalised)
};
}  // namespace detail

/// Hole Rescan generator (models CandidateGenerator). For each hole of find_holes (h_min ≤ |E_H| ≤ h_max):
/// Alg. 2 with `Parameters::hole_directions` samples of a fixed golden-angle spiral around the PCA normal, the
/// occlusion test by a planning ray cast from c_h to d_s (an occupied voxel occludes; unknown does not), and the
/// 20 % rule. Holes are then grouped greedily in index order: a hole joins the first group whose first hole's
/// centre is within `merge_distance_m` and whose direction is within `merge_angle_rad`, if the group's mean
/// direction stays occlusion-free from every member centre. Each group gives one path (Eqs. 4.22–4.23): s_z = −n_h,
/// s_y = the principal direction of the members' rim extremes c ± d_h in the plane ⊥ n_h, ends 1 + end_margin times
/// the half extent from the middle, at d_s along n_h. For a single hole with d_h ⊥ n_h this is exactly Eqs.
/// 4.22–4.23 (otherwise d_h is projected so the path moves along s_y). Area sensors: one viewpoint at c + d_s n_h.
/// Deterministic. Thread-safety: const.
class HoleRescan : public detail::GeneratorWithSetting<HoleRescanSetting> {
public:
  using GeneratorWithSetting::GeneratorWithSetting;

  /// Status: empty_mesh, no_holes, all_rejected (every hole measured or occluded in every sampled direction), else ok.
  template <EdgeMesh Mesh, VoxelSpace Space>
  [[nodiscard]] CandidateSet generate(const PlanningContext<Mesh, Space>& ctx) const {
    if (auto empty = check_mesh(ctx)) return std::move(*empty);
    CandidateSet out;
    const std::vector<Hole> holes = find_holes(ctx.mesh, ctx.params);
    out.considered = holes.size();
    if (holes.empty()) {
      out.status = CandidateStatus::no_holes;
      return out;
    }
    const double d_s = ctx.standoff(), offset = setting_.start_offset_voxels * ctx.space.resolution_m();
    std::vector<detail::HoleView> views;
    for (std::size_t i = 0; i < holes.size(); ++i) {
      if (setting_.skip_measured_holes && measured(ctx.space, holes[i])) {
        ++out.measured;
        continue;
      }
      if (auto n = hole_direction(ctx.space, holes[i], ctx.params.hole_directions, d_s, offset))
        views.push_back({i, holes[i].center, *n, holes[i].largest_direction});
      else
        ++out.rejected;
    }
    for (const auto& group : group_views(ctx.space, views, d_s, offset))
      out.candidates.push_back(path_for(group, ctx.sensor, d_s));
    out.status = out.candidates.empty() ? CandidateStatus::all_rejected : CandidateStatus::ok;
    return out;
  }

  /// True if surface was measured at the hole (see HoleRescanSetting::skip_measured_holes).
  template <VoxelSpace Space>
  [[nodiscard]] bool measured(const Space& space, const Hole& hole) const {
    if (!has_frame(hole)) return false;
    const Vec3 d = setting_.measured_probe_voxels * space.resolution_m() * hole.normal.normalized();
    return space.cast_ray(Ray{hole.center + d, hole.center - d}, detail::ContinueVisit{}).hit;
  }

  /// Alg. 2 for one hole: the selected occlusion-free view direction, or nullopt.
  template <VoxelSpace Space>
  [[nodiscard]] std::optional<Vec3> hole_direction(const Space& space, const Hole& hole, int samples, double d_s,
                                                   double offset_m) const {
    if (!has_frame(hole)) return std::nullopt;
    const Vec3 n_h = hole.normal.normalized();
    const auto dirs = detail::spiral_directions(n_h, samples, setting_.front_hemisphere_only);
    std::vector<char> free(dirs.size(), 0);
    for (std::size_t k = 0; k < dirs.size(); ++k) free[k] = detail::occlusion_free(space, hole.center, dirs[k], d_s, offset_m);
    const auto pick = detail::select_hole_normal(n_h, dirs, free, setting_.selection_fraction);
    if (!pick) return std::nullopt;
    return dirs[*pick];
  }

private:
  /// A finite centre c_h and a usable PCA normal n_h (the probe and Alg. 2 both need them).
  [[nodiscard]] static bool has_frame(const Hole& hole) {
    return hole.center.allFinite() && hole.normal.allFinite() && hole.normal.norm() > 0.5;
  }

  template <VoxelSpace Space>
  [[nodiscard]] std::vector<std::vector<detail::HoleView>> group_views(const Space& space,
                                                                      const std::vector<detail::HoleView>& views,
                                                                      double d_s, double offset) const {
    std::vector<std::vector<detail::HoleView>> groups;
    const double cos_merge = std::cos(setting_.merge_angle_rad);
    for (const auto& v : views) {
      bool placed = false;
      for (auto& g : groups) {
        if ((v.center - g.front().center).norm() > setting_.merge_distance_m || v.normal.dot(g.front().normal) < cos_merge)
          continue;
        Vec3 n = v.normal;
        for (const auto& m : g) n += m.normal;
        n.normalize();
        bool ok = detail::occlusion_free(space, v.center, n, d_s, offset);
        for (const auto& m : g) ok = ok && detail::occlusion_free(space, m.center, n, d_s, offset);
        if (!ok) continue;
        g.push_back(v);
        placed = true;
        break;
      }
      if (!placed) groups.push_back({v});
    }
    return groups;
  }

  [[nodiscard]] ScanCandidate path_for(const std::vector<detail::HoleView>& g, const SensorGeometry& sensor,
                                       double d_s) const {
    Vec3 n = Vec3::Zero(), c = Vec3::Zero();
    for (const auto& m : g) n += m.normal, c += m.center;
    n.normalize();
    c /= static_cast<double>(g.size());
    // Rim extremes c_i ± d_h,i projected into the plane ⊥ n; s_y = their principal direction (d_h for one hole).
    std::vector<Vec3> ends;
    for (const auto& m : g)
      for (double s : {-1.0, 1.0}) {
        const Vec3 e = m.center + s * m.largest - c;
        ends.push_back(e - e.dot(n) * n);
      }
    Mat3 cov = Mat3::Zero();
    for (const Vec3& e : ends) cov += e * e.transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> es(cov);
    Vec3 s_y = es.eigenvalues()[2] > 1e-18 ? Vec3(es.eigenvectors().col(2)) : detail::any_orthogonal(n);
    s_y = (s_y - s_y.dot(n) * n).normalized();
    double t0 = 0.0, t1 = 0.0;
    for (const Vec3& e : ends) t0 = std::min(t0, e.dot(s_y)), t1 = std::max(t1, e.dot(s_y));
    const double mid = 0.5 * (t0 + t1), half = (1.0 + setting_.end_margin) * 0.5 * (t1 - t0);
    const Vec3 s_z = -n, s_x = s_y.cross(s_z);
    ScanCandidate cand;
    cand.source = CandidateSource::hole_rescan;
    cand.index = g.front().index;
    for (const auto& m : g) cand.merged.push_back(m.index);
    if (sensor.kind == SensorGeometry::Kind::line) {
      // Eqs. 4.22–4.23: s_p^{1,2} = c_h ∓ 1.1 d_h + d_s n_h.
      const Viewpoint start = Viewpoint::from_axes(s_x, s_y, s_z, c + (mid - half) * s_y + d_s * n);
      cand.path = LinearScanPath(start, c + (mid + half) * s_y + d_s * n);
    } else {
      cand.path = LinearScanPath(Viewpoint::from_axes(s_x, s_y, s_z, c + d_s * n));
    }
    cand.aim = {c, n};
    // Targets: points along d_h through each member hole (Sec. 4.5.2), with the view direction as normal.
    for (const auto& m : g) {
      const Vec3 d = m.largest - m.largest.dot(n) * n;
      for (double s : {-1.0, -0.5, 0.0, 0.5, 1.0}) cand.targets.push_back({m.center + s * d, n});
    }
    return cand;
  }

};

}  // namespace nbs
