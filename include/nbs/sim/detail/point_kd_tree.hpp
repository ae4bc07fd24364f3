// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// PointKdTree: an owning 3D kd-tree (nanoflann 1.4 or >= 1.5) with nearest-neighbour and "any point within r"
/// queries.

#include <nanoflann.hpp>

#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "nbs/core/types.hpp"

namespace nbs::detail {

// nanoflann 1.5 renamed SearchParams to SearchParameters (API break); the version macro tells which one this is.
#if defined(NANOFLANN_VERSION) && NANOFLANN_VERSION >= 0x150
using KdSearchParameters = nanoflann::SearchParameters;
#else
using KdSearchParameters = nanoflann::SearchParams;
#endif

/// Owns a copy of the points and a kd-tree over them. Distances are Euclidean, metres.
/// Thread-safety: const queries may run concurrently; construction/move is not concurrent with queries.
class PointKdTree {
public:
  PointKdTree() = default;
  explicit PointKdTree(std::vector<Vec3> points) : data_(std::make_unique<Data>(std::move(points))) {
    tree_ = std::make_unique<Tree>(3, *data_, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  }

  [[nodiscard]] std::size_t size() const { return data_ ? data_->points.size() : 0; }
  [[nodiscard]] const std::vector<Vec3>& points() const { return data_->points; }

  /// Index and squared distance of the nearest point; {size(), +inf} if the tree is empty.
  [[nodiscard]] std::pair<std::size_t, double> nearest(const Vec3& q) const {
    std::uint32_t index = 0;
    double dist2 = std::numeric_limits<double>::infinity();
    if (size() == 0) return {0, dist2};
    nanoflann::KNNResultSet<double, std::uint32_t> result(1);
    result.init(&index, &dist2);
    tree_->findNeighbors(result, q.data(), KdSearchParameters());
    return {index, dist2};
  }

  /// True if some point p has (p − q).squaredNorm() ≤ r² (inclusive; the same formula a brute-force check uses).
  [[nodiscard]] bool any_within(const Vec3& q, double r) const {
    if (size() == 0) return false;
    AnyWithin result{&data_->points, q, r * r};
    tree_->findNeighbors(result, q.data(), KdSearchParameters());
    return result.found;
  }

  /// Calls `f(index, squared_distance)` for every point with (p − q).squaredNorm() ≤ r² (unordered).
  template <class F>
  void for_each_within(const Vec3& q, double r, F&& f) const {
    if (size() == 0) return;
    Collect<F> result{&data_->points, q, r * r, f};
    tree_->findNeighbors(result, q.data(), KdSearchParameters());
  }

  /// Index and squared distance of the nearest point p with (p − q).squaredNorm() ≤ r² for which `accept(index)`
  /// holds; {size(), +inf} if there is none. One pruned descent: the bound shrinks only with accepted points.
  template <class Accept>
  [[nodiscard]] std::pair<std::size_t, double> nearest_within(const Vec3& q, double r, Accept&& accept) const {
    if (size() == 0) return {0, std::numeric_limits<double>::infinity()};
    NearestAccepted<Accept> result{&data_->points, q, r * r, accept};
    tree_->findNeighbors(result, q.data(), KdSearchParameters());
    return {result.found ? result.index : size(), result.best};
  }

private:
  struct Data {
    std::vector<Vec3> points;
    explicit Data(std::vector<Vec3> p) : points(std::move(p)) {}
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return points.size(); }
    [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t dim) const { return points[i][static_cast<int>(dim)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Data>, Data, 3, std::uint32_t>;

  // nanoflann result sets (duck-typed). The tree prunes with a slightly inflated bound (it accepts only
  // d² < worstDist and sums squares in its own order); the inclusive test is then redone with our formula.
  [[nodiscard]] static double prune_bound(double radius2) { return radius2 * (1.0 + 1e-9) + 1e-300; }
  struct AnyWithin {
    const std::vector<Vec3>* points;
    Vec3 q;
    double radius2;
    bool found = false;
    [[nodiscard]] std::size_t size() const { return found ? 1 : 0; }
    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return prune_bound(radius2); }
    bool addPoint(double, std::uint32_t i) {
      if (((*points)[i] - q).squaredNorm() <= radius2) found = true;
      return !found;
    }
  };
  template <class F>
  struct Collect {
    const std::vector<Vec3>* points;
    Vec3 q;
    double radius2;
    F& f;
    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return prune_bound(radius2); }
    bool addPoint(double, std::uint32_t i) {
      const double d2 = ((*points)[i] - q).squaredNorm();
      if (d2 <= radius2) f(static_cast<std::size_t>(i), d2);
      return true;
    }
  };

  template <class Accept>
  struct NearestAccepted {
    const std::vector<Vec3>* points;
    Vec3 q;
    double radius2;
    Accept& accept;
    std::size_t index = 0;
    double best = std::numeric_limits<double>::infinity();
    bool found = false;
    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return prune_bound(found ? best : radius2); }
    bool addPoint(double, std::uint32_t i) {
      const double d2 = ((*points)[i] - q).squaredNorm();
      if (d2 <= radius2 && (d2 < best || (d2 == best && i < index)) && accept(static_cast<std::size_t>(i)))
        index = i, best = d2, found = true;
      return true;
    }
  };

  std::unique_ptr<Data> data_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace nbs::detail
