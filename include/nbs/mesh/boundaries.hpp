// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Boundary detection (Sec. 4.2.1, Alg. 1, Tab. 4.1).
///
/// Sensor-frame convention (include/nbs/core/types.hpp): s_z is the viewing direction, the stripe lies along s_x,
/// the scan moves along s_y. The thesis draws its SCS with x to the left and y up, seen from behind the sensor;
/// we apply Tab. 4.1 literally to our s_x, s_y. "Left of an edge" is judged looking from the normal (sensor) side.
/// Hence, where the boundary lies relative to the mesh (as seen by the sensor):
///   left   = mesh border at the +s_x side,   right  = at the −s_x side,
///   top    = mesh border at the +s_y side,   bottom = at the −s_y side.

#include <algorithm>
#include <cmath>
#include <deque>
#include <vector>

#include "nbs/core/parameters.hpp"
#include "nbs/mesh/detail/border_graph.hpp"

namespace nbs {

enum class BoundaryType : std::uint8_t { left, right, top, bottom };

/// One detected boundary B_i = (V_B, E_B).
struct Boundary {
  BoundaryType type = BoundaryType::left;
  std::vector<std::array<VertexId, 2>> edges;  ///< E_B in walking order, each directed along +s (Tab. 4.1).
  std::vector<VertexId> vertices;              ///< vertices of E_B in order (|E_B| + 1 unless closed).
  Vec3 mean_normal = Vec3::Zero();             ///< mean of the vertex normals (not normalised).
};

/// Alg. 1 over the border edges of M_cur (all border edges if the mesh does not track scans). `sensor` is T_WS of
/// the last scan. Boundaries shorter than b_min, or whose mean normal faces away from the sensor (n̄ · s_z ≥ 0),
/// are dropped. A walk ends when the penalty exceeds ρ_t (the trailing badly aligned edges are then removed), at
/// the end of the border chain, or when it closes. Deterministic: border edges are visited in `for_each_edge` order.
template <EdgeMesh M>
[[nodiscard]] std::vector<Boundary> detect_boundaries(const M& mesh, const Pose& sensor, const Parameters& params) {
  params.validate();
  const detail::BorderGraph g(mesh);
  const Vec3 sx = sensor.linear().col(0), sy = sensor.linear().col(1), sz = sensor.linear().col(2);
  const double cos_t = std::cos(params.boundary_angle_rad);
  std::vector<char> taken(g.edges.size(), 0);  // in B_M, or already walked from
  std::vector<Boundary> result;
  auto dir = [&](std::uint32_t e) { return (mesh.position(g.edges[e].to) - mesh.position(g.edges[e].from)).normalized(); };

  for (std::uint32_t start = 0; start < g.edges.size(); ++start) {
    if (taken[start] || !g.edges[start].current) continue;
    const Vec3 d = dir(start);
    if (!d.allFinite()) continue;
    Vec3 s;
    bool vertical;
    if (std::abs(d.dot(sy)) >= cos_t) {
      s = sy, vertical = true;
    } else if (std::abs(d.dot(sx)) >= cos_t) {
      s = sx, vertical = false;
    } else {
      continue;
    }
    const double sigma = d.dot(s) >= 0.0 ? 1.0 : -1.0;  // walking direction vs. s
    // Triangle on the left of the walking direction; after adapting to +s it is on the left iff sigma > 0.
    const bool left_after_adapt = sigma > 0.0;
    const BoundaryType type = vertical ? (left_after_adapt ? BoundaryType::right : BoundaryType::left)
                                       : (left_after_adapt ? BoundaryType::top : BoundaryType::bottom);
    std::deque<std::uint32_t> chain{start};
    std::deque<bool> good{true};
    taken[start] = 1;
    auto usable = [&](std::uint32_t e) { return !taken[e] && g.edges[e].current; };
    auto aligned = [&](std::uint32_t e) {
      const Vec3 de = dir(e);
      return de.allFinite() && sigma * de.dot(s) >= cos_t;
    };
    for (int forward = 1; forward >= 0; --forward) {
      int penalty = 0;
      while (true) {
        const std::uint32_t end = forward ? chain.back() : chain.front();
        const std::int64_t nx = forward ? g.pick(g.out, g.edges[end].to, usable) : g.pick(g.in, g.edges[end].from, usable);
        if (nx < 0) break;
        const auto e = static_cast<std::uint32_t>(nx);
        const bool ok = aligned(e);
        penalty = ok ? 0 : penalty + 1;
        if (penalty > params.boundary_penalty_threshold) break;
        taken[e] = 1;
        if (forward) chain.push_back(e), good.push_back(ok);
        else chain.push_front(e), good.push_front(ok);
      }
    }
    while (!good.empty() && !good.back()) chain.pop_back(), good.pop_back();
    while (!good.empty() && !good.front()) chain.pop_front(), good.pop_front();
    if (static_cast<int>(chain.size()) < params.min_boundary_edges) continue;
    Boundary b;
    b.type = type;
    b.vertices.push_back(g.edges[chain.front()].from);
    for (std::uint32_t e : chain) {
      const auto& ed = g.edges[e];
      b.edges.push_back(sigma > 0 ? std::array<VertexId, 2>{ed.from, ed.to} : std::array<VertexId, 2>{ed.to, ed.from});
      b.vertices.push_back(ed.to);
    }
    for (VertexId v : b.vertices) b.mean_normal += mesh.normal(v);
    b.mean_normal /= static_cast<double>(b.vertices.size());
    if (b.mean_normal.dot(sz) >= 0.0) continue;  // seen from behind: not a boundary for this sensor
    result.push_back(std::move(b));
  }
  return result;
}

}  // namespace nbs
