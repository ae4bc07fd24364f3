// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Test helper: a laser stripe profiler simulated analytically (no Embree). Rays of each profile lie in the sensor
// x–z plane (types.hpp convention), the path moves along sensor y; hits get seeded Gaussian noise along the ray.

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "nbs/core/scan.hpp"
#include "nbs/core/viewpoint.hpp"

namespace nbs::test {

/// Analytic surface: first hit distance along a unit ray and the outward unit normal at a point.
struct Shape {
  virtual ~Shape() = default;
  [[nodiscard]] virtual std::optional<double> hit(const Vec3& o, const Vec3& d) const = 0;
  [[nodiscard]] virtual Vec3 normal_at(const Vec3& p) const = 0;
};

/// Rectangle z = 0, |x| ≤ hx, |y| ≤ hy, normal +z. Optional circular holes (centre x, y, radius).
struct PlanePatch : Shape {
  double hx, hy;
  std::vector<Eigen::Vector3d> holes;  // (cx, cy, r)
  PlanePatch(double hx_, double hy_) : hx(hx_), hy(hy_) {}
  std::optional<double> hit(const Vec3& o, const Vec3& d) const override {
    if (std::abs(d.z()) < 1e-12) return std::nullopt;
    const double t = -o.z() / d.z();
    if (t <= 0) return std::nullopt;
    const Vec3 p = o + t * d;
    if (std::abs(p.x()) > hx || std::abs(p.y()) > hy) return std::nullopt;
    for (const auto& h : holes)
      if (std::hypot(p.x() - h.x(), p.y() - h.y()) < h.z()) return std::nullopt;
    return t;
  }
  Vec3 normal_at(const Vec3&) const override { return Vec3::UnitZ(); }
};

/// Sphere; optional circular holes given by (unit direction from centre, angular radius rad).
struct Sphere : Shape {
  Vec3 c;
  double r;
  std::vector<std::pair<Vec3, double>> holes;
  double min_z = -1e9;  // surface below this height does not return (a dome on a pedestal)
  Sphere(const Vec3& c_, double r_) : c(c_), r(r_) {}
  bool in_hole(const Vec3& p) const {
    const Vec3 u = (p - c).normalized();
    for (const auto& [dir, ang] : holes)
      if (std::acos(std::clamp(u.dot(dir), -1.0, 1.0)) < ang) return true;
    return false;
  }
  std::optional<double> hit(const Vec3& o, const Vec3& d) const override {
    const Vec3 oc = o - c;
    const double b = oc.dot(d), cc = oc.squaredNorm() - r * r, disc = b * b - cc;
    if (disc < 0) return std::nullopt;
    const double s = std::sqrt(disc);
    const double t = -b - s;  // outer face; a hole is a non-returning (black) spot
    if (t <= 0 || in_hole(o + t * d) || (o + t * d).z() < min_z) return std::nullopt;
    return t;
  }
  Vec3 normal_at(const Vec3& p) const override { return (p - c).normalized(); }
};

/// Axis-aligned box.
struct Box : Shape {
  Vec3 lo, hi;
  Box(const Vec3& l, const Vec3& h) : lo(l), hi(h) {}
  std::optional<double> hit(const Vec3& o, const Vec3& d) const override {
    double t0 = 0, t1 = 1e9;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(d[i]) < 1e-15) {
        if (o[i] < lo[i] || o[i] > hi[i]) return std::nullopt;
        continue;
      }
      double a = (lo[i] - o[i]) / d[i], b = (hi[i] - o[i]) / d[i];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
    if (t0 > t1 || t0 <= 0) return std::nullopt;
    return t0;
  }
  Vec3 normal_at(const Vec3& p) const override {
    int best = 0;
    double bd = 1e9, sign = 1;
    for (int i = 0; i < 3; ++i)
      for (double s : {-1.0, 1.0}) {
        const double dd = std::abs(p[i] - (s < 0 ? lo[i] : hi[i]));
        if (dd < bd) bd = dd, best = i, sign = s;
      }
    Vec3 n = Vec3::Zero();
    n[best] = sign;
    return n;
  }
};

/// Cylinder around the world z axis through (cx, cy), radius r, z in [z0, z1], lateral surface only.
struct Cylinder : Shape {
  double cx, cy, r, z0, z1;
  Cylinder(double cx_, double cy_, double r_, double z0_, double z1_) : cx(cx_), cy(cy_), r(r_), z0(z0_), z1(z1_) {}
  std::optional<double> hit(const Vec3& o, const Vec3& d) const override {
    const double ox = o.x() - cx, oy = o.y() - cy;
    const double a = d.x() * d.x() + d.y() * d.y();
    if (a < 1e-15) return std::nullopt;
    const double b = ox * d.x() + oy * d.y(), c = ox * ox + oy * oy - r * r, disc = b * b - a * c;
    if (disc < 0) return std::nullopt;
    const double t = (-b - std::sqrt(disc)) / a;
    if (t <= 0) return std::nullopt;
    const double z = o.z() + t * d.z();
    if (z < z0 || z > z1) return std::nullopt;
    return t;
  }
  Vec3 normal_at(const Vec3& p) const override { return Vec3(p.x() - cx, p.y() - cy, 0).normalized(); }
};

/// Stripe profiler: `rays` rays over ±fov/2 in the sensor x–z plane, profiles every `step_m` along sensor y.
struct StripeSensor {
  int rays = 300;
  double fov_rad = 0.5;
  double step_m = 0.0003;
  double max_range_m = 0.5;
  double noise_sigma_m = 0.00005;
};

/// Scans `shape` along the linear path from `start` (orientation + position) over `length_m` in +s_y.
inline Scan scan_path(const Shape& shape, const Viewpoint& start, double length_m, const StripeSensor& s,
                      unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  Scan scan;
  const int profiles = static_cast<int>(length_m / s.step_m) + 1;
  for (int k = 0; k < profiles; ++k) {
    Pose pose = start.pose();
    pose.translation() += (k * s.step_m) * start.y_axis();
    const auto idx = static_cast<std::uint32_t>(scan.profile_poses.size());
    scan.profile_poses.push_back(pose);
    for (int i = 0; i < s.rays; ++i) {
      const double th = -0.5 * s.fov_rad + s.fov_rad * (i + 0.5) / s.rays;
      const Vec3 d = (std::cos(th) * start.view_direction() + std::sin(th) * start.x_axis()).normalized();
      ++scan.rays_cast;
      const auto t = shape.hit(pose.translation(), d);
      if (!t || *t > s.max_range_m) continue;
      scan.add_point(pose.translation() + (*t + s.noise_sigma_m * noise(rng)) * d, idx);
    }
  }
  return scan;
}

}  // namespace nbs::test

namespace nbs::test {

/// Noise-free hit points of every ray of the scan described by the arguments: the "scanned region" oracle.
inline std::vector<Vec3> scanned_region(const Shape& shape, const Viewpoint& start, double length_m, StripeSensor s,
                                        int ray_stride, int profile_stride) {
  s.noise_sigma_m = 0.0;
  s.rays = std::max(1, s.rays / ray_stride);
  s.step_m *= profile_stride;
  return scan_path(shape, start, length_m, s, 0).points;
}

}  // namespace nbs::test
