// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// ProbabilisticVoxelSpace (PVS, Sec. 3.3.2): a voxel backend updated from scans by an update model, restricted to
/// the bounding box of the unknown area (Sec. 4.1), with beam independence and planning ray casts.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <thread>
#include <type_traits>
#include <unordered_set>
#include <utility>
#include <vector>

#include "nbs/core/detail/parallel_for.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/space/backend.hpp"
#include "nbs/space/concepts.hpp"
#include "nbs/space/detail/block_walk.hpp"
#include "nbs/space/detail/slab_split.hpp"
#include "nbs/space/hashed_block_backend.hpp"
#include "nbs/space/ray_cast.hpp"
#include "nbs/space/space_types.hpp"
#include "nbs/space/thesis_model.hpp"
#include "nbs/space/unknown_area_grid.hpp"
#include "nbs/space/update_model.hpp"

namespace nbs {

/// The probabilistic voxel space; models VoxelSpace, BatchRayCastingSpace and ParallelIntegratingSpace
/// (space/concepts.hpp). `Backend` stores
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
  IntegrationStats integrate(const Scan& scan) { return integrate(scan, 1); }

  /// integrate(scan) on `threads` std::threads (0 = hardware concurrency): the same voxel states and statistics for
  /// any thread count (ParallelIntegratingSpace). At most one thread per kBeamsPerThread points is used (a scan of
  /// fewer than 2 · kBeamsPerThread points runs on the calling thread). The beams are prepared (range, model beam,
  /// clipped segments) in blocks of points, one per thread. With a ConcurrentBlockBackend the keys are then cut into
  /// one slab of whole blocks per thread along one axis (detail::balance_slabs: greedy cuts over a sample of at most
  /// kSplitSample beams, a free walk weighing its voxels and a band kBandWeight voxels; the axis whose heaviest slab is
  /// lightest); each thread runs both passes over every beam, in order, on the voxels of its slab only
  /// (detail::walk_untouched_slab), so each voxel meets the beams in the order one thread would; other backends run
  /// the passes on the calling thread. With threads > 1 the model's const members are called concurrently.
  IntegrationStats integrate(const Scan& scan, unsigned threads) {
    scan.validate();
    threads = static_cast<unsigned>(
        std::clamp<std::size_t>(scan.size() / kBeamsPerThread, 1, detail::resolve_threads(threads)));
    // The beams, in scan order (rejected points keep their slot, marked), prepared on the threads in blocks.
    beams_.resize(scan.size());  // default-initialised (no stores): the threads write them first
    detail::parallel_for(beams_.size(), threads, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) prepare_beam(scan, i, beams_[i]);
    });
    IntegrationStats st;
    st.points = scan.size();
    for (const BeamRecord& b : beams()) {
      st.rejected_zero_length += b.kind == BeamKind::zero_length ? 1 : 0;
      st.rejected_outside_bounds += b.kind == BeamKind::outside_bounds ? 1 : 0;
      st.rejected_model += b.kind == BeamKind::refused ? 1 : 0;
    }
    st.integrated = st.points - st.rejected_zero_length - st.rejected_outside_bounds - st.rejected_model;
    if constexpr (BlockBackend<Backend>) stage_flushed_blocks();  // may throw FileError: nothing changed yet
    begin_scan();
    run_passes(scan, threads, st);
    if constexpr (BlockBackend<Backend>) backend_.end_scan();  // flush policy (off by default)
    totals_ += st;
    return st;
  }
  /// integrate(scan, threads) uses at most one thread per kBeamsPerThread points.
  static constexpr std::size_t kBeamsPerThread = 1024;
  /// The threads the last integrate ran its passes on (one per slab; 1 before the first scan).
  [[nodiscard]] unsigned last_integrate_threads() const { return last_threads_; }

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
  enum class BeamKind : std::uint8_t {
    zero_length,     ///< rejected: end point == origin
    outside_bounds,  ///< rejected: end point outside bounds()
    refused,         ///< rejected by the model
    band_end_voxel,  ///< the band lies in the end voxel: update_band(s, beam, 0, true) there, no walk
    band_walk,       ///< the band is walked from band_from to band_to (the end voxel among its voxels)
    band_none,       ///< the clipped band is empty (cannot happen: the end point is inside)
  };
  /// A beam as the passes need it; fixed-point points in voxel units · 2^10 (SegmentSetup::to_fixed), which fit
  /// 32 bits since |coordinate| ≤ 2^20 voxels.
  /// (Origin, direction and range are not kept: the band walk recomputes them from the scan, with the same
  /// arithmetic; a smaller record is faster to write for an area frame of 300 000 points.)
  struct BeamRecord {
    using Fixed32 = std::array<std::int32_t, 3>;
    typename Model::Beam beam;
    Fixed32 end;        ///< end point
    Fixed32 free_from;  ///< entry of the free segment (origin → end) into voxel_bounds(), if free_walk
    Fixed32 band_from;  ///< the band (end ∓ half width along dir) clipped to voxel_bounds(), if band_walk
    Fixed32 band_to;
    BeamKind kind;
    bool free_walk;  ///< the free segment meets voxel_bounds()

    [[nodiscard]] bool used() const { return kind >= BeamKind::band_end_voxel; }
    [[nodiscard]] static detail::SegmentSetup::Fixed wide(const Fixed32& f) { return {f[0], f[1], f[2]}; }
    [[nodiscard]] static Fixed32 narrow(const detail::SegmentSetup::Fixed& f) {
      return {static_cast<std::int32_t>(f[0]), static_cast<std::int32_t>(f[1]), static_cast<std::int32_t>(f[2])};
    }
    /// Key of the voxel containing fixed-point point f (SegmentSetup::key_of_fixed).
    [[nodiscard]] static VoxelKey key(const Fixed32& f) { return detail::SegmentSetup::key_of_fixed(wide(f)); }
    [[nodiscard]] VoxelKey end_key() const { return key(end); }
    [[nodiscard]] detail::SegmentSetup free_segment() const { return {wide(free_from), wide(end)}; }
    [[nodiscard]] detail::SegmentSetup band_segment() const { return {wide(band_from), wide(band_to)}; }
  };
  [[nodiscard]] static double beam_range(const Vec3& o, const Vec3& p) { return (p - o).norm(); }
  [[nodiscard]] static Vec3 beam_direction(const Vec3& o, const Vec3& p, double range_m) { return (p - o) / range_m; }
  [[nodiscard]] std::span<const BeamRecord> beams() const { return beams_; }
  /// std::allocator whose value-less construct default-initialises, so that resize() leaves trivial records unwritten.
  template <class T>
  struct DefaultInitAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
      using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() = default;
    template <class U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
      ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
      std::allocator_traits<std::allocator<T>>::construct(static_cast<std::allocator<T>&>(*this), p,
                                                          static_cast<Args&&>(args)...);
    }
  };

  // The record of point i of scan (any thread: writes only rec).
  void prepare_beam(const Scan& scan, std::size_t i, BeamRecord& rec) const {
    using Q = detail::SegmentSetup;
    const Vec3 o = scan.origin(i);
    const Vec3& p = scan.points[i];
    const double r = beam_range(o, p);
    if (!(r > 0.0)) {
      rec.kind = BeamKind::zero_length;
      return;
    }
    if (!bounds().contains(p)) {
      rec.kind = BeamKind::outside_bounds;
      return;
    }
    const Vec3 dir = beam_direction(o, p, r);
    const auto b = model_.beam(r, dir);
    if (!b) {
      rec.kind = BeamKind::refused;
      return;
    }
    const double inv = grid().inverse_resolution();
    rec.beam = *b;
    rec.end = BeamRecord::narrow(Q::to_fixed(Vec3(p * inv)));
    double t0, t1;
    rec.free_walk = detail::clip_segment(o, p, voxel_bounds(), t0, t1);
    if (rec.free_walk) rec.free_from = BeamRecord::narrow(Q::to_fixed(Vec3(detail::point_in_box(o, p, t0, voxel_bounds()) * inv)));
    // The band. Inside the end voxel (which lies inside voxel_bounds()): no clipping, no walk. Else clipped; with
    // both ends inside, clip_segment would return exactly [0, 1] (quotients of monotonically rounded differences), so
    // the divisions are skipped, and point_in_box(a, e, 0) is a itself.
    const double w = model_.band_half_width_m(rec.beam);
    const Vec3 a = p - w * dir, e = p + w * dir;
    const VoxelKey end_key = rec.end_key();  // = grid().key_of(p), see SegmentSetup::to_fixed
    if constexpr (BlockBackend<Backend>) {
      if (grid().in_voxel(a, end_key) && grid().in_voxel(e, end_key)) {
        rec.kind = BeamKind::band_end_voxel;
        return;
      }
    }
    Vec3 from, to;
    if (inside(a, voxel_bounds()) && inside(e, voxel_bounds())) {
      from = a;
      to = detail::point_in_box(a, e, 1.0, voxel_bounds());
    } else {
      if (!detail::clip_segment(a, e, voxel_bounds(), t0, t1)) {
        rec.kind = BeamKind::band_none;
        return;
      }
      from = detail::point_in_box(a, e, t0, voxel_bounds());
      to = detail::point_in_box(a, e, t1, voxel_bounds());
    }
    rec.band_from = BeamRecord::narrow(Q::to_fixed(Vec3(from * inv)));
    rec.band_to = BeamRecord::narrow(Q::to_fixed(Vec3(to * inv)));
    rec.kind = BeamKind::band_walk;
    if constexpr (BlockBackend<Backend>) {
      // The walk's keys are VoxelGrid::key_of of the same points (see SegmentSetup::to_fixed): a band whose ends lie in
      // one voxel (the end voxel) needs no walk.
      if (BeamRecord::key(rec.band_from) == BeamRecord::key(rec.band_to))
        rec.kind = BeamKind::band_end_voxel;
    }
  }

  /// One thread's passes: its slab, its statistics, and the band walk it remembers (see band_pass).
  struct alignas(64) PassState {  // (own cache lines: the threads count into theirs per voxel)
    static constexpr std::int32_t kNone = VoxelKey::kMinIndex - 1;  // no walk has this key
    detail::KeySlab slab;  ///< the voxels this thread updates (everything by default)
    IntegrationStats st;
    VoxelKey band_first{kNone, kNone, kNone}, band_last{kNone, kNone, kNone};
    std::uint64_t band_voxels = 0;  ///< voxels of that band walk in the slab
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
      for (const BeamRecord& b : beams()) {
        if (!b.used()) continue;
        note(Backend::block_id(b.end_key()));
        if (b.kind == BeamKind::band_walk) collect(b.band_segment(), true);
        if (b.free_walk) collect(b.free_segment(), false);
      }
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      backend_.reload_blocks(ids);
    }
  }

  void begin_scan() {
    if constexpr (BlockBackend<Backend>) {
      (void)backend_.next_epoch();
    } else {
      touched_.clear();
    }
  }

  // Both passes over every beam on the calling thread, or in parallel, one thread per slab of balance_slabs (see
  // integrate(scan, threads)); adds the walks' statistics to st.
  void run_passes(const Scan& scan, unsigned threads, IntegrationStats& st) {
    if constexpr (ConcurrentBlockBackend<Backend>) {
      if (threads > 1) {
        // The cut is balanced on at most kSplitSample beams, evenly spaced: a free walk weighs its voxels, a band
        // kBandWeight voxels at the end voxel (measured: a band costs about as much as 20 free-walk voxels).
        const std::size_t stride = std::max<std::size_t>(1, beams_.size() / kSplitSample);
        const auto walk_of = [&](std::size_t k) -> std::optional<detail::WeightedWalk> {
          const BeamRecord& b = beams_[(k / 2) * stride];
          if (!b.used()) return std::nullopt;
          if (k % 2 == 1) return detail::WeightedWalk{b.end_key(), b.end_key(), kBandWeight};
          if (!b.free_walk) return std::nullopt;
          const VoxelKey a = BeamRecord::key(b.free_from), e = b.end_key();
          return detail::WeightedWalk{a, e, 1.0 + std::abs(e.x - a.x) + std::abs(e.y - a.y) + std::abs(e.z - a.z)};
        };
        const std::vector<detail::KeySlab> slabs =
            detail::balance_slabs(2 * (beams_.size() / stride), walk_of, threads, Backend::kEdgeBits);
        std::vector<PassState> ps(slabs.size());
        std::mutex m;
        detail::parallel_for(slabs.size(), static_cast<unsigned>(slabs.size()), [&](std::size_t lo, std::size_t hi) {
          for (std::size_t t = lo; t < hi; ++t) {
            typename Backend::ConcurrentWriter w(backend_, m);
            ps[t].slab = slabs[t];
            for (std::size_t i = 0; i < beams_.size(); ++i) band_pass(scan, i, w, ps[t]);
            for (const BeamRecord& b : beams()) free_pass(b, w, ps[t]);
            w.commit();
          }
        });
        for (const PassState& p : ps) st += p.st;
        last_threads_ = static_cast<unsigned>(slabs.size());
        return;
      }
    }
    PassState ps;
    for (std::size_t i = 0; i < beams_.size(); ++i) band_pass(scan, i, backend_, ps);
    for (const BeamRecord& b : beams()) free_pass(b, backend_, ps);
    st += ps.st;
    last_threads_ = 1;
  }
  /// Beams sampled for the cut of integrate(scan, threads), and the weight of a band in free-walk voxels.
  static constexpr std::size_t kSplitSample = 8192;
  static constexpr double kBandWeight = 20.0;

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
  // Native path: apply(State&) to voxel i of blk unless it was already touched in this scan; writes back (through
  // the writer w: the backend or a thread's ConcurrentWriter) if updated.
  template <class W, class Block, class Apply>
  void update_native(W& w, Block& blk, int i, IntegrationStats& st, Apply&& apply) {
    if (!blk.touch(i)) {
      ++st.voxels_same_scan;
      return;
    }
    update_fresh(w, blk, i, st, apply);
  }
  // apply(State&) to voxel i of blk, whose touched bit the caller has just set; writes back if updated.
  template <class W, class Block, class Apply>
  void update_fresh(W& w, Block& blk, int i, IntegrationStats& st, Apply&& apply) {
    State s = blk.get(i);
    count(apply(s), st, [&] {
      blk.put(i, s);
      w.note_observed(blk, i);
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

  struct WalkCount {
    std::uint64_t fresh;   ///< voxels passed to apply (not yet updated in this scan)
    std::uint64_t voxels;  ///< voxels of the walk (in the slab)
  };
  // Walks the quantised segment q (voxel units) with apply(State&, key, is_end) → VoxelUpdate, once per voxel per
  // scan, on the voxels of ps.slab (all of them for a backend that is no BlockBackend: it runs on one thread).
  template <class W, class Apply>
  WalkCount walk(W& w, const detail::SegmentSetup& q, bool include_end, PassState& ps, Apply&& apply) {
    IntegrationStats& st = ps.st;
    if constexpr (BlockBackend<Backend>) {
      // Only voxels not yet updated in this scan reach the callback; the others are counted as voxels_same_scan.
      std::uint64_t fresh = 0;
      const detail::KeySlab& sl = ps.slab;
      const std::int64_t n = detail::walk_untouched_slab(
          w, q, sl.axis, sl.lo, sl.hi, include_end,
          [&](typename Backend::Block& blk, int i, const VoxelKey& block_key, bool is_end) {
            ++fresh;
            update_fresh(w, blk, i, st, [&](State& s) {
              return apply(s, detail::voxel_key_in_block<Backend>(block_key, i), is_end);
            });
          });
      st.voxels_same_scan += static_cast<std::uint64_t>(n) - fresh;
      return {fresh, static_cast<std::uint64_t>(n)};
    } else {
      (void)w;
      detail::SegmentWalker wk(q);
      WalkCount c{0, 0};
      for (;;) {
        const bool last = wk.remaining() == 0;
        if (last && !include_end) return c;
        const VoxelKey k = wk.key();
        ++c.voxels;
        c.fresh += visit_generic(k, st, [&](State& s) { return apply(s, k, last); }) ? 1 : 0;
        if (last) return c;
        wk.step();
      }
    }
  }

  // The band of beam b on the voxels of ps.slab: the end voxel alone, or a walk (see prepare_beam).
  template <class W>
  void band_pass(const Scan& scan, std::size_t i, W& wr, PassState& ps) {
    const BeamRecord& b = beams_[i];
    if constexpr (BlockBackend<Backend>) {  // (prepare_beam gives other backends only walks)
      if (b.kind == BeamKind::band_end_voxel) {
        const VoxelKey k = b.end_key();
        if (ps.slab.owns(k))
          update_native(wr, wr.block(Backend::block_id(k)), Backend::local_index(k), ps.st,
                        [&](State& s) { return model_.update_band(s, b.beam, 0.0, true); });
        return;
      }
    }
    if (b.kind != BeamKind::band_walk) return;
    const VoxelKey ks = BeamRecord::key(b.band_from), ke = BeamRecord::key(b.band_to);
    if (outside_slab(ks, ke, ps.slab)) return;
    const VoxelKey end_key = b.end_key();
    const Vec3 o = scan.origin(i);
    const double r = beam_range(o, scan.points[i]);
    const Vec3 dir = beam_direction(o, scan.points[i], r);
    const auto update = [&](State& s, const VoxelKey& k, bool) {
      const bool is_end = k == end_key;
      const double offset = is_end ? 0.0 : (grid().center(k) - o).dot(dir) - r;
      return model_.update_band(s, b.beam, offset, is_end);
    };
    if constexpr (BlockBackend<Backend>) {
      // Consecutive beams often span the same voxels. A band walk whose first and last voxel differ along one axis
      // only (so that they fix every voxel in between) and that met no voxel of the slab not yet updated in this
      // scan is remembered; the next band with the same first and last voxel only counts the remembered walk's
      // voxels. (The walk skips updated voxels at one bit test each: cheaper than testing the whole key box first.)
      if (ks == ps.band_first && ke == ps.band_last) {
        ps.st.voxels_same_scan += ps.band_voxels;
        return;
      }
      const int axes = (ks.x != ke.x) + (ks.y != ke.y) + (ks.z != ke.z);
      const WalkCount c = walk(wr, b.band_segment(), true, ps, update);
      if (c.fresh == 0 && axes == 1) {
        ps.band_first = ks;
        ps.band_last = ke;
        ps.band_voxels = c.voxels;
      }
    } else {
      walk(wr, b.band_segment(), true, ps, update);
    }
  }

  // The free segment of beam b, end voxel excluded, on the voxels of ps.slab.
  template <class W>
  void free_pass(const BeamRecord& b, W& wr, PassState& ps) {
    if (!b.used() || !b.free_walk) return;
    if (outside_slab(BeamRecord::key(b.free_from), b.end_key(), ps.slab)) return;
    walk(wr, b.free_segment(), false, ps, [&](State& s, const VoxelKey&, bool) { return model_.update_free(s, b.beam); });
  }

  // True if a walk from key a to key b has no voxel in the slab (both ends beyond the same face; walks are monotone).
  [[nodiscard]] static bool outside_slab(const VoxelKey& a, const VoxelKey& b, const detail::KeySlab& sl) {
    const std::int32_t x = a[sl.axis], y = b[sl.axis];
    return (x < sl.lo && y < sl.lo) || (x >= sl.hi && y >= sl.hi);
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
  std::vector<BeamRecord, DefaultInitAllocator<BeamRecord>> beams_;  ///< the scan being integrated, per point
  unsigned last_threads_ = 1;
  std::unordered_set<std::uint64_t> touched_;
};

}  // namespace nbs
