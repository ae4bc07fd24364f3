// SPDX-License-Identifier: BSD-3-Clause
// The scene-exploration loop (nbs/explore/scene_exploration.hpp) with a fake recogniser and modeler on a synthetic
// overview frame: a table grid and box tops of known sizes. The fake recognises a cluster by its xy extent (the
// "shape") against the models it knows, the fake modeler returns the box of the cluster's points; the oracle is
// the sequence of steps the loop's rule gives for these scenes.
#include "nbs_catch.hpp"

#include <cmath>
#include <string>
#include <utility>
#include <numeric>
#include <vector>

#include "nbs/explore/scene_exploration.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs_temp_dir.hpp"
#include "test_meshes.hpp"

using namespace nbs;
using namespace nbs::explore;

namespace {

struct Top {
  Vec3 lo, hi;  ///< xy rectangle at height hi.z
};

/// A 0.6 × 0.6 m table grid at z = 0 (5 mm) and the tops of the given boxes (2 mm grid), seen from above.
Scan frame_of(const std::vector<Top>& tops) {
  Scan s;
  s.profile_poses = {Pose(Eigen::Translation3d(0.0, 0.0, 1.0))};
  for (double x = -0.3; x <= 0.3; x += 0.005)
    for (double y = -0.3; y <= 0.3; y += 0.005) {
      bool under = false;
      for (const Top& t : tops) under |= x >= t.lo.x() && x <= t.hi.x() && y >= t.lo.y() && y <= t.hi.y();
      if (!under) s.add_point(Vec3(x, y, 0.0), 0);
    }
  for (const Top& t : tops)
    for (double x = t.lo.x(); x <= t.hi.x() + 1e-9; x += 0.002)
      for (double y = t.lo.y(); y <= t.hi.y() + 1e-9; y += 0.002) s.add_point(Vec3(x, y, t.hi.z()), 0);
  return s;
}

struct FakeSource {
  Scan frame;
  int calls = 0;
  Scan later{};        ///< the frame from step switch_at on (if ≥ 0)
  int switch_at = -1;
  Scan overview(int step) {
    CHECK(step == calls);
    ++calls;
    return switch_at >= 0 && step >= switch_at ? later : frame;
  }
};

/// FakeSource that can aim: records the boxes each aimed overview was asked to show.
struct FakeAimedSource : FakeSource {
  std::vector<std::vector<Aabb>> aimed;  ///< per call of overview(step, boxes)
  using FakeSource::overview;
  Scan overview(int step, std::span<const Aabb> boxes) {
    aimed.emplace_back(boxes.begin(), boxes.end());
    return overview(step);
  }
};
static_assert(AimedOverviewSource<FakeAimedSource> && !AimedOverviewSource<FakeSource>);

Vec3 extent_of(std::span<const Vec3> pts) {
  Aabb b;
  for (const Vec3& p : pts) b.extend(p);
  return b.max - b.min;
}

/// Knows models by name and xy extent; accepts a cluster whose xy extent is within 5 mm of a model's.
struct FakeRecogniser {
  struct Model {
    std::string name;
    Vec3 extent;
    Vec3 center;  ///< of the model's box, model frame
  };
  std::vector<Model> models;
  /// report the first n matches of the first model as ambiguous (right model, pose open), −1: every match of it
  int ambiguous_matches = 0;
  int matches = 0;
  bool learned_ambiguous = false;  ///< report every match of a learned model as ambiguous
  int ambiguous_from = -1;  ///< ≥ 0: the first model's matches from this one on are ambiguous, posed ambiguous_shift_m off
  double ambiguous_shift_m = 0.02;
  int first_matches = 0;
  Recognition recognise(const scene::ObjectHypothesis& h, const Scan& cluster) {
    CHECK(cluster.size() == h.points.size());
    Recognition r;
    const Vec3 e = extent_of(cluster.points);
    for (const Model& m : models)
      if (std::abs(m.extent.x() - e.x()) < 0.005 && std::abs(m.extent.y() - e.y()) < 0.005) {
        r.model = m.name;
        r.pose = Pose(Eigen::Translation3d(Vec3(h.centroid.x(), h.centroid.y(), 0.0) - Vec3(m.center.x(), m.center.y(), 0.0)));
        r.q_h = 0.9;
        r.v_h = 0.8;
        r.ambiguous = (&m == &models.front() && (ambiguous_matches < 0 || matches++ < ambiguous_matches)) ||
                      (&m != &models.front() && learned_ambiguous);
        if (&m == &models.front() && ambiguous_from >= 0 && first_matches++ >= ambiguous_from) {
          r.ambiguous = true;
          r.pose.translation().x() += ambiguous_shift_m;
        }
        r.accepted = !r.ambiguous;
      }
    return r;
  }
  void learn(const std::string& name, const IndexedMesh& mesh) {
    Aabb b = mesh.bounds();
    models.push_back({name, b.max - b.min, b.center()});
  }
};

/// Returns the box of the cluster's points (min(max_scans, scans_per_object) scans); `empty` gives an empty mesh.
struct FakeModeler {
  int scans_per_object = 5;
  bool empty = false;
  std::vector<int> budgets;
  ModelingResult model(const scene::ObjectHypothesis& h, int max_scans) {
    budgets.push_back(max_scans);
    ModelingResult m;
    m.scans = std::min(max_scans, scans_per_object);
    m.done = m.scans == scans_per_object;
    m.coverage = 0.9;
    if (!empty) {
      Aabb b;
      for (const Vec3& p : h.points) b.extend(p);
      m.mesh = test::box_mesh(Vec3(b.min.x(), b.min.y(), 0.0), b.max);
    }
    return m;
  }
};

/// FakeRecogniser that also finds model "a" in the points of a cluster inside `part` (xy) when the cluster as a
/// whole is not recognised. `bad` 1: reports an index outside the cluster; 2: a part it did not recognise;
/// 3: unsorted indices; 4: no index.
struct FakePartRecogniser : FakeRecogniser {
  Top part;
  std::string part_model = "a";
  int bad = 0;
  int part_calls = 0;
  PartRecognition recognise_part(const scene::ObjectHypothesis& h, const Scan& cluster) {
    ++part_calls;
    PartRecognition p{recognise(h, cluster), {}};
    for (std::size_t i = 0; i < cluster.size(); ++i) {
      const Vec3& q = cluster.points[i];
      if (p.recognition.accepted || (q.x() >= part.lo.x() - 1e-9 && q.x() <= part.hi.x() + 1e-9 &&
                                     q.y() >= part.lo.y() - 1e-9 && q.y() <= part.hi.y() + 1e-9))
        p.points.push_back(i);
    }
    if (p.points.empty()) {
      p.points.resize(cluster.size());
      std::iota(p.points.begin(), p.points.end(), std::size_t{0});
    } else if (p.points.size() < cluster.size()) {
      p.recognition.model = part_model;
      p.recognition.accepted = bad != 2;
      if (bad == 1) p.points.back() = cluster.size();
      if (bad == 3) std::swap(p.points.front(), p.points.back());
      if (bad == 4) p.points.clear();
    }
    return p;
  }
};

const Top kA{Vec3(-0.18, -0.03, 0.0), Vec3(-0.12, 0.03, 0.05)};  // 6 x 6 cm, known
const Top kB{Vec3(0.05, -0.02, 0.0), Vec3(0.15, 0.02, 0.08)};    // 10 x 4 cm, unknown
const Top kC{Vec3(-0.05, 0.15, 0.0), Vec3(0.03, 0.17, 0.04)};    // 8 x 2 cm, unknown

FakeRecogniser knows_a() { return {{{"a", Vec3(0.06, 0.06, 0.05), Vec3(0.0, 0.0, 0.025)}}}; }

/// The loop over a frame of `tops` with a recogniser that knows A.
struct Run {
  FakeRecogniser rec = knows_a();
  FakeModeler modeler;
  ExplorationResult r;
  Run(const std::vector<Top>& tops, const ExplorationSetting& st, FakeModeler m = {}) : modeler(std::move(m)) {
    FakeSource source{frame_of(tops)};
    r = explore_scene(source, rec, modeler, st);
  }
};

}  // namespace

TEST_CASE("explore_scene: the known object is recognised, the unknown one modeled, learned and recognised next step",
          "[scene][explore]") {
  FakeSource source{frame_of({kA, kB})};
  FakeRecogniser rec = knows_a();
  FakeModeler modeler;
  std::vector<int> seen;
  const ExplorationResult r =
      explore_scene(source, rec, modeler, ExplorationSetting{}, [&](const StepRecord& s) { seen.push_back(s.step); });
  REQUIRE(r.steps.size() == 2);
  CHECK(seen == std::vector<int>{0, 1});
  CHECK(r.stop == ExplorationStop::explained);
  CHECK(r.scans == 5);
  CHECK(modeler.budgets == std::vector<int>{60});
  const StepRecord& s0 = r.steps[0];
  REQUIRE(s0.clusters.size() == 2);  // ordered by smallest point index: A's top precedes B's in the frame
  CHECK(s0.clusters[0].state == ClusterState::recognised);
  CHECK(s0.clusters[0].recognition.model == "a");
  CHECK(s0.clusters[0].recognition.pose.translation().isApprox(Vec3(-0.15, 0.0, 0.0), 1e-9));
  CHECK(s0.clusters[1].state == ClusterState::modeling);
  CHECK(s0.modeled_cluster == 1);
  REQUIRE(s0.learned);
  CHECK(s0.learned->name == "object_1");
  CHECK(s0.learned->scans == 5);
  // The model frame is at the bottom centre of B's hypothesis box (grown by the 1 cm margin, bottom on the plane).
  CHECK(s0.learned->T_world_model.translation().isApprox(Vec3(0.10, 0.0, 0.0), 1e-6));
  REQUIRE(rec.models.size() == 2);
  CHECK(rec.models[1].extent.isApprox(Vec3(0.10, 0.04, 0.08), 1e-6));
  const StepRecord& s1 = r.steps[1];
  REQUIRE(s1.clusters.size() == 2);
  CHECK(s1.modeled_cluster == -1);
  CHECK(s1.clusters[1].state == ClusterState::recognised);
  CHECK(s1.clusters[1].recognition.model == "object_1");
  // The learned model placed by its recognised pose is where it was modeled.
  const Pose placed = s1.clusters[1].recognition.pose;
  CHECK((placed * rec.models[1].center - s0.learned->mesh_world.bounds().center()).head<2>().norm() < 1e-6);
  REQUIRE(r.learned.size() == 1);
}

TEST_CASE("explore_scene: the scan budget, an empty model and the step limit", "[scene][explore]") {
  SECTION("the budget is spent on the first unknown object; the second stays unexplained") {
    ExplorationSetting st;
    st.scan_budget = 5;
    const ExplorationResult r = Run({kA, kB, kC}, st).r;
    REQUIRE(r.steps.size() == 2);
    CHECK(r.stop == ExplorationStop::scan_budget);
    CHECK(r.scans == 5);
    const auto& c = r.steps[1].clusters;
    REQUIRE(c.size() == 3);
    std::size_t unexplained = 0, recognised = 0;
    for (const auto& x : c) unexplained += x.state == ClusterState::unexplained, recognised += x.state == ClusterState::recognised;
    CHECK(unexplained == 1);
    CHECK(recognised == 2);
  }
  SECTION("a modeler that gives an empty mesh: nothing learned, the cluster is not modeled again") {
    const Run run({kA, kB}, {}, FakeModeler{.scans_per_object = 4, .empty = true, .budgets = {}});
    const ExplorationResult& r = run.r;
    const FakeRecogniser& rec = run.rec;
    const FakeModeler& modeler = run.modeler;
    REQUIRE(r.steps.size() == 2);
    CHECK(r.stop == ExplorationStop::explained);
    CHECK(rec.models.size() == 1);
    REQUIRE(r.steps[0].learned);
    CHECK(r.steps[0].learned->name.empty());
    CHECK(r.steps[1].clusters[1].state == ClusterState::modeled);
    CHECK(modeler.budgets.size() == 1);
  }
  SECTION("max_steps") {
    ExplorationSetting st;
    st.max_steps = 1;
    const Run run({kA, kB, kC}, st);
    CHECK(run.r.steps.size() == 1);
    CHECK(run.r.stop == ExplorationStop::max_steps);
    CHECK(run.modeler.budgets == std::vector<int>{60});
  }
}

TEST_CASE("explore_scene: no plane stops the loop; invalid settings name the value", "[scene][explore]") {
  Scan wall;
  wall.profile_poses = {Pose::Identity()};
  for (double y = 0.0; y < 0.3; y += 0.005)
    for (double z = 0.0; z < 0.3; z += 0.005) wall.add_point(Vec3(0.5, y, z), 0);
  FakeSource source{wall};
  FakeRecogniser rec;
  FakeModeler modeler;
  const ExplorationResult r = explore_scene(source, rec, modeler);
  REQUIRE(r.steps.size() == 1);
  CHECK(r.stop == ExplorationStop::no_plane);
  CHECK(r.steps[0].segmentation == scene::SegmentationStatus::no_plane);
  CHECK(modeler.budgets.empty());
  ExplorationSetting st;
  st.scan_budget = 0;
  CHECK_THROWS_WITH(explore_scene(source, rec, modeler, st), nbs_test::Contains("scan_budget must be >= 1, got 0"));
  st = {};
  st.max_steps = -2;
  CHECK_THROWS_WITH(explore_scene(source, rec, modeler, st), nbs_test::Contains("max_steps must be >= 1, got -2"));
}

TEST_CASE("explore_scene: a frame without a pose and a modeler over its budget are refused", "[scene][explore]") {
  SECTION("a frame with points but no profile pose") {
    FakeSource source{frame_of({kA})};
    source.frame.profile_poses.clear();
    FakeRecogniser rec;
    FakeModeler modeler;
    const std::string text = "step 0 has " + std::to_string(source.frame.size()) + " points but no profile pose";
    CHECK_THROWS_WITH(explore_scene(source, rec, modeler), nbs_test::Contains(text));
    CHECK(modeler.budgets.empty());
  }
  SECTION("ModelingResult::scans outside [0, max_scans]") {
    struct Liar {
      int extra = 0;
      ModelingResult model(const scene::ObjectHypothesis&, int max_scans) {
        ModelingResult m;
        m.scans = extra > 0 ? max_scans + extra : extra;
        return m;
      }
    };
    ExplorationSetting st;
    st.scan_budget = 7;
    for (const auto& [extra, text] : {std::pair{1, "reported 8 scans, outside [0, 7]"},
                                      std::pair{-3, "reported -3 scans, outside [0, 7]"}}) {
      FakeSource source{frame_of({kA, kB})};
      FakeRecogniser rec = knows_a();
      Liar modeler{extra};
      CHECK_THROWS_WITH(explore_scene(source, rec, modeler, st), nbs_test::Contains(text));
      CHECK(rec.models.size() == 1);  // nothing learned
    }
  }
}

TEST_CASE("PpfRecogniser::learn: an invalid name is refused before the database is read", "[scene][explore]") {
  nbs_test::TempDir dir("nbs_learn_test_");
  ModelDatabase db = ModelDatabase::create(dir.path / "db");
  const ProbabilisticVoxelSpace<> space(0.01, Aabb{Vec3(-0.1, -0.1, -0.1), Vec3(0.1, 0.1, 0.1)});
  PpfRecogniser<BruteForceRayCaster, ProbabilisticVoxelSpace<>> recogniser(db, presets::asus_xtion_pro(), space);
  const IndexedMesh box = test::box_mesh(Vec3(-0.02, -0.02, 0.0), Vec3(0.02, 0.02, 0.04));
  CHECK_THROWS_WITH(recogniser.learn("", box), nbs_test::Contains("model name '' must be"));
  CHECK_THROWS_WITH(recogniser.learn("a b", box), nbs_test::Contains("model name 'a b' must be"));
  CHECK(db.models().empty());
  CHECK(recogniser.database().models().empty());
}

TEST_CASE("explore_scene: an ambiguous recognition is neither accepted nor modeled", "[scene][explore]") {
  FakeSource source{frame_of({kA, kB})};
  FakeRecogniser rec = knows_a();
  rec.ambiguous_matches = -1;
  FakeModeler modeler;
  ExplorationSetting st;
  st.resolve_ambiguous = false;
  const ExplorationResult r = explore_scene(source, rec, modeler, st);
  REQUIRE(r.steps.size() == 2);
  REQUIRE(r.steps[0].clusters.size() == 2);
  CHECK(r.steps[0].clusters[0].state == ClusterState::ambiguous);
  CHECK(std::string(to_string(ClusterState::ambiguous)) == "ambiguous");
  CHECK(r.steps[0].modeled_cluster == 1);  // B only: A is a known model whose pose this view leaves open
  CHECK(modeler.budgets.size() == 1);
  CHECK(r.steps[1].clusters[0].state == ClusterState::ambiguous);
  CHECK(r.stop == ExplorationStop::explained);
}

TEST_CASE("explore_scene: further overviews while a cluster is ambiguous, up to max_steps", "[scene][explore]") {
  ExplorationSetting st;
  st.max_steps = 5;
  FakeModeler modeler;
  SECTION("resolved by the third overview") {
    FakeSource source{frame_of({kA, kB})};
    FakeRecogniser rec = knows_a();
    rec.ambiguous_matches = 3;  // A is ambiguous in steps 0, 1, 2 (B is modeled in step 0, explained from step 1)
    const ExplorationResult r = explore_scene(source, rec, modeler, st);
    REQUIRE(r.steps.size() == 4);
    for (int k = 0; k < 3; ++k) CHECK(r.steps[k].clusters[0].state == ClusterState::ambiguous);
    CHECK(r.steps[3].clusters[0].state == ClusterState::recognised);
    CHECK(r.steps[3].clusters[1].state == ClusterState::recognised);
    CHECK(modeler.budgets.size() == 1);
    CHECK(r.stop == ExplorationStop::explained);
    CHECK(source.calls == 4);
  }
  SECTION("ambiguous inside the box of an object modeled before: modeled, the loop stops") {
    FakeSource source{frame_of({kA, kB})};
    FakeRecogniser rec = knows_a();
    rec.learned_ambiguous = true;  // B, modeled in step 0, fits its learned model only ambiguously from then on
    const ExplorationResult r = explore_scene(source, rec, modeler, st);
    REQUIRE(r.steps.size() == 2);
    CHECK(r.steps[1].clusters[1].recognition.ambiguous);
    CHECK(r.steps[1].clusters[1].state == ClusterState::modeled);
    CHECK(r.stop == ExplorationStop::explained);
  }
  SECTION("never resolved: the step limit") {
    FakeSource source{frame_of({kA})};
    FakeRecogniser rec = knows_a();
    rec.ambiguous_matches = -1;
    const ExplorationResult r = explore_scene(source, rec, modeler, st);
    CHECK(r.steps.size() == 5);
    CHECK(modeler.budgets.empty());
    CHECK(r.stop == ExplorationStop::max_steps);
  }
}

TEST_CASE("explore_scene: a cluster holding a known object and an unknown one is split; the rest is modeled",
          "[scene][explore]") {
  // D touches A (2 mm apart): one segmentation cluster. The recogniser finds A in part of it.
  const Top kD{Vec3(-0.118, -0.02, 0.0), Vec3(-0.06, 0.02, 0.05)};
  FakeSource source{frame_of({kA, kD})};
  FakePartRecogniser rec;
  rec.models = knows_a().models;
  rec.part = kA;
  FakeModeler modeler;
  ExplorationSetting st;
  SECTION("split") {
    const ExplorationResult r = explore_scene(source, rec, modeler, st);
    REQUIRE(r.steps.size() == 2);
    const auto& c0 = r.steps[0].clusters;
    REQUIRE(c0.size() == 2);
    CHECK(c0[0].state == ClusterState::recognised);
    CHECK(c0[0].recognition.model == "a");
    CHECK(c0[0].split);
    CHECK(c0[0].segment == 0);
    CHECK(c0[1].state == ClusterState::modeling);
    CHECK(c0[1].split);
    CHECK(c0[1].segment == 0);
    CHECK(r.steps[0].modeled_cluster == 1);
    // The rest's box is D's top (2 mm grid) grown by the segmentation's margin, not the whole cluster's.
    const double m = st.segmentation.box_margin_m;
    REQUIRE(r.learned.size() == 1);
    CHECK(r.learned[0].box.min.x() == Approx(kD.lo.x() - m).margin(1e-6));
    CHECK(r.learned[0].box.max.x() == Approx(kD.hi.x() + m).margin(1e-6));
    CHECK(c0[1].points == 30 * 21);
    // The records' frame indices: disjoint, each its own count, together every point above the table.
    CHECK(c0[0].indices.size() == c0[0].points);
    CHECK(c0[1].indices.size() == c0[1].points);
    std::vector<std::size_t> all = c0[0].indices;
    all.insert(all.end(), c0[1].indices.begin(), c0[1].indices.end());
    std::sort(all.begin(), all.end());
    CHECK(std::adjacent_find(all.begin(), all.end()) == all.end());
    std::size_t above = 0;
    for (const Vec3& p : source.frame.points) above += p.z() > 0.01;
    CHECK(all.size() == above);
    const auto& c1 = r.steps[1].clusters;
    REQUIRE(c1.size() == 2);
    CHECK(c1[0].state == ClusterState::recognised);
    CHECK(c1[1].state == ClusterState::recognised);
    CHECK(c1[1].recognition.model == r.learned[0].name);
    CHECK(r.stop == ExplorationStop::explained);
  }
  SECTION("max_parts limits the splits: the rest is then recognised as a whole") {
    // A, D and E touch: one cluster. Two splits allowed: recognise_part on the whole and on the rest D + E.
    const Top kE{Vec3(-0.058, -0.02, 0.0), Vec3(-0.03, 0.02, 0.05)};
    for (const int max_parts : {1, 3}) {
      FakeSource three{frame_of({kA, kD, kE})};
      FakePartRecogniser r3;
      r3.models = knows_a().models;
      r3.part = kA;
      FakeModeler m3;
      st.max_parts = max_parts;
      st.max_steps = 1;
      const ExplorationResult r = explore_scene(three, r3, m3, st);
      REQUIRE(r.steps[0].clusters.size() == 2);
      CHECK(r.steps[0].clusters[1].split);
      CHECK(r.steps[0].clusters[1].points == (30 + 15) * 21);
      CHECK(r3.part_calls == (max_parts == 1 ? 1 : 2));
    }
  }
  SECTION("max_parts = 0: one object per cluster, the whole cluster modeled") {
    st.max_parts = 0;
    const ExplorationResult r = explore_scene(source, rec, modeler, st);
    REQUIRE(r.steps[0].clusters.size() == 1);
    CHECK_FALSE(r.steps[0].clusters[0].split);
    CHECK(r.steps[0].clusters[0].state == ClusterState::modeling);
    CHECK(rec.part_calls == 0);
  }
  SECTION("a bad part is refused") {
    const auto refused = [&](int bad, int max_parts, const char* text) {
      FakeSource fresh{source.frame};
      rec.bad = bad;
      st.max_parts = max_parts;
      CHECK_THROWS_WITH(explore_scene(fresh, rec, modeler, st), nbs_test::Contains(text));
    };
    refused(1, 3, "out of range");
    refused(2, 3, "did not recognise");
    refused(3, 3, "unsorted");
    refused(4, 3, "empty");
    refused(0, -1, "max_parts must be >= 0, got -1");
  }
}

TEST_CASE("explore_scene: the piece a learned (partial) model leaves of its cluster is not modeled again",
          "[scene][explore]") {
  // Step 0 shows D alone: modeled and learned as object_1 (its box). From step 1 on F touches D (one cluster); the
  // recogniser finds object_1 in D's part, and the piece left (F) counts as the rest of the learned object.
  const Top kD{Vec3(-0.118, -0.02, 0.0), Vec3(-0.06, 0.02, 0.05)};
  const Top kF{Vec3(-0.058, -0.02, 0.0), Vec3(-0.03, 0.02, 0.05)};
  FakeSource source{frame_of({kD})};
  source.later = frame_of({kD, kF});
  source.switch_at = 1;
  FakePartRecogniser rec;
  rec.part = kD;
  rec.part_model = "object_1";
  FakeModeler modeler;
  const ExplorationResult r = explore_scene(source, rec, modeler, ExplorationSetting{});
  REQUIRE(r.learned.size() == 1);
  REQUIRE(r.steps.size() == 2);
  const auto& c1 = r.steps[1].clusters;
  REQUIRE(c1.size() == 2);
  CHECK(c1[0].recognition.model == "object_1");
  CHECK(c1[0].state == ClusterState::recognised);
  CHECK(c1[1].split);
  CHECK(c1[1].state == ClusterState::modeled);
  CHECK(modeler.budgets.size() == 1);
  CHECK(r.stop == ExplorationStop::explained);
}

TEST_CASE("explore_scene: an aimed source is asked to show the last step's ambiguous boxes", "[scene][explore][aim]") {
  ExplorationSetting st;
  st.max_steps = 5;
  st.aim_ambiguous = true;
  FakeModeler modeler;
  FakeAimedSource source{{frame_of({kA, kB})}, {}};
  FakeRecogniser rec = knows_a();
  rec.ambiguous_matches = 2;  // A is ambiguous in steps 0 and 1
  const ExplorationResult r = explore_scene(source, rec, modeler, st);
  REQUIRE(r.steps.size() == 3);
  CHECK(r.steps[0].aimed_at == 0);
  CHECK(r.steps[1].aimed_at == 1);
  CHECK(r.steps[2].aimed_at == 1);
  REQUIRE(source.aimed.size() == 2);  // steps 1 and 2; step 0 and a step after an unambiguous one are the source's own
  for (std::size_t k = 0; k < 2; ++k) {
    REQUIRE(source.aimed[k].size() == 1);
    CHECK(source.aimed[k][0].min == r.steps[k].clusters[0].box.min);
    CHECK(source.aimed[k][0].max == r.steps[k].clusters[0].box.max);
  }
  CHECK(source.calls == 3);
  CHECK(r.stop == ExplorationStop::explained);
  // A source that cannot aim, or aiming off (the default): overview(step) only, the same steps.
  for (const bool aim : {true, false}) {
    INFO("aim_ambiguous " << aim);
    st.aim_ambiguous = aim;
    FakeSource plain{frame_of({kA, kB})};
    FakeAimedSource aimed{{frame_of({kA, kB})}, {}};
    FakeRecogniser rec2 = knows_a(), rec3 = knows_a();
    rec2.ambiguous_matches = rec3.ambiguous_matches = 2;
    const ExplorationResult r2 = explore_scene(plain, rec2, modeler, st);
    REQUIRE(r2.steps.size() == 3);
    for (const StepRecord& s : r2.steps) CHECK(s.aimed_at == 0);
    if (!aim) {
      const ExplorationResult r3 = explore_scene(aimed, rec3, modeler, st);
      CHECK(r3.steps.size() == 3);
      CHECK(aimed.aimed.empty());
    }
  }
  CHECK_FALSE(ExplorationSetting{}.aim_ambiguous);
}

TEST_CASE("explore_scene: a placement told once is remembered when a later view leaves it ambiguous",
          "[scene][explore][aim]") {
  ExplorationSetting st;
  st.max_steps = 4;
  FakeModeler modeler;
  FakeSource source{frame_of({kA, kB})};
  FakeRecogniser rec = knows_a();
  rec.ambiguous_from = 1;  // A accepted in step 0, ambiguous (and posed 2 cm off) from step 1 on
  const ExplorationResult r = explore_scene(source, rec, modeler, st);
  REQUIRE(r.steps.size() == 2);
  const ClusterRecord& a0 = r.steps[0].clusters[0];
  const ClusterRecord& a1 = r.steps[1].clusters[0];
  CHECK(a0.state == ClusterState::recognised);
  CHECK_FALSE(a0.remembered);
  CHECK(a1.recognition.ambiguous);
  CHECK(a1.state == ClusterState::recognised);
  CHECK(a1.remembered);
  CHECK(a1.recognition.pose.isApprox(a0.recognition.pose, 1e-12));  // step 0's placement, not this view's
  CHECK(r.stop == ExplorationStop::explained);
  // Without the memory every step stands alone, and a placement of this view farther than remember_distance_m from
  // the earlier one is not the same: A stays ambiguous up to the step limit either way.
  for (const bool far : {false, true}) {
    INFO("far " << far);
    ExplorationSetting st2 = st;
    st2.remember_recognitions = far;
    FakeSource again{frame_of({kA, kB})};
    FakeRecogniser rec2 = knows_a();
    rec2.ambiguous_from = 1;
    if (far) rec2.ambiguous_shift_m = 0.04;
    const ExplorationResult r2 = explore_scene(again, rec2, modeler, st2);
    REQUIRE(r2.steps.size() == 4);
    CHECK(r2.steps[3].clusters[0].state == ClusterState::ambiguous);
    CHECK_FALSE(r2.steps[3].clusters[0].remembered);
    CHECK(r2.stop == ExplorationStop::max_steps);
  }
  st.remember_distance_m = -0.01;
  CHECK_THROWS_AS(st.validate(), InvalidArgument);
}
