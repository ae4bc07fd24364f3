// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// One Boundary Search candidate from one boundary (Secs. 4.2.2, 4.3.1, 4.3.2).

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "nbs/candidates/boundary_search_setting.hpp"
#include "nbs/candidates/detail/normal_pca.hpp"
#include "nbs/candidates/detail/patch_viewpoint.hpp"
#include "nbs/candidates/planning_context.hpp"
#include "nbs/candidates/scan_candidate.hpp"

namespace nbs::detail {

/// Data shared by all boundaries of one call.
struct BoundarySearchFrame {
  Pose t_ws, t_sw;                 ///< last sensor pose and its inverse
  std::vector<Vec3> world_vertices;  ///< triangulated vertices (world): path extent, Fig. 4.9
  Aabb sensor_extent;              ///< triangulated vertices in S: mesh extent per axis
  double standoff_m = 0.3;
  double last_path_length_m = 0.0;
  SensorGeometry sensor;
};

/// Boundary inside the FOV of the last scan (not on its limiting line of sight), Sec. 4.3.1. q: c_b in S.
[[nodiscard]] inline bool inside_fov(const Vec3& q, const BoundaryAxes& ax, const BoundarySearchFrame& f,
                                     const BoundarySearchSetting& t) {
  if (!(q.z() > 0.0)) return false;
  if (ax.trend == 0)
    return std::abs(std::atan2(q.x(), q.z())) < 0.5 * f.sensor.fov_x_rad - t.fov_edge_margin_rad;
  if (f.sensor.kind == SensorGeometry::Kind::area)
    return std::abs(std::atan2(q.y(), q.z())) < 0.5 * f.sensor.fov_y_rad - t.fov_edge_margin_rad;
  return q.y() > t.fov_edge_margin_m && q.y() < f.last_path_length_m - t.fov_edge_margin_m;
}

/// Candidate for boundary `b` (index `index`), or nullopt if its region cannot be fitted or no view exists.
template <EdgeMesh M>
[[nodiscard]] std::optional<ScanCandidate> boundary_candidate(const M& mesh, const MeshTopology& topo,
                                                              const Boundary& b, std::size_t index,
                                                              const BoundarySearchFrame& f, const Parameters& params,
                                                              const BoundarySearchSetting& t) {
  if (b.edges.empty() || b.vertices.size() < 2) return std::nullopt;
  const BoundaryAxes ax = boundary_axes(b.type);
  std::vector<Vec3> qb;
  qb.reserve(b.vertices.size());
  for (VertexId v : b.vertices) qb.push_back(f.t_sw * Vec3(mesh.position(v)));
  const VertexId cb = boundary_center_vertex(b);
  const Vec3 q_cb = f.t_sw * Vec3(mesh.position(cb));

  // Boundary region and weighted quadratic patch (Sec. 4.2.2, Eqs. 4.4–4.11).
  const SensorBox box = boundary_box(qb, ax, f.sensor_extent.extent()[ax.trend], t.region_fraction,
                                     params.mesh_radius_m);
  const std::vector<VertexId> region = grow_region(mesh, topo, f.t_sw, cb, box);
  const std::vector<double> weights = region_weights(mesh, region, b.vertices, params.mesh_radius_m);
  std::vector<Vec3> q_region, normals;
  q_region.reserve(region.size());
  for (VertexId v : region) {
    q_region.push_back(f.t_sw * Vec3(mesh.position(v)));
    if (Vec3(mesh.normal(v)).squaredNorm() > 0.0) normals.push_back(mesh.normal(v));
  }
  const auto patch = fit_quadratic_patch(q_region, weights);
  if (!patch) return std::nullopt;

  // Walk along the patch to the wanted overlap (Sec. 4.3.1).
  PatchWalk w;
  w.patch = &*patch;
  w.axes = ax;
  w.c_b = q_cb;
  // d_b = dir(v_1, v_m), Eq. 4.15, oriented along +s (Tab. 4.1: E_B is directed along s).
  w.d_b = (f.t_sw.linear() * (Vec3(mesh.position(b.edges.back()[1])) - Vec3(mesh.position(b.edges.front()[0]))));
  if (!(w.d_b.norm() > 0.0)) return std::nullopt;
  w.d_b.normalize();
  w.standoff_m = f.standoff_m;
  w.baseline_m = f.sensor.baseline_m(f.standoff_m);
  w.step_m = t.step_fraction * w.baseline_m;
  w.overlap = params.scan_overlap;
  w.max_step_angle_rad = t.max_step_angle_rad;
  const auto view = walk_patch(w);
  if (!view) return std::nullopt;

  // To world (Eq. 4.12).
  const Mat3 r = f.t_ws.linear();
  Vec3 s_x = r * view->s_x, s_y = r * view->s_y, s_z = r * view->s_z, s_p = f.t_ws * view->s_p;
  Vec3 p = f.t_ws * view->p;
  ScanCandidate c;
  c.source = CandidateSource::boundary_search;
  c.index = index;
  c.overlap = w.overlap_of(*view);

  // Sharp corner (Sec. 4.3.1, Fig. 4.7): planar region and boundary inside the FOV → rotate about the boundary.
  Eigen::Matrix3d rot = Mat3::Identity();
  const Vec3 cb_w = mesh.position(cb);
  if (normals_planar(normals, params.planar_eigenvalue_max) && inside_fov(q_cb, ax, f, t)) {
    const Vec3 axis = r * w.d_b;
    const Vec3 tangent = r * (w.point(q_cb[ax.trend] + ax.sign * w.step_m) - w.point(q_cb[ax.trend]));
    const double a = params.sharp_corner_rotation_rad;
    rot = Eigen::AngleAxisd(a, axis).toRotationMatrix();
    if ((rot * s_z).dot(tangent) > 0.0) rot = Eigen::AngleAxisd(-a, axis).toRotationMatrix();  // look back at it
    s_x = rot * s_x, s_y = rot * s_y, s_z = rot * s_z;
    s_p = cb_w + rot * (s_p - cb_w);
    p = cb_w + rot * (p - cb_w);
    c.sharp_corner = true;
  }
  const Viewpoint v = Viewpoint::from_axes(s_x.normalized(), s_y.normalized(), s_z.normalized(), s_p);
  c.aim = {p, -v.view_direction()};

  // Scan path over the whole mesh along s_y (Sec. 4.3.2, Fig. 4.9).
  if (f.sensor.kind == SensorGeometry::Kind::line) {
    double t0 = 0.0, t1 = 0.0;
    for (const Vec3& x : f.world_vertices) {
      const double s = (x - p).dot(v.y_axis());
      t0 = std::min(t0, s), t1 = std::max(t1, s);
    }
    Pose start = v.pose();
    start.translation() = s_p + t0 * v.y_axis();
    c.path = LinearScanPath(Viewpoint(start), s_p + t1 * v.y_axis());
  } else {
    c.path = LinearScanPath(v);
  }

  // Targets: the patch points beside each (sub-sampled) boundary vertex, shifted like c_b → p (along d_b).
  const double shift = view->u - q_cb[ax.trend];
  const std::size_t n = qb.size(), k = std::min<std::size_t>(n, static_cast<std::size_t>(t.max_targets));
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3& q = qb[k == 1 ? n / 2 : i * (n - 1) / (k - 1)];
    Eigen::Vector2d xy;
    xy[ax.trend] = q[ax.trend] + shift;
    xy[ax.along] = q[ax.along];
    const Vec3 pt = f.t_ws * patch->point(xy.x(), xy.y());
    const Vec3 nr = (r * patch->normal(xy.x(), xy.y())).normalized();  // points to the sensor side
    if (!pt.allFinite() || !nr.allFinite()) continue;
    c.targets.push_back({cb_w + rot * (pt - cb_w), rot * nr});
  }
  return c;
}

}  // namespace nbs::detail
