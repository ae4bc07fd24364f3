#pragma once
/// \file
/// The CandidateGenerator concept: a policy that turns a planning context into scan candidates (Sec. 4.3, 4.4).

#include <concepts>

#include "nbs/candidates/planning_context.hpp"
#include "nbs/candidates/scan_candidate.hpp"

namespace nbs {

/// G generates scan candidates for meshes of type Mesh and voxel spaces of type Space:
/// `g.generate(ctx)` is const, validates `ctx` (throws InvalidArgument on invalid parameters) and returns a
/// CandidateSet whose `status` explains an empty list. Deterministic: same context, same candidates.
/// Models: BoundarySearch, HoleRescan, SphereSearch.
template <class G, class Mesh, class Space>
concept CandidateGenerator =
    EdgeMesh<Mesh> && PlanningSpace<Space> && requires(const G& g, const PlanningContext<Mesh, Space>& ctx) {
      { g.generate(ctx) } -> std::same_as<CandidateSet>;
    };

}  // namespace nbs
