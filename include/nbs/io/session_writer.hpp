// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Records a session to disk, scan by scan, in the format read_session reads (docs/session-format.md): metres,
/// world frame, one pose per profile; points as binary little-endian PLY (double x y z, uint profile). Not
/// thread-safe.

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "nbs/io/ply_writer.hpp"
#include "nbs/io/session.hpp"
#include "nbs/io/write_json.hpp"

namespace nbs {

/// Writes a session directory. After the constructor and after every `append` the directory is a complete,
/// readable session: each scan's files are written atomically first, then session.json is replaced atomically.
/// A throw (invalid scan, disk full) leaves the directory as it was before the call, apart from at most the
/// finished files of the scan that was not added, which session.json does not list.
class SessionWriter {
public:
  /// Creates `dir` (and its parents) if needed and writes a session.json without scans. Throws InvalidArgument for
  /// an unknown sensor preset or an empty / non-finite box, FileError if `dir` already holds a session.json or
  /// cannot be written.
  SessionWriter(std::filesystem::path dir, SessionInfo info) : dir_(std::move(dir)), info_(std::move(info)) {
    (void)presets::by_name(info_.sensor);
    if (info_.unknown_area) {
      detail::require(info_.unknown_area->min.allFinite() && info_.unknown_area->max.allFinite() &&
                          (info_.unknown_area->min.array() < info_.unknown_area->max.array()).all(),
                      "SessionWriter: the unknown area must be finite with min < max, got min (",
                      info_.unknown_area->min.transpose(), ") max (", info_.unknown_area->max.transpose(), ")");
    }
    if (info_.hand_eye) validate_pose(*info_.hand_eye, "SessionWriter: hand-eye transform");
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec) throw FileError(detail::concat(dir_.string(), ": cannot create the session directory: ", ec.message()));
    if (std::filesystem::exists(dir_ / kSessionManifest))
      throw FileError(detail::concat((dir_ / kSessionManifest).string(),
                                     ": already exists (record each session into a directory of its own)"));
    write_manifest();
  }

  /// Adds `scan` (world frame, metres) and, if given, the path it was taken along. Throws InvalidArgument if the
  /// scan fails `Scan::validate()` (nothing is written), FileError if a file cannot be written.
  void append(const Scan& scan, const std::optional<LinearScanPath>& path = std::nullopt) {
    scan.validate();
    char stem[32];
    std::snprintf(stem, sizeof stem, "scan_%04zu", entries_.size());
    SessionScanEntry e;
    e.points = std::string(stem) + ".ply";
    e.poses = std::string(stem) + ".poses";
    e.pose_per = PosePer::profile;
    e.frame = PointFrame::world;
    e.path = path;
    e.rays_cast = scan.rays_cast;
    {
      PlyWriter w(dir_ / e.points, PlyFormat::binary_little_endian);
      w.comment("nbs session scan: world frame, metres; profile = line of the pose file");
      w.element("vertex", scan.size());
      for (const char* name : {"x", "y", "z"}) w.property(PlyType::f64, name);
      w.property(PlyType::u32, "profile");
      w.end_header();
      for (std::size_t i = 0; i < scan.size(); ++i) {
        for (int k = 0; k < 3; ++k) w.value(scan.points[i][k]);
        w.value(scan.profile_of_point[i]);
        w.end_record();
      }
      w.finish();
    }
    write_pose_file((dir_ / e.poses).string(), scan.profile_poses, "T_WS per profile (3x4 row-major), metres");
    entries_.push_back(std::move(e));
    try {
      write_manifest();
    } catch (...) {
      entries_.pop_back();
      throw;
    }
  }

  [[nodiscard]] std::size_t size() const { return entries_.size(); }
  [[nodiscard]] const std::filesystem::path& directory() const { return dir_; }

private:
  void write_manifest() const {
    using io_detail::pose_json;
    using io_detail::vec3_json;
    nlohmann::json j;
    j["format"] = "nbs-session";
    j["version"] = kSessionFormatVersion;
    j["units"] = "m";
    j["sensor"] = info_.sensor;
    if (info_.unknown_area)
      j["unknown_area"] = {{"min", vec3_json(info_.unknown_area->min)}, {"max", vec3_json(info_.unknown_area->max)}};
    if (info_.hand_eye) j["hand_eye"] = pose_json(*info_.hand_eye);
    j["scans"] = nlohmann::json::array();
    for (const SessionScanEntry& e : entries_) {
      nlohmann::json s = {{"points", e.points},
                          {"poses", e.poses},
                          {"pose_per", io_detail::format_pose_per(e.pose_per)},
                          {"frame", io_detail::format_frame(e.frame)},
                          {"rays_cast", e.rays_cast}};
      if (e.path) s["path"] = {{"start", pose_json(e.path->start().pose())}, {"end", vec3_json(e.path->end_position())}};
      j["scans"].push_back(std::move(s));
    }
    write_json((dir_ / kSessionManifest).string(), j);
  }

  std::filesystem::path dir_;
  SessionInfo info_;
  std::vector<SessionScanEntry> entries_;
};

/// Writes `session` to `dir` (SessionWriter; the same errors).
inline void write_session(const std::filesystem::path& dir, const RecordedSession& session) {
  SessionWriter w(dir, session.info);
  for (const RecordedScan& s : session.scans) w.append(s.scan, s.path);
}

}  // namespace nbs
