// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Voxel classification agreement between a native log-odds space and an OctoMap tree filled by OctoMap's own
// insertion (the oracle of issue 3): every voxel observed by either side is classified unknown / free / occupied
// with the same LogOddsModel thresholds and compared.

#include <octomap/OcTree.h>

#include <cstddef>

#include "nbs/octomap/insert_scan.hpp"
#include "nbs/octomap/octree_backend.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace nbs::test {

using NativeLogOddsSpace = ProbabilisticVoxelSpace<HashedBlockBackend<LogOddsState>, LogOddsModel>;

struct ClassificationAgreement {
  std::size_t total = 0;      ///< voxels observed by either side
  std::size_t same = 0;       ///< classified identically
  std::size_t occupied = 0;   ///< occupied in the native space
  std::size_t only_ref = 0;   ///< observed by OctoMap only
  [[nodiscard]] double share() const { return total ? static_cast<double>(same) / static_cast<double>(total) : 0.0; }
};

inline ClassificationAgreement classification_agreement(const NativeLogOddsSpace& native, const ::octomap::OcTree& ref) {
  enum class Cls { unknown, free, occupied };
  const auto classify = [&](bool observed, const LogOddsState& s) {
    return !observed ? Cls::unknown : (native.model().occupied(s) ? Cls::occupied : Cls::free);
  };
  ClassificationAgreement r;
  native.for_each([&](const VoxelKey& k, const LogOddsState& s) {
    const auto o = nbs::octomap::to_octree_key(k);
    const auto* n = o ? ref.search(*o) : nullptr;
    const Cls a = classify(true, s);
    const Cls b = classify(n != nullptr, n ? LogOddsState{n->getLogOdds()} : LogOddsState{});
    ++r.total;
    r.same += a == b ? 1 : 0;
    r.occupied += a == Cls::occupied ? 1 : 0;
  });
  for_each_voxel(ref, [&](const VoxelKey& k, const LogOddsState&) {
    if (!native.observed(k)) ++r.only_ref;
  });
  r.total += r.only_ref;
  return r;
}

}  // namespace nbs::test
