// SPDX-License-Identifier: BSD-3-Clause
// nbs_plan — the next best scan for a recorded session (docs/session-format.md): reads the session directory,
// integrates every scan into a RuntimePlanner (the session's sensor preset, the unknown area from the session or
// --box) and prints the next best scan as JSON on stdout: the path's start and end sensor poses T_WS (4×4 row-major,
// metres), the utility, the mode (BS / HR), ĉ_m, d̄_m and whether the planner is done; with a hand-eye transform
// T_FS (--hand-eye FILE, else the session's) also the flange poses T_WF = T_WS · T_FS⁻¹. Before any scan it gives
// the planner's first scan. Bad input: message on stderr naming the file or option and the value, exit 2, no output.

#include "nbs/planner/runtime_planner.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/options.hpp"
#include "nbs/io/pose_file.hpp"
#include "nbs/io/session.hpp"

namespace {

struct Options {
  std::string session;
  std::optional<nbs::Aabb> box;
  std::string hand_eye;
  nbs::Method method{};
  std::uint64_t seed = 1;
  int scans = nbs::Parameters{}.max_scans;
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  bool thesis_mesh = false;
  std::optional<nbs::StopRule> stop_rule;
};

/// `xmin,ymin,zmin,xmax,ymax,zmax` in metres, finite, min < max on every axis.
nbs::Aabb parse_box(const std::string& s) {
  const auto bad = [&](const std::string& why) {
    return nbs::tools::UsageError("--box", "expects xmin,ymin,zmin,xmax,ymax,zmax in metres, " + why + ", got '" + s + "'");
  };
  std::array<double, 6> v{};
  std::size_t pos = 0;
  for (std::size_t k = 0; k < 6; ++k) {
    const std::size_t comma = k < 5 ? s.find(',', pos) : s.size();
    if (comma == std::string::npos) throw bad("6 numbers");
    const std::string_view f = std::string_view(s).substr(pos, comma - pos);
    const auto r = std::from_chars(f.data(), f.data() + f.size(), v[k]);
    if (f.empty() || r.ec != std::errc() || r.ptr != f.data() + f.size() || !std::isfinite(v[k]))
      throw bad("number " + std::to_string(k + 1) + " '" + std::string(f) + "' is not a finite number");
    pos = comma + 1;
  }
  if (pos != s.size() + 1) throw bad("6 numbers");
  nbs::Aabb box{nbs::Vec3(v[0], v[1], v[2]), nbs::Vec3(v[3], v[4], v[5])};
  if ((box.min.array() >= box.max.array()).any()) throw bad("min < max on every axis");
  return box;
}

nlohmann::json matrix_json(const nbs::Pose& T) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({T(r, 0), T(r, 1), T(r, 2), T(r, 3)});
  return rows;
}

/// Start and end poses of `path`, sensor (T_WS) and, given T_FS, flange (T_WF = T_WS · T_FS⁻¹).
nlohmann::json path_json(const nbs::LinearScanPath& path, const std::optional<nbs::Pose>& T_FS) {
  const nbs::Pose start = path.start().pose(), end = path.end().pose();
  nlohmann::json j = {{"start", {{"T_WS", matrix_json(start)}}}, {"end", {{"T_WS", matrix_json(end)}}},
                      {"length_m", path.length()}};
  if (T_FS) {
    const nbs::Pose T_SF = T_FS->inverse(Eigen::Isometry);
    j["start"]["T_WF"] = matrix_json(start * T_SF);
    j["end"]["T_WF"] = matrix_json(end * T_SF);
  }
  return j;
}

/// Everything that can be wrong with the input throws nbs::Error (FileError, InvalidArgument) or UsageError.
nlohmann::json plan(const Options& o) {
  using namespace nbs;
  const RecordedSession session = read_session(o.session);
  if (!o.box && !session.info.unknown_area)
    throw tools::UsageError("--box", o.session + "/session.json records no unknown_area; give the box with --box");
  const Aabb box = o.box ? *o.box : *session.info.unknown_area;
  std::optional<Pose> T_FS = session.info.hand_eye;
  if (!o.hand_eye.empty()) {
    const std::vector<Pose> poses = read_pose_file(o.hand_eye);
    if (poses.size() != 1)
      throw FileError(detail::concat(o.hand_eye, ": a hand-eye file holds 1 pose (T_FS), got ", poses.size()));
    T_FS = poses[0];
  }
  LaserStripeProfiler lsp;
  try {
    lsp = presets::lsp_by_name(session.info.sensor);
  } catch (const InvalidArgument& e) {
    throw FileError(detail::concat(o.session, "/session.json: sensor: ", e.what()));
  }
  Parameters params;
  params.max_scans = o.scans;
  PlannerSetting ps;
  ps.threads = o.threads;
  ps.seed = o.seed;
  RuntimePlanner planner(o.method, params, lsp, box, ps, tools::run_models(o.thesis_mesh, o.stop_rule));
  nlohmann::json integrated = nlohmann::json::array();
  for (std::size_t i = 0; i < session.scans.size(); ++i) {
    try {
      integrated.push_back(to_string(planner.integrate(session.scans[i].scan).status));
    } catch (const InvalidArgument& e) {
      throw FileError(detail::concat(o.session, ": scan ", i, ": ", e.what()));
    }
  }
  nlohmann::json j;
  j["session"] = o.session;
  j["method"] = planner.code();
  j["sensor"] = session.info.sensor;
  j["unknown_area"] = {{"min", {box.min.x(), box.min.y(), box.min.z()}}, {"max", {box.max.x(), box.max.y(), box.max.z()}}};
  j["scans"] = session.scans.size();
  j["integration"] = integrated;
  const PlanResult r = planner.next_best_scan();
  j["status"] = r.status == PlanStatus::ok ? "ok"
                : r.status == PlanStatus::nothing_seen_yet ? "nothing_seen_yet"
                : r.status == PlanStatus::done ? "done"
                                               : "no_candidates";
  j["done"] = planner.done();
  j["mode"] = to_string(r.ok() ? r.stats.mode : planner.mode());
  const ModelProgress p = planner.progress();
  j["estimated_coverage"] = p.estimated_coverage;
  j["mean_density"] = p.mean_density;
  j["candidates"] = r.stats.evaluated;
  if (r.ok()) {
    j["utility"] = r.stats.best_utility;
    j["path"] = path_json(r.path(), T_FS);
  } else if (r.status == PlanStatus::nothing_seen_yet) {
    j["utility"] = nullptr;
    j["path"] = path_json(planner.first_scan(o.seed), T_FS);  // the first scan (Sec. 4.1)
    j["first_scan"] = true;
  } else {
    j["utility"] = nullptr;
    j["path"] = nullptr;
  }
  return j;
}

/// `j` as dump(2) does, except that an array of numbers (a matrix row, a point) is written on one line.
void print_json(std::ostream& os, const nlohmann::json& j, int indent = 0) {
  const auto flat = [](const nlohmann::json& a) {
    return a.is_array() && !a.empty() && std::all_of(a.begin(), a.end(), [](const auto& x) { return x.is_number(); });
  };
  const std::string pad(static_cast<std::size_t>(indent + 2), ' ');
  if (flat(j) || !j.is_structured() || j.empty()) {
    os << j.dump();  // compact: [1.0,0.0,0.0,0.1]
    return;
  }
  const bool object = j.is_object();
  os << (object ? "{\n" : "[\n");
  bool first = true;
  for (auto it = j.begin(); it != j.end(); ++it) {
    os << (first ? "" : ",\n") << pad;
    first = false;
    if (object) os << nlohmann::json(it.key()).dump() << ": ";
    print_json(os, *it, indent + 2);
  }
  os << "\n" << std::string(static_cast<std::size_t>(indent), ' ') << (object ? "}" : "]");
}

}  // namespace

int main(int argc, char** argv) {
  namespace tools = nbs::tools;
  Options o;
  CLI::App app("Prints the next best scan for a recorded session directory as JSON on stdout.", "nbs_plan");
  tools::set_conventions(app);
  app.add_option("session", o.session, "recorded session directory (docs/session-format.md)")
      ->required()
      ->type_name("DIR");
  app.add_option_function<std::string>(
         "--box", [&o](const std::string& v) { o.box = parse_box(v); },
         "unknown area xmin,ymin,zmin,xmax,ymax,zmax in metres (default: the session's unknown_area)")
      ->type_name("BOX");
  app.add_option("--hand-eye", o.hand_eye, "pose file (KITTI 3x4) with T_FS; adds flange poses T_WF = T_WS T_FS^-1 "
                                           "(default: the session's hand_eye, if recorded)")
      ->type_name("FILE");
  tools::add_run_options(app, o);
  tools::add_stop_rule(app, o.stop_rule);
  tools::add_config(app);
  if (const auto code = tools::parse(app, argc, argv)) return *code;
  nlohmann::json out;
  try {
    out = plan(o);
  } catch (const CLI::ValidationError& e) {
    std::cerr << "nbs_plan: " << e.what() << "\n";
    return tools::kUsageExit;
  } catch (const nbs::Error& e) {
    std::cerr << "nbs_plan: " << e.what() << "\n";
    return tools::kUsageExit;
  } catch (const std::exception& e) {
    std::cerr << "nbs_plan: error: " << e.what() << "\n";
    return 1;
  }
  print_json(std::cout, out);
  std::cout << "\n";
  return std::cout.good() ? 0 : 1;
}
