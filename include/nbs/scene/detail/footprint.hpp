// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// 2D convex footprints in the table plane (xy, metres): convex hull and the distance between two convex polygons.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

namespace nbs::detail {

using Vec2 = Eigen::Vector2d;

[[nodiscard]] inline double cross2(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Convex hull (Andrew's monotone chain), counter-clockwise, collinear points dropped. Fewer than 3 distinct
/// points give those points.
[[nodiscard]] inline std::vector<Vec2> convex_hull(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<Vec2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross2(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross2(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

/// Distance from `q` to the segment [a, b].
[[nodiscard]] inline double point_segment_distance(const Vec2& q, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((q - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - q).norm();
}

/// True if the closed segments [a, b] and [c, d] intersect.
[[nodiscard]] inline bool segments_intersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = cross2(c, d, a), d2 = cross2(c, d, b), d3 = cross2(a, b, c), d4 = cross2(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && point_segment_distance(a, c, d) == 0.0) || (d2 == 0 && point_segment_distance(b, c, d) == 0.0) ||
         (d3 == 0 && point_segment_distance(c, a, b) == 0.0) || (d4 == 0 && point_segment_distance(d, a, b) == 0.0);
}

/// True if `q` lies inside or on the counter-clockwise convex polygon `poly` (≥ 3 vertices).
[[nodiscard]] inline bool inside_convex(const Vec2& q, std::span<const Vec2> poly) {
  if (poly.size() < 3) return false;
  for (std::size_t i = 0; i < poly.size(); ++i)
    if (cross2(poly[i], poly[(i + 1) % poly.size()], q) < 0.0) return false;
  return true;
}

/// Euclidean distance between two convex polygons (counter-clockwise, ≥ 1 vertex each); 0 if they overlap.
[[nodiscard]] inline double convex_distance(std::span<const Vec2> a, std::span<const Vec2> b) {
  if (inside_convex(a[0], b) || inside_convex(b[0], a)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec2& a0 = a[i];
    const Vec2& a1 = a[(i + 1) % a.size()];
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Vec2& b0 = b[j];
      const Vec2& b1 = b[(j + 1) % b.size()];
      if (segments_intersect(a0, a1, b0, b1)) return 0.0;
      best = std::min({best, point_segment_distance(a0, b0, b1), point_segment_distance(a1, b0, b1),
                       point_segment_distance(b0, a0, a1), point_segment_distance(b1, a0, a1)});
    }
  }
  return best;
}

}  // namespace nbs::detail
