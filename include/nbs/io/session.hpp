// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// A recorded session on disk (format: docs/session-format.md): a directory with `session.json` (units, sensor
/// preset, optional unknown area and hand-eye transform, the list of scans) and per scan a points file (PLY with
/// x y z [profile], or PCD) and a pose file (io/pose_file.hpp) with the sensor pose T_WS per scan, per profile or per
/// point. `read_session` returns every scan as an nbs::Scan in the world frame, in metres, validated.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/io/detail/session_json.hpp"
#include "nbs/io/pose_file.hpp"
#include "nbs/io/read_pcd.hpp"
#include "nbs/io/read_ply.hpp"
#include "nbs/sensor/presets.hpp"

namespace nbs {

/// What the sensor pose of a scan's pose file is given for.
enum class PosePer : std::uint8_t {
  scan,     ///< one line: every point was measured from that pose (an area-sensor frame)
  profile,  ///< one line per profile; each point names its profile (PLY property `profile`)
  point     ///< one line per point, in the points' order
};

/// The frame the points of a scan file are given in.
enum class PointFrame : std::uint8_t {
  world,  ///< world frame W
  sensor  ///< the sensor frame S of the point's pose: p_W = T_WS · p_S
};

/// Session-wide facts. All lengths in metres, world frame (the reader converts from the file's units).
struct SessionInfo {
  std::string sensor = "dlr_lsp";   ///< a presets::kNames name
  std::optional<Aabb> unknown_area; ///< the box to model, if recorded
  std::optional<Pose> hand_eye;     ///< T_FS (flange → sensor, Eq. 3.1), if recorded
};

/// One scan of a session entry as listed in session.json (file names relative to the session directory).
struct SessionScanEntry {
  std::string points;  ///< points file (.ply / .pcd)
  std::string poses;   ///< pose file
  PosePer pose_per = PosePer::profile;
  PointFrame frame = PointFrame::world;
  std::optional<LinearScanPath> path;  ///< the executed linear scan path (metres), if recorded
  std::uint64_t rays_cast = 0;         ///< rays the sensor emitted, if recorded (0 otherwise)
};

/// session.json, parsed.
struct SessionManifest {
  SessionInfo info;
  double scale = 1.0;  ///< file units → metres (1 for "m", 1e-3 for "mm")
  std::vector<SessionScanEntry> scans;
};

/// A recorded scan: the measurements (world frame, metres, `Scan::validate()` passed) and its path if recorded.
struct RecordedScan {
  Scan scan;
  std::optional<LinearScanPath> path;
};

struct RecordedSession {
  SessionInfo info;
  std::vector<RecordedScan> scans;
};

inline constexpr std::string_view kSessionManifest = "session.json";
inline constexpr int kSessionFormatVersion = 1;

namespace io_detail {
[[nodiscard]] inline std::string_view format_pose_per(PosePer p) {
  return p == PosePer::scan ? "scan" : p == PosePer::profile ? "profile" : "point";
}
[[nodiscard]] inline std::string_view format_frame(PointFrame f) { return f == PointFrame::world ? "world" : "sensor"; }

/// A file name inside the session directory: relative, without `..`.
[[nodiscard]] inline std::string session_file_name(const nlohmann::json& j, const JsonWhere& where) {
  const std::string name = json_string(j, where);
  const std::filesystem::path p(name);
  if (name.empty() || p.is_absolute()) where.fail("must be a file name relative to the session directory, got '", name, "'");
  for (const auto& part : p)
    if (part == "..") where.fail("must stay inside the session directory, got '", name, "'");
  return name;
}
}  // namespace io_detail

/// Parses session.json (`text`, the file `path` named in messages). Throws FileError naming the file, the key and
/// the value for invalid JSON, a wrong `format` or `version`, units other than "m" / "mm" (and a scan whose own
/// `units` differ from the session's), an unknown sensor preset, a box with min > max, a pose that is not rigid, a
/// file name outside the directory, an unknown `pose_per` / `frame`, and any unknown key.
[[nodiscard]] inline SessionManifest parse_session_manifest(const std::string& path, const std::string& text) {
  using namespace io_detail;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for a number like 1e400
    throw FileError(detail::concat(path, ": not valid JSON: ", e.what()));
  }
  const JsonWhere top{path, ""};
  if (!j.is_object()) throw FileError(detail::concat(path, ": must hold a JSON object, got ", j.type_name()));
  json_known_keys(j, {"format", "version", "units", "sensor", "unknown_area", "hand_eye", "scans", "comment"}, top);
  if (const std::string f = json_string(json_member(j, "format", top), top["format"]); f != "nbs-session")
    top["format"].fail("must be \"nbs-session\", got '", f, "'");
  if (const auto v = json_count(json_member(j, "version", top), top["version"]); v != kSessionFormatVersion)
    top["version"].fail("must be ", kSessionFormatVersion, " (the version this nbs reads), got ", v);
  SessionManifest m;
  const std::string units = json_string(json_member(j, "units", top), top["units"]);
  if (units == "m") m.scale = 1.0;
  else if (units == "mm") m.scale = 1e-3;
  else top["units"].fail("must be \"m\" or \"mm\", got '", units, "'");
  m.info.sensor = json_string(json_member(j, "sensor", top), top["sensor"]);
  try {
    (void)presets::by_name(m.info.sensor);
  } catch (const InvalidArgument& e) {
    top["sensor"].fail(e.what());
  }
  if (j.contains("unknown_area")) {
    const auto& b = j["unknown_area"];
    const JsonWhere w = top["unknown_area"];
    json_known_keys(b, {"min", "max"}, w);
    Aabb box;
    box.min = json_vec3(json_member(b, "min", w), w["min"], m.scale);
    box.max = json_vec3(json_member(b, "max", w), w["max"], m.scale);
    if ((box.min.array() >= box.max.array()).any())
      w.fail("must have min < max on every axis, got min (", box.min.transpose(), ") max (", box.max.transpose(), ")");
    m.info.unknown_area = box;
  }
  if (j.contains("hand_eye")) m.info.hand_eye = json_pose(j["hand_eye"], top["hand_eye"], m.scale);
  const auto& scans = json_member(j, "scans", top);
  if (!scans.is_array()) top["scans"].fail("must be an array, got ", scans.type_name());
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const auto& s = scans[i];
    const JsonWhere w = top["scans"].at(i);
    json_known_keys(s, {"points", "poses", "pose_per", "frame", "path", "rays_cast", "units"}, w);
    SessionScanEntry e;
    e.points = session_file_name(json_member(s, "points", w), w["points"]);
    e.poses = session_file_name(json_member(s, "poses", w), w["poses"]);
    const std::string per = json_string(json_member(s, "pose_per", w), w["pose_per"]);
    if (per == "scan") e.pose_per = PosePer::scan;
    else if (per == "profile") e.pose_per = PosePer::profile;
    else if (per == "point") e.pose_per = PosePer::point;
    else w["pose_per"].fail("must be \"scan\", \"profile\" or \"point\", got '", per, "'");
    if (s.contains("frame")) {
      const std::string f = json_string(s["frame"], w["frame"]);
      if (f == "world") e.frame = PointFrame::world;
      else if (f == "sensor") e.frame = PointFrame::sensor;
      else w["frame"].fail("must be \"world\" or \"sensor\", got '", f, "'");
    }
    if (s.contains("units"))
      if (const std::string u = json_string(s["units"], w["units"]); u != units)
        w["units"].fail("is '", u, "' but the session's units are '", units, "' (one unit per session)");
    if (s.contains("path")) {
      const JsonWhere pw = w["path"];
      json_known_keys(s["path"], {"start", "end"}, pw);
      const Pose start = json_pose(json_member(s["path"], "start", pw), pw["start"], m.scale);
      e.path = LinearScanPath(Viewpoint(start), json_vec3(json_member(s["path"], "end", pw), pw["end"], m.scale));
    }
    if (s.contains("rays_cast")) e.rays_cast = json_count(s["rays_cast"], w["rays_cast"]);
    m.scans.push_back(std::move(e));
  }
  return m;
}

namespace io_detail {
/// Points (as stored, in the file's units) and, for a PLY file with a `profile` property, the profile per point.
struct SessionPoints {
  std::vector<Vec3> points;
  std::optional<std::vector<std::uint32_t>> profiles;
};

[[nodiscard]] inline SessionPoints read_session_points(const std::string& path) {
  const std::string bytes = read_file_bytes(path);
  SessionPoints out;
  if (bytes.starts_with("ply\n") || bytes.starts_with("ply\r")) {
    static constexpr std::array<std::string_view, 1> kProfile = {"profile"};
    PlyContents c = parse_ply(path, bytes, kProfile);
    out.points = std::move(c.vertices);
    if (c.has_extra[0]) {
      out.profiles.emplace(out.points.size());
      for (std::size_t i = 0; i < out.points.size(); ++i) {
        const double v = c.extras[i];
        if (!(v >= 0.0 && v <= 4294967295.0 && std::floor(v) == v))
          throw FileError(detail::concat(path, ": element 'vertex' record ", i, ": profile ", v,
                                         " is not an unsigned 32-bit integer"));
        (*out.profiles)[i] = static_cast<std::uint32_t>(v);
      }
    }
    return out;
  }
  out.points = read_pcd_bytes(path, bytes).points;
  return out;
}

/// The scan of manifest entry `e` (index `i`) in directory `dir`; world frame, metres, validated.
[[nodiscard]] inline Scan load_session_scan(const std::filesystem::path& dir, const SessionScanEntry& e,
                                            std::size_t i, double scale) {
  const std::string points_path = (dir / e.points).string(), poses_path = (dir / e.poses).string();
  if (!std::filesystem::exists(dir / e.poses))
    throw FileError(detail::concat(poses_path, ": the pose file of scan ", i, " is missing"));
  if (!std::filesystem::exists(dir / e.points))
    throw FileError(detail::concat(points_path, ": the points file of scan ", i, " is missing"));
  SessionPoints pts = read_session_points(points_path);
  Scan scan;
  scan.profile_poses = read_pose_file(poses_path, scale);
  const std::size_t n = pts.points.size(), np = scan.profile_poses.size();
  const auto fail = [&](const auto&... what) { throw FileError(detail::concat(what...)); };
  switch (e.pose_per) {
    case PosePer::scan:
      if (np != 1) fail(poses_path, ": scan ", i, " has pose_per \"scan\" and needs 1 pose, the file has ", np);
      scan.profile_of_point.assign(n, 0);
      break;
    case PosePer::point:
      if (np != n) fail(poses_path, ": scan ", i, " has pose_per \"point\": ", n, " points need ", n, " poses, the file has ", np);
      scan.profile_of_point.resize(n);
      for (std::size_t k = 0; k < n; ++k) scan.profile_of_point[k] = static_cast<std::uint32_t>(k);
      break;
    case PosePer::profile:
      if (!pts.profiles)
        fail(points_path, ": scan ", i, " has pose_per \"profile\" but the file has no 'profile' property per point "
             "(a PLY vertex property)");
      scan.profile_of_point = std::move(*pts.profiles);
      for (std::size_t k = 0; k < n; ++k)
        if (scan.profile_of_point[k] >= np)
          fail(points_path, ": point ", k, " of scan ", i, " names profile ", scan.profile_of_point[k], " but ",
               poses_path, " has ", np, " poses");
      break;
  }
  scan.points.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 p = scale * pts.points[k];
    scan.points[k] = e.frame == PointFrame::world ? p : Vec3(scan.profile_poses[scan.profile_of_point[k]] * p);
  }
  scan.rays_cast = e.rays_cast;
  try {
    scan.validate();
  } catch (const InvalidArgument& err) {
    fail(points_path, ": scan ", i, ": ", err.what());
  }
  return scan;
}
}  // namespace io_detail

/// Reads the session in directory `dir`. Throws FileError naming the file and the key, line or record and the value
/// for everything parse_session_manifest rejects, a missing points or pose file, a malformed PLY / PCD / pose file,
/// a pose count that does not match `pose_per`, a profile index out of range, and a non-finite point.
[[nodiscard]] inline RecordedSession read_session(const std::filesystem::path& dir) {
  const std::filesystem::path manifest = dir / kSessionManifest;
  if (!std::filesystem::is_directory(dir))
    throw FileError(detail::concat(dir.string(), ": not a directory (a session is a directory with ",
                                   kSessionManifest, ")"));
  if (!std::filesystem::exists(manifest))
    throw FileError(detail::concat(manifest.string(), ": missing (", dir.string(), " is not a recorded session)"));
  const SessionManifest m = parse_session_manifest(manifest.string(), io_detail::read_file_bytes(manifest.string()));
  RecordedSession out;
  out.info = m.info;
  out.scans.reserve(m.scans.size());
  for (std::size_t i = 0; i < m.scans.size(); ++i)
    out.scans.push_back({io_detail::load_session_scan(dir, m.scans[i], i, m.scale), m.scans[i].path});
  return out;
}

}  // namespace nbs
