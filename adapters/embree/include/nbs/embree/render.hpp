// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// A small headless renderer on the Embree adapter: one primary ray per pixel against a Scene, Lambert shading with
/// a headlight (light at the eye), and 3D line segments (scan candidates, Fig. 4.16) drawn on top as 2D lines
/// (projected end points, Bresenham). For pictures of the model during a run; ≈ 10–50 ms for 480 × 360 pixels.
/// Units: metres, radians; world frame (z up). Image: row-major RGB, top row first.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <thread>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/embree/scene.hpp"
#include "nbs/io/color.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/sim/surface_color.hpp"

namespace nbs::embree {

/// A pinhole (perspective) or orthographic camera looking from `eye` at `target`; `up` fixes the roll.
struct Camera {
  Vec3 eye = Vec3(0.6, -0.6, 0.45);
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();
  bool orthographic = false;
  double vertical_fov_rad = 0.5;   ///< perspective: full vertical field of view, in (0, π)
  double ortho_height_m = 0.3;     ///< orthographic: height of the image in world units, > 0

  /// Throws InvalidArgument naming the bad field (non-finite, eye = target, up parallel to the view, bad fov).
  void validate() const {
    nbs::detail::require(eye.allFinite() && target.allFinite() && up.allFinite(), "Camera: eye (", eye.transpose(),
                    "), target (", target.transpose(), ") and up (", up.transpose(), ") must be finite");
    const Vec3 f = target - eye;
    nbs::detail::require(f.norm() > 1e-12, "Camera: eye and target coincide");
    nbs::detail::require(f.normalized().cross(up).norm() > 1e-6 * up.norm() && up.norm() > 0.0,
                    "Camera: up must be non-zero and not parallel to the viewing direction");
    if (orthographic)
      nbs::detail::require(std::isfinite(ortho_height_m) && ortho_height_m > 0.0, "Camera.ortho_height_m must be > 0, got ",
                      ortho_height_m);
    else
      nbs::detail::require(vertical_fov_rad > 0.0 && vertical_fov_rad < 3.14159, "Camera.vertical_fov_rad must be in (0, pi), got ",
                      vertical_fov_rad);
  }

  /// A perspective camera at azimuth/elevation (radians, azimuth from +x towards +y) around `box`, at the
  /// distance where the box's bounding sphere fills `fill` of the vertical field of view.
  [[nodiscard]] static Camera around(const Aabb& box, double azimuth_rad, double elevation_rad,
                                     double vertical_fov_rad = 0.5, double fill = 0.9) {
    nbs::detail::require(!box.empty() && box.min.allFinite() && box.max.allFinite(), "Camera::around: empty box");
    Camera c;
    c.vertical_fov_rad = vertical_fov_rad;
    c.target = box.center();
    const double radius = std::max(0.5 * box.extent().norm(), 1e-6);
    const double dist = radius / std::sin(0.5 * vertical_fov_rad * fill);
    c.eye = c.target + dist * unit_from_angles(azimuth_rad, elevation_rad);
    return c;
  }
};

/// A 3D segment drawn as a 2D line of `width_px` (1–3) pixels.
struct Segment {
  Vec3 a, b;
  Rgb color{255, 0, 0};
  int width_px = 1;
};

/// The world axes at `origin` as three segments of `length_m`: x red, y green, z blue (2 px wide).
[[nodiscard]] inline std::array<Segment, 3> axes(const Vec3& origin, double length_m) {
  return {Segment{origin, origin + Vec3(length_m, 0, 0), {220, 30, 30}, 2},
          Segment{origin, origin + Vec3(0, length_m, 0), {30, 160, 30}, 2},
          Segment{origin, origin + Vec3(0, 0, length_m), {30, 60, 220}, 2}};
}

/// A horizontal disc (the pedestal's top, world frame): drawn where a pixel's ray meets it before any mesh.
struct Disc {
  Vec3 center = Vec3::Zero();  ///< centre, metres; the disc lies in the plane z = center.z
  double radius_m = 0.1;       ///< > 0
  Rgb color{190, 175, 150};    ///< albedo; the outer 3 % of the radius is drawn darker as a rim
};

struct RenderSetting {
  std::uint32_t width = 480, height = 360;
  Rgb background{255, 255, 255};
  Rgb surface{205, 205, 215};    ///< albedo of the mesh
  double ambient = 0.15;         ///< share of the albedo shown regardless of the light, [0, 1]
  unsigned threads = 1;          ///< std::threads over image rows, [1, 256]; the image does not depend on it
  std::optional<Disc> pedestal;  ///< drawn under the mesh when set (e.g. the support the object stands on)

  void validate() const {
    nbs::detail::require(width > 0 && height > 0 && width <= 8192 && height <= 8192, "RenderSetting: size ", width, " x ",
                    height, " must be in [1, 8192] per side");
    nbs::detail::require(threads >= 1 && threads <= 256, "RenderSetting.threads must be in [1, 256], got ", threads);
    nbs::detail::require(ambient >= 0.0 && ambient <= 1.0, "RenderSetting.ambient must be in [0, 1], got ", ambient);
    if (pedestal)
      nbs::detail::require(pedestal->center.allFinite() && std::isfinite(pedestal->radius_m) && pedestal->radius_m > 0.0,
                           "RenderSetting.pedestal: centre must be finite and radius > 0, got centre (",
                           pedestal->center.transpose(), "), radius ", pedestal->radius_m);
  }
};

/// A rendered picture: RGB bytes and per-pixel hit distance (metres along the ray; +inf = background). Write it
/// as a PNG file with nbs::png::write_png(path, width, height, rgb) (adapter nbs::png).
struct Image {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  std::vector<float> depth;
  [[nodiscard]] std::size_t hit_count() const {
    return static_cast<std::size_t>(std::count_if(depth.begin(), depth.end(), [](float d) { return std::isfinite(d); }));
  }
};

namespace render_detail {
struct Frame {  // camera basis: right, image-up, forward
  Vec3 r, u, f;
  double tan_half = 0.0, half_h = 0.0, aspect = 1.0;
};
[[nodiscard]] inline Frame frame(const Camera& c, const RenderSetting& s) {
  Frame fr;
  fr.f = (c.target - c.eye).normalized();
  fr.r = fr.f.cross(c.up).normalized();
  fr.u = fr.r.cross(fr.f);
  fr.tan_half = std::tan(0.5 * c.vertical_fov_rad);
  fr.half_h = 0.5 * c.ortho_height_m;
  fr.aspect = double(s.width) / double(s.height);
  return fr;
}
}  // namespace render_detail

/// Pixel coordinates (x right, y down, continuous; pixel (i, j) covers [i, i+1) × [j, j+1)) of world point `p`, or
/// nullopt if it lies behind a perspective camera. Throws InvalidArgument for an invalid camera or setting.
[[nodiscard]] inline std::optional<Eigen::Vector2d> project(const Camera& cam, const RenderSetting& s, const Vec3& p) {
  cam.validate();
  s.validate();
  const render_detail::Frame fr = render_detail::frame(cam, s);
  const Vec3 d = p - cam.eye;
  const double z = d.dot(fr.f);
  double x = d.dot(fr.r), y = d.dot(fr.u);
  if (cam.orthographic) {
    x /= fr.half_h, y /= fr.half_h;
  } else {
    if (!(z > 1e-9)) return std::nullopt;
    x /= z * fr.tan_half, y /= z * fr.tan_half;
  }
  return Eigen::Vector2d((0.5 + 0.5 * x / fr.aspect) * s.width, (0.5 - 0.5 * y) * s.height);
}

/// One triangle scene of a picture with its albedo: the object model (RenderSetting::surface), a robot arm in its own
/// colour. A null scene is skipped. With `colored` set (the mesh `scene` was built from, same triangle order, with one
/// colour per vertex; Sec. 5.3), the albedo at a hit is surface_color(*colored, triangle, hit point) — barycentric
/// interpolation of the vertex colours — shaded as a single-colour layer is; `albedo` is then unused.
struct SceneLayer {
  const Scene* scene = nullptr;
  Rgb albedo{205, 205, 215};
  const IndexedMesh* colored = nullptr;
};

/// Renders the nearest surface among `layers` (each in its albedo or vertex colours) seen by `cam`, then draws
/// `segments` on top. Throws InvalidArgument for an invalid camera or setting, or an invalid `colored` mesh (bad index,
/// not one colour per vertex). A hit on a triangle the `colored` mesh does not have is painted in `albedo`.
[[nodiscard]] inline Image render(std::span<const SceneLayer> layers, const Camera& cam,
                                  std::span<const Segment> segments = {}, const RenderSetting& s = {}) {
  cam.validate();
  s.validate();
  for (const SceneLayer& layer : layers)
    if (layer.colored != nullptr) {
      layer.colored->validate();
      nbs::detail::require(layer.colored->colors.size() == layer.colored->vertices.size(), "SceneLayer.colored: ",
                           layer.colored->colors.size(), " colours for ", layer.colored->vertices.size(), " vertices");
    }
  const render_detail::Frame fr = render_detail::frame(cam, s);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Image img{s.width, s.height, std::vector<std::uint8_t>(3ull * s.width * s.height),
            std::vector<float>(std::size_t(s.width) * s.height, std::numeric_limits<float>::infinity())};
  const auto shade_rows = [&](std::uint32_t j0, std::uint32_t j1) {
   for (std::uint32_t j = j0; j < j1; ++j)
    for (std::uint32_t i = 0; i < s.width; ++i) {
      const double x = (2.0 * (i + 0.5) / s.width - 1.0) * fr.aspect, y = 1.0 - 2.0 * (j + 0.5) / s.height;
      Vec3 origin = cam.eye, dir = fr.f;
      if (cam.orthographic) origin += fr.half_h * (x * fr.r + y * fr.u);
      else dir = (fr.f + fr.tan_half * (x * fr.r + y * fr.u)).normalized();
      const std::size_t k = std::size_t(j) * s.width + i;
      Rgb c = s.background;
      const auto paint = [&](const Rgb& albedo, double lambert, double dist) {  // headlight; both faces lit
        img.depth[k] = static_cast<float>(dist);
        const double shade = s.ambient + (1.0 - s.ambient) * lambert;
        for (int ch = 0; ch < 3; ++ch) c[ch] = static_cast<std::uint8_t>(std::lround(shade * albedo[ch]));
      };
      std::optional<double> mesh_t;
      for (const SceneLayer& layer : layers)
        if (layer.scene != nullptr)
          if (const auto hit = layer.scene->first_hit(origin, dir, mesh_t.value_or(kInf));
              hit && (!mesh_t || hit->distance < *mesh_t)) {  // the nearest layer's surface
            mesh_t = hit->distance;
            const Rgb albedo = layer.colored == nullptr || hit->triangle >= layer.colored->triangles.size()
                                   ? layer.albedo
                                   : surface_color(*layer.colored, hit->triangle, origin + hit->distance * dir);
            paint(albedo, std::abs(hit->normal.dot(dir)), hit->distance);
          }
      if (s.pedestal && dir.z() != 0.0) {
        const double t = (s.pedestal->center.z() - origin.z()) / dir.z();
        const Vec3 p = origin + t * dir;
        const double rho = (p - s.pedestal->center).head<2>().norm();
        if (t > 0.0 && rho <= s.pedestal->radius_m && (!mesh_t || t < *mesh_t)) {
          Rgb albedo = s.pedestal->color;
          if (rho > 0.97 * s.pedestal->radius_m)
            for (auto& ch : albedo) ch = static_cast<std::uint8_t>(ch / 2);
          paint(albedo, std::abs(dir.z()), t);
        }
      }
      std::copy(c.begin(), c.end(), img.rgb.begin() + static_cast<std::ptrdiff_t>(3 * k));
    }
  };
  {  // disjoint row blocks; each pixel depends only on its own ray
    const std::uint32_t n = std::min<std::uint32_t>(s.threads, s.height);
    std::vector<std::thread> pool;
    for (std::uint32_t t = 1; t < n; ++t)
      pool.emplace_back(shade_rows, std::uint32_t(std::uint64_t(s.height) * t / n), std::uint32_t(std::uint64_t(s.height) * (t + 1) / n));
    shade_rows(0, std::uint32_t(s.height / n));
    for (std::thread& th : pool) th.join();
  }
  const auto plot = [&](long x, long y, const Rgb& c) {
    if (x < 0 || y < 0 || x >= long(s.width) || y >= long(s.height)) return;
    std::copy(c.begin(), c.end(), img.rgb.begin() + static_cast<std::ptrdiff_t>(3 * (std::size_t(y) * s.width + x)));
  };
  const double limit = 4.0 * std::max(s.width, s.height);  // clip absurd projections (points near the eye plane)
  for (const Segment& seg : segments) {
    const auto pa = project(cam, s, seg.a), pb = project(cam, s, seg.b);
    if (!pa || !pb || !pa->allFinite() || !pb->allFinite()) continue;
    if (pa->cwiseAbs().maxCoeff() > limit || pb->cwiseAbs().maxCoeff() > limit) continue;
    long x0 = std::lround(std::floor(pa->x())), y0 = std::lround(std::floor(pa->y()));
    const long x1 = std::lround(std::floor(pb->x())), y1 = std::lround(std::floor(pb->y()));
    const long dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    const int w = std::clamp(seg.width_px, 1, 3);
    for (long err = dx + dy;;) {  // Bresenham
      for (int oy = 0; oy < w; ++oy)
        for (int ox = 0; ox < w; ++ox) plot(x0 + ox - w / 2, y0 + oy - w / 2, seg.color);
      if (x0 == x1 && y0 == y1) break;
      const long e2 = 2 * err;
      if (e2 >= dy) err += dy, x0 += sx;
      if (e2 <= dx) err += dx, y0 += sy;
    }
  }
  return img;
}

/// Renders `scene` (may be null: background only) in RenderSetting::surface seen by `cam`, then draws `segments` on
/// top. Throws InvalidArgument for an invalid camera or setting.
[[nodiscard]] inline Image render(const Scene* scene, const Camera& cam, std::span<const Segment> segments = {},
                                  const RenderSetting& s = {}) {
  const SceneLayer layer{scene, s.surface};
  return render(std::span<const SceneLayer>(&layer, scene != nullptr ? 1 : 0), cam, segments, s);
}

}  // namespace nbs::embree
