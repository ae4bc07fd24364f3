// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The robot's links against the voxel space and the table (issue 19, item 2; thesis Sec. 3.2.2: voxels with
/// p > 0.05 are obstacles, unknown space included). `LinkCollisionChecker` tests the collision shapes
/// `robot.collision_shapes(q)` of a configuration; `RobotPathChecker` runs `check_scan_path` with it as the
/// configuration check and reports a collision with the link's name and the step.
///
/// Voxels: a voxel is hit by a shape if the distance from the voxel's centre to the solid shape is at most
/// `safety_margin_m` + √3/2 · l_v (half the voxel diagonal). This is conservative: every voxel whose cube comes within
/// the margin of the shape is hit; a hit voxel's cube may be up to √3 · l_v + margin from the shape. The sensor link
/// is checked like any other: at the scanning standoff (≥ 0.15 m for the thesis's sensors) it is far from the
/// voxels it scans, so it does not collide with them; a sensor body driven into the object does.
/// Table: the half-space z < `table_height_m` (optionally limited to an xy rectangle) — a shape collides if its
/// lowest point is below `table_height_m` + margin. Links mounted on the table by design (the robot's base) are
/// exempt by name (`table_exempt_links`); they are still checked against the voxels.
/// Meshes (`LinkShape::mesh`, loaded once by the robot model, e.g. nbs::kdl::UrdfRobot): the same rule with the
/// distance to the solid mesh — the nearest triangle, or inside for a closed mesh (ray parity; an open mesh is a thin
/// shell, see robot/collision_mesh.hpp), voxels restricted to the mesh's exact world AABB (its transformed vertices);
/// table test by its lowest transformed vertex. Cost per voxel: the voxel's p look-up, then for an obstacle
/// CollisionMesh::within (the triangles binned near the voxel centre and in its column; docs/robot.md for timings).
/// A mesh shape whose model did not load it (null `mesh`) is refused at construction, naming the link and file,
/// unless `skip_mesh_shapes` is set, which leaves every mesh unchecked.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "nbs/candidates/collision.hpp"
#include "nbs/robot/reachability.hpp"
#include "nbs/robot/robot.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs {

/// What the links must not touch. Metres, world frame.
struct LinkCollisionSetting {
  double obstacle_probability = 0.05;  ///< voxels with p above this are obstacles (Sec. 3.2.2), in [0, 1]
  bool unknown_is_obstacle = true;     ///< unknown voxels (p = 0.5) are obstacles (the thesis); false: observed only
  double safety_margin_m = 0.0;        ///< extra clearance around every shape (≥ 0)
  bool check_table = true;             ///< test the table half-space
  double table_height_m = 0.0;         ///< table top z (the pedestal top is z = 0 in nbs's world frame)
  Eigen::Vector2d table_min_xy = Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity());
  Eigen::Vector2d table_max_xy = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  std::vector<std::string> table_exempt_links;  ///< links standing on the table by design (e.g. "lwr_base_link")
  bool skip_mesh_shapes = false;  ///< true: mesh shapes are not checked (false: checked; refused if not loaded)

  /// Throws InvalidArgument naming the bad field.
  void validate() const {
    detail::require_in_range("LinkCollisionSetting::obstacle_probability", obstacle_probability, 0.0, 1.0);
    detail::require_non_negative("LinkCollisionSetting::safety_margin_m", safety_margin_m);
    detail::require(std::isfinite(table_height_m), "LinkCollisionSetting::table_height_m must be finite, got ",
                    table_height_m);
    for (int a = 0; a < 2; ++a)
      detail::require(!std::isnan(table_min_xy[a]) && !std::isnan(table_max_xy[a]) &&
                          table_min_xy[a] <= table_max_xy[a],
                      "LinkCollisionSetting table extent along ", a == 0 ? "x" : "y", " is [", table_min_xy[a], ", ",
                      table_max_xy[a], "] (NaN or inverted)");
  }
};

/// Where a configuration collides: the link, and a voxel (its key) or the table.
struct LinkContact {
  enum class With { voxel, table };
  std::string link;
  With with = With::voxel;
  VoxelKey voxel{};  ///< the first obstacle voxel hit (With::voxel only)
};

namespace detail {

/// Signed distance from the world point p to the solid shape placed at T_WG (negative inside), metres; for a mesh
/// CollisionMesh::distance (≥ 0 for an open mesh; +inf if it is not loaded). Shapes as defined at LinkShape.
[[nodiscard]] inline double shape_distance(const LinkShape& s, const Pose& T_WG, const Vec3& p) {
  const Vec3 g = T_WG.linear().transpose() * (p - T_WG.translation());  // p in the shape frame G
  switch (s.kind) {
    case LinkShape::Kind::sphere: return g.norm() - s.radius;
    case LinkShape::Kind::capsule: {
      const double h = std::clamp(g.z(), -0.5 * s.length, 0.5 * s.length);
      return (g - Vec3(0, 0, h)).norm() - s.radius;
    }
    case LinkShape::Kind::cylinder: {
      const double dr = std::hypot(g.x(), g.y()) - s.radius, da = std::abs(g.z()) - 0.5 * s.length;
      return std::min(std::max(dr, da), 0.0) + std::hypot(std::max(dr, 0.0), std::max(da, 0.0));
    }
    case LinkShape::Kind::box: {
      const Vec3 d = g.cwiseAbs() - 0.5 * s.size;
      return std::min(d.maxCoeff(), 0.0) + d.cwiseMax(0.0).norm();
    }
    case LinkShape::Kind::mesh:
      if (s.mesh) return s.mesh->distance(g);
      break;
  }
  return std::numeric_limits<double>::infinity();
}

/// The exact world AABB of the solid shape placed at T_WG (empty for a mesh that is not loaded).
[[nodiscard]] inline Aabb shape_bounds(const LinkShape& s, const Pose& T_WG) {
  const Mat3& R = T_WG.linear();
  Vec3 r = Vec3::Zero();
  switch (s.kind) {
    case LinkShape::Kind::sphere: r = Vec3::Constant(s.radius); break;
    case LinkShape::Kind::capsule: r = 0.5 * s.length * R.col(2).cwiseAbs() + Vec3::Constant(s.radius); break;
    case LinkShape::Kind::cylinder:
      for (int i = 0; i < 3; ++i)
        r[i] = 0.5 * s.length * std::abs(R(i, 2)) + s.radius * std::sqrt(std::max(0.0, 1.0 - R(i, 2) * R(i, 2)));
      break;
    case LinkShape::Kind::box: r = R.cwiseAbs() * (0.5 * s.size); break;
    case LinkShape::Kind::mesh: return s.mesh ? s.mesh->world_bounds(T_WG) : Aabb{};
  }
  return {T_WG.translation() - r, T_WG.translation() + r};
}

/// Throws InvalidArgument naming the link unless the shape's dimensions are finite and ≥ 0 and its pose is finite.
inline void validate_shape(const PlacedShape& p) {
  const LinkShape& s = p.shape;
  detail::require(p.T_WG.matrix().allFinite() && s.size.allFinite() && (s.size.array() >= 0.0).all() &&
                      std::isfinite(s.radius) && s.radius >= 0.0 && std::isfinite(s.length) && s.length >= 0.0,
                  "collision shape of link '", p.link, "' has a non-finite pose or a negative or non-finite size "
                  "(size ", s.size.transpose(), ", radius ", s.radius, ", length ", s.length, ")");
}

/// validate_shape, and a mesh shape must be loaded; `owner` names where the shape comes from (e.g. "GrippedSetup
/// finger").
inline void validate_loaded_shape(const PlacedShape& p, std::string_view owner) {
  validate_shape(p);
  detail::require(p.shape.kind != LinkShape::Kind::mesh || p.shape.mesh != nullptr, owner, " '", p.link,
                  "' is a mesh that is not loaded");
}

}  // namespace detail

/// The robot's collision shapes at q against the obstacle voxels of a space and the table (see the file comment for
/// the tests and their tolerance). Holds references to the robot and the space: both must outlive the checker, and
/// the space must not change while a check runs. Const members may run concurrently (if the robot's do).
/// Cost: per shape, one distance evaluation per voxel of its world AABB inflated by margin + √3/2 l_v (clipped to
/// the space's bounds), one p look-up only for voxels within reach (a mesh: the p look-up first, then the mesh test,
/// O(triangles)); stops at the first collision.
template <Robot R, VoxelSpace Space>
class LinkCollisionChecker {
public:
  using Setting = LinkCollisionSetting;

  /// Throws InvalidArgument for an invalid setting, or — found from the shapes at the middle of the joint limits
  /// (0 for an unlimited joint) — a shape with bad dimensions or, unless `skip_mesh_shapes`, a mesh shape whose
  /// mesh is not loaded, naming the link and the file.
  LinkCollisionChecker(const R& robot, const Space& space, Setting setting = {})
      : robot_(&robot), space_(&space), setting_(std::move(setting)) {
    setting_.validate();
    const JointLimits lim = robot.joint_limits();
    JointVector q0 = JointVector::Zero(static_cast<Eigen::Index>(robot.joint_count()));
    for (Eigen::Index j = 0; j < q0.size(); ++j)
      if (std::isfinite(lim.lower[j]) && std::isfinite(lim.upper[j])) q0[j] = 0.5 * (lim.lower[j] + lim.upper[j]);
    for (const PlacedShape& p : robot.collision_shapes(q0)) {
      detail::validate_shape(p);
      require_loaded(p);
    }
    reach_m_ = setting_.safety_margin_m + 0.5 * std::sqrt(3.0) * space.resolution_m();
  }

  [[nodiscard]] const Setting& setting() const { return setting_; }

  /// The first contact of the links at q (shapes in the robot's order, the table before the voxels per shape), or
  /// nullopt if q is collision-free. Throws InvalidArgument for a q of the wrong size or not finite, or a mesh shape
  /// that is not loaded (unless `skip_mesh_shapes`).
  [[nodiscard]] std::optional<LinkContact> first_contact(const JointVector& q) const {
    validate_joint_vector(q, robot_->joint_count(), "LinkCollisionChecker q");
    for (const PlacedShape& p : robot_->collision_shapes(q)) {
      const bool mesh = p.shape.kind == LinkShape::Kind::mesh;
      if (mesh && setting_.skip_mesh_shapes) continue;
      if (mesh) require_loaded(p);
      const Aabb b = detail::shape_bounds(p.shape, p.T_WG);
      if (hits_table(p.link, b)) return LinkContact{p.link, LinkContact::With::table, {}};
      const Aabb reach{b.min - Vec3::Constant(reach_m_), b.max + Vec3::Constant(reach_m_)};
      const double l = space_->resolution_m();
      const Pose T_GW = p.T_WG.inverse();
      const auto key = detail::first_voxel_in(*space_, reach, [&](const VoxelKey& k, const Aabb& cube) {
        const Vec3 c = cube.min + Vec3::Constant(0.5 * l);
        if (mesh) return is_obstacle(k) && p.shape.mesh->within(T_GW * c, reach_m_);
        return detail::shape_distance(p.shape, p.T_WG, c) <= reach_m_ && is_obstacle(k);
      });
      if (key) return LinkContact{p.link, LinkContact::With::voxel, *key};
    }
    return std::nullopt;
  }

  /// True if q collides (first_contact(q) has a value).
  [[nodiscard]] bool collides(const JointVector& q) const { return first_contact(q).has_value(); }

  /// True if voxel k is an obstacle: p > obstacle_probability and, unless unknown_is_obstacle, observed.
  [[nodiscard]] bool is_obstacle(const VoxelKey& k) const {
    return space_->probability(k) > setting_.obstacle_probability &&
           (setting_.unknown_is_obstacle || space_->observed(k));
  }

private:
  // Throws InvalidArgument naming the link and file if p is a mesh shape without a loaded mesh (and meshes are not
  // skipped).
  void require_loaded(const PlacedShape& p) const {
    detail::require(p.shape.kind != LinkShape::Kind::mesh || p.shape.mesh != nullptr || setting_.skip_mesh_shapes,
                    "link '", p.link, "' has a mesh collision shape (", p.shape.mesh_path,
                    ") whose mesh is not loaded (LinkShape::mesh is null): load it when making the robot "
                    "(nbs::kdl::UrdfRobot does), or set LinkCollisionSetting::skip_mesh_shapes to leave meshes "
                    "unchecked");
  }

  // The table test of one shape with world AABB b: lowest point below the table top + margin, and b (inflated by the
  // margin) over the table's xy extent (conservative for a shape partly beside a finite table).
  [[nodiscard]] bool hits_table(const std::string& link, const Aabb& b) const {
    const auto& exempt = setting_.table_exempt_links;
    if (!setting_.check_table || std::ranges::find(exempt, link) != exempt.end()) return false;
    const double m = setting_.safety_margin_m;
    return b.min.z() < setting_.table_height_m + m && b.max.x() + m >= setting_.table_min_xy.x() &&
           b.min.x() - m <= setting_.table_max_xy.x() && b.max.y() + m >= setting_.table_min_xy.y() &&
           b.min.y() - m <= setting_.table_max_xy.y();
  }

  const R* robot_;
  const Space* space_;
  Setting setting_;
  double reach_m_ = 0.0;
};

/// Is a linear scan path executable by the robot (issue 19, item 2)? `check_scan_path` (IK at every ≤ 10 mm step,
/// continuous joints within limits) with the links checked against the voxel space and the table at every sampled
/// configuration. A collision is reported as PathFailure::collision with the link (`ScanPathReach::link`), the step
/// and its arc-length fraction t (`value`). Same lifetime rules and thread-safety as LinkCollisionChecker.
template <Robot R, VoxelSpace Space>
class RobotPathChecker {
public:
  /// Throws InvalidArgument for an invalid setting (either) or a robot LinkCollisionChecker refuses.
  RobotPathChecker(const R& robot, const Space& space, LinkCollisionSetting collision = {},
                   ScanPathReachSetting reach = {})
      : robot_(&robot), links_(robot, space, std::move(collision)), reach_(reach) {
    reach_.validate();
  }

  [[nodiscard]] const LinkCollisionChecker<R, Space>& links() const { return links_; }
  [[nodiscard]] const ScanPathReachSetting& reach_setting() const { return reach_; }

  /// check_scan_path(robot, path, seed, reach setting) with the links' collision test; throws as it does.
  [[nodiscard]] ScanPathReach check(const LinearScanPath& path, const JointVector& seed) const {
    std::optional<LinkContact> contact;
    const auto collision_free = [&](const JointVector& q, const Pose&) {
      contact = links_.first_contact(q);
      return !contact;
    };
    ScanPathReach out = check_scan_path(*robot_, path, seed, reach_, collision_free);
    if (out.failure == PathFailure::configuration_rejected && contact) {
      out.failure = PathFailure::collision;
      out.link = contact->link;
    }
    return out;
  }

private:
  const R* robot_;
  LinkCollisionChecker<R, Space> links_;
  ScanPathReachSetting reach_;
};

}  // namespace nbs
