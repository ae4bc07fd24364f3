// SPDX-License-Identifier: BSD-3-Clause
// 01 — embed the planner. The whole Next-Best-Scan loop in your program: build an nbs::NbsPlanner<>, feed it a first
// scan, then next_best_scan() → move the sensor and scan → integrate() until done(). Replace scan_with_my_robot()
// with your robot and sensor; here it ray-casts a sphere on the pedestal so the example runs anywhere.
// Usage: 01_embed_the_planner (exits 1 unless the planner stops itself with ≥ 90 % of the sphere covered)

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <numbers>
#include <random>
#include <string>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/sensor/presets.hpp"

// The object only scan_with_my_robot() knows: a sphere of radius 5 cm standing on the pedestal (z = 0).
const nbs::Vec3 kCenter(0.0, 0.0, 0.05);
constexpr double kRadius = 0.05;

// ==== REPLACE WITH YOUR ROBOT: move the sensor along `path`, record a profile at each of sensor.profile_poses(path)
// (sensor poses T_WS, world frame, metres) and return the points in the world frame (examples/04 converts units and
// frames of a real driver). This stand-in casts the sensor's rays at the sphere, with the sensor's range noise. ====
nbs::Scan scan_with_my_robot(const nbs::LinearScanPath& path, const nbs::LaserStripeProfiler& sensor) {
  static std::mt19937 rng(1);
  std::normal_distribution<double> unit(0.0, 1.0);
  nbs::Scan scan;
  scan.profile_poses = sensor.profile_poses(path);
  for (std::uint32_t k = 0; k < scan.profile_poses.size(); ++k) {
    const nbs::Pose& T_WS = scan.profile_poses[k];
    for (int i = 0; i < sensor.points_per_profile; ++i, ++scan.rays_cast) {
      const nbs::Vec3 o = T_WS.translation(), d = T_WS.linear() * sensor.ray_direction_sensor(i);
      const double b = (o - kCenter).dot(d), disc = b * b - (o - kCenter).squaredNorm() + kRadius * kRadius;
      const double t = disc >= 0.0 ? -b - std::sqrt(disc) : -1.0;  // first hit on the sphere along the ray
      if (t <= 0.0 || !sensor.range.contains(t) || (d.z() < 0.0 && o.z() + t * d.z() < 0.0)) continue;  // pedestal
      scan.add_point(o + (t + sensor.noise.sigma_m(t) * unit(rng)) * d, k);
    }
  }
  return scan;
}

/// Ground truth for the exit code: share of 2000 points spread over the sphere above z = 1 cm that have a mesh
/// vertex within 3 mm (c_a of Sec. 4.7.2 with a cruder "bottom").
template <class Mesh>
double true_coverage(const Mesh& mesh) {
  int total = 0, covered = 0;
  for (int j = 0; j < 2000; ++j) {  // Fibonacci sphere
    const double z = 1.0 - 2.0 * (j + 0.5) / 2000.0, r = std::sqrt(1.0 - z * z);
    const double a = j * std::numbers::pi * (3.0 - std::sqrt(5.0));  // golden angle
    const nbs::Vec3 x = kCenter + kRadius * nbs::Vec3(r * std::cos(a), r * std::sin(a), z);
    if (x.z() < 0.01) continue;
    ++total;
    for (nbs::VertexId v = 0; v < mesh.vertex_count(); ++v)
      if ((mesh.position(v) - x).squaredNorm() <= 0.003 * 0.003) {
        ++covered;
        break;
      }
  }
  return static_cast<double>(covered) / total;
}

int main() {
  try {
    // ---- The planner-facing part: what you copy. -------------------------------------------------------------------
    const nbs::Aabb unknown_area{nbs::Vec3(-0.06, -0.06, 0.0), nbs::Vec3(0.06, 0.06, 0.11)};  // encloses the object
    nbs::Parameters params;  // Tab. 4.3; stop when ĉ_m held 0.9, settled or stalled, d̄_m ≥ 0.2; or after n_abort scans
    params.max_scans = 15;
    nbs::NbsPlanner<> planner(params, nbs::presets::dlr_lsp(), unknown_area);
    nbs::LinearScanPath path = planner.first_scan(/*seed*/ 1);  // or any path of yours that sees the object
    nbs::PlanResult plan;
    for (;;) {
      const nbs::IntegrationReport r = planner.integrate(scan_with_my_robot(path, planner.sensor()));
      std::printf("scan %2d  %6zu points  c_m %.3f  d_m %.3f\n", r.scans, r.points, r.estimated_coverage,
                  r.mean_density);
      plan = planner.next_best_scan();  // status done once planner.done()
      if (!plan.ok()) break;
      path = plan.path();
    }
    std::printf("stop: %s after %d scans\n", std::string(nbs::to_string(plan.status)).c_str(), planner.scans());
    // ---- End of the planner-facing part. ---------------------------------------------------------------------------

    const double c_a = true_coverage(planner.mesh());
    const bool reached = planner.done() && planner.scans() < params.max_scans && c_a >= 0.9;
    std::printf("true coverage c_a %.1f %% (required: 90 %%, and the planner's own stop rule held): %s\n",
                100.0 * c_a, reached ? "ok" : "FAILED");
    return reached ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "01_embed_the_planner: %s\n", e.what());
    return 1;
  }
}
