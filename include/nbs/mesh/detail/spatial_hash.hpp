#pragma once
/// \file
/// Spatial hash grid of point ids for ball queries. Cells are cubes of edge `cell_m`; the table is open-addressing
/// (linear probing) keyed by packed integer cell coordinates. With the density limitation (no two points closer
/// than R_r) a cell holds at most O((cell_m / R_r)^3) points, so a ball query costs O(1) independent of the number
/// of stored points. Not thread-safe.

#include <cmath>
#include <cstdint>
#include <vector>

#include "nbs/core/types.hpp"

namespace nbs::detail {

class SpatialHash {
public:
  explicit SpatialHash(double cell_m = 0.003) : cell_m_(cell_m), inv_cell_(1.0 / cell_m) { rehash(1024); }

  [[nodiscard]] double cell_size() const { return cell_m_; }

  /// Adds point `id` at `p`.
  void insert(const Vec3& p, std::uint32_t id) {
    const std::uint64_t key = key_of(cell_of(p));
    if (2 * (used_ + 1) > keys_.size()) rehash(keys_.size() * 2);
    std::size_t slot = find_slot(key);
    if (keys_[slot] == kEmpty) {
      keys_[slot] = key;
      bucket_of_slot_[slot] = static_cast<std::uint32_t>(buckets_.size());
      buckets_.emplace_back();
      ++used_;
    }
    buckets_[bucket_of_slot_[slot]].push_back(id);
  }

  /// Calls `f(id)` for every stored id whose cell intersects the axis-aligned cube of half-size `r` around `p`.
  /// The caller filters by exact distance.
  template <class F>
  void for_each_candidate(const Vec3& p, double r, F&& f) const {
    const Eigen::Vector3i lo = cell_of(p - Vec3::Constant(r));
    const Eigen::Vector3i hi = cell_of(p + Vec3::Constant(r));
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z) {
          const std::size_t slot = find_slot(key_of(Eigen::Vector3i(x, y, z)));
          if (keys_[slot] == kEmpty) continue;
          for (std::uint32_t id : buckets_[bucket_of_slot_[slot]]) f(id);
        }
  }

  /// Heap bytes used by the table and the buckets (approximate: capacity-based).
  [[nodiscard]] std::size_t memory_bytes() const {
    std::size_t b = keys_.capacity() * sizeof(std::uint64_t) + bucket_of_slot_.capacity() * sizeof(std::uint32_t) +
                    buckets_.capacity() * sizeof(std::vector<std::uint32_t>);
    for (const auto& v : buckets_) b += v.capacity() * sizeof(std::uint32_t);
    return b;
  }

private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  [[nodiscard]] Eigen::Vector3i cell_of(const Vec3& p) const {
    // Coordinates are clamped to ±2^20 cells (±3 km at 3 mm): far beyond any workspace, keeps the key packing valid.
    auto c = [this](double v) {
      double f = std::floor(v * inv_cell_);
      if (std::isnan(f)) f = 0.0;  // callers never pass NaN; this only keeps the cast defined.
      return static_cast<int>(f < -1048575.0 ? -1048575.0 : (f > 1048575.0 ? 1048575.0 : f));
    };
    return {c(p.x()), c(p.y()), c(p.z())};
  }
  [[nodiscard]] static std::uint64_t key_of(const Eigen::Vector3i& c) {
    constexpr std::uint64_t mask = (std::uint64_t{1} << 21) - 1;
    return ((static_cast<std::uint64_t>(c.x() + 1048576) & mask) << 42) |
           ((static_cast<std::uint64_t>(c.y() + 1048576) & mask) << 21) |
           (static_cast<std::uint64_t>(c.z() + 1048576) & mask);
  }
  [[nodiscard]] std::size_t find_slot(std::uint64_t key) const {
    std::uint64_t h = key * 0x9E3779B97F4A7C15ull;
    h ^= h >> 29;
    const std::size_t m = keys_.size() - 1;
    std::size_t s = static_cast<std::size_t>(h) & m;
    while (keys_[s] != kEmpty && keys_[s] != key) s = (s + 1) & m;
    return s;
  }
  void rehash(std::size_t capacity) {
    std::vector<std::uint64_t> old_keys(capacity, kEmpty);
    std::vector<std::uint32_t> old_bucket(capacity, 0);
    old_keys.swap(keys_);
    old_bucket.swap(bucket_of_slot_);
    for (std::size_t i = 0; i < old_keys.size(); ++i) {
      if (old_keys[i] == kEmpty) continue;
      const std::size_t s = find_slot(old_keys[i]);
      keys_[s] = old_keys[i];
      bucket_of_slot_[s] = old_bucket[i];
    }
  }

  double cell_m_;
  double inv_cell_;
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> bucket_of_slot_;
  std::vector<std::vector<std::uint32_t>> buckets_;
  std::size_t used_ = 0;
};

}  // namespace nbs::detail
