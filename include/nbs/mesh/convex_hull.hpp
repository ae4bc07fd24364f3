// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The 3-D convex hull of a point set (quickhull with conflict lists, Barber, Dobkin & Huhdanpaa 1996), its coplanar
/// triangles merged into planar convex facets with outward normals. Used for the resting faces of an object
/// (sim/reorientation.hpp, thesis Sec. 5.3). Pure function, deterministic (fixed processing order, ties to the lower
/// input index), not randomised; expected O(n log n).
///
/// Tolerance ε = `relative_epsilon` · s, s = the largest |coordinate| of the input (≥ the extent): a point within ε
/// of a face's plane counts as on it (coplanar and duplicate points add no vertex); adjacent triangles whose opposite
/// vertices lie within ε of each other's plane are one facet. Hull vertices lying on a facet's interior or on an edge
/// (collinear) are dropped, so V − E + F = 2 holds for the output. Every input point lies at most a few ε outside
/// every facet plane (points within ε of a face are not added; 7 ε seen for 2·10⁵ points on a sphere).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

/// One planar facet of the hull: a convex polygon.
struct HullFacet {
  std::vector<std::uint32_t> polygon;  ///< indices into ConvexHull::vertices, counter-clockwise seen from outside
  Vec3 normal = Vec3::UnitZ();         ///< outward unit normal
  double offset = 0.0;                 ///< plane normal·x = offset (the largest over its vertices), metres
  double area = 0.0;                   ///< polygon area, m²
};

/// The hull: its vertices (a subset of the input) and facets.
struct ConvexHull {
  std::vector<Vec3> vertices;
  std::vector<std::uint32_t> input_index;  ///< input index of each vertex
  std::vector<HullFacet> facets;
  double epsilon = 0.0;                    ///< the absolute tolerance used, metres
};

namespace detail {

struct QhFace {
  std::array<std::uint32_t, 3> v{};  // input indices, ccw seen from outside
  std::array<std::uint32_t, 3> nbr{};  // face across edge v[i] → v[i+1]
  Vec3 n = Vec3::Zero();
  double d = 0.0;
  std::vector<std::uint32_t> outside;  // conflict list
  bool alive = true;
};

inline void qh_plane(QhFace& f, const std::vector<Vec3>& p) {
  const Vec3 c = (p[f.v[1]] - p[f.v[0]]).cross(p[f.v[2]] - p[f.v[0]]);
  f.n = c.normalized();
  f.d = f.n.dot(p[f.v[0]]);
}

/// Checks that `hull` is a closed polytope surface: every facet has ≥ 3 vertices, every directed polygon edge is met
/// by exactly one reverse edge of another facet, and V − E + F = 2. Near-coplanar input can break quickhull's
/// horizon or the facet merge silently; this turns that into InvalidArgument naming ε.
inline void require_closed_hull(const ConvexHull& hull, double relative_epsilon) {
  std::vector<std::uint64_t> edges;
  for (std::size_t f = 0; f < hull.facets.size(); ++f) {
    const std::vector<std::uint32_t>& poly = hull.facets[f].polygon;
    require(poly.size() >= 3, "convex_hull: facet ", f, " has ", poly.size(), " vertices (numerically degenerate "
            "input at relative_epsilon ", relative_epsilon, ")");
    for (std::size_t i = 0; i < poly.size(); ++i)
      edges.push_back(std::uint64_t{poly[i]} << 32 | poly[(i + 1) % poly.size()]);
  }
  std::ranges::sort(edges);
  const bool unique = std::adjacent_find(edges.begin(), edges.end()) == edges.end();
  bool matched = unique;
  for (std::size_t i = 0; matched && i < edges.size(); ++i)
    matched = std::ranges::binary_search(edges, (edges[i] & 0xffffffffu) << 32 | edges[i] >> 32);
  const auto v = static_cast<long long>(hull.vertices.size()), e = static_cast<long long>(edges.size() / 2),
             f = static_cast<long long>(hull.facets.size());
  require(matched && v - e + f == 2, "convex_hull: the result is not a closed convex polytope (edges ",
          matched ? "matched" : "not matched", ", V - E + F = ", v - e + f, ") at relative_epsilon ", relative_epsilon,
          ": numerically degenerate input; try a larger relative_epsilon");
}

}  // namespace detail

/// The convex hull of `points`. Throws InvalidArgument for a non-finite point (naming its index), fewer than 4
/// points, all points coincident, collinear or coplanar (within ε), or a bad `relative_epsilon` (must be in (0, 1e-3]).
[[nodiscard]] inline ConvexHull convex_hull(const std::vector<Vec3>& points, double relative_epsilon = 1e-9) {
  detail::require(relative_epsilon > 0.0 && relative_epsilon <= 1e-3, "convex_hull: relative_epsilon ",
                  relative_epsilon, " must be in (0, 1e-3]");
  detail::require(points.size() >= 4, "convex_hull: needs at least 4 points, got ", points.size());
  double s = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    detail::require(points[i].allFinite(), "convex_hull: point ", i, " is not finite");
    s = std::max(s, points[i].cwiseAbs().maxCoeff());
  }
  const double eps = relative_epsilon * std::max(s, std::numeric_limits<double>::min());
  const std::vector<Vec3>& p = points;
  const auto n_pts = static_cast<std::uint32_t>(points.size());

  // Initial simplex: the farthest pair among the axis extremes, the farthest point from their line, from their plane.
  std::array<std::uint32_t, 6> ext{};
  for (int a = 0; a < 3; ++a)
    for (std::uint32_t i = 0; i < n_pts; ++i) {
      if (p[i][a] < p[ext[2 * a]][a]) ext[2 * a] = i;
      if (p[i][a] > p[ext[2 * a + 1]][a]) ext[2 * a + 1] = i;
    }
  std::uint32_t i0 = 0, i1 = 0;
  double best = -1.0;
  for (int a = 0; a < 6; ++a)
    for (int b = a + 1; b < 6; ++b)
      if (const double d = (p[ext[a]] - p[ext[b]]).squaredNorm(); d > best) best = d, i0 = ext[a], i1 = ext[b];
  detail::require(std::sqrt(best) > eps, "convex_hull: all ", points.size(), " points coincide (within ", eps, " m)");
  const Vec3 dir = (p[i1] - p[i0]).normalized();
  std::uint32_t i2 = 0;
  best = -1.0;
  for (std::uint32_t i = 0; i < n_pts; ++i)
    if (const double d = (p[i] - p[i0]).cross(dir).norm(); d > best) best = d, i2 = i;
  detail::require(best > eps, "convex_hull: all ", points.size(), " points are collinear (within ", eps, " m)");
  const Vec3 n0 = (p[i1] - p[i0]).cross(p[i2] - p[i0]).normalized();
  std::uint32_t i3 = 0;
  best = -1.0;
  for (std::uint32_t i = 0; i < n_pts; ++i)
    if (const double d = std::abs(n0.dot(p[i] - p[i0])); d > best) best = d, i3 = i;
  detail::require(best > eps, "convex_hull: all ", points.size(), " points are coplanar (within ", eps, " m)");

  std::vector<detail::QhFace> faces;
  faces.reserve(4 * points.size() / 2 + 16);
  {
    std::array<std::uint32_t, 4> s4{i0, i1, i2, i3};
    if (n0.dot(p[i3] - p[i0]) > 0.0) std::swap(s4[1], s4[2]);  // i3 behind face (i0, i1, i2)
    // Faces of the tetrahedron s4 = (a, b, c, d) with (a, b, c) ccw from outside.
    const std::array<std::array<std::uint32_t, 3>, 4> tri{{{s4[0], s4[1], s4[2]},
                                                          {s4[0], s4[3], s4[1]},
                                                          {s4[1], s4[3], s4[2]},
                                                          {s4[2], s4[3], s4[0]}}};
    for (const auto& t : tri) {
      detail::QhFace f;
      f.v = t;
      detail::qh_plane(f, p);
      faces.push_back(std::move(f));
    }
    // Neighbours: the face holding the reversed edge.
    for (std::uint32_t a = 0; a < 4; ++a)
      for (int e = 0; e < 3; ++e)
        for (std::uint32_t b = 0; b < 4; ++b)
          for (int k = 0; k < 3; ++k)
            if (faces[b].v[k] == faces[a].v[(e + 1) % 3] && faces[b].v[(k + 1) % 3] == faces[a].v[e])
              faces[a].nbr[e] = b;
    for (std::uint32_t i = 0; i < n_pts; ++i) {
      if (i == i0 || i == i1 || i == i2 || i == i3) continue;
      for (auto& f : faces)
        if (f.n.dot(p[i]) - f.d > eps) {
          f.outside.push_back(i);
          break;
        }
    }
  }

  std::vector<std::uint32_t> stack{0, 1, 2, 3}, visible, new_faces;
  std::vector<std::uint32_t> visit_mark;  // per face: the iteration that visited it
  std::vector<std::array<std::uint32_t, 3>> horizon;  // (a, b, face across) with a → b an edge of a visible face
  std::vector<std::pair<std::uint32_t, std::uint32_t>> dfs;
  std::uint32_t iter = 0;
  while (!stack.empty()) {
    const std::uint32_t fi = stack.back();
    stack.pop_back();
    if (!faces[fi].alive || faces[fi].outside.empty()) continue;
    ++iter;
    // Eye: the farthest outside point (ties: the first in the list).
    std::uint32_t eye = faces[fi].outside.front();
    double far = -1.0;
    for (const std::uint32_t i : faces[fi].outside)
      if (const double d = faces[fi].n.dot(p[i]) - faces[fi].d; d > far) far = d, eye = i;
    const Vec3& e = p[eye];
    // Visible faces (connected, depth first) and the horizon.
    visit_mark.resize(faces.size(), 0);
    visible.clear();
    horizon.clear();
    visit_mark[fi] = iter;
    visible.push_back(fi);
    dfs.assign(1, {fi, 0u});
    while (!dfs.empty()) {
      auto& [f, k] = dfs.back();
      if (k == 3) {
        dfs.pop_back();
        continue;
      }
      const std::uint32_t edge = k++;
      const std::uint32_t g = faces[f].nbr[edge];
      if (visit_mark[g] == iter) continue;  // already visible
      if (faces[g].n.dot(e) - faces[g].d > eps) {
        visit_mark[g] = iter;
        visible.push_back(g);
        dfs.emplace_back(g, 0u);
      } else {
        horizon.push_back({faces[f].v[edge], faces[f].v[(edge + 1) % 3], g});
      }
    }
    // New faces (a, b, eye) on the horizon edges; link them to the faces across and to each other.
    new_faces.clear();
    for (const auto& h : horizon) {
      detail::QhFace f;
      f.v = {h[0], h[1], eye};
      detail::qh_plane(f, p);
      f.nbr[0] = h[2];
      const auto id = static_cast<std::uint32_t>(faces.size());
      auto& across = faces[h[2]];
      for (int k = 0; k < 3; ++k)
        if (across.v[k] == h[1] && across.v[(k + 1) % 3] == h[0]) across.nbr[k] = id;
      faces.push_back(std::move(f));
      new_faces.push_back(id);
    }
    // Edge b → eye of the face on (a, b) meets eye → b of the face on (b, c).
    for (const std::uint32_t a : new_faces)
      for (const std::uint32_t b : new_faces)
        if (faces[b].v[0] == faces[a].v[1]) {
          faces[a].nbr[1] = b;
          faces[b].nbr[2] = a;
        }
    // Reassign the conflict lists of the visible faces.
    for (const std::uint32_t v : visible) {
      faces[v].alive = false;
      for (const std::uint32_t i : faces[v].outside) {
        if (i == eye) continue;
        for (const std::uint32_t nf : new_faces)
          if (faces[nf].n.dot(p[i]) - faces[nf].d > eps) {
            faces[nf].outside.push_back(i);
            break;
          }
      }
      std::vector<std::uint32_t>().swap(faces[v].outside);
    }
    for (const std::uint32_t nf : new_faces)
      if (!faces[nf].outside.empty()) stack.push_back(nf);
  }

  // Merge adjacent coplanar triangles (union-find), then each group's boundary = the 2-D hull of its vertices.
  std::vector<std::uint32_t> parent(faces.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto root = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::uint32_t a = 0; a < faces.size(); ++a) {
    if (!faces[a].alive) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t b = faces[a].nbr[k];
      if (b < a) continue;
      const auto far_of = [&](const detail::QhFace& f, const detail::QhFace& g) {  // g's vertex off f's edge
        double m = 0.0;
        for (const std::uint32_t v : g.v) m = std::max(m, std::abs(f.n.dot(p[v]) - f.d));
        return m;
      };
      if (far_of(faces[a], faces[b]) <= eps && far_of(faces[b], faces[a]) <= eps) parent[root(a)] = root(b);
    }
  }
  std::vector<std::vector<std::uint32_t>> groups(faces.size());
  for (std::uint32_t a = 0; a < faces.size(); ++a)
    if (faces[a].alive) groups[root(a)].push_back(a);

  ConvexHull hull;
  hull.epsilon = eps;
  std::vector<std::uint32_t> vertex_of(points.size(), std::numeric_limits<std::uint32_t>::max());
  std::vector<std::uint32_t> members;
  for (const auto& g : groups) {
    if (g.empty()) continue;
    HullFacet facet;
    Vec3 nsum = Vec3::Zero();
    members.clear();
    for (const std::uint32_t f : g) {
      const auto& v = faces[f].v;
      nsum += (p[v[1]] - p[v[0]]).cross(p[v[2]] - p[v[0]]);
      members.insert(members.end(), v.begin(), v.end());
    }
    std::ranges::sort(members);
    members.erase(std::unique(members.begin(), members.end()), members.end());
    facet.normal = nsum.normalized();
    const Vec3 u = (std::abs(facet.normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(facet.normal).normalized();
    const Vec3 w = facet.normal.cross(u);  // (u, w, n) right-handed: ccw in (u, w) is ccw from outside
    const auto uv = [&](std::uint32_t i) { return std::pair<double, double>(u.dot(p[i]), w.dot(p[i])); };
    std::ranges::sort(members,
                      [&](std::uint32_t a, std::uint32_t b) { return uv(a) < uv(b) || (uv(a) == uv(b) && a < b); });
    // Andrew's monotone chain; points within ε/2 of a chain line are dropped (collinear; a hull triangle is ≥ ε high).
    const auto turn = [&](std::uint32_t o, std::uint32_t a, std::uint32_t b) {
      const auto [ox, oy] = uv(o);
      const auto [ax, ay] = uv(a);
      const auto [bx, by] = uv(b);
      const double len = std::hypot(ax - ox, ay - oy);  // signed distance of b from the line o → a, > 0 left
      return ((ax - ox) * (by - oy) - (ay - oy) * (bx - ox)) / std::max(len, std::numeric_limits<double>::min());
    };
    std::vector<std::uint32_t> h(2 * members.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < members.size(); ++i) {
      while (k >= 2 && turn(h[k - 2], members[i], h[k - 1]) >= -0.5 * eps) --k;  // pop unless a left turn
      h[k++] = members[i];
    }
    for (std::size_t i = members.size() - 1, t = k + 1; i-- > 0;) {
      while (k >= t && turn(h[k - 2], members[i], h[k - 1]) >= -0.5 * eps) --k;
      h[k++] = members[i];
    }
    h.resize(k - 1);
    facet.offset = -std::numeric_limits<double>::infinity();
    for (const std::uint32_t i : h) facet.offset = std::max(facet.offset, facet.normal.dot(p[i]));
    for (std::size_t i = 0; i < h.size(); ++i) {
      const auto [ax, ay] = uv(h[i]);
      const auto [bx, by] = uv(h[(i + 1) % h.size()]);
      facet.area += 0.5 * (ax * by - bx * ay);
    }
    for (const std::uint32_t i : h) {
      if (vertex_of[i] == std::numeric_limits<std::uint32_t>::max()) {
        vertex_of[i] = static_cast<std::uint32_t>(hull.vertices.size());
        hull.vertices.push_back(p[i]);
        hull.input_index.push_back(i);
      }
      facet.polygon.push_back(vertex_of[i]);
    }
    hull.facets.push_back(std::move(facet));
  }
  detail::require_closed_hull(hull, relative_epsilon);
  return hull;
}

}  // namespace nbs
