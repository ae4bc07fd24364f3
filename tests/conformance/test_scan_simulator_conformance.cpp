// SPDX-License-Identifier: BSD-3-Clause
// ScanSimulator conformance (core): the analytic sphere scanner of the planner tests and a minimal user-written
// scanner (the Embree SimulatedScanner, both sensor kinds: test_conformance_embree).
#include "scan_simulator_conformance.hpp"

#include "../planner/support/analytic_scanner.hpp"
#include "nbs/sensor/counter_gaussian.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/initial_scan_paths.hpp"

namespace {

using nbs::Vec3;

/// The user-written scanner: an LSP over the floor z = 0 (exact ray-plane casts, noise along the ray).
struct FloorScanner {
  [[nodiscard]] nbs::Scan scan(const nbs::LinearScanPath& path, const nbs::LaserStripeProfiler& s,
                               std::uint64_t seed) const {
    nbs::Scan out;
    out.profile_poses = s.profile_poses(path);
    const nbs::CounterGaussian gauss(seed);
    for (std::size_t k = 0; k < out.profile_poses.size(); ++k)
      for (int i = 0; i < s.points_per_profile; ++i, ++out.rays_cast) {
        const nbs::Pose& p = out.profile_poses[k];
        const Vec3 d = p.linear() * s.ray_direction_sensor(i);
        const double t = d.z() < 0.0 ? -p.translation().z() / d.z() : -1.0;
        if (t > 0.0 && s.range.contains(t))
          out.add_point(p.translation() + (t + s.noise.sigma_m(t) * gauss(k, static_cast<std::uint64_t>(i))) * d,
                        static_cast<std::uint32_t>(k));
      }
    return out;
  }
};

nbs::LaserStripeProfiler light_lsp() { return nbs::test::light_lsp(100); }

}  // namespace

TEST_CASE("ScanSimulator conformance: the analytic sphere scanner", "[conformance][scanner]") {
  const nbs::test::SphereOnPedestal sphere;
  const nbs::Aabb box{Vec3(-0.06, -0.06, 0.0), Vec3(0.06, 0.06, 0.10)};
  nbs::conformance::ScanCase c;
  for (int i : {0, 1, 5, 9}) c.paths.push_back(nbs::initial_scan_path(box, 0.3, i));
  c.surface_distance = [&](const Vec3& p) { return std::abs((p - sphere.center).norm() - sphere.radius_m); };
  c.surface_tol_m = 1e-9;
  nbs::conformance::check_scan_simulator_conformance(sphere, light_lsp(), c);
}

TEST_CASE("ScanSimulator conformance: a user-written scanner", "[conformance][scanner]") {
  nbs::conformance::ScanCase c;
  const nbs::Viewpoint down = nbs::Viewpoint::from_axes(Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1), Vec3(0, 0, 0.3));
  c.paths = {nbs::LinearScanPath(down, Vec3(0, -0.05, 0.3)), nbs::LinearScanPath(down)};
  c.surface_distance = [](const Vec3& p) { return std::abs(p.z()); };
  c.surface_tol_m = 1e-9;
  nbs::conformance::check_scan_simulator_conformance(FloorScanner{}, light_lsp(), c);
}
