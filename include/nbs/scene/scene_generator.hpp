// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Seeded simulated table-top scenes: several meshes placed upright on a table plane with random yaw, their xy
/// footprints (convex hulls) at least `min_gap_m` apart; ground truth per object; one combined mesh with per-triangle
/// object ids for a ray caster.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <cstdint>
#include <optional>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "nbs/core/detail/random.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/mesh/transformed_mesh.hpp"
#include "nbs/scene/detail/footprint.hpp"

namespace nbs::scene {

/// An object to place: a mesh in its own frame (metres, +z is its up axis; it is set down on its lowest vertex).
struct ObjectSpec {
  std::string name;
  IndexedMesh mesh;
};

/// Settings of generate_scene. World frame, metres. The table top is the rectangle
/// [−size_x/2, size_x/2] × [−size_y/2, size_y/2] at z = height_m.
struct SceneSettings {
  double table_height_m = 0.0;   ///< z of the table top.
  double table_size_x_m = 0.8;   ///< table extent along x.
  double table_size_y_m = 0.6;   ///< table extent along y.
  double min_gap_m = 0.005;      ///< least xy distance between the footprints (convex hulls) of two objects.
  /// If set, every object after the first is placed within this xy distance of an already placed one (close
  /// scenes: neighbours that nearly touch and, seen from the side, partly occlude each other). ≥ min_gap_m.
  std::optional<double> max_gap_m;
  int max_attempts = 2000;       ///< random placements tried per object before generate_scene gives up.

  /// Throws InvalidArgument naming the first invalid value.
  void validate() const {
    detail::require(std::isfinite(table_height_m), "SceneSettings.table_height_m must be finite, got ", table_height_m);
    detail::require_positive("SceneSettings.table_size_x_m", table_size_x_m);
    detail::require_positive("SceneSettings.table_size_y_m", table_size_y_m);
    detail::require_non_negative("SceneSettings.min_gap_m", min_gap_m);
    if (max_gap_m)
      detail::require(std::isfinite(*max_gap_m) && *max_gap_m >= min_gap_m, "SceneSettings.max_gap_m must be finite and >= min_gap_m (",
                      min_gap_m, "), got ", *max_gap_m);
    detail::require(max_attempts > 0, "SceneSettings.max_attempts must be > 0, got ", max_attempts);
  }
};

/// Ground truth of one placed object.
struct PlacedObject {
  std::string name;
  Pose T_world_object;                    ///< object frame → world: a yaw about +z and a translation.
  IndexedMesh mesh;                       ///< the mesh in the world frame (T_world_object applied).
  std::vector<detail::Vec2> footprint;    ///< convex hull of the mesh's xy, world frame, counter-clockwise.
};

/// A mesh whose triangles carry the index of the object they belong to (−1: the table).
struct LabeledMesh {
  IndexedMesh mesh;
  std::vector<int> triangle_object;  ///< one per triangle.
};

/// A generated scene. Plain data: const access may be concurrent.
struct SimulatedScene {
  SceneSettings settings;
  std::vector<PlacedObject> objects;

  /// The table top as two triangles (normal +z) at z = table_height_m.
  [[nodiscard]] IndexedMesh table_mesh() const {
    const double hx = 0.5 * settings.table_size_x_m, hy = 0.5 * settings.table_size_y_m, z = settings.table_height_m;
    IndexedMesh m;
    m.vertices = {Vec3(-hx, -hy, z), Vec3(hx, -hy, z), Vec3(hx, hy, z), Vec3(-hx, hy, z)};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
  }

  /// The table (object id −1) and every object (its index in `objects`) in one mesh.
  [[nodiscard]] LabeledMesh combined_mesh() const {
    LabeledMesh out;
    const auto append = [&](const IndexedMesh& m, int id) {
      const auto base = static_cast<std::uint32_t>(out.mesh.vertices.size());
      out.mesh.vertices.insert(out.mesh.vertices.end(), m.vertices.begin(), m.vertices.end());
      for (const auto& t : m.triangles) out.mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
      out.triangle_object.insert(out.triangle_object.end(), m.triangles.size(), id);
    };
    append(table_mesh(), -1);
    for (std::size_t i = 0; i < objects.size(); ++i) append(objects[i].mesh, static_cast<int>(i));
    return out;
  }
};

/// Places `objects` in the given order on the table: per object a yaw uniform in [0, 2π) and a position uniform
/// over the places where its footprint lies on the table, retried until the footprint is ≥ min_gap_m from every
/// placed one (and, with max_gap_m, ≤ max_gap_m from some placed one). Deterministic for a seed.
/// Throws InvalidArgument for invalid settings or meshes, and when an object finds no place within max_attempts
/// (the message names the object, the count and the table size).
[[nodiscard]] inline SimulatedScene generate_scene(std::span<const ObjectSpec> objects, const SceneSettings& settings,
                                                   std::uint64_t seed) {
  settings.validate();
  detail::require(!objects.empty(), "generate_scene: no objects given");
  std::mt19937_64 rng(seed);
  const auto u01 = [&] { return detail::uniform01(rng); };
  SimulatedScene scene{settings, {}};
  const double hx = 0.5 * settings.table_size_x_m, hy = 0.5 * settings.table_size_y_m;
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const ObjectSpec& spec = objects[k];
    spec.mesh.validate();
    const double min_z = spec.mesh.bounds().min.z();
    bool placed = false;
    for (int attempt = 0; attempt < settings.max_attempts && !placed; ++attempt) {
      const double yaw = 2.0 * std::numbers::pi * u01();
      const Eigen::Matrix2d r = Eigen::Rotation2Dd(yaw).toRotationMatrix();
      std::vector<detail::Vec2> xy;
      xy.reserve(spec.mesh.vertices.size());
      for (const Vec3& v : spec.mesh.vertices) xy.push_back(r * v.head<2>());
      std::vector<detail::Vec2> hull = detail::convex_hull(std::move(xy));
      detail::Vec2 lo = hull[0], hi = hull[0];
      for (const auto& p : hull) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      // Translation range keeping the hull on the table; none if the rotated object is larger than the table.
      const double tx_lo = -hx - lo.x(), tx_hi = hx - hi.x(), ty_lo = -hy - lo.y(), ty_hi = hy - hi.y();
      if (tx_lo > tx_hi || ty_lo > ty_hi) continue;
      // y before x, in two statements: the order of draws within one expression is unspecified (gcc and clang
      // differ); this is the order gcc 12 drew the former one-expression form, so seeds keep their documented scenes.
      const double uy = u01(), ux = u01();
      detail::Vec2 t(tx_lo + (tx_hi - tx_lo) * ux, ty_lo + (ty_hi - ty_lo) * uy);
      if (settings.max_gap_m && !scene.objects.empty()) {
        // Aim next to a random placed object: within the sum of both radii plus the gap of its centre.
        const auto& other = scene.objects[static_cast<std::size_t>(u01() * static_cast<double>(scene.objects.size()))];
        detail::Vec2 oc = detail::Vec2::Zero();
        double orad = 0.0, rad = 0.0;
        for (const auto& p : other.footprint) oc += p;
        oc /= static_cast<double>(other.footprint.size());
        for (const auto& p : other.footprint) orad = std::max(orad, (p - oc).norm());
        for (const auto& p : hull) rad = std::max(rad, p.norm());
        const double a = 2.0 * std::numbers::pi * u01();
        const double d = (orad + rad + *settings.max_gap_m) * std::sqrt(u01());
        t = oc + d * detail::Vec2(std::cos(a), std::sin(a));
        if (t.x() < tx_lo || t.x() > tx_hi || t.y() < ty_lo || t.y() > ty_hi) continue;
      }
      for (auto& p : hull) p += t;
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& o : scene.objects) nearest = std::min(nearest, detail::convex_distance(hull, o.footprint));
      if (nearest < settings.min_gap_m) continue;
      if (settings.max_gap_m && !scene.objects.empty() && nearest > *settings.max_gap_m) continue;
      PlacedObject obj{spec.name, Pose::Identity(), spec.mesh, std::move(hull)};
      obj.T_world_object.linear() = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
      obj.T_world_object.translation() = Vec3(t.x(), t.y(), settings.table_height_m - min_z);
      obj.mesh = transformed_mesh(obj.mesh, obj.T_world_object);
      scene.objects.push_back(std::move(obj));
      placed = true;
    }
    if (!placed) {
      std::ostringstream os;  // default precision: "0.3", not "0.29999999999999999"
      os << "generate_scene: cannot place object " << k << " (\"" << spec.name << "\") of " << objects.size()
         << " objects on the " << settings.table_size_x_m << " x " << settings.table_size_y_m
         << " m table with min_gap_m " << settings.min_gap_m << " after " << settings.max_attempts
         << " attempts: too many or too large objects for the table";
      throw InvalidArgument(os.str());
    }
  }
  return scene;
}

}  // namespace nbs::scene
