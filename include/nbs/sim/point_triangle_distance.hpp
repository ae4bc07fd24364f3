// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Exact closest point on a triangle (Ericson, Real-Time Collision Detection, Sec. 5.1.5), degenerate-safe.

#include <algorithm>

#include "nbs/core/types.hpp"

namespace nbs {

/// Closest point to `p` on the segment [a, b] (a point when a == b).
[[nodiscard]] inline Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0.0)) return a;
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

/// Closest point to `p` on the solid triangle (a, b, c), world units. Exact up to floating-point rounding by
/// Voronoi-region classification. Zero-area triangles (collinear or coincident corners) are treated as the union of
/// their three edges, so the result is always finite for finite input.
[[nodiscard]] inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const double scale = std::max({ab.squaredNorm(), ac.squaredNorm(), (c - b).squaredNorm()});
  if (!(ab.cross(ac).squaredNorm() > 1e-24 * scale * scale)) {  // degenerate: nearest of the three edges
    const Vec3 q1 = closest_point_on_segment(p, a, b);
    const Vec3 q2 = closest_point_on_segment(p, b, c);
    const Vec3 q3 = closest_point_on_segment(p, c, a);
    const double d1 = (q1 - p).squaredNorm(), d2 = (q2 - p).squaredNorm(), d3 = (q3 - p).squaredNorm();
    return d1 <= d2 ? (d1 <= d3 ? q1 : q3) : (d2 <= d3 ? q2 : q3);
  }
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Euclidean distance from `p` to the solid triangle (a, b, c).
[[nodiscard]] inline double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return (closest_point_on_triangle(p, a, b, c) - p).norm();
}

}  // namespace nbs
