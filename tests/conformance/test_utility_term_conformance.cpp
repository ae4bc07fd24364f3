// SPDX-License-Identifier: BSD-3-Clause
// UtilityTerm conformance: every term in the repo (thesis terms, peer terms, RandomSelection, TermSet) and a minimal
// user-written term, on one random voxel world.
#include "utility_term_conformance.hpp"

#include "nbs/explore/recognition_view.hpp"
#include "nbs/utility/peer_terms.hpp"
#include "nbs/utility/surface_gain.hpp"
#include "nbs/utility/thesis_terms.hpp"
#include "nbs/utility/unseen_surface.hpp"

namespace {

using nbs::conformance::CandidateStream;
using nbs::conformance::RandomVoxelWorld;

/// The user-written term: the number of rays that end on an occupied voxel.
struct HitRays {
  double hits = 0.0;
  void begin_candidate(std::size_t) { hits = 0.0; }
  void begin_ray() {}
  void visit(const nbs::VoxelVisit&) {}
  void end_ray(const nbs::RayEnd& e) { hits += e.hit ? 1.0 : 0.0; }
  [[nodiscard]] double value() const { return hits; }
};
static_assert(nbs::UtilityTerm<HitRays>);

/// The random world seen as a space, for ProximityField::build (resolution, for_each, observed, model().occupied).
struct WorldSpace {
  const RandomVoxelWorld* world;
  struct Model {
    [[nodiscard]] bool occupied(bool s) const { return s; }
  };
  [[nodiscard]] double resolution_m() const { return 0.005; }
  [[nodiscard]] Model model() const { return {}; }
  [[nodiscard]] bool observed(const nbs::VoxelKey& k) const {
    const int n = RandomVoxelWorld::n;
    const bool inside = k.x >= 0 && k.y >= 0 && k.z >= 0 && k.x < n && k.y < n && k.z < n;
    return inside && world->observed(k);
  }
  template <class F>
  void for_each(F&& f) const {
    const int n = RandomVoxelWorld::n;
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) f(nbs::VoxelKey{x, y, z}, world->occupied(nbs::VoxelKey{x, y, z}));
  }
};

double entropy_oracle(const CandidateStream& s, bool count_once, double n_v) {
  double sum = 0.0;
  for (const auto& r : s)
    for (const auto& v : r.visits)
      if (v.first_visit || !count_once) sum += nbs::voxel_entropy(v.probability);
  return sum / n_v;
}

const RandomVoxelWorld& world() {
  static const RandomVoxelWorld w(7);
  return w;
}

}  // namespace

TEST_CASE("UtilityTerm conformance: thesis terms (Eqs. 4.30-4.34) and RandomSelection", "[conformance][utility]") {
  using nbs::conformance::check_utility_term_conformance;
  for (const bool once : {true, false}) {
    INFO("count_once " << once);
    check_utility_term_conformance(nbs::VolumetricEntropy({3.0, once}), world(),
                                   [&](std::size_t, const CandidateStream& s) { return entropy_oracle(s, once, 3.0); });
    check_utility_term_conformance(nbs::SurfaceQuality({2.0, 0.7, 1.2, once}), world());
    nbs::WeightedUtility::Setting ws = nbs::WeightedUtility::thesis(2.0, 3.0);
    ws.count_once = once;
    check_utility_term_conformance(nbs::WeightedUtility(ws), world(), [&](std::size_t i, const CandidateStream& s) {
      nbs::VolumetricEntropy e({2.0, once});
      nbs::SurfaceQuality q({2.0, ws.lambda, ws.cutoff_rad, once});
      const double ev = nbs::conformance::evaluate(e, i, s), ms = nbs::conformance::evaluate(q, i, s);
      return (1.0 - ws.omega) * ev + ws.omega * ms;  // Eq. (4.30)
    });
  }
  nbs::SurfaceGain::Setting sg;
  sg.non_free_voxels = 2.0;
  sg.omega = nbs::modeling_weight(3.0);
  check_utility_term_conformance(nbs::SurfaceGain(sg), world(), [&](std::size_t i, const CandidateStream& s) {
    nbs::RearSideEntropyVI r;  // default form: no modeling term, whatever ω
    return nbs::conformance::evaluate(r, i, s) / 2.0;
  });
  sg.modeling = true;
  std::vector<double> lengths(100);
  for (std::size_t i = 0; i < lengths.size(); ++i) lengths[i] = 0.01 * static_cast<double>(i % 17);
  check_utility_term_conformance(nbs::SurfaceGain(sg), world(), [&](std::size_t i, const CandidateStream& s) {
    nbs::RearSideEntropyVI r;
    nbs::SurfaceQuality q({2.0, sg.lambda, sg.cutoff_rad, true});
    return (1.0 - sg.omega) * nbs::conformance::evaluate(r, i, s) / 2.0 + sg.omega * nbs::conformance::evaluate(q, i, s);
  });
  check_utility_term_conformance(nbs::SurfaceGain(sg, lengths), world(), [&](std::size_t i, const CandidateStream& s) {
    nbs::SurfaceGain plain(sg);
    return nbs::conformance::evaluate(plain, i, s) / (lengths[i] + sg.length_offset_m);
  });
  // SGU: unseen fan samples in every third voxel of the world (voxel centres, l_v = 5 mm); oracle: the map's value
  // summed over the distinct unobserved voxels the candidate's rays visit, plus SG's bracket.
  const int n = RandomVoxelWorld::n;
  std::vector<nbs::UnseenSample> samples;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        if ((x + 2 * y + 5 * z) % 3 == 0) samples.push_back({nbs::Vec3(x + 0.5, y + 0.5, z + 0.5) * 0.005, 1e-5 * (1 + x % 4)});
  const nbs::UnseenSurfaceMap map = nbs::UnseenSurfaceMap::build(samples, nbs::VoxelGrid(0.005));
  REQUIRE(map.voxels() == samples.size());
  const auto unseen_oracle = [&](const CandidateStream& s) {
    double sum = 0.0;
    for (const auto& r : s)
      for (const auto& v : r.visits)
        if (v.first_visit && !v.observed) sum += map.at(v.key);
    return sum;
  };
  check_utility_term_conformance(nbs::UnseenSurfaceVI(&map), world(),
                                 [&](std::size_t, const CandidateStream& s) { return unseen_oracle(s); });
  sg.modeling = false;
  sg.unseen_weight = 3.0;
  check_utility_term_conformance(nbs::SurfaceGain(sg, {}, &map), world(), [&](std::size_t i, const CandidateStream& s) {
    nbs::RearSideEntropyVI r;
    return (nbs::conformance::evaluate(r, i, s) + 3.0 * unseen_oracle(s)) / 2.0;
  });
  const nbs::RandomSelection random({42});
  check_utility_term_conformance(random, world(), [&](std::size_t i, const CandidateStream&) {
    nbs::RandomSelection r({42});
    return nbs::conformance::evaluate(r, i, world().candidate(99, 2));  // depends on (seed, i) only
  });
}

TEST_CASE("UtilityTerm conformance: peer terms of Delmerico et al. 2018", "[conformance][utility]") {
  using nbs::conformance::check_utility_term_conformance;
  const nbs::ProximityField field = nbs::ProximityField::build(WorldSpace{&world()}, 0.011);
  REQUIRE(field.size() > 0);
  for (const bool once : {false, true}) {
    INFO("count_once " << once);
    const nbs::PeerTermSetting s{once};
    check_utility_term_conformance(nbs::OcclusionAwareVI(s), world());
    check_utility_term_conformance(nbs::UnobservedVoxelVI(s), world());
    check_utility_term_conformance(nbs::RearSideVoxelVI(s), world());
    check_utility_term_conformance(nbs::RearSideEntropyVI(s), world());
    check_utility_term_conformance(nbs::ProximityCountVI(field, s), world());
    check_utility_term_conformance(nbs::AverageEntropyVI({once, false}), world());
    check_utility_term_conformance(nbs::AverageEntropyVI({once, true}), world());
  }
  check_utility_term_conformance(nbs::VasquezGomezVI(field), world());
}

TEST_CASE("UtilityTerm conformance: TermSet and a user-written term", "[conformance][utility]") {
  using nbs::conformance::check_utility_term_conformance;
  // The recognition-view score (explore/recognition_view.hpp): distinct unobserved voxels in the boxes.
  const int n = RandomVoxelWorld::n;
  const std::vector<nbs::KeyBox> boxes{{{0, 0, 0}, {n / 2, n - 1, n - 1}}, {{0, 0, 0}, {n - 1, 1, 1}}};
  check_utility_term_conformance(nbs::explore::UnobservedInBoxes{boxes}, world(), [&](std::size_t, const CandidateStream& s) {
    double count = 0.0;
    for (const auto& r : s)
      for (const auto& v : r.visits)
        if (v.first_visit && !v.observed && (boxes[0].contains(v.key) || boxes[1].contains(v.key))) ++count;
    return count;
  });
  check_utility_term_conformance(HitRays{}, world(), [](std::size_t, const CandidateStream& s) {
    double hits = 0.0;
    for (const auto& r : s) hits += r.end.hit ? 1.0 : 0.0;
    return hits;
  });
  using Set = nbs::TermSet<HitRays, nbs::VolumetricEntropy, nbs::RandomSelection>;
  static_assert(nbs::UtilityTerm<Set> && Set::kNeedsRays);
  const Set set(HitRays{}, nbs::VolumetricEntropy({1.0, true}), nbs::RandomSelection({5}));
  CHECK_FALSE(nbs::visits_first_only(set));  // HitRays does not declare it
  check_utility_term_conformance(set, world(), [](std::size_t i, const CandidateStream& s) {
    HitRays h;
    return nbs::conformance::evaluate(h, i, s);  // value() is the first term's
  });
  // Every member of the set sees the same stream as if it were fed alone.
  Set fed = set;
  const CandidateStream s = world().candidate(5, 6);
  (void)nbs::conformance::evaluate(fed, 17, s);
  nbs::VolumetricEntropy e({1.0, true});
  nbs::RandomSelection r({5});
  CHECK(fed.values()[1] == nbs::conformance::evaluate(e, 17, s));
  CHECK(fed.values()[2] == nbs::conformance::evaluate(r, 17, s));
  // Nested sets and a set of first-visit terms only.
  using Nested = nbs::TermSet<nbs::TermSet<nbs::VolumetricEntropy, nbs::SurfaceQuality>, nbs::OcclusionAwareVI>;
  check_utility_term_conformance(Nested{}, world());
  const nbs::TermSet<nbs::VolumetricEntropy, nbs::SurfaceQuality> thesis;
  CHECK(nbs::visits_first_only(thesis));
  check_utility_term_conformance(thesis, world(), [](std::size_t, const CandidateStream& cs) {
    return entropy_oracle(cs, true, 1.0);
  });
}
