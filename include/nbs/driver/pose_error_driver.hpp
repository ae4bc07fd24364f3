// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `PoseErrorDriver`: a ScanDriver decorator that reports every scan with erroneous poses (sim/pose_error.hpp), as a
/// robot with an absolute positioning error and a hand-eye calibration error would (Sec. 3.2.3, Sec. 5.1.1). The
/// wrapped driver measures from the true poses T; the scan handed on carries T' = E_i · T · Δ and the points
/// p' = T' · T⁻¹ · p (each sensor-frame measurement placed with the wrong pose). The truth is exposed for metrics
/// only (`last_error()`).

#include <cstdint>
#include <utility>
#include <vector>

#include "nbs/driver/concepts.hpp"
#include "nbs/sim/pose_error.hpp"

namespace nbs {

/// The truth behind the last scan of a PoseErrorDriver (for metrics; a planner must not see it).
struct PoseErrorRecord {
  std::uint64_t path_index = 0;              ///< i: 0-based count of successful acquisitions
  Pose error = Pose::Identity();             ///< E_i (world → world)
  Pose hand_eye_error = Pose::Identity();    ///< Δ (sensor frame)
  /// The true → reported map of the scan at its path start T₀: E_i · T₀ · Δ · T₀⁻¹ (= E_i without hand-eye error;
  /// with one, points of later profiles of a rotated Δ move slightly differently).
  Pose true_to_reported = Pose::Identity();
  Vec3 true_centroid = Vec3::Zero();         ///< centroid of the true points (world frame; zero for an empty scan)
};

/// Wraps `Driver` (owned; e.g. a SimulatedDriver, which is cheap to copy). Path i (counting successful
/// acquisitions) gets the error E_i = PoseErrorModel(setting).error(i, sensor origin at the path's start).
/// `move_to` and `current_pose` forward to the wrapped driver: the robot reports the commanded pose, as a real
/// robot does (its absolute error is what it cannot see), so the conformance suite holds at the wrapped driver's
/// accuracy; only the acquired scan's poses carry the error. With a zero setting the scans are bit-identical to the
/// wrapped driver's. Not thread-safe.
template <ScanDriver Driver>
class PoseErrorDriver {
public:
  /// Throws InvalidArgument for an invalid setting.
  PoseErrorDriver(Driver driver, const PoseErrorSetting& setting) : driver_(std::move(driver)), model_(setting) {}

  /// The wrapped driver's scan along `path`, reported with the erroneous poses. Throws what the wrapped driver
  /// throws (nothing changes then).
  [[nodiscard]] Scan acquire(const LinearScanPath& path) {
    Scan scan = driver_.acquire(path);
    PoseErrorRecord rec;
    rec.path_index = scans_++;
    for (const Vec3& p : scan.points) rec.true_centroid += p;
    if (!scan.empty()) rec.true_centroid /= static_cast<double>(scan.size());
    const PoseErrorSetting& s = model_.setting();
    rec.hand_eye_error = s.hand_eye_error;
    if (!s.zero()) {
      const Pose T0 = path.start().pose();
      rec.error = model_.error(rec.path_index, T0.translation());
      rec.true_to_reported = rec.error * T0 * s.hand_eye_error * T0.inverse();
      std::vector<Pose> move(scan.profile_poses.size());  // T' · T⁻¹ per profile
      for (std::size_t k = 0; k < scan.profile_poses.size(); ++k) {
        const Pose T = scan.profile_poses[k];
        scan.profile_poses[k] = rec.error * T * s.hand_eye_error;
        move[k] = scan.profile_poses[k] * T.inverse();
      }
      for (std::size_t j = 0; j < scan.points.size(); ++j) scan.points[j] = move[scan.profile_of_point[j]] * scan.points[j];
    }
    last_ = rec;
    return scan;
  }

  /// Forwards to the wrapped driver (the commanded pose; see the class comment).
  void move_to(const Pose& T_WS) { driver_.move_to(T_WS); }
  [[nodiscard]] Pose current_pose() const { return driver_.current_pose(); }

  /// The truth behind the last acquired scan (identity error before the first).
  [[nodiscard]] const PoseErrorRecord& last_error() const { return last_; }
  [[nodiscard]] const PoseErrorModel& model() const { return model_; }
  [[nodiscard]] Driver& driver() { return driver_; }
  [[nodiscard]] const Driver& driver() const { return driver_; }

private:
  Driver driver_;
  PoseErrorModel model_;
  std::uint64_t scans_ = 0;
  PoseErrorRecord last_;
};

}  // namespace nbs
