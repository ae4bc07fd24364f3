// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// LocalTriangulator, placing the new vertex v (see local_triangulation.hpp for the class and the steps): collecting
/// the faces of the R_m patch with their tangent-plane projections, splitting the face that contains v, else the fan
/// of visible neighbours, then the Lawson flips. Only included by local_triangulation.hpp, after the class.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "nbs/mesh/detail/local_triangulation.hpp"

namespace nbs::detail {

inline void LocalTriangulator::collect_local_faces() {
  // Marks of this call start above every earlier one: face_base_ + faces_.size() of the previous call + 1.
  face_base_ += static_cast<std::uint32_t>(faces_.size()) + 1;
  if (face_base_ > 0x7FFFFFFFu) {  // far from wrapping (a call adds far fewer than 2^31): forget every old mark
    std::fill(face_mark_.begin(), face_mark_.end(), 0u);
    face_base_ = 1;
  }
  faces_.clear();
  if (face_mark_.size() < fs_.face_count()) face_mark_.resize(fs_.face_count(), 0);
  for (VertexId q : local_)
    for (std::uint32_t f : fs_.faces_of(q))
      if (face_mark_[f] < face_base_) {  // each face once, then in id order
        face_mark_[f] = face_base_;
        faces_.push_back(f);
      }
  std::sort(faces_.begin(), faces_.end());
  for (std::size_t i = 0; i < faces_.size(); ++i) face_mark_[faces_[i]] = face_base_ + static_cast<std::uint32_t>(i);
  // Distinct corners with their projections, computed once for split_containing_face() and fan().
  next_generation();
  verts_.clear();
  corner_.clear();
  for (std::uint32_t f : faces_)
    for (VertexId q : fs_.face(f)) corner_.push_back(marked(q) ? slot_[q] : vert_index(q, project(q)));
}

inline bool LocalTriangulator::split_containing_face() {
  const P2 o(0.0, 0.0);
  // The per-face tests only reject, so the cheap 2D ones go first; the first face passing all is split.
  for (std::size_t i = 0; i < faces_.size(); ++i) {
    const std::uint32_t f = faces_[i];
    const auto [a, b, c] = fs_.face(f);
    const P2& pa = verts_[corner_[3 * i]].p2;
    const P2& pb = verts_[corner_[3 * i + 1]].p2;
    const P2& pc = verts_[corner_[3 * i + 2]].p2;
    const double area = orient(pa, pb, pc);
    if (area <= kEps) continue;
    // An orientation below −1e-200 makes its barycentric coordinate negative (no underflow for areas below 1e100).
    const double oa = orient(pb, pc, o), ob = orient(pc, pa, o), oc = orient(pa, pb, o);
    if (oa < -1e-200 || ob < -1e-200 || oc < -1e-200) continue;
    const std::array<double, 3> bary{oa / area, ob / area, oc / area};
    if (*std::min_element(bary.begin(), bary.end()) < 0.0) continue;
    if (!normal_agrees(a, b, c)) continue;
    const Vec3 fn = face_normal(a, b, c).normalized();
    if (std::abs(fn.dot(pos_[v_] - pos_[a])) > 0.25 * s_.radius_m) continue;
    // v on (or very near) an edge: bary of the opposite corner ≈ 0.
    const int k = static_cast<int>(std::min_element(bary.begin(), bary.end()) - bary.begin());
    const std::array<VertexId, 3> t{a, b, c};
    const VertexId e0 = t[(k + 1) % 3], e1 = t[(k + 2) % 3], opp = t[k];
    if (bary[k] < 0.02) {
      if (fs_.face_with(e1, e0) == FaceStore::kNoFace) {  // border edge e0→e1: split the face in two
        fs_.replace(f, e0, v_, opp, scan_);
        const std::uint32_t g = fs_.add(v_, e1, opp, scan_);
        new_faces_.push_back(f);
        new_faces_.push_back(g);
        touched_ += 2;
        return true;
      }
    }
    fs_.replace(f, a, b, v_, scan_);
    new_faces_.push_back(f);
    new_faces_.push_back(fs_.add(b, c, v_, scan_));
    new_faces_.push_back(fs_.add(c, a, v_, scan_));
    touched_ += 3;
    return true;
  }
  return false;
}

inline void LocalTriangulator::fan() {
  const P2 o(0.0, 0.0);
  edges_.clear();  // local edges (2D) of the collected faces, once per face side; verts_ from collect_local_faces
  for (std::size_t i = 0; i < faces_.size(); ++i) {
    const auto& t = fs_.face(faces_[i]);
    for (int k = 0; k < 3; ++k)
      edges_.push_back({t[k], t[(k + 1) % 3], corner_[3 * i + k], corner_[3 * i + (k + 1) % 3], 0});
  }
  for (auto& e : edges_) e.side_o = side_class(orient(verts_[e.ia].p2, verts_[e.ib].p2, o));
  vis_.clear();
  std::size_t hint = 0;
  for (std::size_t i = 0; i < local_.size(); ++i) {
    const VertexId q = local_[i];
    const P2& pq = local_p2_[i];
    // Only the face edges exist yet (3 per face, edges_[3 i + k]); a face whose corners all lie on one side (or on
    // the line) of o→pq has no straddling edge, so its three edges are skipped at once. sd: the corners' side_class
    // of orient(o, pq, corner).
    auto blocks = [&](std::size_t i, const std::array<int, 3>& sd) {
      if (sd[0] * sd[1] >= 0 && sd[1] * sd[2] >= 0 && sd[2] * sd[0] >= 0) return false;
      for (int k = 0; k < 3; ++k) {
        const Edge2& e = edges_[3 * i + static_cast<std::size_t>(k)];
        // cross(o, pq, pa, pb): d1 = sd[k], d2 = sd[k + 1], d3 = side_o, d4 = orient(pa, pb, pq). An edge at q
        // has orient(o, pq, pq) = 0 exactly at that end, so it never counts (the old explicit skip).
        if (sd[k] * sd[(k + 1) % 3] < 0 && e.side_o * side_class(orient(verts_[e.ia].p2, verts_[e.ib].p2, pq)) < 0)
          return true;
      }
      return false;
    };
    auto face_blocks = [&](std::size_t i) {
      std::array<int, 3> sd{};
      for (std::size_t k = 0; k < 3; ++k) sd[k] = side_class(orient(o, pq, verts_[corner_[3 * i + k]].p2));
      return blocks(i, sd);
    };
    // "Some face blocks" does not depend on the order, so the likely blockers are tried first, on their own, before
    // the sides of all patch vertices: q's own faces (all in the patch; their far edges ring q, so they block an
    // interior q seen from outside its ring) and the face that blocked the last neighbour.
    bool blocked = false;
    for (std::uint32_t f : fs_.faces_of(q))
      if (face_blocks(patch_index(f))) {
        blocked = true;
        hint = patch_index(f);
        break;
      }
    if (!blocked && hint < faces_.size()) blocked = face_blocks(hint);
    if (!blocked) {
      side_.resize(verts_.size());
      for (std::size_t j = 0; j < verts_.size(); ++j) side_[j] = side_class(orient(o, pq, verts_[j].p2));
      for (std::size_t i = 0; i < faces_.size() && !blocked; ++i)
        if (i != hint && blocks(i, {side_[corner_[3 * i]], side_[corner_[3 * i + 1]], side_[corner_[3 * i + 2]]})) {
          blocked = true;
          hint = i;
        }
    }
    if (!blocked) vis_.push_back({q, std::atan2(pq.y(), pq.x()), pq});
  }
  if (vis_.size() < 2) return;
  std::sort(vis_.begin(), vis_.end(), [](const FanCandidate& x, const FanCandidate& y) { return x.angle < y.angle; });
  // Neighbours in (almost) the same direction: the nearer one hides the farther.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < vis_.size(); ++i) {
    if (kept > 0 && vis_[i].angle - vis_[kept - 1].angle < kSameDirectionRad) {
      if (vis_[i].p2.squaredNorm() < vis_[kept - 1].p2.squaredNorm()) vis_[kept - 1] = vis_[i];
      continue;
    }
    vis_[kept++] = vis_[i];
  }
  vis_.resize(kept);
  if (vis_.size() > 2 && vis_.back().angle - vis_.front().angle > 2.0 * std::numbers::pi - kSameDirectionRad) {
    if (vis_.back().p2.squaredNorm() < vis_.front().p2.squaredNorm()) vis_.front() = vis_.back();
    vis_.pop_back();
  }
  if (vis_.size() < 2) return;
  const std::size_t m = vis_.size();
  for (std::size_t i = 0; i < m; ++i) {
    const FanCandidate& cp = vis_[i];
    const FanCandidate& cq = vis_[(i + 1) % m];
    if (cp.id == cq.id) continue;
    double gap = cq.angle - cp.angle;
    if (gap <= 0.0) gap += 2.0 * std::numbers::pi;
    if (gap <= 1e-9 || gap > s_.max_fan_gap_rad) continue;
    try_fan_triangle(cp, cq);
  }
}

inline void LocalTriangulator::try_fan_triangle(const FanCandidate& cp, const FanCandidate& cq) {
  const P2 o(0.0, 0.0);
  const VertexId p = cp.id, q = cq.id;
  const P2& pp = cp.p2;
  const P2& pq = cq.p2;
  if (orient(o, pp, pq) <= kEps) return;
  if ((pos_[p] - pos_[q]).norm() > s_.radius_m) return;
  if (fs_.face_with(p, q) != FaceStore::kNoFace || fs_.face_with(v_, p) != FaceStore::kNoFace ||
      fs_.face_with(q, v_) != FaceStore::kNoFace)
    return;
  if (!normal_agrees(v_, p, q) || !angles_at_least(v_, p, q, fan_angle_)) return;
  side_.resize(verts_.size());
  for (std::size_t j = 0; j < verts_.size(); ++j) side_[j] = side_class(orient(pp, pq, verts_[j].p2));
  for (const auto& e : edges_) {
    // cross(pp, pq, pa, pb); an edge at p or q has side class 0 there (exact zero), so it never counts.
    const P2& pa = verts_[e.ia].p2;
    const P2& pb = verts_[e.ib].p2;
    if (side_[e.ia] * side_[e.ib] < 0 && side_class(orient(pa, pb, pp)) * side_class(orient(pa, pb, pq)) < 0) return;
  }
  auto inside = [&](const P2& x) {
    return orient(o, pp, x) > kEps && orient(pp, pq, x) > kEps && orient(pq, o, x) > kEps;
  };
  for (std::size_t i = 0; i < local_.size(); ++i)
    if (local_[i] != p && local_[i] != q && inside(local_p2_[i])) return;
  // Every patch vertex starts a patch edge; v's edges are excluded as in the edge list form.
  for (std::size_t j = 0; j < verts_.size(); ++j) {
    const VertexId a = verts_[j].id;
    if (a != p && a != q && a != v_ && side_[j] > 0 && orient(o, pp, verts_[j].p2) > kEps &&
        orient(pq, o, verts_[j].p2) > kEps)
      return;
  }
  new_faces_.push_back(fs_.add(v_, p, q, scan_));
  const std::uint32_t iv = vert_index(v_, o), ip = vert_index(p, pp), iq = vert_index(q, pq);
  const std::array<std::uint32_t, 3> ix{iv, ip, iq};
  const std::array<VertexId, 3> id{v_, p, q};
  for (int k = 0; k < 3; ++k) {
    Edge2 e{id[k], id[(k + 1) % 3], ix[k], ix[(k + 1) % 3], 0};
    e.side_o = side_class(orient(verts_[e.ia].p2, verts_[e.ib].p2, o));
    edges_.push_back(e);
  }
  ++touched_;
}

inline void LocalTriangulator::legalize() {
  int flips = 0;
  while (!new_faces_.empty()) {
    const std::uint32_t f = new_faces_.back();
    new_faces_.pop_back();
    if (flips >= s_.max_flips) continue;
    auto t = fs_.face(f);
    int k = 0;
    while (k < 3 && t[k] != v_) ++k;
    if (k == 3) continue;
    const VertexId p = t[(k + 1) % 3], q = t[(k + 2) % 3];
    const std::uint32_t g = fs_.face_with(q, p);
    if (g == FaceStore::kNoFace) continue;
    const VertexId r = fs_.opposite(g, q, p);
    if (r == v_ || r == kNoVertex || fs_.has_edge(v_, r)) continue;
    if ((pos_[r] - pos_[v_]).norm() > s_.radius_m) continue;
    if (!normal_agrees(q, p, r)) continue;
    const P2 o(0.0, 0.0), pp = project(p), pq = project(q), pr = project(r);
    if (orient(o, pp, pr) <= kEps || orient(o, pr, pq) <= kEps) continue;  // quad not convex
    if (incircle(o, pp, pq, pr) <= kEps * kEps) continue;
    fs_.replace(f, v_, p, r, scan_);
    fs_.replace(g, v_, r, q, scan_);
    new_faces_.push_back(f);
    new_faces_.push_back(g);
    ++flips;
    ++touched_;
  }
}

}  // namespace nbs::detail
