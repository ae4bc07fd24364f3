// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Triangles of a robot's collision shapes (robot.hpp `PlacedShape`), for pictures of the arm (nbs_model's
/// view_NN.png with --robot, issue 19 item 5). Every shape becomes a closed, consistently oriented triangle mesh
/// (counter-clockwise seen from outside) whose vertices lie on the shape's surface, in the world frame:
/// box 8 vertices / 12 triangles; cylinder, sphere and capsule surfaces of revolution about the shape frame's z
/// axis with `segments` vertices per ring (sphere and capsule caps: segments / 2 latitude steps per π). The mesh
/// is inscribed: its volume is below the shape's by O(1/segments²). Mesh shapes (a file) are not tessellated.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/robot/collision_mesh.hpp"
#include "nbs/robot/robot.hpp"

namespace nbs {

namespace detail {
/// Appends the surface of revolution of `profile` (radius ≥ 0, z) about z, from the first profile point to the
/// last, with `n` vertices per ring (radius 0: one vertex, a pole). Vertices mapped by `T`.
inline void append_revolution(IndexedMesh& out, const std::vector<std::pair<double, double>>& profile, int n,
                              const Pose& T) {
  std::vector<std::vector<std::uint32_t>> rings;
  for (const auto& [r, z] : profile) {
    std::vector<std::uint32_t> ring;
    const int m = r > 0.0 ? n : 1;
    for (int k = 0; k < m; ++k) {
      const double a = 2.0 * std::numbers::pi * k / n;
      ring.push_back(static_cast<std::uint32_t>(out.vertices.size()));
      out.vertices.push_back(T * Vec3(r * std::cos(a), r * std::sin(a), z));
    }
    rings.push_back(std::move(ring));
  }
  for (std::size_t i = 1; i < rings.size(); ++i) {
    const auto& a = rings[i - 1];
    const auto& b = rings[i];
    if (a.size() == 1 && b.size() == 1) continue;
    for (int k = 0; k < n; ++k) {
      const auto at = [&](const std::vector<std::uint32_t>& ring, int j) { return ring[ring.size() == 1 ? 0 : j % n]; };
      // the quad a_k, a_{k+1}, b_{k+1}, b_k (outward for a profile going up); one triangle collapses at a pole
      if (a.size() > 1) out.triangles.push_back({at(a, k), at(a, k + 1), at(b, k + 1)});
      if (b.size() > 1) out.triangles.push_back({at(a, k), at(b, k + 1), at(b, k)});
    }
  }
}
/// Profile of a half circle of radius r centred at z = c: the lower one (from the pole up to the equator) or the
/// upper one (from the equator up to the pole), `steps` segments.
inline void append_arc(std::vector<std::pair<double, double>>& p, double r, double c, int steps, bool upper) {
  for (int i = 0; i <= steps; ++i) {
    const double t = 0.5 * std::numbers::pi * i / steps + (upper ? 0.5 * std::numbers::pi : 0.0);  // from the bottom
    p.emplace_back(upper && i == steps ? 0.0 : r * std::sin(t), c - r * std::cos(t));  // the top pole exactly on z
  }
}
}  // namespace detail

/// Appends the triangles of `s` (world frame, metres) to `out` (vertices appended, indices offset); a mesh shape's
/// loaded triangles as they are (three vertices each), nothing for one that was not loaded. `segments` ≥ 3 vertices per ring. Throws InvalidArgument naming the link and value for a
/// negative, zero-size or non-finite dimension or a bad `segments` (nothing appended then).
inline void append_shape_mesh(IndexedMesh& out, const PlacedShape& s, int segments = 24) {
  using K = LinkShape::Kind;
  const LinkShape& g = s.shape;
  detail::require(segments >= 3, "append_shape_mesh: segments must be >= 3, got ", segments);
  detail::require(s.T_WG.matrix().allFinite(), "append_shape_mesh: link ", s.link, ": shape pose not finite");
  const Pose T = s.T_WG;
  switch (g.kind) {
    case K::mesh: {  // a loaded mesh as it is (not loaded: nothing to draw)
      if (!g.mesh) return;
      const auto base = static_cast<std::uint32_t>(out.vertices.size());
      for (std::size_t t = 0; t < g.mesh->triangle_count(); ++t) {
        for (int k = 0; k < 3; ++k) out.vertices.push_back(T * g.mesh->corner(t, k));
        const auto v = base + static_cast<std::uint32_t>(3 * t);
        out.triangles.push_back({v, v + 1, v + 2});
      }
      return;
    }
    case K::box: {
      detail::require(g.size.allFinite() && (g.size.array() > 0.0).all(), "append_shape_mesh: link ", s.link,
                      ": box size (", g.size.transpose(), ") must be finite and > 0");
      const auto base = static_cast<std::uint32_t>(out.vertices.size());
      for (int i = 0; i < 8; ++i)  // corner i: bit 0 → +x, bit 1 → +y, bit 2 → +z
        out.vertices.push_back(T * (0.5 * g.size.cwiseProduct(Vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1))));
      static constexpr std::uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},   // -z, +z
                                                 {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},   // -y, +y
                                                 {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};  // -x, +x
      for (const auto& t : f) out.triangles.push_back({base + t[0], base + t[1], base + t[2]});
      return;
    }
    case K::cylinder:
    case K::capsule:
    case K::sphere: {
      const double r = g.radius, h = g.kind == K::sphere ? 0.0 : g.length;
      detail::require(std::isfinite(r) && r > 0.0 && std::isfinite(h) && (g.kind == K::cylinder ? h > 0.0 : h >= 0.0),
                      "append_shape_mesh: link ", s.link, ": radius ", r, " and length ", h,
                      " must be finite, radius > 0, length >= 0 (cylinder: > 0)");
      std::vector<std::pair<double, double>> p;
      if (g.kind == K::cylinder) {
        p = {{0.0, -0.5 * h}, {r, -0.5 * h}, {r, 0.5 * h}, {0.0, 0.5 * h}};
      } else {  // lower cap up to its equator, then the upper cap (sphere: one shared equator)
        const int steps = std::max(2, segments / 4);  // per quarter circle
        detail::append_arc(p, r, -0.5 * h, steps, false);
        std::vector<std::pair<double, double>> top;
        detail::append_arc(top, r, 0.5 * h, steps, true);
        p.insert(p.end(), top.begin() + (h > 0.0 ? 0 : 1), top.end());
      }
      detail::append_revolution(out, p, segments, T);
      return;
    }
  }
}

/// The triangles of every shape in `shapes` (e.g. `robot.collision_shapes(q)`) in one mesh, world frame; see
/// append_shape_mesh. Empty if no shape can be drawn (a model without links, only meshes that were not loaded).
[[nodiscard]] inline IndexedMesh shapes_mesh(const std::vector<PlacedShape>& shapes, int segments = 24) {
  IndexedMesh m;
  for (const PlacedShape& s : shapes) append_shape_mesh(m, s, segments);
  return m;
}

}  // namespace nbs
