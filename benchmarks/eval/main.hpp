// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// nbs_eval as a function, `nbs::eval::main(argc, argv)` (callable from tests). See config.hpp for the options.
/// Output directory: eval.json (configuration + c_obs), runs.jsonl (one line per run, appended and flushed per
/// finished run, rewritten sorted by (method, run) at the end), summary.json / summary.md / summary.csv.

#include "eval/runner.hpp"  // first: includes the planner headers

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "eval/ceiling.hpp"
#include "eval/config.hpp"
#include "eval/records.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"

namespace nbs::eval {

namespace detail {

namespace fs = std::filesystem;

/// Writes `text` to `path` through a temporary file renamed into place.
inline void write_text(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write '" + tmp.string() + "'");
    out << text;
    if (!out.flush()) throw std::runtime_error("cannot write '" + tmp.string() + "'");
  }
  fs::rename(tmp, path);
}

[[nodiscard]] inline std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError("cannot read '" + path.string() + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The parsed lines of a runs.jsonl, keyed by (method rank, run). Lines that do not parse (e.g. the partial last
/// line of an interrupted run) are skipped with a warning; a duplicate (method, run) keeps the first.
using RunMap = std::map<std::pair<std::size_t, int>, Json>;

inline void read_runs(const fs::path& path, RunMap& runs, std::ostream& log) {
  std::ifstream in(path);
  if (!in) return;
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    try {
      Json j = Json::parse(line);
      const RunRecord r = record_from_json(j);
      runs.emplace(std::make_pair(method_rank(r.method), r.run), std::move(j));
    } catch (const std::exception& e) {
      log << "nbs_eval: warning: " << path.string() << ":" << n << ": skipping unreadable line (" << e.what() << ")\n";
    }
  }
}

/// Rewrites runs.jsonl sorted and writes the three summaries.
inline void write_outputs(const fs::path& dir, const RunMap& runs, int n_abort) {
  std::string lines;
  std::vector<RunRecord> records;
  for (const auto& [key, j] : runs) {
    lines += j.dump() + "\n";
    records.push_back(record_from_json(j));
  }
  write_text(dir / "runs.jsonl", lines);
  const std::vector<MethodSummary> rows = records.empty() ? std::vector<MethodSummary>{} : summarize_records(records);
  write_text(dir / "summary.json", summary_json(rows).dump(2) + "\n");
  write_text(dir / "summary.md", summary_markdown(rows, n_abort));
  write_text(dir / "summary.csv", summary_csv(rows));
}

/// Progress on stderr: a bar redrawn in place on a terminal, else one line per finished run.
class Progress {
public:
  Progress(std::size_t total, std::ostream& log) : total_(total), log_(log), tty_(::isatty(2) == 1) {}
  void finished(const RunRecord& r) {
    ++done_;
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    const double eta = done_ ? el / static_cast<double>(done_) * static_cast<double>(total_ - done_) : 0.0;
    char buf[256];
    if (tty_) {
      constexpr int kWidth = 30;
      const int fill = static_cast<int>(kWidth * done_ / std::max<std::size_t>(total_, 1));
      std::snprintf(buf, sizeof buf, "\r[%s%s] %zu/%zu runs  %.0f s elapsed  ETA %.0f s  (last %s #%d n_s %d)   ",
                    std::string(static_cast<std::size_t>(fill), '#').c_str(),
                    std::string(static_cast<std::size_t>(kWidth - fill), '.').c_str(), done_, total_, el, eta,
                    r.method.c_str(), r.run, r.n_s);
      log_ << buf << (done_ == total_ ? "\n" : "") << std::flush;
    } else {
      std::snprintf(buf, sizeof buf, "run %zu/%zu  %s #%d  n_s %d  c_a(n_s) %.2f %%  c_a(end) %.2f %%  l_s %.2f m  %.0f s\n",
                    done_, total_, r.method.c_str(), r.run, r.n_s,
                    100.0 * outcome(r).ca_at_stop, 100.0 * r.scans.back().c_a, r.scans.back().l_s_m, el);
      log_ << buf << std::flush;
    }
  }

private:
  std::size_t total_, done_ = 0;
  std::ostream& log_;
  bool tty_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

/// The configuration that determines the results (everything but --runs, --methods, --threads, --shard); a rerun
/// into the same --out skips finished runs only if it is equal (pose error and registration included).
[[nodiscard]] inline Json eval_json(const Options& o, const Setup& s) {
  Json j{{"mesh", o.mesh}, {"size_m", o.size_m}, {"up", o.up_name}, {"seed", o.seed},
         {"n_abort", o.scans}, {"setup", setup_json(s)}};
  // Only when given, so that the configuration of runs without them stays as it was.
  if (o.pose.translation_mm)
    j["pose_error"] = Json{{"translation_mm", *o.pose.translation_mm}, {"rotation_deg", *o.pose.rotation_deg}};
  if (o.pose.registration) j["registration"] = std::string(to_string(*o.pose.registration));
  if (o.robot.active())
    j["robot"] = Json{{"urdf", o.robot.urdf},
                      {"links", {o.robot.base_link, o.robot.flange_link, o.robot.sensor_link}}};
  if (o.robot.active() && o.robot.transfer_cost != 0.0) j["robot"]["transfer_cost"] = o.robot.transfer_cost;
  if (o.robot.active() && o.robot.transfer_retries != 5) j["robot"]["transfer_retries"] = o.robot.transfer_retries;
  return j;
}

inline int run_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& log) {
  bool help = false;
  Options o = parse_options(args, help);
  if (help) {
    out << usage();
    return 0;
  }
  Setup setup = resolve_setup(o);
  if (o.scans_given) setup.params.max_scans = o.scans;
  else o.scans = setup.params.max_scans;
  setup.params.object_size_m = o.size_m;
  try {
    setup.params.validate();
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
  const LaserStripeProfiler sensor = sensor_preset(setup.sensor);
  const IndexedMesh mesh = load_eval_mesh(o.mesh, o.size_m, o.up);

  // --robot: loaded and the object checked to be in its reach before any work (a bad file names its path).
  std::optional<tools::LoadedRobot> robot;
  try {
    if (o.robot.active()) {
      robot = tools::load_robot(o.robot);
      require_object_in_reach(robot->robot, unknown_area_of(mesh, o.size_m).center(),
                              0.5 * (sensor.range.min_m + sensor.range.max_m), robot->start);
    }
  } catch (const Error& e) {
    throw UsageError(std::string("--robot: ") + e.what());
  }

  const fs::path dir(o.out);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw UsageError("cannot create --out directory '" + o.out + "': " + ec.message());
  Json config = eval_json(o, setup);
  double c_obs = -1.0;
  if (fs::exists(dir / "eval.json")) {
    Json old;
    try {
      old = Json::parse(read_text(dir / "eval.json"));
    } catch (const Json::exception& e) {
      throw UsageError("'" + (dir / "eval.json").string() + "' is not valid JSON: " + e.what());
    }
    Json old_cfg = with_selection_defaults(old);
    old_cfg.erase("c_obs");
    old_cfg.erase(kCObsIncidenceKey);
    if (old_cfg != config)
      throw UsageError("--out '" + o.out + "' holds runs of a different configuration (" + old_cfg.dump() +
                       "); use another --out");
    if (c_obs_current(old)) c_obs = old["c_obs"].get<double>();  // else computed again below (an older rule)
  }
  RunMap runs;
  read_runs(dir / "runs.jsonl", runs, log);

  // The (method, run) pairs of this shard that are not finished yet.
  std::vector<std::pair<Method, int>> todo;
  std::size_t index = 0, skipped = 0;
  for (const Method& m : o.methods)
    for (int r = 0; r < o.runs; ++r, ++index) {
      if (static_cast<int>(index % static_cast<std::size_t>(o.shard_n)) != o.shard_k - 1) continue;
      if (runs.count({method_rank(format_method(m)), r})) {
        ++skipped;
        continue;
      }
      todo.emplace_back(m, r);
    }
  if (skipped) log << "nbs_eval: " << skipped << " finished runs found in " << (dir / "runs.jsonl").string() << ", skipped\n";

  // c_obs is computed when missing or of an older rule, also when no run is left to do: finished runs are then
  // restamped with it (their records carry c_obs).
  if (!todo.empty() || c_obs < 0.0) {
    const embree::SimulatedScanner scanner(mesh);
    const GroundTruth truth = eval_ground_truth(mesh, setup.params.completeness_radius_m);
    if (c_obs < 0.0) {
      c_obs = compute_c_obs(scanner, truth, sensor, o.threads, log);
      if (const std::size_t n = restamp_runs(runs, c_obs))
        log << "nbs_eval: c_obs of " << n << " finished runs replaced\n";
    }
    stamp_c_obs(config, c_obs);
    write_text(dir / "eval.json", config.dump(2) + "\n");
    if (todo.empty()) {
      write_outputs(dir, runs, o.scans);
      out << "nbs_eval: " << runs.size() << " runs in " << (dir / "runs.jsonl").string() << " (c_obs recomputed)\n";
      return 0;
    }

    RuntimeModels models = setup.models;
    if (o.pose.registration) models.registration = *o.pose.registration;
    const RunContext ctx{scanner, truth, setup.params, sensor, unknown_area_of(mesh, o.size_m), o.scans, c_obs,
                         setup.planner, models, o.pose, robot};
    std::ofstream lines(dir / "runs.jsonl", std::ios::app);
    if (!lines) throw std::runtime_error("cannot append to '" + (dir / "runs.jsonl").string() + "'");
    Progress progress(todo.size(), log);
    std::mutex mu;
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    std::string error;
    const auto worker = [&] {
      for (std::size_t i = next++; i < todo.size() && !failed; i = next++) {
        try {
          const RunRecord rec = run_one(ctx, todo[i].first, todo[i].second, run_seed(o.seed, todo[i].second));
          Json j = to_json(rec);
          const std::lock_guard<std::mutex> lock(mu);
          lines << j.dump() << '\n' << std::flush;
          runs.emplace(std::make_pair(method_rank(rec.method), rec.run), std::move(j));
          progress.finished(rec);
        } catch (const std::exception& e) {
          const std::lock_guard<std::mutex> lock(mu);
          if (!failed.exchange(true))
            error = format_method(todo[i].first) + " run " + std::to_string(todo[i].second) + ": " + e.what();
        }
      }
    };
    const unsigned n = std::min<unsigned>(o.threads, static_cast<unsigned>(todo.size()));
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < n; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    lines.close();
    if (failed) throw std::runtime_error(error);
  } else {
    stamp_c_obs(config, c_obs);
    write_text(dir / "eval.json", config.dump(2) + "\n");
  }
  write_outputs(dir, runs, o.scans);
  out << "nbs_eval: " << runs.size() << " runs in " << (dir / "runs.jsonl").string() << "; summary in "
      << (dir / "summary.md").string() << "\n";
  return 0;
}

inline int merge_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& log) {
  std::string target;
  std::vector<std::string> dirs;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out") {
      if (i + 1 >= args.size()) throw UsageError("merge: --out needs a directory");
      target = args[++i];
    } else if (args[i] == "--help" || args[i] == "-h") {
      out << usage();
      return 0;
    } else {
      dirs.push_back(args[i]);
    }
  }
  if (target.empty()) throw UsageError("merge: --out DIR is required");
  if (dirs.empty()) throw UsageError("merge: give at least one shard directory");
  Json config;
  RunMap runs;
  for (const std::string& d : dirs) {
    const fs::path p(d);
    if (!fs::exists(p / "eval.json")) throw UsageError("merge: '" + d + "' has no eval.json (not an nbs_eval output)");
    Json c;
    try {
      c = with_selection_defaults(Json::parse(read_text(p / "eval.json")));
    } catch (const Json::exception& e) {
      throw UsageError("merge: '" + (p / "eval.json").string() + "' is not valid JSON: " + e.what());
    }
    if (config.is_null()) config = c;
    else if (c != config)
      throw UsageError("merge: '" + d + "' was run with a different configuration than '" + dirs.front() + "'");
    const std::size_t before = runs.size();
    std::size_t lines_before = 0;
    {
      std::ifstream in(p / "runs.jsonl");
      std::string l;
      while (std::getline(in, l)) lines_before += l.empty() ? 0 : 1;
    }
    read_runs(p / "runs.jsonl", runs, log);
    if (runs.size() - before < lines_before)
      log << "nbs_eval: merge: " << lines_before - (runs.size() - before) << " lines of '" << d
          << "' skipped (unreadable or (method, run) already present)\n";
  }
  const fs::path dir(target);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw UsageError("cannot create '" + target + "': " + ec.message());
  write_text(dir / "eval.json", config.dump(2) + "\n");
  write_outputs(dir, runs, config.at("n_abort").get<int>());
  out << "nbs_eval: merged " << runs.size() << " runs into " << (dir / "runs.jsonl").string() << "\n";
  return 0;
}

/// `nbs_eval c-obs [--threads N] DIR...`: recomputes c_obs of finished outputs with the current rule (ceiling.hpp)
/// from what their eval.json names (mesh path relative to the working directory, up, size, sensor, completeness
/// radius), restamps eval.json and every run record, and rewrites the summaries. No run is repeated.
inline int c_obs_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& log) {
  unsigned threads = 0;
  std::vector<std::string> dirs;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--threads") {
      if (i + 1 >= args.size()) throw UsageError("c-obs: --threads needs a count");
      try {
        threads = static_cast<unsigned>(std::stoul(args[++i]));
      } catch (const std::exception&) {
        throw UsageError("c-obs: --threads expects a count, got '" + args[i] + "'");
      }
    } else if (args[i] == "--help" || args[i] == "-h") {
      out << usage();
      return 0;
    } else {
      dirs.push_back(args[i]);
    }
  }
  if (dirs.empty()) throw UsageError("c-obs: give at least one nbs_eval output directory");
  std::map<std::string, double> c_obs_by_setup;
  for (const std::string& d : dirs) {
    const fs::path dir(d);
    if (!fs::exists(dir / "eval.json")) throw UsageError("c-obs: '" + d + "' has no eval.json (not an nbs_eval output)");
    Json config;
    try {
      config = Json::parse(read_text(dir / "eval.json"));
    } catch (const Json::exception& e) {
      throw UsageError("c-obs: '" + (dir / "eval.json").string() + "' is not valid JSON: " + e.what());
    }
    const Json& setup = config.at("setup");
    // Outputs of one mesh, placement, sensor and radius share their c_obs: computed once per invocation.
    const std::string key = Json::array({config.at("mesh"), config.at("up"), config.at("size_m"), setup.at("sensor"),
                                          setup.at("completeness_radius_m")})
                                .dump();
    const double before = config.value("c_obs", -1.0);
    auto cached = c_obs_by_setup.find(key);
    if (cached == c_obs_by_setup.end()) {
      const IndexedMesh mesh = eval_mesh(config);
      const LaserStripeProfiler sensor = sensor_preset(setup.at("sensor").get<std::string>());
      const embree::SimulatedScanner scanner(mesh);
      const GroundTruth truth = eval_ground_truth(mesh, setup.at("completeness_radius_m").get<double>());
      cached = c_obs_by_setup.emplace(key, compute_c_obs(scanner, truth, sensor, threads, log)).first;
    }
    const double c_obs = cached->second;
    RunMap runs;
    read_runs(dir / "runs.jsonl", runs, log);
    restamp_runs(runs, c_obs);
    stamp_c_obs(config, c_obs);
    write_text(dir / "eval.json", config.dump(2) + "\n");
    write_outputs(dir, runs, config.at("n_abort").get<int>());
    out << "nbs_eval: " << d << ": c_obs " << before << " -> " << c_obs << " (" << runs.size() << " runs)\n";
  }
  return 0;
}

}  // namespace detail

/// The nbs_eval program. Returns 0 on success, 2 on a usage or input error (printed with the usage on `log`),
/// 1 on a failure during the runs.
inline int main(int argc, const char* const* argv, std::ostream& out = std::cout, std::ostream& log = std::cerr) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (!args.empty() && args.front() == "merge")
      return detail::merge_command(std::vector<std::string>(args.begin() + 1, args.end()), out, log);
    if (!args.empty() && args.front() == "c-obs")
      return detail::c_obs_command(std::vector<std::string>(args.begin() + 1, args.end()), out, log);
    return detail::run_command(args, out, log);
  } catch (const UsageError& e) {
    log << "nbs_eval: error: " << e.what() << "\n" << usage();
    return 2;
  } catch (const std::exception& e) {
    log << "nbs_eval: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace nbs::eval
