#pragma once
/// \file
/// Localized triangulation of one new vertex (Sec. 3.3.1, "mesh generation" stage): the R_m neighbourhood is
/// projected onto the tangent plane of the new vertex v and the patch around v is re-triangulated:
///  - v inside a projected face: the face is split (1→3, or 1→2 when v lies on a border edge);
///  - otherwise v is joined to a fan of its visible neighbours (consecutive in angle around v), where a fan
///    triangle must not cross an existing edge, contain a neighbour, reuse a directed edge, or be a sliver;
///  - then edges opposite v are flipped while the local Delaunay criterion (in v's tangent plane) asks for it;
///  - finally border loops and notches that fit inside R_m (gaps the fan left) are closed (close_gaps).
/// Every step keeps: a directed edge belongs to at most one face, no face repeats a vertex set.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "nbs/mesh/detail/face_store.hpp"

namespace nbs::detail {

struct TriangulationSettings {
  double radius_m = 0.006;        ///< R_m.
  double min_normal_dot = 0.5;    ///< faces / neighbours whose normal differs by more than 60° are not joined.
  double max_fan_gap_rad = 2.8;   ///< a fan triangle spans at most ≈160° at v.
  double min_angle_rad = 0.12;    ///< ≈7°: no fan triangle with a smaller interior angle.
  int max_fan_neighbours = 16;    ///< nearest neighbours considered for the fan.
  int max_flips = 64;             ///< per inserted vertex.
  int max_gap_edges = 12;         ///< border loops / notches up to this many edges are closed (close_gaps).
  double min_notch_ratio = 1.3;   ///< a notch is closed if its border is this many times longer than its chord.
};

class LocalTriangulator {
  using P2 = Eigen::Vector2d;
  struct FanCandidate {
    VertexId id;
    double angle;
    P2 p2;
  };
  struct Vert2 {
    VertexId id;
    P2 p2;  ///< projection into v's tangent plane, in units of R_m.
  };
  struct Edge2 {
    VertexId a, b;
    std::uint32_t ia, ib;  ///< indices of a and b in verts_.
    int side_o;            ///< side class of orient(pa, pb, o): where v's projection o lies relative to the edge.
  };

public:
  LocalTriangulator(FaceStore& faces, const std::vector<Vec3>& positions, const std::vector<Vec3>& normals)
      : fs_(faces), pos_(positions), nrm_(normals) {}

  /// Triangulates the meshless vertex v with unit normal nrm_[v]. `neighbours`: vertices with normals within R_m
  /// of v, nearest first. Returns the number of faces created or changed.
  int insert(VertexId v, std::span<const VertexId> neighbours, const TriangulationSettings& s, std::uint32_t scan) {
    v_ = v;
    s_ = s;
    scan_ = scan;
    n_ = nrm_[v];
    inv_r_ = 1.0 / s.radius_m;
    u_ = n_.unitOrthogonal();
    w_ = n_.cross(u_);
    touched_ = 0;
    set_angle_bound(fan_angle_, s.min_angle_rad);
    set_angle_bound(notch_angle_, 0.25 * s.min_angle_rad);
    local_.clear();
    for (VertexId q : neighbours) {
      if (static_cast<int>(local_.size()) >= s.max_fan_neighbours) break;
      if (fan_neighbour(v, q, s)) local_.push_back(q);
    }
    if (local_.empty()) return 0;
    local_p2_.clear();
    for (VertexId q : local_) local_p2_.push_back(project(q));
    collect_local_faces();
    if (!split_containing_face()) fan();
    legalize();
    close_gaps();
    return touched_;
  }

  /// True if insert(v, ...) would take the meshed vertex q into v's fan patch (the first max_fan_neighbours such
  /// neighbours are taken): normals within acos(min_normal_dot), q within 30° of v's tangent plane.
  [[nodiscard]] bool fan_neighbour(VertexId v, VertexId q, const TriangulationSettings& s) const {
    const Vec3 d = pos_[q] - pos_[v];
    return !(nrm_[q].dot(nrm_[v]) < s.min_normal_dot || std::abs(d.dot(nrm_[v])) > 0.5 * d.norm());
  }

  /// Heap bytes of the per-vertex marks and border memo (20 B per vertex) and the face marks (4 B per face); the other
  /// scratch buffers are bounded by the patch size.
  [[nodiscard]] std::size_t memory_bytes() const {
    return (mark_.capacity() + slot_.capacity() + face_mark_.capacity()) * sizeof(std::uint32_t) +
           border_.capacity() * sizeof(BorderMemo);
  }

private:
  static constexpr double kEps = 1e-12;
  static constexpr double kSameDirectionRad = 0.035;  // 2°
  /// Threshold of angles_at_least(); `fast` (0 < thr < 1.5) enables the tangent pre-test.
  struct AngleBound {
    double thr = -1.0, tan_lo = 0.0, tan_hi = 0.0;
    bool fast = false;
  };
  static void set_angle_bound(AngleBound& b, double thr) {
    if (thr == b.thr) return;
    b.thr = thr;
    b.fast = thr > 0.0 && thr < 1.5;
    const double t = b.fast ? std::tan(thr) : 0.0;
    b.tan_lo = t * (1.0 - 1e-6);
    b.tan_hi = t * (1.0 + 1e-6);
  }

  [[nodiscard]] P2 project(VertexId q) const {
    const Vec3 d = (pos_[q] - pos_[v_]) * inv_r_;
    return {d.dot(u_), d.dot(w_)};
  }
  [[nodiscard]] static double orient(const P2& a, const P2& b, const P2& c) {
    return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  }
  /// True if segments ab and cd cross at a point interior to both (touching/collinear does not count).
  [[nodiscard]] static bool cross(const P2& a, const P2& b, const P2& c, const P2& d) {
    const double d1 = orient(a, b, c), d2 = orient(a, b, d);
    if (!((d1 > kEps && d2 < -kEps) || (d1 < -kEps && d2 > kEps))) return false;
    const double d3 = orient(c, d, a), d4 = orient(c, d, b);
    return (d3 > kEps && d4 < -kEps) || (d3 < -kEps && d4 > kEps);
  }
  /// > 0 if d is strictly inside the circumcircle of the counter-clockwise triangle abc.
  [[nodiscard]] static double incircle(const P2& a, const P2& b, const P2& c, const P2& d) {
    const P2 ad = a - d, bd = b - d, cd = c - d;
    const double a2 = ad.squaredNorm(), b2 = bd.squaredNorm(), c2 = cd.squaredNorm();
    return ad.x() * (bd.y() * c2 - b2 * cd.y()) - ad.y() * (bd.x() * c2 - b2 * cd.x()) +
           a2 * (bd.x() * cd.y() - bd.y() * cd.x());
  }
  [[nodiscard]] Vec3 face_normal(VertexId a, VertexId b, VertexId c) const {
    return (pos_[b] - pos_[a]).cross(pos_[c] - pos_[a]);
  }
  [[nodiscard]] bool normal_agrees(VertexId a, VertexId b, VertexId c) const {
    const Vec3 fn = face_normal(a, b, c);
    const double len = fn.norm();
    return len > 0.0 && fn.dot(n_) >= s_.min_normal_dot * len;
  }
  /// min_angle(a, b, c) >= thr, with atan2 only for corner angles within a relative 1e-6 of tan(thr) (tan_lo/tan_hi,
  /// set by set_angle_bound); a NaN angle is skipped as by the std::min of min_angle.
  [[nodiscard]] bool angles_at_least(VertexId a, VertexId b, VertexId c, const AngleBound& t) const {
    if (!t.fast) return min_angle(a, b, c) >= t.thr;
    const std::array<Vec3, 3> p{pos_[a], pos_[b], pos_[c]};
    for (int k = 0; k < 3; ++k) {
      const Vec3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
      const double sn = e1.cross(e2).norm(), cs = e1.dot(e2);
      if (cs > 1e-200) {
        if (sn >= cs * t.tan_hi) continue;
        if (sn < cs * t.tan_lo) return false;
      } else if (cs < 0.0 && sn >= 0.0) {
        continue;  // obtuse: atan2 ≥ π/2 > thr
      }
      if (std::atan2(sn, cs) < t.thr) return false;
    }
    return true;
  }
  [[nodiscard]] double min_angle(VertexId a, VertexId b, VertexId c) const {
    const std::array<Vec3, 3> p{pos_[a], pos_[b], pos_[c]};
    double m = std::numbers::pi;
    for (int k = 0; k < 3; ++k) {
      const Vec3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
      m = std::min(m, std::atan2(e1.cross(e2).norm(), e1.dot(e2)));
    }
    return m;
  }

  void collect_local_faces() {
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

  /// Index in faces_ of the collected face f.
  [[nodiscard]] std::size_t patch_index(std::uint32_t f) const { return face_mark_[f] - face_base_; }

  /// Case "inside": v projects into a compatible local face → split it. Returns true if it did.
  bool split_containing_face() {
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

  /// Index of vertex q in verts_ (the distinct edge ends of the fan patch), adding it with projection `p2` if new.
  std::uint32_t vert_index(VertexId q, const P2& p2) {
    if (!marked(q)) {
      set_mark(q, static_cast<std::uint32_t>(verts_.size()));
      verts_.push_back({q, p2});
    }
    return slot_[q];
  }
  /// Marks q in the current generation with `value`.
  void set_mark(VertexId q, std::uint32_t value) {
    if (mark_.size() <= q) {
      mark_.resize(pos_.size() > q ? pos_.size() : std::size_t{q} + 1, 0);
      slot_.resize(mark_.size(), 0);
    }
    mark_[q] = gen_;
    slot_[q] = value;
  }
  [[nodiscard]] bool marked(VertexId q) const { return q < mark_.size() && mark_[q] == gen_; }
  /// Starts a new generation of the vertex marks (mark_ == gen_ means "set in this generation").
  void next_generation() {
    if (++gen_ == 0) {  // wrapped: forget every old mark
      std::fill(mark_.begin(), mark_.end(), 0u);
      gen_ = 1;
    }
  }

  /// Case "outside": fan of visible neighbours.
  /// The patch's directed edges (once per face side) are kept as indices into verts_, the distinct edge ends with
  /// their projections, so an orientation test of a segment against every patch vertex is computed once per vertex
  /// and shared by the edges meeting there; every test is the same floating-point expression as the plain
  /// segment-crossing test `cross()`, so the result does not depend on this bookkeeping.
  void fan() {
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

  /// +1 / −1 when an orientation value is beyond ±kEps, else 0. Two values straddle strictly (the test of `cross()`)
  /// exactly when the product of their classes is negative.
  [[nodiscard]] static int side_class(double d) { return d > kEps ? 1 : (d < -kEps ? -1 : 0); }

  /// Adds fan triangle (v, p, q) unless it crosses a patch edge, contains a local vertex or patch vertex, reuses a
  /// directed edge, disagrees with v's normal or is a sliver. All tests only reject, so their order is free.
  void try_fan_triangle(const FanCandidate& cp, const FanCandidate& cq) {
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

  /// next_border(x), memoised per vertex until x's faces change (FaceStore::version).
  /// border_ covers every vertex (close_gaps sizes it).
  [[nodiscard]] VertexId next_border_cached(VertexId x) {
    const BorderMemo& m = border_[x];
    if (m.valid && m.version == fs_.version(x)) return m.next;
    return update_border_memo(x);
  }
  [[gnu::noinline]] VertexId update_border_memo(VertexId x) {
    border_[x] = {next_border(x), fs_.version(x), true};
    return border_[x].next;
  }
  /// Border edge x→y (its face on the left, none on the right) leaving x, first found; kNoVertex if none.
  /// A face holding y→x also holds x, so "no face on the right" is checked among x's own faces: y is not the
  /// predecessor of x in any of them.
  [[nodiscard]] VertexId next_border(VertexId x) const {
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
  /// Closes the gaps the fan left: Bodenmüller joins every pair of vertices within R_m, so a border loop or a border
  /// notch that fits inside R_m is a triangulation gap, not a hole. From v and each neighbour the border is walked
  /// (faces on the left, the gap on the right) for at most `max_gap_edges` edges; a chain x = c0 → … → ck is filled
  ///  - when it closes (ck = x): a small loop;
  ///  - when |ck − x| ≤ R_m, the chord ck–x is not an edge yet and the chain is at least `min_notch_ratio` times
  ///    longer than the chord: a notch cut into the mesh (a gently curved hole rim is shorter and stays open).
  /// The polygon must be simple and clockwise in v's tangent plane (the gap lies on the right of the border), contain
  /// no other local vertex, and be ear-clippable with new edges ≤ R_m and faces agreeing with v's normal; all faces
  /// are checked before any is added, so a gap is either filled completely or left alone.
  void close_gaps() {
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

  bool close_gap_from(VertexId x) {
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

  /// The polygon chain_ is clockwise in projection (the gap is on the right of the border walk): the chain's shoelace
  /// sum (summed in walk order by close_gap_from) plus the closing edge.
  [[nodiscard]] bool clockwise() const {
    const P2 &last = chain_p2_[chain_n_ - 1], &first = chain_p2_[0];
    return !(chain_area2_ + (last.x() * first.y() - last.y() * first.x()) >= -kEps);
  }
  /// Ear-clips the polygon chain_ (closed by the chord back to chain_[0] unless `closed`). See close_gaps().
  bool fill_polygon(bool closed) {
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
  /// A fill face of a closed loop only has to be counter-clockwise in v's tangent plane (checked by the caller): the
  /// gaps are often near-collinear slivers whose 3D normal is meaningless. Notch faces must also agree with v's
  /// normal and not be slivers. Never the reverse of an existing face (the 3-edge "loop" around a lone triangle's
  /// back would close it into a two-face pillow).
  [[nodiscard]] bool gap_face_ok(VertexId a, VertexId b, VertexId c, bool closed) const {
    return (closed || (normal_agrees(a, b, c) && angles_at_least(a, b, c, notch_angle_))) &&
           fs_.face_with(a, b) == FaceStore::kNoFace && fs_.face_with(b, c) == FaceStore::kNoFace &&
           fs_.face_with(c, a) == FaceStore::kNoFace && fs_.left_vertex(b, a) != c;
  }

  /// Flips edges opposite v while the opposite vertex lies inside the circumcircle (Lawson), bounded by max_flips.
  void legalize() {
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


  FaceStore& fs_;
  const std::vector<Vec3>& pos_;
  const std::vector<Vec3>& nrm_;
  VertexId v_ = kNoVertex;
  TriangulationSettings s_;
  std::uint32_t scan_ = 0;
  Vec3 n_ = Vec3::UnitZ(), u_ = Vec3::UnitX(), w_ = Vec3::UnitY();
  double inv_r_ = 1.0;
  AngleBound fan_angle_, notch_angle_;  ///< min_angle_rad and 0.25 min_angle_rad (gap_face_ok)
  int touched_ = 0;
  std::vector<VertexId> local_;
  std::vector<P2> local_p2_;
  std::vector<std::uint32_t> faces_;
  std::vector<Edge2> edges_;
  std::vector<Vert2> verts_;
  std::vector<int> side_;                     ///< side_class of one orientation test per verts_ entry.
  std::vector<std::uint32_t> corner_;        ///< verts_ index of corner k of faces_[i] at 3 i + k.
  /// Per vertex: generation of its mark and the marked value, the verts_ index (collect_local_faces, fan). A vertex
  /// is marked iff mark_[v] == gen_.
  std::vector<std::uint32_t> mark_, slot_;
  std::uint32_t gen_ = 0;
  /// Per face: face_base_ + its index in faces_ once collected by collect_local_faces(); below face_base_: not collected.
  std::vector<std::uint32_t> face_mark_;
  std::uint32_t face_base_ = 0;
  struct BorderMemo {
    VertexId next = kNoVertex;  ///< next_border() of the vertex
    std::uint32_t version = 0;  ///< FaceStore::version() it was computed at
    bool valid = false;
  };
  std::vector<BorderMemo> border_;  ///< per vertex
  std::vector<FanCandidate> vis_;
  std::vector<std::uint32_t> new_faces_;
  std::vector<VertexId> chain_;  ///< the border walk of close_gap_from: chain_n_ entries (chain_p2_: their projections)
  std::size_t chain_n_ = 0;
  std::size_t chain_checked_ = 0;  ///< the first chain_checked_ chain edges are pairwise checked (fill_polygon)
  bool chain_crossed_ = false;     ///< two non-adjacent chain edges cross
  std::vector<P2> chain_p2_;
  double chain_area2_ = 0.0;  ///< Σ of x_i y_{i+1} − y_i x_{i+1} over the edges of chain_p2_, in order.
  std::vector<std::uint32_t> ring_;
  std::vector<std::array<VertexId, 3>> ears_;
};

}  // namespace nbs::detail
