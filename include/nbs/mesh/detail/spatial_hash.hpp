// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Spatial hash grid of point ids for ball queries. Cells are cubes of edge `cell_m`, grouped in blocks of 4×4×4
/// cells; an open-addressing table (linear probing) keyed by packed integer block coordinates holds, per block, the
/// index of each cell's list of points (id and a copy of the position, so a query touches only its cells). A query
/// walks its cells in (x, y, z) order and looks a block up once for its run of cells, so neighbouring cells cost
/// an array read instead of a hash probe. With the density limitation (no two points closer than R_r) a cell holds
/// at most O((cell_m / R_r)^3) points, so a ball query costs O(1) independent of the number of stored points.
/// Not thread-safe.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "nbs/core/detail/cell_key.hpp"
#include "nbs/core/types.hpp"

namespace nbs::detail {

class SpatialHash {
  /// Largest |cell index| on an axis: 2^20 − 1 = kMaxCellIndex, so that every (clamped) cell packs (cell_key.hpp).
  static constexpr double kMaxCell = kMaxCellIndex;

public:
  explicit SpatialHash(double cell_m = 0.003) : cell_m_(cell_m), inv_cell_(1.0 / cell_m), slots_(128) {}

  [[nodiscard]] double cell_size() const { return cell_m_; }

  /// Largest |coordinate| (m, each axis) of a point at cells of `cell_m`: half the ±(2^20 − 1) cells of the key
  /// packing, so that the cells of any query ball of radius < that around the point are still distinct (beyond
  /// it cells are clamped onto the edge of the range and share it).
  [[nodiscard]] static double max_abs_coordinate(double cell_m) { return 0.5 * (kMaxCell - 1.0) * cell_m; }
  /// True if every coordinate of `p` is within ±max_abs_coordinate(cell_size()) (false for NaN).
  [[nodiscard]] bool in_range(const Vec3& p) const {
    return (p.array().abs() <= max_abs_coordinate(cell_m_)).all();
  }

  /// Adds point `id` at `p`.
  void insert(const Vec3& p, std::uint32_t id) {
    const Eigen::Vector3i c = cell_of(p);
    const auto [block, fresh] =
        slots_.try_emplace(pack_cell_key(block_of(c)), static_cast<std::uint32_t>(blocks_.size()));
    if (fresh) {
      blocks_.emplace_back();
      blocks_.back().fill(0);
    }
    std::uint32_t& bucket = blocks_[block][local_of(c)];
    if (bucket == 0) {
      buckets_.emplace_back();
      bucket = static_cast<std::uint32_t>(buckets_.size());
    }
    buckets_[bucket - 1].push_back({p, id});
  }

  /// Key of the cell of `p`; keys grow with the cells' (x, y, z) in lexicographic order.
  [[nodiscard]] std::uint64_t cell_key(const Vec3& p) const { return pack_cell_key(cell_of(p)); }

  /// Calls `f(id, position)` for every stored point whose cell intersects the ball of radius `r` around `p` (cells
  /// are visited in x, y, z order, i.e. by ascending cell_key(), points of a cell in insertion order). The caller
  /// filters by exact distance.
  template <class F>
  void for_each_candidate(const Vec3& p, double r, F&& f) const {
    const Eigen::Vector3i lo = cell_of(p - Vec3::Constant(r));
    const Eigen::Vector3i hi = cell_of(p + Vec3::Constant(r));
    // A cell is skipped when its box (grown by a relative 1e-6 against rounding in cell_of) is farther than r.
    const double r2 = r * r, grow = 1e-6 * cell_m_;
    auto gap = [&](int c, double v) {
      const double lo_c = c * cell_m_ - grow, hi_c = (c + 1) * cell_m_ + grow;
      return v < lo_c ? lo_c - v : (v > hi_c ? v - hi_c : 0.0);
    };
    // Squared z gaps once per query (the same values as computed per cell).
    constexpr int kSpan = 16;
    const int nz = hi.z() - lo.z() + 1;
    std::array<double, kSpan> gz2{};
    const bool cached = nz <= kSpan;
    CellLookup lookup{*this};
    if (cached)
      for (int k = 0; k < nz; ++k) gz2[static_cast<std::size_t>(k)] = square(gap(lo.z() + k, p.z()));
    for (int x = lo.x(); x <= hi.x(); ++x) {
      const double gx = gap(x, p.x());
      for (int y = lo.y(); y <= hi.y(); ++y) {
        const double gxy = gx * gx + square(gap(y, p.y()));
        if (gxy > r2) continue;
        for (int z = lo.z(); z <= hi.z(); ++z) {
          if (gxy + (cached ? gz2[static_cast<std::size_t>(z - lo.z())] : square(gap(z, p.z()))) > r2) continue;
          const std::vector<Entry>* cell = lookup.cell(Eigen::Vector3i(x, y, z));
          if (cell == nullptr) continue;
          for (const Entry& e : *cell) f(e.id, e.p);
        }
      }
    }
  }

  /// True if `pred(id, position)` holds for some stored point whose cell intersects the cube of half-size `r` around `p`. The
  /// cell of `p` is probed first and the search stops at the first hit, so a point inside a dense region costs one
  /// probe.
  template <class Pred>
  [[nodiscard]] bool any_candidate(const Vec3& p, double r, Pred&& pred) const {
    CellLookup lookup{*this};
    const Eigen::Vector3i c = cell_of(p);
    if (any_in(lookup.cell(c), pred)) return true;
    const Eigen::Vector3i lo = cell_of(p - Vec3::Constant(r));
    const Eigen::Vector3i hi = cell_of(p + Vec3::Constant(r));
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z) {
          const Eigen::Vector3i k(x, y, z);
          if (k != c && any_in(lookup.cell(k), pred)) return true;
        }
    return false;
  }

  /// True if `pred(id, position)` holds for some stored point within `r` of the segment from `p - h·dir` to
  /// `p + h·dir` (`dir` unit, h ≥ 0) — `pred` may be called for farther points too and decides. The cell of `p` is
  /// probed first and the search stops at the first hit. Only cells whose centre lies within r + half the cell
  /// diagonal of the segment are probed (a thin cylinder touches a few cells of its bounding cube).
  template <class Pred>
  [[nodiscard]] bool any_candidate_near_segment(const Vec3& p, const Vec3& dir, double h, double r,
                                                Pred&& pred) const {
    CellLookup lookup{*this};
    const Eigen::Vector3i c = cell_of(p);
    if (any_in(lookup.cell(c), pred)) return true;
    const Vec3 ext = dir.cwiseAbs() * h + Vec3::Constant(r);
    const Eigen::Vector3i lo = cell_of(p - ext);
    const Eigen::Vector3i hi = cell_of(p + ext);
    const double reach = r + 0.5 * std::sqrt(3.0) * cell_m_ * (1.0 + 1e-6), reach2 = reach * reach;
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z) {
          const Eigen::Vector3i k(x, y, z);
          if (k == c) continue;
          const Vec3 d = (k.cast<double>() + Vec3::Constant(0.5)) * cell_m_ - p;
          const double t = std::clamp(d.dot(dir), -h, h);
          if ((d - t * dir).squaredNorm() > reach2) continue;
          if (any_in(lookup.cell(k), pred)) return true;
        }
    return false;
  }

  /// Heap bytes used by the table and the buckets (approximate: capacity-based).
  [[nodiscard]] std::size_t memory_bytes() const {
    std::size_t b = slots_.memory_bytes() + blocks_.capacity() * sizeof(Block) +
                    buckets_.capacity() * sizeof(std::vector<Entry>);
    for (const auto& v : buckets_) b += v.capacity() * sizeof(Entry);
    return b;
  }

private:
  /// A stored point.
  struct Entry {
    Vec3 p;
    std::uint32_t id;
  };
  /// Per cell of a 4×4×4 block: 1 + index of its list in buckets_, 0 = no point.
  using Block = std::array<std::uint32_t, 64>;

  /// Cell lookups of one query: remembers the last block looked up (a query's cells come in runs per block).
  struct CellLookup {
    const SpatialHash& h;
    std::uint64_t key = ~std::uint64_t{0};  // no packed key
    const Block* block = nullptr;
    /// The points of cell c, or nullptr if it has none.
    [[nodiscard]] const std::vector<Entry>* cell(const Eigen::Vector3i& c) {
      const std::uint64_t k = pack_cell_key(block_of(c));
      if (k != key) {
        key = k;
        const std::uint32_t b = h.slots_.find(k);
        block = b == CellKeyMap::kNone ? nullptr : &h.blocks_[b];
      }
      if (block == nullptr) return nullptr;
      const std::uint32_t b = (*block)[local_of(c)];
      return b == 0 ? nullptr : &h.buckets_[b - 1];
    }
  };

  [[nodiscard]] static double square(double v) { return v * v; }

  template <class Pred>
  [[nodiscard]] static bool any_in(const std::vector<Entry>* cell, Pred& pred) {
    if (cell == nullptr) return false;
    for (const Entry& e : *cell)
      if (pred(e.id, e.p)) return true;
    return false;
  }
  /// Block of cell c (floor division by 4 per axis) and c's index in it.
  [[nodiscard]] static Eigen::Vector3i block_of(const Eigen::Vector3i& c) {
    return {c.x() >> 2, c.y() >> 2, c.z() >> 2};
  }
  [[nodiscard]] static std::size_t local_of(const Eigen::Vector3i& c) {
    return static_cast<std::size_t>((c.x() & 3) | ((c.y() & 3) << 2) | ((c.z() & 3) << 4));
  }

  [[nodiscard]] Eigen::Vector3i cell_of(const Vec3& p) const {
    // Cells are clamped to ±kMaxCell (±3 km at 3 mm) to keep the key packing and the cast defined; callers keep
    // their points in_range() (half of that), so only query boxes ever reach the clamp.
    auto c = [this](double v) {
      double f = std::floor(v * inv_cell_);
      if (std::isnan(f)) f = 0.0;  // callers never pass NaN; this only keeps the cast defined.
      return static_cast<int>(f < -kMaxCell ? -kMaxCell : (f > kMaxCell ? kMaxCell : f));
    };
    return {c(p.x()), c(p.y()), c(p.z())};
  }

  double cell_m_;
  double inv_cell_;
  CellKeyMap slots_;                         ///< packed block key → index in blocks_
  std::vector<Block> blocks_;
  std::vector<std::vector<Entry>> buckets_;  ///< the points of each non-empty cell
};

}  // namespace nbs::detail
