// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `CollisionMesh`: a link's triangle mesh as a collision shape (issue 19, item 1), in its shape frame G, metres, the
/// model's per-axis scale applied, immutable once made (built once when the robot is loaded, shared by every copy of
/// the `LinkShape`). Queries take points in G.
///
/// Solid: a mesh is *closed* if every edge (vertex pair, after welding equal vertices) is shared by an even number of
/// triangles; a closed mesh is the solid it bounds (inside = odd parity of the crossings of the ray from the point
/// along G's +z; edge ties broken by simulation of simplicity, one sign per edge, so a ray through an edge or vertex
/// counts consistently). An *open* mesh is a thin shell: only its surface counts (a point deep inside an open mesh's
/// hull is outside). Cost: the triangles are binned once into a uniform grid over the bounds; `within` tests the
/// triangles of the cells within reach of the point, then (closed meshes) those of its xy column — O(triangles) in
/// the worst case; `surface_distance` / `distance` test every triangle (bounding-sphere rejection).
///
/// A query point with a non-finite coordinate (NaN, ±∞) is outside and beyond any reach: `contains` and `within`
/// give false, `surface_distance` and `distance` +∞.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/sim/point_triangle_distance.hpp"

namespace nbs {

/// A triangle mesh collision shape in its frame G (metres). See the file comment for closed / open meshes.
class CollisionMesh {
public:
  /// `mesh` (as loaded, any unit) scaled by `scale` per axis of G. `name` (the file) is used in messages. Throws
  /// InvalidArgument naming `name` for an invalid mesh (IndexedMesh::validate), a scale that is not finite and > 0,
  /// a scaled vertex that is not finite (the scale overflowed) or scaled bounds whose grid cell is not finite and
  /// > 0 (the scale underflowed to a flat or point mesh).
  CollisionMesh(const IndexedMesh& mesh, const Vec3& scale = Vec3::Ones(), std::string name = "collision mesh")
      : name_(std::move(name)) {
    detail::require(scale.allFinite() && (scale.array() > 0.0).all(), name_, ": mesh scale (", scale.transpose(),
                    ") must be finite and > 0 per axis");
    try {
      mesh.validate();
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(detail::concat(name_, ": ", e.what()));
    }
    // Weld equal scaled vertices, so shared edges share indices.
    std::map<std::tuple<double, double, double>, std::uint32_t> index;
    std::vector<std::uint32_t> remap(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      const Vec3 v = mesh.vertices[i].cwiseProduct(scale);
      detail::require(v.allFinite(), name_, ": vertex ", i, " scaled by (", scale.transpose(), ") is (",
                      v.transpose(), "), not finite");
      const auto [it, inserted] =
          index.try_emplace(std::make_tuple(v.x(), v.y(), v.z()), static_cast<std::uint32_t>(vertices_.size()));
      if (inserted) vertices_.push_back(v);
      remap[i] = it->second;
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_uses;
    for (const auto& t : mesh.triangles) {
      Tri r;
      r.v = {remap[t[0]], remap[t[1]], remap[t[2]]};
      const Vec3 &a = vertices_[r.v[0]], &b = vertices_[r.v[1]], &c = vertices_[r.v[2]];
      r.center = (a + b + c) / 3.0;
      r.radius = std::sqrt(std::max({(a - r.center).squaredNorm(), (b - r.center).squaredNorm(),
                                     (c - r.center).squaredNorm()}));
      r.lo = a.head<2>().cwiseMin(b.head<2>()).cwiseMin(c.head<2>());
      r.hi = a.head<2>().cwiseMax(b.head<2>()).cwiseMax(c.head<2>());
      if (r.v[0] != r.v[1] && r.v[1] != r.v[2] && r.v[0] != r.v[2])
        for (int k = 0; k < 3; ++k) ++edge_uses[std::minmax(r.v[k], r.v[(k + 1) % 3])];
      tris_.push_back(r);
    }
    closed_ = std::ranges::all_of(edge_uses, [](const auto& e) { return e.second % 2 == 0; });
    for (const Vec3& v : vertices_) bounds_.extend(v);
    build_grids();
  }

  [[nodiscard]] const std::string& name() const { return name_; }
  /// True if every edge is shared by an even number of triangles (the mesh bounds a solid).
  [[nodiscard]] bool closed() const { return closed_; }
  [[nodiscard]] std::size_t triangle_count() const { return tris_.size(); }
  /// Welded vertices in G, metres.
  [[nodiscard]] const std::vector<Vec3>& vertices() const { return vertices_; }
  /// Corner k (0..2) of triangle t, in G.
  [[nodiscard]] const Vec3& corner(std::size_t t, int k) const {
    return vertices_[tris_[t].v[static_cast<std::size_t>(k)]];
  }
  /// Bounds of the vertices in G.
  [[nodiscard]] const Aabb& bounds() const { return bounds_; }

  /// The exact world AABB of the mesh placed at T_WG (the bounds of its transformed vertices).
  [[nodiscard]] Aabb world_bounds(const Pose& T_WG) const {
    Aabb b;
    for (const Vec3& v : vertices_) b.extend(T_WG * v);
    return b;
  }

  /// Unsigned distance from g (in G) to the nearest triangle, metres.
  [[nodiscard]] double surface_distance(const Vec3& g) const {
    double best = std::numeric_limits<double>::infinity();
    if (!g.allFinite()) return best;
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      const Tri& r = tris_[t];
      const double lower = (g - r.center).norm() - r.radius;
      if (lower >= best) continue;
      best = std::min(best, point_triangle_distance(g, corner(t, 0), corner(t, 1), corner(t, 2)));
    }
    return best;
  }

  /// True if g (in G) lies inside the closed mesh (ray parity); always false for an open mesh.
  [[nodiscard]] bool contains(const Vec3& g) const {
    if (!closed_ || !g.allFinite()) return false;
    if (!(g.x() >= bounds_.min.x() && g.x() < bounds_.max.x() && g.y() >= bounds_.min.y() && g.y() < bounds_.max.y()))
      return false;
    bool inside = false;
    const std::size_t col = cell_index(g, 0) + columns_.n[0] * cell_index(g, 1);
    for (std::uint32_t i = columns_.start[col]; i < columns_.start[col + 1]; ++i) {
      const Tri& r = tris_[columns_.tris[i]];
      // Half-open xy bounds: the point perturbed by (ε, ε²) is outside where x ≥ max or y ≥ max.
      if (g.x() < r.lo.x() || g.x() >= r.hi.x() || g.y() < r.lo.y() || g.y() >= r.hi.y()) continue;
      double w[3];  // w[k]: signed doubled xy area of (edge opposite corner k, g)
      int sign[3];
      for (int k = 0; k < 3; ++k)
        sign[k] = edge_side(r.v[static_cast<std::size_t>((k + 1) % 3)], r.v[static_cast<std::size_t>((k + 2) % 3)], g,
                            w[k]);
      if (sign[0] == 0 || sign[0] != sign[1] || sign[1] != sign[2]) continue;
      const double sum = w[0] + w[1] + w[2];
      if (sum == 0.0) continue;
      const double z =
          (w[0] * vertices_[r.v[0]].z() + w[1] * vertices_[r.v[1]].z() + w[2] * vertices_[r.v[2]].z()) / sum;
      if (z > g.z()) inside = !inside;
    }
    return inside;
  }

  /// Signed distance from g (in G) to the solid, metres: negative inside a closed mesh; an open mesh's is ≥ 0.
  [[nodiscard]] double distance(const Vec3& g) const {
    const double d = surface_distance(g);
    return contains(g) ? -d : d;
  }

  /// True if g (in G) is within `reach` (≥ 0, metres) of the solid: a triangle within reach, or inside. Stops at the
  /// first triangle within reach; equals distance(g) ≤ reach. False for a NaN reach.
  [[nodiscard]] bool within(const Vec3& g, double reach) const {
    if (!g.allFinite() || std::isnan(reach)) return false;
    // The cells of the cube [g − reach, g + reach] (a triangle within reach has its closest point there).
    std::size_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      if (g[a] + reach < bounds_.min[a] || g[a] - reach > bounds_.max[a]) return false;  // beyond the bounds
      lo[a] = cell_of(g[a] - reach, a);
      hi[a] = cell_of(g[a] + reach, a);
    }
    for (std::size_t z = lo[2]; z <= hi[2]; ++z)
      for (std::size_t y = lo[1]; y <= hi[1]; ++y)
        for (std::size_t x = lo[0]; x <= hi[0]; ++x) {
          const std::size_t c = x + cells_.n[0] * (y + cells_.n[1] * z);
          for (std::uint32_t i = cells_.start[c]; i < cells_.start[c + 1]; ++i) {
            const std::uint32_t t = cells_.tris[i];
            const Tri& r = tris_[t];
            const double s = r.radius + reach;
            if ((g - r.center).squaredNorm() > s * s) continue;
            if (point_triangle_distance(g, corner(t, 0), corner(t, 1), corner(t, 2)) <= reach) return true;
          }
        }
    return contains(g);
  }

private:
  // Triangles binned by their AABB into a uniform grid over the bounds (CSR): 3D for the surface query, one layer
  // (xy columns) for the ray parity. ⌈∛triangles⌉ cells along the longest axis, cubic cells, at most 64 per axis.
  struct Grid {
    std::size_t n[3] = {1, 1, 1};
    std::vector<std::uint32_t> start, tris;
  };

  [[nodiscard]] std::size_t cell_of(double x, int a) const {
    const double f = std::floor((x - bounds_.min[a]) / cell_m_);
    return static_cast<std::size_t>(std::clamp(f, 0.0, static_cast<double>(cells_.n[a] - 1)));
  }
  [[nodiscard]] std::size_t cell_index(const Vec3& g, int a) const { return cell_of(g[a], a); }

  void build_grids() {
    const double extent = bounds_.extent().maxCoeff();
    const double per_axis = std::clamp(std::ceil(std::cbrt(static_cast<double>(tris_.size()))), 1.0, 64.0);
    cell_m_ = extent / per_axis;
    detail::require(std::isfinite(cell_m_) && cell_m_ > 0.0, name_, ": the scaled bounds' extent (",
                    bounds_.extent().transpose(), ") gives a grid cell of ", cell_m_, " m; it must be finite and > 0");
    for (int a = 0; a < 3; ++a)
      cells_.n[a] = static_cast<std::size_t>(
          std::clamp(std::ceil(bounds_.extent()[a] / cell_m_), 1.0, 64.0));
    columns_.n[0] = cells_.n[0];
    columns_.n[1] = cells_.n[1];
    const auto fill = [&](Grid& grid, int dims) {
      const std::size_t count = grid.n[0] * grid.n[1] * grid.n[2];
      grid.start.assign(count + 1, 0);
      for (int pass = 0; pass < 2; ++pass) {
        std::vector<std::uint32_t> at(grid.start.begin(), grid.start.end() - 1);
        if (pass == 1) grid.tris.resize(grid.start.back());
        for (std::size_t t = 0; t < tris_.size(); ++t) {
          Vec3 lo = vertices_[tris_[t].v[0]], hi = lo;
          for (int k = 1; k < 3; ++k) {
            lo = lo.cwiseMin(corner(t, k));
            hi = hi.cwiseMax(corner(t, k));
          }
          std::size_t l[3] = {0, 0, 0}, h[3] = {0, 0, 0};
          for (int a = 0; a < dims; ++a) {
            l[a] = cell_of(lo[a], a);
            h[a] = cell_of(hi[a], a);
          }
          for (std::size_t z = l[2]; z <= h[2]; ++z)
            for (std::size_t y = l[1]; y <= h[1]; ++y)
              for (std::size_t x = l[0]; x <= h[0]; ++x) {
                const std::size_t c = x + grid.n[0] * (y + grid.n[1] * z);
                if (pass == 0) ++grid.start[c + 1];
                else grid.tris[at[c]++] = static_cast<std::uint32_t>(t);
              }
        }
        if (pass == 0)
          for (std::size_t c = 0; c < count; ++c) grid.start[c + 1] += grid.start[c];
      }
    };
    fill(cells_, 3);
    fill(columns_, 2);
  }

  struct Tri {
    std::array<std::uint32_t, 3> v{};
    Vec3 center = Vec3::Zero();
    double radius = 0.0;
    Eigen::Vector2d lo = Eigen::Vector2d::Zero(), hi = Eigen::Vector2d::Zero();
  };

  // Side of g's xy projection relative to the directed edge i → j (+1 left, −1 right, 0 for an edge of zero xy
  // length); `area` gets the signed doubled area. Computed once per undirected edge in index order and negated for
  // the other direction, so both triangles of an edge see the same sign; a zero area is resolved as for the point
  // moved by (ε, ε²) (simulation of simplicity).
  [[nodiscard]] int edge_side(std::uint32_t i, std::uint32_t j, const Vec3& g, double& area) const {
    const bool swapped = i > j;
    if (swapped) std::swap(i, j);
    const Vec3 &a = vertices_[i], &b = vertices_[j];
    const double dx = b.x() - a.x(), dy = b.y() - a.y();
    const double s = dx * (g.y() - a.y()) - dy * (g.x() - a.x());
    int sign = s > 0.0 ? 1 : s < 0.0 ? -1 : dy != 0.0 ? (dy > 0.0 ? -1 : 1) : dx > 0.0 ? 1 : dx < 0.0 ? -1 : 0;
    area = swapped ? -s : s;
    return swapped ? -sign : sign;
  }

  std::string name_;
  std::vector<Vec3> vertices_;
  std::vector<Tri> tris_;
  Aabb bounds_;
  bool closed_ = false;
  double cell_m_ = 1.0;
  Grid cells_, columns_;
};

}  // namespace nbs
