// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Verification of a pose hypothesis by rendering (thesis Sec. 3.4): the database model is ray cast at the
/// hypothesis pose into the pixel grid of the area sensor that took the current range image, and the rendered
/// depths are compared with the cluster's measured depths by q_h (Eq. 3.10, hypothesis_quality.hpp). CPU ray casting
/// over any RayCaster (BruteForceRayCaster; nbs::embree::Scene is the fast one).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "nbs/core/detail/parallel_for.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/recognition/hypothesis_quality.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/sim/ray_caster.hpp"

namespace nbs {

/// A depth image in an area sensor's pixel grid: depth[v·w + u] is the z coordinate (metres, sensor frame S,
/// along the viewing direction) of the surface seen through pixel (u, v); NaN = no depth. `sensor_pose` is T_WS.
struct RangeImage {
  AreaSensor sensor;
  Pose sensor_pose = Pose::Identity();
  std::vector<double> depth;

  /// The pixel (u, v) whose ray passes nearest to the sensor-frame point `p_s` (the pixel whose footprint
  /// [u, u+1) × [v, v+1) in AreaSensor's image-plane coordinates holds it), or nullopt if p_s is not in front
  /// (z ≤ 0) or outside the image.
  [[nodiscard]] std::optional<std::array<int, 2>> pixel_of(const Vec3& p_s) const {
    if (!(p_s.z() > 0.0)) return std::nullopt;
    const double cu = (p_s.x() / p_s.z() / std::tan(0.5 * sensor.horizontal_fov_rad) + 1.0) * 0.5 * sensor.width_px;
    const double cv = (p_s.y() / p_s.z() / std::tan(0.5 * sensor.vertical_fov_rad) + 1.0) * 0.5 * sensor.height_px;
    if (!(cu >= 0.0 && cu < sensor.width_px && cv >= 0.0 && cv < sensor.height_px)) return std::nullopt;
    return std::array<int, 2>{static_cast<int>(cu), static_cast<int>(cv)};
  }
};

/// The range image of world points seen by `sensor` at T_WS = `sensor_pose` (e.g. the points of one cluster of an
/// area-sensor Scan): each point is projected into its pixel; a pixel hit by several keeps the nearest depth.
/// Points behind the sensor or outside the image are dropped. Throws InvalidArgument for an invalid sensor or a
/// non-finite point.
[[nodiscard]] inline RangeImage range_image(const AreaSensor& sensor, const Pose& sensor_pose,
                                            std::span<const Vec3> points_w) {
  sensor.validate();
  validate_pose(sensor_pose, "range_image: sensor_pose");
  RangeImage img{sensor, sensor_pose, std::vector<double>(sensor.ray_count(), std::numeric_limits<double>::quiet_NaN())};
  const Pose t_sw = sensor_pose.inverse();
  for (std::size_t i = 0; i < points_w.size(); ++i) {
    detail::require(points_w[i].allFinite(), "range_image: point ", i, " is not finite");
    const Vec3 p = t_sw * points_w[i];
    const auto px = img.pixel_of(p);
    if (!px) continue;
    double& d = img.depth[static_cast<std::size_t>((*px)[1]) * sensor.width_px + (*px)[0]];
    if (!(d <= p.z())) d = p.z();  // NaN or farther: keep the nearer
  }
  return img;
}

/// Renders the model held by `model` (a RayCaster in the model frame M) placed at T_WM = `model_pose` into the
/// pixel grid of `geometry` (its sensor and T_WS; its depths are not used): per pixel the first hit of the pixel's
/// ray, kept if its distance lies in the sensor's working range, as depth along S's z. Only the pixels in the
/// image rectangle of `model_box`'s projected corners (the model's bounding box, model frame) are cast — no other
/// pixel centre's ray can hit it — or all pixels if a corner of the box is not in front of the sensor. Rows are split over `threads` std::threads
/// (0 = hardware concurrency); the image does not depend on the count. Throws InvalidArgument for an invalid pose,
/// sensor or an empty box.
template <RayCaster R>
[[nodiscard]] RangeImage render_range_image(const R& model, const Aabb& model_box, const Pose& model_pose,
                                            const RangeImage& geometry, unsigned threads = 1) {
  validate_pose(model_pose, "render_range_image: model_pose");
  detail::require(!model_box.empty() && model_box.min.allFinite() && model_box.max.allFinite(),
                  "render_range_image: model_box is empty or not finite");
  const AreaSensor& sensor = geometry.sensor;
  sensor.validate();
  RangeImage out{sensor, geometry.sensor_pose,
                 std::vector<double>(sensor.ray_count(), std::numeric_limits<double>::quiet_NaN())};
  const Pose t_ms = model_pose.inverse() * geometry.sensor_pose;  // sensor → model frame
  // Pixel rectangle of the box: the pixels whose footprint meets the projected corners' hull (one pixel margin).
  int u0 = 0, u1 = sensor.width_px - 1, v0 = 0, v1 = sensor.height_px - 1;
  {
    const Pose t_sm = t_ms.inverse();
    const double tx = std::tan(0.5 * sensor.horizontal_fov_rad), ty = std::tan(0.5 * sensor.vertical_fov_rad);
    double lo_u = std::numeric_limits<double>::infinity(), hi_u = -lo_u, lo_v = lo_u, hi_v = -lo_u;
    bool all_in_front = true;
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner((c & 1) ? model_box.max.x() : model_box.min.x(), (c & 2) ? model_box.max.y() : model_box.min.y(),
                        (c & 4) ? model_box.max.z() : model_box.min.z());
      const Vec3 p = t_sm * corner;
      if (!(p.z() > 1e-9)) {
        all_in_front = false;
        break;
      }
      const double cu = (p.x() / p.z() / tx + 1.0) * 0.5 * sensor.width_px;
      const double cv = (p.y() / p.z() / ty + 1.0) * 0.5 * sensor.height_px;
      lo_u = std::min(lo_u, cu), hi_u = std::max(hi_u, cu), lo_v = std::min(lo_v, cv), hi_v = std::max(hi_v, cv);
    }
    if (all_in_front) {  // pixel centres inside the hull lie in [floor(lo), floor(hi)]; clamped before the cast
      const auto cell = [](double x, int n) { return static_cast<int>(std::floor(std::clamp(x, -1.0, double(n)))); };
      u0 = std::max(0, cell(lo_u, sensor.width_px)), u1 = std::min(sensor.width_px - 1, cell(hi_u, sensor.width_px));
      v0 = std::max(0, cell(lo_v, sensor.height_px)), v1 = std::min(sensor.height_px - 1, cell(hi_v, sensor.height_px));
    }
  }
  if (u0 > u1 || v0 > v1) return out;
  const Vec3 origin = t_ms.translation();
  const Mat3 rot = t_ms.linear();
  detail::parallel_for(static_cast<std::size_t>(v1 - v0 + 1), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t row = b; row < e; ++row) {
      const int v = v0 + static_cast<int>(row);
      for (int u = u0; u <= u1; ++u) {
        const Vec3 d_s = sensor.ray_direction_sensor(u, v);
        const std::optional<RayHit> hit = model.first_hit(origin, rot * d_s, sensor.range.max_m);
        if (hit && sensor.range.contains(hit->distance))
          out.depth[static_cast<std::size_t>(v) * sensor.width_px + u] = hit->distance * d_s.z();
      }
    }
  });
  return out;
}

/// q_h (Eq. 3.10) of the hypothesis T_WM = `model_pose`: the model rendered into the pixel grid of `cluster` (the
/// range image of the cluster's points, range_image()) and compared with its depths within `tolerance_m`.
/// Throws InvalidArgument as render_range_image and hypothesis_quality.
template <RayCaster R>
[[nodiscard]] HypothesisQuality verify_hypothesis(const R& model, const Aabb& model_box, const Pose& model_pose,
                                                  const RangeImage& cluster, double tolerance_m, unsigned threads = 1) {
  detail::require(cluster.depth.size() == cluster.sensor.ray_count(), "verify_hypothesis: cluster has ",
                  cluster.depth.size(), " depths for ", cluster.sensor.ray_count(), " pixels");
  const RangeImage r = render_range_image(model, model_box, model_pose, cluster, threads);
  return hypothesis_quality(r.depth, cluster.depth, tolerance_m);
}

}  // namespace nbs
