// SPDX-License-Identifier: BSD-3-Clause
// 04 — a hardware driver adapter: wrap a robot + stripe-sensor SDK as an nbs::ScanDriver (include/nbs/driver/
// concepts.hpp) and let nbs::run_loop drive it. Units and frames are converted once, at the boundary (SI, T_WS;
// docs/architecture.md): the SDK's millimetre profiles in its head frame and flange poses T_WF → nbs::Scan; planned
// sensor poses T_WS → flange poses to command; the robot's flange pose → the current T_WS.
// Usage: 04_driver_adapter (no hardware: the "SDK" is faked); exits 1 if a conversion or the loop is off.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "nbs/driver/concepts.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sensor/presets.hpp"

// The SDK of a made-up cell: a stripe sensor whose fan lies in its head frame H's x–y plane looking along +y, on a
// robot that reports and takes flange poses T_WF in millimetres and sweeps linearly between two flange poses.
namespace sdk {
struct Point2 {
  float x_mm, y_mm;  // in the head frame H: x along the stripe, y = depth (viewing direction)
};
struct Profile {
  std::vector<Point2> points;
  int robot_sample;  // index of the flange pose recorded with this profile
};
struct FlangePose {
  double x_mm, y_mm, z_mm;  // T_WF translation
  double qw, qx, qy, qz;    // T_WF rotation
};
struct Sweep {
  std::vector<FlangePose> robot;  // flange poses sampled during the sweep
  std::vector<Profile> profiles;
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

/// T_FS = T_FH · T_HS: the hand-eye transform in nbs's sensor convention.
Pose hand_eye() { return flange_to_head() * head_to_sensor(); }

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
}  // namespace adapter

namespace fake {  // the "hardware": a 12 × 12 cm plate at z = 0 under a robot with the stripe head
struct Cell {
  sdk::FlangePose flange = adapter::to_flange(nbs::Pose(Eigen::Translation3d(0.0, 0.0, 0.5)));

  void move(const sdk::FlangePose& f) { flange = f; }

  /// Sweeps linearly from the current flange pose to `to` (same orientation) in 1 mm steps, one profile per step:
  /// a fan of ±12° (200 rays) in H's x–y plane, the hits on the plate in H, millimetres.
  sdk::Sweep sweep(const sdk::FlangePose& to) {
    using nbs::Vec3;
    sdk::Sweep out;
    const Vec3 a(flange.x_mm, flange.y_mm, flange.z_mm), b(to.x_mm, to.y_mm, to.z_mm);
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm())));
    for (int k = 0; k <= steps; ++k) {
      const Vec3 p = a + (b - a) * (static_cast<double>(k) / steps);
      sdk::FlangePose f = to;
      f.x_mm = p.x(), f.y_mm = p.y(), f.z_mm = p.z();
      out.robot.push_back(f);
      const nbs::Pose T_WH = adapter::to_pose(f) * adapter::flange_to_head();
      sdk::Profile prof{{}, k};
      for (int i = 0; i < 200; ++i) {
        const double ang = -0.21 + 0.42 * i / 199.0;
        const Vec3 d_H(std::sin(ang), std::cos(ang), 0.0), d = T_WH.linear() * d_H;
        const double t = d.z() < 0.0 ? -T_WH.translation().z() / d.z() : -1.0;
        const Vec3 hit = T_WH.translation() + t * d;
        if (t > 0.0 && std::abs(hit.x()) <= 0.06 && std::abs(hit.y()) <= 0.06)
          prof.points.push_back({static_cast<float>(1e3 * t * d_H.x()), static_cast<float>(1e3 * t * d_H.y())});
      }
      out.profiles.push_back(prof);
    }
    flange = to;
    return out;
  }
};
}  // namespace fake

namespace adapter {
/// The cell as an nbs::ScanDriver. Every pose nbs sees is the sensor pose T_WS = T_WF · T_FS (metres); the robot
/// only ever sees flange poses T_WF = T_WS · T_FS⁻¹ (millimetres).
class SdkDriver {
public:
  explicit SdkDriver(fake::Cell& cell) : cell_(&cell) {}

  /// Moves the flange so that the sensor is at T_WS. Throws InvalidArgument for a non-finite or non-rigid pose.
  void move_to(const Pose& T_WS) {
    nbs::validate_pose(T_WS, "SdkDriver::move_to: target pose");
    cell_->move(to_flange(nbs::flange_from_sensor(T_WS, hand_eye())));
  }

  /// The sensor pose of the flange pose the robot reports.
  [[nodiscard]] Pose current_pose() const { return nbs::sensor_from_flange(to_pose(cell_->flange), hand_eye()); }

  /// Sweeps from the path's start to its end; profiles (mm, head frame) and flange samples → nbs::Scan (world, m):
  /// T_WS = T_WF · T_FH · T_HS per profile.
  [[nodiscard]] nbs::Scan acquire(const nbs::LinearScanPath& path) {
    move_to(path.start().pose());
    const sdk::Sweep sweep = cell_->sweep(to_flange(nbs::flange_from_sensor(path.pose_at(1.0), hand_eye())));
    nbs::Scan scan;
    for (const sdk::Profile& p : sweep.profiles) {
      const Pose T_WH = to_pose(sweep.robot.at(static_cast<std::size_t>(p.robot_sample))) * flange_to_head();
      const auto k = static_cast<std::uint32_t>(scan.profile_poses.size());
      scan.profile_poses.push_back(T_WH * head_to_sensor());
      for (const sdk::Point2& q : p.points) scan.add_point(T_WH * (1e-3 * Vec3(q.x_mm, q.y_mm, 0.0)), k);
      scan.rays_cast += 200;
    }
    scan.validate();  // throws, naming the bad point or pose, before anything reaches the planner
    return scan;
  }

private:
  fake::Cell* cell_;
};
static_assert(nbs::ScanDriver<SdkDriver>);
}  // namespace adapter

int main() {
  fake::Cell cell;
  adapter::SdkDriver driver(cell);

  // Round trip of the frame conversion: a commanded sensor pose comes back from the robot's flange pose.
  nbs::Pose T_WS = nbs::Pose::Identity();
  T_WS.linear() = Eigen::AngleAxisd(2.5, nbs::Vec3(1, 1, 0).normalized()).toRotationMatrix();
  T_WS.translation() = nbs::Vec3(0.1, -0.05, 0.3);
  driver.move_to(T_WS);
  double worst_round_trip = (driver.current_pose().matrix() - T_WS.matrix()).cwiseAbs().maxCoeff();
  bool rejected = false;  // bad input: a non-rigid pose is refused and the robot does not move
  nbs::Pose scaled = T_WS;
  scaled.linear() *= 1.1;
  try {
    driver.move_to(scaled);
  } catch (const nbs::InvalidArgument&) {
    rejected = (driver.current_pose().matrix() - T_WS.matrix()).cwiseAbs().maxCoeff() < 1e-12;
  }

  // The unknown area reaches 5 mm below the plate: points measured on z = 0 come back ±1e-17 m off it after the
  // unit and frame conversions and must still fall inside.
  const nbs::Aabb unknown{nbs::Vec3(-0.07, -0.07, -0.005), nbs::Vec3(0.07, 0.07, 0.03)};
  nbs::Parameters params;
  params.target_density = 1.0;  // a flat plate is "complete" after one sweep; keep planning to drive the robot
  nbs::NbsPlanner<> planner(params, nbs::presets::dlr_lsp(), unknown);
  nbs::SimulationSetting loop;
  loop.max_scans = 3;
  loop.initial_index = 0;  // the top face: the first sweep sees the plate
  // The plate is z = 0: the conversion is right if every point lands on it. A sweep along the first path, directly:
  const nbs::Scan probe = driver.acquire(planner.initial_scan(0));
  double worst_plate = 0.0, worst_rest = 0.0;
  for (const nbs::Vec3& p : probe.points) worst_plate = std::max(worst_plate, std::abs(p.z()));
  std::printf("probe sweep: %zu profiles, %zu points; farthest from the plate %.2e m\n", probe.profile_poses.size(),
              probe.size(), worst_plate);
  std::size_t points = 0;
  const nbs::SimulationResult res = nbs::run_loop(planner, driver, loop, [&](const nbs::ScanRecord& r) {
    const nbs::Pose rest = driver.current_pose();
    worst_rest = std::max(worst_rest, (rest.matrix() - r.path.pose_at(1.0).matrix()).cwiseAbs().maxCoeff());
    const sdk::FlangePose f = cell.flange;
    std::printf("scan %d: %zu points, c_m %.3f; robot flange at (%.1f, %.1f, %.1f) mm, q = (%.4f, %.4f, %.4f, %.4f)\n",
                r.scan, r.points, r.integration.estimated_coverage, f.x_mm, f.y_mm, f.z_mm, f.qw, f.qx, f.qy, f.qz);
    points += r.points;
  });
  // The loop's scans from the planner's side: every mesh vertex (a measured point) lies on the plate.
  for (nbs::VertexId v = 0; v < planner.mesh().vertex_count(); ++v)
    worst_plate = std::max(worst_plate, std::abs(planner.mesh().stored_position(v).z()));
  std::printf("loop: %zu scans (%s), %zu points; farthest mesh vertex from the plate %.2e m; pose round trip %.1e, "
              "rest pose after a scan %.1e\n",
              res.records.size(), res.stop == nbs::LoopStop::max_scans ? "max_scans" : "stopped early", points,
              worst_plate, worst_round_trip, worst_rest);
  // Points are floats in millimetres (≈ 1e-5 mm resolution at 300 mm), poses doubles: both errors must be tiny.
  const bool ok = rejected && worst_round_trip < 1e-9 && worst_rest < 1e-9 && worst_plate < 1e-6 &&
                  res.records.size() >= 2 && probe.size() > 0 && res.records.front().points > 0 &&
                  planner.mesh().vertex_count() > 0;
  if (!ok)
    std::fprintf(stderr,
                 "04_driver_adapter: off (bad pose rejected %d, round trip %.1e, rest %.1e, plate %.1e m, %zu scans, "
                 "%zu vertices)\n",
                 rejected, worst_round_trip, worst_rest, worst_plate, res.records.size(), planner.mesh().vertex_count());
  return ok ? 0 : 1;
}
