// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The CandidateGenerator concept: a policy that turns a planning context into scan candidates (Sec. 4.3, 4.4).

#include <concepts>
#include <optional>

#include "nbs/candidates/planning_context.hpp"
#include "nbs/candidates/scan_candidate.hpp"

namespace nbs {

/// G generates scan candidates for meshes of type Mesh and voxel spaces of type Space:
/// `g.generate(ctx)` is const, validates `ctx` (throws InvalidArgument on invalid parameters) and returns a
/// CandidateSet whose `status` explains an empty list. Deterministic: same context, same candidates.
/// Models: BoundarySearch, HoleRescan, SphereSearch.
template <class G, class Mesh, class Space>
concept CandidateGenerator =
    EdgeMesh<Mesh> && VoxelSpace<Space> && requires(const G& g, const PlanningContext<Mesh, Space>& ctx) {
      { g.generate(ctx) } -> std::same_as<CandidateSet>;
    };

namespace detail {

/// Common part of the generators: owns a validated `Setting` (a struct with `validate()`).
template <class S>
class GeneratorWithSetting {
public:
  using Setting = S;
  GeneratorWithSetting() = default;
  /// Throws InvalidArgument if `s` is invalid.
  explicit GeneratorWithSetting(const Setting& s) : setting_((s.validate(), s)) {}
  [[nodiscard]] const Setting& setting() const { return setting_; }

protected:
  /// Validates `ctx` and the setting; returns a set with status empty_mesh if the mesh has no triangle.
  template <class Ctx>
  [[nodiscard]] std::optional<CandidateSet> check_mesh(const Ctx& ctx) const {
    ctx.validate();
    setting_.validate();
    if (ctx.mesh.face_count() != 0) return std::nullopt;
    CandidateSet out;
    out.status = CandidateStatus::empty_mesh;
    return out;
  }
  Setting setting_{};
};

}  // namespace detail
}  // namespace nbs
