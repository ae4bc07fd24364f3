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
/// Units: metres, world frame. Not thread-safe; const members may be called concurrently when no thread writes.

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <numbers>
#include <span>
#include <vector>

#include "nbs/core/parameters.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/mesh/detail/face_store.hpp"
#include "nbs/mesh/detail/local_triangulation.hpp"
#include "nbs/mesh/detail/normal_estimation.hpp"
#include "nbs/mesh/detail/spatial_hash.hpp"
#include "nbs/mesh/mesh_concept.hpp"

namespace nbs {

/// Settings of the streaming reconstruction. Radii from `Parameters` (Tab. 4.3); the rest are our choices.
struct StreamingMeshSettings {
  double reduction_radius_m = 0.0005;  ///< R_r.
  double normal_radius_m = 0.004;      ///< R_n.
  double mesh_radius_m = 0.006;        ///< R_m.
  Aabb pass_through;                   ///< bounding box of the unknown area; empty box = no filter.
  detail::NormalRobustness robustness; ///< when a PCA normal counts as robust.
  double min_normal_dot = 0.5;         ///< vertices/faces with normals more than 60° apart are not connected.
  /// Depth of the density limitation along the line of sight (ours; 0, the default, is the thesis's R_r ball only).
  /// A point is also rejected if a stored point that faces its sensor lies within R_r of its line of sight and
  /// within this depth along it. Meant for range noise above R_r (Eq. 4.39: σ ≈ 1.1 mm at 0.3 m against R_r =
  /// 0.5 mm): the ball alone then keeps a slab of noisy layers whose tangent-plane triangulations overlap; the
  /// cylinder keeps one layer. R_n is a good value. Use with `project_vertices`.
  double density_depth_m = 0.0;
  /// Move a vertex onto the plane of its weighted PCA (through the ball's weighted mean, along its normal) when it
  /// gets its robust normal (ours, off by default: a one-step MLS projection). Triangulation and `position()` use the
  /// projected point; the density limitation and the normal stage keep the measured one (`stored_position()`).
  /// Measured with both options (density_depth_m = R_n) on a 60 mm plane at σ = 1 mm, 3 scans: triangles projected
  /// on the plane cover 1.03× its area (3–4× without) and the vertex RMS error is 0.43 mm; on the bunny (C_H, 30
  /// scans) the vertex RMS error drops from 1.07 to 0.66 mm with half the vertices. Off here (the thesis's stream as
  /// written); on in NoiseRobustStreamingMesh and in a planner's StreamingMesh by default (PlannerSetting::
  /// noise_robust_mesh, with coverage_estimate = unseen_open).
  bool project_vertices = false;

  [[nodiscard]] static StreamingMeshSettings from(const Parameters& p, const Aabb& unknown_area = {}) {
    p.validate();
    StreamingMeshSettings s;
    s.reduction_radius_m = p.reduction_radius_m;
    s.normal_radius_m = p.normal_radius_m;
    s.mesh_radius_m = p.mesh_radius_m;
    s.pass_through = unknown_area;
    return s;
  }
  /// Throws InvalidArgument naming the first bad field.
  void validate() const {
    detail::require_positive("reduction_radius_m", reduction_radius_m);
    detail::require_positive("normal_radius_m", normal_radius_m);
    detail::require_positive("mesh_radius_m", mesh_radius_m);
    detail::require(reduction_radius_m < mesh_radius_m && reduction_radius_m < normal_radius_m,
                    "reduction_radius_m (", reduction_radius_m, ") must be smaller than normal_radius_m (",
                    normal_radius_m, ") and mesh_radius_m (", mesh_radius_m, ")");
    detail::require(robustness.min_neighbours >= 3, "robustness.min_neighbours must be >= 3, got ",
                    robustness.min_neighbours);
    detail::require_in_range("min_normal_dot", min_normal_dot, -1.0, 1.0);
    detail::require_in_range("density_depth_m", density_depth_m, 0.0, normal_radius_m);
  }
};

/// What happened to one incoming point.
enum class InsertResult : std::uint8_t {
  invalid,        ///< non-finite point or line of sight, or zero line of sight: skipped.
  outside,        ///< outside the pass-through box: skipped.
  too_close,      ///< closer than R_r to a stored point: skipped (density limitation).
  pending,        ///< stored, normal not (yet) robust: not a mesh vertex yet.
  meshed,         ///< stored with a robust normal and triangulated.
};

/// Counters of the stream (all since construction).
struct StreamingStats {
  std::uint64_t received = 0;       ///< points offered to insert().
  std::uint64_t invalid = 0;        ///< skipped: NaN/inf coordinates or zero line of sight.
  std::uint64_t outside = 0;        ///< skipped by the pass-through filter.
  std::uint64_t too_close = 0;      ///< skipped by the density limitation.
  std::uint64_t stored = 0;         ///< points kept (= vertex_count()).
  std::uint64_t meshed = 0;         ///< points with a robust normal, passed to triangulation.
  std::uint64_t normal_failures = 0;///< normal estimations that were not robust (collinear, too few neighbours...).
};

class StreamingMesh {
public:
  explicit StreamingMesh(const Parameters& p = {}, const Aabb& unknown_area = {})
      : StreamingMesh(StreamingMeshSettings::from(p, unknown_area)) {}
  explicit StreamingMesh(const StreamingMeshSettings& s)
      : settings_((s.validate(), s)),
        grid_(s.mesh_radius_m / 2.0),
        tri_(faces_, s.project_vertices ? surf_ : pos_, nrm_) {
    tri_settings_.radius_m = s.mesh_radius_m;
    tri_settings_.min_normal_dot = s.min_normal_dot;
  }
  StreamingMesh(const StreamingMesh&) = delete;  // the triangulator borrows members
  StreamingMesh& operator=(const StreamingMesh&) = delete;

  // --- Stream input ---------------------------------------------------------------------------------------------
  /// Starts a new scan: M_cur becomes empty; `sensor` (T_WS of the scan, e.g. its first profile) is remembered
  /// for boundary detection.
  void begin_scan(const Pose& sensor = Pose::Identity()) {
    ++scan_;
    sensor_ = sensor;
  }

  /// Inserts one measured point `p` (world, m) seen along `line_of_sight` (sensor → point, any positive length).
  InsertResult insert(const Vec3& p, const Vec3& line_of_sight);

  /// begin_scan(scan's first profile pose) + insert every point with its line of sight. Returns points meshed.
  std::size_t integrate(const Scan& scan) {
    begin_scan(scan.profile_poses.empty() ? Pose::Identity() : scan.profile_poses.front());
    std::size_t meshed = 0;
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      const bool ok_profile = i < scan.profile_of_point.size() && scan.profile_of_point[i] < scan.profile_poses.size();
      const Vec3 los = ok_profile ? scan.line_of_sight(i) : Vec3::Zero();
      meshed += insert(scan.points[i], los) == InsertResult::meshed ? 1 : 0;
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
           free_moments_.capacity() * sizeof(std::uint32_t);
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
  /// Weighted moments of a pending vertex's points within R_n, relative to the vertex (centre included): Σw, Σw d,
  /// Σw d dᵀ (lower triangle). Kept for every pending vertex (80 bytes) from its insertion until it is meshed, and
  /// updated as points join its ball, so that a retry with a clearly non-robust neighbourhood costs O(1). One-pass,
  /// so only good for a clear verdict (clearly_not_robust with a 1e-4 margin, which estimate() then agrees with).
  struct BallMoments {
    double w = 0.0;
    Vec3 wd = Vec3::Zero();
    Mat3 wdd = Mat3::Zero();
    void add(const Vec3& d, double weight) {
      w += weight;
      wd += weight * d;
      for (int j = 0; j < 3; ++j)
        for (int i = j; i < 3; ++i) wdd(i, j) += weight * d(i) * d(j);
    }
    [[nodiscard]] Mat3 covariance() const {
      const Vec3 mean = wd / w;
      Mat3 c = Mat3::Zero();
      for (int j = 0; j < 3; ++j)
        for (int i = j; i < 3; ++i) c(i, j) = wdd(i, j) / w - mean(i) * mean(j);
      return c;
    }
  };
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

// ---- implementation ------------------------------------------------------------------------------------------------

inline InsertResult StreamingMesh::insert(const Vec3& p, const Vec3& line_of_sight) {
  ++stats_.received;
  const double los_norm = line_of_sight.norm();
  if (!p.allFinite() || !line_of_sight.allFinite() || !(los_norm > 1e-12)) {
    ++stats_.invalid;
    return InsertResult::invalid;
  }
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

static_assert(EdgeMesh<StreamingMesh>);
static_assert(TracksCurrentScan<StreamingMesh>);
static_assert(KnowsFaceBorders<StreamingMesh>);

}  // namespace nbs
