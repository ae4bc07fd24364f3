// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// RayCaster concept: anything that returns the first intersection of a ray with a surface, plus a brute-force
/// model over an IndexedMesh that serves as the test oracle for faster ray casters (Embree).

#include <concepts>
#include <cstdint>
#include <limits>
#include <optional>

#include "nbs/core/types.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

/// First intersection of a ray with a surface.
struct RayHit {
  double distance = 0.0;          ///< metres along the (unit) direction from the origin.
  std::uint32_t triangle = 0;     ///< index of the hit triangle.
  Vec3 normal = Vec3::Zero();     ///< unit geometric normal of the hit triangle (orientation as stored).
};

/// A RayCaster answers `first_hit(origin, unit_direction, max_distance)` in world coordinates, metres.
/// Hits at distance <= 0 or > max_distance are not reported. Must be safe to call concurrently (const).
template <class R>
concept RayCaster = requires(const R& r, const Vec3& origin, const Vec3& direction, double max_distance) {
  { r.first_hit(origin, direction, max_distance) } -> std::convertible_to<std::optional<RayHit>>;
};

/// O(\#F) ray caster over an IndexedMesh (Möller–Trumbore, double precision, both faces). Borrows the mesh: it must
/// outlive the caster. Thread-safe for concurrent `first_hit` calls. Intended as an oracle and for tiny meshes.
class BruteForceRayCaster {
public:
  explicit BruteForceRayCaster(const IndexedMesh& mesh) : mesh_(&mesh) { mesh.validate(); }

  [[nodiscard]] std::optional<RayHit> first_hit(const Vec3& origin, const Vec3& direction,
                                                double max_distance = std::numeric_limits<double>::infinity()) const {
    std::optional<RayHit> best;
    double best_t = max_distance;
    for (std::size_t t = 0; t < mesh_->triangles.size(); ++t) {
      const Vec3& a = mesh_->corner(t, 0);
      const Vec3 e1 = mesh_->corner(t, 1) - a;
      const Vec3 e2 = mesh_->corner(t, 2) - a;
      const Vec3 p = direction.cross(e2);
      const double det = e1.dot(p);
      if (std::abs(det) < 1e-300) continue;
      const double inv = 1.0 / det;
      const Vec3 s = origin - a;
      const double u = s.dot(p) * inv;
      if (u < 0.0 || u > 1.0) continue;
      const Vec3 q = s.cross(e1);
      const double v = direction.dot(q) * inv;
      if (v < 0.0 || u + v > 1.0) continue;
      const double dist = e2.dot(q) * inv;
      if (dist > 0.0 && dist <= best_t) {
        best_t = dist;
        best = RayHit{dist, static_cast<std::uint32_t>(t), e1.cross(e2).normalized()};
      }
    }
    return best;
  }

private:
  const IndexedMesh* mesh_;
};

static_assert(RayCaster<BruteForceRayCaster>);

}  // namespace nbs
