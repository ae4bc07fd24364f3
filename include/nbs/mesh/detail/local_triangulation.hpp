// SPDX-License-Identifier: BSD-3-Clause
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
/// This file holds the settings, the class with its small geometric helpers and per-call marks; the steps that place
/// v are defined in local_triangulation_patch.hpp, the gap closing in local_triangulation_gaps.hpp (both included
/// at the end). Not thread-safe: one triangulator per mesh, its scratch buffers are reused by every insert().

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

  // Placing v (local_triangulation_patch.hpp).
  void collect_local_faces();

  /// Index in faces_ of the collected face f.
  [[nodiscard]] std::size_t patch_index(std::uint32_t f) const { return face_mark_[f] - face_base_; }

  /// Case "inside": v projects into a compatible local face → split it. Returns true if it did.
  bool split_containing_face();

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
  void fan();

  /// +1 / −1 when an orientation value is beyond ±kEps, else 0. Two values straddle strictly (the test of `cross()`)
  /// exactly when the product of their classes is negative.
  [[nodiscard]] static int side_class(double d) { return d > kEps ? 1 : (d < -kEps ? -1 : 0); }

  /// Adds fan triangle (v, p, q) unless it crosses a patch edge, contains a local vertex or patch vertex, reuses a
  /// directed edge, disagrees with v's normal or is a sliver. All tests only reject, so their order is free.
  void try_fan_triangle(const FanCandidate& cp, const FanCandidate& cq);

  // Gap closing (local_triangulation_gaps.hpp, but for the border memo and the two short tests).
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
  [[nodiscard]] VertexId next_border(VertexId x) const;
  /// Closes the gaps the fan left: Bodenmüller joins every pair of vertices within R_m, so a border loop or a border
  /// notch that fits inside R_m is a triangulation gap, not a hole. From v and each neighbour the border is walked
  /// (faces on the left, the gap on the right) for at most `max_gap_edges` edges; a chain x = c0 → … → ck is filled
  ///  - when it closes (ck = x): a small loop;
  ///  - when |ck − x| ≤ R_m, the chord ck–x is not an edge yet and the chain is at least `min_notch_ratio` times
  ///    longer than the chord: a notch cut into the mesh (a gently curved hole rim is shorter and stays open).
  /// The polygon must be simple and clockwise in v's tangent plane (the gap lies on the right of the border), contain
  /// no other local vertex, and be ear-clippable with new edges ≤ R_m and faces agreeing with v's normal; all faces
  /// are checked before any is added, so a gap is either filled completely or left alone.
  void close_gaps();

  bool close_gap_from(VertexId x);

  /// The polygon chain_ is clockwise in projection (the gap is on the right of the border walk): the chain's shoelace
  /// sum (summed in walk order by close_gap_from) plus the closing edge.
  [[nodiscard]] bool clockwise() const {
    const P2 &last = chain_p2_[chain_n_ - 1], &first = chain_p2_[0];
    return !(chain_area2_ + (last.x() * first.y() - last.y() * first.x()) >= -kEps);
  }
  /// Ear-clips the polygon chain_ (closed by the chord back to chain_[0] unless `closed`). See close_gaps().
  bool fill_polygon(bool closed);
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
  void legalize();  // local_triangulation_patch.hpp


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

#include "nbs/mesh/detail/local_triangulation_gaps.hpp"
#include "nbs/mesh/detail/local_triangulation_patch.hpp"
