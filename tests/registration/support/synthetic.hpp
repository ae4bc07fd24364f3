// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Analytic test data for registration: a NormalMesh of sampled points + normals (PointModel), analytic surfaces
// (plane with bumps, plane, sphere cap, box corner), one-frame synthetic scans of them (seeded noise along the line
// of sight) and the pose errors and their residuals.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <vector>

#include "nbs/core/scan.hpp"
#include "nbs/core/viewpoint.hpp"
#include "nbs/mesh/mesh_concept.hpp"
#include "nbs/registration/registration.hpp"
#include "nbs/sensor/counter_gaussian.hpp"

namespace nbs::test {

/// Model points with unit normals (zero = no normal): a NormalMesh.
struct PointModel {
  std::vector<Vec3> points, normals;
  [[nodiscard]] std::size_t vertex_count() const { return points.size(); }
  [[nodiscard]] const Vec3& position(VertexId v) const { return points[v]; }
  [[nodiscard]] const Vec3& normal(VertexId v) const { return normals[v]; }
  [[nodiscard]] bool has_normal(VertexId v) const { return normals[v].squaredNorm() > 0.0; }
  void add(const Vec3& p, const Vec3& n) { points.push_back(p), normals.push_back(n); }
};
static_assert(NormalMesh<PointModel>);

/// A sample generator: calls `emit(point, unit normal)` for the samples of a surface at grid spacing h (metres) with
/// grid offset o (fraction of h), so that model (o = 0) and scan (o = 0.5) samples differ.
using Surface = std::function<void(double h, double o, const std::function<void(const Vec3&, const Vec3&)>& emit)>;

/// Height field z = f(x, y) over [−half, half]², with normal (−f_x, −f_y, 1) (facing +z).
inline Surface height_field(double half, std::function<double(double, double)> f,
                            std::function<Vec3(double, double)> grad) {
  return [=](double h, double o, const auto& emit) {
    const int n = static_cast<int>(std::floor(2.0 * half / h));
    for (int iy = 0; iy < n; ++iy)
      for (int ix = 0; ix < n; ++ix) {
        const double x = -half + (ix + o) * h, y = -half + (iy + o) * h;
        const Vec3 g = grad(x, y);
        emit(Vec3(x, y, f(x, y)), Vec3(-g.x(), -g.y(), 1.0).normalized());
      }
  };
}

/// Two anisotropic Gaussian bumps (6 mm and 5 mm high, 12 × 6 mm and 6 × 10 mm wide) on the plane z = z0 over
/// [−30, 30] mm²: all six DoF fixed.
inline Surface bumpy_plane(double z0 = 0.0) {
  struct Bump {
    double a, x0, y0, sx, sy;
  };
  static constexpr Bump bumps[] = {{0.006, -0.010, 0.004, 0.012, 0.006}, {0.005, 0.012, -0.008, 0.006, 0.010}};
  auto f = [z0](double x, double y) {
    double z = z0;
    for (const Bump& b : bumps)
      z += b.a * std::exp(-((x - b.x0) * (x - b.x0) / (b.sx * b.sx) + (y - b.y0) * (y - b.y0) / (b.sy * b.sy)));
    return z;
  };
  auto grad = [](double x, double y) {
    Vec3 g = Vec3::Zero();
    for (const Bump& b : bumps) {
      const double e =
          b.a * std::exp(-((x - b.x0) * (x - b.x0) / (b.sx * b.sx) + (y - b.y0) * (y - b.y0) / (b.sy * b.sy)));
      g.x() += -2.0 * (x - b.x0) / (b.sx * b.sx) * e;
      g.y() += -2.0 * (y - b.y0) / (b.sy * b.sy) * e;
    }
    return g;
  };
  return height_field(0.03, f, grad);
}

/// The plane z = 0 over [−30, 30] mm².
inline Surface flat_plane() {
  return height_field(0.03, [](double, double) { return 0.0; }, [](double, double) { return Vec3::Zero(); });
}

/// The upper cap (z > 0) of the sphere of radius 30 mm about the origin, sampled over its xy projection.
inline Surface sphere_cap() {
  constexpr double r = 0.03;
  return [=](double h, double o, const auto& emit) {
    const int n = static_cast<int>(std::floor(1.6 * r / h));
    for (int iy = 0; iy < n; ++iy)
      for (int ix = 0; ix < n; ++ix) {
        const double x = -0.8 * r + (ix + o) * h, y = -0.8 * r + (iy + o) * h;
        if (x * x + y * y > 0.64 * r * r) continue;
        const Vec3 p(x, y, std::sqrt(r * r - x * x - y * y));
        emit(p, p.normalized());
      }
  };
}

/// The inside corner of a box: the faces x = 0, y = 0, z = 0 over [0, 30] mm² each, normals +x, +y, +z.
inline Surface box_corner() {
  constexpr double a = 0.03;
  return [=](double h, double o, const auto& emit) {
    const int n = static_cast<int>(std::floor(a / h));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double u = (i + o + 0.5) * h, v = (j + o + 0.5) * h;
        emit(Vec3(0.0, u, v), Vec3::UnitX());
        emit(Vec3(u, 0.0, v), Vec3::UnitY());
        emit(Vec3(u, v, 0.0), Vec3::UnitZ());
      }
  };
}

/// A model of `surface` sampled at 1 mm.
inline PointModel model_of(const Surface& surface, double h = 0.001) {
  PointModel m;
  surface(h, 0.0, [&](const Vec3& p, const Vec3& n) { m.add(p, n); });
  return m;
}

/// A one-frame scan of `surface` (samples at h, offset half a grid step from the model's) seen from `eye` (its one
/// profile pose looks at `target`): the samples whose normal faces the eye, with noise of `sigma_m` along each line
/// of sight (CounterGaussian(seed)).
inline Scan scan_of(const Surface& surface, const Vec3& eye, const Vec3& target, double sigma_m, std::uint64_t seed,
                    double h = 0.0005) {
  Scan s;
  const Pose pose = Viewpoint::look_at(eye, target, std::abs((target - eye).normalized().z()) > 0.9
                                                        ? Vec3::UnitY()
                                                        : Vec3::UnitZ())
                        .pose();
  s.profile_poses.push_back(pose);
  const CounterGaussian gauss(seed);
  surface(h, 0.5, [&](const Vec3& p, const Vec3& n) {
    const Vec3 d = (p - eye).normalized();
    if (n.dot(d) >= -0.1) return;  // back-facing or grazing
    const auto i = static_cast<std::uint64_t>(s.points.size());
    s.add_point(p + sigma_m * gauss(0, i) * d, 0);
  });
  return s;
}

/// The pose error x ↦ R(angle, axis)(x − pivot) + pivot + t (world → world).
inline Pose pose_error(const Vec3& t, double angle_rad, const Vec3& axis, const Vec3& pivot) {
  Pose e = Pose::Identity();
  e.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  e.translation() = pivot + t - e.linear() * pivot;
  return e;
}

/// What is left of a pose error E after a correction C, as the rigid motion C·E: its displacement of `pivot`, its
/// rotation angle, and its largest displacement of a point of `exact` (metres, radians).
struct Residual {
  double translation_m, rotation_rad, max_displacement_m;
};
inline Residual residual(const Pose& correction, const Pose& error, const Vec3& pivot, const Scan& exact) {
  const Pose left = correction * error;
  double max_d = 0.0;
  for (const Vec3& p : exact.points) max_d = std::max(max_d, (left * p - p).norm());
  return {(left * pivot - pivot).norm(), Eigen::AngleAxisd(left.linear()).angle(), max_d};
}

/// Mean of the scan's points.
inline Vec3 centroid(const Scan& s) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : s.points) c += p;
  return c / static_cast<double>(s.size());
}

}  // namespace nbs::test
