// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Turning the object over for a second modeling session that sees its bottom (thesis Sec. 5.3): the placements of
/// a ground-truth mesh lying on one face of its axis-aligned bounding box (upright frame), each checked for
/// stability. Pure geometry.
///
/// Rule (simpler than the convex hull's faces, stated): the six candidate down-directions are ±x, ±y, ±z of the
/// upright world frame (the faces of the mesh's axis-aligned bounding box). For down-direction d the object is
/// rotated so that d points to −z; its contact set is the vertices within `contact_tolerance_m` of the lowest one;
/// the support polygon is the 2D convex hull of the contact set in the plane; the placement is stable iff the
/// polygon has positive area and the object's centre of mass — the area-weighted centroid of its **surface** (the
/// meshes need not be closed) — projects inside it at least `min_margin_m` from its boundary.

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/mesh/transformed_mesh.hpp"
#include "nbs/scene/detail/footprint.hpp"

namespace nbs {

/// The face of the upright bounding box the object lies on after the turn (minus_z: as it stands).
enum class SupportFace : std::uint8_t { minus_x, plus_x, minus_y, plus_y, minus_z, plus_z };

[[nodiscard]] constexpr std::string_view to_string(SupportFace f) {
  switch (f) {
    case SupportFace::minus_x: return "minus_x";
    case SupportFace::plus_x: return "plus_x";
    case SupportFace::minus_y: return "minus_y";
    case SupportFace::plus_y: return "plus_y";
    case SupportFace::minus_z: return "minus_z";
    case SupportFace::plus_z: return "plus_z";
  }
  return "?";
}

inline constexpr std::array<SupportFace, 6> kSupportFaces{SupportFace::minus_x, SupportFace::plus_x,
                                                          SupportFace::minus_y, SupportFace::plus_y,
                                                          SupportFace::minus_z, SupportFace::plus_z};

/// Settings of the stability test.
struct PlacementSetting {
  double contact_tolerance_m = 0.002;  ///< vertices this close to the lowest one touch the support plane, ≥ 0
  double min_margin_m = 0.0;           ///< the projected centre of mass must lie farther inside than this, ≥ 0

  void validate() const {
    detail::require_non_negative("PlacementSetting::contact_tolerance_m", contact_tolerance_m);
    detail::require_non_negative("PlacementSetting::min_margin_m", min_margin_m);
  }
};

/// One placement of the object.
struct Placement {
  SupportFace face = SupportFace::minus_z;
  Vec3 down = -Vec3::UnitZ();  ///< the upright-frame direction that points down (−z) after the turn, unit
  /// T_turn: upright world → reoriented world. The rotation takes `down` to −z (the shortest rotation; π about x for
  /// plus_z); the translation puts the lowest vertex on z = 0 and keeps the centre of mass's x, y.
  Pose T_turn = Pose::Identity();
  double support_area_m2 = 0.0;  ///< area of the support polygon (0: a point or a line of contact)
  /// Signed distance of the projected centre of mass to the support polygon's boundary, metres: > 0 inside; for a
  /// degenerate polygon minus its distance to the contact points' segment (≤ 0).
  double margin_m = 0.0;
  bool stable = false;  ///< support_area_m2 > 0 and margin_m > min_margin_m
};

/// The area-weighted centroid of the mesh's surface (world frame). Throws InvalidArgument for an invalid mesh.
[[nodiscard]] inline Vec3 surface_centroid(const IndexedMesh& mesh) {
  mesh.validate();
  Vec3 sum = Vec3::Zero();
  double area = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const double a = mesh.triangle_area(t);
    sum += a * (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)) / 3.0;
    area += a;
  }
  return sum / area;
}

namespace detail {
inline Vec3 down_direction(SupportFace f) {
  switch (f) {
    case SupportFace::minus_x: return -Vec3::UnitX();
    case SupportFace::plus_x: return Vec3::UnitX();
    case SupportFace::minus_y: return -Vec3::UnitY();
    case SupportFace::plus_y: return Vec3::UnitY();
    case SupportFace::minus_z: return -Vec3::UnitZ();
    case SupportFace::plus_z: return Vec3::UnitZ();
  }
  return -Vec3::UnitZ();
}
}  // namespace detail

/// The placement of `mesh` (upright world frame) lying on `face`, with its stability (see the file comment); never
/// throws for an unstable one. Throws InvalidArgument for an invalid mesh or setting.
[[nodiscard]] inline Placement evaluate_placement(const IndexedMesh& mesh, SupportFace face,
                                                  const PlacementSetting& setting = {}) {
  setting.validate();
  const Vec3 com = surface_centroid(mesh);  // validates the mesh
  Placement p;
  p.face = face;
  p.down = detail::down_direction(face);
  const Mat3 R = face == SupportFace::plus_z
                     ? Mat3(Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()))
                     : Mat3(Eigen::Quaterniond::FromTwoVectors(p.down, -Vec3::UnitZ()).toRotationMatrix());
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& t : mesh.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  double z_min = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) z_min = std::min(z_min, (R * mesh.vertices[v]).z());
  std::vector<detail::Vec2> contact;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (!used[v]) continue;
    const Vec3 q = R * mesh.vertices[v];
    if (q.z() <= z_min + setting.contact_tolerance_m) contact.emplace_back(q.x(), q.y());
  }
  const Vec3 c3 = R * com;
  const detail::Vec2 c(c3.x(), c3.y());
  const std::vector<detail::Vec2> hull = detail::convex_hull(contact);
  if (hull.size() >= 3) {
    double area = 0.0;
    double margin = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < hull.size(); ++i) {
      const detail::Vec2& a = hull[i];
      const detail::Vec2& b = hull[(i + 1) % hull.size()];
      area += 0.5 * (a.x() * b.y() - b.x() * a.y());
      margin = std::min(margin, detail::cross2(a, b, c) / (b - a).norm());  // > 0 left of a ccw edge: inside
    }
    p.support_area_m2 = area;
    // Outside: the signed edge distance can underrate the true distance; use the distance to the boundary.
    if (margin < 0.0) {
      double d = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < hull.size(); ++i)
        d = std::min(d, detail::point_segment_distance(c, hull[i], hull[(i + 1) % hull.size()]));
      margin = -d;
    }
    p.margin_m = margin;
  } else {
    p.margin_m = -detail::point_segment_distance(c, hull.front(), hull.back());
  }
  p.stable = p.support_area_m2 > 0.0 && p.margin_m > setting.min_margin_m;
  p.T_turn.linear() = R;
  p.T_turn.translation() = Vec3(com.x() - c3.x(), com.y() - c3.y(), -z_min);
  return p;
}

/// The placement on `face`; throws InvalidArgument naming the face, the margin and the support area if it is not
/// stable (the object would tip over), or for an invalid mesh or setting.
[[nodiscard]] inline Placement placement_on(const IndexedMesh& mesh, SupportFace face,
                                            const PlacementSetting& setting = {}) {
  const Placement p = evaluate_placement(mesh, face, setting);
  detail::require(p.stable, "placement on face ", to_string(face), " is not stable: the centre of mass projects ",
                  p.margin_m, " m inside the support polygon of area ", p.support_area_m2,
                  " m^2 (needs area > 0 and margin > min_margin_m = ", setting.min_margin_m, ")");
  return p;
}

/// The stable placements among the six, by descending support area (ties: the order of kSupportFaces).
[[nodiscard]] inline std::vector<Placement> stable_placements(const IndexedMesh& mesh,
                                                              const PlacementSetting& setting = {}) {
  std::vector<Placement> out;
  for (const SupportFace f : kSupportFaces)
    if (Placement p = evaluate_placement(mesh, f, setting); p.stable) out.push_back(p);
  std::stable_sort(out.begin(), out.end(),
                   [](const Placement& a, const Placement& b) { return a.support_area_m2 > b.support_area_m2; });
  return out;
}

/// The turn for the second session: the stable placement with the largest support area other than minus_z (the
/// pose the object stands in). Throws InvalidArgument, listing every face's margin, if there is none.
[[nodiscard]] inline Placement reorientation_placement(const IndexedMesh& mesh, const PlacementSetting& setting = {}) {
  for (const Placement& p : stable_placements(mesh, setting))
    if (p.face != SupportFace::minus_z) return p;
  std::string why;
  for (const SupportFace f : kSupportFaces) {
    if (f == SupportFace::minus_z) continue;
    const Placement p = evaluate_placement(mesh, f, setting);
    why += detail::concat(" ", to_string(f), ": margin ", p.margin_m, " m, area ", p.support_area_m2, " m^2;");
  }
  detail::require(false, "reorientation_placement: no stable placement other than minus_z;", why);
  return {};
}

}  // namespace nbs
