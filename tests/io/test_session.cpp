// SPDX-License-Identifier: BSD-3-Clause
// Recorded sessions: writer → reader round trips bit for bit; hand-written sessions in mm / sensor frame / per scan
// and per point against the analytic world points; malformed sessions fail naming file, key or line and the value.
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "nbs/io/session_writer.hpp"
#include "nbs_catch.hpp"
#include "temp_dir.hpp"
#include "nbs_random.hpp"

namespace {
namespace fs = std::filesystem;
using nbs::Pose;
using nbs::Vec3;

Pose random_pose(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Pose T = Pose::Identity();
  T.linear() = nbs_test::random_quaternion(u, rng).normalized().toRotationMatrix();
  T.translation() = nbs_test::random_vec3(u, rng);
  return T;
}

nbs::Scan random_scan(unsigned seed, std::size_t profiles, std::size_t points) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  nbs::Scan s;
  for (std::size_t k = 0; k < profiles; ++k) s.profile_poses.push_back(random_pose(rng));
  for (std::size_t i = 0; i < points; ++i) {
    const Vec3 p = nbs_test::random_vec3(u, rng);
    s.add_point(p, static_cast<std::uint32_t>(rng() % profiles));
  }
  s.rays_cast = points + 17;
  return s;
}

fs::path fresh(const std::string& name) {
  const fs::path d = nbs_test::temp_dir() / name;
  fs::remove_all(d);
  return d;
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
}

/// A minimal valid session with one scan in `dir` (pose per scan, world frame); `manifest_extra` is spliced into
/// the scan entry, `top_extra` into the top-level object.
fs::path one_scan_session(const std::string& name, const std::string& poses, const std::string& points_ply,
                          const std::string& scan_extra = "", const std::string& top = "\"units\": \"m\"") {
  const fs::path d = fresh(name);
  fs::create_directories(d);
  write_text(d / "a.poses", poses);
  write_text(d / "a.ply", points_ply);
  write_text(d / "session.json", "{\"format\": \"nbs-session\", \"version\": 1, " + top +
                                     ", \"sensor\": \"dlr_lsp\", \"scans\": [{\"points\": \"a.ply\", \"poses\": "
                                     "\"a.poses\", \"pose_per\": \"scan\"" + scan_extra + "}]}");
  return d;
}

const std::string kIdentity = "1 0 0 0 0 1 0 0 0 0 1 0\n";
const std::string kTwoPoints = "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
                               "property double z\nend_header\n1 2 3\n-4 5 6\n";
}  // namespace

TEST_CASE("a recorded session reads back bit for bit", "[io][session]") {
  const fs::path dir = fresh("session_roundtrip");
  nbs::SessionInfo info;
  info.sensor = "scancontrol_2700_100";
  info.unknown_area = nbs::Aabb{Vec3(-0.1, -0.2, 0.0), Vec3(0.1, 0.2, 0.3)};
  std::mt19937_64 rng(5);
  info.hand_eye = random_pose(rng);
  const nbs::Scan a = random_scan(1, 40, 500), b = random_scan(2, 1, 3);
  const nbs::LinearScanPath path(nbs::Viewpoint(random_pose(rng)), Vec3(0.1 / 3.0, 0.2, -0.7));
  {
    nbs::SessionWriter w(dir, info);
    CHECK(nbs::read_session(dir).scans.empty());  // readable after the constructor
    w.append(a, path);
    w.append(b);
    CHECK(w.size() == 2);
  }
  const nbs::RecordedSession s = nbs::read_session(dir);
  CHECK(s.info.sensor == info.sensor);
  REQUIRE(s.info.unknown_area);
  CHECK(s.info.unknown_area->min == info.unknown_area->min);
  CHECK(s.info.unknown_area->max == info.unknown_area->max);
  REQUIRE(s.info.hand_eye);
  CHECK(s.info.hand_eye->matrix() == info.hand_eye->matrix());
  REQUIRE(s.scans.size() == 2);
  for (const auto& [got, want] : {std::pair{&s.scans[0].scan, &a}, std::pair{&s.scans[1].scan, &b}}) {
    CHECK(got->points == want->points);
    CHECK(got->profile_of_point == want->profile_of_point);
    CHECK(got->rays_cast == want->rays_cast);
    REQUIRE(got->profile_poses.size() == want->profile_poses.size());
    for (std::size_t k = 0; k < got->profile_poses.size(); ++k)
      CHECK(got->profile_poses[k].matrix() == want->profile_poses[k].matrix());
  }
  REQUIRE(s.scans[0].path);
  CHECK(s.scans[0].path->start().pose().matrix() == path.start().pose().matrix());
  CHECK(s.scans[0].path->end_position() == path.end_position());
  CHECK_FALSE(s.scans[1].path);

  // write_session of what was read gives the same session again.
  const fs::path again = fresh("session_roundtrip_again");
  nbs::write_session(again, s);
  CHECK(nbs::read_session(again).scans[0].scan.points == a.points);
}

TEST_CASE("hand-written sessions: millimetres, sensor frame, pose per point, PCD", "[io][session]") {
  // Sensor 100 mm above the origin, rotated 90° about z: p_W = R p_S + t.
  const std::string pose_mm = "0 -1 0 0  1 0 0 0  0 0 1 100\n";
  SECTION("mm, sensor frame, one pose per scan") {
    const fs::path d = one_scan_session("session_mm", "# a comment\n\n" + pose_mm, kTwoPoints,
                                        ", \"frame\": \"sensor\"", "\"units\": \"mm\", \"unknown_area\": "
                                        "{\"min\": [-50, -50, 0], \"max\": [50, 50, 80]}");
    const nbs::RecordedSession s = nbs::read_session(d);
    const nbs::Scan& scan = s.scans.at(0).scan;
    REQUIRE(scan.size() == 2);
    // (1, 2, 3) mm in S → (−2, 1, 103) mm in W; (−4, 5, 6) → (−5, −4, 106).
    CHECK((scan.points[0] - Vec3(-0.002, 0.001, 0.103)).norm() < 1e-15);
    CHECK((scan.points[1] - Vec3(-0.005, -0.004, 0.106)).norm() < 1e-15);
    CHECK(scan.origin(1) == Vec3(0, 0, 0.1));
    CHECK(s.info.unknown_area->max == Vec3(0.05, 0.05, 0.08));
  }
  SECTION("pose per point") {
    const fs::path d = one_scan_session("session_point", kIdentity + pose_mm, kTwoPoints, "");
    fs::remove(d / "session.json");
    write_text(d / "session.json", "{\"format\": \"nbs-session\", \"version\": 1, \"units\": \"m\", \"sensor\": "
                                   "\"asus_xtion_pro\", \"scans\": [{\"points\": \"a.ply\", \"poses\": \"a.poses\", "
                                   "\"pose_per\": \"point\"}]}");
    const nbs::Scan scan = nbs::read_session(d).scans.at(0).scan;
    CHECK(scan.profile_of_point == std::vector<std::uint32_t>{0, 1});
    CHECK(scan.origin(1) == Vec3(0, 0, 100));
    CHECK(scan.points[1] == Vec3(-4, 5, 6));  // world frame: as stored
  }
  SECTION("PCD points") {
    const fs::path d = one_scan_session("session_pcd", kIdentity, kTwoPoints);
    write_text(d / "a.ply", "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
                            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n0.5 0.25 2\n");
    CHECK(nbs::read_session(d).scans.at(0).scan.points.at(0) == Vec3(0.5, 0.25, 2));
  }
}

TEST_CASE("malformed sessions fail naming the file, the key or line and the value", "[io][session][validation]") {
  using nbs_test::Contains;
  const auto fails = [](const fs::path& d) {
    try {
      (void)nbs::read_session(d);
    } catch (const nbs::FileError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(fails(fresh("session_none")), Contains("not a directory"));
  fs::create_directories(fresh("session_empty_dir"));
  CHECK_THAT(fails(nbs_test::temp_dir() / "session_empty_dir"), Contains("session.json: missing"));

  const fs::path ok = one_scan_session("session_ok", kIdentity, kTwoPoints);
  CHECK(nbs::read_session(ok).scans.at(0).scan.size() == 2);

  CHECK_THAT(fails(one_scan_session("s1", kIdentity, kTwoPoints, ", \"units\": \"mm\"")),
             Contains("scans[0].units is 'mm' but the session's units are 'm'"));
  CHECK_THAT(fails(one_scan_session("s2", kIdentity, kTwoPoints, "", "\"units\": \"inch\"")),
             Contains("units must be \"m\" or \"mm\", got 'inch'"));
  CHECK_THAT(fails(one_scan_session("s3", kIdentity, kTwoPoints, ", \"pose_pre\": 1")),
             Contains("scans[0].pose_pre is not a known key"));
  CHECK_THAT(fails(one_scan_session("s4", "1 0 0 0 0 1 0 0 0 0 2 0\n", kTwoPoints)),
             Contains("a.poses:1: pose 0 is not rigid"));
  CHECK_THAT(fails(one_scan_session("s5", "1 0 0 0 0 1 0 0 0 0 1\n", kTwoPoints)),
             Contains("a.poses:1: a pose needs 12 numbers (3×4 row-major), got 11"));
  CHECK_THAT(fails(one_scan_session("s6", "1 0 0 nan 0 1 0 0 0 0 1 0\n", kTwoPoints)),
             Contains("a.poses:1: number 4 'nan' is not a finite number"));
  CHECK_THAT(fails(one_scan_session("s7", kIdentity + kIdentity, kTwoPoints)),
             Contains("needs 1 pose, the file has 2"));
  const fs::path bad_json = one_scan_session("s8", kIdentity, kTwoPoints);
  write_text(bad_json / "session.json", "{\"format\": ");
  CHECK_THAT(fails(bad_json), Contains("session.json: not valid JSON"));
  // Found by fuzz_session: nlohmann throws out_of_range (not parse_error) for a number beyond double.
  write_text(bad_json / "session.json", "{\"format\": \"nbs-session\", \"version\": 1e3080}");
  CHECK_THAT(fails(bad_json), Contains("not valid JSON") && Contains("number overflow parsing '1e3080'"));
  const fs::path missing = one_scan_session("s9", kIdentity, kTwoPoints);
  fs::remove(missing / "a.poses");
  CHECK_THAT(fails(missing), Contains("a.poses: the pose file of scan 0 is missing"));
  const fs::path truncated = one_scan_session("s10", kIdentity, kTwoPoints.substr(0, kTwoPoints.size() - 4));
  CHECK_THAT(fails(truncated), Contains("a.ply"));
  const fs::path outside = one_scan_session("s11", kIdentity, kTwoPoints);
  write_text(outside / "session.json", "{\"format\": \"nbs-session\", \"version\": 1, \"units\": \"m\", \"sensor\": "
                                       "\"dlr_lsp\", \"scans\": [{\"points\": \"../a.ply\", \"poses\": \"a.poses\", "
                                       "\"pose_per\": \"scan\"}]}");
  CHECK_THAT(fails(outside), Contains("scans[0].points must stay inside the session directory, got '../a.ply'"));
  const std::string with_profile = "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
                                   "property double z\nproperty uint profile\nend_header\n1 2 3 4\n";
  const fs::path profile = one_scan_session("s12", kIdentity, with_profile);
  write_text(profile / "session.json", "{\"format\": \"nbs-session\", \"version\": 1, \"units\": \"m\", \"sensor\": "
                                       "\"dlr_lsp\", \"scans\": [{\"points\": \"a.ply\", \"poses\": \"a.poses\", "
                                       "\"pose_per\": \"profile\"}]}");
  CHECK_THAT(fails(profile), Contains("point 0 of scan 0 names profile 4 but"));
  const fs::path no_profile = one_scan_session("s13", kIdentity, kTwoPoints);
  write_text(no_profile / "session.json", "{\"format\": \"nbs-session\", \"version\": 2, \"units\": \"m\", \"sensor\": "
                                          "\"dlr_lsp\", \"scans\": []}");
  CHECK_THAT(fails(no_profile), Contains("version must be 1"));
  const fs::path sensor = one_scan_session("s14", kIdentity, kTwoPoints);
  write_text(sensor / "session.json", "{\"format\": \"nbs-session\", \"version\": 1, \"units\": \"m\", \"sensor\": "
                                      "\"kinect\", \"scans\": []}");
  CHECK_THAT(fails(sensor), Contains("sensor unknown sensor preset 'kinect'"));
  const fs::path point_at_origin = one_scan_session("s15", "1 0 0 1 0 1 0 2 0 0 1 3\n", kTwoPoints);
  CHECK(nbs::read_session(point_at_origin).scans[0].scan.size() == 2);  // a point at its origin is the mesh's business
}

TEST_CASE("SessionWriter changes nothing on an invalid scan and refuses an existing session", "[io][session][validation]") {
  const fs::path dir = fresh("session_writer_bad");
  nbs::SessionWriter w(dir, {});
  nbs::Scan bad = random_scan(3, 2, 5);
  bad.points[2].x() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(w.append(bad), nbs_test::Contains("scan point 2 is not finite"));
  CHECK(w.size() == 0);
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);  // session.json only
  CHECK_THROWS_WITH(nbs::SessionWriter(dir, {}), nbs_test::Contains("session.json: already exists"));
  nbs::SessionInfo unknown;
  unknown.sensor = "none";
  CHECK_THROWS_AS(nbs::SessionWriter(fresh("session_writer_sensor"), unknown), nbs::InvalidArgument);
}
