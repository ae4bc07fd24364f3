// SPDX-License-Identifier: BSD-3-Clause
// All-or-nothing integration with flushed blocks: a flushed block file that is truncated, corrupted or deleted makes
// integrate throw FileError with the voxel states, totals and flush counters unchanged; a failed flush after a scan
// is reported in BlockFlushStats and the scan still succeeds.
#include "nbs_catch.hpp"
#include "nbs_temp_dir.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <csignal>
#include <cstdint>
#include <iterator>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "nbs/space/probabilistic_voxel_space.hpp"
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

struct TempDir : nbs_test::TempDir {
  TempDir() : nbs_test::TempDir("nbs_test_flush_atomic_") {}
};

// FNV-1a over (key, state bytes) of every observed voxel in for_each order (sorted by block id for flushed blocks,
// so compared only between spaces with the same residency), plus the count.
struct Digest {
  std::uint64_t hash = 1469598103934665603ull;
  std::size_t count = 0;
  bool operator==(const Digest&) const = default;
};
Digest digest(const Space& s) {
  std::vector<std::pair<std::uint64_t, nbs::ThesisState>> all;
  s.for_each([&](const VoxelKey& k, const nbs::ThesisState& st) { all.push_back({k.pack(), st}); });
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Digest d;
  const auto mix = [&d](const void* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) d.hash = (d.hash ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  };
  for (const auto& [k, st] : all) {
    mix(&k, sizeof k);
    mix(&st.free, sizeof st.free);  // field by field: the struct has padding
    mix(&st.surf, sizeof st.surf);
    mix(&st.spec, sizeof st.spec);
    mix(&st.direction, sizeof st.direction);
  }
  d.count = all.size();
  return d;
}
bool same_totals(const nbs::IntegrationStats& a, const nbs::IntegrationStats& b) {
  return a.points == b.points && a.integrated == b.integrated && a.voxel_updates == b.voxel_updates &&
         a.voxels_same_scan == b.voxels_same_scan && a.voxels_similar_beam == b.voxels_similar_beam;
}
}  // namespace

TEST_CASE("integrate with a damaged flushed block throws and changes nothing", "[space][flush][atomic]") {
  enum class Damage { truncate, corrupt, remove };
  const Damage damage = GENERATE(Damage::truncate, Damage::corrupt, Damage::remove);
  TempDir dir;
  Space s(0.004, kFlushBox);
  for (int i = 0; i < 3; ++i) (void)s.integrate(scan(i));
  auto& backend = s.mutable_backend();
  backend.set_flush_policy({.directory = dir.path});
  REQUIRE(backend.flush_all() > 0);
  // Damage every other block file (by name): the next scan reads good blocks (which an integrate without staging
  // would already update) and damaged ones.
  std::vector<fs::path> paths;
  for (const auto& e : fs::directory_iterator(backend.flush_folder()))
    if (e.path().extension() == ".blk") paths.push_back(e.path());
  std::sort(paths.begin(), paths.end());
  const std::size_t files = paths.size();
  for (std::size_t i = 1; i < paths.size(); i += 2) {
    const fs::directory_entry e(paths[i]);
    if (damage == Damage::truncate) {
      fs::resize_file(e.path(), fs::file_size(e.path()) / 2);
    } else if (damage == Damage::corrupt) {
      std::fstream f(e.path(), std::ios::in | std::ios::out | std::ios::binary);
      const char bad[4] = {'X', 'X', 'X', 'X'};
      f.write(bad, sizeof bad);  // the magic
    } else {
      fs::remove(e.path());
    }
  }
  REQUIRE(files == backend.flushed_block_count());
  // Const reads of damaged blocks throw, so the state is compared by counts here and by digest in the next test.
  const nbs::IntegrationStats totals = s.totals();
  const std::size_t flushed = backend.flushed_block_count(), resident = backend.resident_block_count();
  const nbs::BlockFlushStats stats = backend.flush_stats();
  const std::size_t observed = backend.size();
  REQUIRE_THROWS_AS(s.integrate(scan(3)), nbs::FileError);
  CHECK(same_totals(s.totals(), totals));
  CHECK(backend.flushed_block_count() == flushed);
  CHECK(backend.resident_block_count() == resident);
  CHECK(backend.size() == observed);
  CHECK(backend.flush_stats().blocks_reloaded == stats.blocks_reloaded);
  CHECK(backend.flush_stats().blocks_written == stats.blocks_written);
}

TEST_CASE("integrate with a damaged flushed block: voxel digest unchanged, later good scans as without failure",
          "[space][flush][atomic]") {
  // Every other block file is truncated, then restored after the failed integrate.
  TempDir dir;
  Space s(0.004, kFlushBox), reference(0.004, kFlushBox);
  for (int i = 0; i < 3; ++i) {
    (void)s.integrate(scan(i));
    (void)reference.integrate(scan(i));
  }
  auto& backend = s.mutable_backend();
  backend.set_flush_policy({.directory = dir.path});
  REQUIRE(backend.flush_all() > 0);
  const Digest before = digest(s);
  REQUIRE(before == digest(reference));
  // Truncate every other file (by name), keeping a copy to restore.
  std::vector<std::pair<fs::path, std::string>> saved;
  for (const auto& e : fs::directory_iterator(backend.flush_folder())) {
    if (e.path().extension() != ".blk") continue;
    std::ifstream in(e.path(), std::ios::binary);
    saved.push_back({e.path(), std::string(std::istreambuf_iterator<char>(in), {})});
  }
  std::sort(saved.begin(), saved.end());
  for (std::size_t i = 1; i < saved.size(); i += 2) fs::resize_file(saved[i].first, saved[i].second.size() / 2);
  const nbs::IntegrationStats totals = s.totals();
  REQUIRE_THROWS_AS(s.integrate(scan(3)), nbs::FileError);
  CHECK(same_totals(s.totals(), totals));
  for (const auto& [p, bytes] : saved) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  CHECK(digest(s) == before);  // nothing was written into any block
  for (int i = 3; i < 5; ++i) {
    const auto a = s.integrate(scan(i));
    const auto b = reference.integrate(scan(i));
    CHECK(a.voxel_updates == b.voxel_updates);
  }
  CHECK(same_totals(s.totals(), reference.totals()));
  CHECK(digest(s) == digest(reference));
}

TEST_CASE("a failed flush after a scan is reported, the scan succeeds and the blocks stay resident",
          "[space][flush][atomic]") {
  TempDir dir;
  // The flush directory's parent is a regular file: no folder can be created, also as root.
  const fs::path file = dir.path / "not_a_dir";
  std::ofstream(file) << "x";
  Space s(0.004, kFlushBox), reference(0.004, kFlushBox);
  s.mutable_backend().set_flush_policy({.directory = file / "flush", .idle_scans = 1});
  for (int i = 0; i < 3; ++i) {
    const auto a = s.integrate(scan(i));
    const auto b = reference.integrate(scan(i));
    CHECK(a.voxel_updates == b.voxel_updates);
  }
  const auto& st = s.backend().flush_stats();
  CHECK(st.failed_writes > 0);
  CHECK(st.blocks_written == 0);
  CHECK(!st.last_error.empty());
  CHECK(s.backend().flushed_block_count() == 0);
  CHECK(digest(s) == digest(reference));
  CHECK(same_totals(s.totals(), reference.totals()));
}

TEST_CASE("a write that fails mid-file (file-size limit) leaves no block file behind and loses nothing",
          "[space][flush][atomic]") {
  // RLIMIT_FSIZE makes write(2) fail with EFBIG once a file would pass 64 bytes: the header is written, the
  // voxel states are not — a full disk as the kernel reports it, injected without a hook in the library.
  struct FileSizeLimit {
    rlimit saved{};
    void (*old_handler)(int) = nullptr;
    explicit FileSizeLimit(rlim_t bytes) {
      REQUIRE(getrlimit(RLIMIT_FSIZE, &saved) == 0);
      old_handler = std::signal(SIGXFSZ, SIG_IGN);  // else the process is killed instead of write failing
      rlimit lower = saved;
      lower.rlim_cur = bytes;
      REQUIRE(setrlimit(RLIMIT_FSIZE, &lower) == 0);
    }
    ~FileSizeLimit() {
      setrlimit(RLIMIT_FSIZE, &saved);
      std::signal(SIGXFSZ, old_handler);
    }
  };
  TempDir dir;
  Space s(0.004, kFlushBox), reference(0.004, kFlushBox);
  s.mutable_backend().set_flush_policy({.directory = dir.path, .idle_scans = 1});
  for (int i = 0; i < 2; ++i) {
    (void)s.integrate(scan(i));
    (void)reference.integrate(scan(i));
  }
  const std::uint64_t written = s.backend().flush_stats().blocks_written;
  REQUIRE(written > 0);  // flushing works before the limit
  const std::size_t files_before = s.backend().flushed_block_count();
  {
    const FileSizeLimit limit(64);
    for (int i = 2; i < 4; ++i) {
      const auto a = s.integrate(scan(i));
      const auto b = reference.integrate(scan(i));
      CHECK(a.voxel_updates == b.voxel_updates);
    }
  }
  const auto& st = s.backend().flush_stats();
  CHECK(st.failed_writes > 0);
  CHECK(st.blocks_written == written);
  CHECK(st.last_error.find("failed") != std::string::npos);
  INFO(st.last_error);
  std::size_t blk = 0, tmp = 0;
  for (const auto& e : fs::directory_iterator(s.backend().flush_folder())) {
    blk += e.path().extension() == ".blk" ? 1 : 0;
    tmp += e.path().extension() == ".tmp" ? 1 : 0;
  }
  CHECK(tmp == 0);  // no half-written file left
  CHECK(blk == s.backend().flushed_block_count());
  CHECK(s.backend().flushed_block_count() <= files_before);  // nothing new was flushed (some were reloaded)
  CHECK(digest(s) == digest(reference));
  CHECK(same_totals(s.totals(), reference.totals()));
  // With the limit lifted, flushing resumes and the space still equals the reference.
  const std::uint64_t written_during_limit = st.blocks_written;
  (void)s.integrate(scan(4));
  (void)reference.integrate(scan(4));
  CHECK(s.backend().flush_stats().blocks_written > written_during_limit);
  CHECK(digest(s) == digest(reference));
}
