// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The voxel-space contract: one concept, `VoxelSpace`, for everything a planner, a generator, a utility or a
/// collision checker reads or writes in a voxel space, and the capability concepts that unlock fast paths. Any model
/// gets a fast path by providing the capability; nbs never tests for a concrete type.
///
/// | concept | what | models |
/// |---|---|---|
/// | `VoxelSpace` | integrate scans; p / occupied / observed per key; key ↔ position; planning ray casts | ProbabilisticVoxelSpace (any backend), a user space (examples/my_voxel_space.hpp) |
/// | `BatchRayCastingSpace` | `cast_rays(rays, threads, visit)`, identical for any thread count | ProbabilisticVoxelSpace |
/// | `NoiseModelSpace` | built with a sensor-noise σ(d) (the thesis's inverse sensor model, Sec. 3.3.2) | ProbabilisticVoxelSpace<B, ThesisModel> |
/// | `ParallelIntegratingSpace` | `integrate(scan, threads)`, identical for any thread count | ProbabilisticVoxelSpace |
/// | `BlockBackend` | storage in blocks of kEdge³ voxels with per-scan touched bits and cached readers | HashedBlockBackend |
/// | `ConcurrentBlockBackend` | a BlockBackend whose threads may write disjoint blocks at once | HashedBlockBackend |
///
/// Frames: world, metres. Thread-safety of every model: const members may run concurrently; `integrate` needs
/// exclusive access.

#include <concepts>
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <vector>

#include "nbs/core/scan.hpp"
#include "nbs/core/types.hpp"
#include "nbs/space/space_types.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs {

namespace detail {
/// Planning-ray visitor that never stops early (generic over key and state types).
struct ContinueVisit {
  template <class K, class S>
  bool operator()(const K&, const S&) const {
    return true;
  }
};
/// for_each visitor used only to check the concept.
struct VoxelSink {
  template <class K, class S>
  void operator()(const K&, const S&) const {}
};
}  // namespace detail

/// A probabilistic voxel space restricted to the bounding box of the unknown area (Sec. 4.1):
/// - `S(resolution_m, unknown_area)` builds it empty (every voxel unknown);
/// - `integrate(scan)` fuses a scan (Scan::validate'd; throws InvalidArgument and changes nothing if invalid);
/// - `State` is the per-voxel state, `State{}` = unknown; `state(k)`; `model().probability(state)` (p, 0.5 when
///   unknown) and `model().occupied(state)` interpret it (`model()` may return the space itself);
/// - `probability(k)`, `probability(x)` (world point; 0.5 outside), `occupied(k)`, `observed(k)`;
/// - `grid()` (key ↔ position, l_v), `resolution_m()`, `bounds()` (the unknown area used), `voxel_bounds()` (the
///   voxels overlapping it, rays are clipped to it), `bounds_keys()` (their keys) — UnknownAreaGrid provides all;
/// - `for_each(f(key, state))` over the observed voxels;
/// - `cast_ray(ray, visit(key, state))`: the voxels on the ray inside voxel_bounds() in order, unknown ones
///   included, stopping after the first occupied one (`.hit`) or when visit returns false (nbs::walk_ray_generic
///   implements it for any space).
template <class S>
concept VoxelSpace =
    std::constructible_from<S, double, const Aabb&> && std::default_initializable<typename S::State> &&
    requires(S& s, const S& cs, const Scan& scan, const VoxelKey& k, const Vec3& x, const Ray& r,
             const typename S::State& st, detail::ContinueVisit visit, detail::VoxelSink sink) {
      { s.integrate(scan) } -> std::convertible_to<IntegrationStats>;
      { cs.grid() } -> std::convertible_to<const VoxelGrid&>;
      { cs.resolution_m() } -> std::convertible_to<double>;
      { cs.bounds() } -> std::convertible_to<const Aabb&>;
      { cs.voxel_bounds() } -> std::convertible_to<const Aabb&>;
      { cs.bounds_keys() } -> std::convertible_to<KeyBox>;
      { cs.state(k) } -> std::convertible_to<typename S::State>;
      { cs.model().probability(st) } -> std::convertible_to<double>;
      { cs.model().occupied(st) } -> std::convertible_to<bool>;
      { cs.probability(k) } -> std::convertible_to<double>;
      { cs.probability(x) } -> std::convertible_to<double>;
      { cs.occupied(k) } -> std::convertible_to<bool>;
      { cs.observed(k) } -> std::convertible_to<bool>;
      cs.for_each(sink);
      { cs.cast_ray(r, visit) } -> std::convertible_to<RaycastResult>;
    };

/// Capability: many planning rays at once on `threads` std::threads, visit(ray_index, key, state) called
/// concurrently for different rays and in order within one; results identical for any thread count.
template <class S>
concept BatchRayCastingSpace =
    VoxelSpace<S> && requires(const S& cs, std::span<const Ray> rays, unsigned threads,
                              bool (*visit)(std::size_t, const VoxelKey&, const typename S::State&)) {
      { cs.cast_rays(rays, threads, visit) } -> std::convertible_to<std::vector<RaycastResult>>;
    };

/// Capability: `integrate(scan, threads)` fuses a scan on `threads` std::threads (0 = hardware concurrency) with the
/// same voxel states and IntegrationStats as `integrate(scan)`, for any thread count.
template <class S>
concept ParallelIntegratingSpace = VoxelSpace<S> && requires(S& s, const Scan& scan, unsigned threads) {
  { s.integrate(scan, threads) } -> std::convertible_to<IntegrationStats>;
};

/// `space.integrate(scan, threads)` where the space has it (ParallelIntegratingSpace), else `space.integrate(scan)`.
template <VoxelSpace S>
IntegrationStats integrate_scan(S& space, const Scan& scan, unsigned threads) {
  if constexpr (ParallelIntegratingSpace<S>) {
    return space.integrate(scan, threads);
  } else {
    (void)threads;
    return space.integrate(scan);
  }
}

/// Capability: the space can be built as S(l_v, box, ModelType(setting)) with the range noise σ(d) of the sensor
/// (`setting.sigma_m`, metres → metres), which its inverse sensor model uses (the thesis model, Sec. 3.3.2). The planner builds such a space with its sensor's σ(d).
template <class S>
concept NoiseModelSpace =
    VoxelSpace<S> && requires { typename S::ModelType::Setting; } &&
    requires(typename S::ModelType::Setting st, std::function<double(double)> sigma) {
      st.sigma_m = sigma;
      requires std::constructible_from<S, double, const Aabb&, typename S::ModelType>;
      requires std::constructible_from<typename S::ModelType, typename S::ModelType::Setting>;
    };

/// Capability of a storage backend: voxels in blocks of kEdge³ (kEdge = 2^kEdgeBits) with a per-scan "touched" bit,
/// which lets ProbabilisticVoxelSpace update and ray-cast block by block (one lookup per block entered, a bit test
/// per revisited voxel) instead of one lookup per voxel:
/// - `B::Block`: `get(i)`, `put(i, s)`, `touch(i)` (sets the bit, true if it was clear), `is_touched(i)`;
/// - `B::block_id(key)`, `B::local_index(key)` (static); `b.block(id)` → Block& (allocated or reloaded);
///   `b.note_observed(block, i)`; `b.next_epoch()` clears every touched bit; `b.end_scan()` after a scan (e.g. flush);
/// - `B::BasicReader<CacheBits>(b).find(id)` → const Block* (nullptr = never written), one reader per thread.
template <class B>
concept BlockBackend =
    requires { typename B::Block; typename B::State; typename B::template BasicReader<0>; } &&
    requires(B& b, const B& cb, typename B::Block& blk, const typename B::Block& cblk, const VoxelKey& k,
             std::uint64_t id, int i, const typename B::State& s, typename B::template BasicReader<0>& rd) {
      { B::kEdgeBits } -> std::convertible_to<int>;
      { B::kEdge } -> std::convertible_to<int>;
      { B::block_id(k) } -> std::convertible_to<std::uint64_t>;
      { B::local_index(k) } -> std::convertible_to<int>;
      { b.block(id) } -> std::same_as<typename B::Block&>;
      b.note_observed(blk, i);
      b.next_epoch();
      b.end_scan();
      { cblk.get(i) } -> std::convertible_to<typename B::State>;
      blk.put(i, s);
      { blk.touch(i) } -> std::convertible_to<bool>;
      { cblk.is_touched(i) } -> std::convertible_to<bool>;
      { rd.find(id) } -> std::convertible_to<const typename B::Block*>;
    };

/// Capability of a BlockBackend: threads that write disjoint sets of blocks may do so at once, each through its own
/// `B::ConcurrentWriter w(b, mutex)` (one std::mutex shared by them): `w.block(id)` → Block& (as b.block(id)),
/// `w.note_observed(block, i)`, and `w.commit()` when the thread's writes are done. Until every writer has committed,
/// nothing else may use b.
template <class B>
concept ConcurrentBlockBackend =
    BlockBackend<B> && std::constructible_from<typename B::ConcurrentWriter, B&, std::mutex&> &&
    requires(typename B::ConcurrentWriter& w, std::uint64_t id, typename B::Block& blk, int i) {
      { w.block(id) } -> std::same_as<typename B::Block&>;
      w.note_observed(blk, i);
      w.commit();
    };

}  // namespace nbs
