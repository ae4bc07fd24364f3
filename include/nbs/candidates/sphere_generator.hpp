// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The sphere search baseline (Sec. 4.7.2) as a CandidateGenerator.

#include "nbs/candidates/candidate_generator.hpp"
#include "nbs/candidates/sphere_search.hpp"

namespace nbs {

/// Sphere baseline generator (models CandidateGenerator): the fixed paths of sphere_scan_paths around the centre of
/// the bounding box of the unknown area (Sec. 4.1). Radius = d_s + half the largest box extent, so a surface at the
/// box's half extent from the centre is seen at d_s (our choice; the thesis gives none). The aim of each candidate is
/// that point, centre − half·s_z. Independent of mesh and voxel space. Thread-safety: const.
class SphereSearch : public detail::GeneratorWithSetting<SphereSearchSetting> {
public:
  using GeneratorWithSetting::GeneratorWithSetting;
  /// The candidates depend only on the unknown-area box: the planner generates them once (FixedCandidateSpace).
  static constexpr bool kFixedCandidateSpace = true;

  /// Status: empty_unknown_area if ctx.unknown_area is empty, else ok (inclinations × azimuths candidates).
  template <EdgeMesh Mesh, VoxelSpace Space>
  [[nodiscard]] CandidateSet generate(const PlanningContext<Mesh, Space>& ctx) const {
    ctx.validate();
    setting_.validate();
    CandidateSet out;
    if (ctx.unknown_area.empty()) {
      out.status = CandidateStatus::empty_unknown_area;
      return out;
    }
    const Vec3 center = ctx.unknown_area.center();
    const double half = 0.5 * ctx.unknown_area.extent().maxCoeff(), d_s = ctx.standoff();
    const auto paths = sphere_scan_paths(center, d_s + half, setting_);
    out.considered = paths.size();
    for (std::size_t k = 0; k < paths.size(); ++k) {
      ScanCandidate c;
      c.path = paths[k];
      c.source = CandidateSource::sphere;
      c.index = k;
      const Vec3 s_z = paths[k].start().view_direction();
      c.aim = {center - half * s_z, -s_z};
      c.targets.push_back(c.aim);
      out.candidates.push_back(std::move(c));
    }
    return out;
  }

};

}  // namespace nbs
