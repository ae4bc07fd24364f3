// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Command line and planner set-up file of nbs_eval. Everything is validated here, before any work starts.
/// `--config FILE` is the tools' options file (tools/common/options.hpp); the planner set-up is `--setup FILE`.
///
/// Set-up file (JSON object, every key optional; docs/eval/configs/*.json): each field of nbs::Parameters by its C++
/// name (Tab. 4.3, SI units, e.g. "voxel_size_m": 0.005, "max_scans": 30), "sensor": a laser stripe profiler preset
/// ("dlr_lsp", "scancontrol_2700_100"), "mesh": "noise_robust" (default) | "thesis" and "coverage_estimate": "unknown_open"
/// (default) | "unseen_open" | "unseen_loops" | "thesis" and "keep_exploring": true (default) | false (RuntimeModels::noise_robust_mesh,
/// ::coverage_estimate, PlannerSetting::keep_exploring; the defaults are theirs), "unseen_weight" (β of SGU, ≥ 0) and
/// "unseen_min_edge_distance_m" (SGU, metres, ≥ 0) (RuntimeModels::selection), "stop_rule": "settled" (default) |
/// "thesis" | "max_scans" (RuntimeModels::stop_rule: the rule that judges n_s; every run still goes to n_abort).
/// Unknown keys, wrong types and out-of-range values are errors naming the key.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "nbs/core/parameters.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/planner/runtime_planner.hpp"
#include "nbs/sensor/presets.hpp"

#include "common/options.hpp"
#include "common/robot_option.hpp"

namespace nbs::eval {

/// A usage or input error: printed with the usage, exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The experiment's physical set-up, read from the set-up file (`--sensor` overrides its "sensor").
struct Setup {
  Parameters params{};
  std::string sensor = "dlr_lsp";
  /// Planner choices that are not thesis parameters: keep_exploring (true | false); threads and seed are the
  /// runner's.
  PlannerSetting planner{};
  /// The mesh ("mesh": "thesis" | "noise_robust") and the ĉ_m form ("coverage_estimate": "unknown_open" |
  /// "observable_open" | "unseen_open" | "unseen_loops" | "thesis") of the runtime facade.
  RuntimeModels models{};
};

namespace detail {
inline constexpr std::string_view kMeshNames[] = {"thesis", "noise_robust"};  // index = RuntimeModels::noise_robust_mesh

/// Index of the string value of set-up key `key` in `names`. Throws UsageError naming the key, the value and the
/// valid names.
template <std::size_t N>
[[nodiscard]] std::size_t choice(const nlohmann::json& v, const std::string& key, const std::string_view (&names)[N]) {
  std::string list;
  for (std::string_view n : names) list += (list.empty() ? "" : " | ") + std::string(n);
  if (!v.is_string()) throw UsageError("set-up key '" + key + "' must be a string (" + list + "), got " + v.dump());
  const std::string s = v.get<std::string>();
  for (std::size_t i = 0; i < N; ++i)
    if (s == names[i]) return i;
  throw UsageError("set-up key '" + key + "' must be one of " + list + ", got '" + s + "'");
}
}  // namespace detail

[[nodiscard]] inline LaserStripeProfiler sensor_preset(const std::string& name) {
  if (name == "dlr_lsp") return presets::dlr_lsp();
  if (name == "scancontrol_2700_100") return presets::scancontrol_2700_100();
  if (name == "asus_xtion_pro" || name == "guppy_pro_stereo")
    throw UsageError("sensor '" + name + "' is an area sensor; the runtime planner plans laser stripe scans only "
                     "(valid: dlr_lsp, scancontrol_2700_100)");
  throw UsageError("unknown sensor preset '" + name + "' (valid: dlr_lsp, scancontrol_2700_100)");
}

namespace detail {
template <class T>
void set_field(const nlohmann::json& v, const std::string& key, T& field) {
  if constexpr (std::is_same_v<T, int>) {
    if (!v.is_number_integer()) throw UsageError("set-up key '" + key + "' must be an integer, got " + v.dump());
    const auto x = v.get<std::int64_t>();
    if (x < -1000000000 || x > 1000000000) throw UsageError("set-up key '" + key + "' is out of range: " + v.dump());
    field = static_cast<int>(x);
  } else {
    if (!v.is_number()) throw UsageError("set-up key '" + key + "' must be a number, got " + v.dump());
    field = v.get<double>();
  }
}

/// Calls f(name, field) for every Parameters field.
template <class F>
void for_each_parameter(Parameters& p, F&& f) {
#define NBS_EVAL_FIELD(name) f(#name, p.name)
  NBS_EVAL_FIELD(reduction_radius_m);
  NBS_EVAL_FIELD(normal_radius_m);
  NBS_EVAL_FIELD(mesh_radius_m);
  NBS_EVAL_FIELD(voxel_size_m);
  NBS_EVAL_FIELD(occupied_threshold);
  NBS_EVAL_FIELD(boundary_penalty_threshold);
  NBS_EVAL_FIELD(min_boundary_edges);
  NBS_EVAL_FIELD(boundary_angle_rad);
  NBS_EVAL_FIELD(scan_overlap);
  NBS_EVAL_FIELD(planar_eigenvalue_max);
  NBS_EVAL_FIELD(sharp_corner_rotation_rad);
  NBS_EVAL_FIELD(hole_min_edges);
  NBS_EVAL_FIELD(hole_max_edges);
  NBS_EVAL_FIELD(hole_directions);
  NBS_EVAL_FIELD(quality_weight);
  NBS_EVAL_FIELD(quality_half_scans);
  NBS_EVAL_FIELD(incidence_cutoff_rad);
  NBS_EVAL_FIELD(target_coverage);
  NBS_EVAL_FIELD(target_density);
  NBS_EVAL_FIELD(max_scans);
  NBS_EVAL_FIELD(mode_switch_gain);
  NBS_EVAL_FIELD(object_size_m);
  NBS_EVAL_FIELD(completeness_radius_m);
  NBS_EVAL_FIELD(sphere_path_length_m);
#undef NBS_EVAL_FIELD
}
}  // namespace detail

/// Parameters + sensor as JSON (the keys the set-up file accepts, with their values).
[[nodiscard]] inline nlohmann::json setup_json(Setup s) {
  nlohmann::json j = nlohmann::json::object();
  detail::for_each_parameter(s.params, [&](const char* name, auto& field) { j[name] = field; });
  j["sensor"] = s.sensor;
  j["mesh"] = detail::kMeshNames[s.models.noise_robust_mesh ? 1 : 0];
  j["coverage_estimate"] = kCoverageEstimateNames[static_cast<std::size_t>(s.models.coverage_estimate)];
  j["keep_exploring"] = s.planner.keep_exploring;
  j["unseen_weight"] = s.models.selection.unseen_weight;
  j["unseen_min_edge_distance_m"] = s.models.selection.unseen_min_edge_distance_m;
  j["stop_rule"] = format_stop_rule(s.models.stop_rule);
  return j;
}

/// An eval.json configuration written before later set-up keys existed: SGU's ("unseen_weight",
/// "unseen_min_edge_distance_m") ran with their defaults (no method used them), and n_s was judged by the thesis's
/// rule before "stop_rule" existed. Adds the missing ones, so that such an output can be resumed and merged. Leaves
/// every other key as it is.
[[nodiscard]] inline nlohmann::json with_selection_defaults(nlohmann::json config) {
  if (!config.is_object() || !config.contains("setup") || !config["setup"].is_object()) return config;
  const nlohmann::json defaults = setup_json(Setup{});
  for (const char* key : {"unseen_weight", "unseen_min_edge_distance_m"})
    if (!config["setup"].contains(key)) config["setup"][key] = defaults.at(key);
  if (!config["setup"].contains("stop_rule")) config["setup"]["stop_rule"] = format_stop_rule(StopRule::thesis);
  return config;
}

/// Parses a set-up JSON text. `origin` names the source in messages. Throws UsageError.
[[nodiscard]] inline Setup parse_setup(const std::string& text, const std::string& origin) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw UsageError(origin + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw UsageError(origin + ": must be a JSON object");
  Setup s;
  for (const auto& item : j.items()) {
    // named, not structured bindings: clang before 16 cannot capture those in the lambda below
    const std::string& key = item.key();
    const nlohmann::json& value = item.value();
    if (key == "sensor") {
      if (!value.is_string()) throw UsageError(origin + ": set-up key 'sensor' must be a string, got " + value.dump());
      s.sensor = value.get<std::string>();
      (void)sensor_preset(s.sensor);
      continue;
    }
    try {
      if (key == "mesh") {
        s.models.noise_robust_mesh = detail::choice(value, key, detail::kMeshNames) == 1;
        continue;
      }
      if (key == "stop_rule") {
        s.models.stop_rule = static_cast<StopRule>(detail::choice(value, key, kStopRuleNames));
        continue;
      }
      if (key == "coverage_estimate") {
        s.models.coverage_estimate = static_cast<CoverageEstimate>(detail::choice(value, key, kCoverageEstimateNames));
        continue;
      }
      if (key == "unseen_weight" || key == "unseen_min_edge_distance_m") {
        if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0.0)
          throw UsageError("set-up key '" + key + "' must be a finite number >= 0, got " + value.dump());
        (key == "unseen_weight" ? s.models.selection.unseen_weight : s.models.selection.unseen_min_edge_distance_m) =
            value.get<double>();
        continue;
      }
      if (key == "keep_exploring") {
        if (!value.is_boolean()) throw UsageError("set-up key 'keep_exploring' must be true or false, got " + value.dump());
        s.planner.keep_exploring = value.get<bool>();
        continue;
      }
    } catch (const UsageError& e) {
      throw UsageError(origin + ": " + e.what());
    }
    bool found = false;
    try {
      detail::for_each_parameter(s.params, [&](const char* name, auto& field) {
        if (key == name) {
          detail::set_field(value, key, field);
          found = true;
        }
      });
    } catch (const UsageError& e) {
      throw UsageError(origin + ": " + e.what());
    }
    if (!found) {
      std::string valid;
      detail::for_each_parameter(s.params, [&](const char* name, auto&) { valid += std::string(name) + ", "; });
      throw UsageError(origin + ": unknown set-up key '" + key + "' (valid keys: " + valid + "sensor, mesh, coverage_estimate, keep_exploring, unseen_weight, unseen_min_edge_distance_m, stop_rule)");
    }
  }
  try {
    s.params.validate();
  } catch (const Error& e) {
    throw UsageError(origin + ": out-of-range value: " + e.what());
  }
  return s;
}

[[nodiscard]] inline Setup load_setup(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UsageError("--setup: cannot read '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_setup(ss.str(), "--setup '" + path + "'");
}

/// Options of `nbs_eval` (the run command).
struct Options {
  std::string mesh;
  double size_m = 0.16;
  UpAxis up = UpAxis::y;  // the default of every tool (tools/common/options.hpp kDefaultUp)
  std::string up_name = "y";
  std::vector<Method> methods;
  int runs = 20;
  int scans = 30;
  bool scans_given = false;
  std::uint64_t seed = 1;
  unsigned threads = 2;
  std::string out;
  std::string setup;   ///< `--setup FILE`, empty: the defaults
  std::string sensor;  ///< `--sensor NAME`, empty: the set-up's
  int shard_k = 1, shard_n = 1;  ///< this process runs the (method, run) pairs with index % n == k − 1
  tools::PoseErrorOptions pose;  ///< `--pose-error T_MM,R_DEG`, `--registration none|icp`
  tools::RobotOptions robot;     ///< `--robot PATH`, `--robot-links BASE,FLANGE,SENSOR`
};

inline constexpr std::string_view kUsage =
    "usage: nbs_eval --mesh PATH --out DIR [options]\n"
    "       nbs_eval merge --out DIR SHARD_DIR...\n"
    "       nbs_eval c-obs [--threads N] DIR...\n"
    "Runs the thesis comparison (Sec. 4.7.2, Tab. 4.5) on a mesh: for each method and run r, a simulated\n"
    "autonomous modeling from a seeded initial scan (the same for every method in run r) to n_abort scans.\n"
    "options:\n"
    "  --mesh PATH       OBJ or PLY mesh of the object (required)\n"
    "  --size M          largest bounding-box extent after scaling, metres (default 0.16)\n"
    "  --up x|y|z        axis of the file that points up (default y, as in the bundled bunny and every tool)\n"
    "  --methods LIST    comma-separated method codes (default SGU_H), or 'all' / 'thesis' (the 12 R,I,Q,C x S,B,H)\n"
    "  --method CODE     one method: the same as --methods CODE (not both)\n"
    "  --runs N          runs per method, >= 1 (default 20)\n"
    "  --scans N         n_abort, scans per run (default: max_scans of the set-up, 30)\n"
    "  --seed N          base seed; run r uses a seed derived from (seed, r) only (default 1)\n"
    "  --threads N       parallel runs (each run is single-threaded; results do not depend on N) (default 2)\n"
    "  --out DIR         output directory: runs.jsonl, summary.json, summary.md, summary.csv, eval.json\n"
    "  --setup FILE      planner set-up, JSON: any nbs::Parameters field by name, \"sensor\": dlr_lsp |\n"
    "                    scancontrol_2700_100, \"mesh\": noise_robust | thesis, \"coverage_estimate\": unknown_open |\n"
    "                    observable_open | unseen_open | unseen_loops | thesis, \"keep_exploring\": true |\n"
    "                    false, \"unseen_weight\": beta >= 0 of SGU (default 16), \"unseen_min_edge_distance_m\":\n"
    "                    SGU (default 0.005) (defaults first;\n"
    "                    docs/eval/configs/thesis.json: the thesis's)\n"
    "  --sensor NAME     laser stripe profiler preset: dlr_lsp | scancontrol_2700_100; overrides the set-up's\n"
    "                    \"sensor\" (default: the set-up's, dlr_lsp)\n"
    "  --config FILE     JSON file with options: {\"<long option>\": value, ...} (e.g. \"runs\": 5, \"setup\":\n"
    "                    \"docs/eval/configs/thesis.json\"); the command line wins\n"
    "  --pose-error T_MM,R_DEG  simulated robot pose error per scan path: exactly T_MM mm in a random direction\n"
    "                    and R_DEG degrees about a random axis through the sensor (default: none; docs/evaluation.md)\n"
    "  --registration none|icp  registration of each scan before it is integrated (default none)\n"
    "  --robot PATH      plan for the URDF arm in PATH (needs nbs::kdl and nbs::ompl): only scan paths it can fly\n"
    "                    are kept, transfers between scans planned in joint space; runs.jsonl gains\n"
    "                    unreachable_candidates, transfer_joint_rad, transfer_sensor_m, t_motion_s and\n"
    "                    transfer_failures per scan (default: a free-flying sensor)\n"
    "  --robot-links BASE,FLANGE,SENSOR  the URDF's links (default world,lwr_flange,sensor: data/robots/lwr4.urdf)\n"
    "  --transfer-cost L with --robot: choose the reachable candidate of the largest u*exp(-L*d), d (rad) the\n"
    "                    straight joint-space distance to its start configuration (default 0: utility only)\n"
    "  --transfer-retries N  with --robot: after a failed transfer try up to N next best candidates (default 5)\n"
    "  --shard K/N       run only the K-th of N interleaved shares of the (method, run) pairs (1 <= K <= N)\n"
    "  --help            this text\n"
    "A rerun with the same --out skips finished (method, run) pairs. 'merge' combines shard directories into\n"
    "the output of the unsharded run. 'c-obs' recomputes the observability ceiling c_obs of finished outputs with\n"
    "the scanner's rule (any incidence) and rewrites their records and summaries (run from where they were made).\n"
    "method codes: selection R(andom) I(G) Q(uality) C(IG+Quality) x search S(phere) B(oundary Search)\n"
    "  H(BS + Hole Rescan); peer metrics with BS+HR: OA_H UV_H RSV_H RSE_H PC_H AE_H VG_H; surface gains (ours) SG_H\n"
    "  SGU_H;\n"
    "  the peer planner SEE (Surface Edge Explorer: density frontier, nearest view). Valid codes:\n"
    "  ";

[[nodiscard]] inline std::string usage() {
  std::string u(kUsage);
  for (const Method& m : kAllMethods) u += format_method(m) + " ";
  return u + "\n";
}

namespace detail {
[[nodiscard]] inline long long parse_int(std::string_view s, const std::string& what) {
  long long v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size()) throw UsageError(what + ": not an integer: '" + std::string(s) + "'");
  return v;
}
[[nodiscard]] inline std::uint64_t parse_u64(std::string_view s, const std::string& what) {
  std::uint64_t v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size())
    throw UsageError(what + ": not a non-negative integer: '" + std::string(s) + "'");
  return v;
}
[[nodiscard]] inline double parse_double(const std::string& s, const std::string& what) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != s.size() || s.empty()) throw UsageError(what + ": not a number: '" + s + "'");
  return v;
}
}  // namespace detail

/// Parses the method list ("C_H,C_S", "all", "thesis"). Throws UsageError listing the valid codes.
[[nodiscard]] inline std::vector<Method> parse_methods(const std::string& list) {
  std::vector<Method> out;
  if (list == "all") return {kAllMethods.begin(), kAllMethods.end()};
  if (list == "thesis") return {kAllMethods.begin(), kAllMethods.begin() + 12};
  std::size_t b = 0;
  while (b <= list.size()) {
    const std::size_t e = std::min(list.find(',', b), list.size());
    try {
      const Method m = parse_method(std::string_view(list).substr(b, e - b));
      bool dup = false;
      for (const Method& o : out) dup = dup || o == m;
      if (!dup) out.push_back(m);
    } catch (const Error& err) {
      throw UsageError(std::string("--methods: ") + err.what());
    }
    b = e + 1;
  }
  return out;
}

namespace detail {
/// Whether `name` is among the arguments themselves (`name V` or `name=V`), not only in a `--config` file.
[[nodiscard]] inline bool given(const std::vector<std::string>& args, std::string_view name) {
  for (const std::string& a : args)
    if (a == name || (a.starts_with(name) && a.size() > name.size() && a[name.size()] == '=')) return true;
  return false;
}
}  // namespace detail

/// Parses the run command's arguments (argv[0] excluded) with the tools' shared options (tools/common/options.hpp:
/// --mesh --up --size --seed --method --sensor --config --out). Throws UsageError naming the option and the value.
/// Sets `help` for --help.
[[nodiscard]] inline Options parse_options(const std::vector<std::string>& args, bool& help) {
  Options o;
  o.methods = {Method{}};
  help = false;
  CLI::App app("nbs_eval", "nbs_eval");
  tools::set_conventions(app);
  tools::add_mesh(app, o.mesh, "OBJ or PLY mesh of the object")->required();
  tools::add_size(app, o.size_m);
  tools::add_up(app, o.up)->each([&o](const std::string& v) { o.up_name = v; });
  std::vector<Method> list;
  app.add_option_function<std::string>("--methods", [&list](const std::string& v) { list = parse_methods(v); });
  Method one{};
  tools::add_method(app, one);
  tools::add_sensor(app, o.sensor);
  app.add_option("--setup", o.setup);
  tools::add_config(app);
  app.add_option("--runs", o.runs)->check(tools::integer_in(1, 1000000));
  app.add_option_function<int>("--scans", [&o](int n) { o.scans = n, o.scans_given = true; })
      ->check(tools::integer_in(1, 100000));
  tools::add_seed(app, o.seed);
  app.add_option("--threads", o.threads)->check(tools::integer_in(1, 1024));
  tools::add_out(app, o.out)->required();
  tools::add_pose_error_options(app, o.pose);
  tools::add_robot_options(app, o.robot);
  app.add_option_function<std::string>("--shard", [&o](const std::string& v) {
    const std::size_t slash = v.find('/');
    if (slash == std::string::npos) throw UsageError("--shard must be K/N, got '" + v + "'");
    const long long k = detail::parse_int(std::string_view(v).substr(0, slash), "--shard K");
    const long long n = detail::parse_int(std::string_view(v).substr(slash + 1), "--shard N");
    if (n < 1 || n > 100000 || k < 1 || k > n) throw UsageError("--shard K/N needs 1 <= K <= N, got '" + v + "'");
    o.shard_k = static_cast<int>(k);
    o.shard_n = static_cast<int>(n);
  });
  try {
    std::vector<std::string> all = tools::with_config(app, args);
    std::reverse(all.begin(), all.end());  // CLI11 takes the arguments reversed
    app.parse(all);
  } catch (const CLI::CallForHelp&) {
    help = true;
    return o;
  } catch (const CLI::ParseError& e) {
    const std::string what = e.what();
    if (what.starts_with("--config") && what.find("unknown key") != std::string::npos)
      throw UsageError(what + "; a planner set-up file is --setup FILE");
    throw UsageError(what);
  }
  // --method and --methods: one of them, or the one on the command line over the other in the --config file.
  const bool method = app.count("--method") > 0, methods = app.count("--methods") > 0;
  if (method && methods && detail::given(args, "--method") == detail::given(args, "--methods"))
    throw UsageError("--method and --methods: give one of them, not both");
  if (method && (!methods || detail::given(args, "--method"))) o.methods = {one};
  else if (methods) o.methods = list;
  if (o.mesh.empty()) throw UsageError("--mesh is required");
  if (o.out.empty()) throw UsageError("--out is required");
  return o;
}

/// The set-up of a run: `--setup`'s file (the defaults without it) with its "sensor" replaced by `--sensor` if
/// given. Throws UsageError.
[[nodiscard]] inline Setup resolve_setup(const Options& o) {
  Setup s = o.setup.empty() ? Setup{} : load_setup(o.setup);
  if (!o.sensor.empty()) s.sensor = o.sensor;
  return s;
}

}  // namespace nbs::eval
