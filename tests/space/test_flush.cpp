// SPDX-License-Identifier: BSD-3-Clause
// HashedBlockBackend flushing of cold blocks to disk: exact round trip (also after further updates and through const
// access), failed writes leave the space unchanged and are reported, memory drops, LRU budget, folder clean-up.
#include "nbs_catch.hpp"
#include "nbs_temp_dir.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "support/random_rays.hpp"
#include "support/synthetic_scan.hpp"
#include "support/test_boxes.hpp"

namespace {
using nbs::Vec3;
using nbs::VoxelKey;
using Space = nbs::ProbabilisticVoxelSpace<>;
namespace fs = std::filesystem;

using nbs_test::kFlushBox;
const nbs::test::SphereLspSetup kSetup{.profiles = 20, .rays_per_profile = 60, .noise_sigma_m = 0.0005};

nbs::Scan scan(int i) { return nbs::test::sphere_lsp_scan(kSetup, nbs::test::ring_position(kSetup, i, 6, 0.3), 40 + i); }

// A fresh folder under the system temp dir, removed at scope exit.
struct TempDir : nbs_test::TempDir {
  TempDir() : nbs_test::TempDir("nbs_test_flush_") {}
};

using StateMap = std::map<std::tuple<int, int, int>, nbs::ThesisState>;
StateMap states_of(const Space& s) {
  StateMap m;
  s.for_each([&](const VoxelKey& k, const nbs::ThesisState& st) { m[{k.x, k.y, k.z}] = st; });
  return m;
}

using nbs::test::random_rays;

// Per ray: visited keys and states, hit.
struct CastLog {
  std::vector<std::vector<std::tuple<int, int, int, nbs::ThesisState>>> visits;
  std::vector<bool> hit;
  bool operator==(const CastLog&) const = default;
};
CastLog cast_all(const Space& s, const std::vector<nbs::Ray>& rays, unsigned threads) {
  CastLog log;
  log.visits.resize(rays.size());
  const auto res = s.cast_rays(rays, threads, [&](std::size_t i, const VoxelKey& k, const nbs::ThesisState& st) {
    log.visits[i].push_back({k.x, k.y, k.z, st});
  });
  for (const auto& r : res) log.hit.push_back(r.hit);
  return log;
}
}  // namespace

TEST_CASE("flush to disk and reload is exact, also after further updates", "[space][flush]") {
  TempDir dir;
  Space flushed(0.004, kFlushBox), reference(0.004, kFlushBox);
  for (int i = 0; i < 3; ++i) {
    (void)flushed.integrate(scan(i));
    (void)reference.integrate(scan(i));
  }
  const StateMap before = states_of(reference);
  REQUIRE(states_of(flushed) == before);
  REQUIRE(before.size() > 1000);

  auto& backend = flushed.mutable_backend();
  backend.set_flush_policy({.directory = dir.path});
  const std::size_t resident = backend.resident_block_count();
  const std::size_t bytes = flushed.memory_bytes();
  REQUIRE(backend.flush_all() == resident);
  REQUIRE(backend.resident_block_count() == 0);
  REQUIRE(backend.flushed_block_count() == resident);
  REQUIRE(backend.block_count() == resident);
  REQUIRE(flushed.memory_bytes() < bytes / 10);
  REQUIRE(fs::is_directory(backend.flush_folder()));
  REQUIRE(backend.flush_folder().parent_path() == dir.path);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(backend.flush_folder())) files += e.path().extension() == ".blk" ? 1 : 0;
  REQUIRE(files == resident);

  // Const access reads the files: every state, count and bound identical; nothing is reloaded.
  REQUIRE(states_of(flushed) == before);
  REQUIRE(nbs::observed_count(flushed.backend()) == nbs::observed_count(reference.backend()));
  for (const auto& [k, st] : before) {
    const VoxelKey key{std::get<0>(k), std::get<1>(k), std::get<2>(k)};
    REQUIRE(flushed.state(key) == st);
    REQUIRE(flushed.observed(key));
  }
  const nbs::KeyBox kb = nbs::observed_key_bounds(flushed.backend()), kr = nbs::observed_key_bounds(reference.backend());
  REQUIRE(kb.min == kr.min);
  REQUIRE(kb.max == kr.max);
  const auto rays = random_rays(300, 9);
  const CastLog ref_cast = cast_all(reference, rays, 1);
  REQUIRE(cast_all(flushed, rays, 1) == ref_cast);
  REQUIRE(cast_all(flushed, rays, 3) == ref_cast);  // concurrent const reads of flushed blocks
  REQUIRE(backend.resident_block_count() == 0);
  REQUIRE(backend.flush_stats().blocks_reloaded == 0);

  // Further scans reload the blocks they write; the result equals the never-flushed space exactly.
  for (int i = 3; i < 6; ++i) {
    const auto a = flushed.integrate(scan(i));
    const auto b = reference.integrate(scan(i));
    REQUIRE(a.voxel_updates == b.voxel_updates);
    REQUIRE(a.voxels_same_scan == b.voxels_same_scan);
    REQUIRE(a.voxels_similar_beam == b.voxels_similar_beam);
  }
  REQUIRE(backend.flush_stats().blocks_reloaded > 0);
  REQUIRE(backend.flushed_block_count() > 0);  // blocks the later scans did not write stay on disk
  REQUIRE(states_of(flushed) == states_of(reference));
  // Resident and flushed blocks mixed: ray casts (whose per-thread reader caches resident blocks only) still agree.
  REQUIRE(backend.resident_block_count() > 0);
  REQUIRE(cast_all(flushed, rays, 2) == cast_all(reference, rays, 1));
  backend.reload_all();
  REQUIRE(backend.flushed_block_count() == 0);
  REQUIRE(states_of(flushed) == states_of(reference));
  REQUIRE(cast_all(flushed, rays, 2) == cast_all(reference, rays, 1));
}

TEST_CASE("automatic flushing of idle blocks gives the same space as no flushing", "[space][flush]") {
  TempDir dir;
  using LogOddsSpace = nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<nbs::LogOddsState>, nbs::LogOddsModel>;
  LogOddsSpace flushed(0.004, kFlushBox), reference(0.004, kFlushBox);
  flushed.mutable_backend().set_flush_policy({.directory = dir.path, .idle_scans = 1});
  std::size_t max_flushed = 0;
  for (int i = 0; i < 6; ++i) {
    const auto a = flushed.integrate(scan(i));
    const auto b = reference.integrate(scan(i));
    REQUIRE(a.voxel_updates == b.voxel_updates);
    REQUIRE(a.voxels_same_scan == b.voxels_same_scan);
    max_flushed = std::max(max_flushed, flushed.backend().flushed_block_count());
    // After each scan only the blocks written by it are resident; no block is lost.
    REQUIRE(flushed.backend().block_count() == reference.backend().block_count());
    REQUIRE(flushed.backend().resident_block_count() <= reference.backend().resident_block_count());
  }
  REQUIRE(max_flushed > 0);
  REQUIRE(flushed.backend().flush_stats().failed_writes == 0);
  std::map<std::tuple<int, int, int>, float> a, b;
  flushed.for_each([&](const VoxelKey& k, const nbs::LogOddsState& s) { a[{k.x, k.y, k.z}] = s.log_odds; });
  reference.for_each([&](const VoxelKey& k, const nbs::LogOddsState& s) { b[{k.x, k.y, k.z}] = s.log_odds; });
  REQUIRE(a == b);
}

TEST_CASE("a memory budget flushes the least recently written blocks", "[space][flush]") {
  TempDir dir;
  Space flushed(0.004, kFlushBox), reference(0.004, kFlushBox);
  for (int i = 0; i < 2; ++i) {
    (void)flushed.integrate(scan(i));
    (void)reference.integrate(scan(i));
  }
  const std::size_t budget = reference.memory_bytes() / 2;
  flushed.mutable_backend().set_flush_policy({.directory = dir.path, .memory_budget_bytes = budget});
  for (int i = 2; i < 6; ++i) {
    (void)flushed.integrate(scan(i));
    (void)reference.integrate(scan(i));
    REQUIRE(flushed.backend().memory_bytes() <= budget);
  }
  REQUIRE(reference.memory_bytes() > budget);
  REQUIRE(flushed.backend().flushed_block_count() > 0);
  REQUIRE(states_of(flushed) == states_of(reference));
}

TEST_CASE("a failed flush leaves the space unchanged and reports the error", "[space][flush]") {
  TempDir dir;
  const fs::path file = dir.path / "not_a_directory";
  std::ofstream(file) << "x";
  Space space(0.004, kFlushBox), reference(0.004, kFlushBox);
  for (int i = 0; i < 2; ++i) {
    (void)space.integrate(scan(i));
    (void)reference.integrate(scan(i));
  }
  auto& backend = space.mutable_backend();
  const std::size_t bytes = space.memory_bytes(), blocks = backend.resident_block_count();

  // Explicit flush: FileError naming the folder, nothing flushed.
  backend.set_flush_policy({.directory = file / "blocks"});
  try {
    (void)backend.flush_all();
    FAIL("flush_all into an unwritable directory did not throw");
  } catch (const nbs::FileError& e) {
    REQUIRE(std::string(e.what()).find("not_a_directory") != std::string::npos);
  }
  REQUIRE(backend.flush_stats().failed_writes == 1);
  REQUIRE(backend.flush_stats().blocks_written == 0);
  REQUIRE_FALSE(backend.flush_stats().last_error.empty());
  REQUIRE(backend.resident_block_count() == blocks);
  REQUIRE(backend.flushed_block_count() == 0);
  REQUIRE(space.memory_bytes() == bytes);
  REQUIRE(states_of(space) == states_of(reference));

  // Automatic policy: integrate does not throw, the failure is counted, the space equals the reference.
  backend.set_flush_policy({.directory = file / "blocks", .idle_scans = 1});
  for (int i = 2; i < 4; ++i) {
    const auto a = space.integrate(scan(i));
    const auto b = reference.integrate(scan(i));
    REQUIRE(a.voxel_updates == b.voxel_updates);
  }
  REQUIRE(backend.flush_stats().failed_writes == 3);
  REQUIRE(backend.flushed_block_count() == 0);
  REQUIRE(states_of(space) == states_of(reference));
  nbs::BlockFlushSetting no_directory;
  no_directory.idle_scans = 1;
  REQUIRE_THROWS_AS(backend.set_flush_policy(no_directory), nbs::InvalidArgument);
}

TEST_CASE("the flush folder is the backend's own and is removed with it", "[space][flush]") {
  TempDir dir;
  fs::path folder_a, folder_b;
  {
    nbs::HashedBlockBackend<nbs::ThesisState> a(0.01), b(0.01);
    a.set_flush_policy({.directory = dir.path});
    b.set_flush_policy({.directory = dir.path});
    nbs::ThesisState s;
    s.free = -100;
    s.surf = 7;
    s.direction = 3;
    a.set({1, 2, 3}, s);
    b.set({1, 2, 3}, nbs::ThesisState{});
    REQUIRE(a.flush_all() == 1);
    REQUIRE(b.flush_all() == 1);
    folder_a = a.flush_folder();
    folder_b = b.flush_folder();
    REQUIRE(folder_a != folder_b);
    REQUIRE(a.get({1, 2, 3}) == s);
    REQUIRE(b.get({1, 2, 3}) == nbs::ThesisState{});
    REQUIRE(b.observed({1, 2, 3}));
    // Moving keeps the flushed blocks and hands the folder over.
    nbs::HashedBlockBackend<nbs::ThesisState> c(std::move(a));
    REQUIRE(c.get({1, 2, 3}) == s);
    REQUIRE(c.flush_folder() == folder_a);
    REQUIRE(a.flush_folder().empty());  // NOLINT(bugprone-use-after-move): documented moved-from state
    REQUIRE(fs::exists(folder_a));
    // A damaged file is reported, not silently read as unknown.
    for (const auto& e : fs::directory_iterator(folder_b)) std::ofstream(e.path(), std::ios::trunc) << "garbage";
    REQUIRE_THROWS_AS(b.get({1, 2, 3}), nbs::FileError);
  }
  REQUIRE_FALSE(fs::exists(folder_a));
  REQUIRE_FALSE(fs::exists(folder_b));
}
