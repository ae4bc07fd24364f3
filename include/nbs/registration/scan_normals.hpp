// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Per-point normals of a scan for the ICP's normal gate (Sec. 3.2.3): principal component analysis over a cubic
/// neighbourhood in the scan itself (covariance moments summed per cell), oriented towards the sensor.

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nbs/core/detail/cell_key.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

/// The rule of estimate_scan_normals.
struct ScanNormalSetting {
  double radius_m = 0.003;          ///< half the edge of the neighbourhood cube, metres
  std::size_t min_neighbours = 6;   ///< a point needs this many scan points (itself included) in its neighbourhood
  double min_planarity = 0.05;      ///< and λ_mid / λ_max of their covariance ≥ this (not collinear, e.g. one profile)
};

/// Unit normal of every scan point (world frame), or zero for a point without one. Rule: space is divided into
/// cubic cells of edge (2/3)·radius_m (aligned to the scan's bounding-box minimum); the neighbourhood of point i is
/// the scan points in the 3 × 3 × 3 cells around its cell (a cube of edge 2·radius_m, the bounding cube of the ball
/// of radius radius_m, centred within radius_m/3 of the point); the normal is the eigenvector of the smallest
/// eigenvalue of their covariance, flipped to point towards the sensor origin `scan.origin(i)`. Point i gets no
/// normal if its neighbourhood holds fewer than `min_neighbours` points or λ_mid < min_planarity·λ_max (a line, e.g.
/// one stripe profile: radius_m must exceed the profile spacing), or if it lies more than 2²⁰ cells from the box
/// minimum. Cost O(n) (hashed cells, moments summed per cell, one 3 × 3 eigen-solve per occupied cell); deterministic.
/// Throws InvalidArgument for a radius that is not finite and > 0.
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] inline std::vector<Vec3> estimate_scan_normals(const Scan& scan, const ScanNormalSetting& s) {
  detail::require_positive("scan normal radius_m", s.radius_m);
  std::vector<Vec3> normals(scan.size(), Vec3::Zero());
  if (scan.empty()) return normals;
  const double edge = 2.0 * s.radius_m / 3.0;
  Vec3 lo = scan.points[0];
  for (const Vec3& p : scan.points) lo = lo.cwiseMin(p);

  // Moments per occupied cell, about the cell's minimum corner (small numbers: no cancellation).
  struct Cell {
    Eigen::Vector3i key;
    double count = 0.0;
    Vec3 sum = Vec3::Zero();
    Mat3 outer = Mat3::Zero();
    int state = 0;  // 0 not computed, 1 normal, 2 none
    Vec3 normal = Vec3::Zero();
  };
  std::vector<Cell> cells;
  detail::CellKeyMap index(scan.size() / 4);
  std::vector<std::uint32_t> cell_of(scan.size(), detail::CellKeyMap::kNone);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Vec3 f = ((scan.points[i] - lo) / edge).array().floor();
    // The cell and its neighbours (one more) must pack: cells ≥ 0 from the box minimum, at most kMaxCellIndex − 1.
    if (!(f.maxCoeff() < detail::kMaxCellIndex)) continue;
    const Eigen::Vector3i k = f.cast<int>();
    const auto [id, fresh] = index.try_emplace(detail::pack_cell_key(k), static_cast<std::uint32_t>(cells.size()));
    if (fresh) cells.push_back(Cell{k});
    Cell& c = cells[id];
    const Vec3 d = scan.points[i] - (lo + edge * k.cast<double>());
    c.count += 1.0;
    c.sum += d;
    c.outer.noalias() += d * d.transpose();
    cell_of[i] = id;
  }

  auto cell_normal = [&](Cell& c) {
    double count = 0.0;
    Vec3 sum = Vec3::Zero();
    Mat3 outer = Mat3::Zero();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::uint32_t found = index.find(detail::pack_cell_key(c.key + Eigen::Vector3i(dx, dy, dz)));
          if (found == detail::CellKeyMap::kNone) continue;
          const Cell& o = cells[found];
          // Moments about c's corner: d' = d + t with t the offset of o's corner.
          const Vec3 t = edge * Vec3(dx, dy, dz);
          count += o.count;
          sum += o.sum + o.count * t;
          outer += o.outer + o.sum * t.transpose() + t * o.sum.transpose() + o.count * t * t.transpose();
        }
    c.state = 2;
    if (count < static_cast<double>(s.min_neighbours)) return;
    const Vec3 mean = sum / count;
    const Mat3 cov = outer / count - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Mat3> eig;
    eig.computeDirect(cov);  // closed form for 3 × 3 (Eigen scales and shifts the matrix first); ascending
    const Vec3 lambda = eig.eigenvalues();
    if (!(lambda[2] > 0.0) || !(lambda[1] >= s.min_planarity * lambda[2])) return;
    c.normal = eig.eigenvectors().col(0).normalized();
    c.state = 1;
  };

  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (cell_of[i] == detail::CellKeyMap::kNone) continue;
    Cell& c = cells[cell_of[i]];
    if (c.state == 0) cell_normal(c);
    if (c.state != 1) continue;
    normals[i] = c.normal.dot(scan.origin(i) - scan.points[i]) < 0.0 ? Vec3(-c.normal) : c.normal;
  }
  return normals;
}

}  // namespace nbs
