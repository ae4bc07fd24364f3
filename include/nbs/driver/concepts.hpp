// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The hardware boundary of the closed loop (docs/architecture.md): a `ScanSource` acquires a scan along a linear
/// scan path, a `RobotDriver` moves the sensor to a pose and reports where it is; `ScanDriver` is both, what
/// `run_loop` (planner/simulation_loop.hpp) drives. Models: `SimulatedDriver` (any `ScanSimulator`), `ReplayDriver`
/// (a recorded session), `RecordingDriver` (records any driver). Frames and units: every pose is the sensor pose
/// T_WS (sensor → world), metres; a robot that works with flange poses T_WF converts at the boundary with its hand-eye
/// transform T_FS: T_WS = T_WF · T_FS (`sensor_from_flange`, `flange_from_sensor`).

#include <concepts>
#include <cstdint>

#include "nbs/core/scan.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

/// A simulated (or real) scanner: executes a linear scan path with the sensor and returns the measured Scan
/// (valid: `Scan::validate()` passes; world frame, metres). `seed` selects the noise; the same (path, sensor, seed)
/// must give the same Scan. An area sensor takes one frame at `path.start()` (the utility evaluates it there).
template <class S, class Sensor>
concept ScanSimulator = requires(const S& s, const LinearScanPath& path, const Sensor& sensor, std::uint64_t seed) {
  { s.scan(path, sensor, seed) } -> std::same_as<Scan>;
};

/// Acquires one scan along `path` (the sensor moves from `path.start()` to `path.end_position()`; a zero-length
/// path is one area-sensor frame) and returns it valid (`Scan::validate()` passes), world frame, metres. Throws
/// (nbs::Error or the driver's own exception) when the scan cannot be taken; the source is then as before the call.
template <class D>
concept ScanSource = requires(D& d, const LinearScanPath& path) {
  { d.acquire(path) } -> std::same_as<Scan>;
};

/// Moves the sensor to T_WS and reports the current T_WS. `move_to` throws InvalidArgument for a non-finite or
/// non-rigid pose (naming it) and changes nothing; after it returns, `current_pose()` is the target within the
/// driver's stated accuracy. A driver whose robot reports flange poses T_WF returns T_WF · T_FS.
template <class D>
concept RobotDriver = requires(D& d, const D& cd, const Pose& T_WS) {
  d.move_to(T_WS);
  { cd.current_pose() } -> std::same_as<Pose>;
};

/// Both: what the closed loop drives. After `acquire(path)` the current pose is `path.pose_at(1.0)`.
template <class D>
concept ScanDriver = ScanSource<D> && RobotDriver<D>;

/// T_WS = T_WF · T_FS: the sensor pose of flange pose `T_WF` with hand-eye transform `T_FS` (flange → sensor).
[[nodiscard]] inline Pose sensor_from_flange(const Pose& T_WF, const Pose& T_FS) { return T_WF * T_FS; }

/// T_WF = T_WS · T_FS⁻¹: the flange pose that puts the sensor at `T_WS`.
[[nodiscard]] inline Pose flange_from_sensor(const Pose& T_WS, const Pose& T_FS) { return T_WS * T_FS.inverse(); }

}  // namespace nbs
