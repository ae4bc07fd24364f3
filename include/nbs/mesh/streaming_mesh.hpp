// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// StreamingMesh: the default EdgeMesh, built point by point from the sensor stream (Sec. 3.3.1, after
/// Bodenmüller 2009). Each point passes three stages:
///  1. density limitation: dropped if closer than R_r to a stored point (so no two vertices are closer than R_r),
///     optionally also within R_r across the line of sight of a stored point facing the same side (density_depth_m);
///  2. normal estimation: weighted PCA over the R_n ball, oriented against the line of sight; a point whose normal is
///     not robust (too few neighbours, collinear or non-flat neighbourhood) is kept pending and retried when new
///     points arrive within R_n;
///  3. localized triangulation of the R_m ball in the tangent plane of the new vertex (detail/local_triangulation),
///     optionally with the vertex first moved onto its PCA plane (`project_vertices`).
/// Neighbour queries use a spatial hash with cells of R_m / 2; the density limitation bounds the points per cell,
/// so the cost per point does not grow with the model. Points outside the bounding box of the unknown area are
/// dropped (pass-through filter, Sec. 4.1). Faces created or changed since `begin_scan()` form M_cur (Sec. 4.2).
///
/// Colour (Sec. 5.3): a point inserted with a colour (insert(p, los, colour), or integrate() of a Scan with colours)
/// adds it to one stored vertex — the vertex it creates, or, when the density limitation drops it, the stored point
/// that rejected it (within R_r of the point, or with density_depth_m within R_r of its line of sight; the first found,
/// not necessarily the nearest). color(v) is the rounded per-channel mean of all colours added to v. Rule chosen
/// because the density limitation keeps only the first of the measurements within R_r of a vertex: the mean uses all
/// of them (it averages out per-measurement noise and blurs colour edges by at most about R_r), while picking one
/// measurement (e.g. the best incidence) would keep its noise. The colour storage is allocated on the first coloured
/// point: a mesh fed only scans without colour pays nothing.
///
/// Units: metres, world frame. Not thread-safe; const members may be called concurrently when no thread writes.
///
/// The settings and counters are in streaming_mesh_settings.hpp; insert() and its normal and triangulation stages
/// are defined in detail/streaming_mesh_impl.hpp (included at the end).

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <numbers>
#include <span>
#include <vector>

#include "nbs/core/parameters.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/mesh/detail/ball_moments.hpp"
#include "nbs/mesh/detail/face_store.hpp"
#include "nbs/mesh/detail/local_triangulation.hpp"
#include "nbs/mesh/detail/normal_estimation.hpp"
#include "nbs/mesh/detail/spatial_hash.hpp"
#include "nbs/mesh/mesh_concept.hpp"
#include "nbs/mesh/streaming_mesh_settings.hpp"

namespace nbs {

class StreamingMesh {
public:
  explicit StreamingMesh(const Parameters& p = {}, const Aabb& unknown_area = {})
      : StreamingMesh(StreamingMeshSettings::from(p, unknown_area)) {}
  explicit StreamingMesh(const StreamingMeshSettings& s)
      : settings_((s.validate(), s)),
        grid_(s.hash_cell_m()),
        tri_(faces_, s.project_vertices ? surf_ : pos_, nrm_) {
    tri_settings_.radius_m = s.mesh_radius_m;
    tri_settings_.min_normal_dot = s.min_normal_dot;
  }
  StreamingMesh(const StreamingMesh&) = delete;  // the triangulator borrows members
  StreamingMesh& operator=(const StreamingMesh&) = delete;

  // --- Stream input ---------------------------------------------------------------------------------------------
  /// Starts a new scan: M_cur becomes empty; `sensor` (T_WS of the scan, e.g. its first profile) is remembered
  /// for boundary detection. Throws InvalidArgument, changing nothing, unless `sensor` is a rigid transform.
  void begin_scan(const Pose& sensor = Pose::Identity()) {
    validate_pose(sensor, "StreamingMesh::begin_scan sensor pose");
    ++scan_;
    sensor_ = sensor;
  }

  /// Inserts one measured point `p` (world, m) seen along `line_of_sight` (sensor → point, any positive length).
  /// Throws InvalidArgument, changing nothing, if `p` or `line_of_sight` is not finite, the line of sight has no
  /// length (≤ 1e-12), or `p` lies beyond ±settings().max_abs_coordinate_m() on an axis.
  InsertResult insert(const Vec3& p, const Vec3& line_of_sight);
  /// insert(p, line_of_sight) of a point measured with colour `color`, which is then added to the vertex the point
  /// created or, if it was too close, to the stored point that rejected it (see the file comment). The same errors.
  InsertResult insert(const Vec3& p, const Vec3& line_of_sight, const Rgb& color);

  /// Throws InvalidArgument naming the first offending index and value unless integrate(scan) can take every point:
  /// Scan::validate() holds, every point lies within ±settings().max_abs_coordinate_m() on each axis (whether or not
  /// the pass-through box would drop it) and differs from its sensor origin. Changes nothing.
  void check_scan(const Scan& scan) const {
    scan.validate();
    const double limit = settings_.max_abs_coordinate_m();
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      const Vec3& p = scan.points[i];
      detail::require(grid_.in_range(p), "scan point ", i, " (", p.transpose(), ") lies beyond ±", limit,
                      " m on an axis, the coordinate range of the mesh's spatial hash at mesh_radius_m = ",
                      settings_.mesh_radius_m, " m");
      detail::require(p != scan.origin(i), "scan point ", i, " (", p.transpose(), ") coincides with its sensor origin");
    }
  }

  /// check_scan(scan), then — unless the scan is empty, which changes nothing — begin_scan(its first profile pose)
  /// and insert() every point with its line of sight (and its colour, if the scan has colours). All or nothing: a
  /// scan check_scan rejects changes nothing. Returns the points meshed.
  std::size_t integrate(const Scan& scan) {
    check_scan(scan);
    if (scan.empty()) return 0;
    begin_scan(scan.profile_poses.front());
    std::size_t meshed = 0;
    const bool colored = scan.has_colors();
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      const InsertResult r = colored ? insert(scan.points[i], scan.line_of_sight(i), scan.colors[i])
                                     : insert(scan.points[i], scan.line_of_sight(i));
      meshed += r == InsertResult::meshed ? 1 : 0;
    }
    return meshed;
  }

  // --- EdgeMesh concept -----------------------------------------------------------------------------------------
  [[nodiscard]] std::size_t vertex_count() const { return pos_.size(); }
  /// The vertex: the measured point, moved onto its PCA plane once it has a robust normal (`project_vertices`).
  [[nodiscard]] const Vec3& position(VertexId v) const {
    return settings_.project_vertices ? surf_[v] : pos_[v];
  }
  /// The measured point as stored by the density limitation (no two closer than R_r).
  [[nodiscard]] const Vec3& stored_position(VertexId v) const { return pos_[v]; }
  /// Unit normal pointing to the sensor side; zero while the vertex is pending (no robust normal).
  [[nodiscard]] const Vec3& normal(VertexId v) const { return nrm_[v]; }
  [[nodiscard]] std::size_t face_count() const { return faces_.face_count(); }
  [[nodiscard]] VertexId left_vertex(VertexId a, VertexId b) const { return faces_.left_vertex(a, b); }
  [[nodiscard]] MeshFace face(std::size_t f) const {
    const auto& t = faces_.face(static_cast<std::uint32_t>(f));
    return {t[0], t[1], t[2]};
  }
  /// Bit k set iff edge (t[k], t[k+1]) of face f has no twin (KnowsFaceBorders); up to date after every insert.
  [[nodiscard]] unsigned border_mask(std::size_t f) const { return faces_.border_mask(static_cast<std::uint32_t>(f)); }
  template <class F>
  void for_each_face(F&& f) const {
    for (std::uint32_t i = 0; i < faces_.face_count(); ++i) {
      const auto& t = faces_.face(i);
      f(MeshFace{t[0], t[1], t[2]});
    }
  }
  /// Every undirected edge once, directed from the smaller to the larger vertex id: in face order, a face's edges in
  /// order, each edge from the face that holds it as a→b with a < b, or from its only face.
  template <class F>
  void for_each_edge(F&& f) const {
    for (std::uint32_t i = 0; i < faces_.face_count(); ++i) {
      const auto& t = faces_.face(i);
      const unsigned border = faces_.border_mask(i);
      for (int k = 0; k < 3; ++k) {
        const VertexId a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
        const bool no_twin = (border >> k) & 1u;
        if (a < b)
          f(MeshEdge{a, b, c, no_twin ? kNoVertex : faces_.left_vertex(b, a)});
        else if (no_twin)
          f(MeshEdge{b, a, kNoVertex, c});
      }
    }
  }
  /// The border edges (Eq. 4.1) of for_each_edge, in its order, read off per-face masks (no adjacency lookups).
  template <class F>
  void for_each_border_edge(F&& f) const {
    for (std::uint32_t i = 0; i < faces_.face_count(); ++i) {
      const unsigned border = faces_.border_mask(i);
      if (border == 0) continue;
      const auto& t = faces_.face(i);
      for (int k = 0; k < 3; ++k) {
        if (!((border >> k) & 1u)) continue;
        const VertexId a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
        f(a < b ? MeshEdge{a, b, c, kNoVertex} : MeshEdge{b, a, kNoVertex, c});
      }
    }
  }
  /// The faces created or changed in the current scan (M_cur's faces), in for_each_face order.
  template <class F>
  void for_each_current_face(F&& f) const {
    for (std::uint32_t i = 0; i < faces_.face_count(); ++i) {
      if (faces_.face_scan(i) != scan_) continue;
      const auto& t = faces_.face(i);
      f(MeshFace{t[0], t[1], t[2]});
    }
  }
  /// True if a triangle of `e` was created or changed in the current scan (e ∈ M_cur, Eq. 4.2).
  [[nodiscard]] bool in_current_scan(const MeshEdge& e) const {
    for (VertexId c : {e.left, e.right}) {
      if (c == kNoVertex) continue;
      const std::uint32_t f = c == e.left ? faces_.face_with(e.a, e.b) : faces_.face_with(e.b, e.a);
      if (f != detail::FaceStore::kNoFace && faces_.face_scan(f) == scan_) return true;
    }
    return false;
  }

  // --- Colour (ColoredMesh) -----------------------------------------------------------------------------------
  /// True once a point with colour was inserted.
  [[nodiscard]] bool has_colors() const { return !color_count_.empty(); }
  /// Number of colours added to vertex v (0: none, e.g. v was stored from a point without colour).
  [[nodiscard]] std::uint32_t color_count(VertexId v) const { return v < color_count_.size() ? color_count_[v] : 0; }
  /// Fused colour of v: the rounded per-channel mean of the colours added to it; black if none was.
  [[nodiscard]] Rgb color(VertexId v) const {
    const std::uint32_t n = color_count(v);
    if (n == 0) return {0, 0, 0};
    Rgb c{};
    for (std::size_t k = 0; k < 3; ++k) c[k] = static_cast<std::uint8_t>((color_sum_[v][k] + n / 2) / n);
    return c;
  }

  // --- Analysis -------------------------------------------------------------------------------------------------
  /// True once v has a robust normal (it is a mesh vertex, possibly without triangles yet).
  [[nodiscard]] bool has_normal(VertexId v) const { return nrm_[v].squaredNorm() > 0.0; }
  /// True if v belongs to at least one triangle.
  [[nodiscard]] bool in_triangle(VertexId v) const { return faces_.has_faces(v); }
  /// N_act: stored points within R_n of v, v included (Eq. 4.24).
  [[nodiscard]] std::uint32_t neighbour_count(VertexId v) const { return count_[v]; }
  /// N_max = √2 π R_n² / R_r² (Eq. 4.25).
  [[nodiscard]] double max_neighbours() const {
    const double q = settings_.normal_radius_m / settings_.reduction_radius_m;
    return std::numbers::sqrt2 * std::numbers::pi * q * q;
  }
  /// Relative density d(v) = N_act / N_max ∈ [0, 1] (Eq. 4.24, clamped).
  [[nodiscard]] double relative_density(VertexId v) const {
    return std::min(1.0, static_cast<double>(count_[v]) / max_neighbours());
  }
  /// Index of the current scan (0 before the first begin_scan) and its sensor pose.
  [[nodiscard]] std::uint32_t current_scan() const { return scan_; }
  [[nodiscard]] const Pose& current_sensor() const { return sensor_; }
  [[nodiscard]] const StreamingStats& stats() const { return stats_; }
  [[nodiscard]] const StreamingMeshSettings& settings() const { return settings_; }
  /// Heap + object bytes (capacity-based estimate).
  [[nodiscard]] std::size_t memory_bytes() const {
    return sizeof(*this) + (pos_.capacity() + surf_.capacity() + nrm_.capacity()) * sizeof(Vec3) +
           los_.capacity() * sizeof(Eigen::Vector3f) + count_.capacity() * sizeof(std::uint32_t) +
           attempt_.capacity() * sizeof(std::uint32_t) + faces_.memory_bytes() + grid_.memory_bytes() +
           tri_.memory_bytes() + cached_of_.capacity() * sizeof(std::uint32_t) + cached_bytes() +
           moments_of_.capacity() * sizeof(std::uint32_t) + moments_.capacity() * sizeof(BallMoments) +
           free_moments_.capacity() * sizeof(std::uint32_t) + color_count_.capacity() * sizeof(std::uint32_t) +
           color_sum_.capacity() * sizeof(std::array<std::uint64_t, 3>);
  }

private:
  /// Stored points within `r` of `c` (excluding `self`) into `out` as (squared distance, id).
  void gather(const Vec3& c, double r, VertexId self, std::vector<std::pair<double, VertexId>>& out) const {
    out.clear();
    const double r2 = r * r;
    grid_.for_each_candidate(c, r, [&](std::uint32_t id, const Vec3& q) {
      if (id == self) return;
      const double d2 = (q - c).squaredNorm();
      if (d2 <= r2) out.emplace_back(d2, id);
    });
  }
  /// Density limitation: true if a stored point q lies closer than R_r to p (Sec. 3.3.1), or q faces p's sensor
  /// (its normal, or while pending its line of sight, on p's sensor side) and lies within R_r of p's line of sight
  /// `dir` (unit) and within `density_depth_m` along it. The point that rejected the previous incoming point is
  /// tried first (neighbouring rays of a profile usually fall near the same stored point), then the hash cell of p,
  /// then the other cells within reach; the search stops at the first hit.
  [[nodiscard]] bool too_close(const Vec3& p, const Vec3& dir) {
    const double r2 = settings_.reduction_radius_m * settings_.reduction_radius_m;
    const double depth = settings_.density_depth_m;
    const auto rejects = [&](std::uint32_t id, const Vec3& q) {
      const Vec3 d = q - p;
      const double n2 = d.squaredNorm();
      if (n2 < r2) return true;
      if (!(depth > 0.0)) return false;
      const double along = d.dot(dir);
      if (!(std::abs(along) < depth) || !(n2 - along * along < r2)) return false;
      return has_normal(id) ? nrm_[id].dot(dir) < 0.0 : los_[id].cast<double>().dot(dir) > 0.0;
    };
    if (last_close_ < pos_.size() && rejects(last_close_, pos_[last_close_])) return true;
    const auto hit = [&](std::uint32_t id, const Vec3& q) {
      if (!rejects(id, q)) return false;
      last_close_ = id;
      return true;
    };
    if (!(depth > 0.0)) return grid_.any_candidate(p, settings_.reduction_radius_m, hit);
    // Every rejecting point lies within R_r of the segment p ± depth·dir (the ball around p included).
    return grid_.any_candidate_near_segment(p, dir, depth, settings_.reduction_radius_m, hit);
  }
  /// First ball of a pending vertex, kept equal to what gather(position, first_ball_radius()) would return: entries
  /// in gather()'s order (ascending cell key, then id, which is insertion order); each new point within the radius is
  /// inserted at its place. Saves the gather when the vertex is retried. Kept only for vertices whose moments did not
  /// give a clear verdict at a retry (near a robustness threshold), at most kMaxCachedBalls at a time.
  struct CachedEntry {
    std::uint64_t key;  ///< SpatialHash::cell_key of the point.
    double d2;
    VertexId id;
  };
  using BallMoments = detail::BallMoments;
  /// One slot of the cache of first balls of pending vertices (slots are reused).
  struct CachedBall {
    std::vector<CachedEntry> entries;
    VertexId owner = kNoVertex;  ///< kNoVertex: the slot is free
  };
  static constexpr std::size_t kMaxCachedBalls = 4096;  ///< beyond this all cached balls are dropped (memory bound).
  [[nodiscard]] CachedBall* cached_ball(VertexId v) {
    return cached_of_[v] == 0 ? nullptr : &cached_[cached_of_[v] - 1];
  }
  /// A free slot of `pool` (from `free`, else a new one at the end).
  template <class T>
  [[nodiscard]] static std::uint32_t take_slot(std::vector<T>& pool, std::vector<std::uint32_t>& free) {
    if (free.empty()) {
      pool.emplace_back();
      return static_cast<std::uint32_t>(pool.size() - 1);
    }
    const std::uint32_t slot = free.back();
    free.pop_back();
    return slot;
  }
  /// Caches `ball_` (v's first ball, as gathered) for the pending vertex v.
  void cache_ball(VertexId v) {
    if (live_cached_ >= kMaxCachedBalls) {
      for (CachedBall& b : cached_) {
        if (b.owner != kNoVertex) cached_of_[b.owner] = 0;
        b.owner = kNoVertex;
      }
      free_cached_.clear();
      for (std::uint32_t i = static_cast<std::uint32_t>(cached_.size()); i-- > 0;) free_cached_.push_back(i);
      live_cached_ = 0;
    }
    const std::uint32_t slot = take_slot(cached_, free_cached_);
    std::vector<CachedEntry>& c = cached_[slot].entries;
    c.clear();
    for (const auto& [d2, q] : ball_) c.push_back({grid_.cell_key(pos_[q]), d2, q});
    cached_of_[v] = slot + 1;
    cached_[slot].owner = v;
    ++live_cached_;
  }
  void uncache_ball(VertexId v) {
    if (cached_of_[v] == 0) return;
    const std::uint32_t slot = cached_of_[v] - 1;
    cached_[slot].entries.clear();
    cached_[slot].owner = kNoVertex;
    free_cached_.push_back(slot);
    cached_of_[v] = 0;
    --live_cached_;
  }
  /// Starts the moments of the new pending vertex v from its first ball (`ball_`, as gathered).
  void start_moments(VertexId v) {
    const std::uint32_t slot = take_slot(moments_, free_moments_);
    BallMoments& m = moments_[slot];
    m = {};
    const double rn2 = settings_.normal_radius_m * settings_.normal_radius_m;
    m.add(Vec3::Zero(), detail::pca_weight(0.0, 1.0 / rn2));
    for (const auto& [d2, q] : ball_)
      if (d2 <= rn2) m.add(pos_[q] - pos_[v], detail::pca_weight(d2, 1.0 / rn2));
    moments_of_[v] = slot + 1;
  }
  void drop_moments(VertexId v) {
    if (moments_of_[v] == 0) return;
    free_moments_.push_back(moments_of_[v] - 1);
    moments_of_[v] = 0;
  }
  [[nodiscard]] std::size_t cached_bytes() const {
    std::size_t b = cached_.capacity() * sizeof(CachedBall) + free_cached_.capacity() * sizeof(std::uint32_t);
    for (const auto& c : cached_) b += c.entries.capacity() * sizeof(CachedEntry);
    return b;
  }
  /// Radius of the ball gathered first: min(R_n, R_m). Normals and N_act use the part within R_n (so with R_m < R_n
  /// they see only the R_m ball, as before this ball was split); triangulate() widens it to R_m when needed.
  [[nodiscard]] double first_ball_radius() const {
    return std::min(settings_.normal_radius_m, settings_.mesh_radius_m);
  }
  /// Estimates the normal of v from its R_n ball (in `ball_` after gather; farther entries are ignored). True if
  /// robust.
  bool estimate(VertexId v);
  /// Triangulates v (normal set) from the nearest meshed points of its R_m ball (`ball_` holds v's R_n ball).
  void triangulate(VertexId v);

  StreamingMeshSettings settings_;
  detail::TriangulationSettings tri_settings_;
  std::vector<Vec3> pos_;
  std::vector<Vec3> surf_;  ///< per vertex with project_vertices: pos_ projected onto its PCA plane once meshed
  std::vector<Vec3> nrm_;
  std::vector<Eigen::Vector3f> los_;        ///< unit line of sight, kept for pending re-estimation.
  std::vector<std::uint32_t> count_;        ///< N_act.
  std::vector<std::uint32_t> attempt_;      ///< N_act at the last failed normal estimation (0 = never tried).
  std::vector<std::uint32_t> color_count_;  ///< colours added per vertex; empty until the first coloured point,
                                            ///< then grown lazily (may be shorter than pos_: missing = 0).
  std::vector<std::array<std::uint64_t, 3>> color_sum_;  ///< per vertex: sum of the colours added, per channel.
  detail::FaceStore faces_;
  detail::SpatialHash grid_;
  detail::LocalTriangulator tri_;
  std::uint32_t scan_ = 0;
  VertexId last_close_ = kNoVertex;  ///< the stored point that rejected the last too-close point.
  Pose sensor_ = Pose::Identity();
  StreamingStats stats_;
  // scratch
  std::vector<std::pair<double, VertexId>> ball_, ball2_;
  std::vector<Vec3> pts_;
  std::vector<double> wts_;
  std::vector<VertexId> meshed_nb_, retry_;
  std::vector<std::uint32_t> cached_of_;          ///< per vertex: 1 + slot in cached_, 0 = no cached ball.
  std::vector<CachedBall> cached_;                ///< cached first balls of pending vertices
  std::vector<std::uint32_t> free_cached_;
  std::size_t live_cached_ = 0;
  std::vector<std::uint32_t> moments_of_;         ///< per vertex: 1 + slot in moments_, 0 = none (not pending).
  std::vector<BallMoments> moments_;              ///< moments of the pending vertices
  std::vector<std::uint32_t> free_moments_;
};

/// StreamingMesh with both noise-robust options on (density_depth_m = R_n, project_vertices): a Mesh policy for
/// NbsPlanner, which builds its mesh from (Parameters, unknown-area box). See StreamingMeshSettings for what they do;
/// NbsPlanner's default (StreamingMesh with PlannerSetting::noise_robust_mesh) builds the same mesh.
class NoiseRobustStreamingMesh : public StreamingMesh {
public:
  explicit NoiseRobustStreamingMesh(const Parameters& p = {}, const Aabb& unknown_area = {})
      : StreamingMesh(robust(StreamingMeshSettings::from(p, unknown_area))) {}

  /// `s` with both noise-robust options on (density_depth_m = s.normal_radius_m, project_vertices).
  [[nodiscard]] static StreamingMeshSettings robust(StreamingMeshSettings s) {
    s.density_depth_m = s.normal_radius_m;
    s.project_vertices = true;
    return s;
  }
};

static_assert(EdgeMesh<StreamingMesh>);
static_assert(TracksCurrentScan<StreamingMesh>);
static_assert(KnowsFaceBorders<StreamingMesh>);
static_assert(ColoredMesh<StreamingMesh>);

}  // namespace nbs

#include "nbs/mesh/detail/streaming_mesh_impl.hpp"
