// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// ProbabilisticVoxelSpace (PVS, Sec. 3.3.2): a voxel backend updated from scans by an update model, restricted to
/// the bounding box of the unknown area (Sec. 4.1), with beam independence and planning ray casts.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <span>
#include <thread>
#include <type_traits>
#include <unordered_set>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/space/backend.hpp"
#include "nbs/space/concepts.hpp"
#include "nbs/space/detail/block_walk.hpp"
#include "nbs/space/hashed_block_backend.hpp"
#include "nbs/space/ray_cast.hpp"
#include "nbs/space/space_types.hpp"
#include "nbs/space/thesis_model.hpp"
#include "nbs/space/unknown_area_grid.hpp"
#include "nbs/space/update_model.hpp"

namespace nbs {

/// The probabilistic voxel space; models VoxelSpace and BatchRayCastingSpace (space/concepts.hpp). `Backend` stores
/// the states (native hashed blocks by default, or any VoxelBackend such as `octomap::OcTree` via nbs/octomap),
/// `Model` turns beams into state updates. A backend that is also a BlockBackend is updated and ray-cast block by
/// block; any other backend voxel by voxel (same voxels, states and statistics).
/// Thread-safety: const members (queries, ray casts) may run concurrently; `integrate` and setters need exclusive
/// access.
template <class Backend = HashedBlockBackend<ThesisState>, class Model = ThesisModel>
  requires VoxelBackend<Backend> && UpdateModel<Model> &&
           std::same_as<backend_state_t<Backend>, typename Model::State>
class ProbabilisticVoxelSpace {
public:
  using State = typename Model::State;
  using BackendType = Backend;
  using ModelType = Model;

  /// Space of voxel edge `resolution_m` restricted to `unknown_area` (Sec. 4.1; empty box = everything the backend
  /// can store). Throws InvalidArgument if resolution_m ≤ 0 / not finite or unknown_area is not finite.
  explicit ProbabilisticVoxelSpace(double resolution_m, const Aabb& unknown_area = {}, Model model = Model{})
      : backend_(backend_traits<Backend>::make((detail::require_positive("resolution_m", resolution_m), resolution_m))),
        model_(std::move(model)),
        area_(resolution_m, unknown_area, nbs::key_range(backend_)) {}

  // ---- Update ------------------------------------------------------------------------------------------------
  /// Integrates one scan: beam i runs from scan.origin(i) to scan.points[i]. Throws InvalidArgument (space
  /// unchanged) if the scan violates its invariants (Scan::validate). Beams of zero length or with an end point
  /// outside the unknown area, and beams the model refuses, are counted and skipped. Each voxel is updated at most
  /// once per scan; the voxels around the end points (the model's band) take precedence over pass-through voxels,
  /// as in OctoMap's insertPointCloud. Returns what happened to this scan (also added to totals()).
  IntegrationStats integrate(const Scan& scan) {
    scan.validate();
    IntegrationStats st;
    st.points = scan.size();
    beams_.clear();
    beams_.reserve(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const Vec3 o = scan.origin(i);
      const Vec3& p = scan.points[i];
      const double r = (p - o).norm();
      if (!(r > 0.0)) {
        ++st.rejected_zero_length;
        continue;
      }
      if (!bounds().contains(p)) {
        ++st.rejected_outside_bounds;
        continue;
      }
      const Vec3 dir = (p - o) / r;
      auto b = model_.beam(r, dir);
      if (!b) {
        ++st.rejected_model;
        continue;
      }
      beams_.push_back({o, p, dir, r, *b, detail::SegmentSetup::to_fixed(Vec3(p * grid().inverse_resolution()))});
    }
    st.integrated = beams_.size();
    if constexpr (BlockBackend<Backend>) stage_flushed_blocks();  // may throw FileError: nothing changed yet
    begin_scan();
    for (const BeamRecord& b : beams_) band_pass(b, st);
    for (const BeamRecord& b : beams_) free_pass(b, st);
    if constexpr (BlockBackend<Backend>) backend_.end_scan();  // flush policy (off by default)
    totals_ += st;
    return st;
  }

  // ---- Queries -----------------------------------------------------------------------------------------------
  [[nodiscard]] const VoxelGrid& grid() const { return area_.grid(); }
  [[nodiscard]] double resolution_m() const { return area_.resolution_m(); }
  /// The bounding box of the unknown area actually used (clipped to the backend's key range), world metres.
  /// End points must lie inside it.
  [[nodiscard]] const Aabb& bounds() const { return area_.bounds(); }
  /// The union of the voxels overlapping bounds() (shrunk by 10⁻⁶ l_v): beams and rays are clipped to it, so
  /// every voxel that overlaps the unknown area can be updated (as OctoMap's bounding-box limit does).
  [[nodiscard]] const Aabb& voxel_bounds() const { return area_.voxel_bounds(); }
  /// Keys of the voxels overlapping bounds().
  [[nodiscard]] KeyBox bounds_keys() const { return area_.bounds_keys(); }
  [[nodiscard]] const Backend& backend() const { return backend_; }
  /// Mutable access to the backend, e.g. to set HashedBlockBackend's flush policy. Writing voxel states through it
  /// bypasses the update model.
  [[nodiscard]] Backend& mutable_backend() { return backend_; }
  [[nodiscard]] const Model& model() const { return model_; }
  /// Sum of the statistics of every integrated scan.
  [[nodiscard]] const IntegrationStats& totals() const { return totals_; }

  /// State of voxel k (State{} = unknown if never updated).
  [[nodiscard]] State state(const VoxelKey& k) const { return voxel_state(backend_, k); }
  /// Occupancy probability p of voxel k (0.5 if unknown), Eq. 3.8 for the thesis model.
  [[nodiscard]] double probability(const VoxelKey& k) const { return model_.probability(state(k)); }
  /// p of the voxel containing world point x; 0.5 outside the key range.
  [[nodiscard]] double probability(const Vec3& x) const {
    const auto k = grid().key_of(x);
    return k ? probability(*k) : 0.5;
  }
  [[nodiscard]] bool occupied(const VoxelKey& k) const { return model_.occupied(state(k)); }
  [[nodiscard]] bool observed(const VoxelKey& k) const { return is_observed(backend_, k); }
  /// Calls f(key, state) for every observed voxel.
  template <class F>
  void for_each(F&& f) const {
    for_each_voxel(backend_, static_cast<F&&>(f));
  }
  /// Bytes held by the voxel states (backend).
  [[nodiscard]] std::size_t memory_bytes() const { return nbs::memory_bytes(backend_); }

  // ---- Planning ray casts ------------------------------------------------------------------------------------
  /// Visits the voxels on `ray` inside voxel_bounds(), in order from the origin, calling visit(key, state) for each
  /// (unknown voxels included, as State{}); stops after the first occupied voxel (hit) or when visit returns
  /// false. A ray that misses voxel_bounds() visits nothing. Throws InvalidArgument if the ray is not finite.
  template <class Visit>
  RaycastResult cast_ray(const Ray& ray, Visit&& visit) const {
    detail::check_ray(ray, 0);
    RayReader reader(backend_);
    return cast_ray_unchecked(reader, ray, visit);
  }
  /// cast_ray for every ray, on `threads` std::threads (0 = hardware concurrency; the calling thread is one of them).
  /// Threads take chunks of kCastChunk consecutive rays from a shared counter until none is left, so uneven rays
  /// (early hits, misses) do not leave a thread idle; visit(ray_index, key, state) is called concurrently for
  /// different rays, in order within one ray, so results written per ray are identical for any thread count. All
  /// rays are checked before any is cast. An exception thrown by visit stops the handing out of chunks and is
  /// rethrown after every thread has finished.
  template <class Visit>
  std::vector<RaycastResult> cast_rays(std::span<const Ray> rays, unsigned threads, Visit&& visit) const {
    for (std::size_t i = 0; i < rays.size(); ++i) detail::check_ray(rays[i], i);
    std::vector<RaycastResult> out(rays.size());
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    const std::size_t chunks = (rays.size() + kCastChunk - 1) / kCastChunk;
    threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(chunks, 1)));
    std::atomic<std::size_t> next{0};
    std::vector<std::exception_ptr> errors(threads);
    const auto work = [&](unsigned t) {
      try {
        BlockReader reader(backend_);
        for (;;) {
          const std::size_t lo = next.fetch_add(kCastChunk, std::memory_order_relaxed);
          if (lo >= rays.size()) return;
          const std::size_t hi = std::min(rays.size(), lo + kCastChunk);
          for (std::size_t i = lo; i < hi; ++i) {
            auto per_ray = [&](const VoxelKey& k, const State& s) { return visit(i, k, s); };
            out[i] = cast_ray_unchecked(reader, rays[i], per_ray);
          }
        }
      } catch (...) {
        errors[t] = std::current_exception();
        next.store(rays.size(), std::memory_order_relaxed);
      }
    };
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, t);
    work(0);
    for (auto& th : pool) th.join();
    for (auto& e : errors)
      if (e) std::rethrow_exception(e);
    return out;
  }
  /// Rays per chunk of cast_rays (a few hundred microseconds of work at 2 mm).
  static constexpr std::size_t kCastChunk = 64;

private:
  struct BeamRecord {
    Vec3 origin;
    Vec3 end;
    Vec3 dir;
    double range_m;
    typename Model::Beam beam;
    detail::SegmentSetup::Fixed end_fixed;  ///< end point in the walks' fixed point (voxel units · 2^10)
  };
  struct NoReader {
    explicit NoReader(const Backend&) {}
  };
  /// Block lookups of the planning ray casts: a BlockBackend's cached reader per thread of cast_rays, an uncached
  /// one for a single cast_ray.
  using BlockReader =
      typename std::conditional_t<BlockBackend<Backend>, detail::ReaderOf<Backend, 8>, std::type_identity<NoReader>>::type;
  using RayReader =
      typename std::conditional_t<BlockBackend<Backend>, detail::ReaderOf<Backend, 0>, std::type_identity<NoReader>>::type;

  // All-or-nothing integration with flushing: reloads every flushed block the walks of beams_ will write (the same
  // segments as band_pass and free_pass) before any voxel changes; throws FileError, space unchanged, if one cannot
  // be read. Free when no block is flushed.
  void stage_flushed_blocks() {
    if constexpr (requires(std::uint64_t id) {
                    backend_.flushed_block_count();
                    backend_.is_flushed(id);
                    backend_.reload_blocks(std::vector<std::uint64_t>{});
                  }) {
      if (backend_.flushed_block_count() == 0) return;
      using Q = detail::SegmentSetup;
      // Only the flushed blocks are kept, and a block is looked up once per run of voxels in it: a walk stays in a
      // block for several steps, and a list of every step's block (≈ 13 M ids for a 160 × 120 area scan at 5 mm)
      // cost ~100 MiB and a sort per scan.
      std::vector<std::uint64_t> ids;
      std::uint64_t last_id = 0;
      bool have_last = false;
      const auto note = [&](std::uint64_t id) {
        if (have_last && id == last_id) return;
        have_last = true;
        last_id = id;
        if (backend_.is_flushed(id)) ids.push_back(id);
      };
      const auto collect = [&](const Q& q, bool include_end) {
        detail::SegmentWalker w(q);
        for (;;) {
          const bool last = w.remaining() == 0;
          if (last && !include_end) return;
          note(Backend::block_id(w.key()));
          if (last) return;
          w.step();
        }
      };
      const double inv = grid().inverse_resolution();
      for (const BeamRecord& b : beams_) {
        const double w = model_.band_half_width_m(b.beam);
        const Vec3 a = b.end - w * b.dir, e = b.end + w * b.dir;
        note(Backend::block_id(Q::key_of_fixed(b.end_fixed)));
        double t0, t1;
        if (detail::clip_segment(a, e, voxel_bounds(), t0, t1)) {
          const Vec3 from = detail::point_in_box(a, e, t0, voxel_bounds());
          const Vec3 to = detail::point_in_box(a, e, t1, voxel_bounds());
          collect(Q(Q::to_fixed(Vec3(from * inv)), Q::to_fixed(Vec3(to * inv))), true);
        }
        if (detail::clip_segment(b.origin, b.end, voxel_bounds(), t0, t1)) {
          const Vec3 from = detail::point_in_box(b.origin, b.end, t0, voxel_bounds());
          collect(Q(Q::to_fixed(Vec3(from * inv)), b.end_fixed), false);
        }
      }
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      backend_.reload_blocks(ids);
    }
  }

  void begin_scan() {
    if constexpr (BlockBackend<Backend>) {
      (void)backend_.next_epoch();
      constexpr std::int32_t kNone = VoxelKey::kMinIndex - 1;  // no walk has this key
      full_band_[0] = full_band_[1] = VoxelKey{kNone, kNone, kNone};
    } else {
      touched_.clear();
    }
  }

  // Calls apply(State&) for voxel k unless it was already touched in this scan; writes back if updated.
  template <class Apply>
  bool visit_generic(const VoxelKey& k, IntegrationStats& st, Apply&& apply) {
    if (!touched_.insert(k.pack()).second) {
      ++st.voxels_same_scan;
      return false;
    }
    State s = voxel_state(backend_, k);
    count(apply(s), st, [&] { set_voxel_state(backend_, k, s); });
    return true;
  }
  // Native path: apply(State&) to voxel i of blk unless it was already touched in this scan; writes back if updated.
  template <class Block, class Apply>
  void update_native(Block& blk, int i, IntegrationStats& st, Apply&& apply) {
    if (!blk.touch(i)) {
      ++st.voxels_same_scan;
      return;
    }
    update_fresh(blk, i, st, apply);
  }
  // apply(State&) to voxel i of blk, whose touched bit the caller has just set; writes back if updated.
  template <class Block, class Apply>
  void update_fresh(Block& blk, int i, IntegrationStats& st, Apply&& apply) {
    State s = blk.get(i);
    count(apply(s), st, [&] {
      blk.put(i, s);
      backend_.note_observed(blk, i);
    });
  }
  template <class OnUpdate>
  static void count(VoxelUpdate u, IntegrationStats& st, OnUpdate&& on_update) {
    if (u == VoxelUpdate::updated) {
      ++st.voxel_updates;
      on_update();
    } else if (u == VoxelUpdate::similar_beam) {
      ++st.voxels_similar_beam;
    }
  }

  // Walks the quantised segment q (voxel units) with apply(State&, key, is_end) → VoxelUpdate, once per voxel per
  // scan. Returns the number of voxels passed to apply (not yet updated in this scan).
  template <class Apply>
  std::uint64_t walk(const detail::SegmentSetup& q, bool include_end, IntegrationStats& st, Apply&& apply) {
    if constexpr (BlockBackend<Backend>) {
      // Only voxels not yet updated in this scan reach the callback; the others are counted as voxels_same_scan.
      std::uint64_t fresh = 0;
      const std::int64_t n = detail::walk_untouched(
          backend_, q, include_end, [&](typename Backend::Block& blk, int i, const VoxelKey& block_key, bool is_end) {
            ++fresh;
            update_fresh(blk, i, st, [&](State& s) {
              return apply(s, detail::voxel_key_in_block<Backend>(block_key, i), is_end);
            });
          });
      st.voxels_same_scan += static_cast<std::uint64_t>(n) - fresh;
      return fresh;
    } else {
      detail::SegmentWalker w(q);
      std::uint64_t fresh = 0;
      for (;;) {
        const bool last = w.remaining() == 0;
        if (last && !include_end) return fresh;
        const VoxelKey k = w.key();
        fresh += visit_generic(k, st, [&](State& s) { return apply(s, k, last); }) ? 1 : 0;
        if (last) return fresh;
        w.step();
      }
    }
  }

  void band_pass(const BeamRecord& b, IntegrationStats& st) {
    const double w = model_.band_half_width_m(b.beam);
    const Vec3 a = b.end - w * b.dir, e = b.end + w * b.dir;
    using Q = detail::SegmentSetup;
    const VoxelKey end_key = Q::key_of_fixed(b.end_fixed);  // = grid().key_of(b.end), see SegmentSetup::to_fixed
    if constexpr (BlockBackend<Backend>) {
      // The band lies inside the end voxel (which lies inside voxel_bounds()): no clipping, no walk.
      if (grid().in_voxel(a, end_key) && grid().in_voxel(e, end_key)) {
        update_native(backend_.block(Backend::block_id(end_key)), Backend::local_index(end_key), st,
                      [&](State& s) { return model_.update_band(s, b.beam, 0.0, true); });
        return;
      }
    }
    // Clipped band. With both ends inside, clip_segment would return exactly [0, 1] (quotients of monotonically
    // rounded differences), so the divisions are skipped, and point_in_box(a, e, 0) is a itself.
    Vec3 from, to;
    if (inside(a, voxel_bounds()) && inside(e, voxel_bounds())) {
      from = a;
      to = detail::point_in_box(a, e, 1.0, voxel_bounds());
    } else {
      double t0, t1;
      if (!detail::clip_segment(a, e, voxel_bounds(), t0, t1)) return;  // cannot happen: b.end is inside
      from = detail::point_in_box(a, e, t0, voxel_bounds());
      to = detail::point_in_box(a, e, t1, voxel_bounds());
    }
    const auto update = [&](State& s, const VoxelKey& k, bool) {
      const bool is_end = k == end_key;
      const double offset = is_end ? 0.0 : (grid().center(k) - b.origin).dot(b.dir) - b.range_m;
      return model_.update_band(s, b.beam, offset, is_end);
    };
    const double inv = grid().inverse_resolution();
    const Q::Fixed fs = Q::to_fixed(Vec3(from * inv)), fe = Q::to_fixed(Vec3(to * inv));
    if constexpr (BlockBackend<Backend>) {
      // The walk's keys are VoxelGrid::key_of of the same points (see SegmentSetup::to_fixed).
      const VoxelKey ks = Q::key_of_fixed(fs), ke = Q::key_of_fixed(fe);
      if (ks == ke) {  // the band lies in one voxel (the end voxel): no walk
        update_native(backend_.block(Backend::block_id(end_key)), Backend::local_index(end_key), st,
                      [&](State& s) { return update(s, end_key, true); });
        return;
      }
      // Consecutive beams often span the same voxels. A band walk whose first and last voxel differ along one axis
      // only (so that they fix every voxel in between) and that met no voxel not yet updated in this scan is
      // remembered; the next band with the same first and last voxel only counts its Σ|Δkey| + 1 voxels. (The walk
      // skips updated voxels at one bit test each: cheaper than testing the whole key box first.)
      if (ks == full_band_[0] && ke == full_band_[1]) {
        st.voxels_same_scan += static_cast<std::uint64_t>(std::abs(ke.x - ks.x) + std::abs(ke.y - ks.y) +
                                                          std::abs(ke.z - ks.z)) + 1;
        return;
      }
      const int axes = (ks.x != ke.x) + (ks.y != ke.y) + (ks.z != ke.z);
      if (walk(Q(fs, fe), true, st, update) == 0 && axes == 1) {
        full_band_[0] = ks;
        full_band_[1] = ke;
      }
    } else {
      walk(Q(fs, fe), true, st, update);
    }
  }

  void free_pass(const BeamRecord& b, IntegrationStats& st) {
    double t0, t1;
    if (!detail::clip_segment(b.origin, b.end, voxel_bounds(), t0, t1)) return;
    const Vec3 from = detail::point_in_box(b.origin, b.end, t0, voxel_bounds());
    const double inv = grid().inverse_resolution();
    walk(detail::SegmentSetup(detail::SegmentSetup::to_fixed(Vec3(from * inv)), b.end_fixed), false, st,
         [&](State& s, const VoxelKey&, bool) { return model_.update_free(s, b.beam); });
  }

  [[nodiscard]] static bool inside(const Vec3& p, const Aabb& box) {
    return p.x() >= box.min.x() && p.x() <= box.max.x() && p.y() >= box.min.y() && p.y() <= box.max.y() &&
           p.z() >= box.min.z() && p.z() <= box.max.z();
  }

  // A planning cast of a checked ray: block by block for a BlockBackend (the voxels and stop rule of
  // walk_ray_generic), else walk_ray_generic's per-voxel lookups.
  template <class Reader, class Visit>
  RaycastResult cast_ray_unchecked(Reader& reader, const Ray& ray, Visit& visit) const {
    if constexpr (BlockBackend<Backend>) {
      RaycastResult res;
      Vec3 a, b;
      if (!detail::clip_ray(ray, voxel_bounds(), grid().inverse_resolution(), a, b)) return res;
      detail::walk_blocks_const(reader, a, b, [&](const typename Backend::Block* blk, int i, const VoxelKey& k) {
        const State s = blk ? blk->get(i) : State{};
        return detail::ray_step(res, visit, k, s, model_.occupied(s));
      });
      return res;
    } else {
      (void)reader;
      return detail::walk_ray_unchecked(*this, ray, visit);
    }
  }

  Backend backend_;
  Model model_;
  UnknownAreaGrid area_;
  IntegrationStats totals_;
  std::vector<BeamRecord> beams_;
  VoxelKey full_band_[2];  ///< first and last key (one axis apart) of a band walk that met only voxels updated in this scan
  std::unordered_set<std::uint64_t> touched_;
};

}  // namespace nbs
