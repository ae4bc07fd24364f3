// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `SimulatedDriver`: a `ScanDriver` over any `ScanSimulator` (e.g. nbs::embree::SimulatedScanner, for a
/// LaserStripeProfiler or an AreaSensor). The robot is ideal: it reaches every pose exactly (infinite workspace,
/// Sec. 4.7).

#include <cstdint>
#include <utility>

#include "nbs/core/detail/random.hpp"
#include "nbs/driver/concepts.hpp"

namespace nbs {

/// Scan i (0-based, counting successful acquisitions) uses the noise seed splitmix64(seed ^ (0x5CA9 + i)), the
/// sequence run_simulation has always used. Holds a reference to `scanner` (it must outlive the driver) and a copy
/// of `sensor`. Not thread-safe.
template <class Scanner, class Sensor>
  requires ScanSimulator<Scanner, Sensor>
class SimulatedDriver {
public:
  /// Throws InvalidArgument if `home` (the initial T_WS) is not finite and rigid.
  SimulatedDriver(const Scanner& scanner, Sensor sensor, std::uint64_t seed, const Pose& home = Pose::Identity())
      : scanner_(&scanner), sensor_(std::move(sensor)), seed_(seed), pose_(home) {
    validate_pose(home, "SimulatedDriver: home pose");
  }

  /// Scans along `path` with the next seed; the sensor then rests at the path's end. Throws what the scanner throws
  /// (nothing changes then).
  [[nodiscard]] Scan acquire(const LinearScanPath& path) {
    Scan scan = scanner_->scan(path, sensor_, detail::splitmix64(seed_ ^ (0x5CA9ULL + scans_)));
    ++scans_;
    pose_ = path.pose_at(1.0);
    return scan;
  }

  /// Exact: `current_pose()` becomes `T_WS`. Throws InvalidArgument (naming the pose) if it is not finite and rigid.
  void move_to(const Pose& T_WS) {
    validate_pose(T_WS, "SimulatedDriver::move_to: target pose");
    pose_ = T_WS;
  }

  [[nodiscard]] Pose current_pose() const { return pose_; }
  [[nodiscard]] std::uint64_t scans() const { return scans_; }
  [[nodiscard]] const Sensor& sensor() const { return sensor_; }

private:
  const Scanner* scanner_;
  Sensor sensor_;
  std::uint64_t seed_;
  std::uint64_t scans_ = 0;
  Pose pose_;
};

}  // namespace nbs
