// SPDX-License-Identifier: BSD-3-Clause
// bench_motion: joint-space transfer motions of the shipped arm (issue 19, item 3). data/robots/lwr4.urdf beside a
// bunny-sized object: a 0.16 m box of unknown voxels (5 mm, every voxel an obstacle, as before the first scan) on
// the pedestal at the origin. Scan start poses look at the box centre from 0.3 m at elevations 0°, 20°, 50° and the
// azimuths 90°…270° (the base's side, step 45°; the far side is out of reach); each is solved by IK seeded with
// the previous pose's solution (the first from a fixed home configuration) and kept if its links are free
// (LinkCollisionChecker, base exempt from the table). Transfers go between every pair of kept poses (i < j), seed =
// pair number, JointTransferSetting's defaults.
// Headlines (names of issue 19): motion.transfer_plan_median_s — the median over the pairs of one
// plan_joint_transfer (a free straight motion, or RRT-Connect + shortcutting; each pair's best of 3 runs, 1 with
// --quick; the plan is deterministic, repeats only measure noise; goal ≤ 0.1 s); motion.success_rate — the share of
// pairs planned (status ok within the iteration budget; goal ≥ 0.99); motion.reachability_check_per_path_ms — the
// median of one RobotPathChecker::check of a 0.1 m horizontal scan path starting at each kept view (IK every
// ≤ 10 mm, links against the space); motion.transfer_searched_ms (report) — the transfer median over the pairs whose
// straight motion collides. Then motion.c_a_at_10_robot_vs_free (bench_motion_loop.cpp).

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <ompl/util/Console.h>

#include "headline.hpp"
#include "nbs/kdl/urdf_robot.hpp"
#include "nbs/ompl/joint_transfer_planner.hpp"
#include "nbs/robot/link_collision.hpp"
#include "nbs/robot/reachability.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace nbs::bench {
void report_robot_vs_free(bool quick);  // bench_motion_loop.cpp
}  // namespace nbs::bench

namespace {

using nbs::bench::median;

/// The sensor pose looking at `centre` from `standoff_m` at elevation e and azimuth az (radians), +y horizontal.
nbs::Pose look_at(const nbs::Vec3& centre, double standoff_m, double e, double az) {
  const nbs::Vec3 eye = centre + standoff_m * nbs::Vec3(std::cos(e) * std::cos(az), std::cos(e) * std::sin(az),
                                                        std::sin(e));
  const nbs::Vec3 z = (centre - eye).normalized();
  const nbs::Vec3 x = nbs::Vec3::UnitZ().cross(z).normalized();
  nbs::Pose T = nbs::Pose::Identity();
  T.linear() << x, z.cross(x), z;
  T.translation() = eye;
  return T;
}

}  // namespace

int main() {
  using namespace nbs;
  ::ompl::msg::setLogLevel(::ompl::msg::LOG_WARN);
  const bool quick = bench::quick_mode();
  const double deg = std::numbers::pi / 180.0;
  const auto robot = kdl::UrdfRobot::load(NBS_DATA_DIR "/robots/lwr4.urdf", "world", "lwr_flange", "sensor");
  const Aabb object{Vec3(-0.08, -0.08, 0.0), Vec3(0.08, 0.08, 0.16)};
  const ProbabilisticVoxelSpace<> space(0.005, object);  // every voxel unknown: an obstacle
  LinkCollisionSetting link_setting;
  link_setting.table_exempt_links = {"lwr_base_link"};
  const LinkCollisionChecker links(robot, space, link_setting);

  JointVector home(7);
  home << 0, 0.6, 0, -1.2, 0, 0.9, 0;
  std::vector<JointVector> starts;
  JointVector seed = home;
  for (double e : {0.0, 20.0, 50.0})
    for (double az = 90.0; az <= 270.0; az += 45.0) {
      const auto q = robot.ik(look_at(Vec3(0, 0, 0.08), 0.3, e * deg, az * deg), seed);
      const bool ok = q && !links.collides(*q);
      std::printf("viewpoint e %2.0f az %3.0f: %s\n", e, az, ok ? "reachable, free" : "unreachable or colliding");
      if (!ok) continue;
      starts.push_back(*q);
      seed = *q;
    }

  const nbs::ompl::JointTransferSetting base;
  std::vector<double> ms, searched_ms;
  int solved = 0;
  for (std::size_t pair = 0; pair < starts.size() * starts.size(); ++pair) {
    const std::size_t i = pair / starts.size(), j = pair % starts.size();
    if (j <= i) continue;
    nbs::ompl::JointTransferSetting setting = base;
    setting.seed = ms.size() + 1;
    nbs::ompl::JointTransfer t;
    double best = 1e300;
    for (int r = 0; r < (quick ? 1 : 3); ++r)
      best = std::min(best, bench::seconds([&] { t = nbs::ompl::plan_joint_transfer(robot, links, starts[i], starts[j],
                                                                                setting); }));
    ms.push_back(1e3 * best);
    solved += t.ok() ? 1 : 0;
    if (t.iterations > 0) searched_ms.push_back(1e3 * best);
    std::printf("%zu -> %zu: %-8s %6.1f ms  %4u iterations  %3zu waypoints  joints %.3f rad  sensor %.3f m  (%s)\n", i,
                j, std::string(nbs::ompl::to_string(t.status)).c_str(), 1e3 * best, t.iterations, t.waypoints.size(),
                t.joint_length, t.sensor_length_m, t.reason.c_str());
  }
  if (ms.empty()) {
    std::printf("bench_motion: fewer than two reachable viewpoints\n");
    return 1;
  }
  std::printf("solved %d of %zu transfers (%zu needed RRT-Connect, the others were straight); min %.1f ms, max %.1f "
              "ms\n",
              solved, ms.size(), searched_ms.size(), *std::min_element(ms.begin(), ms.end()),
              *std::max_element(ms.begin(), ms.end()));
  // One scan path per kept view: 0.1 m along the view's x axis (horizontal), checked from the view's configuration.
  const RobotPathChecker<kdl::UrdfRobot, ProbabilisticVoxelSpace<>> paths(robot, space, link_setting);
  std::vector<double> check_ms;
  for (const JointVector& q : starts) {
    const Viewpoint start(robot.fk(q));
    const LinearScanPath path(start, start.position() + 0.1 * start.pose().linear().col(0));
    ScanPathReach reach;
    double best = 1e300;
    for (int r = 0; r < (quick ? 1 : 3); ++r)
      best = std::min(best, bench::seconds([&] { reach = paths.check(path, q); }));
    check_ms.push_back(1e3 * best);
    std::printf("scan path from view %zu: %s, %zu samples, %.2f ms\n", check_ms.size() - 1,
                reach.ok() ? "executable" : std::string(to_string(reach.failure)).c_str(), reach.samples, 1e3 * best);
  }
  char note[160];
  std::snprintf(note, sizeof note, "median joint-space transfer, lwr4.urdf, 5 mm voxels, %zu pairs; goal <= 0.1 s",
                ms.size());
  bench::report_headline("motion.transfer_plan_median_s", 1e-3 * median(ms), note);
  std::snprintf(note, sizeof note, "%d of %zu transfers planned within the iteration budget; goal >= 0.99", solved,
                ms.size());
  bench::report_headline("motion.success_rate", static_cast<double>(solved) / static_cast<double>(ms.size()), note);
  bench::report_headline("motion.reachability_check_per_path_ms", median(check_ms),
                         "report: one 0.1 m scan path, IK every <= 10 mm + links vs the space, median over the views");
  bench::report_headline("motion.transfer_searched_ms", median(searched_ms),
                         "report: the transfer median over the pairs whose straight motion collides");
  bench::report_robot_vs_free(quick);
  return 0;
}
