// SPDX-License-Identifier: BSD-3-Clause
// The bottom by reorientation (thesis Sec. 5.3; issue 22 item 3), measured once for docs/evaluation.md: a mesh on the
// pedestal is modeled in one simulated session (Embree, a close-range depth camera, NbsPlanner), turned onto its
// largest stable side (nbs/sim/reorientation.hpp), modeled again, the two models aligned (PPF + ICP,
// nbs/recognition/model_alignment.hpp) and merged. Prints c_b before and after, the merged model's ē and the
// alignment error against the known turn.
//
//   nbs_reorient [mesh.obj|ply|stl] [scans per session = 8] [seed = 1] [contact tolerance m = 0.002] [up = y]
//                [rule = hull]
//   (the mesh is scaled to 0.16 m on the pedestal; up: x, y or z, the mesh file's up axis; rule: hull (the convex
//   hull's facets) or box (the upright bounding box's faces, the first rule))

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/conversion.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/recognition/model_alignment.hpp"
#include "nbs/sim/ground_truth.hpp"
#include "nbs/sim/reorientation.hpp"

using namespace nbs;

namespace {

using AreaPlanner = NbsPlanner<IgQualityUtility, BoundaryHoleSpace, AreaSensor>;

/// A close-range depth camera: 320 × 240, 0.6 × 0.45 rad, 0.15–0.6 m, σ = 0.2 mm.
AreaSensor camera() {
  return {.width_px = 320, .height_px = 240, .horizontal_fov_rad = 0.6, .vertical_fov_rad = 0.45,
          .range = {0.15, 0.6}, .noise = RangeNoise::constant(0.0002)};
}

IndexedMesh session(const IndexedMesh& object, int scans, std::uint64_t seed) {
  const embree::SimulatedScanner scanner(object);
  Aabb box = object.bounds();
  box.min -= Vec3(0.01, 0.01, 0.0);
  box.max += Vec3(0.01, 0.01, 0.01);
  Parameters params;
  params.voxel_size_m = 0.004;
  AreaPlanner planner(params, camera(), box);
  SimulationSetting sim;
  sim.seed = seed;
  sim.max_scans = scans;
  const SimulationResult r = run_simulation(planner, scanner, sim);
  std::printf("  %zu scans (stop %s)\n", r.records.size(), to_string(r.stop));
  return to_indexed_mesh(planner.mesh());
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : std::string(NBS_DATA_DIR) + "/meshes/stanford-bunny.obj";
  const int scans = argc > 2 ? std::atoi(argv[2]) : 8;
  const std::uint64_t seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1;
  PlacementSetting place;
  if (argc > 4) place.contact_tolerance_m = std::atof(argv[4]);
  const std::string up = argc > 5 ? argv[5] : "y";
  const std::string rule = argc > 6 ? argv[6] : "hull";
  if (rule != "hull" && rule != "box") {
    std::fprintf(stderr, "nbs_reorient: rule '%s' must be hull or box\n", rule.c_str());
    return 2;
  }
  place.rule = rule == "box" ? PlacementRule::bounding_box : PlacementRule::convex_hull;
  try {
    IndexedMesh upright = load_mesh(path);
    normalize_on_pedestal(upright, 0.16, up == "x" ? UpAxis::x : up == "z" ? UpAxis::z : UpAxis::y);
    const auto th0 = std::chrono::steady_clock::now();
    const Placement turn = reorientation_placement(upright, place);
    const auto th1 = std::chrono::steady_clock::now();
    std::printf("object %s: rule %s, turned onto %s (hull facet %d, down %.3f %.3f %.3f; support %.1f cm^2, "
                "margin %.1f mm, contact band %.1f mm; %.3f s)\n",
                path.c_str(), std::string(to_string(place.rule)).c_str(), std::string(to_string(turn.face)).c_str(),
                turn.hull_facet, turn.down.x(), turn.down.y(), turn.down.z(), 1e4 * turn.support_area_m2,
                1e3 * turn.margin_m, 1e3 * place.contact_tolerance_m, std::chrono::duration<double>(th1 - th0).count());
    if (place.rule == PlacementRule::convex_hull) {
      const auto tc0 = std::chrono::steady_clock::now();
      const ConvexHull hull = convex_hull(upright.vertices);
      const auto tc1 = std::chrono::steady_clock::now();
      const std::vector<Placement> stable = stable_placements(upright, place);
      std::printf("convex hull of %zu vertices: %zu vertices, %zu facets, %.3f s; %zu stable facets; "
                  "centre of mass: %s\n",
                  upright.vertices.size(), hull.vertices.size(), hull.facets.size(),
                  std::chrono::duration<double>(tc1 - tc0).count(), stable.size(),
                  detail::is_closed_mesh(upright) ? "volume centroid (closed mesh)" : "surface centroid (open mesh)");
    }
    const IndexedMesh turned = transformed_mesh(upright, turn.T_turn);
    const auto t0 = std::chrono::steady_clock::now();
    std::printf("session 1 (upright)\n");
    const IndexedMesh a = session(upright, scans, seed);
    std::printf("session 2 (turned)\n");
    const IndexedMesh b = session(turned, scans, seed + 1);
    const auto t1 = std::chrono::steady_clock::now();
    const ModelAlignment al = align_models(oriented_points(a), oriented_points(b));
    const auto t2 = std::chrono::steady_clock::now();
    const Pose truth = turn.T_turn.inverse();
    const double angle = rotation_angle_between(al.T_ab.linear(), truth.linear());
    double offset = 0.0, mean = 0.0;
    for (const Vec3& v : turned.vertices) {
      const double d = (al.T_ab * v - truth * v).norm();
      offset = std::max(offset, d);
      mean += d / double(turned.vertices.size());
    }
    const IndexedMesh merged = merge_models(a, b, al.T_ab);
    const GroundTruth gt(upright);
    const Completeness c1 = gt.completeness(a.vertices), cm = gt.completeness(merged.vertices);
    const std::size_t bottom = cm.samples - cm.non_bottom;
    std::printf("alignment: %zu PPF hypotheses, chosen %zu (votes %.0f), ICP %s, inliers %.1f %%, %.2f s\n",
                al.hypotheses, al.hypothesis, al.votes, std::string(to_string(al.icp.status)).c_str(),
                100.0 * al.score, std::chrono::duration<double>(t2 - t1).count());
    std::printf("alignment error: rotation %.3f deg, vertex displacement mean %.3f mm, max %.3f mm\n",
                angle * 180.0 / std::numbers::pi, 1e3 * mean, 1e3 * offset);
    std::printf("c_a session 1 %.2f %%, merged %.2f %%\n", 100.0 * c1.c_a(), 100.0 * cm.c_a());
    std::printf("c_b session 1 %.2f %%, merged %.2f %%; bottom samples covered %zu -> %zu of %zu\n",
                100.0 * c1.c_b(), 100.0 * cm.c_b(), c1.covered - c1.covered_non_bottom,
                cm.covered - cm.covered_non_bottom, bottom);
    std::printf("e session 1 %.3f mm, session 2 %.3f mm (its own frame), merged %.3f mm; sessions %.1f s\n",
                1e3 * gt.rms_error(a.vertices), 1e3 * GroundTruth(turned).rms_error(b.vertices),
                1e3 * gt.rms_error(merged.vertices), std::chrono::duration<double>(t1 - t0).count());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nbs_reorient: %s\n", e.what());
    return 1;
  }
  return 0;
}
