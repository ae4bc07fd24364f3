// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// A read-only snapshot of a voxel space for candidate evaluation: for every voxel of the bounding box of the unknown
/// area (`bounds_keys()`) a class id into a small table of what a VoxelVisit needs (p, H(p), occupied, observed,
/// surface features), and a planning ray cast over it that visits exactly the voxels `space.cast_ray` visits, in the
/// same order, with the same stop rule. It replaces, per visited voxel, the block hash lookup, the observed lookup,
/// the log/exp of the occupancy and the log₂ of the entropy by two array loads.
///
/// Built from the VoxelSpace contract only (`bounds_keys`, `voxel_bounds`, `for_each`, `model`, `grid`), the surface
/// features the caller passes, and the exact DDA every planning cast uses (space/ray_traversal.hpp, ray_cast.hpp).
/// Relies on the backend contract that a never-written (unobserved) voxel reads as `State{}`. Not built (`enabled()`
/// false) when the box has more than `kMaxVoxels` voxels or when the model calls `State{}` occupied; the evaluator then
/// uses `space.cast_ray` with per-voxel lookups.

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/space/concepts.hpp"
#include "nbs/space/ray_cast.hpp"
#include "nbs/space/ray_traversal.hpp"
#include "nbs/space/surface_features.hpp"
#include "nbs/utility/utility_function.hpp"

namespace nbs::detail {

/// Everything a VoxelVisit takes from the voxel itself.
struct VoxelClass {
  double probability = 0.5;                    ///< model().probability(state)
  double entropy_bits = 1.0;                   ///< voxel_entropy(probability)
  const SurfaceFeatures* features = nullptr;   ///< features().find(key) if occupied, else nullptr
  bool occupied = false;                       ///< model().occupied(state)
  bool observed = false;                       ///< space.observed(key)
};

/// One bit per voxel of the snapshot box: the per-candidate visited marking of Sec. 4.5.3. One per thread.
class VisitedBits {
public:
  void reset(std::size_t voxels) {
    words_.assign((voxels + 63) / 64, 0);
  }
  /// Sets bit i; returns true if it was clear.
  bool insert(std::size_t i) {
    std::uint64_t& w = words_[i >> 6];
    const std::uint64_t bit = std::uint64_t{1} << (i & 63);
    const bool fresh = (w & bit) == 0;
    w |= bit;
    return fresh;
  }
  /// The bit words (bit i of the box index i lives in word i / 64, bit i % 64).
  [[nodiscard]] std::uint64_t* words() { return words_.data(); }

private:
  std::vector<std::uint64_t> words_;
};

template <class Space>
class PlanningSnapshot {
public:
  using State = typename Space::State;
  /// Largest box (voxels) that is snapshotted: 2^24 voxels = 64 MiB of class ids.
  static constexpr std::uint64_t kMaxVoxels = std::uint64_t{1} << 24;

  /// A disabled snapshot.
  PlanningSnapshot() = default;
  /// Snapshot of `space` with the surface features of `features` (may be nullptr: none).
  explicit PlanningSnapshot(const Space& space, const SurfaceFeatureMap* features = nullptr) : space_(&space) {
    build(features);
  }

  /// False: use space.cast_ray instead (see file comment).
  [[nodiscard]] bool enabled() const { return enabled_; }
  /// Voxels in the box (valid if enabled()).
  [[nodiscard]] std::size_t voxel_count() const { return ids_.size(); }
  /// Number of distinct voxel classes.
  [[nodiscard]] std::size_t class_count() const { return classes_.size(); }

  /// True if key k lies in the box (always false if not enabled()).
  [[nodiscard]] bool contains(const VoxelKey& k) const { return enabled_ && box_.contains(k); }
  /// Index of key k in the box. Precondition: contains(k).
  [[nodiscard]] std::size_t index_of(const VoxelKey& k) const { return index(k); }

  /// True if every voxel a cast of `ray` can visit lies in the box, so `cast` may be used. Precondition: enabled().
  /// Rays are clipped exactly as ProbabilisticVoxelSpace::cast_ray does it.
  struct Clipped {
    bool meets = false;        ///< the ray meets voxel_bounds()
    bool inside = false;       ///< both end keys of the clipped segment lie in the box
    SegmentSetup::Fixed a{}, b{};  ///< clipped end points, DDA fixed point (SegmentSetup::to_fixed of voxel units)
  };
  [[nodiscard]] Clipped clip(const Ray& ray) const {
    Clipped c;
    double t0, t1;
    if (!clip_segment(ray.origin, ray.end, vbounds_, t0, t1)) return c;
    c.meets = true;
    c.a = SegmentSetup::to_fixed(Vec3(point_in_box(ray.origin, ray.end, t0, vbounds_) * inv_));
    c.b = SegmentSetup::to_fixed(Vec3(point_in_box(ray.origin, ray.end, t1, vbounds_) * inv_));
    c.inside = key_in_box(c.a) && key_in_box(c.b);
    return c;
  }

  /// Casts a clipped segment (clip(ray).inside): visit(key, const VoxelClass&, box index) for each voxel in order
  /// until the first occupied one (hit) or until visit returns false. The DDA visits keys monotonically per axis
  /// from the start key to the end key, so every key lies in the box.
  template <class Visit>
  [[gnu::flatten]] RaycastResult cast(const Clipped& c, Visit&& visit) const {
    const std::uint32_t* ids = ids_.data();
    const VoxelClass* classes = classes_.data();
    auto at = [&](const std::int32_t (&k)[3], std::size_t idx, std::uint32_t) {
      const VoxelClass& vc = classes[ids[idx]];
      if (!visit(VoxelKey{k[0], k[1], k[2]}, vc, idx)) return Step::stop;
      return vc.occupied ? Step::hit : Step::next;
    };
    return walk(c, at);
  }

  /// The walk of cast() (same voxels, order and stop rule) for a visitor that needs only the first visit of each
  /// voxel per candidate: `first(key, const VoxelClass&, n)` is called for the voxels whose bit in `visited` is clear
  /// (the bit is then set), n being the voxel's position along the ray (0 for the first). Voxels already marked are
  /// stepped over without a class lookup (the stop test reads a bit set of the occupied voxels). res.voxels counts
  /// every voxel stepped into.
  template <class First>
  [[gnu::flatten]] RaycastResult cast_first_visits(const Clipped& c, VisitedBits& visited, First&& first) const {
    std::uint64_t* seen = visited.words();
    const std::uint64_t* occupied = occupied_.data();
    const std::uint32_t* ids = ids_.data();
    const VoxelClass* classes = classes_.data();
    auto at = [&](const std::int32_t (&k)[3], std::size_t idx, std::uint32_t n) {
      const std::size_t word = idx >> 6;
      const std::uint64_t bit = std::uint64_t{1} << (idx & 63);
      if ((seen[word] & bit) == 0) {
        seen[word] |= bit;
        first(VoxelKey{k[0], k[1], k[2]}, classes[ids[idx]], n);
      }
      return (occupied[word] & bit) != 0 ? Step::hit : Step::next;
    };
    return walk(c, at);
  }

private:
  /// What the policy of walk() answers for the voxel the walk is at.
  enum class Step { next, stop, hit };

  /// The one walk of cast() and cast_first_visits(): at(key, box index, n) for each voxel of the clipped segment in
  /// order (n: position along the ray, 0 for the first) until it answers stop or hit or the end voxel is reached.
  /// res.voxels counts the voxels at() was called for; res.hit / hit_key are set if it answered hit. Steps with
  /// CommonDenominatorStepper where make() allows, else SegmentWalker (the same voxels; tests/space/test_dda.cpp).
  /// The key is an int32[3], not a VoxelKey, so that k[axis] compiles without branches on the axis. `gnu::flatten`
  /// on the callers inlines the stepper and the policy into the loop.
  template <class At>
  RaycastResult walk(const Clipped& c, At& at) const {
    const SegmentSetup q(c.a, c.b);
    if (const auto fast = CommonDenominatorStepper::make(q)) return walk_steps(*fast, q, at);
    return walk_steps(SegmentWalker(q), q, at);
  }
  template <class Stepper, class At>
  RaycastResult walk_steps(Stepper st, const SegmentSetup& q, At& at) const {
    std::int32_t k[3] = {q.key.x, q.key.y, q.key.z};
    std::size_t idx = index(q.key);
    const std::ptrdiff_t delta[3] = {q.sign[0], q.sign[1] * static_cast<std::ptrdiff_t>(nx_),
                                     q.sign[2] * static_cast<std::ptrdiff_t>(nx_ * ny_)};
    const auto steps = static_cast<std::uint32_t>(q.steps());
    for (std::uint32_t n = 0;; ++n) {
      const Step s = at(k, idx, n);
      if (s != Step::next || n == steps) {
        RaycastResult res;
        res.voxels = n + 1;
        if (s == Step::hit) {
          res.hit = true;
          res.hit_key = VoxelKey{k[0], k[1], k[2]};
        }
        return res;
      }
      const int a = st.step();
      k[a] += q.sign[a];
      idx = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(idx) + delta[a]);
    }
  }

  void build(const SurfaceFeatureMap* features) {
    const Space& s = *space_;
    const auto& model = s.model();
    if (model.occupied(State{})) return;
    box_ = s.bounds_keys();
    if (box_.empty()) return;
    nx_ = static_cast<std::uint64_t>(box_.max.x - box_.min.x) + 1;
    ny_ = static_cast<std::uint64_t>(box_.max.y - box_.min.y) + 1;
    const std::uint64_t nz = static_cast<std::uint64_t>(box_.max.z - box_.min.z) + 1;
    if (nx_ > kMaxVoxels || ny_ > kMaxVoxels || nz > kMaxVoxels || nx_ * ny_ * nz > kMaxVoxels) return;
    vbounds_ = s.voxel_bounds();
    inv_ = s.grid().inverse_resolution();
    ids_.assign(nx_ * ny_ * nz, 0u);
    classes_.clear();
    classes_.push_back(unknown_class());  // class 0: never observed
    // Voxels with equal (p, occupied, features) share a class; surface voxels (features) are usually unique.
    struct Key {
      std::uint64_t p_bits;
      const SurfaceFeatures* f;
      bool occupied;
      bool operator==(const Key&) const = default;
    };
    struct KeyHash {
      std::size_t operator()(const Key& k) const {
        return static_cast<std::size_t>((k.p_bits ^ reinterpret_cast<std::uintptr_t>(k.f) ^ (k.occupied ? 1u : 0u)) *
                                        0x9E3779B97F4A7C15ull);
      }
    };
    std::unordered_map<Key, std::uint32_t, KeyHash> index_of;
    const bool have_features = features != nullptr && features->size() > 0;
    bool ok = true;
    s.for_each([&](const VoxelKey& k, const State& st) {
      if (!box_.contains(k) || !ok) return;
      const bool occ = model.occupied(st);
      const SurfaceFeatures* f = (have_features && occ) ? features->find(k) : nullptr;
      const double p = model.probability(st);
      std::uint64_t bits;
      std::memcpy(&bits, &p, sizeof bits);
      const auto [it, fresh] = index_of.try_emplace(Key{bits, f, occ}, static_cast<std::uint32_t>(classes_.size()));
      if (fresh) {
        if (classes_.size() == std::numeric_limits<std::uint32_t>::max()) {
          ok = false;
          return;
        }
        classes_.push_back(observed_class(p, occ, f));
      }
      ids_[index(k)] = it->second;
    });
    if (!ok) {
      ids_.clear();
      classes_.clear();
      return;
    }
    occupied_.assign((ids_.size() + 63) / 64, 0);
    for (std::size_t i = 0; i < ids_.size(); ++i)
      if (classes_[ids_[i]].occupied) occupied_[i >> 6] |= std::uint64_t{1} << (i & 63);
    enabled_ = true;
  }

  [[nodiscard]] VoxelClass unknown_class() const {
    VoxelClass c = observed_class(space_->model().probability(State{}), false, nullptr);
    c.observed = false;
    return c;
  }
  [[nodiscard]] static VoxelClass observed_class(double p, bool occupied, const SurfaceFeatures* f) {
    VoxelClass c;
    c.probability = p;
    c.entropy_bits = voxel_entropy(p);
    c.features = f;
    c.occupied = occupied;
    c.observed = true;
    return c;
  }

  [[nodiscard]] bool key_in_box(const SegmentSetup::Fixed& f) const {
    for (int a = 0; a < 3; ++a) {
      const std::int32_t k = SegmentSetup::key_of_fixed(f[static_cast<std::size_t>(a)]);
      if (k < box_.min[a] || k > box_.max[a]) return false;
    }
    return true;
  }
  [[nodiscard]] std::size_t index(const VoxelKey& k) const {
    return static_cast<std::size_t>(static_cast<std::uint64_t>(k.x - box_.min.x) +
                                    nx_ * (static_cast<std::uint64_t>(k.y - box_.min.y) +
                                           ny_ * static_cast<std::uint64_t>(k.z - box_.min.z)));
  }

  const Space* space_ = nullptr;
  bool enabled_ = false;
  KeyBox box_;
  Aabb vbounds_;
  double inv_ = 1.0;
  std::uint64_t nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> ids_;
  std::vector<VoxelClass> classes_;
  std::vector<std::uint64_t> occupied_;  // one bit per box voxel: classes_[ids_[i]].occupied
};

}  // namespace nbs::detail
