// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `--robot PATH` and `--robot-links BASE,FLANGE,SENSOR` (nbs_model, nbs_eval; issue 19): plan for a URDF arm loaded
/// through nbs::kdl (RuntimePlanner::set_robot); the transfers between scans are planned through nbs::ompl
/// (`transfer_planner`: RRT-Connect in joint space against the voxel space after each scan). Without `--robot` the
/// tools behave as before, byte for byte. A binary built without nbs::kdl or nbs::ompl refuses `--robot` with a
/// message saying so.

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/planner/robot_policy.hpp"
#include "nbs/robot/any_robot.hpp"
#include "nbs/robot/free_flying.hpp"
#include "nbs/robot/reachability.hpp"
#include "nbs/robot/transfer.hpp"
#if defined(NBS_TOOLS_HAVE_KDL) && defined(NBS_TOOLS_HAVE_OMPL)
#include "nbs/kdl/urdf_robot.hpp"
#include "nbs/ompl/joint_transfer_planner.hpp"
#endif

namespace nbs::tools {

struct RobotOptions {
  std::string urdf;  ///< --robot PATH; empty: the sensor flies freely
  std::string base_link = "world", flange_link = "lwr_flange", sensor_link = "sensor";  ///< --robot-links
  double transfer_cost = 0.0;  ///< --transfer-cost: RobotReach::Setting::transfer_cost_weight λ, 1/rad
  int transfer_retries = 5;    ///< --transfer-retries: SimulationSetting::transfer_retries

  [[nodiscard]] bool active() const { return !urdf.empty(); }
};

inline void add_robot_options(CLI::App& app, RobotOptions& o) {
  app.add_option("--robot", o.urdf,
                 "plan for the URDF arm in PATH (e.g. data/robots/lwr4.urdf): Alg. 3 keeps only scan paths the arm "
                 "can fly (IK every 10 mm, joint limits and jumps, links vs the voxel space), transfers between "
                 "scans planned in joint space; needs nbs::kdl and nbs::ompl")
      ->type_name("PATH");
  app.add_option_function<std::string>(
         "--robot-links",
         [&o](const std::string& v) {
           const std::size_t a = v.find(','), b = a == std::string::npos ? a : v.find(',', a + 1);
           if (b == std::string::npos || v.find(',', b + 1) != std::string::npos || a == 0 || b == a + 1 ||
               b + 1 == v.size())
             throw CLI::ValidationError("--robot-links",
                                        "expects BASE,FLANGE,SENSOR (three link names), got '" + v + "'");
           o.base_link = v.substr(0, a);
           o.flange_link = v.substr(a + 1, b - a - 1);
           o.sensor_link = v.substr(b + 1);
         },
         "the URDF's base, flange and sensor links (default world,lwr_flange,sensor: data/robots/lwr4.urdf)")
      ->type_name("BASE,FLANGE,SENSOR");
  app.add_option("--transfer-cost", o.transfer_cost,
                 "with --robot: choose the reachable candidate of the largest u*exp(-L*d), d the straight joint-space "
                 "distance (rad) to its start configuration (default 0: utility only, as the thesis)")
      ->type_name("L")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--transfer-retries", o.transfer_retries,
                 "with --robot: after a failed transfer try up to N next best candidates before stopping (default 5)")
      ->type_name("N")
      ->check(CLI::NonNegativeNumber);
}

/// A robot loaded for a run: the model, its start configuration (the middle of each joint's limits, 0 for an
/// unlimited joint) and the reach setting (links that no joint moves — the base — are exempt from the table test).
struct LoadedRobot {
  AnyRobot robot;
  JointVector start;
  RobotReach<AnyRobot>::Setting setting;
  int transfer_retries = 5;  ///< SimulationSetting::transfer_retries of the runs
};

/// Loads `o.urdf` through nbs::kdl. Throws nbs::Error naming the path (unreadable, bad URDF, missing link, ...), or
/// InvalidArgument saying that the binary was built without KDL or OMPL.
[[nodiscard]] inline LoadedRobot load_robot(const RobotOptions& o) {
#if defined(NBS_TOOLS_HAVE_KDL) && defined(NBS_TOOLS_HAVE_OMPL)
  AnyRobot robot(kdl::UrdfRobot::load(o.urdf, o.base_link, o.flange_link, o.sensor_link));
  const JointLimits lim = robot.joint_limits();
  JointVector start = JointVector::Zero(lim.size()), moved = start;
  for (Eigen::Index j = 0; j < lim.size(); ++j) {
    if (std::isfinite(lim.lower[j]) && std::isfinite(lim.upper[j])) start[j] = 0.5 * (lim.lower[j] + lim.upper[j]);
    moved[j] = std::clamp(start[j] + 0.3, lim.lower[j], lim.upper[j]);
    if (moved[j] == start[j]) moved[j] = std::clamp(start[j] - 0.3, lim.lower[j], lim.upper[j]);
  }
  RobotReach<AnyRobot>::Setting setting;
  setting.transfer_cost_weight = o.transfer_cost;
  const std::vector<PlacedShape> a = robot.collision_shapes(start), b = robot.collision_shapes(moved);
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    if (a[i].link == b[i].link && a[i].T_WG.isApprox(b[i].T_WG, 1e-12) &&
        std::ranges::find(setting.links.table_exempt_links, a[i].link) == setting.links.table_exempt_links.end())
      setting.links.table_exempt_links.push_back(a[i].link);
  setting.validate();
  return {std::move(robot), std::move(start), std::move(setting), o.transfer_retries};
#else
  nbs::detail::require(false, "--robot ", o.urdf,
                  ": this binary was built without KDL or OMPL (the nbs::kdl adapter: Debian liborocos-kdl-dev and "
                  "liburdfdom-dev; nbs::ompl: libompl-dev), so it cannot load a URDF robot and plan its transfers");
  return {AnyRobot(FreeFlyingSensor{}), {}, {}};
#endif
}

#if defined(NBS_TOOLS_HAVE_KDL) && defined(NBS_TOOLS_HAVE_OMPL)
/// The transfer planner of a loaded robot: nbs::ompl::JointTransferPlanner with the robot's link setting (p > 0.05
/// and unknown voxels are obstacles, the table; the base exempt from it) and JointTransferSetting's defaults
/// (RRT-Connect, 5000 iterations, shortcutting, seed 1).
using ToolTransferPlanner = ompl::JointTransferPlanner<AnyRobot>;
[[nodiscard]] inline ToolTransferPlanner transfer_planner(const LoadedRobot& r) {
  return ToolTransferPlanner(r.robot, r.setting.links);
}
#else
/// Without OMPL no robot is loaded (load_robot refuses), so this is never called with one.
using ToolTransferPlanner = NoTransfer;
[[nodiscard]] inline ToolTransferPlanner transfer_planner(const LoadedRobot&) { return {}; }
#endif

}  // namespace nbs::tools
