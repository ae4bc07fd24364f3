// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Holes (Sec. 4.4) and the estimated mesh coverage (Sec. 4.6, Eqs. 4.35–4.37).

#include <Eigen/Eigenvalues>

#include <limits>
#include <utility>
#include <vector>

#include "nbs/core/parameters.hpp"
#include "nbs/mesh/detail/border_graph.hpp"

namespace nbs {

/// A closed loop of border edges E_H (Sec. 4.4).
struct Hole {
  std::vector<VertexId> vertices;  ///< loop in walking order (triangles on the left); |E_H| = vertices.size().
  Vec3 center = Vec3::Zero();      ///< c_h: mean of the loop vertices.
  Vec3 normal = Vec3::Zero();      ///< n_h: PCA normal of the loop vertices, oriented like their mean vertex normal.
  Vec3 largest_direction = Vec3::Zero();  ///< d_h = v_max − c_h (not normalised; Eqs. 4.22–4.23 use its length).
  double area_m2 = 0.0;           ///< A_hole, Eq. (4.37).
};

/// Eq. (4.37): A_hole = ½ Σ |(v_{i−1} − c_h) × (v_i − c_h)| over the loop. The thesis prints dir(·,·) (unit
/// vectors), which would make the sum dimensionless; we use the difference vectors so A_hole is an area in m².
[[nodiscard]] inline double hole_area(const std::vector<Vec3>& loop, const Vec3& c) {
  double a = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
    a += (loop[(i + loop.size() - 1) % loop.size()] - c).cross(loop[i] - c).norm();
  return 0.5 * a;
}

/// All closed border loops with h_min ≤ |E_H| ≤ h_max edges (`params.hole_min_edges`, `hole_max_edges`).
/// Walks may not pass a vertex with several outgoing border edges consistently; such walks that do not close
/// within h_max edges are skipped. Deterministic.
template <EdgeMesh M>
[[nodiscard]] std::vector<Hole> find_holes(const M& mesh, const Parameters& params) {
  params.validate();
  const detail::BorderGraph g(mesh);
  std::vector<char> visited(g.edges.size(), 0);
  std::vector<Hole> holes;
  std::vector<std::uint32_t> walk;
  for (std::uint32_t start = 0; start < g.edges.size(); ++start) {
    if (visited[start]) continue;
    walk.assign(1, start);
    visited[start] = 1;
    const VertexId origin = g.edges[start].from;
    bool closed = false;
    while (static_cast<int>(walk.size()) <= params.hole_max_edges) {
      const VertexId at = g.edges[walk.back()].to;
      if (at == origin) {
        closed = true;
        break;
      }
      const std::int64_t nx = g.pick(g.out, at, [&](std::uint32_t e) { return !visited[e]; });
      if (nx < 0) break;
      visited[static_cast<std::uint32_t>(nx)] = 1;
      walk.push_back(static_cast<std::uint32_t>(nx));
    }
    if (!closed || static_cast<int>(walk.size()) < params.hole_min_edges) continue;
    Hole h;
    std::vector<Vec3> pts;
    Vec3 mean_normal = Vec3::Zero();
    for (std::uint32_t e : walk) {
      h.vertices.push_back(g.edges[e].from);
      pts.push_back(mesh.position(g.edges[e].from));
      mean_normal += mesh.normal(g.edges[e].from);
    }
    for (const Vec3& p : pts) h.center += p;
    h.center /= static_cast<double>(pts.size());
    Mat3 cov = Mat3::Zero();
    double far = -1.0;
    for (const Vec3& p : pts) {
      cov += (p - h.center) * (p - h.center).transpose();
      if ((p - h.center).norm() > far) far = (p - h.center).norm(), h.largest_direction = p - h.center;
    }
    const Eigen::SelfAdjointEigenSolver<Mat3> es(cov);
    h.normal = es.eigenvectors().col(0);
    if (h.normal.dot(mean_normal) < 0.0) h.normal = -h.normal;
    h.area_m2 = hole_area(pts, h.center);
    holes.push_back(std::move(h));
  }
  return holes;
}

/// Every closed border loop with at least h_min edges (find_holes without the h_max limit), e.g. for
/// estimated_coverage_unseen.
template <EdgeMesh M>
[[nodiscard]] std::vector<Hole> find_all_loops(const M& mesh, Parameters params) {
  params.hole_max_edges = std::numeric_limits<int>::max();
  return find_holes(mesh, params);
}

/// A_filled, Eq. (4.36): total triangle area, m² (difference vectors, as for Eq. 4.37).
template <EdgeMesh M>
[[nodiscard]] double filled_area(const M& mesh) {
  double a = 0.0;
  mesh.for_each_face([&](const MeshFace& f) {
    a += 0.5 * (mesh.position(f.b) - mesh.position(f.a)).cross(mesh.position(f.c) - mesh.position(f.a)).norm();
  });
  return a;
}

namespace detail {
/// Eq. (4.35): A_filled / (A_filled + Σ empty(h)) over `holes`; 0 for a mesh without triangles.
template <EdgeMesh M, class Empty>
[[nodiscard]] double coverage_ratio(const M& mesh, const std::vector<Hole>& holes, Empty&& empty_of) {
  const double filled = filled_area(mesh);
  double empty = 0.0;
  for (const Hole& h : holes) empty += empty_of(h);
  return filled > 0.0 ? filled / (filled + empty) : 0.0;
}
}  // namespace detail

/// Estimated mesh coverage ĉ_m = A_filled / (A_filled + A_empty), Eq. (4.35), A_empty = Σ A_hole over `holes`.
/// 0 for a mesh without triangles.
template <EdgeMesh M>
[[nodiscard]] double estimated_coverage(const M& mesh, const std::vector<Hole>& holes) {
  return detail::coverage_ratio(mesh, holes, [](const Hole& h) { return h.area_m2; });
}

/// Calls f(x, d) for the 3·|E_H| samples x (world, m) of hole h's Eq. 4.37 fan: per fan triangle (c_h, v_{i−1}, v_i)
/// the points 1/4, 1/2 and 3/4 of the way from c_h to the midpoint m_i of v_{i−1}v_i; d = |x − m_i| (m), the
/// sample's distance from the midpoint of its triangle's loop edge.
template <EdgeMesh M, class F>
void for_each_fan_sample_at(const M& mesh, const Hole& h, F&& f) {
  const std::size_t k = h.vertices.size();
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3 mid = 0.5 * (mesh.position(h.vertices[(i + k - 1) % k]) + mesh.position(h.vertices[i]));
    for (const double t : {0.25, 0.5, 0.75}) f(Vec3(h.center + t * (mid - h.center)), (1.0 - t) * (mid - h.center).norm());
  }
}

/// Calls f(x) for the fan samples of for_each_fan_sample_at.
template <EdgeMesh M, class F>
void for_each_fan_sample(const M& mesh, const Hole& h, F&& f) {
  for_each_fan_sample_at(mesh, h, [&](const Vec3& x, double) { f(x); });
}

/// A fan sample of a closed border loop that ĉ_m counts as missing surface (an Eq. 4.37 fan sample neither seen nor
/// in a seam's free space): where the estimate believes unseen surface lies.
struct UnseenSample {
  Vec3 position = Vec3::Zero();  ///< world, metres
  double area_m2 = 0.0;          ///< the share of A_hole it stands for: A_hole / (3·|E_H|), m²
  /// distance from the midpoint of its fan triangle's loop edge (for_each_fan_sample_at), m: small for the samples
  /// of small loops and near the border of large ones
  double edge_distance_m = 0.0;
};

/// Share of hole h's Eq. 4.37 fan samples (for_each_fan_sample) that `seen(x)` (x: world point, m) calls measured
/// surface. 1 for a loop without vertices. `unseen` (optional) gets the samples not seen appended.
template <EdgeMesh M, class Seen>
[[nodiscard]] double fan_seen_share(const M& mesh, const Hole& h, Seen&& seen,
                                    std::vector<UnseenSample>* unseen = nullptr) {
  if (h.vertices.empty()) return 1.0;
  const double n = static_cast<double>(3 * h.vertices.size());
  std::size_t hits = 0;
  for_each_fan_sample_at(mesh, h, [&](const Vec3& x, double d) {
    if (seen(x)) ++hits;
    else if (unseen) unseen->push_back({x, h.area_m2 / n, d});
  });
  return static_cast<double>(hits) / n;
}

/// ĉ_m = A_filled / (A_filled + A_empty) (Eq. 4.35) with A_empty = Σ A_hole · (1 − fan_seen_share) over `loops`,
/// meant to be every closed border loop (find_all_loops). Our reading for noisy streams: a loop
/// whose fan lies in voxels already measured as surface is a gap of the triangulation, not missing surface, and the
/// not yet seen surface of a partial model lies in loops longer than any h_max. `seen(x)`: x lies in a voxel
/// measured as surface (e.g. p > Parameters::occupied_threshold). 0 for a mesh without triangles. `unseen`
/// (optional) gets the fan samples A_empty is made of appended (Σ area_m2 = A_empty).
template <EdgeMesh M, class Seen>
[[nodiscard]] double estimated_coverage_unseen(const M& mesh, const std::vector<Hole>& loops, Seen&& seen,
                                               std::vector<UnseenSample>* unseen = nullptr) {
  return detail::coverage_ratio(
      mesh, loops, [&](const Hole& h) { return h.area_m2 * (1.0 - fan_seen_share(mesh, h, seen, unseen)); });
}

/// Where a long loop's fan lies in empty space (issue 18): what counts as a seam rather than a hole.
struct FreeSeamRule {
  int min_edges = 200;         ///< only loops with more edges than this (h_max: shorter loops are holes, Sec. 4.4).
  double min_free_share = 0.5; ///< ... whose fan samples are at least this share `free(x)` (and not seen).
};

/// Unseen share of loop h's fan samples: 1 − (seen + free) / n if h has more than rule.min_edges edges and at least
/// rule.min_free_share of its samples are free and not seen (a seam whose fan crosses measured empty space: no
/// surface can lie there), else 1 − seen / n as in estimated_coverage_unseen. `seen(x)`, `free(x)`: world point x
/// (m) lies in measured surface (or is walled in by it) / in measured free space. 0 for a loop without vertices.
/// `unseen` (optional) gets the samples the share counts appended.
template <EdgeMesh M, class Seen, class Free>
[[nodiscard]] double fan_unseen_share(const M& mesh, const Hole& h, Seen&& seen, Free&& free, const FreeSeamRule& rule,
                                      std::vector<UnseenSample>* unseen = nullptr) {
  if (h.vertices.empty()) return 0.0;
  enum class State : unsigned char { seen, free, unknown };
  struct Sample {
    Vec3 x;
    double d;
    State st;
  };
  std::vector<Sample> samples;
  samples.reserve(3 * h.vertices.size());
  std::size_t hits = 0, empty = 0;
  for_each_fan_sample_at(mesh, h, [&](const Vec3& x, double d) {
    State st = State::unknown;
    if (seen(x)) {
      st = State::seen;
      ++hits;
    } else if (free(x)) {
      st = State::free;
      ++empty;
    }
    samples.push_back({x, d, st});
  });
  const std::size_t n = samples.size();
  const bool seam = static_cast<long long>(h.vertices.size()) > rule.min_edges &&
                    static_cast<double>(empty) >= rule.min_free_share * static_cast<double>(n);
  if (unseen) {
    for (const Sample& q : samples)
      if (q.st == State::unknown || (q.st == State::free && !seam))
        unseen->push_back({q.x, h.area_m2 / static_cast<double>(n), q.d});
  }
  return static_cast<double>(n - hits - (seam ? empty : 0)) / static_cast<double>(n);
}

/// estimated_coverage_unseen with the free-seam rule: A_empty = Σ A_hole · fan_unseen_share(h, seen, free, rule)
/// over `loops` (every closed border loop). 0 for a mesh without triangles. `unseen` (optional) gets the fan
/// samples A_empty is made of appended (Σ area_m2 = A_empty).
template <EdgeMesh M, class Seen, class Free>
[[nodiscard]] double estimated_coverage_unseen_free(const M& mesh, const std::vector<Hole>& loops, Seen&& seen,
                                                    Free&& free, const FreeSeamRule& rule,
                                                    std::vector<UnseenSample>* unseen = nullptr) {
  return detail::coverage_ratio(mesh, loops, [&](const Hole& h) {
    return h.area_m2 * fan_unseen_share(mesh, h, seen, free, rule, unseen);
  });
}

}  // namespace nbs
