// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Turning the object over for a second modeling session that sees its bottom (thesis Sec. 5.3): the placements of
/// a ground-truth mesh lying on one of its faces, each checked for stability. Pure geometry.
///
/// Two rules for the candidate down-directions d (`PlacementSetting::rule`):
/// - `convex_hull` (default): the outward normals of the facets of the mesh's convex hull (mesh/convex_hull.hpp) —
///   a rigid object comes to rest on a hull facet. Centre of mass (`centre_of_mass`): the volume centroid if the mesh
///   is closed (by vertex index: every directed edge matched by exactly one reverse one), else the area-weighted
///   centroid of its surface.
/// - `bounding_box` (the first rule, kept so old results are reproducible): ±x, ±y, ±z of the upright world frame (the
///   faces of the mesh's axis-aligned bounding box); centre of mass always the surface centroid.
/// For down-direction d the object is rotated so that d points to −z; its contact set is the vertices within
/// `contact_tolerance_m` of the lowest one (for a hull facet: of the facet's plane, so its own vertices are in it); the support polygon is
/// the 2D convex hull of the contact set in the plane; the placement is stable iff the polygon has positive area and
/// the centre of mass projects inside it at least `min_margin_m` from its boundary.

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/mesh/convex_hull.hpp"
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

/// The candidate faces: the convex hull's facets or the upright bounding box's six faces (see the file comment).
enum class PlacementRule : std::uint8_t { convex_hull, bounding_box };

[[nodiscard]] constexpr std::string_view to_string(PlacementRule r) {
  return r == PlacementRule::convex_hull ? "convex_hull" : "bounding_box";
}

/// Settings of the stability test.
struct PlacementSetting {
  double contact_tolerance_m = 0.002;  ///< vertices this close to the lowest one touch the support plane, ≥ 0
  double min_margin_m = 0.0;           ///< the projected centre of mass must lie farther inside than this, ≥ 0
  /// the candidate faces of `stable_placements` / `reorientation_placement`
  PlacementRule rule = PlacementRule::convex_hull;
  /// Hull rule: a facet whose down-direction is within this angle of −z is the bottom the object stands on, not a
  /// turn (`reorientation_placement` skips it), radians in [0, π].
  double min_turn_rad = std::numbers::pi / 6;

  void validate() const {
    detail::require_non_negative("PlacementSetting::contact_tolerance_m", contact_tolerance_m);
    detail::require_non_negative("PlacementSetting::min_margin_m", min_margin_m);
    detail::require(min_turn_rad >= 0.0 && min_turn_rad <= std::numbers::pi, "PlacementSetting::min_turn_rad ",
                    min_turn_rad, " must be in [0, pi]");
  }
};

/// One placement of the object.
struct Placement {
  /// The bounding-box face; hull rule: the one whose direction is nearest to `down` (ties: x before y before z).
  SupportFace face = SupportFace::minus_z;
  int hull_facet = -1;  ///< hull rule: facet index in `convex_hull` of the used vertices; −1: box rule
  Vec3 down = -Vec3::UnitZ();  ///< the upright-frame direction that points down (−z) after the turn, unit
  /// T_turn: upright world → reoriented world. The rotation takes `down` to −z (the shortest rotation; π about x for
  /// down = +z); the translation puts the lowest vertex on z = 0 and keeps the centre of mass's x, y.
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
/// True if every directed edge of a triangle is matched by the reverse edge of exactly one other triangle.
[[nodiscard]] inline bool is_closed_mesh(const IndexedMesh& mesh) {
  std::unordered_map<std::uint64_t, int> count;
  count.reserve(3 * mesh.triangles.size());
  const auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++count[key(t[k], t[(k + 1) % 3])];
  for (const auto& [e, n] : count) {
    const auto it = count.find(key(static_cast<std::uint32_t>(e & 0xffffffffu), static_cast<std::uint32_t>(e >> 32)));
    if (n != 1 || it == count.end() || it->second != 1) return false;
  }
  return !mesh.triangles.empty();
}
}  // namespace detail

/// The centre of mass of the object the mesh bounds (world frame): the volume centroid (signed tetrahedra about the
/// bounds' centre) if the mesh is closed and its volume is not ~0, else `surface_centroid`. Throws InvalidArgument
/// for an invalid mesh.
[[nodiscard]] inline Vec3 centre_of_mass(const IndexedMesh& mesh) {
  mesh.validate();
  if (!detail::is_closed_mesh(mesh)) return surface_centroid(mesh);
  const Vec3 o = mesh.bounds().center();
  Vec3 sum = Vec3::Zero();
  double volume = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3 a = mesh.corner(t, 0) - o, b = mesh.corner(t, 1) - o, c = mesh.corner(t, 2) - o;
    const double v = a.dot(b.cross(c)) / 6.0;
    volume += v;
    sum += v * (a + b + c) / 4.0;
  }
  const double extent = mesh.bounds().extent().norm();
  if (!(std::abs(volume) > 1e-12 * extent * extent * extent)) return surface_centroid(mesh);
  return o + sum / volume;
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

namespace detail {
/// The placement lying on down-direction `down` (unit) with rotation R (R·down = −z), centre of mass `com`; heights
/// (R v).z if `rotate_all`, else −down · v. The contact set is the vertices within `band_m` above `contact_from_m`
/// (a hull facet's plane height, so that its own vertices are in it even where rounding puts another vertex a few ε
/// below the plane), or above the lowest vertex if that is NaN; the lowest vertex goes to z = 0 in T_turn.
inline Placement evaluate_down(const IndexedMesh& mesh, const std::vector<char>& used, const Vec3& down, const Mat3& R,
                               const Vec3& com, double band_m, double min_margin_m, bool rotate_all,
                               double contact_from_m = std::numeric_limits<double>::quiet_NaN()) {
  Placement p;
  p.down = down;
  // Heights: (R v).z (the bounding-box rule, as first published) or −down · v (the same up to rounding, cheaper).
  const auto height = [&](const Vec3& v) { return rotate_all ? (R * v).z() : -down.dot(v); };
  double z_min = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) z_min = std::min(z_min, height(mesh.vertices[v]));
  const double contact_top = (std::isnan(contact_from_m) ? z_min : contact_from_m) + band_m;
  std::vector<detail::Vec2> contact;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (!used[v] || height(mesh.vertices[v]) > contact_top) continue;
    const Vec3 q = R * mesh.vertices[v];
    contact.emplace_back(q.x(), q.y());
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
  p.stable = p.support_area_m2 > 0.0 && p.margin_m > min_margin_m;
  p.T_turn.linear() = R;
  p.T_turn.translation() = Vec3(com.x() - c3.x(), com.y() - c3.y(), -z_min);
  return p;
}

/// A rotation R with R·down = −z for a unit `down`, orthonormal to rounding for every direction: Eigen's
/// FromTwoVectors loses precision for nearly opposite vectors (s = √(2(1 + c)) cancels, the quaternion is not
/// re-normalised: |q|² − 1 ≈ 1e-5 µrad from +z), so a `down` with z > 0.9 is first turned onto +z and then by π
/// about x. Below that the direct rotation is accurate and kept as it was (published runs stay reproducible).
inline Mat3 rotation_down(const Vec3& down) {
  if (down.z() > 0.9) {
    const Mat3 to_up = Eigen::Quaterniond::FromTwoVectors(down, Vec3::UnitZ()).normalized().toRotationMatrix();
    return Mat3(Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX())) * to_up;
  }
  return Eigen::Quaterniond::FromTwoVectors(down, -Vec3::UnitZ()).toRotationMatrix();
}

inline std::vector<char> used_vertices(const IndexedMesh& mesh) {
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& t : mesh.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  return used;
}

/// The bounding-box face whose direction is nearest to `down` (ties: x, then y, then z).
inline SupportFace nearest_face(const Vec3& down) {
  int a = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(down[k]) > std::abs(down[a])) a = k;
  return kSupportFaces[static_cast<std::size_t>(2 * a + (down[a] > 0.0 ? 1 : 0))];
}
}  // namespace detail

/// The placement of `mesh` (upright world frame) lying on bounding-box `face` (the bounding-box rule, surface
/// centroid), with its stability (see the file comment); never throws for an unstable one. Throws InvalidArgument
/// for an invalid mesh or setting.
[[nodiscard]] inline Placement evaluate_placement(const IndexedMesh& mesh, SupportFace face,
                                                  const PlacementSetting& setting = {}) {
  setting.validate();
  const Vec3 com = surface_centroid(mesh);  // validates the mesh
  const Vec3 down = detail::down_direction(face);
  Placement p = detail::evaluate_down(mesh, detail::used_vertices(mesh), down, detail::rotation_down(down), com,
                                      setting.contact_tolerance_m, setting.min_margin_m, true);
  p.face = face;
  return p;
}

/// The placements of `mesh` (upright world frame) on every facet of its convex hull (the hull rule; centre of mass
/// `centre_of_mass`), in facet order, stable or not; `hull_facet` indexes `convex_hull` of the mesh's used vertices
/// (in vertex order). The contact band is `contact_tolerance_m` + the hull's ε. Throws InvalidArgument for an invalid
/// mesh or setting, or a mesh without volume (its used vertices coplanar).
[[nodiscard]] inline std::vector<Placement> hull_placements(const IndexedMesh& mesh,
                                                            const PlacementSetting& setting = {}) {
  setting.validate();
  const Vec3 com = centre_of_mass(mesh);  // validates the mesh
  const std::vector<char> used = detail::used_vertices(mesh);
  std::vector<Vec3> pts;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) pts.push_back(mesh.vertices[v]);
  const ConvexHull hull = convex_hull(pts);
  std::vector<Placement> out;
  out.reserve(hull.facets.size());
  for (std::size_t f = 0; f < hull.facets.size(); ++f) {
    const Vec3 down = hull.facets[f].normal;
    const Mat3 R = detail::rotation_down(down);
    // The facet's plane is at height −offset (its lowest vertex); the band is measured from there.
    Placement p = detail::evaluate_down(mesh, used, down, R, com, setting.contact_tolerance_m + 4.0 * hull.epsilon,
                                        setting.min_margin_m, false, -hull.facets[f].offset);
    p.face = detail::nearest_face(down);
    p.hull_facet = static_cast<int>(f);
    out.push_back(std::move(p));
  }
  return out;
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

/// The stable placements by `setting.rule` (the hull's facets or the six bounding-box faces), by descending support
/// area; ties (areas equal to 1e-9 of the largest) in the order of `face` in kSupportFaces, then of `down`
/// (lexicographic).
[[nodiscard]] inline std::vector<Placement> stable_placements(const IndexedMesh& mesh,
                                                              const PlacementSetting& setting = {}) {
  std::vector<Placement> out;
  if (setting.rule == PlacementRule::bounding_box) {
    for (const SupportFace f : kSupportFaces)
      if (Placement p = evaluate_placement(mesh, f, setting); p.stable) out.push_back(p);
  } else {
    for (Placement& p : hull_placements(mesh, setting))
      if (p.stable) out.push_back(std::move(p));
  }
  double largest = 0.0;
  for (const Placement& p : out) largest = std::max(largest, p.support_area_m2);
  const auto key = [&](const Placement& p) {
    const double q = largest > 0.0 ? std::round(p.support_area_m2 / (1e-9 * largest)) : 0.0;
    return std::make_tuple(-q, static_cast<int>(p.face), p.down.x(), p.down.y(), p.down.z());
  };
  std::stable_sort(out.begin(), out.end(), [&](const Placement& a, const Placement& b) { return key(a) < key(b); });
  return out;
}

/// The turn for the second session: the stable placement with the largest support area (`stable_placements`) other
/// than the bottom the object stands on (bounding-box rule: minus_z; hull rule: facets within `min_turn_rad` of −z).
/// Largest area rather than largest margin: the object lies flattest and the area is what the band rule used before;
/// the margin is reported. Throws InvalidArgument, listing the candidates' margins (hull rule: the six largest
/// facets), if there is none.
[[nodiscard]] inline Placement reorientation_placement(const IndexedMesh& mesh, const PlacementSetting& setting = {}) {
  const auto is_bottom = [&](const Placement& p) {
    return setting.rule == PlacementRule::bounding_box ? p.face == SupportFace::minus_z
                                                       : -p.down.z() >= std::cos(setting.min_turn_rad);
  };
  for (const Placement& p : stable_placements(mesh, setting))
    if (!is_bottom(p)) return p;
  std::string why;
  if (setting.rule == PlacementRule::bounding_box) {
    for (const SupportFace f : kSupportFaces) {
      if (f == SupportFace::minus_z) continue;
      const Placement p = evaluate_placement(mesh, f, setting);
      why += detail::concat(" ", to_string(f), ": margin ", p.margin_m, " m, area ", p.support_area_m2, " m^2;");
    }
  } else {
    std::vector<Placement> all = hull_placements(mesh, setting);
    std::erase_if(all, is_bottom);
    std::stable_sort(all.begin(), all.end(),
                     [](const Placement& a, const Placement& b) { return a.support_area_m2 > b.support_area_m2; });
    why = detail::concat(" ", all.size(), " hull facets;");
    for (std::size_t i = 0; i < std::min<std::size_t>(6, all.size()); ++i)
      why += detail::concat(" facet ", all[i].hull_facet, " (near ", to_string(all[i].face), "): margin ",
                            all[i].margin_m, " m, area ", all[i].support_area_m2, " m^2;");
  }
  detail::require(false, "reorientation_placement (", to_string(setting.rule),
                  "): no stable placement other than the bottom;", why);
  return {};
}

}  // namespace nbs
