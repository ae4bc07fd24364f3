// SPDX-License-Identifier: BSD-3-Clause
// integrate(scan, threads): the rest of a walk after a crossing, walks restricted to a slab of keys, the balanced cut
// into slabs, and the parallel passes against integrate(scan) on one thread.
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "nbs/space/detail/block_walk.hpp"
#include "nbs/space/detail/slab_split.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs_random.hpp"
#include "nbs_temp_dir.hpp"
#include "support/random_scan.hpp"
#include "support/synthetic_scan.hpp"

namespace {
using nbs::Vec3;
using nbs::VoxelKey;
using nbs::detail::SegmentSetup;
using nbs::detail::SegmentWalker;

struct FullWalk {
  std::vector<VoxelKey> keys;  // keys[n]: the voxel after n steps
  std::vector<int> axes;       // axes[n]: the axis crossed by step n + 1
};
FullWalk full_walk(const SegmentSetup& q) {
  SegmentWalker w(q);
  FullWalk f{{w.key()}, {}};
  while (w.remaining() > 0) {
    f.axes.push_back(w.step());
    f.keys.push_back(w.key());
  }
  return f;
}

// For every crossing j along every axis: after_crossing's step count is where the full walk makes that crossing, and
// the walkers of the rest (SegmentWalker; CommonDenominatorStepper where it serves) take the full walk's remaining
// steps. Returns the number of crossings compared.
int check_rests(const Vec3& a, const Vec3& b) {
  const SegmentSetup q(a, b);
  const FullWalk f = full_walk(q);
  int compared = 0;
  for (int axis = 0; axis < 3; ++axis) {
    int seen = 0;
    for (std::size_t n = 0; n < f.axes.size(); ++n) {
      if (f.axes[n] != axis) continue;
      ++seen;
      const nbs::detail::SegmentRest r = nbs::detail::after_crossing(q, axis, seen);
      INFO("segment (" << a.transpose() << ") → (" << b.transpose() << "), axis " << axis << ", crossing " << seen);
      REQUIRE(r.done == static_cast<std::int64_t>(n) + 1);
      REQUIRE(r.rest.key == f.keys[n + 1]);
      REQUIRE(r.rest.steps() == static_cast<std::int64_t>(f.axes.size() - n - 1));
      REQUIRE(r.rest.end_key() == q.end_key());
      const FullWalk rest = full_walk(r.rest);
      REQUIRE(rest.keys == std::vector<VoxelKey>(f.keys.begin() + static_cast<std::ptrdiff_t>(n) + 1, f.keys.end()));
      if (auto fast = nbs::detail::CommonDenominatorStepper::make(r.rest)) {
        std::vector<int> axes;
        for (std::int64_t m = 0; m < r.rest.steps(); ++m) axes.push_back(fast->step());
        REQUIRE(axes == rest.axes);
      }
      ++compared;
    }
    REQUIRE(seen == q.remaining[axis]);
  }
  return compared;
}

// Records the blocks a walk looks up; otherwise the backend's own write access.
template <class B>
struct RecordingWriter {
  using Block = typename B::Block;
  static constexpr int kEdgeBits = B::kEdgeBits;
  static constexpr int kEdge = B::kEdge;
  static int local_index(const VoxelKey& k) { return B::local_index(k); }
  B* be;
  std::set<std::uint64_t> ids;
  Block& block(std::uint64_t id) {
    ids.insert(id);
    return be->block(id);
  }
};
}  // namespace

TEST_CASE("after_crossing: the rest of a walk after each crossing, ties included", "[space][dda][parallel]") {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-12.0, 12.0);
  std::uniform_int_distribution<int> lattice(-12 * 1024, 12 * 1024), corner(-9, 9);
  int compared = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 a = nbs_test::random_vec3(u, rng);
    compared += check_rests(a, nbs_test::random_vec3(u, rng));
  }
  // End points on the 1/1024 lattice and on voxel corners: exact ties between the axes' crossings.
  const auto on_lattice = [&] { return nbs_test::random_vec3([&] { return lattice(rng) / 1024.0; }); };
  const auto on_corner = [&] { return nbs_test::random_vec3([&] { return double(corner(rng)); }); };
  for (int i = 0; i < 400; ++i) {
    const Vec3 a = on_lattice();
    compared += check_rests(a, on_lattice());
  }
  for (int i = 0; i < 400; ++i) {
    const Vec3 a = on_corner();
    compared += check_rests(a, on_corner());
  }
  compared += check_rests(Vec3(0.5, 0.5, 0.5), Vec3(9.0, 9.0, 9.0));  // through corners, ends on faces moving up
  compared += check_rests(Vec3(9.0, 9.0, 9.0), Vec3(0.5, 0.5, 0.5));  // starts on corners moving down
  compared += check_rests(Vec3(3.5, -2.0, 1.5), Vec3(-4.0, 5.0, 1.5));  // ends on faces moving down and up
  REQUIRE(compared > 20000);
}

TEST_CASE("walk_untouched_slab visits the walk's voxels in the slab, in order, and looks up only their blocks",
          "[space][parallel]") {
  using Backend = nbs::HashedBlockBackend<nbs::ThesisState>;
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  std::uniform_int_distribution<int> cut(-24, 24), axis_of(0, 2), coin(0, 1), kind_of(0, 3);
  std::uniform_int_distribution<int> lattice(-20 * 1024, 20 * 1024), corner(-20, 20);
  // End points: real-valued, on the 1/1024 lattice, on voxel corners, or real-valued with Δx = Δy = 0.
  const auto point = [&](int kind) {
    if (kind == 1) return nbs_test::random_vec3([&] { return lattice(rng) / 1024.0; });
    if (kind == 2) return nbs_test::random_vec3([&] { return double(corner(rng)); });
    return nbs_test::random_vec3(u, rng);
  };
  int runs_split = 0, empty = 0;
  for (int i = 0; i < 3000; ++i) {
    const int kind = kind_of(rng);
    const Vec3 a = point(kind);
    const Vec3 b = kind == 3 ? Vec3(a.x(), a.y(), u(rng)) : point(kind);
    const SegmentSetup q(a, b);
    const int axis = axis_of(rng);
    const bool aligned = coin(rng) == 1, include_end = coin(rng) == 1;
    std::int32_t lo = cut(rng), hi = cut(rng);
    if (lo > hi) std::swap(lo, hi);
    if (aligned) lo *= Backend::kEdge, hi = hi * Backend::kEdge + Backend::kEdge;
    const nbs::detail::KeySlab slab{axis, lo, hi};
    // Oracle: the full walk's keys in the slab (its end voxel only if include_end).
    const FullWalk f = full_walk(q);
    std::vector<VoxelKey> want;
    for (std::size_t n = 0; n < f.keys.size(); ++n)
      if (slab.owns(f.keys[n]) && (include_end || n + 1 < f.keys.size())) want.push_back(f.keys[n]);
    Backend be(0.01);
    (void)be.next_epoch();
    RecordingWriter<Backend> w{&be, {}};
    std::vector<VoxelKey> got;
    int ends = 0;
    const std::int64_t n = nbs::detail::walk_untouched_slab(
        w, q, axis, lo, hi, include_end, [&](Backend::Block&, int idx, const VoxelKey& bk, bool is_end) {
          got.push_back(nbs::detail::voxel_key_in_block<Backend>(bk, idx));
          if (is_end) {
            ++ends;
            REQUIRE(got.back() == q.end_key());
          }
        });
    INFO("segment (" << a.transpose() << ") → (" << b.transpose() << "), axis " << axis << ", slab [" << lo << ", "
                     << hi << ")");
    REQUIRE(got == want);
    REQUIRE(n == static_cast<std::int64_t>(want.size()));
    REQUIRE(ends == (include_end && slab.owns(q.end_key()) ? 1 : 0));
    if (aligned)
      for (const std::uint64_t id : w.ids) REQUIRE(slab.owns(Backend::block_origin(id)));
    runs_split += !want.empty() && want.size() + 1 < f.keys.size() ? 1 : 0;
    empty += want.empty() ? 1 : 0;
  }
  REQUIRE(runs_split > 400);  // many walks cross a slab face
  REQUIRE(empty > 200);
}

TEST_CASE("balance_slabs: block-aligned slabs that partition the keys and balance the walks' voxels",
          "[space][parallel]") {
  using Walk = std::pair<VoxelKey, VoxelKey>;
  std::vector<Walk> walks;
  const auto keys_of = [&](std::size_t k) {
    const Walk& w = walks[k];
    return std::optional{nbs::detail::WeightedWalk{w.first, w.second, 1.0 + w.second.y - w.first.y}};
  };
  REQUIRE(nbs::detail::balance_slabs(0, keys_of, 4, 3).size() == 1);
  // Walks along y, spread over y = 0 … 799 and inside one block in x and z: only y splits them.
  std::mt19937_64 rng(33);
  std::uniform_int_distribution<int> start(0, 780), len(1, 19), off(0, 7);
  for (int i = 0; i < 3000; ++i) {
    const int y0 = start(rng), x = off(rng), z = off(rng);
    walks.push_back({VoxelKey{x, y0, z}, VoxelKey{x, y0 + len(rng), z}});
  }
  REQUIRE(nbs::detail::balance_slabs(walks.size(), keys_of, 1, 3).size() == 1);
  for (const unsigned n : {2u, 3u, 4u}) {
    const auto slabs = nbs::detail::balance_slabs(walks.size(), keys_of, n, 3);
    REQUIRE(slabs.size() == n);
    REQUIRE(slabs.front().lo == VoxelKey::kMinIndex);
    REQUIRE(slabs.back().hi == VoxelKey::kMaxIndex + 1);
    double total = 0.0;
    std::vector<double> load(n, 0.0);
    for (std::size_t s = 0; s < n; ++s) {
      REQUIRE(slabs[s].axis == 1);
      if (s > 0) REQUIRE(slabs[s].lo == slabs[s - 1].hi);
      REQUIRE(slabs[s].lo < slabs[s].hi);
      if (s > 0) REQUIRE(slabs[s].lo % 8 == 0);
    }
    for (const Walk& w : walks)
      for (int y = w.first.y; y <= w.second.y; ++y) {
        total += 1.0;
        for (std::size_t s = 0; s < n; ++s) load[s] += slabs[s].owns(VoxelKey{0, y, 0}) ? 1.0 : 0.0;
      }
    for (const double l : load) REQUIRE(std::abs(l / total - 1.0 / n) < 0.03);  // a block is ~1 % of the walks
  }
}

namespace {
template <class Space>
std::vector<std::pair<VoxelKey, typename Space::State>> voxels_in_order(const Space& s) {
  std::vector<std::pair<VoxelKey, typename Space::State>> v;
  s.for_each([&](const VoxelKey& k, const typename Space::State& st) { v.push_back({k, st}); });
  return v;
}

// Integrates the same scans with 1 thread and with `threads` (into spaces flushing with `flush`, if set): every
// statistic, every voxel state, the for_each order and the observed and block counts agree, and the parallel space
// did split the scans.
template <class Model, class MakeScan>
void check_parallel_equals_serial(double resolution_m, const Model& model, unsigned threads, int scans,
                                  MakeScan&& make_scan, const nbs::BlockFlushSetting* flush = nullptr) {
  using State = typename Model::State;
  using Space = nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<State>, Model>;
  const nbs::Aabb box{Vec3(-0.1, -0.1, 0.0), Vec3(0.1, 0.1, 0.2)};
  Space serial(resolution_m, box, model), parallel(resolution_m, box, model);
  if (flush) {
    serial.mutable_backend().set_flush_policy(*flush);
    parallel.mutable_backend().set_flush_policy(*flush);
  }
  for (int k = 0; k < scans; ++k) {
    const nbs::Scan scan = make_scan(k);
    const auto a = serial.integrate(scan), b = parallel.integrate(scan, threads);
    INFO("resolution " << resolution_m << ", " << threads << " threads, scan " << k << ", " << scan.size() << " points");
    // One thread per slab; fewer slabs where the walks span fewer blocks (a 0.2 m box at 4 mm: 7 blocks an axis).
    REQUIRE(parallel.last_integrate_threads() <= std::min<std::size_t>(threads, scan.size() / Space::kBeamsPerThread));
    REQUIRE(parallel.last_integrate_threads() >= std::min(threads, 3u));
    REQUIRE(serial.last_integrate_threads() == 1);
    REQUIRE(a.integrated == b.integrated);
    REQUIRE(a.rejected_outside_bounds == b.rejected_outside_bounds);
    REQUIRE(a.voxel_updates == b.voxel_updates);
    REQUIRE(a.voxels_same_scan == b.voxels_same_scan);
    REQUIRE(a.voxels_similar_beam == b.voxels_similar_beam);
    REQUIRE(a.voxel_updates > 0);
  }
  REQUIRE(serial.backend().size() == parallel.backend().size());
  REQUIRE(serial.backend().block_count() == parallel.backend().block_count());
  REQUIRE(serial.backend().flushed_block_count() == parallel.backend().flushed_block_count());
  REQUIRE(serial.backend().flush_stats().blocks_reloaded == parallel.backend().flush_stats().blocks_reloaded);
  if (flush) REQUIRE(serial.backend().flush_stats().blocks_reloaded > 0);
  const auto one = voxels_in_order(serial), many = voxels_in_order(parallel);
  REQUIRE(one.size() == many.size());
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < one.size(); ++i)
    mismatches += one[i].first == many[i].first && one[i].second == many[i].second ? 0 : 1;
  REQUIRE(mismatches == 0);  // same states, visited in the same order
}
}  // namespace

TEST_CASE("integrate(scan, threads) gives the states and statistics of integrate(scan)", "[space][pvs][parallel]") {
  nbs::ThesisModel::Setting noisy;
  noisy.sigma_m = [](double d) { return 0.002 * d * d + 0.0002; };
  const nbs::ThesisModel thesis(noisy);
  for (const unsigned threads : {2u, 3u, 8u}) {
    std::mt19937_64 rng(34 + threads);
    const int profiles = threads == 8 ? 90 : 40;  // 100 beams each, one thread per 1,024
    const auto random = [&](int) { return nbs::test::random_scan(rng, profiles, 100); };
    check_parallel_equals_serial(0.004, thesis, threads, 3, random);
    check_parallel_equals_serial(0.002, nbs::LogOddsModel{}, threads, 2, random);
    if (threads == 8) continue;
    // Laser-stripe scans of a sphere: neighbouring beams from neighbouring origins re-walk the same voxels.
    const nbs::test::SphereLspSetup setup{.profiles = 60, .rays_per_profile = 120, .noise_sigma_m = 0.0005};
    const auto lsp = [&](int k) {
      return nbs::test::sphere_lsp_scan(setup, nbs::test::ring_position(setup, k, 4, 0.3), 50 + k);
    };
    check_parallel_equals_serial(0.003, thesis, threads, 4, lsp);
  }
  // A scan of fewer than 2 · kBeamsPerThread points runs on the calling thread.
  nbs::ProbabilisticVoxelSpace<> space(0.004, nbs::Aabb{Vec3(-0.1, -0.1, 0.0), Vec3(0.1, 0.1, 0.2)});
  std::mt19937_64 rng(40);
  (void)space.integrate(nbs::test::random_scan(rng, 20, 100), 4);
  REQUIRE(space.last_integrate_threads() == 1);
}

TEST_CASE("integrate(scan, threads) with flushing: blocks reloaded and flushed as on one thread",
          "[space][pvs][parallel][flush]") {
  const nbs_test::TempDir dir("nbs_test_parallel_flush_");
  nbs::BlockFlushSetting flush;
  flush.directory = dir.path;
  flush.idle_scans = 1;  // every block not written by the last scan goes to disk
  std::mt19937_64 rng(41);
  const auto random = [&](int) { return nbs::test::random_scan(rng, 40, 100); };
  check_parallel_equals_serial(0.004, nbs::ThesisModel{}, 3, 5, random, &flush);
}
