// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// LocalTriangulator, closing the gaps the fan left (close_gaps, see its comment in local_triangulation.hpp): the
/// border walk from v and its neighbours, the simple-polygon and containment tests, and the ear clipping that fills
/// a loop or notch completely or not at all. Only included by local_triangulation.hpp, after the class.

#include <algorithm>
#include <cstddef>

#include "nbs/mesh/detail/local_triangulation.hpp"

namespace nbs::detail {

inline VertexId LocalTriangulator::next_border(VertexId x) const {
  const auto& fx = fs_.faces_of(x);
  auto after = [&](std::uint32_t f, int step) {  // the corner `step` places after x in face f
    const auto& t = fs_.face(f);
    const int k = t[0] == x ? 0 : (t[1] == x ? 1 : 2);
    return t[(k + step) % 3];
  };
  for (std::uint32_t f : fx) {
    const VertexId y = after(f, 1);
    if (std::none_of(fx.begin(), fx.end(), [&](std::uint32_t g) { return after(g, 2) == y; })) return y;
  }
  return kNoVertex;
}

inline void LocalTriangulator::close_gaps() {
  const std::size_t cap = static_cast<std::size_t>(std::max(s_.max_gap_edges, 0)) + 1;
  if (chain_.size() < cap) {
    chain_.resize(cap);
    chain_p2_.resize(cap);
  }
  if (border_.size() < pos_.size()) border_.resize(pos_.size());
  std::vector<VertexId>& cand = local_;
  cand.push_back(v_);
  local_p2_.push_back(project(v_));  // local_p2_[i] = project(local_[i]) stays true
  for (std::size_t i = 0; i < cand.size(); ++i)
    for (int guard = 0; guard < 4 && close_gap_from(cand[i]); ++guard) {
    }
}

inline bool LocalTriangulator::close_gap_from(VertexId x) {
  VertexId y = next_border_cached(x);
  if (y == kNoVertex) return false;
  const double r2 = s_.radius_m * s_.radius_m;
  chain_[0] = x;
  chain_p2_[0] = project(x);
  chain_n_ = 1;
  chain_checked_ = 0;
  chain_crossed_ = false;
  chain_area2_ = 0.0;
  double length = 0.0;
  for (int k = 1; k <= s_.max_gap_edges; ++k) {
    if (k > 1) y = next_border_cached(chain_[chain_n_ - 1]);
    if (y == kNoVertex) return false;
    if (y == x) return k >= 3 && fill_polygon(true);
    const auto chain_end = chain_.begin() + static_cast<std::ptrdiff_t>(chain_n_);
    if (std::find(chain_.begin(), chain_end, y) != chain_end) return false;
    if ((pos_[y] - pos_[v_]).squaredNorm() > 4.0 * r2) return false;
    const VertexId prev = chain_[chain_n_ - 1];
    length += (pos_[y] - pos_[prev]).norm();
    const P2 py = project(y), &pb = chain_p2_[chain_n_ - 1];
    chain_area2_ += pb.x() * py.y() - pb.y() * py.x();
    chain_[chain_n_] = y;
    chain_p2_[chain_n_] = py;
    ++chain_n_;
    const double chord2 = (pos_[y] - pos_[x]).squaredNorm();
    // fill_polygon's clockwise test first (the cheapest reject; all of them only reject).
    if (k >= 2 && chord2 <= r2 && length * length >= s_.min_notch_ratio * s_.min_notch_ratio * chord2 &&
        clockwise() && !fs_.has_edge(x, y)) {
      if (fill_polygon(false)) return true;
      if (chain_crossed_) return false;  // two chain edges cross: every longer polygon of this walk is not simple
    }
  }
  return false;
}

inline bool LocalTriangulator::fill_polygon(bool closed) {
  const std::size_t m = chain_n_;
  if (!clockwise()) return false;
  // Simple: no two non-adjacent polygon edges cross. Edge j is c_j → c_j+1 (mod m); the pairs of chain edges
  // (j < m − 1) are checked once per walk (chain_checked_), the closing edge j = m − 1 every time.
  for (std::size_t j = chain_checked_; j + 1 < m; ++j)
    for (std::size_t i = 0; i + 2 <= j; ++i)
      if (cross(chain_p2_[i], chain_p2_[i + 1], chain_p2_[j], chain_p2_[j + 1])) {
        chain_crossed_ = true;
        return false;
      }
  chain_checked_ = m - 1;
  for (std::size_t i = 1; i + 3 <= m; ++i)
    if (cross(chain_p2_[i], chain_p2_[i + 1], chain_p2_[m - 1], chain_p2_[0])) return false;
  // No other local vertex inside (winding number in projection; zero for a point below or on/above the polygon's
  // y range, where no edge passes the crossing conditions).
  double min_y = chain_p2_[0].y(), max_y = min_y;
  for (std::size_t i = 1; i < m; ++i) {
    min_y = std::min(min_y, chain_p2_[i].y());
    max_y = std::max(max_y, chain_p2_[i].y());
  }
  for (std::size_t iq = 0; iq < local_.size(); ++iq) {
    const P2& pq = local_p2_[iq];
    if (pq.y() < min_y || pq.y() >= max_y) continue;
    int wind = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const P2& a = chain_p2_[i];
      const P2& b = chain_p2_[i + 1 == m ? 0 : i + 1];
      if (a.y() <= pq.y()) {
        if (b.y() > pq.y() && orient(a, b, pq) > 0.0) ++wind;
      } else if (b.y() <= pq.y() && orient(a, b, pq) < 0.0) {
        --wind;
      }
    }
    if (wind == 0) continue;
    const auto chain_end = chain_.begin() + static_cast<std::ptrdiff_t>(m);  // the polygon's own corners do not count
    if (std::find(chain_.begin(), chain_end, local_[iq]) == chain_end) return false;
  }
  // Ear clipping on the reversed (counter-clockwise) polygon; faces are collected first, added at the end.
  ring_.clear();
  for (std::size_t i = m; i-- > 0;) ring_.push_back(static_cast<std::uint32_t>(i));
  ears_.clear();
  const double r2 = s_.radius_m * s_.radius_m;
  while (ring_.size() > 3) {
    std::size_t best = ring_.size();
    double best_len = r2;
    for (std::size_t i = 0; i < ring_.size(); ++i) {
      const std::size_t n = ring_.size();
      const std::uint32_t ia = ring_[i == 0 ? n - 1 : i - 1], ib = ring_[i], ic = ring_[i + 1 == n ? 0 : i + 1];
      const P2 &pa = chain_p2_[ia], &pb = chain_p2_[ib], &pc = chain_p2_[ic];
      if (orient(pa, pb, pc) <= kEps) continue;
      const double len = (pos_[chain_[ia]] - pos_[chain_[ic]]).squaredNorm();
      if (len > best_len) continue;
      bool empty = true;
      for (std::uint32_t j : ring_) {
        if (j == ia || j == ib || j == ic) continue;
        const P2& x = chain_p2_[j];
        if (orient(pa, pb, x) >= -kEps && orient(pb, pc, x) >= -kEps && orient(pc, pa, x) >= -kEps) {
          empty = false;
          break;
        }
      }
      if (!empty || fs_.has_edge(chain_[ia], chain_[ic]) || !gap_face_ok(chain_[ia], chain_[ib], chain_[ic], closed))
        continue;
      best = i;
      best_len = len;
    }
    if (best == ring_.size()) return false;
    const std::size_t n = ring_.size();
    ears_.push_back({chain_[ring_[(best + n - 1) % n]], chain_[ring_[best]], chain_[ring_[(best + 1) % n]]});
    ring_.erase(ring_.begin() + static_cast<std::ptrdiff_t>(best));
  }
  const VertexId a = chain_[ring_[0]], b = chain_[ring_[1]], c = chain_[ring_[2]];
  if (orient(chain_p2_[ring_[0]], chain_p2_[ring_[1]], chain_p2_[ring_[2]]) <= kEps || !gap_face_ok(a, b, c, closed))
    return false;
  if (!closed && (pos_[chain_[0]] - pos_[chain_[m - 1]]).squaredNorm() > r2) return false;
  ears_.push_back({a, b, c});
  for (const auto& t : ears_) {
    fs_.add(t[0], t[1], t[2], scan_);
    ++touched_;
  }
  return true;
}

}  // namespace nbs::detail
