// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The planner's candidate search policy (Secs. 4.1, 4.6): which generator explores the object first and which one
/// rescans holes after the process-control switch (Eq. 4.38).

#include <type_traits>

#include "nbs/planner/detail/components.hpp"

namespace nbs {

/// "No second mode": the planner never switches from the explore generator.
struct NoRescan {};

/// A generator whose candidates do not depend on the model (the sphere baseline, Sec. 4.7.2) declares it with
/// `static constexpr bool kFixedCandidateSpace = true;`: the planner generates them once, before the first planning
/// step, and consumes them.
template <class G>
concept FixedCandidateSpace = requires {
  requires G::kFixedCandidateSpace;
};

/// A generator whose candidates replace the candidate set S each step instead of joining it (SEE, which re-derives
/// its frontier from all measurements) declares `static constexpr bool kReplacesCandidateSet = true;`.
template <class G>
concept ReplacesCandidateSet = requires {
  requires G::kReplacesCandidateSet;
};

/// Candidate search: `explore` in the first mode, `rescan` after the switch of Sec. 4.6 (unless `Rescan` is
/// NoRescan). Each generator is a public member with its own `Setting` (e.g. `search.explore.setting()`).
/// Pool rule (Sec. 4.1): candidates of `explore` are added to the candidate set S after every scan (fixed spaces:
/// once); on the switch the remaining S is discarded and `rescan` runs once on the current model (holes detected
/// once), its candidates form the new S. The planner removes each selected candidate from S.
template <class Explore = BoundarySearch, class Rescan = HoleRescan>
struct CandidateSearch {
  using ExploreGenerator = Explore;
  using RescanGenerator = Rescan;
  /// True if this search switches to `Rescan` when ĉ_m stagnates (Eq. 4.38).
  static constexpr bool kHasRescan = !std::is_same_v<Rescan, NoRescan>;

  Explore explore{};
  [[no_unique_address]] Rescan rescan{};
};

/// The three search spaces of Sec. 4.7: sphere (S), Boundary Search (B), Boundary Search + Hole Rescan (H).
using SphereSpace = CandidateSearch<SphereSearch, NoRescan>;
using BoundarySpace = CandidateSearch<BoundarySearch, NoRescan>;
using BoundaryHoleSpace = CandidateSearch<BoundarySearch, HoleRescan>;
/// The SEE peer planner's search (method code SEE): the density frontier, no second mode.
using SurfaceEdgeSpace = CandidateSearch<SurfaceEdgeExplorer, NoRescan>;

/// G is a CandidateSearch whose generators model CandidateGenerator for Mesh and Space.
template <class G, class Mesh, class Space>
concept CandidateSearchPolicy =
    requires(const G& g) {
      g.explore;
      g.rescan;
      { G::kHasRescan } -> std::convertible_to<bool>;
    } && CandidateGenerator<typename G::ExploreGenerator, Mesh, Space> &&
    (!G::kHasRescan || CandidateGenerator<typename G::RescanGenerator, Mesh, Space>);

}  // namespace nbs
