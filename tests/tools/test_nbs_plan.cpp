// SPDX-License-Identifier: BSD-3-Clause
// nbs_plan end to end: a simulated session recorded to disk (SessionWriter, analytic sphere scanner) and replanned by
// the tool gives the same next scan as the in-memory planner fed the same scans; bad input exits 2 with a message
// naming the file or option and the value, and writes nothing on stdout.

#include "nbs/planner/runtime_planner.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "nbs/io/session_writer.hpp"
#include "nbs_catch.hpp"
#include "planner/support/analytic_scanner.hpp"
#include "nbs_read_file.hpp"

namespace fs = std::filesystem;
using nbs::Vec3;

namespace {

const nbs::Aabb kBox{Vec3(-0.06, -0.06, 0.0), Vec3(0.06, 0.06, 0.10)};

/// A per-process directory, removed at exit.
fs::path temp_root() {
  struct Dir {
    fs::path path = fs::temp_directory_path() / ("nbs_tools_test_" + std::to_string(::getpid()));
    Dir() { fs::create_directories(path); }
    ~Dir() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

using nbs_test::slurp;

struct Run {
  int code = -1;
  std::string out, err;
};

/// Runs nbs_plan with `args` (shell words), stdout and stderr captured.
Run run_plan(const std::string& args) {
  const fs::path out = temp_root() / "stdout.txt", err = temp_root() / "stderr.txt";
  const std::string cmd = std::string("'") + NBS_PLAN_EXE + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  Run r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

nbs::Pose matrix_of(const nlohmann::json& rows) {
  nbs::Pose T = nbs::Pose::Identity();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = rows.at(static_cast<std::size_t>(r)).at(static_cast<std::size_t>(c)).get<double>();
  return T;
}

/// A two-scan session of the sphere on the pedestal: the planner's first scan, then its next best scan. Returns the
/// scans as taken (in memory).
std::vector<nbs::Scan> record(const fs::path& dir, bool with_box, const std::optional<nbs::Pose>& hand_eye) {
  const nbs::test::SphereOnPedestal sphere;
  const nbs::LaserStripeProfiler lsp = nbs::presets::dlr_lsp();
  nbs::RuntimePlanner planner(nbs::parse_method("C_H"), {}, lsp, kBox);
  nbs::SessionInfo info;
  info.sensor = "dlr_lsp";
  if (with_box) info.unknown_area = kBox;
  info.hand_eye = hand_eye;
  nbs::SessionWriter writer(dir, info);
  std::vector<nbs::Scan> scans;
  nbs::LinearScanPath path = planner.first_scan(1);
  for (int i = 0; i < 2; ++i) {
    scans.push_back(sphere.scan(path, lsp, 10 + static_cast<std::uint64_t>(i)));
    writer.append(scans.back(), path);
    (void)planner.integrate(scans.back());
    if (i == 0) path = planner.next_best_scan().path();
  }
  return scans;
}

}  // namespace

TEST_CASE("nbs_plan replans a recorded session to the in-memory planner's next scan", "[tools][nbs_plan]") {
  const fs::path dir = temp_root() / "session";
  static const std::vector<nbs::Scan> scans = record(dir, true, std::nullopt);  // once for every SECTION

  nbs::PlannerSetting ps;
  ps.threads = 1;
  nbs::RuntimePlanner twin(nbs::kDefaultMethod, {}, nbs::presets::dlr_lsp(), kBox, ps);  // nbs_plan's default
  for (const nbs::Scan& s : scans) (void)twin.integrate(s);
  const nbs::PlanResult expected = twin.next_best_scan();
  REQUIRE(expected.ok());

  // A hand-eye transform T_FS (flange → sensor) in a file of its own.
  nbs::Pose T_FS = nbs::Pose::Identity();
  T_FS.linear() = Eigen::AngleAxisd(0.3, Vec3(0.2, 1.0, -0.4).normalized()).toRotationMatrix();
  T_FS.translation() = Vec3(0.01, -0.02, 0.15);
  const fs::path he = temp_root() / "hand_eye.txt";
  nbs::write_pose_file(he.string(), std::span<const nbs::Pose>(&T_FS, 1));

  const Run r = run_plan(quoted(dir) + " --threads 2 --hand-eye " + quoted(he));
  INFO(r.err);
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  {  // Each matrix row on one line: no line holds a lone number.
    std::istringstream lines(r.out);
    std::size_t lone = 0, rows = 0;
    for (std::string l; std::getline(lines, l);) {
      const auto b = l.find_first_not_of(' ');
      if (b != std::string::npos && (std::isdigit(static_cast<unsigned char>(l[b])) || l[b] == '-')) ++lone;
      rows += l.find("[[") == std::string::npos && l.find('[') != std::string::npos && l.find(']') != std::string::npos;
    }
    CHECK(lone == 0);
    CHECK(rows >= 4);
  }
  CHECK(j.at("status") == "ok");
  CHECK(j.at("method") == "SGU_H");
  CHECK(j.at("scans") == 2);
  CHECK(j.at("done") == twin.done());
  CHECK(j.at("mode") == std::string(nbs::to_string(expected.stats.mode)));
  CHECK(j.at("utility").get<double>() == Approx(expected.stats.best_utility).epsilon(1e-12));
  CHECK(j.at("estimated_coverage").get<double>() == Approx(twin.progress().estimated_coverage).epsilon(1e-12));
  CHECK(j.at("mean_density").get<double>() == Approx(twin.progress().mean_density).epsilon(1e-12));
  const nbs::Pose start = matrix_of(j.at("path").at("start").at("T_WS"));
  const nbs::Pose end = matrix_of(j.at("path").at("end").at("T_WS"));
  CHECK((start.matrix() - expected.path().start().pose().matrix()).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((end.matrix() - expected.path().end().pose().matrix()).cwiseAbs().maxCoeff() < 1e-9);
  // Flange poses: T_WF · T_FS = T_WS.
  const nbs::Pose start_f = matrix_of(j.at("path").at("start").at("T_WF"));
  const nbs::Pose end_f = matrix_of(j.at("path").at("end").at("T_WF"));
  CHECK(((start_f * T_FS).matrix() - start.matrix()).cwiseAbs().maxCoeff() < 1e-9);
  CHECK(((end_f * T_FS).matrix() - end.matrix()).cwiseAbs().maxCoeff() < 1e-9);

  SECTION("the session's hand-eye transform when there is no --hand-eye") {
    const fs::path with_he = temp_root() / "session_hand_eye";
    if (!fs::exists(with_he)) {
      nbs::RecordedSession rec = nbs::read_session(dir);
      rec.info.hand_eye = T_FS;
      nbs::write_session(with_he, rec);
    }
    const Run h = run_plan(quoted(with_he) + " --threads 1");
    INFO(h.err);
    REQUIRE(h.code == 0);
    const nlohmann::json jh = nlohmann::json::parse(h.out);
    CHECK((matrix_of(jh.at("path").at("end").at("T_WF")).matrix() - end_f.matrix()).cwiseAbs().maxCoeff() < 1e-9);
  }
  SECTION("--method C_H --stop-rule thesis is the thesis's planner") {
    nbs::RuntimeModels thesis_stop;
    thesis_stop.stop_rule = nbs::StopRule::thesis;
    nbs::RuntimePlanner c_h(nbs::kThesisMethod, {}, nbs::presets::dlr_lsp(), kBox, ps, thesis_stop);
    for (const nbs::Scan& s : scans) (void)c_h.integrate(s);
    const nbs::PlanResult want = c_h.next_best_scan();
    REQUIRE(want.ok());
    const Run t = run_plan(quoted(dir) + " --threads 1 --method C_H --stop-rule thesis");
    INFO(t.err);
    REQUIRE(t.code == 0);
    const nlohmann::json jt = nlohmann::json::parse(t.out);
    CHECK(jt.at("method") == "C_H");
    CHECK(jt.at("done") == c_h.done());
    CHECK(jt.at("utility").get<double>() == Approx(want.stats.best_utility).epsilon(1e-12));
    CHECK(jt.at("utility").get<double>() != Approx(expected.stats.best_utility).epsilon(1e-6));  // not the default's
  }
  SECTION("--box instead of the session's box, same plan") {
    const Run b = run_plan(quoted(dir) + " --box=-0.06,-0.06,0,0.06,0.06,0.1");
    INFO(b.err);
    REQUIRE(b.code == 0);
    const nlohmann::json jb = nlohmann::json::parse(b.out);
    CHECK(jb.at("utility").get<double>() == Approx(expected.stats.best_utility).epsilon(1e-12));
    CHECK((matrix_of(jb.at("path").at("start").at("T_WS")).matrix() - start.matrix()).cwiseAbs().maxCoeff() < 1e-9);
    CHECK_FALSE(jb.at("path").at("start").contains("T_WF"));
  }
}

TEST_CASE("nbs_plan on a session without scans gives the planner's first scan", "[tools][nbs_plan]") {
  const fs::path dir = temp_root() / "empty";
  if (!fs::exists(dir)) {
    nbs::SessionInfo info;
    info.unknown_area = kBox;
    nbs::SessionWriter w(dir, info);
  }
  const Run r = run_plan(quoted(dir) + " --seed 5");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j.at("status") == "nothing_seen_yet");
  CHECK(j.at("first_scan") == true);
  CHECK(j.at("utility").is_null());
  const nbs::RuntimePlanner twin(nbs::parse_method("C_H"), {}, nbs::presets::dlr_lsp(), kBox);
  const nbs::LinearScanPath first = twin.first_scan(5);
  CHECK((matrix_of(j.at("path").at("start").at("T_WS")).matrix() - first.start().pose().matrix()).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((matrix_of(j.at("path").at("end").at("T_WS")).matrix() - first.end().pose().matrix()).cwiseAbs().maxCoeff() < 1e-12);
}

TEST_CASE("nbs_plan: bad input exits 2 with a message and writes nothing", "[tools][nbs_plan]") {
  const fs::path dir = temp_root() / "bad_base";
  const nbs::test::SphereOnPedestal sphere;
  const nbs::LaserStripeProfiler lsp = nbs::presets::dlr_lsp();
  if (!fs::exists(dir)) {  // once for every SECTION
    nbs::SessionInfo info;
    nbs::SessionWriter w(dir, info);  // no unknown area
    const nbs::LinearScanPath p(nbs::Viewpoint::look_at(Vec3(0.0, -0.3, 0.04), Vec3(0.0, 0.0, 0.04)),
                                Vec3(0.0, -0.3, 0.05));
    w.append(sphere.scan(p, lsp, 1), p);
  }
  const auto expect_usage = [](const Run& r, const std::string& needle) {
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.out.empty());
    CHECK_THAT(r.err, nbs_test::Contains(needle));
  };
  const std::string box = " --box=-0.06,-0.06,0,0.06,0.06,0.1";
  SECTION("missing session directory") { expect_usage(run_plan(quoted(temp_root() / "nowhere") + box), "nowhere"); }
  SECTION("no box anywhere") { expect_usage(run_plan(quoted(dir)), "--box"); }
  SECTION("bad box") {
    expect_usage(run_plan(quoted(dir) + " --box 0,0,0,1,1"), "'0,0,0,1,1'");
    expect_usage(run_plan(quoted(dir) + " --box 0,0,0,1,1,abc"), "'abc'");
    expect_usage(run_plan(quoted(dir) + " --box 0,0,1,1,1,0"), "min < max");
  }
  SECTION("bad numbers and codes") {
    expect_usage(run_plan(quoted(dir) + box + " --seed 12x"), "'12x'");
    expect_usage(run_plan(quoted(dir) + box + " --threads 0"), "--threads");
    expect_usage(run_plan(quoted(dir) + box + " --method Z_Z"), "'Z_Z'");
    expect_usage(run_plan(quoted(dir) + box + " --stop-rule never"), "'never'");
    expect_usage(run_plan(quoted(dir) + box + " --no-such-option"), "--no-such-option");
  }
  SECTION("malformed session.json") {
    const fs::path bad = temp_root() / "bad_json";
    fs::copy(dir, bad, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    std::ofstream(bad / "session.json") << "{\"format\": \"nbs-session\", \"version\": 1, ";
    expect_usage(run_plan(quoted(bad) + box), "session.json");
  }
  SECTION("missing pose file") {
    const fs::path bad = temp_root() / "bad_poses";
    fs::copy(dir, bad, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    fs::remove(bad / "scan_0000.poses");
    expect_usage(run_plan(quoted(bad) + box), "scan_0000.poses");
  }
  SECTION("hand-eye file missing or not rigid") {
    expect_usage(run_plan(quoted(dir) + box + " --hand-eye " + quoted(temp_root() / "no_he.txt")), "no_he.txt");
    const fs::path he = temp_root() / "skew_he.txt";
    std::ofstream(he) << "1 0 0 0 0 2 0 0 0 0 1 0\n";
    expect_usage(run_plan(quoted(dir) + box + " --hand-eye " + quoted(he)), "not rigid");
  }
  SECTION("bad --config") {
    const fs::path cfg = temp_root() / "cfg.json";
    std::ofstream(cfg) << "{\"seed\": \"x\"}";
    expect_usage(run_plan(quoted(dir) + box + " --config " + quoted(cfg)), "'x'");
  }
}
