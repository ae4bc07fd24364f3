// SPDX-License-Identifier: BSD-3-Clause
// 04 — a thin hardware-driver adapter: convert a driver's units and frames to nbs's (SI, docs/architecture.md)
// once, at the boundary: driver profiles and robot flange poses → nbs::Scan, next best scan → flange poses.
// Usage: 04_driver_adapter (no hardware: the "SDK" is faked); exits 1 if a conversion or round trip is off.

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/sensor/presets.hpp"

// Both directions:
//   driver → nbs: profiles in millimetres in the head frame H of a (made-up) stripe sensor SDK, whose fan lies in
//                 H's x–y plane looking along +y, plus robot flange poses T_WF in millimetres → nbs::Scan (world
//                 z up, sensor +z = viewing direction, a stripe along sensor x, linear scans along sensor y);
//   nbs → robot:  the next best scan (sensor poses T_WS) → flange poses T_WF in millimetres to command.
// The "SDK" is faked with a flat plate; the planner is the default NbsPlanner.
namespace sdk {  // what a vendor driver might hand out
struct Point2 {
  float x_mm, y_mm;  // in the head frame H: x along the stripe, y = depth (viewing direction)
};
struct Profile {
  std::vector<Point2> points;
  int robot_sample;  // index of the flange pose recorded with this profile
};
struct FlangePose {
  double x_mm, y_mm, z_mm;   // T_WF translation
  double qw, qx, qy, qz;     // T_WF rotation
};
}  // namespace sdk

namespace adapter {
using nbs::Pose;
using nbs::Vec3;

/// H → S: s_x = h_x, s_z = h_y (viewing), s_y = s_z × s_x = −h_z (right-handed). Rotation only.
Pose head_to_sensor() {
  Pose T_HS = Pose::Identity();
  T_HS.linear().col(0) = Vec3::UnitX();   // s_x in H
  T_HS.linear().col(1) = -Vec3::UnitZ();  // s_y in H
  T_HS.linear().col(2) = Vec3::UnitY();   // s_z in H
  return T_HS;
}

/// Hand-eye calibration T_FH (flange → head), from the robot cell (Sec. 3.2.1); here 8 cm along the flange z.
Pose flange_to_head() {
  Pose T = Pose::Identity();
  T.translation() = Vec3(0.0, 0.0, 0.08);
  return T;
}

Pose to_pose(const sdk::FlangePose& f) {
  Pose T = Pose::Identity();
  T.linear() = Eigen::Quaterniond(f.qw, f.qx, f.qy, f.qz).normalized().toRotationMatrix();
  T.translation() = 1e-3 * Vec3(f.x_mm, f.y_mm, f.z_mm);
  return T;
}

sdk::FlangePose to_flange(const Pose& T_WF) {
  const Eigen::Quaterniond q(T_WF.linear());
  const Vec3 t = 1e3 * T_WF.translation();
  return {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()};
}

/// Driver data → nbs::Scan (SI, world frame): T_WS = T_WF · T_FH · T_HS per profile.
nbs::Scan to_scan(const std::vector<sdk::Profile>& profiles, const std::vector<sdk::FlangePose>& robot) {
  nbs::Scan scan;
  for (const sdk::Profile& p : profiles) {
    const Pose T_WH = to_pose(robot.at(static_cast<std::size_t>(p.robot_sample))) * flange_to_head();
    const auto k = static_cast<std::uint32_t>(scan.profile_poses.size());
    scan.profile_poses.push_back(T_WH * head_to_sensor());
    for (const sdk::Point2& q : p.points) scan.add_point(T_WH * (1e-3 * Vec3(q.x_mm, q.y_mm, 0.0)), k);
    scan.rays_cast += p.points.size();
  }
  scan.validate();  // throws, naming the bad point or pose, before anything reaches the planner
  return scan;
}

/// A planned sensor pose T_WS → the flange pose to command: T_WF = T_WS · T_HS⁻¹ · T_FH⁻¹.
sdk::FlangePose command(const Pose& T_WS) {
  return to_flange(T_WS * head_to_sensor().inverse() * flange_to_head().inverse());
}
}  // namespace adapter

namespace fake {  // the "hardware": a 12 × 12 cm plate at z = 0 seen from 0.3 m, swept along world x
std::vector<sdk::FlangePose> robot;
std::vector<sdk::Profile> profiles;
void record_sweep() {
  // Head looking down (h_y = −z_W), stripe along y_W (h_x = y_W), so h_z = h_x × h_y = x_W: the sweep direction.
  nbs::Pose T_WH = nbs::Pose::Identity();
  T_WH.linear().col(0) = nbs::Vec3::UnitY();
  T_WH.linear().col(1) = -nbs::Vec3::UnitZ();
  T_WH.linear().col(2) = T_WH.linear().col(0).cross(T_WH.linear().col(1));
  for (int k = 0; k <= 120; ++k) {
    T_WH.translation() = nbs::Vec3(-0.06 + 0.001 * k, 0.0, 0.3);
    robot.push_back(adapter::to_flange(T_WH * adapter::flange_to_head().inverse()));
    sdk::Profile p{{}, k};
    for (int i = 0; i < 200; ++i) {  // fan of ±12° in H's x–y plane
      const double a = -0.21 + 0.42 * i / 199.0;
      const double depth = 0.3 / std::cos(a);  // to the plate z = 0
      const double x = depth * std::sin(a);
      if (std::abs(x) <= 0.06) p.points.push_back({static_cast<float>(1e3 * x), static_cast<float>(1e3 * 0.3)});
    }
    profiles.push_back(p);
  }
}
}  // namespace fake

int main() {
  fake::record_sweep();
  const nbs::Scan scan = adapter::to_scan(fake::profiles, fake::robot);
  double worst = 0.0;  // the plate is z = 0: the conversion is right if every point lands on it
  for (const nbs::Vec3& p : scan.points) worst = std::max(worst, std::abs(p.z()));
  std::printf("driver: %zu profiles, %zu points; farthest from the plate after conversion: %.2e m\n",
              scan.profile_poses.size(), scan.size(), worst);

  const nbs::Aabb unknown{nbs::Vec3(-0.07, -0.07, 0.0), nbs::Vec3(0.07, 0.07, 0.03)};
  nbs::Parameters params;
  params.target_density = 1.0;  // a flat plate is "complete" after one sweep; keep planning to show a command
  nbs::NbsPlanner<> planner(params, nbs::presets::dlr_lsp(), unknown);
  const nbs::IntegrationReport r = planner.integrate(scan);
  std::printf("planner: %zu points integrated, c_m %.3f, d_m %.3f\n", r.points, r.estimated_coverage,
              r.mean_density);
  const nbs::PlanResult plan = planner.next_best_scan();
  if (!plan.ok()) {
    std::fprintf(stderr, "04_driver_adapter: no scan planned: %s\n", std::string(nbs::to_string(plan.status)).c_str());
    return 1;
  }
  const nbs::LinearScanPath& path = plan.path();
  double worst_round_trip = 0.0;
  for (const nbs::Pose& T_WS : {path.start().pose(), path.pose_at(1.0)}) {
    const sdk::FlangePose f = adapter::command(T_WS);
    // Round trip: the commanded flange pose puts the sensor back at T_WS.
    const nbs::Pose back = adapter::to_pose(f) * adapter::flange_to_head() * adapter::head_to_sensor();
    std::printf("move flange to (%.1f, %.1f, %.1f) mm, q = (%.4f, %.4f, %.4f, %.4f); sensor pose error %.1e\n",
                f.x_mm, f.y_mm, f.z_mm, f.qw, f.qx, f.qy, f.qz, (back.matrix() - T_WS.matrix()).norm());
    worst_round_trip = std::max(worst_round_trip, (back.matrix() - T_WS.matrix()).norm());
  }
  // Points are floats in millimetres (≈ 1e-5 mm resolution at 300 mm), poses doubles: both errors must be tiny.
  const bool ok = worst < 1e-6 && worst_round_trip < 1e-9 && r.points == scan.size();
  if (!ok) std::fprintf(stderr, "04_driver_adapter: conversion off (plate %.1e m, round trip %.1e)\n", worst,
                        worst_round_trip);
  return ok ? 0 : 1;
}
