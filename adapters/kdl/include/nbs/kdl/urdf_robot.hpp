// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `nbs::kdl::UrdfRobot`: a `Robot` (robot/robot.hpp) read from a URDF file (urdfdom) with KDL's kinematics: the chain
/// base link → flange link (revolute, continuous, prismatic and fixed joints), a sensor link rigidly attached below
/// the flange (its fixed joints give the hand-eye transform T_FS), the base placed in the world at T_WB, and the
/// links' `<collision>` elements as `LinkShape`s (meshes loaded once, found by `resolve_mesh_uri`). IK: KDL's
/// Levenberg–Marquardt solver (`ChainIkSolverPos_LMA`) from the seed, then from seeded random configurations within
/// the limits; revolute angles are wrapped by 2π into their limits, a solution outside the limits or off the target
/// by more than the tolerances is rejected.
/// Thread-safety: const members may run concurrently (each ik call makes its own solver); `load` is not
/// thread-safe while urdfdom's console output is captured (console_bridge's global handler).

#include <console_bridge/console.h>
#include <kdl/chain.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "nbs/core/detail/random.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/driver/concepts.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/robot/collision_mesh.hpp"
#include "nbs/robot/robot.hpp"

namespace nbs::kdl {

/// Inverse-kinematics settings of `UrdfRobot`.
struct IkSetting {
  std::uint64_t seed = 1;             ///< seeds the random restarts: the same seed gives the same solutions
  int restarts = 30;                  ///< attempts from random configurations after the one from the seed (≥ 0)
  int max_iterations = 300;           ///< LMA iterations per attempt (> 0)
  double position_tolerance_m = 1e-5; ///< a solution's sensor position error, metres (> 0)
  double angle_tolerance_rad = 1e-5;  ///< a solution's sensor rotation error, radians (> 0)

  void validate() const {
    detail::require(restarts >= 0, "IkSetting::restarts must be >= 0, got ", restarts);
    detail::require(max_iterations > 0, "IkSetting::max_iterations must be > 0, got ", max_iterations);
    detail::require_positive("IkSetting::position_tolerance_m", position_tolerance_m);
    detail::require_positive("IkSetting::angle_tolerance_rad", angle_tolerance_rad);
  }
};

/// The file a URDF mesh reference `uri` names, for the URDF file `urdf`:
///  - `package://NAME/REST`: the first existing of R/NAME/REST, or R/REST if R's own name is NAME, for each
///    directory R in `package_roots` (in order), then in the environment variable ROS_PACKAGE_PATH (':'-separated);
///    then, if the URDF's directory or one of its ancestors is named NAME, the nearest such directory /REST (the
///    usual layout NAME/urdf/arm.urdf with NAME/meshes/);
///  - `file://PATH` and a plain PATH: PATH if absolute, else relative to the URDF's directory.
/// Throws FileError naming the URDF, `what` (the link) and the reference if no such file exists (listing the places
/// tried) or the scheme is not one of these.
[[nodiscard]] inline std::filesystem::path resolve_mesh_uri(const std::string& uri, const std::filesystem::path& urdf,
                                                            const std::vector<std::filesystem::path>& package_roots,
                                                            const std::string& what) {
  namespace fs = std::filesystem;
  const fs::path dir = urdf.has_parent_path() ? urdf.parent_path() : fs::path(".");
  const auto fail = [&](const std::string& why) {
    throw FileError(nbs::detail::concat(urdf.string(), ": ", what, ": collision mesh '", uri, "' ", why));
  };
  std::string tried;
  const auto exists = [&](const fs::path& p) {
    std::error_code ec;
    tried += (tried.empty() ? "" : ", ") + p.string();
    return fs::is_regular_file(p, ec);
  };
  constexpr std::string_view package = "package://", file = "file://";
  if (uri.starts_with(package)) {
    const std::string rest_all = uri.substr(package.size());
    const std::size_t slash = rest_all.find('/');
    if (slash == std::string::npos || slash == 0) fail("is not package://NAME/PATH");
    const std::string name = rest_all.substr(0, slash), rest = rest_all.substr(slash + 1);
    std::vector<fs::path> roots = package_roots;
    if (const char* env = std::getenv("ROS_PACKAGE_PATH"))
      for (std::string_view e(env); !e.empty();) {
        const std::size_t colon = e.find(':');
        if (colon != 0) roots.emplace_back(std::string(e.substr(0, colon)));
        e = colon == std::string_view::npos ? std::string_view() : e.substr(colon + 1);
      }
    for (const fs::path& r : roots) {
      if (exists(r / name / rest)) return r / name / rest;
      if (r.filename() == name && exists(r / rest)) return r / rest;
    }
    for (fs::path a = fs::absolute(dir); !a.empty(); a = a.parent_path()) {
      if (a.filename() == name) {
        if (exists(a / rest)) return a / rest;
        break;
      }
      if (a == a.parent_path()) break;
    }
    fail(nbs::detail::concat("not found (package roots: the given ones, then ROS_PACKAGE_PATH, then an ancestor "
                             "directory of the URDF named '", name, "'; tried: ", tried.empty() ? "nothing" : tried,
                             ")"));
  }
  std::string path = uri;
  if (uri.starts_with(file)) path = uri.substr(file.size());
  else if (uri.find("://") != std::string::npos) fail("has an unsupported scheme (package:// and file:// are)");
  if (path.empty()) fail("is empty");
  const fs::path p = fs::path(path).is_absolute() ? fs::path(path) : dir / path;
  if (!exists(p)) fail(nbs::detail::concat("not found (", p.string(), ")"));
  return p;
}

namespace detail_urdf {

/// Loads each (file, scale) once per URDF.
struct MeshCache {
  const std::filesystem::path& urdf;
  const std::vector<std::filesystem::path>& package_roots;
  std::map<std::pair<std::string, std::tuple<double, double, double>>, std::shared_ptr<const CollisionMesh>> loaded;

  [[nodiscard]] std::shared_ptr<const CollisionMesh> get(const std::string& uri, const Vec3& scale,
                                                         const std::string& link) {
    const std::string what = nbs::detail::concat("link '", link, "'");
    const std::filesystem::path p = resolve_mesh_uri(uri, urdf, package_roots, what);
    auto& slot = loaded[{p.string(), std::make_tuple(scale.x(), scale.y(), scale.z())}];
    if (slot) return slot;
    try {
      slot = std::make_shared<const CollisionMesh>(load_mesh(p.string()), scale, p.string());
    } catch (const nbs::Error& e) {
      throw FileError(nbs::detail::concat(urdf.string(), ": ", what, ": collision mesh '", uri, "': ", e.what()));
    }
    return slot;
  }
};

[[nodiscard]] inline Pose to_pose(const urdf::Pose& p) {
  double x = 0, y = 0, z = 0, w = 1;
  p.rotation.getQuaternion(x, y, z, w);
  Pose T = Pose::Identity();
  T.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  T.translation() = Vec3(p.position.x, p.position.y, p.position.z);
  return T;
}

[[nodiscard]] inline KDL::Frame to_kdl(const Pose& T) {
  const Mat3& R = T.linear();
  return KDL::Frame(KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)),
                    KDL::Vector(T.translation().x(), T.translation().y(), T.translation().z()));
}

[[nodiscard]] inline Pose to_pose(const KDL::Frame& f) {
  Pose T = Pose::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = f.M(r, c);
    T.translation()[r] = f.p(r);
  }
  return T;
}

/// Captures urdfdom's console_bridge messages during a parse (restored on destruction).
class CaptureConsole : public console_bridge::OutputHandler {
public:
  CaptureConsole() { console_bridge::useOutputHandler(this); }
  ~CaptureConsole() override { console_bridge::restorePreviousOutputHandler(); }
  CaptureConsole(const CaptureConsole&) = delete;
  CaptureConsole& operator=(const CaptureConsole&) = delete;
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) text_ += (text_.empty() ? "" : "; ") + text;
  }
  [[nodiscard]] const std::string& text() const { return text_; }

private:
  std::string text_;
};

/// The collision shapes of a URDF link, in the link frame; meshes loaded through `meshes`.
[[nodiscard]] inline std::vector<LinkShape> link_shapes(const urdf::Link& link, const std::string& file,
                                                        MeshCache& meshes) {
  std::vector<LinkShape> out;
  for (const auto& c : link.collision_array) {
    if (!c || !c->geometry) continue;
    LinkShape s;
    s.T_LG = to_pose(c->origin);
    switch (c->geometry->type) {
      case urdf::Geometry::BOX: {
        const auto& b = static_cast<const urdf::Box&>(*c->geometry);
        s.kind = LinkShape::Kind::box;
        s.size = Vec3(b.dim.x, b.dim.y, b.dim.z);
        break;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& y = static_cast<const urdf::Cylinder&>(*c->geometry);
        s.kind = LinkShape::Kind::cylinder;
        s.radius = y.radius;
        s.length = y.length;
        break;
      }
      case urdf::Geometry::SPHERE:
        s.kind = LinkShape::Kind::sphere;
        s.radius = static_cast<const urdf::Sphere&>(*c->geometry).radius;
        break;
      case urdf::Geometry::MESH: {
        const auto& m = static_cast<const urdf::Mesh&>(*c->geometry);
        s.kind = LinkShape::Kind::mesh;
        s.mesh_path = m.filename;
        s.size = Vec3(m.scale.x, m.scale.y, m.scale.z);
        nbs::detail::require(s.size.allFinite() && (s.size.array() > 0).all(), file, ": link '", link.name,
                             "': collision mesh '", m.filename, "' has scale (", s.size.transpose(),
                             "); it must be finite and > 0 per axis");
        s.mesh = meshes.get(m.filename, s.size, link.name);
        break;
      }
    }
    nbs::detail::require(s.size.allFinite() && (s.size.array() >= 0).all() && std::isfinite(s.radius) &&
                             s.radius >= 0 && std::isfinite(s.length) && s.length >= 0,
                         file, ": link '", link.name, "' has a collision shape with a negative or non-finite size");
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace detail_urdf

/// A URDF arm carrying the sensor. Joints are the movable joints of the chain base → flange, in chain order
/// (radians or metres); continuous joints are unlimited. Make it with `load`.
class UrdfRobot {
public:
  /// Reads `urdf` and builds the chain `base_link` → `flange_link`; `sensor_link` must hang below the flange on fixed
  /// joints only (or be the flange), which gives T_FS; `T_WB` places the base link in the world. Throws FileError
  /// (naming the file) if it cannot be read or parsed, InvalidArgument (naming the file and the link, joint or value)
  /// for a missing link, a flange not below the base, a sensor not rigidly below the flange, an unsupported joint
  /// type (floating, planar) or a mimic joint, a zero joint axis, NaN or inverted limits, a non-rigid `T_WB` or bad
  /// `ik` settings. Collision meshes (STL, OBJ, PLY; `scale` applied) are loaded here, once each, found by
  /// `resolve_mesh_uri` with `package_roots`; a missing, unreadable or malformed mesh or a scale that is not > 0
  /// throws FileError / InvalidArgument naming the URDF, the link and the mesh file.
  [[nodiscard]] static UrdfRobot load(const std::filesystem::path& urdf, const std::string& base_link,
                                      const std::string& flange_link, const std::string& sensor_link,
                                      const Pose& T_WB = Pose::Identity(), const IkSetting& ik = {},
                                      const std::vector<std::filesystem::path>& package_roots = {});

  [[nodiscard]] std::size_t joint_count() const { return static_cast<std::size_t>(limits_.size()); }
  [[nodiscard]] JointLimits joint_limits() const { return limits_; }
  [[nodiscard]] const std::vector<std::string>& joint_names() const { return joint_names_; }
  [[nodiscard]] Pose hand_eye() const { return T_FS_; }
  [[nodiscard]] Pose base_pose() const { return T_WB_; }
  [[nodiscard]] const IkSetting& ik_setting() const { return ik_; }
  [[nodiscard]] const std::filesystem::path& file() const { return file_; }

  /// Replaces T_FS (e.g. by a calibrated one, registration/hand_eye.hpp); throws InvalidArgument unless rigid.
  void set_hand_eye(const Pose& T_FS) {
    validate_pose(T_FS, "UrdfRobot hand-eye T_FS");
    T_FS_ = T_FS;
  }
  /// Replaces the IK settings; throws InvalidArgument (nothing changed) if invalid.
  void set_ik_setting(const IkSetting& s) {
    s.validate();
    ik_ = s;
  }

  /// The flange pose T_WF of q; throws InvalidArgument for a q of the wrong size or not finite.
  [[nodiscard]] Pose flange_pose(const JointVector& q) const { return link_poses(q).back(); }
  /// The sensor pose T_WS = T_WF · T_FS of q.
  [[nodiscard]] Pose fk(const JointVector& q) const { return sensor_from_flange(flange_pose(q), T_FS_); }

  /// A q within the limits with fk(q) = T_WS within the IK setting's tolerances, or nullopt; see the file comment.
  /// Throws InvalidArgument for a non-rigid T_WS or a seed of the wrong size or not finite.
  [[nodiscard]] std::optional<JointVector> ik(const Pose& T_WS, const JointVector& seed) const;

  /// Every collision shape of the base link, the chain's links and the sensor's links, placed for q.
  [[nodiscard]] std::vector<PlacedShape> collision_shapes(const JointVector& q) const;

private:
  struct ChainLink {
    std::string name;
    int joint = -1;  ///< index into q, −1 for a fixed joint
    std::vector<LinkShape> shapes;
  };

  /// T_WL of the base link, then of every segment's link (the last is the flange).
  [[nodiscard]] std::vector<Pose> link_poses(const JointVector& q) const {
    validate_joint_vector(q, joint_count(), "UrdfRobot joint vector");
    std::vector<Pose> out{T_WB_};
    out.reserve(links_.size() + 1);
    // KDL::Joint::pose caches its last result in mutable members: a chain shared by concurrent const calls races,
    // so every call works on its own copy (a few µs).
    const KDL::Chain chain = chain_;
    for (unsigned i = 0; i < chain.getNrOfSegments(); ++i) {
      const int j = links_[i + 1].joint;
      out.push_back(out.back() * detail_urdf::to_pose(chain.getSegment(i).pose(j < 0 ? 0.0 : q[j])));
    }
    return out;
  }

  /// `a` moved by whole turns into joint j's limits, nearest `near` (unchanged for a prismatic joint).
  [[nodiscard]] double wrap_into_limits(double a, double near, Eigen::Index j) const {
    if (!revolute_[static_cast<std::size_t>(j)]) return a;
    const double two_pi = 2.0 * std::numbers::pi;
    const double k0 = std::round((near - a) / two_pi);
    double best = a;
    bool found = false;
    for (double k = k0 - 2; k <= k0 + 2; k += 1.0) {
      const double v = a + k * two_pi;
      if (v < limits_.lower[j] || v > limits_.upper[j]) continue;
      if (!found || std::abs(v - near) < std::abs(best - near)) best = v;
      found = true;
    }
    return best;
  }

  std::filesystem::path file_;
  KDL::Chain chain_;
  std::vector<ChainLink> links_;  ///< [0] the base link, then one per chain segment
  std::vector<std::pair<std::string, Pose>> sensor_links_;  ///< links below the flange: name, T_FL
  std::vector<std::vector<LinkShape>> sensor_link_shapes_;
  std::vector<std::string> joint_names_;
  std::vector<bool> revolute_;
  JointLimits limits_;
  Pose T_WB_ = Pose::Identity();
  Pose T_FS_ = Pose::Identity();
  IkSetting ik_;
};

// ---- implementation ------------------------------------------------------------------------------------------------

inline UrdfRobot UrdfRobot::load(const std::filesystem::path& urdf, const std::string& base_link,
                                 const std::string& flange_link, const std::string& sensor_link, const Pose& T_WB,
                                 const IkSetting& ik, const std::vector<std::filesystem::path>& package_roots) {
  using nbs::detail::concat;
  using nbs::detail::require;
  const std::string file = urdf.string();
  validate_pose(T_WB, "UrdfRobot base pose T_WB");
  ik.validate();
  std::ifstream in(urdf);
  if (!in) throw FileError(concat(file, ": cannot open the URDF file"));
  std::stringstream text;
  text << in.rdbuf();
  urdf::ModelInterfaceSharedPtr model;
  std::string log;
  {
    detail_urdf::CaptureConsole capture;
    try {
      model = urdf::parseURDF(text.str());
    } catch (const std::exception& e) {
      throw FileError(concat(file, ": not a valid URDF: ", e.what()));
    }
    log = capture.text();
  }
  if (!model) throw FileError(concat(file, ": not a valid URDF", log.empty() ? "" : ": ", log));

  const auto link = [&](const std::string& name, const char* role) {
    urdf::LinkConstSharedPtr l = model->getLink(name);
    require(l != nullptr, file, ": ", role, " link '", name, "' is not in the URDF (robot '", model->getName(), "')");
    return l;
  };
  const urdf::LinkConstSharedPtr base = link(base_link, "base");
  const urdf::LinkConstSharedPtr flange = link(flange_link, "flange");
  const urdf::LinkConstSharedPtr sensor = link(sensor_link, "sensor");

  // Joints from the flange up to the base.
  std::vector<urdf::JointConstSharedPtr> joints;
  for (urdf::LinkConstSharedPtr l = flange; l->name != base_link;) {
    require(l->parent_joint != nullptr && l->getParent() != nullptr, file, ": flange link '", flange_link,
            "' is not below base link '", base_link, "' (the chain ends at the root '", l->name, "')");
    joints.push_back(l->parent_joint);
    l = l->getParent();
  }
  // The sensor below the flange, on fixed joints only.
  std::vector<urdf::JointConstSharedPtr> sensor_joints;
  for (urdf::LinkConstSharedPtr l = sensor; l->name != flange_link;) {
    require(l->parent_joint != nullptr && l->getParent() != nullptr, file, ": sensor link '", sensor_link,
            "' is not on the chain below flange link '", flange_link, "'");
    sensor_joints.push_back(l->parent_joint);
    l = l->getParent();
  }
  for (const auto& j : sensor_joints)
    require(j->type == urdf::Joint::FIXED, file, ": sensor link '", sensor_link, "' is not rigidly attached to flange link '",
            flange_link, "': joint '", j->name, "' is not fixed");

  detail_urdf::MeshCache meshes{urdf, package_roots, {}};
  UrdfRobot r;
  r.file_ = urdf;
  r.T_WB_ = T_WB;
  r.ik_ = ik;
  r.links_.push_back({base_link, -1, detail_urdf::link_shapes(*base, file, meshes)});
  std::vector<double> lower, upper;
  for (auto it = joints.rbegin(); it != joints.rend(); ++it) {
    const urdf::Joint& j = **it;
    const Pose F = detail_urdf::to_pose(j.parent_to_joint_origin_transform);
    const Vec3 axis(j.axis.x, j.axis.y, j.axis.z);
    const KDL::Frame f = detail_urdf::to_kdl(F);
    const KDL::Vector a = f.M * KDL::Vector(axis.x(), axis.y(), axis.z());
    KDL::Joint kj(j.name, KDL::Joint::Fixed);
    int index = -1;
    if (j.type != urdf::Joint::FIXED) {
      require(j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS || j.type == urdf::Joint::PRISMATIC,
              file, ": joint '", j.name, "' has a type nbs::kdl does not support (floating or planar)");
      require(axis.allFinite() && axis.norm() > 1e-9, file, ": joint '", j.name, "' has axis (", axis.transpose(),
              ")");
      require(j.mimic == nullptr, file, ": joint '", j.name, "' mimics joint '", j.mimic ? j.mimic->joint_name : "",
              "' (mimic joints are not supported)");
      const bool prismatic = j.type == urdf::Joint::PRISMATIC;
      kj = KDL::Joint(j.name, f.p, a / a.Norm(), prismatic ? KDL::Joint::TransAxis : KDL::Joint::RotAxis);
      double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
      if (j.type != urdf::Joint::CONTINUOUS) {
        require(j.limits != nullptr, file, ": joint '", j.name, "' has no <limit>");
        lo = j.limits->lower;
        hi = j.limits->upper;
        require(!std::isnan(lo) && !std::isnan(hi) && lo <= hi, file, ": joint '", j.name, "' has limits [", lo,
                ", ", hi, "] (NaN or inverted)");
      }
      index = static_cast<int>(lower.size());
      lower.push_back(lo);
      upper.push_back(hi);
      r.joint_names_.push_back(j.name);
      r.revolute_.push_back(!prismatic);
    }
    r.chain_.addSegment(KDL::Segment(j.child_link_name, kj, f));
    r.links_.push_back(
        {j.child_link_name, index, detail_urdf::link_shapes(*model->getLink(j.child_link_name), file, meshes)});
  }
  r.limits_.lower = Eigen::Map<const JointVector>(lower.data(), static_cast<Eigen::Index>(lower.size()));
  r.limits_.upper = Eigen::Map<const JointVector>(upper.data(), static_cast<Eigen::Index>(upper.size()));
  Pose T_FL = Pose::Identity();
  for (auto it = sensor_joints.rbegin(); it != sensor_joints.rend(); ++it) {
    T_FL = T_FL * detail_urdf::to_pose((*it)->parent_to_joint_origin_transform);
    r.sensor_links_.emplace_back((*it)->child_link_name, T_FL);
    r.sensor_link_shapes_.push_back(detail_urdf::link_shapes(*model->getLink((*it)->child_link_name), file, meshes));
  }
  r.T_FS_ = T_FL;
  return r;
}

inline std::optional<JointVector> UrdfRobot::ik(const Pose& T_WS, const JointVector& seed) const {
  validate_pose(T_WS, "UrdfRobot ik target T_WS");
  validate_joint_vector(seed, joint_count(), "UrdfRobot ik seed");
  const auto n = static_cast<Eigen::Index>(joint_count());
  if (n == 0) {  // a fixed sensor: the one pose or nothing
    const JointVector none(0);
    if (poses_agree(fk(none), T_WS, ik_.position_tolerance_m, ik_.angle_tolerance_rad)) return none;
    return std::nullopt;
  }
  const KDL::Frame goal = detail_urdf::to_kdl(T_WB_.inverse() * flange_from_sensor(T_WS, T_FS_));
  Eigen::Matrix<double, 6, 1> weights;
  weights << 1, 1, 1, 1, 1, 1;
  const KDL::Chain chain = chain_;  // the solver's own copy: KDL::Joint::pose caches in mutable members (races)
  KDL::ChainIkSolverPos_LMA solver(chain, weights, 1e-12, ik_.max_iterations, 1e-15);
  std::mt19937_64 rng(nbs::detail::splitmix64(ik_.seed));
  KDL::JntArray init(static_cast<unsigned>(n)), out(static_cast<unsigned>(n));
  for (int attempt = 0; attempt <= ik_.restarts; ++attempt) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const double lo = std::max(limits_.lower[j], -std::numbers::pi);
      const double hi = std::min(limits_.upper[j], std::numbers::pi);
      init(static_cast<unsigned>(j)) = attempt == 0 ? std::clamp(seed[j], limits_.lower[j], limits_.upper[j])
                                                    : lo + (hi - lo) * nbs::detail::uniform01(rng);
    }
    (void)solver.CartToJnt(init, goal, out);  // judged below by the limits and the pose error
    JointVector q(n);
    for (Eigen::Index j = 0; j < n; ++j) q[j] = wrap_into_limits(out(static_cast<unsigned>(j)), seed[j], j);
    if (!limits_.contains(q)) continue;
    if (poses_agree(fk(q), T_WS, ik_.position_tolerance_m, ik_.angle_tolerance_rad)) return q;
  }
  return std::nullopt;
}

inline std::vector<PlacedShape> UrdfRobot::collision_shapes(const JointVector& q) const {
  const std::vector<Pose> T_WL = link_poses(q);
  std::vector<PlacedShape> out;
  const auto place = [&out](const std::string& link, const std::vector<LinkShape>& shapes, const Pose& T) {
    for (const LinkShape& s : shapes) out.push_back({link, s, T * s.T_LG});
  };
  for (std::size_t i = 0; i < links_.size(); ++i) place(links_[i].name, links_[i].shapes, T_WL[i]);
  for (std::size_t i = 0; i < sensor_links_.size(); ++i)
    place(sensor_links_[i].first, sensor_link_shapes_[i], T_WL.back() * sensor_links_[i].second);
  return out;
}

}  // namespace nbs::kdl
