// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::UtilityTerm (include/nbs/utility/utility_term.hpp). A term is fed seeded random
// candidate streams that follow the documented call protocol — begin_candidate(i); per ray begin_ray(), visit(v) for
// each voxel in order (the ray ends at its first occupied voxel), end_ray(e); value() — over a small key cube, so
// voxels repeat within and across rays (first_visit as the evaluator marks it). Checked contract:
//  - value() is finite and a pure function of what the term was fed since begin_candidate: a fresh copy fed the same
//    stream, a copy taken mid-stream and fed the rest, and a term reused after another candidate all give the
//    bit-identical value;
//  - visits_first_only(t): feeding only the first visits (what the evaluator then does) changes nothing;
//  - kNeedsRays = false: the value does not depend on the rays at all;
//  - optionally, an oracle: the expected value of a stream.
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <set>
#include <vector>

#include "nbs/utility/utility_term.hpp"
#include "nbs_random.hpp"

namespace nbs::conformance {

/// One simulated ray: its voxel visits in order and how it ended.
struct StreamRay {
  std::vector<VoxelVisit> visits;
  RayEnd end;
};
/// The rays of one candidate.
using CandidateStream = std::vector<StreamRay>;

/// Fixed per-voxel state of the random world: keys in [0, n)³.
class RandomVoxelWorld {
public:
  static constexpr int n = 6;
  explicit RandomVoxelWorld(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < n * n * n; ++i) {
      Cell c;
      const double r = u(rng);
      c.occupied = r < 0.12;
      c.observed = c.occupied || r > 0.55;
      c.p = c.occupied ? 0.6 + 0.4 * u(rng) : (c.observed ? 0.4 * u(rng) : 0.5);
      if (c.occupied || u(rng) < 0.1) {
        SurfaceFeatures f;
        f.mean_density = static_cast<float>(u(rng));
        f.border_share = static_cast<float>(u(rng));
        f.mean_normal = (nbs_test::random_vec3(u, rng) - Vec3::Constant(0.5)).cast<float>();
        if (f.mean_normal.norm() > 1.0f) f.mean_normal.normalize();
        c.features = static_cast<int>(features_.size());
        features_.push_back(f);
      }
      cells_.push_back(c);
    }
  }
  [[nodiscard]] bool occupied(const VoxelKey& k) const { return cell(k).occupied; }
  [[nodiscard]] bool observed(const VoxelKey& k) const { return cell(k).observed; }
  [[nodiscard]] double probability(const VoxelKey& k) const { return cell(k).p; }

  /// A candidate of `rays` random rays (random walks through the cube, at most 12 voxels each).
  [[nodiscard]] CandidateStream candidate(std::uint64_t seed, int rays, bool precompute_entropy = true) const {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<int> key(0, n - 1), len(1, 12), axis(0, 2), step(0, 1);
    std::normal_distribution<double> g;
    std::set<std::uint64_t> visited;
    CandidateStream out;
    for (int r = 0; r < rays; ++r) {
      StreamRay ray;
      VoxelKey k{key(rng), key(rng), key(rng)};
      const Vec3 dir = nbs_test::random_vec3(g, rng).normalized();
      const int length = len(rng);
      for (int i = 0; i < length; ++i) {
        const Cell& c = cell(k);
        VoxelVisit v;
        v.key = k;
        v.probability = c.p;
        v.observed = c.observed;
        v.occupied = c.occupied;
        v.first_visit = visited.insert(k.pack()).second;
        v.features = c.features >= 0 ? &features_[static_cast<std::size_t>(c.features)] : nullptr;
        v.direction = dir;
        v.distance_m = 0.005 * (i + 0.5);
        v.index = static_cast<std::uint32_t>(i);
        v.entropy_bits = precompute_entropy ? voxel_entropy(c.p) : -1.0;
        ray.visits.push_back(v);
        if (c.occupied) {
          ray.end.hit = true;
          break;
        }
        const int a = axis(rng);
        k[a] = std::clamp(k[a] + (step(rng) ? 1 : -1), 0, n - 1);
      }
      ray.end.voxels = static_cast<std::uint32_t>(ray.visits.size());
      out.push_back(std::move(ray));
    }
    return out;
  }

private:
  struct Cell {
    double p = 0.5;
    bool observed = false, occupied = false;
    int features = -1;
  };
  [[nodiscard]] const Cell& cell(const VoxelKey& k) const {
    return cells_[static_cast<std::size_t>((k.z * n + k.y) * n + k.x)];
  }
  std::vector<Cell> cells_;
  std::vector<SurfaceFeatures> features_;
};

/// Feeds rays [from, to) of `s` to `t` (no begin_candidate). With `first_only`, only first visits are fed.
template <UtilityTerm T>
void feed(T& t, const CandidateStream& s, std::size_t from, std::size_t to, bool first_only = false) {
  for (std::size_t r = from; r < to; ++r) {
    t.begin_ray();
    for (const VoxelVisit& v : s[r].visits)
      if (!first_only || v.first_visit) t.visit(v);
    t.end_ray(s[r].end);
  }
}

/// begin_candidate(i), then the whole stream; returns value().
template <UtilityTerm T>
double evaluate(T& t, std::size_t i, const CandidateStream& s, bool first_only = false) {
  t.begin_candidate(i);
  feed(t, s, 0, s.size(), first_only);
  return static_cast<double>(t.value());
}

/// Expected value of candidate i's stream, or NaN for "no oracle".
using UtilityOracle = std::function<double(std::size_t candidate, const CandidateStream&)>;

/// Runs the UtilityTerm contract on copies of `prototype` over `rounds` random candidates of `world`.
template <class T>
void check_utility_term_conformance(const T& prototype, const RandomVoxelWorld& world, const UtilityOracle& oracle = {},
                                    int rounds = 12) {
  static_assert(UtilityTerm<T>);
  T reused = prototype;
  for (int round = 0; round < rounds; ++round) {
    INFO("round " << round);
    const auto i = static_cast<std::size_t>(round * 7 + 3);
    const CandidateStream s = world.candidate(1000 + static_cast<std::uint64_t>(round), 4 + round % 5);
    T fresh = prototype;
    const double v = evaluate(fresh, i, s);
    REQUIRE(std::isfinite(v));
    // Pure: a second fresh copy, a copy of `fresh` reset by begin_candidate, the term reused over all rounds.
    T again = prototype;
    CHECK(evaluate(again, i, s) == v);
    T copy = fresh;
    CHECK(evaluate(copy, i, s) == v);
    CHECK(evaluate(reused, i, s) == v);
    // A copy taken mid-stream continues exactly like the original.
    T a = prototype;
    a.begin_candidate(i);
    feed(a, s, 0, s.size() / 2);
    T b = a;
    feed(a, s, s.size() / 2, s.size());
    feed(b, s, s.size() / 2, s.size());
    CHECK(static_cast<double>(a.value()) == v);
    CHECK(static_cast<double>(b.value()) == v);
    // The precomputed entropy is only a cache: -1 (not precomputed) gives the same value up to rounding.
    T e = prototype;
    const CandidateStream s_raw = world.candidate(1000 + static_cast<std::uint64_t>(round), 4 + round % 5, false);
    CHECK(evaluate(e, i, s_raw) == Approx(v).epsilon(1e-12).margin(1e-12));
    if (visits_first_only(prototype)) {  // the evaluator then skips repeated visits
      T f = prototype;
      CHECK(evaluate(f, i, s, true) == v);
    }
    if constexpr (!term_needs_rays<T>()) {  // the evaluator then casts no ray at all
      T r = prototype;
      r.begin_candidate(i);
      CHECK(static_cast<double>(r.value()) == v);
    }
    if (oracle) {
      const double expected = oracle(i, s);
      CHECK(v == Approx(expected).epsilon(1e-12).margin(1e-12));
    }
  }
}

}  // namespace nbs::conformance
