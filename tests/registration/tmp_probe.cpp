#include "nbs_catch.hpp"
#include <iostream>
#include <chrono>
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/registration/icp.hpp"
#include "support/synthetic.hpp"
#include "support/sphere_and_block.hpp"
using namespace nbs; using namespace nbs::test;
constexpr double kDeg = std::numbers::pi / 180.0;
nbs::LinearScanPath path_at(double deg) {
  const double a = deg * kDeg;
  const Vec3 eye(0.3 * std::sin(a), -0.3 * std::cos(a), 0.005);
  return {nbs::Viewpoint::look_at(eye, Vec3(0.0, 0.0, 0.005)), eye + Vec3(0.0, 0.0, 0.07)};
}
void run(const char* label, double sigma, double gate, double trim, double mincond) {
  const SphereAndBlock object;
  auto lsp = light_lsp(); if (sigma > 0) lsp.noise = RangeNoise::constant(sigma);
  NbsPlanner<> p({}, lsp, sphere_box());
  p.integrate(object.scan(path_at(20.0), lsp, 1));
  const Scan second0 = object.scan(path_at(60.0), lsp, 2);
  const Pose E = pose_error(0.0015 * Vec3(0.6, -1.0, 0.4).normalized(), 0.3 * kDeg, Vec3(0.2, 0.5, 1.0), centroid(second0));
  IcpSetting s; s.max_normal_angle_rad = gate * kDeg; s.trim_factor = trim; s.min_condition = mincond;
  for (bool err : {true, false}) {
    const auto r = Icp(s).register_scan(err ? transformed(second0, E) : second0, p.mesh());
    const Residual left = residual(r.correction, err ? E : Pose::Identity(), centroid(second0), second0);
    std::cout << label << (err ? " error: " : " exact: ") << to_string(r.status) << " cond " << r.condition << " left " << left.translation_m*1e3 << " mm " << left.rotation_rad/kDeg << " deg maxd " << left.max_displacement_m*1e3 << " mm t " << r.t_s*1e3 << " ms n " << second0.size() << "\n";
  }
}
TEST_CASE("probe") {
  run("precise 60 trim5", 5e-5, 60, 5, 3e-3);
  run("precise 60 notrim", 5e-5, 60, 0, 3e-3);
  run("precise 15 notrim", 5e-5, 15, 0, 3e-3);
  run("thesis-noise 60 trim5", 0, 60, 5, 3e-3);
  run("thesis-noise 60 notrim", 0, 60, 0, 3e-3);
  const SphereAndBlock object;
  auto lsp = light_lsp(); lsp.noise = RangeNoise::constant(5e-5);
  NbsPlanner<> p({}, lsp, sphere_box());
  for (double deg : {20.0, 60.0, 40.0, 80.0, 100.0}) {
    const Scan sc = object.scan(path_at(deg), lsp, 7);
    IcpSetting s; s.min_condition = 1e-6;
    const auto r = Icp(s).register_scan(sc, p.mesh());
    Pose c = r.correction; Vec3 cc = centroid(sc);
    std::cout << deg << ": " << to_string(r.status) << " cond " << r.condition << " moved " << (c*cc-cc).norm()*1e3 << " rot " << Eigen::AngleAxisd(c.linear()).angle()/kDeg << "\n";
    p.integrate(sc);
  }
}
