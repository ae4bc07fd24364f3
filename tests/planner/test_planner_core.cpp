// SPDX-License-Identifier: BSD-3-Clause
// Core-only planner tests (no Embree): bad input and statuses, the runtime facade's codes, and the closed loop on an
// analytic sphere standing on the pedestal (determinism over thread counts, termination, BS → HR switch).

#include "nbs_catch.hpp"

#include <algorithm>
#include <set>
#include <string>
#include <variant>

#include "nbs/mesh/invariants.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/runtime_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sensor/presets.hpp"
#include "support/analytic_scanner.hpp"
#include "support/loop_settings.hpp"
#include "support/same_plan.hpp"

namespace {

using nbs::Aabb;
using nbs::Vec3;

using nbs::test::light_lsp;
using nbs::test::sphere_box;

using nbs::test::loop_setting;
using nbs::test::setting;

using nbs::test::check_same_plan;

}  // namespace

TEST_CASE("planner: invalid parameters, sensor, box and setting throw InvalidArgument", "[planner]") {
  const Aabb box = sphere_box();
  const auto lsp = light_lsp();
  nbs::Parameters bad;
  bad.voxel_size_m = -0.005;
  CHECK_THROWS_AS(nbs::NbsPlanner<>(bad, lsp, box), nbs::InvalidArgument);
  bad = {};
  bad.target_coverage = 1.5;
  CHECK_THROWS_AS(nbs::NbsPlanner<>(bad, lsp, box), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::NbsPlanner<>({}, lsp, Aabb{}), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::NbsPlanner<>({}, lsp, Aabb{Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.0)}), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::NbsPlanner<>({}, lsp, Aabb{Vec3(0, 0, 0), Vec3(0.1, 0.1, NAN)}), nbs::InvalidArgument);
  auto bad_lsp = lsp;
  bad_lsp.fan_angle_rad = 0.0;
  CHECK_THROWS_AS(nbs::NbsPlanner<>({}, bad_lsp, box), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::NbsPlanner<>({}, lsp, box, setting(0)), nbs::InvalidArgument);
  for (const nbs::CoarseToFine bad_refine : {nbs::CoarseToFine{0, 32}, nbs::CoarseToFine{4, 0}}) {
    nbs::PlannerSetting s = setting(1);
    s.refine = bad_refine;
    CHECK_THROWS_AS(nbs::NbsPlanner<>({}, lsp, box, s), nbs::InvalidArgument);
  }
  nbs::PlannerSetting far;
  far.standoff_m = 0.9;  // outside the 0.15–0.45 m working range
  CHECK_THROWS_AS(nbs::NbsPlanner<>({}, lsp, box, far), nbs::InvalidArgument);
  nbs::SimulationSetting sim;
  sim.max_scans = 0;
  CHECK_THROWS_AS(sim.validate(), nbs::InvalidArgument);
}

TEST_CASE("planner: empty mesh gives nothing_seen_yet, never a silent empty plan", "[planner]") {
  nbs::NbsPlanner<> p({}, light_lsp(), sphere_box());
  const nbs::PlanResult r = p.next_best_scan();
  CHECK(r.status == nbs::PlanStatus::nothing_seen_yet);
  CHECK_FALSE(r.ok());
  CHECK_FALSE(r.candidate.has_value());
  CHECK_THROWS_AS(r.path(), nbs::InvalidArgument);
  CHECK(p.scans() == 0);
  // A first scan is always available (Sec. 4.1) and lies at d_s outside the box, looking into it.
  const nbs::LinearScanPath first = p.first_scan(7);
  CHECK_FALSE(p.unknown_area().contains(first.start().position()));
}

TEST_CASE("planner: a scan entirely outside the bounding box gets a clear status and changes nothing", "[planner]") {
  nbs::NbsPlanner<> p({}, light_lsp(), sphere_box());
  const nbs::test::SphereOnPedestal far_sphere{Vec3(0.5, 0.0, 0.04), 0.04};  // outside the box
  const nbs::LinearScanPath path(nbs::Viewpoint::look_at(Vec3(0.5, -0.3, 0.04), Vec3(0.5, 0.0, 0.04)),
                                 Vec3(0.5, -0.3, 0.08));
  const nbs::Scan scan = far_sphere.scan(path, p.sensor(), 1);
  REQUIRE(scan.size() > 100);
  const nbs::IntegrationReport r = p.integrate(scan);
  CHECK(r.status == nbs::IntegrationStatus::outside_unknown_area);
  CHECK(r.points == scan.size());
  CHECK(r.points_inside == 0);
  CHECK(r.scans == 1);
  CHECK(p.mesh().vertex_count() == 0);
  CHECK(p.space().totals().integrated == 0);
  CHECK(p.next_best_scan().status == nbs::PlanStatus::nothing_seen_yet);

  CHECK(p.integrate(nbs::Scan{}).status == nbs::IntegrationStatus::empty_scan);
  nbs::Scan broken = scan;
  broken.points[3].x() = NAN;
  CHECK_THROWS_AS(p.integrate(broken), nbs::InvalidArgument);
  CHECK(p.scans() == 2);  // the invalid scan was not counted
}

TEST_CASE("planner: a scan the mesh rejects leaves the planner unchanged (space, mesh, n_s, next plan)",
          "[planner][validation]") {
  // A finite point far outside the mesh's coordinate range passes Scan::validate and is clipped by the voxel space,
  // which would update the free voxels of its beam inside the box; the mesh then throws. The planner checks the
  // mesh first (ChecksScans), so nothing changes.
  const nbs::test::SphereOnPedestal sphere;
  nbs::NbsPlanner<> p({}, light_lsp(), sphere_box()), twin({}, light_lsp(), sphere_box());
  const nbs::LinearScanPath first_path(nbs::Viewpoint::look_at(Vec3(0.0, -0.3, 0.04), Vec3(0.0, 0.0, 0.04)),
                                       Vec3(0.0, -0.3, 0.08));
  const nbs::Scan first = sphere.scan(first_path, p.sensor(), 1);
  REQUIRE(first.size() > 100);
  (void)p.integrate(first);
  (void)twin.integrate(first);
  const nbs::LinearScanPath second_path(nbs::Viewpoint::look_at(Vec3(-0.3, 0.0, 0.04), Vec3(0.0, 0.0, 0.04)),
                                        Vec3(-0.3, 0.0, 0.08));
  nbs::Scan bad = sphere.scan(second_path, p.sensor(), 2);
  REQUIRE(bad.size() > 100);
  const std::size_t last = bad.size() - 1;
  bad.points[last] = bad.origin(last) + 1e30 * bad.line_of_sight(last);
  REQUIRE_NOTHROW(bad.validate());

  const nbs::IntegrationStats totals = p.space().totals();
  const std::size_t vertices = p.mesh().vertex_count(), faces = p.mesh().face_count();
  CHECK_THROWS_AS(p.integrate(bad), nbs::InvalidArgument);
  CHECK(p.scans() == 1);
  CHECK(p.space().totals().integrated == totals.integrated);
  CHECK(p.space().totals().voxel_updates == totals.voxel_updates);
  CHECK(p.space().totals().points == totals.points);
  CHECK(p.mesh().vertex_count() == vertices);
  CHECK(p.mesh().face_count() == faces);
  const nbs::PlanResult a = p.next_best_scan(), b = twin.next_best_scan();
  REQUIRE(a.status == b.status);
  REQUIRE(a.ok());
  CHECK(a.path().start().pose().matrix() == b.path().start().pose().matrix());
  CHECK(a.path().end_position() == b.path().end_position());
}

TEST_CASE("loop: a scanner that throws mid-run leaves the planner as after its last good scan", "[planner][loop]") {
  // A scan source failing (device lost, driver error) throws out of run_simulation before integrate: the planner
  // keeps the scans it had, and plans exactly as a twin that stopped there.
  struct FailingScanner {
    const nbs::test::SphereOnPedestal* sphere;
    int fail_at;  // 1-based call that throws
    mutable int calls = 0;
    nbs::Scan scan(const nbs::LinearScanPath& path, const nbs::LaserStripeProfiler& s, std::uint64_t seed) const {
      if (++calls == fail_at) throw nbs::FileError("scanner: device lost mid-scan");
      return sphere->scan(path, s, seed);
    }
  };
  const nbs::test::SphereOnPedestal sphere;
  nbs::NbsPlanner<> p({}, light_lsp(), sphere_box()), twin({}, light_lsp(), sphere_box());
  const FailingScanner failing{&sphere, 3};
  CHECK_THROWS_WITH(nbs::run_simulation(p, failing, loop_setting(5, 6)), nbs_test::Contains("device lost"));
  const auto ran = nbs::run_simulation(twin, sphere, loop_setting(5, 2));
  REQUIRE(ran.records.size() == 2);
  (void)twin.next_best_scan();  // the failing run planned its third scan before the scanner threw
  CHECK(p.scans() == 2);
  CHECK(p.mesh().vertex_count() == twin.mesh().vertex_count());
  CHECK(p.mesh().face_count() == twin.mesh().face_count());
  CHECK(p.space().totals().voxel_updates == twin.space().totals().voxel_updates);
  CHECK(p.estimated_coverage() == twin.estimated_coverage());
  const nbs::PlanResult a = p.next_best_scan(), b = twin.next_best_scan();
  REQUIRE(a.status == b.status);
  REQUIRE(a.ok());
  CHECK(a.path().start().pose().matrix() == b.path().start().pose().matrix());
  CHECK(a.path().end_position() == b.path().end_position());
}

TEST_CASE("runtime facade: every method code parses and round-trips; unknown codes are rejected", "[planner]") {
  std::set<std::string> codes;
  for (const nbs::Method& m : nbs::kAllMethods) {
    const std::string code = nbs::format_method(m);
    CHECK(nbs::parse_method(code) == m);
    codes.insert(code);
  }
  CHECK(codes.size() == nbs::kAllMethods.size());
  CHECK(codes.size() == 22);
  // The facade hands RuntimeModels::selection (SGU's β, d_min, ...) to its selection utility.
  nbs::RuntimeModels models;
  models.selection.unseen_weight = 3.5;
  models.selection.unseen_min_edge_distance_m = 0.02;
  const nbs::RuntimePlanner rp(nbs::parse_method("SGU_H"), {}, light_lsp(), sphere_box(), setting(1), models);
  const auto* bh = std::get_if<nbs::RuntimePlannerOf<nbs::SearchSpace::boundary_hole>>(&rp.variant());
  REQUIRE(bh != nullptr);
  CHECK(bh->utility.setting.selection == nbs::Selection::surface_gain_unseen);
  CHECK(bh->utility.setting.options == models.selection);
  for (const char* c : {"R_S", "R_B", "R_H", "I_S", "I_B", "I_H", "Q_S", "Q_B", "Q_H", "C_S", "C_B", "C_H", "OA_H",
                        "UV_H", "RSV_H", "RSE_H", "PC_H", "AE_H", "VG_H", "SG_H", "SGU_H", "SEE"})
    CHECK(codes.count(c) == 1);
  CHECK(nbs::parse_method(" c_h ") == nbs::Method{nbs::Selection::ig_quality, nbs::SearchSpace::boundary_hole});
  CHECK(nbs::parse_method("r_s") == nbs::Method{nbs::Selection::random, nbs::SearchSpace::sphere});
  CHECK(nbs::parse_method(" see") == nbs::kSeeMethod);
  // SEE has one selection (its own): another one with its search is not a precompiled method.
  CHECK_THROWS_AS(nbs::RuntimePlanner(nbs::Method{nbs::Selection::random, nbs::SearchSpace::surface_edge}, {},
                                      light_lsp(), sphere_box()),
                  nbs::InvalidArgument);
  for (const char* bad : {"", "C", "C_X", "X_H", "OA_S", "CH", "C_H_", "SEE_H", "C_SEE"}) {
    CHECK_THROWS_AS(nbs::parse_method(bad), nbs::InvalidArgument);
    try {
      (void)nbs::parse_method(bad);
    } catch (const nbs::InvalidArgument& e) {
      const std::string msg = e.what();
      CHECK(msg.find("valid codes") != std::string::npos);
      CHECK(msg.find("C_H") != std::string::npos);
      CHECK(msg.find("VG_H") != std::string::npos);
    }
  }
  for (const nbs::Method& m : nbs::kAllMethods) {
    const nbs::RuntimePlanner p(m, {}, light_lsp(), sphere_box());
    CHECK(p.method() == m);
    CHECK(p.variant().index() == static_cast<std::size_t>(m.search));
  }
  CHECK_THROWS_AS(nbs::RuntimePlanner("nope", {}, light_lsp(), sphere_box()), nbs::InvalidArgument);
}

TEST_CASE("loop: same seed, same scan sequence with 1 and 2 threads; facade equals the composed planner",
          "[planner][loop]") {
  const nbs::test::SphereOnPedestal sphere;
  const nbs::SimulationSetting sim = loop_setting(3, 5);
  nbs::NbsPlanner<> p1({}, light_lsp(), sphere_box(), setting(1));
  nbs::NbsPlanner<> p2({}, light_lsp(), sphere_box(), setting(2));
  nbs::RuntimePlanner rp(nbs::kDefaultMethod, {}, light_lsp(), sphere_box(), setting(2));
  const auto a = nbs::run_simulation(p1, sphere, sim);
  const auto b = nbs::run_simulation(p2, sphere, sim);
  const auto c = nbs::run_simulation(rp, sphere, sim);
  REQUIRE(a.records.size() >= 3);  // a first scan and at least two planned ones
  CHECK(a.records[0].initial_index == nbs::random_initial_scan_index(3));
  check_same_plan(a, b);
  check_same_plan(a, c);
  // The thesis's planner: ThesisPlanner<> equals the facade's C_H with the thesis's stop rule (d̄_m target 0: the
  // light sphere's density stays below 0.2, and the rule is to fire here).
  nbs::Parameters no_density;
  no_density.target_density = 0.0;
  nbs::ThesisPlanner<> t1(no_density, light_lsp(), sphere_box(), setting(1));
  nbs::RuntimeModels thesis_stop;
  thesis_stop.stop_rule = nbs::StopRule::thesis;
  nbs::RuntimePlanner rt(nbs::kThesisMethod, no_density, light_lsp(), sphere_box(), setting(2), thesis_stop);
  CHECK(rt.code() == "C_H");
  CHECK(std::get<nbs::RuntimePlannerOf<nbs::SearchSpace::boundary_hole>>(rt.variant()).termination.rule ==
        nbs::StopRule::thesis);
  const auto ta = nbs::run_simulation(t1, sphere, sim), tb = nbs::run_simulation(rt, sphere, sim);
  check_same_plan(ta, tb);
  INFO("thesis loop: " << ta.records.size() << " scans, last c_m " << ta.records.back().integration.estimated_coverage);
  CHECK(ta.stop == nbs::LoopStop::done);  // the thesis rule fired (within the 5 scans)
}

TEST_CASE("loop: the noise-robust mesh policy plans, stays consistent and is deterministic over threads",
          "[planner][loop]") {
  const nbs::test::SphereOnPedestal sphere;
  const nbs::SimulationSetting sim = loop_setting(5, 4);
  // The unseen_loops form of ĉ_m: UnseenLoopCoverage without the enclosure test and the free-seam rule.
  nbs::NbsPlanner<> p1({}, light_lsp(), sphere_box(), setting(1));
  nbs::NbsPlanner<> p2({}, light_lsp(), sphere_box(), setting(2));
  p1.coverage.setting.enclosure = p2.coverage.setting.enclosure = false;
  p1.coverage.setting.free_space = p2.coverage.setting.free_space = false;
  const auto a = nbs::run_simulation(p1, sphere, sim);
  const auto b = nbs::run_simulation(p2, sphere, sim);
  REQUIRE(a.records.size() == 4);
  check_same_plan(a, b);
  // ĉ_m is the unseen-loop form: it equals estimated_coverage_unseen recomputed from the final models.
  const nbs::Parameters params;
  const auto seen = [&](const Vec3& x) { return p1.space().probability(x) > params.occupied_threshold; };
  CHECK(p1.estimated_coverage() ==
        std::clamp(nbs::estimated_coverage_unseen(p1.mesh(), nbs::find_all_loops(p1.mesh(), params), seen), 0.0, 1.0));
  const auto& mesh = p1.mesh();
  const auto rep = nbs::check_invariants(mesh, mesh.settings().reduction_radius_m);
  INFO(rep.problems);
  CHECK(rep.ok());
  // The default Mesh policy is NoiseRobustStreamingMesh: both noise-robust options on.
  CHECK(mesh.settings().project_vertices);
  CHECK(mesh.settings().density_depth_m == mesh.settings().normal_radius_m);
  std::size_t moved = 0;  // meshed vertices sit on their PCA planes, not at the measured points
  for (nbs::VertexId v = 0; v < mesh.vertex_count(); ++v)
    moved += mesh.has_normal(v) && mesh.position(v) != mesh.stored_position(v) ? 1 : 0;
  CHECK(moved > mesh.vertex_count() / 2);

  // A StreamingMesh policy is the thesis's stream as written; given the noise-robust settings it builds the same
  // mesh as NoiseRobustStreamingMesh: the same plan, step for step.
  using Plain = nbs::NbsPlanner<nbs::SurfaceGainUnseenUtility, nbs::BoundaryHoleSpace, nbs::LaserStripeProfiler,
                                nbs::NoCollisions, nbs::DefaultTermination, nbs::ProbabilisticVoxelSpace<>,
                                nbs::StreamingMesh>;
  const Plain thesis({}, light_lsp(), sphere_box(), setting(1));
  CHECK_FALSE(thesis.mesh().settings().project_vertices);
  CHECK(thesis.mesh().settings().density_depth_m == 0.0);
  Plain p3({}, light_lsp(), sphere_box(), setting(1),
           nbs::NoiseRobustStreamingMesh::robust(nbs::StreamingMeshSettings::from({}, sphere_box())));
  p3.coverage.setting.enclosure = false;
  const auto c = nbs::run_simulation(p3, sphere, sim);
  check_same_plan(a, c);
  CHECK(p3.mesh().vertex_count() == mesh.vertex_count());
  CHECK(p3.mesh().settings().project_vertices);
  CHECK(p3.mesh().settings().density_depth_m == p3.mesh().settings().normal_radius_m);
  // The default ĉ_m (UnseenLoopCoverage with the enclosure test and the free-seam rule, unknown_open) also calls
  // fan samples walled in by measured surface seen (and free ones of long loops mostly in free space): recomputed
  // from the final models with the public functions; the policy's seen() agrees sample for sample; on the sphere
  // standing on its pedestal the enclosure test fires (the contact loop), so ĉ_m exceeds the unseen_loops value.
  CHECK(nbs::UnseenLoopCoverage{}.setting.enclosure);
  CHECK(nbs::UnseenLoopCoverage{}.setting.free_space);
  nbs::NbsPlanner<> p4({}, light_lsp(), sphere_box(), setting(1));
  (void)nbs::run_simulation(p4, sphere, sim);
  const auto loops4 = nbs::find_all_loops(p4.mesh(), params);
  const auto seen4 = [&](const Vec3& x) { return p4.space().probability(x) > params.occupied_threshold; };
  const double reach = (sphere_box().max - sphere_box().min).norm();
  const auto open4 = [&](const Vec3& x) { return seen4(x) || nbs::enclosed_by_surface(p4.space(), x, reach); };
  const nbs::UnseenLoopCoverage::Setting def;
  const auto free4 = [&](const Vec3& x) { return p4.space().probability(x) < def.free_below; };
  const double c_open = std::clamp(
      nbs::estimated_coverage_unseen_free(p4.mesh(), loops4, open4, free4, {params.hole_max_edges, def.min_free_share}),
      0.0, 1.0);
  CHECK(p4.estimated_coverage() == c_open);
  const auto planner_seen = p4.coverage.seen(p4.space(), p4.params(), p4.unknown_area());
  std::size_t enclosed = 0, mismatched = 0;
  for (const nbs::Hole& h : loops4)
    nbs::for_each_fan_sample(p4.mesh(), h, [&](const Vec3& x) {
      enclosed += !seen4(x) && open4(x) ? 1 : 0;
      mismatched += planner_seen(x) != open4(x) ? 1 : 0;
    });
  CHECK(mismatched == 0);
  CHECK(enclosed > 0);
  CHECK(c_open > std::clamp(nbs::estimated_coverage_unseen(p4.mesh(), loops4, seen4), 0.0, 1.0));
  CHECK(c_open >= std::clamp(nbs::estimated_coverage_unseen(p4.mesh(), loops4, open4), 0.0, 1.0));
  // SelectableCoverage (the runtime facade's) gives the same values as the policy it names.
  const nbs::CoverageInput<nbs::NoiseRobustStreamingMesh, nbs::ProbabilisticVoxelSpace<>> in{
      p4.mesh(), p4.space(), p4.params(), p4.unknown_area()};
  CHECK(nbs::SelectableCoverage{}.estimate(in).coverage == c_open);
  CHECK(nbs::SelectableCoverage{{nbs::CoverageEstimate::unseen_loops}}.estimate(in).coverage ==
        nbs::UnseenLoopCoverage{{.enclosure = false, .free_space = false}}.estimate(in).coverage);
  CHECK(nbs::SelectableCoverage{{nbs::CoverageEstimate::unseen_open}}.estimate(in).coverage ==
        nbs::UnseenLoopCoverage{{.enclosure = true, .free_space = false}}.estimate(in).coverage);
  CHECK(nbs::SelectableCoverage{{nbs::CoverageEstimate::thesis}}.estimate(in).coverage ==
        std::clamp(nbs::estimated_coverage(p4.mesh(), nbs::find_holes(p4.mesh(), params)), 0.0, 1.0));
  // observable_open: unknown_open whose enclosure test also looks down from where a sensor 0.15 m away stands above
  // the pedestal (the box's bottom): recomputed with the public functions, sample for sample.
  const nbs::LowViews low{p4.unknown_area().min.z(), 0.15};
  const auto open_low = [&](const Vec3& x) { return seen4(x) || nbs::enclosed_by_surface(p4.space(), x, reach, low); };
  const nbs::SelectableCoverage observable{{nbs::CoverageEstimate::observable_open}};
  const auto observable_seen = observable.seen(p4.space(), p4.params(), p4.unknown_area());
  std::size_t low_mismatched = 0, low_freed = 0;
  for (const nbs::Hole& h : loops4)
    nbs::for_each_fan_sample(p4.mesh(), h, [&](const Vec3& x) {
      const bool lo = open_low(x);
      low_mismatched += observable_seen(x) != lo ? 1 : 0;
      low_freed += !lo && open4(x) ? 1 : 0;
    });
  CHECK(low_mismatched == 0);
  // The sphere bulges over the pedestal: some of its fans are walled in above and at the sides but open below.
  CHECK(low_freed > 0);
  CHECK(observable.estimate(in).coverage ==
        std::clamp(nbs::estimated_coverage_unseen_free(p4.mesh(), loops4, open_low, free4,
                                                       {params.hole_max_edges, def.min_free_share}),
                   0.0, 1.0));

  // Where ĉ_m puts the missing surface (CoverageResult::unseen, handed to the utility): brute force over the fan
  // samples with the per-loop seam rule; the areas sum to A_empty of Eq. 4.35.
  const nbs::CoverageResult res = nbs::SelectableCoverage{}.estimate(in);
  std::vector<nbs::UnseenSample> expected;
  for (const nbs::Hole& h : loops4) {
    std::vector<std::pair<Vec3, double>> fan;  // the Eq. 4.37 fan samples and their distance from the edge midpoint
    const std::size_t k = h.vertices.size();
    for (std::size_t i = 0; i < k; ++i) {
      const Vec3 mid = 0.5 * (p4.mesh().position(h.vertices[(i + k - 1) % k]) + p4.mesh().position(h.vertices[i]));
      for (const double t : {0.25, 0.5, 0.75}) {
        const Vec3 x = h.center + t * (mid - h.center);
        fan.emplace_back(x, (x - mid).norm());
      }
    }
    std::size_t free_n = 0;
    for (const auto& [x, d] : fan) free_n += !open4(x) && free4(x) ? 1 : 0;
    const bool seam = static_cast<int>(k) > params.hole_max_edges &&
                      static_cast<double>(free_n) >= def.min_free_share * static_cast<double>(fan.size());
    for (const auto& [x, d] : fan)
      if (!open4(x) && !(seam && free4(x))) expected.push_back({x, h.area_m2 / static_cast<double>(fan.size()), d});
  }
  REQUIRE(res.unseen.size() == expected.size());
  REQUIRE_FALSE(expected.empty());
  double a_empty = 0.0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CHECK(res.unseen[i].position.isApprox(expected[i].position, 1e-12));
    CHECK(res.unseen[i].area_m2 == Approx(expected[i].area_m2));
    CHECK(res.unseen[i].edge_distance_m == Approx(expected[i].edge_distance_m).margin(1e-12));
    a_empty += res.unseen[i].area_m2;
  }
  const double filled = nbs::filled_area(p4.mesh());
  CHECK(filled / (filled + a_empty) == Approx(c_open).epsilon(1e-12));
  // The unseen_open form (the one docs/eval's SG and SGU runs used): its samples also sum to its A_empty.
  const nbs::CoverageResult open_res = nbs::SelectableCoverage{{nbs::CoverageEstimate::unseen_open}}.estimate(in);
  double a_open = 0.0;
  for (const nbs::UnseenSample& u : open_res.unseen) a_open += u.area_m2;
  CHECK(open_res.unseen.size() >= res.unseen.size());  // no free-seam rule: a superset of the samples
  CHECK(filled / (filled + a_open) == Approx(open_res.coverage).epsilon(1e-12));
  const nbs::UtilityContext ctx = p4.utility_context();
  REQUIRE(ctx.unseen_surface.size() == res.unseen.size());
  CHECK(ctx.unseen_surface.front().position == res.unseen.front().position);
  // The thesis form's holes are missing surface as a whole: 3·|E_H| samples of A_hole / (3·|E_H|) each.
  const auto holes = nbs::find_holes(p4.mesh(), params);
  std::size_t hole_samples = 0;
  for (const nbs::Hole& h : holes) hole_samples += 3 * h.vertices.size();
  CHECK(nbs::SelectableCoverage{{nbs::CoverageEstimate::thesis}}.estimate(in).unseen.size() == hole_samples);
}

TEST_CASE("loop: termination criterion and BS -> HR switch inside the loop", "[planner][loop]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::Parameters params;
  params.max_scans = 12;
  nbs::SimulationSetting sim;
  sim.seed = 11;
  sim.max_scans = 40;  // larger than n_abort: the planner's criterion must stop the loop
  nbs::PlannerSetting thesis = setting(2);
  thesis.keep_exploring = false;  // Sec. 4.4 as written: Boundary Search candidates are discarded at the switch
  // and the thesis's mesh and ĉ_m (Secs. 3.3.1, 4.4)
  nbs::ThesisMeshPlanner<> p(params, light_lsp(), sphere_box(), thesis);
  std::vector<int> seen;
  const auto res = nbs::run_simulation(p, sphere, sim, [&](const nbs::ScanRecord& r) { seen.push_back(r.scan); });
  const auto& rec = res.records;
  REQUIRE(!rec.empty());
  CHECK(seen.size() == rec.size());
  CHECK(res.stop == nbs::LoopStop::done);
  const auto criterion = [&](const nbs::IntegrationReport& r) {
    return (r.estimated_coverage >= params.target_coverage && r.mean_density >= params.target_density) ||
           r.scans >= params.max_scans;
  };
  for (std::size_t i = 0; i + 1 < rec.size(); ++i) CHECK_FALSE(criterion(rec[i].integration));
  CHECK(criterion(rec.back().integration));
  CHECK(rec.back().integration.done);
  CHECK(p.next_best_scan().status == nbs::PlanStatus::done);

  // Eq. (4.38): the mode switches at the first scan i ≥ 2 whose ĉ_m gain is < 1 %, and never back.
  std::size_t switch_at = rec.size();
  for (std::size_t i = 1; i < rec.size(); ++i)
    if (rec[i].integration.estimated_coverage - rec[i - 1].integration.estimated_coverage < params.mode_switch_gain) {
      switch_at = i;
      break;
    }
  INFO("switch at scan " << switch_at + 1 << " of " << rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    CHECK(rec[i].integration.switched == (i == switch_at));
    const bool hr = rec[i].integration.mode == nbs::SearchMode::HoleRescan;
    if (i < switch_at) CHECK_FALSE(hr);
    // After the switch every planned scan comes from Hole Rescan (remaining BS candidates discarded).
    if (i > switch_at && i < rec.size()) {
      REQUIRE(rec[i].candidate.has_value());
      CHECK(rec[i].candidate->source == nbs::CandidateSource::hole_rescan);
      CHECK(rec[i].planning.mode == nbs::SearchMode::HoleRescan);
    }
    if (i >= 1 && i <= switch_at) {
      REQUIRE(rec[i].candidate.has_value());
      CHECK(rec[i].candidate->source == nbs::CandidateSource::boundary_search);
    }
  }
  REQUIRE(switch_at + 1 < rec.size());  // the switch happened and at least one HR scan followed
}

TEST_CASE("loop: a custom termination policy stops the loop exactly", "[planner][loop]") {
  const nbs::test::SphereOnPedestal sphere;
  using Planner = nbs::NbsPlanner<nbs::RandomUtility, nbs::BoundarySpace, nbs::LaserStripeProfiler, nbs::NoCollisions,
                                  nbs::MaxScansReached, nbs::ProbabilisticVoxelSpace<>, nbs::StreamingMesh>;
  Planner p({}, light_lsp(), sphere_box());
  p.termination = nbs::MaxScansReached(3);
  const auto res = nbs::run_simulation(p, sphere, {});
  CHECK(res.records.size() == 3);
  CHECK(res.stop == nbs::LoopStop::done);
  for (std::size_t i = 1; i < res.records.size(); ++i) {
    REQUIRE(res.records[i].candidate.has_value());
    CHECK(res.records[i].candidate->source == nbs::CandidateSource::boundary_search);
    CHECK(res.records[i].planning.best_utility >= 0.0);
    CHECK(res.records[i].planning.best_utility < 1.0);  // Random: uniform in [0, 1)
  }
}

TEST_CASE("loop: CoverageSettled reads the planner's ĉ_m history and stops where the replayed rule does",
          "[planner][loop]") {
  const nbs::test::SphereOnPedestal sphere;
  using Settled = nbs::AnyOf<nbs::CoverageSettled, nbs::MaxScansReached>;
  using Planner = nbs::NbsPlanner<nbs::IgQualityUtility, nbs::BoundaryHoleSpace, nbs::LaserStripeProfiler,
                                  nbs::NoCollisions, Settled>;
  Planner p({}, light_lsp(), sphere_box(), setting(1));
  // d̄_m stays below Tab. 4.3's 20 % on this light sphere scan: the density target is 0 here.
  const nbs::CoverageSettled rule(0.9, 2, 0.75, 3, 0.03, 0.0);
  p.termination = Settled{{rule, nbs::MaxScansReached(12)}};
  nbs::SimulationSetting sim;
  sim.seed = 3;
  sim.max_scans = 20;
  const auto res = nbs::run_simulation(p, sphere, sim);
  const auto& rec = res.records;
  REQUIRE(!rec.empty());
  // The history is ĉ_m after every scan, as integrate() reported it.
  const nbs::ModelProgress last = p.progress();
  REQUIRE(last.coverage_history.size() == rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i)
    CHECK(last.coverage_history[i] == rec[i].integration.estimated_coverage);
  // The loop stopped at the first scan where the rule, replayed on the history's prefix, holds (or at 12 scans).
  std::size_t first = rec.size();
  for (std::size_t i = 0; i < rec.size() && first == rec.size(); ++i) {
    const std::vector<double> prefix(last.coverage_history.begin(), last.coverage_history.begin() + (i + 1));
    if (rule.done({static_cast<int>(i + 1), prefix.back(), rec[i].integration.mean_density, prefix})) first = i;
  }
  INFO("stopped after " << rec.size() << " scans; rule first holds after " << first + 1);
  CHECK(res.stop == nbs::LoopStop::done);
  CHECK(first + 1 < 12);  // the rule, not n_abort, stops this run
  CHECK(rec.size() == first + 1);
  CHECK(p.next_best_scan().status == nbs::PlanStatus::done);
}

TEST_CASE("loop: the quality term sees surface after one scan; no planned path enters the pedestal", "[planner][loop]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::NbsPlanner<> planner({}, light_lsp(), sphere_box(), setting(2));
  const nbs::IntegrationReport r = planner.integrate(sphere.scan(planner.first_scan(5), planner.sensor(), 1));
  // Sec. 4.5.1: the voxels of the first scan's mesh carry features (one hit per voxel and scan, p = P_hit = 0.7,
  // must pass Parameters::occupied_threshold), so Eq. 4.33 has something to weigh from the first planning step on.
  REQUIRE(r.meshed > 0);
  CHECK(r.features_written > 0);
  CHECK(planner.features().size() == r.features_written);
  // The integrate() time split: four non-negative, consecutive parts that add up to at most the total.
  for (const double t : {r.t_space_s, r.t_mesh_s, r.t_features_s, r.t_coverage_s}) CHECK(t >= 0.0);
  CHECK(r.t_mesh_s > 0.0);
  CHECK(r.t_space_s + r.t_mesh_s + r.t_features_s + r.t_coverage_s <= r.t_integrate_s);
  nbs::SimulationSetting sim;
  sim.seed = 5;
  sim.max_scans = 6;
  nbs::NbsPlanner<> loop({}, light_lsp(), sphere_box(), setting(2));
  const auto res = nbs::run_simulation(loop, sphere, sim);
  REQUIRE(res.records.size() >= 3);
  for (const auto& rec : res.records) {
    INFO("scan " << rec.scan);
    CHECK(rec.path.start().position().z() >= sphere_box().min.z());  // Sec. 4.1: the box bottom is the support
    CHECK(rec.path.end_position().z() >= sphere_box().min.z());
  }
  for (const nbs::ScanCandidate& c : loop.candidate_set()) {
    CHECK(c.path.start().position().z() >= 0.0);
    CHECK(c.path.end_position().z() >= 0.0);
  }
}

TEST_CASE("loop: SEE replaces its candidate set each step and flies to the nearest view", "[planner][loop][see]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::RuntimePlanner rp("SEE", {}, light_lsp(), sphere_box(), setting(1));
  auto& see = std::get<nbs::RuntimePlannerOf<nbs::SearchSpace::surface_edge>>(rp.variant());
  // light_lsp samples 2 mm × 0.8 mm: thinning spacing and r scaled by 1.5 from the dlr_lsp defaults.
  nbs::SurfaceEdgeSetting s;
  s.spacing_m = 0.003;
  s.radius_m = 0.009;
  see.search.explore = nbs::SurfaceEdgeExplorer(s);
  std::vector<Vec3> ends;  // where the sensor rested after each scan
  int checked = 0;
  const auto result = nbs::run_simulation(rp, sphere, loop_setting(3, 5), [&](const nbs::ScanRecord& r) {
    if (r.candidate) {
      CHECK(r.candidate->source == nbs::CandidateSource::surface_edge);
      // Oracle: S now holds the rest of this step's SEE views; none is nearer to where the sensor rested.
      const Vec3 from = ends.back();
      const double chosen = (r.path.start().position() - from).norm();
      for (const nbs::ScanCandidate& c : see.candidate_set()) {
        CHECK(c.source == nbs::CandidateSource::surface_edge);
        CHECK(chosen <= (c.path.start().position() - from).norm());
      }
      ++checked;
    }
    ends.push_back(r.path.end_position());
    CHECK((see.utility_context().sensor_position - ends.back()).norm() < 1e-9);
  });
  CHECK(checked >= 2);
  CHECK(result.records.size() >= 3);
}

TEST_CASE("planner: an occluder hiding the half space of the chosen view moves the choice out of it", "[planner][occluder]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::NbsPlanner<> open({}, light_lsp(), sphere_box(), setting(2));
  REQUIRE(open.integrate(sphere.scan(open.first_scan(5), open.sensor(), 1)).meshed > 0);
  const nbs::PlanResult free = open.next_best_scan();
  REQUIRE(free.ok());
  const Vec3 c = sphere.center;
  const Vec3 side = (free.path().start().position() - c).normalized();
  // Every beam from that side of the plane through the centre is blocked at its origin.
  nbs::PlannerSetting s = setting(2);
  s.occluder = [c, side](const nbs::Ray& r) { return (r.origin - c).dot(side) > 0.0 ? 0.0 : 1.0; };
  nbs::NbsPlanner<> p({}, light_lsp(), sphere_box(), s);
  REQUIRE(p.integrate(sphere.scan(p.first_scan(5), p.sensor(), 1)).meshed > 0);
  const nbs::PlanResult hidden = p.next_best_scan();
  REQUIRE(hidden.ok());
  CHECK(p.last_stats().best_utility > 0.0);
  const Vec3 a = hidden.path().start().position(), b = hidden.path().end_position();
  CHECK(std::min((a - c).dot(side), (b - c).dot(side)) <= 0.0);
  CHECK((a - free.path().start().position()).norm() > 1e-6);
  // Scored as the planner scores (its evaluation setting carries the occluder): a candidate wholly on the hidden
  // side sees nothing, one wholly on the other side what it sees without the occluder.
  std::vector<nbs::LinearScanPath> paths;
  for (const nbs::ScanCandidate& k : p.candidate_set()) paths.push_back(k.path);
  const auto with = nbs::evaluate_candidates(paths, p.sensor(), p.space(), nbs::VolumetricEntropy(), p.evaluation_setting());
  nbs::EvaluationSetting plain = p.evaluation_setting();
  plain.occluder = nullptr;
  const auto without = nbs::evaluate_candidates(paths, p.sensor(), p.space(), nbs::VolumetricEntropy(), plain);
  int hidden_paths = 0, open_paths = 0;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const double da = (paths[i].start().position() - c).dot(side), db = (paths[i].end_position() - c).dot(side);
    if (da > 0.0 && db > 0.0) {
      ++hidden_paths;
      CHECK(with.values[i] == 0.0);
    } else if (da <= 0.0 && db <= 0.0) {
      ++open_paths;
      CHECK(with.values[i] == without.values[i]);
    }
  }
  CHECK(hidden_paths > 0);
  INFO(open_paths << " candidates wholly on the open side");  // often none: S lies around the first scan's boundary
}
