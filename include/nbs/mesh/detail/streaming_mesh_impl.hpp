// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// StreamingMesh's stream stages, defined out of the class (streaming_mesh.hpp, which includes this file at its
/// end): insert() (validity, pass-through and density checks, storing the point, updating the neighbours' counts,
/// cached balls and moments, retrying pending neighbours), estimate() (the normal stage) and triangulate() (choosing
/// the meshed neighbours for the local triangulation).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <vector>

#include "nbs/mesh/streaming_mesh.hpp"

namespace nbs {

inline InsertResult StreamingMesh::insert(const Vec3& p, const Vec3& line_of_sight, const Rgb& color) {
  const auto created = static_cast<VertexId>(pos_.size());
  const InsertResult r = insert(p, line_of_sight);  // throws before any change
  if (r == InsertResult::outside) return r;
  const VertexId v = r == InsertResult::too_close ? last_close_ : created;  // too_close() leaves the rejecter there
  if (color_count_.size() <= v) {
    color_count_.resize(pos_.size(), 0);
    color_sum_.resize(pos_.size(), {0, 0, 0});
  }
  ++color_count_[v];
  for (std::size_t k = 0; k < 3; ++k) color_sum_[v][k] += color[k];
  return r;
}

inline InsertResult StreamingMesh::insert(const Vec3& p, const Vec3& line_of_sight) {
  detail::require(p.allFinite(), "StreamingMesh::insert: point is not finite: (", p.transpose(), ")");
  const double los_norm = line_of_sight.norm();
  detail::require(line_of_sight.allFinite() && los_norm > 1e-12,
                  "StreamingMesh::insert: line of sight must be finite with a length > 1e-12, got (",
                  line_of_sight.transpose(), ")");
  detail::require(grid_.in_range(p), "StreamingMesh::insert: point (", p.transpose(), ") lies beyond ±",
                  settings_.max_abs_coordinate_m(), " m on an axis, the coordinate range of the spatial hash at ",
                  "mesh_radius_m = ", settings_.mesh_radius_m, " m");
  ++stats_.received;
  if (!settings_.pass_through.empty() && !settings_.pass_through.contains(p)) {
    ++stats_.outside;
    return InsertResult::outside;
  }
  if (too_close(p, line_of_sight / los_norm)) {
    ++stats_.too_close;
    return InsertResult::too_close;
  }
  const auto v = static_cast<VertexId>(pos_.size());
  pos_.push_back(p);
  if (settings_.project_vertices) surf_.push_back(p);
  nrm_.push_back(Vec3::Zero());
  los_.push_back((line_of_sight / los_norm).cast<float>());
  count_.push_back(1);
  attempt_.push_back(0);
  cached_of_.push_back(0);
  moments_of_.push_back(0);
  faces_.add_vertex();
  grid_.insert(p, v);
  ++stats_.stored;

  gather(p, first_ball_radius(), v, ball_);
  const double rn2 = settings_.normal_radius_m * settings_.normal_radius_m;
  std::vector<VertexId>& retry = retry_;
  retry.clear();
  const std::uint64_t key = grid_.cell_key(p);
  for (const auto& [d2, q] : ball_) {
    if (CachedBall* c = cached_ball(q)) {  // v joins q's ball after the entries of cells <= v's cell
      auto at = c->entries.end();
      while (at != c->entries.begin() && std::prev(at)->key > key) --at;
      c->entries.insert(at, CachedEntry{key, d2, v});
    }
    if (d2 > rn2) continue;
    if (moments_of_[q] != 0) moments_[moments_of_[q] - 1].add(p - pos_[q], detail::pca_weight(d2, 1.0 / rn2));
    ++count_[v];
    ++count_[q];
    if (!has_normal(q) && static_cast<int>(count_[q]) >= settings_.robustness.min_neighbours &&
        count_[q] >= attempt_[q] + 2)
      retry.push_back(q);
  }
  InsertResult result = InsertResult::pending;
  if (estimate(v)) {
    triangulate(v);
    result = InsertResult::meshed;
  } else {
    start_moments(v);
  }
  // Pending neighbours got a new point: retry them, each with its own ball.
  for (VertexId q : retry_) {
    // A clear failure by the moments is one of estimate() too (its verdict, with its bookkeeping).
    if (detail::clearly_not_robust(moments_[moments_of_[q] - 1].covariance(), settings_.robustness, 1e-4)) {
      ++stats_.normal_failures;
      attempt_[q] = count_[q];
      continue;
    }
    if (const CachedBall* c = cached_ball(q)) {
      ball_.clear();
      for (const CachedEntry& e : c->entries) ball_.emplace_back(e.d2, e.id);
    } else {
      gather(pos_[q], first_ball_radius(), q, ball_);
    }
    if (estimate(q)) {
      uncache_ball(q);
      drop_moments(q);
      triangulate(q);
    } else if (cached_of_[q] == 0) {
      cache_ball(q);
    }
  }
  faces_.refresh_border();  // the faces are consistent again: bring the border masks up to date
  return result;
}

inline bool StreamingMesh::estimate(VertexId v) {
  const double rn2 = settings_.normal_radius_m * settings_.normal_radius_m, inv_rn2 = 1.0 / rn2;
  pts_.clear();
  wts_.clear();
  pts_.push_back(pos_[v]);
  wts_.push_back(detail::pca_weight(0.0, inv_rn2));
  for (const auto& [d2, q] : ball_)
    if (d2 <= rn2) {
      pts_.push_back(pos_[q]);
      wts_.push_back(detail::pca_weight(d2, inv_rn2));
    }
  const auto est = detail::estimate_normal(pts_, wts_, los_[v].cast<double>(), settings_.robustness);
  if (!est.robust) {
    ++stats_.normal_failures;
    attempt_[v] = count_[v];
    return false;
  }
  nrm_[v] = est.normal;
  if (settings_.project_vertices) surf_[v] = pos_[v] - (pos_[v] - est.mean).dot(est.normal) * est.normal;
  ++stats_.meshed;
  return true;
}

inline void StreamingMesh::triangulate(VertexId v) {
  // The 2·max_fan_neighbours nearest meshed points of the R_m ball. ball_ holds the first ball (the R_m ball's points
  // within min(R_n, R_m), in the same order); if it has fewer meshed points than needed, the R_m ball is gathered —
  // unless the first ball already holds max_fan_neighbours points the fan takes (LocalTriangulator::fan_neighbour):
  // the fan takes the nearest such points, and every point of the wider ball lies farther.
  const std::size_t k_max = 2 * static_cast<std::size_t>(tri_settings_.max_fan_neighbours);
  const double rm2 = settings_.mesh_radius_m * settings_.mesh_radius_m;
  auto select = [&] {
    ball2_.clear();
    for (const auto& e : ball_)
      if (e.first <= rm2 && has_normal(e.second)) ball2_.push_back(e);
  };
  select();
  const auto enough_fan_neighbours = [&] {
    int taken = 0;
    for (const auto& e : ball2_)
      if (tri_.fan_neighbour(v, e.second, tri_settings_) && ++taken >= tri_settings_.max_fan_neighbours) return true;
    return false;
  };
  if (ball2_.size() < k_max && settings_.mesh_radius_m > settings_.normal_radius_m && !enough_fan_neighbours()) {
    gather(pos_[v], settings_.mesh_radius_m, v, ball_);
    select();
  }
  const std::size_t k = std::min(ball2_.size(), k_max);
  // The k nearest, sorted by (squared distance, id): a total order, so nth_element + sort equals partial_sort.
  const auto kth = ball2_.begin() + static_cast<std::ptrdiff_t>(k);
  if (kth != ball2_.end()) std::nth_element(ball2_.begin(), kth, ball2_.end());
  std::sort(ball2_.begin(), kth);
  meshed_nb_.clear();
  for (std::size_t i = 0; i < k; ++i) meshed_nb_.push_back(ball2_[i].second);
  tri_.insert(v, meshed_nb_, tri_settings_, scan_);
}

}  // namespace nbs
