// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The option set shared by nbs's command-line tools (CLI11): `--mesh --up --size --seed --method --sensor --config
/// --out` mean the same in every tool, with the same defaults. `parse` runs a CLI11 app with the nbs conventions:
/// `--help` prints and exits 0; a bad option or value prints `<tool>: <message naming option and value>` and the
/// hint to `--help` on stderr and exits 2 (kUsageExit); `--config FILE` reads a JSON object whose keys are long
/// option names without `--` (`{"size": 0.2, "up": "z", "no-images": true}`), the command line wins over the file.
/// `--pose-error` and `--registration` (nbs_model, nbs_eval) are declared here once as well.
/// Used by nbs_plan, nbs_model, nbs_diagnose and nbs_eval (whose planner set-up file is `--setup`, and which takes
/// `--methods LIST` next to `--method`: benchmarks/eval/config.hpp).

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "nbs/core/parameters.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/planner/runtime_planner.hpp"
#include "nbs/registration/selectable_registration.hpp"
#include "nbs/sim/pose_error.hpp"
#include "nbs/sensor/presets.hpp"

namespace nbs::tools {

/// Exit code for bad input (options, values, input files); 1 is left for failures while running.
inline constexpr int kUsageExit = 2;

/// `--up` default: y, the up axis of the bundled Stanford bunny OBJ, the default `--mesh` of every tool (and of the
/// Stanford repository's meshes); z-up files (nbs's own PLY output, rocker-arm) pass `--up z`.
inline constexpr UpAxis kDefaultUp = UpAxis::y;

[[nodiscard]] inline std::string_view format_up(UpAxis up) { return up == UpAxis::x ? "x" : up == UpAxis::y ? "y" : "z"; }
/// The axis named "x", "y" or "z"; std::nullopt for anything else.
[[nodiscard]] inline std::optional<UpAxis> parse_up(std::string_view v) {
  if (v == "x") return UpAxis::x;
  if (v == "y") return UpAxis::y;
  if (v == "z") return UpAxis::z;
  return std::nullopt;
}

/// A value that is wrong for its option; `parse` prints it and exits 2.
struct UsageError : CLI::ValidationError {
  UsageError(const std::string& option, const std::string& what) : CLI::ValidationError(option, what) {}
};

/// `--mesh PATH`: the ground-truth mesh, OBJ or PLY (read by load_mesh; its errors are usage errors).
inline CLI::Option* add_mesh(CLI::App& app, std::string& path, const std::string& what = "ground-truth mesh, OBJ or PLY") {
  return app.add_option("--mesh", path, what)->type_name("PATH");
}

/// `--up x|y|z`: the axis of the mesh file that points up (default kDefaultUp).
inline CLI::Option* add_up(CLI::App& app, UpAxis& up) {
  up = kDefaultUp;
  return app
      .add_option_function<std::string>(
          "--up",
          [&up](const std::string& v) {
            const std::optional<UpAxis> a = parse_up(v);
            if (!a) throw UsageError("--up", "expects x, y or z, got '" + v + "'");
            up = *a;
          },
          "axis of the mesh file that points up: x, y or z (default y, as in the bundled bunny)")
      ->type_name("AXIS");
}

/// The finite number that is all of `s`, or std::nullopt.
[[nodiscard]] inline std::optional<double> finite_number(const std::string& s) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

/// A finite number > 0 (CLI11 validator naming the value).
inline const CLI::Validator kPositive(
    [](std::string& s) -> std::string {
      const std::optional<double> v = finite_number(s);
      if (!v || !(*v > 0.0)) return "expects a finite number > 0, got '" + s + "'";
      return {};
    },
    "", "positive");

/// `--size M`: largest extent of the object after normalisation, metres (default Parameters::object_size_m).
inline CLI::Option* add_size(CLI::App& app, double& size_m) {
  return app.add_option("--size", size_m, "largest extent of the object after normalisation, metres, > 0")
      ->check(kPositive)
      ->type_name("M")
      ->capture_default_str();
}

/// An unsigned integer in [lo, hi] (CLI11 validator naming the value; rejects signs and trailing text).
[[nodiscard]] inline CLI::Validator integer_in(std::uint64_t lo, std::uint64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& s) -> std::string {
        std::size_t used = 0;
        unsigned long long v = 0;
        try {
          if (!s.empty() && s[0] != '-' && s[0] != '+') v = std::stoull(s, &used, 10);
        } catch (const std::exception&) {
          used = 0;
        }
        if (s.empty() || used != s.size() || v < lo || v > hi)
          return "expects an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + s + "'";
        return {};
      },
      "", "integer_in");
}

/// `--seed N`: seed of everything random in the tool (default 1).
inline CLI::Option* add_seed(CLI::App& app, std::uint64_t& seed) {
  return app.add_option("--seed", seed, "seed of the first scan path, sensor noise, samples and Random selection")
      ->check(integer_in(0, ~0ULL))
      ->type_name("N")
      ->capture_default_str();
}

/// `--method CODE`: the planning method (parse_method; default SGU_H, kDefaultMethod).
inline CLI::Option* add_method(CLI::App& app, Method& method) {
  return app
      .add_option_function<std::string>(
          "--method",
          [&method](const std::string& v) {
            try {
              method = parse_method(v);
            } catch (const InvalidArgument& e) {
              throw UsageError("--method", e.what());
            }
          },
          "planning method (default SGU_H): R|I|Q|C _ S|B|H (Fig. 4.19) or OA_H UV_H RSV_H RSE_H PC_H AE_H VG_H SG_H SGU_H, or the "
          "peer planner SEE")
      ->type_name("CODE");
}

/// `--sensor NAME`: a laser stripe profiler preset (presets::lsp_by_name; default dlr_lsp).
inline CLI::Option* add_sensor(CLI::App& app, std::string& name) {
  std::string names;  // the laser stripe profiler presets
  for (std::string_view n : presets::kNames)
    if (std::holds_alternative<LaserStripeProfiler>(presets::by_name(n))) (names += names.empty() ? "" : ", ") += n;
  return app
      .add_option_function<std::string>(
          "--sensor",
          [&name](const std::string& v) {
            try {
              (void)presets::lsp_by_name(v);
            } catch (const InvalidArgument& e) {
              throw UsageError("--sensor", e.what());
            }
            name = v;
          },
          "laser stripe profiler preset: " + names + " (default dlr_lsp)")
      ->type_name("NAME");
}

/// `--scans N`: n_abort, the hard limit on the number of scans (Tab. 4.3), 1 to 1000.
inline CLI::Option* add_scans(CLI::App& app, int& scans) {
  return app.add_option("--scans", scans, "n_abort, hard limit on the number of scans (Tab. 4.3)")
      ->check(integer_in(1, 1000))
      ->capture_default_str();
}

/// `--threads N`: candidate evaluation threads, 1 to 1024 (results do not depend on it).
inline CLI::Option* add_threads(CLI::App& app, unsigned& threads) {
  return app.add_option("--threads", threads, "candidate evaluation threads (default: hardware threads); same results")
      ->check(integer_in(1, 1024));
}

/// `--thesis-mesh`: the thesis's mesh, estimated coverage and stop rule (RuntimeModels::thesis).
inline CLI::Option* add_thesis_mesh(CLI::App& app, bool& thesis_mesh) {
  return app.add_flag("--thesis-mesh", thesis_mesh,
                      "the thesis's mesh, estimated coverage and stop rule (RuntimeModels::thesis) instead of the "
                      "noise-robust mesh, the unknown_open estimate and the settled stop rule");
}

/// `--stop-rule settled|thesis|max_scans` (nbs_model, nbs_plan): the planner's stop rule (RuntimeModels::stop_rule);
/// unset: the settled rule, or the thesis's with --thesis-mesh. `--method C_H --stop-rule thesis` is ThesisPlanner<>.
inline CLI::Option* add_stop_rule(CLI::App& app, std::optional<StopRule>& rule) {
  return app
      .add_option_function<std::string>(
          "--stop-rule",
          [&rule](const std::string& v) {
            try {
              rule = parse_stop_rule(v);
            } catch (const InvalidArgument& e) {
              throw UsageError("--stop-rule", e.what());
            }
          },
          "stop rule: settled (default: ĉ_m held 0.9 on 2 scans, settled or stalled), thesis (ĉ_m >= 0.8 and d_m >= 0.2; the "
          "default with --thesis-mesh) or max_scans (n_abort only)")
      ->type_name("RULE");
}

/// The models of a planning run: RuntimeModels::thesis() with --thesis-mesh, else the defaults; then --stop-rule.
[[nodiscard]] inline RuntimeModels run_models(bool thesis_mesh, const std::optional<StopRule>& stop_rule) {
  RuntimeModels m = thesis_mesh ? RuntimeModels::thesis() : RuntimeModels{};
  if (stop_rule) m.stop_rule = *stop_rule;
  return m;
}

/// The object options of the simulating tools (nbs_model, nbs_diagnose): `--mesh --up --size --sensor`, into the
/// members `mesh`, `up`, `size_m`, `sensor` of `o`.
template <class O>
void add_object_options(CLI::App& app, O& o) {
  add_mesh(app, o.mesh, "ground-truth mesh, OBJ or PLY (default: the bundled Stanford bunny)");
  add_up(app, o.up);
  add_size(app, o.size_m);
  add_sensor(app, o.sensor);
}

/// The options of a planning run (nbs_model, nbs_diagnose, nbs_plan): `--method --seed --scans --threads
/// --thesis-mesh`, into the members `method`, `seed`, `scans`, `threads`, `thesis_mesh` of `o`.
template <class O>
void add_run_options(CLI::App& app, O& o) {
  add_method(app, o.method);
  add_seed(app, o.seed);
  add_scans(app, o.scans);
  add_threads(app, o.threads);
  add_thesis_mesh(app, o.thesis_mesh);
}

/// `--pose-error T_MM,R_DEG` and `--registration none|icp` (nbs_model, nbs_eval): a simulated robot pose error
/// (sim/pose_error.hpp) of exactly T_MM millimetres and R_DEG degrees per scan path, and the registration step that
/// may correct it (RuntimeModels::registration). Neither given: the tools behave as without them, byte for byte.
struct PoseErrorOptions {
  std::optional<double> translation_mm, rotation_deg;  ///< both set by --pose-error
  std::optional<RegistrationMethod> registration;       ///< --registration

  /// Whether either option was given (the tools then report residual pose error and registration per scan).
  [[nodiscard]] bool active() const { return translation_mm.has_value() || registration.has_value(); }

  /// The error setting of a run with seed `run_seed` (zero error without --pose-error); its seed is derived from
  /// `run_seed` only, so every method sees the same errors in the same run.
  [[nodiscard]] PoseErrorSetting setting(std::uint64_t run_seed) const {
    PoseErrorSetting s;
    s.translation_m = 1e-3 * translation_mm.value_or(0.0);
    s.rotation_rad = rotation_deg.value_or(0.0) * std::numbers::pi / 180.0;
    s.seed = nbs::detail::splitmix64(run_seed ^ 0x504F53454552524FULL);
    return s;
  }
};

/// Adds `--pose-error T_MM,R_DEG` (two finite numbers >= 0; R_DEG <= 180) and `--registration none|icp`.
inline void add_pose_error_options(CLI::App& app, PoseErrorOptions& o) {
  app.add_option_function<std::string>(
         "--pose-error",
         [&o](const std::string& v) {
           const auto bad = [&v] {
             return UsageError("--pose-error",
                               "expects T_MM,R_DEG (two finite numbers >= 0: millimetres, degrees <= 180), got '" + v + "'");
           };
           const std::size_t comma = v.find(',');
           if (comma == std::string::npos) throw bad();
           const std::optional<double> t = finite_number(v.substr(0, comma)), r = finite_number(v.substr(comma + 1));
           if (!t || !r || !(*t >= 0.0) || !(*r >= 0.0) || *r > 180.0) throw bad();
           o.translation_mm = *t;
           o.rotation_deg = *r;
         },
         "simulated robot pose error per scan path: translation in mm, rotation in degrees (e.g. 1,0.1: the KR16's "
         "millimetre range, Sec. 5.1.1); default: none")
      ->type_name("T_MM,R_DEG");
  app.add_option_function<std::string>(
         "--registration",
         [&o](const std::string& v) {
           try {
             o.registration = parse_registration_method(v);
           } catch (const InvalidArgument& e) {
             throw UsageError("--registration", e.what());
           }
         },
         "registration of each scan before it is integrated (Sec. 3.2.3): none or icp (default none)")
      ->type_name("none|icp");
}

/// `--out DIR`: output directory, created if missing.
inline CLI::Option* add_out(CLI::App& app, std::string& dir) {
  return app.add_option("--out", dir, "output directory, created if missing")->type_name("DIR")->capture_default_str();
}

/// `--config FILE` (read by `parse` before the command line; listed here for --help).
inline CLI::Option* add_config(CLI::App& app) {
  return app.add_option("--config", "JSON file with options: {\"<long option>\": value, ...}; the command line wins")
      ->type_name("FILE");
}

namespace detail {
/// The value of `--config` in the arguments, if any (`--config F` or `--config=F`).
[[nodiscard]] inline std::optional<std::string> config_argument(const std::vector<std::string>& args) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    if (a == "--config") return i + 1 < args.size() ? std::optional<std::string>(args[i + 1]) : std::nullopt;
    if (a.starts_with("--config=")) return std::string(a.substr(9));
  }
  return std::nullopt;
}

/// The arguments that the JSON object in `path` stands for. Throws UsageError naming the file, key and value.
[[nodiscard]] inline std::vector<std::string> config_arguments(const CLI::App& app, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError("--config", path + ": cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(ss.str());
  } catch (const nlohmann::json::exception& e) {
    throw UsageError("--config", path + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw UsageError("--config", path + ": must hold a JSON object, got " + j.type_name());
  std::vector<std::string> args;
  for (const auto& [key, value] : j.items()) {
    const CLI::Option* opt = app.get_option_no_throw("--" + key);
    if (key == "config" || opt == nullptr)
      throw UsageError("--config", path + ": unknown key '" + key + "' (keys are the tool's long options without --)");
    const std::string name = "--" + key;
    if (opt->get_expected_max() == 0) {  // a flag
      if (!value.is_boolean()) throw UsageError("--config", path + ": '" + key + "' is a flag and needs true or false");
      if (value.get<bool>()) args.push_back(name);
      continue;
    }
    if (value.is_string()) args.insert(args.end(), {name, value.get<std::string>()});
    else if (value.is_number()) args.insert(args.end(), {name, value.dump()});
    else throw UsageError("--config", path + ": '" + key + "' needs a string or a number, got " + value.dump());
  }
  return args;
}
}  // namespace detail

/// The arguments (argv[0] excluded) with those of `--config FILE` put first, so that the command line wins.
/// Throws UsageError naming the file, key and value.
[[nodiscard]] inline std::vector<std::string> with_config(const CLI::App& app, const std::vector<std::string>& args) {
  std::vector<std::string> all;
  if (const auto cfg = detail::config_argument(args)) all = detail::config_arguments(app, *cfg);
  all.insert(all.end(), args.begin(), args.end());
  return all;
}

/// Sets the nbs conventions on a new app (a repeated option: the last value wins); call before adding options.
inline void set_conventions(CLI::App& app) {
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

/// Parses argv (after `--config FILE`'s options) into `app`. Returns the exit code if the tool must stop (0 after
/// --help, kUsageExit after printing the error), std::nullopt to go on.
[[nodiscard]] inline std::optional<int> parse(CLI::App& app, int argc, char** argv) {
  try {
    std::vector<std::string> args = with_config(app, std::vector<std::string>(argv + 1, argv + argc));
    std::reverse(args.begin(), args.end());  // CLI11 takes the arguments reversed
    app.parse(args);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << app.get_name() << ": " << e.what() << "\nRun with --help for more information.\n";
    return kUsageExit;
  }
  return std::nullopt;
}

}  // namespace nbs::tools
