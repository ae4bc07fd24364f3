// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `RecordingDriver`: wraps any `ScanDriver` and records every scan it acquires, with the requested path, into a
/// session directory (SessionWriter, docs/session-format.md), so the run can be replayed with `ReplayDriver`.

#include <filesystem>
#include <utility>

#include "nbs/driver/concepts.hpp"
#include "nbs/io/session_writer.hpp"

namespace nbs {

/// Forwards to `driver` (held by reference; it must outlive this object). Not thread-safe.
template <ScanDriver Driver>
class RecordingDriver {
public:
  /// Starts the session in `dir` (SessionWriter: FileError if `dir` already holds a session or cannot be written,
  /// InvalidArgument for an invalid `info`).
  RecordingDriver(Driver& driver, std::filesystem::path dir, SessionInfo info)
      : driver_(&driver), writer_(std::move(dir), std::move(info)) {}

  /// The wrapped driver's scan, appended to the session with `path` before it is returned. If writing fails
  /// (FileError) the scan is lost to the caller but the session on disk stays complete without it.
  [[nodiscard]] Scan acquire(const LinearScanPath& path) {
    Scan scan = driver_->acquire(path);
    writer_.append(scan, path);
    return scan;
  }
  void move_to(const Pose& T_WS) { driver_->move_to(T_WS); }
  [[nodiscard]] Pose current_pose() const { return driver_->current_pose(); }
  [[nodiscard]] const SessionWriter& writer() const { return writer_; }

private:
  Driver* driver_;
  SessionWriter writer_;
};

}  // namespace nbs
