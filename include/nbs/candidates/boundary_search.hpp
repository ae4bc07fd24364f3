// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Boundary Search (Secs. 4.2–4.3): one scan candidate per boundary of the last scan, from the surface trend beside
/// the boundary.

#include <exception>
#include <numbers>
#include <optional>
#include <thread>
#include <vector>

#include "nbs/candidates/candidate_generator.hpp"
#include "nbs/candidates/detail/boundary_candidate.hpp"
#include "nbs/core/detail/parallel_for.hpp"

namespace nbs {

/// Boundary Search generator (models CandidateGenerator). Per boundary of detect_boundaries (Alg. 1):
/// region growing from c_b (Eq. 4.4) inside the Sec. 4.2.2 box in the last sensor frame; weighted quadratic patch
/// (Eqs. 4.5–4.11, weights boundary_distance_weight with scale R_m); walk along the patch in the Tab. 4.2
/// direction until the overlap o = `Parameters::scan_overlap` (Eq. 4.14) is reached, the viewing direction turns by
/// more than `max_step_angle_rad` between consecutive steps, or the walk exceeds l_b; viewpoint by Eqs. 4.13,
/// 4.15–4.18 at d_s; sharp-corner rule (Eqs. 4.19–4.21: λ2, λ3 ≤ `planar_eigenvalue_max` and c_b inside the FOV of
/// the last scan → rotate by `sharp_corner_rotation_rad` about the boundary line through c_b, towards the unknown
/// side); line sensors get a path along s_y over the extent of the whole mesh (Fig. 4.9), area sensors a single
/// viewpoint. Candidates are in boundary order, the same for any `PlanningContext::threads`. Thread-safety: const,
/// no shared state; with ≥ 2 threads the mesh's const members are called concurrently.
class BoundarySearch : public detail::GeneratorWithSetting<BoundarySearchSetting> {
public:
  using GeneratorWithSetting::GeneratorWithSetting;

  /// Candidates for the boundaries of the last scan. Throws InvalidArgument on an invalid context.
  /// Status: empty_mesh (no triangle), no_boundaries, all_rejected (no patch could be fitted), else ok.
  template <EdgeMesh Mesh, VoxelSpace Space>
  [[nodiscard]] CandidateSet generate(const PlanningContext<Mesh, Space>& ctx) const {
    if (auto empty = check_mesh(ctx)) return std::move(*empty);
    CandidateSet out;
    // With ≥ 2 threads the topology is built beside boundary detection (both only read the mesh).
    detail::MeshTopology topo;
    std::exception_ptr topo_error;
    std::thread topo_thread;
    if (ctx.threads >= 2) {
      topo_thread = std::thread([&] {
        try {
          topo = detail::mesh_topology(ctx.mesh);
        } catch (...) {
          topo_error = std::current_exception();
        }
      });
    }
    std::vector<Boundary> boundaries;
    try {
      boundaries = detect_boundaries(ctx.mesh, ctx.last_sensor, ctx.params);
    } catch (...) {
      if (topo_thread.joinable()) topo_thread.join();
      throw;
    }
    if (topo_thread.joinable()) topo_thread.join();
    if (topo_error) std::rethrow_exception(topo_error);
    out.considered = boundaries.size();
    if (boundaries.empty()) {
      out.status = CandidateStatus::no_boundaries;
      return out;
    }
    if (ctx.threads < 2) topo = detail::mesh_topology(ctx.mesh);
    detail::BoundarySearchFrame f;
    f.t_ws = ctx.last_sensor;
    f.t_sw = ctx.last_sensor.inverse(Eigen::Isometry);
    f.standoff_m = ctx.standoff();
    f.last_path_length_m = ctx.last_path_length_m;
    f.sensor = ctx.sensor;
    for (VertexId v = 0; v < topo.triangulated.size(); ++v) {
      if (!topo.triangulated[v]) continue;
      f.world_vertices.push_back(ctx.mesh.position(v));
      f.sensor_extent.extend(f.t_sw * f.world_vertices.back());
    }
    // One slot per boundary, filled by any thread, collected in boundary order: the same set for any count.
    std::vector<std::optional<ScanCandidate>> slots(boundaries.size());
    detail::parallel_for(boundaries.size(), ctx.threads, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        slots[i] = detail::boundary_candidate(ctx.mesh, topo, boundaries[i], i, f, ctx.params, setting_);
    });
    for (auto& c : slots) {
      if (c)
        out.candidates.push_back(std::move(*c));
      else
        ++out.rejected;
    }
    out.status = out.candidates.empty() ? CandidateStatus::all_rejected : CandidateStatus::ok;
    return out;
  }

};

}  // namespace nbs
