// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `ReplayDriver`: a `ScanDriver` that hands back the scans of a recorded session (io/session.hpp,
/// docs/session-format.md) in order, and checks that the loop asks for the path that was recorded.

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "nbs/core/error.hpp"
#include "nbs/driver/concepts.hpp"
#include "nbs/io/session.hpp"

namespace nbs {

/// How far a requested path may be from the recorded one. Sessions written by nbs store paths with 17 digits (bit
/// exact), so the defaults only absorb rounding of a re-planned path; a different plan is far outside them.
struct ReplayTolerance {
  double position_m = 1e-6;  ///< bound on |start − recorded start| and on |end − recorded end|, metres
  double angle_rad = 1e-6;   ///< bound on the rotation angle between the requested and the recorded start pose

  void validate() const {
    detail::require(std::isfinite(position_m) && position_m >= 0.0,
                    "ReplayTolerance.position_m must be finite and >= 0, got ", position_m);
    detail::require(std::isfinite(angle_rad) && angle_rad >= 0.0,
                    "ReplayTolerance.angle_rad must be finite and >= 0, got ", angle_rad);
  }
};

/// Replays a session: the i-th `acquire` returns the i-th recorded scan. If that scan has a recorded path, the
/// requested path must match it within the tolerance (start position, start rotation, end position), else
/// InvalidArgument naming the scan, both paths and the deviation; a scan recorded without a path is handed back
/// for any path. Asking for more scans than recorded throws InvalidArgument naming both counts. A throwing call
/// changes nothing. The robot is ideal: `move_to` reaches the pose exactly; after a scan the sensor rests at the
/// end of the recorded path (the requested one if none was recorded). Not thread-safe.
class ReplayDriver {
public:
  /// Replays `session` (`name` appears in messages). Throws InvalidArgument if it has no scans, the tolerance is
  /// invalid, or `home` (the initial T_WS) is not finite and rigid.
  explicit ReplayDriver(RecordedSession session, const ReplayTolerance& tolerance = {},
                        const Pose& home = Pose::Identity(), std::string name = "recorded session")
      : session_(std::move(session)), tol_(tolerance), pose_(home), name_(std::move(name)) {
    tol_.validate();
    validate_pose(home, "ReplayDriver: home pose");
    detail::require(!session_.scans.empty(), "ReplayDriver: ", name_, " has no scans to replay");
  }

  /// Reads the session in `dir` (read_session: FileError for anything wrong with it), then as above.
  explicit ReplayDriver(const std::filesystem::path& dir, const ReplayTolerance& tolerance = {},
                        const Pose& home = Pose::Identity())
      : ReplayDriver(read_session(dir), tolerance, home, dir.string()) {}

  /// The next recorded scan (see the class comment for the checks).
  [[nodiscard]] Scan acquire(const LinearScanPath& path) {
    const std::size_t i = next_;
    detail::require(i < session_.scans.size(), "ReplayDriver: scan ", i + 1, " requested, but ", name_, " has only ",
                    session_.scans.size(), " scans");
    const RecordedScan& rec = session_.scans[i];
    if (rec.path) check_path(i, path, *rec.path);
    pose_ = (rec.path ? *rec.path : path).pose_at(1.0);
    ++next_;
    return rec.scan;
  }

  /// Exact: `current_pose()` becomes `T_WS`. Throws InvalidArgument (naming the pose) if it is not finite and rigid.
  void move_to(const Pose& T_WS) {
    validate_pose(T_WS, "ReplayDriver::move_to: target pose");
    pose_ = T_WS;
  }

  [[nodiscard]] Pose current_pose() const { return pose_; }
  /// Scans handed back so far, and how many are left.
  [[nodiscard]] std::size_t replayed() const { return next_; }
  [[nodiscard]] std::size_t remaining() const { return session_.scans.size() - next_; }
  [[nodiscard]] const SessionInfo& info() const { return session_.info; }

private:
  void check_path(std::size_t i, const LinearScanPath& want, const LinearScanPath& rec) const {
    const double d_start = (want.start().position() - rec.start().position()).norm();
    const double d_end = (want.end_position() - rec.end_position()).norm();
    const double angle =
        Eigen::AngleAxisd(rec.start().pose().linear().transpose() * want.start().pose().linear()).angle();
    if (!(d_start <= tol_.position_m && d_end <= tol_.position_m && angle <= tol_.angle_rad))
      throw InvalidArgument(detail::concat(
          "ReplayDriver: scan ", i + 1, " of ", name_, ": the requested path from (",
          want.start().position().transpose(), ") to (", want.end_position().transpose(),
          ") is not the recorded one from (", rec.start().position().transpose(), ") to (",
          rec.end_position().transpose(), "): start ", d_start, " m, end ", d_end, " m, rotation ", angle,
          " rad apart (tolerance ", tol_.position_m, " m, ", tol_.angle_rad, " rad)"));
  }

  RecordedSession session_;
  ReplayTolerance tol_;
  Pose pose_;
  std::string name_;
  std::size_t next_ = 0;
};

}  // namespace nbs
