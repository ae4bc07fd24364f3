// SPDX-License-Identifier: BSD-3-Clause
// PlannerSetting::flush (issue 22, workspace runs): the planner switches block flushing on in its voxel space; the
// oracle is the same loop without flushing — identical plans and an identical space — while blocks really went to
// disk and came back.

#include "nbs_catch.hpp"
#include "nbs_temp_dir.hpp"

#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <tuple>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "support/analytic_scanner.hpp"
#include "support/same_plan.hpp"

namespace {

namespace fs = std::filesystem;

struct TempDir : nbs_test::TempDir {
  TempDir() : nbs_test::TempDir("nbs_test_planner_flush_") {}
};

template <class Space>
std::map<std::tuple<int, int, int>, nbs::ThesisState> states_of(const Space& s) {
  std::map<std::tuple<int, int, int>, nbs::ThesisState> m;
  s.for_each([&](const nbs::VoxelKey& k, const nbs::ThesisState& st) { m[{k.x, k.y, k.z}] = st; });
  return m;
}

static_assert(nbs::FlushableBackend<nbs::HashedBlockBackend<nbs::ThesisState>>);
static_assert(!nbs::FlushableBackend<int>);

}  // namespace

TEST_CASE("planner flush setting: identical plans and space with blocks flushed after every scan", "[planner][flush]") {
  TempDir dir;
  const nbs::test::SphereOnPedestal sphere;
  nbs::SimulationSetting sim;
  sim.seed = 4;
  sim.max_scans = 4;
  nbs::PlannerSetting plain;
  plain.threads = 2;
  nbs::PlannerSetting flushing = plain;
  flushing.flush.directory = dir.path;
  flushing.flush.memory_budget_bytes = 1;  // after every scan every block goes to disk
  nbs::NbsPlanner<> a({}, nbs::test::light_lsp(), nbs::test::sphere_box(), plain);
  nbs::NbsPlanner<> b({}, nbs::test::light_lsp(), nbs::test::sphere_box(), flushing);
  const auto ra = nbs::run_simulation(a, sphere, sim);
  const auto rb = nbs::run_simulation(b, sphere, sim);
  REQUIRE(ra.records.size() >= 3);
  nbs::test::check_same_plan(ra, rb);
  const nbs::BlockFlushStats& st = b.space().backend().flush_stats();
  INFO("written " << st.blocks_written << ", reloaded " << st.blocks_reloaded << ", failed " << st.failed_writes);
  CHECK(st.blocks_written > 0);
  CHECK(st.blocks_reloaded > 0);  // later scans wrote into flushed blocks
  CHECK(st.failed_writes == 0);
  CHECK(a.space().backend().flush_stats().blocks_written == 0);
  CHECK(states_of(a.space()) == states_of(b.space()));
}

TEST_CASE("planner flush setting: a rule without a directory is refused before anything is built", "[planner][flush]") {
  nbs::PlannerSetting s;
  s.flush.memory_budget_bytes = 1 << 20;
  CHECK_THROWS_WITH(nbs::NbsPlanner<>({}, nbs::test::light_lsp(), nbs::test::sphere_box(), s),
                    nbs_test::Contains("PlannerSetting.flush"));
  s.flush = {};
  s.flush.directory = "/nonexistent-but-unused";  // a directory without a rule: flushing stays off
  CHECK(!s.flush.enabled());
  CHECK_NOTHROW(nbs::NbsPlanner<>({}, nbs::test::light_lsp(), nbs::test::sphere_box(), s));
}
