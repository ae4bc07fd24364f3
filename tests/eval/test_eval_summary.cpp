// SPDX-License-Identifier: BSD-3-Clause
// nbs_eval (issue 6): statistics against hand-computed values (type-7 quantiles, Eq. 4.41 notch, means), run
// outcome and summary, set-up file and CLI errors (before any work), --setup / --config / --sensor / --method, and
// shards merged == the unsharded run.

#include "nbs_catch.hpp"

#include "eval/main.hpp"  // first: includes the planner headers

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using nbs::eval::Json;

namespace {

std::vector<double> v(std::initializer_list<double> x) { return x; }

/// A fresh, empty temporary directory removed at scope exit.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name) : path(fs::temp_directory_path() / ("nbs_eval_test_" + name)) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

int run_cli(const std::vector<std::string>& args, std::string& log) {
  std::vector<const char*> argv{"nbs_eval"};
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  const int rc = nbs::eval::main(static_cast<int>(argv.size()), argv.data(), out, err);
  log = out.str() + err.str();
  return rc;
}

/// Checks that nbs_eval `args` exits 2 with `needle` in its output, before writing `out`.
void expect_rejected(const std::vector<std::string>& args, const std::string& needle, const fs::path& out) {
  std::string log;
  const int rc = run_cli(args, log);
  INFO(log);
  CHECK(rc == 2);
  CHECK_THAT(log, nbs_test::Contains(needle));
  CHECK(!fs::exists(out));  // nothing written
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<Json> lines_of(const fs::path& p) {
  std::vector<Json> out;
  std::istringstream in(read(p));
  std::string l;
  while (std::getline(in, l))
    if (!l.empty()) out.push_back(Json::parse(l));
  return out;
}

/// Removes the wall-clock fields (the only ones that differ between identical runs).
Json without_timing(Json j) {
  if (j.contains("scans")) j["scans"].erase("t_nbs_s");
  for (auto& [k, row] : j.items())
    if (row.is_object()) row.erase("mean_t_nbs_s");
  return j;
}

nbs::eval::RunRecord hand_record() {
  nbs::eval::RunRecord r;
  r.method = "C_H";
  r.run = 3;
  r.seed = 42;
  r.initial_index = 7;
  r.n_abort = 3;
  r.n_s = 2;
  r.stop = "max_scans";
  r.c_obs = 0.95;
  const double ca[] = {0.5, 0.8, 0.9}, ls[] = {0.1, 0.3, 0.6}, t[] = {0.0, 1.0, 3.0};
  for (int i = 0; i < 3; ++i) {
    nbs::eval::ScanRow row;
    row.c_a = ca[i];
    row.c_b = ca[i] - 0.1;
    row.c_m = 0.4 * (i + 1);
    row.d_m = 0.1 * (i + 1);
    row.e_bar_m = 0.001;
    row.l_s_m = ls[i];
    row.t_nbs_s = t[i];
    row.candidates = static_cast<std::size_t>(10 * i);
    row.mode = i == 0 ? "init" : "BS";
    r.scans.push_back(row);
  }
  return r;
}

}  // namespace

TEST_CASE("quantiles: type 7 (linear between order statistics at (n-1)p)", "[eval]") {
  const auto a = v({4, 1, 3, 2});  // sorted 1 2 3 4
  CHECK(nbs::eval::quantile(a, 0.25) == Approx(1.75));  // h = 0.75
  CHECK(nbs::eval::median(a) == Approx(2.5));           // h = 1.5
  CHECK(nbs::eval::quantile(a, 0.75) == Approx(3.25));  // h = 2.25
  CHECK(nbs::eval::quantile(a, 0.0) == 1.0);
  CHECK(nbs::eval::quantile(a, 1.0) == 4.0);
  CHECK(nbs::eval::iqr(a) == Approx(1.5));
  const auto b = v({7, 1, 3, 9, 5});  // sorted 1 3 5 7 9: Q1 = 3, Q3 = 7 exactly
  CHECK(nbs::eval::median(b) == 5.0);
  CHECK(nbs::eval::iqr(b) == 4.0);
  CHECK(nbs::eval::quantile(v({10, 20}), 0.3) == Approx(13.0));
  CHECK(nbs::eval::median(v({6})) == 6.0);
  CHECK_THROWS_AS(nbs::eval::quantile(std::vector<double>{}, 0.5), std::invalid_argument);
  CHECK_THROWS_AS(nbs::eval::quantile(a, 1.5), std::invalid_argument);
}

TEST_CASE("notch of Eq. 4.41 and mean", "[eval]") {
  CHECK(nbs::eval::notch(v({4, 1, 3, 2})) == Approx(1.57 * 1.5 / 2.0));        // 1.1775
  CHECK(nbs::eval::notch(v({7, 1, 3, 9, 5})) == Approx(1.57 * 4.0 / std::sqrt(5.0)));
  CHECK(nbs::eval::notch(v({10, 10, 10})) == 0.0);
  // 100 runs (the thesis's s = 100): 25 × 9, 50 × 10, 25 × 12. Q1: h = 24.75 -> 9 + 0.75·(10 − 9) = 9.75;
  // Q3: h = 74.25 -> 10 + 0.25·(12 − 10) = 10.5; IQR 0.75, notch 1.57·0.75/10 = 0.11775.
  std::vector<double> hundred;
  for (int i = 0; i < 100; ++i) hundred.push_back(i < 25 ? 9 : i < 75 ? 10 : 12);
  CHECK(nbs::eval::quantile(hundred, 0.25) == Approx(9.75));
  CHECK(nbs::eval::quantile(hundred, 0.75) == Approx(10.5));
  CHECK(nbs::eval::notch(hundred) == Approx(0.11775));
  // x_i = i, i = 0..99: Q1 = 24.75, Q3 = 74.25, IQR 49.5, notch 7.7715.
  std::vector<double> ramp;
  for (int i = 0; i < 100; ++i) ramp.push_back(i);
  CHECK(nbs::eval::iqr(ramp) == Approx(49.5));
  CHECK(nbs::eval::notch(ramp) == Approx(7.7715));
  CHECK(nbs::eval::mean(v({1, 2, 3, 4})) == 2.5);
  CHECK_THROWS_AS(nbs::eval::mean(std::vector<double>{}), std::invalid_argument);
}

TEST_CASE("run outcome and method summary", "[eval]") {
  const nbs::eval::RunRecord r = hand_record();
  const nbs::eval::RunOutcome o = nbs::eval::outcome(r);
  CHECK(o.n_s == 2);
  CHECK(o.ca_at_stop == 0.8);     // c_a after scan 2
  CHECK(o.ca_at_end == 0.9);      // c_a after the last scan
  CHECK(o.path_length_m == 0.6);  // l_s over all scans
  CHECK(o.mean_t_nbs_s == Approx(2.0));  // planning steps 2 and 3: (1 + 3) / 2
  CHECK(o.c_obs == 0.95);

  nbs::eval::RunRecord r2 = r;
  r2.run = 4;
  r2.n_s = 3;
  r2.scans[2].c_a = 0.7;
  r2.scans[2].l_s_m = 1.0;
  const auto rows = nbs::eval::summarize_records({r2, r});
  REQUIRE(rows.size() == 1);
  const nbs::eval::MethodSummary& s = rows[0];
  CHECK(s.method == "C_H");
  CHECK(s.runs == 2);
  CHECK(s.median_scans == Approx(2.5));
  CHECK(s.notch == Approx(1.57 * 0.5 / std::sqrt(2.0)));  // IQR of {2, 3} = 2.75 − 2.25
  CHECK(s.mean_ca_at_stop == Approx((0.8 + 0.7) / 2));   // r2 stops at scan 3 (c_a 0.7)
  CHECK(s.mean_ca_at_30 == Approx((0.9 + 0.7) / 2));
  CHECK(s.mean_path_length_m == Approx((0.6 + 1.0) / 2));
  CHECK(s.mean_t_nbs_s == Approx(2.0));
  CHECK(s.mean_c_obs == Approx(0.95));

  const Json js = nbs::eval::summary_json(rows);
  for (const char* key : {"runs", "median_scans", "notch", "mean_ca_at_stop", "mean_ca_at_30", "mean_path_length_m",
                          "mean_t_nbs_s", "mean_c_obs"})
    CHECK(js.at("C_H").contains(key));
  const std::string md = nbs::eval::summary_markdown(rows, 3);
  // Never reaches 0.95 · c_obs = 0.9025: k95 = k99 = n_abort + 1 = 4; l_s to k99 = all of it; n_s − k99 = −2, −1.
  CHECK(md.find("| C_H | IG/Quality | BS/HR | 2 | 2.5 | ±0.56 | 75.00 | 80.00 | 0.80 | 2.00 | 95.00 | 4.0 | 4.0 | "
                "0.80 | -1.5 |") != std::string::npos);
}

TEST_CASE("truth-based summary columns from a hand-made runs.jsonl", "[eval]") {
  // Two RSE_H runs, n_abort 5, c_obs 0.9: 0.95 c_obs = 0.855, 0.99 c_obs = 0.891.
  // Run 0: c_a .5 .86 .89 .895 .9 -> k95 = 2, k99 = 4 (0.89 < 0.891), l_s after scan 4 = 0.7, n_s 3 -> −1.
  // Run 1: c_a .6 .7 .8 .85 .88 -> k95 = 5, k99 never = 6, l_s of all 5 scans = 1.0, n_s 5 -> −1.
  const char* lines[] = {
      R"({"method":"RSE_H","run":0,"seed":1,"initial_index":2,"n_abort":5,"n_s":3,"stop":"max_scans","c_obs":0.9,)"
      R"("scans":{"c_m":[0,0,0,0,0],"d_m":[0,0,0,0,0],"c_a":[0.5,0.86,0.89,0.895,0.9],"c_b":[0,0,0,0,0],)"
      R"("e_bar_m":[0,0,0,0,0],"l_s_m":[0.1,0.3,0.5,0.7,0.9],"t_nbs_s":[0,0,0,0,0],"candidates":[0,1,1,1,1],)"
      R"("mode":["init","BS","BS","HR","HR"]}})",
      R"({"method":"RSE_H","run":1,"seed":2,"initial_index":5,"n_abort":5,"n_s":5,"stop":"max_scans","c_obs":0.9,)"
      R"("scans":{"c_m":[0,0,0,0,0],"d_m":[0,0,0,0,0],"c_a":[0.6,0.7,0.8,0.85,0.88],"c_b":[0,0,0,0,0],)"
      R"("e_bar_m":[0,0,0,0,0],"l_s_m":[0.2,0.4,0.6,0.8,1.0],"t_nbs_s":[0,0,0,0,0],"candidates":[0,1,1,1,1],)"
      R"("mode":["init","BS","BS","BS","BS"]}})"};
  std::vector<nbs::eval::RunRecord> records;
  for (const char* l : lines) records.push_back(nbs::eval::record_from_json(Json::parse(l)));
  const nbs::eval::RunOutcome o0 = nbs::eval::outcome(records[0]), o1 = nbs::eval::outcome(records[1]);
  CHECK(o0.k95 == 2);
  CHECK(o0.k99 == 4);
  CHECK(o0.path_to_k99_m == 0.7);
  CHECK(o0.stop_minus_k99 == -1);
  CHECK(o1.k95 == 5);
  CHECK(o1.k99 == 6);
  CHECK(o1.path_to_k99_m == 1.0);
  CHECK(o1.stop_minus_k99 == -1);
  const auto rows = nbs::eval::summarize_records(records);
  REQUIRE(rows.size() == 1);
  CHECK(rows[0].median_k95 == Approx(3.5));
  CHECK(rows[0].median_k99 == Approx(5.0));
  CHECK(rows[0].mean_path_to_k99_m == Approx(0.85));
  CHECK(rows[0].median_stop_minus_k99 == Approx(-1.0));
  const Json js = nbs::eval::summary_json(rows);
  CHECK(js.at("RSE_H").at("median_k95").get<double>() == Approx(3.5));
  CHECK(js.at("RSE_H").at("median_k99").get<double>() == Approx(5.0));
  CHECK(js.at("RSE_H").at("mean_path_to_k99_m").get<double>() == Approx(0.85));
  CHECK(js.at("RSE_H").at("stop_minus_k99").get<double>() == Approx(-1.0));
  CHECK(nbs::eval::summary_markdown(rows, 5).find("| 3.5 | 5.0 | 0.85 | -1.0 |") != std::string::npos);
  CHECK(nbs::eval::summary_csv(rows).find(",3.5,5,0.85,-1\n") != std::string::npos);
}

TEST_CASE("run record JSON round trip", "[eval]") {
  const nbs::eval::RunRecord r = hand_record();
  const Json j = nbs::eval::to_json(r);
  const nbs::eval::RunRecord back = nbs::eval::record_from_json(Json::parse(j.dump()));
  CHECK(nbs::eval::to_json(back) == j);
  CHECK(back.scans[1].candidates == 10);
  CHECK(back.scans[0].mode == "init");
  Json broken = j;
  broken["scans"]["c_b"].erase(0);
  CHECK_THROWS(nbs::eval::record_from_json(broken));
  // The parts of ĉ_m (A_filled, A_empty by edge distance) round-trip; a file without them reads them as 0; a wrong
  // length is refused.
  nbs::eval::RunRecord parts = r;
  parts.scans[1].a_filled_m2 = 0.03;
  parts.scans[1].a_unseen_m2 = 0.02;
  parts.scans[1].a_unseen_5mm_m2 = 0.004;
  parts.scans[1].a_unseen_10mm_m2 = 0.001;
  const nbs::eval::RunRecord parts_back = nbs::eval::record_from_json(Json::parse(nbs::eval::to_json(parts).dump()));
  CHECK(parts_back.scans[1].a_filled_m2 == 0.03);
  CHECK(parts_back.scans[1].a_unseen_m2 == 0.02);
  CHECK(parts_back.scans[1].a_unseen_5mm_m2 == 0.004);
  CHECK(parts_back.scans[1].a_unseen_10mm_m2 == 0.001);
  Json old_file = nbs::eval::to_json(parts);
  for (const char* key : {"a_filled_m2", "a_unseen_m2", "a_unseen_5mm_m2", "a_unseen_10mm_m2"})
    old_file["scans"].erase(key);
  CHECK(nbs::eval::record_from_json(old_file).scans[1].a_unseen_m2 == 0.0);
  Json short_parts = nbs::eval::to_json(parts);
  short_parts["scans"]["a_unseen_5mm_m2"].erase(0);
  CHECK_THROWS(nbs::eval::record_from_json(short_parts));
  Json some_parts = nbs::eval::to_json(parts);
  some_parts["scans"].erase("a_unseen_10mm_m2");
  CHECK_THROWS(nbs::eval::record_from_json(some_parts));
}

TEST_CASE("set-up file: mesh, coverage_estimate and keep_exploring choose the planner setting", "[eval]") {
  const nbs::eval::Setup d = nbs::eval::parse_setup("{}", "cfg");  // the planner's defaults
  CHECK(d.models.noise_robust_mesh);
  CHECK(d.models.coverage_estimate == nbs::CoverageEstimate::unknown_open);
  CHECK(d.planner.keep_exploring);
  const nbs::eval::Setup r = nbs::eval::parse_setup(
      R"({"mesh": "thesis", "coverage_estimate": "thesis", "keep_exploring": false})", "cfg");
  CHECK_FALSE(r.models.noise_robust_mesh);
  CHECK(r.models.coverage_estimate == nbs::CoverageEstimate::thesis);
  CHECK_FALSE(r.planner.keep_exploring);
  // The written configuration names them, so a rerun with another choice in the same --out is refused, and it
  // reads back to the same set-up.
  CHECK(nbs::eval::setup_json(r)["mesh"] == "thesis");
  CHECK(nbs::eval::setup_json(r)["coverage_estimate"] == "thesis");
  CHECK(nbs::eval::setup_json(r)["keep_exploring"] == false);
  CHECK(nbs::eval::setup_json(d)["mesh"] == "noise_robust");
  CHECK(nbs::eval::setup_json(d)["coverage_estimate"] == "unknown_open");
  CHECK(nbs::eval::parse_setup(R"({"coverage_estimate": "unseen_open"})", "cfg").models.coverage_estimate ==
        nbs::CoverageEstimate::unseen_open);
  CHECK(nbs::eval::parse_setup(R"({"coverage_estimate": "unseen_loops"})", "cfg").models.coverage_estimate ==
        nbs::CoverageEstimate::unseen_loops);
  CHECK(nbs::eval::parse_setup(R"({"coverage_estimate": "observable_open"})", "cfg").models.coverage_estimate ==
        nbs::CoverageEstimate::observable_open);
  CHECK(nbs::eval::setup_json(d)["keep_exploring"] == true);
  const nbs::eval::Setup back = nbs::eval::parse_setup(nbs::eval::setup_json(r).dump(), "cfg");
  CHECK_FALSE(back.models.noise_robust_mesh);
  CHECK(back.models.coverage_estimate == nbs::CoverageEstimate::thesis);
  CHECK_FALSE(back.planner.keep_exploring);
  // SGU's options (the selection options of the runtime facade): defaults, values, round trip, bad values.
  CHECK(d.models.selection == nbs::SelectionOptions{});
  const nbs::eval::Setup u =
      nbs::eval::parse_setup(R"({"unseen_weight": 4, "unseen_min_edge_distance_m": 0.01})", "cfg");
  CHECK(u.models.selection.unseen_weight == 4.0);
  CHECK(u.models.selection.unseen_min_edge_distance_m == 0.01);
  CHECK(nbs::eval::parse_setup(nbs::eval::setup_json(u).dump(), "cfg").models == u.models);
  for (const char* bad : {R"({"unseen_weight": -1})", R"({"unseen_weight": "a"})", R"({"unseen_min_edge_distance_m": -0.1})"})
    CHECK_THROWS_WITH(nbs::eval::parse_setup(bad, "cfg"), nbs_test::Contains("must be a finite number >= 0"));
  // An eval.json written before these keys existed compares equal to today's with the defaults (resume, merge).
  nbs::eval::Json older = {{"mesh", "m.obj"}, {"setup", nbs::eval::setup_json(d)}};
  older["setup"].erase("unseen_weight");
  older["setup"].erase("unseen_min_edge_distance_m");
  const nbs::eval::Json today = {{"mesh", "m.obj"}, {"setup", nbs::eval::setup_json(d)}};
  CHECK(older != today);
  CHECK(nbs::eval::with_selection_defaults(older) == today);
  nbs::eval::Json other = {{"mesh", "m.obj"}, {"setup", nbs::eval::setup_json(u)}};
  CHECK(nbs::eval::with_selection_defaults(other) == other);  // present keys stay as they are
  // "stop_rule": the default is the settled rule; values, round trip, a bad value; an eval.json without the key was
  // judged by the thesis's rule and reads so.
  CHECK(d.models.stop_rule == nbs::StopRule::settled);
  CHECK(nbs::eval::setup_json(d)["stop_rule"] == "settled");
  for (const nbs::StopRule rule : {nbs::StopRule::settled, nbs::StopRule::thesis, nbs::StopRule::max_scans}) {
    const std::string text = std::string(R"({"stop_rule": ")") + std::string(nbs::format_stop_rule(rule)) + "\"}";
    const nbs::eval::Setup sr = nbs::eval::parse_setup(text, "cfg");
    CHECK(sr.models.stop_rule == rule);
    CHECK(nbs::eval::parse_setup(nbs::eval::setup_json(sr).dump(), "cfg").models == sr.models);
  }
  CHECK_THROWS_WITH(nbs::eval::parse_setup(R"({"stop_rule": "never"})", "cfg"),
                    nbs_test::Contains("'stop_rule' must be one of settled | thesis | max_scans, got 'never'"));
  nbs::eval::Json before_rule = today;
  before_rule["setup"].erase("stop_rule");
  CHECK(nbs::eval::with_selection_defaults(before_rule)["setup"]["stop_rule"] == "thesis");
}

TEST_CASE("CLI: n_s is judged by the set-up's stop rule, replayed on the recorded c_m and d_m", "[eval]") {
  TempDir tmp("stop_rule");
  const std::string bunny = NBS_DATA_DIR "/meshes/stanford-bunny.obj";
  std::size_t judged = 0;
  std::vector<int> n_s[2];
  for (const char* rule : {"settled", "thesis"}) {
    const fs::path setup = tmp.path / (std::string(rule) + ".json"), out = tmp.path / rule;
    std::ofstream(setup) << R"({"stop_rule": ")" << rule << R"("})";
    std::string log;
    REQUIRE(run_cli({"--mesh", bunny, "--up", "y", "--size", "0.1", "--methods", "SGU_H", "--runs", "2", "--scans",
                     "8", "--seed", "3", "--threads", "2", "--setup", setup.string(), "--out", out.string()},
                    log) == 0);
    INFO(rule << ": " << log);
    for (const Json& r : lines_of(out / "runs.jsonl")) {
      // The oracle: the rule's documented thresholds applied to every prefix of the recorded series (all scans of
      // these runs changed the models: the history is the c_m series itself).
      const std::vector<double> c = r["scans"]["c_m"], d = r["scans"]["d_m"];
      REQUIRE(c.size() == 8);
      int want = 8;
      for (std::size_t k = 1; k <= c.size() && want == 8; ++k) {
        bool stop = false;
        if (std::string(rule) == "thesis") {
          stop = c[k - 1] >= 0.8 && d[k - 1] >= 0.2;
        } else if (d[k - 1] >= 0.2) {
          // Held (≥ 0.9 twice), settled (≥ 0.75, the last 3 within 0.03) or stalled (≥ 0.5, the last 5 within 0.03).
          const auto still = [&](double level, std::size_t w) {
            if (k < w || c[k - 1] < level) return false;
            const auto [lo, hi] = std::minmax_element(c.begin() + static_cast<std::ptrdiff_t>(k - w),
                                                      c.begin() + static_cast<std::ptrdiff_t>(k));
            return *hi - *lo < 0.03;
          };
          const bool held = k >= 2 && c[k - 1] >= 0.9 && c[k - 2] >= 0.9;
          stop = held || still(0.75, 3) || still(0.5, 5);
        }
        if (stop) want = static_cast<int>(k);
      }
      CHECK(r["n_s"].get<int>() == want);
      judged += want < 8 ? 1 : 0;
      n_s[std::string(rule) == "thesis" ? 1 : 0].push_back(want);
    }
  }
  CHECK(judged > 0);       // some run stops before n_abort under some rule: the replay is exercised
  CHECK(n_s[0] != n_s[1]);  // and the two rules judge these runs differently: the key is not ignored
}

TEST_CASE("set-up file: fields by name, errors name the key", "[eval]") {
  const nbs::eval::Setup s =
      nbs::eval::parse_setup(R"({"voxel_size_m": 0.004, "max_scans": 12, "sensor": "scancontrol_2700_100"})", "cfg");
  CHECK(s.params.voxel_size_m == 0.004);
  CHECK(s.params.max_scans == 12);
  CHECK(s.params.target_coverage == nbs::Parameters{}.target_coverage);
  CHECK(s.sensor == "scancontrol_2700_100");
  const auto error_of = [](const std::string& text) -> std::string {
    try {
      (void)nbs::eval::parse_setup(text, "cfg");
    } catch (const nbs::eval::UsageError& e) {
      return e.what();
    }
    return "";
  };
  CHECK_THAT(error_of(R"({"voxel_size": 0.004})"), nbs_test::Contains("unknown set-up key 'voxel_size'"));
  CHECK_THAT(error_of(R"({"voxel_size": 0.004})"), nbs_test::Contains("voxel_size_m"));  // lists the valid keys
  CHECK_THAT(error_of(R"({"scan_overlap": 1.5})"), nbs_test::Contains("scan_overlap"));
  CHECK_THAT(error_of(R"({"scan_overlap": 1.5})"), nbs_test::Contains("out-of-range"));
  CHECK_THAT(error_of(R"({"max_scans": 0})"), nbs_test::Contains("max_scans"));
  CHECK_THAT(error_of(R"({"max_scans": 2.5})"), nbs_test::Contains("'max_scans' must be an integer"));
  CHECK_THAT(error_of(R"({"voxel_size_m": "small"})"), nbs_test::Contains("'voxel_size_m' must be a number"));
  CHECK_THAT(error_of(R"({"sensor": "kinect"})"), nbs_test::Contains("unknown sensor preset 'kinect'"));
  CHECK_THAT(error_of(R"({"sensor": "asus_xtion_pro"})"), nbs_test::Contains("area sensor"));
  CHECK_THAT(error_of(R"({"mesh": "smooth"})"), nbs_test::Contains("'mesh' must be one of thesis | noise_robust"));
  CHECK_THAT(error_of(R"({"coverage_estimate": 1})"), nbs_test::Contains("'coverage_estimate' must be a string"));
  CHECK_THAT(error_of(R"({"keep_exploring": "no"})"), nbs_test::Contains("'keep_exploring' must be true or false"));
  CHECK_THAT(error_of(R"([1, 2])"), nbs_test::Contains("JSON object"));
  CHECK_THAT(error_of(R"({"voxel_size_m": )"), nbs_test::Contains("not valid JSON"));
}

TEST_CASE("CLI: bad input is reported before any work starts", "[eval]") {
  TempDir tmp("badinput");
  const std::string bunny = NBS_DATA_DIR "/meshes/stanford-bunny.obj";
  const std::string out = (tmp.path / "out").string();
  std::string log;
  const auto rejected = [&](const std::vector<std::string>& args, const std::string& needle) {
    expect_rejected(args, needle, out);
  };
  rejected({"--mesh", bunny, "--out", out, "--methods", "C_H,X_Y"}, "unknown planning method 'X_Y'");
  rejected({"--mesh", bunny, "--out", out, "--methods", "X_Y"}, "valid codes: R_S");
  rejected({"--mesh", bunny, "--out", out, "--runs", "0"}, "--runs: expects an integer in [1");
  rejected({"--mesh", bunny, "--out", out, "--shard", "3/2"}, "--shard K/N needs 1 <= K <= N");
  rejected({"--mesh", bunny, "--out", out, "--shard", "0/2"}, "--shard K/N needs 1 <= K <= N");
  rejected({"--mesh", bunny, "--out", out, "--shard", "12"}, "--shard must be K/N");
  rejected({"--mesh", bunny, "--out", out, "--up", "w"}, "--up: expects x, y or z, got 'w'");
  rejected({"--mesh", bunny, "--out", out, "--frobnicate", "1"}, "--frobnicate");
  rejected({"--out", out}, "--mesh is required");
  const fs::path cfg = tmp.path / "bad.json";
  std::ofstream(cfg) << R"({"target_coverage": 2.0})";
  rejected({"--mesh", bunny, "--out", out, "--setup", cfg.string()}, "target_coverage");
  const fs::path text = tmp.path / "notamesh.obj";
  std::ofstream(text) << "this is not a mesh\n";
  rejected({"--mesh", text.string(), "--out", out}, "error: mesh '" + text.string() + "': ");
  rejected({"--mesh", (tmp.path / "missing.ply").string(), "--out", out}, "missing.ply");
  CHECK(run_cli({"--help"}, log) == 0);
  CHECK_THAT(log, nbs_test::Contains("--shard K/N"));
  CHECK_THAT(log, nbs_test::Contains("VG_H"));
  CHECK_THAT(log, nbs_test::Contains("--setup FILE"));
  CHECK_THAT(log, nbs_test::Contains("overrides the set-up's"));
}

TEST_CASE("CLI: --setup is the planner set-up, --config the shared options file, --sensor and --method", "[eval]") {
  TempDir tmp("options");
  const std::string bunny = NBS_DATA_DIR "/meshes/stanford-bunny.obj";
  const std::string out = (tmp.path / "out").string();
  const auto parse = [](const std::vector<std::string>& args) {
    bool help = false;
    return nbs::eval::parse_options(args, help);
  };
  // --setup reads the set-up file that --config read before.
  const std::string text = R"({"voxel_size_m": 0.004, "max_scans": 12, "sensor": "scancontrol_2700_100",
                               "coverage_estimate": "thesis", "keep_exploring": false})";
  const fs::path setup = tmp.path / "setup.json";
  std::ofstream(setup) << text;
  const nbs::eval::Options o = parse({"--mesh", bunny, "--out", out, "--setup", setup.string()});
  CHECK(o.setup == setup.string());
  CHECK(nbs::eval::setup_json(nbs::eval::resolve_setup(o)) ==
        nbs::eval::setup_json(nbs::eval::parse_setup(text, "cfg")));
  const nbs::eval::Setup thesis = nbs::eval::resolve_setup(
      parse({"--mesh", bunny, "--out", out, "--setup", NBS_DATA_DIR "/../docs/eval/configs/thesis.json"}));
  CHECK_FALSE(thesis.models.noise_robust_mesh);
  CHECK(thesis.models.coverage_estimate == nbs::CoverageEstimate::thesis);
  // --sensor overrides the set-up's "sensor".
  CHECK(nbs::eval::resolve_setup(o).sensor == "scancontrol_2700_100");
  CHECK(nbs::eval::resolve_setup(parse({"--mesh", bunny, "--out", out, "--setup", setup.string(), "--sensor",
                                        "dlr_lsp"}))
            .sensor == "dlr_lsp");
  CHECK(nbs::eval::resolve_setup(parse({"--mesh", bunny, "--out", out, "--sensor", "scancontrol_2700_100"})).sensor ==
        "scancontrol_2700_100");

  // --config: the long option names; the command line wins.
  const fs::path cfg = tmp.path / "options.json";
  std::ofstream(cfg) << R"({"runs": 3, "methods": "C_H,C_S", "seed": 9, "setup": ")" + setup.string() + R"("})";
  const nbs::eval::Options c = parse({"--mesh", bunny, "--out", out, "--config", cfg.string(), "--runs", "5"});
  CHECK(c.runs == 5);
  CHECK(c.seed == 9);
  CHECK(c.setup == setup.string());
  REQUIRE(c.methods.size() == 2);
  CHECK(nbs::format_method(c.methods[1]) == "C_S");
  // --method: one method; on the command line it wins over the file's "methods".
  const nbs::eval::Options m = parse({"--mesh", bunny, "--out", out, "--config", cfg.string(), "--method", "R_S"});
  REQUIRE(m.methods.size() == 1);
  CHECK(nbs::format_method(m.methods[0]) == "R_S");
  const nbs::eval::Options q = parse({"--mesh", bunny, "--out", out, "--method", "Q_B"});
  REQUIRE(q.methods.size() == 1);
  CHECK(nbs::format_method(q.methods[0]) == "Q_B");

  const auto rejected = [&](const std::vector<std::string>& args, const std::string& needle) {
    expect_rejected(args, needle, out);
  };
  // A planner set-up given to --config is an error naming the key.
  const fs::path planner = tmp.path / "planner.json";
  std::ofstream(planner) << R"({"coverage_estimate": "thesis"})";
  rejected({"--mesh", bunny, "--out", out, "--config", planner.string()}, "unknown key 'coverage_estimate'");
  rejected({"--mesh", bunny, "--out", out, "--config", planner.string()}, "--setup FILE");
  rejected({"--mesh", bunny, "--out", out, "--sensor", "kinect"}, "--sensor: unknown sensor preset 'kinect'");
  rejected({"--mesh", bunny, "--out", out, "--sensor", "kinect"}, "valid names: dlr_lsp, scancontrol_2700_100");
  rejected({"--mesh", bunny, "--out", out, "--sensor", "asus_xtion_pro"}, "area sensor");
  rejected({"--mesh", bunny, "--out", out, "--method", "C_H", "--methods", "C_S"}, "--method and --methods");
  rejected({"--mesh", bunny, "--out", out, "--method", "C_X"}, "--method: unknown planning method 'C_X'");
  const fs::path both = tmp.path / "both.json";
  std::ofstream(both) << R"({"method": "C_H", "methods": "C_S"})";
  rejected({"--mesh", bunny, "--out", out, "--config", both.string()}, "--method and --methods");
  rejected({"--mesh", bunny, "--out", out, "--setup", (tmp.path / "missing.json").string()}, "--setup: cannot read");
}

TEST_CASE("CLI: two shards merged equal the unsharded run; a rerun skips finished runs", "[eval][slow]") {
  TempDir tmp("merge");
  const std::string bunny = NBS_DATA_DIR "/meshes/stanford-bunny.obj";
  const std::vector<std::string> common{"--mesh", bunny, "--up", "y", "--size", "0.05", "--methods", "C_H",
                                        "--runs", "2", "--scans", "2", "--seed", "7"};
  const auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = common;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const fs::path full = tmp.path / "full", s1 = tmp.path / "s1", s2 = tmp.path / "s2", merged = tmp.path / "merged";
  std::string log;
  REQUIRE(run_cli(with({"--threads", "2", "--out", full.string()}), log) == 0);
  INFO(log);
  REQUIRE(run_cli(with({"--threads", "1", "--shard", "1/2", "--out", s1.string()}), log) == 0);
  REQUIRE(run_cli(with({"--threads", "1", "--shard", "2/2", "--out", s2.string()}), log) == 0);
  CHECK(lines_of(s1 / "runs.jsonl").size() == 1);
  CHECK(lines_of(s2 / "runs.jsonl").size() == 1);
  REQUIRE(run_cli({"merge", "--out", merged.string(), s2.string(), s1.string()}, log) == 0);

  const std::vector<Json> a = lines_of(full / "runs.jsonl"), b = lines_of(merged / "runs.jsonl");
  REQUIRE(a.size() == 2);
  REQUIRE(b.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(a[i]["method"] == "C_H");
    CHECK(a[i]["run"] == static_cast<int>(i));  // sorted by (method, run)
    CHECK(a[i]["scans"]["c_a"].size() <= 2);
    CHECK(without_timing(a[i]) == without_timing(b[i]));
  }
  // The same initial scan would be used by every method in run r: it depends on (seed, r) only.
  CHECK(a[0]["seed"].get<std::uint64_t>() == nbs::eval::run_seed(7, 0));
  CHECK(a[1]["seed"].get<std::uint64_t>() == nbs::eval::run_seed(7, 1));
  CHECK(a[0]["initial_index"].get<int>() == nbs::random_initial_scan_index(nbs::eval::run_seed(7, 0)));
  CHECK(read(full / "eval.json") == read(merged / "eval.json"));
  CHECK(without_timing(Json::parse(read(full / "summary.json"))) ==
        without_timing(Json::parse(read(merged / "summary.json"))));
  const Json sj = Json::parse(read(merged / "summary.json"));
  CHECK(sj.at("C_H").at("runs") == 2);
  CHECK(sj.at("C_H").at("mean_c_obs").get<double>() == a[0]["c_obs"].get<double>());

  // Interrupted run: a partial last line. The rerun keeps the finished lines, skips them and drops the fragment.
  { std::ofstream(full / "runs.jsonl", std::ios::app) << R"({"method":"C_H","run":1,"se)"; }
  REQUIRE(run_cli(with({"--threads", "2", "--out", full.string()}), log) == 0);
  CHECK_THAT(log, nbs_test::Contains("2 finished runs found"));
  CHECK_THAT(log, nbs_test::Contains("skipping unreadable line"));
  const std::vector<Json> again = lines_of(full / "runs.jsonl");
  REQUIRE(again.size() == 2);
  CHECK(again[0] == a[0]);
  CHECK(again[1] == a[1]);
  // The same configuration through --config (options) and --setup (planner set-up, here the defaults) resumes it:
  // eval.json holds the parsed set-up, not the file names.
  const fs::path options = tmp.path / "options.json", defaults = tmp.path / "defaults.json";
  std::ofstream(defaults) << "{}";
  std::ofstream(options) << Json{{"mesh", bunny}, {"up", "y"}, {"size", 0.05}, {"method", "C_H"}, {"runs", 2},
                                 {"scans", 2}, {"seed", 7}, {"setup", defaults.string()}}
                                .dump();
  REQUIRE(run_cli({"--config", options.string(), "--out", full.string()}, log) == 0);
  CHECK_THAT(log, nbs_test::Contains("2 finished runs found"));
  CHECK(lines_of(full / "runs.jsonl") == a);
  // A different configuration in the same --out is refused.
  CHECK(run_cli({"--mesh", bunny, "--up", "y", "--size", "0.06", "--methods", "C_H", "--runs", "2", "--scans", "2",
                 "--seed", "7", "--out", full.string()},
                log) == 2);
  CHECK_THAT(log, nbs_test::Contains("different configuration"));

  // c_obs is stamped with the scanner's incidence limit. An output of an older rule (no stamp, another c_obs) is
  // recomputed by a rerun and by `c-obs`, and every record is restamped; the runs themselves are not repeated.
  const Json cfg = Json::parse(read(full / "eval.json"));
  CHECK(cfg.at("c_obs_incidence_rad").get<double>() == nbs::embree::SimulatedScanner::max_incidence_rad);
  const auto make_stale = [&] {
    Json old = cfg;
    old.erase("c_obs_incidence_rad");
    old["c_obs"] = 0.5;
    std::ofstream(full / "eval.json") << old.dump(2);
    std::ofstream lines(full / "runs.jsonl");
    for (Json j : a) {
      j["c_obs"] = 0.5;
      lines << j.dump() << "\n";
    }
  };
  make_stale();
  REQUIRE(run_cli(with({"--threads", "2", "--out", full.string()}), log) == 0);
  CHECK_THAT(log, nbs_test::Contains("c_obs of 2 finished runs replaced"));
  CHECK(Json::parse(read(full / "eval.json")) == cfg);
  CHECK(lines_of(full / "runs.jsonl") == a);
  make_stale();
  REQUIRE(run_cli({"c-obs", "--threads", "2", full.string()}, log) == 0);
  CHECK(Json::parse(read(full / "eval.json")) == cfg);
  CHECK(lines_of(full / "runs.jsonl") == a);
  CHECK(run_cli({"c-obs", (tmp.path / "nowhere").string()}, log) == 2);
  CHECK_THAT(log, nbs_test::Contains("has no eval.json"));
}

TEST_CASE("pose fields: JSON round trip and the run's means", "[eval][pose_error]") {
  nbs::eval::RunRecord r = hand_record();
  CHECK_FALSE(nbs::eval::to_json(r).contains("double_surface_share"));  // without the options: as before
  r.pose = true;
  r.double_surface_share = 0.25;
  r.double_surface_share_rel = 0.125;
  const double t[] = {1.0, 0.5, 0.0}, a[] = {0.1, 0.1, 0.4};
  for (int i = 0; i < 3; ++i) {
    r.scans[i].pose_t_mm = t[i];
    r.scans[i].pose_r_deg = a[i];
    r.scans[i].pose_rel_t_mm = 0.5 * t[i];
    r.scans[i].pose_rel_r_deg = 0.5 * a[i];
    r.scans[i].e_bar_rel_m = 1e-3 * (i + 1);
    r.scans[i].registration = i == 0 ? "refused_empty_model" : "applied";
    r.scans[i].icp_s = 0.01 * i;
  }
  const Json j = nbs::eval::to_json(r);
  CHECK(j.at("scans").at("registration")[1] == "applied");
  const nbs::eval::RunRecord back = nbs::eval::record_from_json(Json::parse(j.dump()));
  CHECK(back.pose);
  CHECK(back.double_surface_share_rel == 0.125);
  CHECK(back.scans[2].e_bar_rel_m == 3e-3);
  CHECK(nbs::eval::to_json(back) == j);
  Json missing = j;  // a pose record without a series is malformed
  missing["scans"].erase("pose_rel_t_mm");
  CHECK_THROWS(nbs::eval::record_from_json(missing));
  const nbs::eval::RunOutcome o = nbs::eval::outcome(back);
  CHECK(o.mean_pose_t_mm == Approx(0.5));
  CHECK(o.mean_pose_r_deg == Approx(0.2));
  CHECK(o.double_surface_share == 0.25);
  const auto rows = nbs::eval::summarize_records({back, back});
  CHECK(nbs::eval::summary_json(rows).at("C_H").at("mean_double_surface_share") == 0.25);
  CHECK_THAT(nbs::eval::summary_markdown(rows, 3), nbs_test::Contains("double surface %"));
  CHECK_FALSE(nbs::eval::summary_json(nbs::eval::summarize_records({hand_record()})).at("C_H").contains("mean_pose_t_mm"));
}

TEST_CASE("CLI: bad --pose-error and --registration exit 2 naming option and value", "[eval][pose_error]") {
  const TempDir tmp("pose_bad");
  const std::string bunny = NBS_DATA_DIR "/meshes/stanford-bunny.obj";
  const std::string out = (tmp.path / "out").string();
  for (const std::string v : {"1", "1,", ",1", "-1,0.1", "1,-0.1", "nan,0", "1,inf", "a,b", "1,200", "1,0.1,2"})
    expect_rejected({"--mesh", bunny, "--out", out, "--pose-error", v}, "--pose-error: expects T_MM,R_DEG", out);
  expect_rejected({"--mesh", bunny, "--out", out, "--pose-error", "1,x"}, "got '1,x'", out);
  expect_rejected({"--mesh", bunny, "--out", out, "--registration", "gicp"}, "unknown registration method 'gicp'", out);
}

TEST_CASE("CLI: --pose-error runs: new fields consistent, zero error identical to no option, rerun check",
          "[eval][pose_error]") {
  const TempDir tmp("pose_runs");
  const std::string bunny = NBS_DATA_DIR "/meshes/stanford-bunny.obj";
  const std::vector<std::string> common{"--mesh", bunny, "--size", "0.05", "--methods", "C_H", "--runs", "1",
                                        "--scans", "2", "--seed", "7", "--threads", "1"};
  const auto with = [&](std::vector<std::string> extra, const fs::path& out) {
    std::vector<std::string> a = common;
    a.insert(a.end(), extra.begin(), extra.end());
    a.insert(a.end(), {"--out", out.string()});
    return a;
  };
  std::string log;
  REQUIRE(run_cli(with({}, tmp.path / "plain"), log) == 0);
  REQUIRE(run_cli(with({"--pose-error", "0,0"}, tmp.path / "zero"), log) == 0);
  REQUIRE(run_cli(with({"--pose-error", "1,0.1", "--registration", "icp"}, tmp.path / "err"), log) == 0);
  const std::vector<Json> plain = lines_of(tmp.path / "plain" / "runs.jsonl");
  std::vector<Json> zero = lines_of(tmp.path / "zero" / "runs.jsonl");
  const std::vector<Json> err = lines_of(tmp.path / "err" / "runs.jsonl");
  REQUIRE(plain.size() == 1);
  REQUIRE(zero.size() == 1);
  REQUIRE(err.size() == 1);
  CHECK_FALSE(plain[0].contains("double_surface_share"));
  CHECK_FALSE(plain[0]["scans"].contains("pose_t_mm"));
  // Zero error: the scans are bit-identical, so everything but the timing and the new fields is equal.
  for (const char* k : {"pose_t_mm", "pose_r_deg", "pose_rel_t_mm", "pose_rel_r_deg", "icp_s"})
    for (const Json& v : zero[0]["scans"][k]) CHECK(v.get<double>() == 0.0);
  for (const Json& v : zero[0]["scans"]["registration"]) CHECK(v == "not_run");
  // Without error the model's frame is the true one: the relative measures equal the absolute ones.
  CHECK(zero[0]["scans"]["e_bar_rel_m"] == zero[0]["scans"]["e_bar_m"]);
  CHECK(zero[0]["double_surface_share_rel"] == zero[0]["double_surface_share"]);
  zero[0].erase("double_surface_share");
  zero[0].erase("double_surface_share_rel");
  for (const char* k : {"pose_t_mm", "pose_r_deg", "pose_rel_t_mm", "pose_rel_r_deg", "e_bar_rel_m", "registration", "icp_s"})
    zero[0]["scans"].erase(k);
  CHECK(without_timing(zero[0]) == without_timing(plain[0]));
  // 1 mm, 0.1°, the ICP refusing on this branch or correcting: per scan a status, and without a correction the
  // residual is E itself: 0.1° exactly, |t| within 1 mm ± the lever arm 2 sin(0.05°)·|c − s0| (|c − s0| < 0.5 m).
  const Json& s = err[0]["scans"];
  REQUIRE(s["pose_t_mm"].size() == 2);
  // The first scan defines the model's frame: its relative error is zero (E₁⁻¹ · E₁), its ē_rel that of the true
  // placement, which is not larger than ē by more than the 1 mm shift.
  CHECK(s["pose_rel_t_mm"][0].get<double>() < 1e-9);
  CHECK(s["pose_rel_r_deg"][0].get<double>() < 1e-6);
  CHECK(s["e_bar_rel_m"][0].get<double>() <= s["e_bar_m"][0].get<double>() + 1e-3);
  for (std::size_t i = 0; i < 2; ++i) {
    INFO("scan " << i);
    CHECK(s["registration"][i].is_string());
    CHECK(s["icp_s"][i].get<double>() >= 0.0);
    if (s["registration"][i] != "applied") {
      CHECK(s["pose_r_deg"][i].get<double>() == Approx(0.1).epsilon(1e-9));
      CHECK(std::abs(s["pose_t_mm"][i].get<double>() - 1.0) <= 1e3 * 2.0 * std::sin(0.05 * M_PI / 180.0) * 0.5);
    }
  }
  const double share = err[0]["double_surface_share"].get<double>();
  CHECK((share >= 0.0 && share <= 1.0));
  const Json cfg = Json::parse(read(tmp.path / "err" / "eval.json"));
  CHECK(cfg.at("pose_error").at("translation_mm") == 1.0);
  CHECK(cfg.at("registration") == "icp");
  CHECK_FALSE(Json::parse(read(tmp.path / "plain" / "eval.json")).contains("pose_error"));
  CHECK(Json::parse(read(tmp.path / "err" / "summary.json")).at("C_H").contains("mean_pose_t_mm"));
  // A rerun with the same options skips the finished run; with another pose error it is refused.
  REQUIRE(run_cli(with({"--pose-error", "1,0.1", "--registration", "icp"}, tmp.path / "err"), log) == 0);
  CHECK_THAT(log, nbs_test::Contains("1 finished runs found"));
  CHECK(run_cli(with({"--pose-error", "2,0.1", "--registration", "icp"}, tmp.path / "err"), log) == 2);
  CHECK_THAT(log, nbs_test::Contains("different configuration"));
  CHECK(run_cli(with({"--pose-error", "1,0.1"}, tmp.path / "err"), log) == 2);
}

TEST_CASE("runs.jsonl with --robot: unreachable_candidates round-trips; a bad --robot exits 2 naming the path",
          "[eval][robot]") {
  nbs::eval::RunRecord r = hand_record();
  r.robot = true;
  for (std::size_t i = 0; i < r.scans.size(); ++i) r.scans[i].unreachable_candidates = 3 * i;
  const Json j = nbs::eval::to_json(r);
  CHECK(j.at("scans").at("unreachable_candidates").size() == r.scans.size());
  const nbs::eval::RunRecord back = nbs::eval::record_from_json(Json::parse(j.dump()));
  CHECK(back.robot);
  CHECK(nbs::eval::to_json(back) == j);
  CHECK_FALSE(nbs::eval::to_json(hand_record()).at("scans").contains("unreachable_candidates"));
  const TempDir tmp("robot_bad");
  const std::string bunny = NBS_DATA_DIR "/meshes/stanford-bunny.obj";
  const std::string out = (tmp.path / "out").string();
  expect_rejected({"--mesh", bunny, "--out", out, "--robot", "/nonexistent/arm.urdf"}, "/nonexistent/arm.urdf", out);
}

TEST_CASE("without --robot the record and the summary files are byte-identical to before the transfer columns",
          "[eval][robot]") {
  // The golden strings were written by this same code built from main at 311f4bb (before issue 19's transfers).
  // Since 2026-12-07 every record also carries the parts of ĉ_m (a_filled_m2, a_unseen*_m2); without them the
  // record is the golden one.
  const nbs::eval::RunRecord r = hand_record();
  Json without_parts = nbs::eval::to_json(r);
  for (const char* key : {"a_filled_m2", "a_unseen_m2", "a_unseen_5mm_m2", "a_unseen_10mm_m2"}) {
    CHECK(without_parts.at("scans").at(key).size() == r.scans.size());
    without_parts["scans"].erase(key);
  }
  CHECK(without_parts.dump() ==
        R"({"c_obs":0.95,"initial_index":7,"method":"C_H","n_abort":3,"n_s":2,"run":3,"scans":{"c_a":[0.5,0.8,0.9],)"
        R"("c_b":[0.4,0.7000000000000001,0.8],"c_m":[0.4,0.8,1.2000000000000002],"candidates":[0,10,20],)"
        R"("d_m":[0.1,0.2,0.30000000000000004],"e_bar_m":[0.001,0.001,0.001],"l_s_m":[0.1,0.3,0.6],)"
        R"("mode":["init","BS","BS"],"t_nbs_s":[0.0,1.0,3.0]},"seed":42,"stop":"max_scans"})");
  const auto rows = nbs::eval::summarize_records({r});
  CHECK(nbs::eval::summary_json(rows).dump() ==
        R"({"C_H":{"mean_c_obs":0.95,"mean_ca_at_30":0.9,"mean_ca_at_stop":0.8,"mean_path_length_m":0.6,)"
        R"("mean_path_to_k99_m":0.6,"mean_t_nbs_s":2.0,"median_k95":4.0,"median_k99":4.0,"median_scans":2.0,)"
        R"("notch":0.0,"q1_scans":2.0,"q3_scans":2.0,"runs":1,"stop_minus_k99":-2.0}})");
  CHECK(nbs::eval::summary_markdown(rows, 3) ==
        "| Method | Selection | Search | runs | median n_s | Notch | mean c_a(n_s) % | mean c_a(3) % | mean l_s / m | "
        "mean t_nbs / s | c_obs % | median k95 | median k99 | mean l_s to k99 / m | n_s − k99 |\n"
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
        "| C_H | IG/Quality | BS/HR | 1 | 2.0 | ±0.00 | 80.00 | 90.00 | 0.60 | 2.00 | 95.00 | 4.0 | 4.0 | 0.60 | -2.0 |\n");
  CHECK(nbs::eval::summary_csv(rows) ==
        "method,selection,search,runs,median_n_s,notch,mean_c_a_at_n_s_percent,mean_c_a_at_n_abort_percent,"
        "mean_l_s_m,mean_t_nbs_s,c_obs_percent,median_k95,median_k99,mean_path_to_k99_m,stop_minus_k99\n"
        "C_H,IG/Quality,BS/HR,1,2,0,80,90,0.6,2,95,4,4,0.6,-2\n");
}

TEST_CASE("robot summary columns from a hand-made runs.jsonl: mean transfer length and planning time",
          "[eval][robot]") {
  // Two C_H runs with --robot, 3 scans each (2 transfers each; the first scan has none, its zeros are not counted).
  // Run 0: transfers 1.0 and 3.0 rad, 0.2 and 0.6 m, 0.01 and 0.03 s -> means 2.0 rad, 0.4 m, 0.02 s.
  // Run 1: transfers 0.5 and 0.5 rad, 0.1 and 0.3 m, 0.004 and 0.002 s -> means 0.5 rad, 0.2 m, 0.003 s.
  // Method: 1.25 rad, 0.3 m, 0.0115 s.
  const char* lines[] = {
      R"({"method":"C_H","run":0,"seed":1,"initial_index":2,"n_abort":3,"n_s":3,"stop":"max_scans","c_obs":0.9,)"
      R"("scans":{"c_m":[0,0,0],"d_m":[0,0,0],"c_a":[0.5,0.6,0.7],"c_b":[0,0,0],"e_bar_m":[0,0,0],)"
      R"("l_s_m":[0.1,0.2,0.3],"t_nbs_s":[0,1,1],"candidates":[0,1,1],"mode":["init","BS","BS"],)"
      R"("unreachable_candidates":[0,4,2],"transfer_joint_rad":[0,1.0,3.0],"transfer_sensor_m":[0,0.2,0.6],)"
      R"("t_motion_s":[0,0.01,0.03]}})",
      R"({"method":"C_H","run":1,"seed":2,"initial_index":5,"n_abort":3,"n_s":3,"stop":"transfer_failed","c_obs":0.9,)"
      R"("scans":{"c_m":[0,0,0],"d_m":[0,0,0],"c_a":[0.5,0.6,0.7],"c_b":[0,0,0],"e_bar_m":[0,0,0],)"
      R"("l_s_m":[0.1,0.2,0.3],"t_nbs_s":[0,1,1],"candidates":[0,1,1],"mode":["init","BS","BS"],)"
      R"("unreachable_candidates":[0,0,1],"transfer_joint_rad":[0,0.5,0.5],"transfer_sensor_m":[0,0.1,0.3],)"
      R"("t_motion_s":[0,0.004,0.002],"transfer_failures":[0,2,0]}})"};
  std::vector<nbs::eval::RunRecord> records;
  for (const char* l : lines) records.push_back(nbs::eval::record_from_json(Json::parse(l)));
  REQUIRE(records[0].robot);
  CHECK(records[1].scans[2].transfer_sensor_m == 0.3);
  CHECK(records[1].scans[1].transfer_failures == 2);  // read back and written again (the round trip below)
  CHECK(records[0].scans[1].transfer_failures == 0);  // a file written before the column: 0
  CHECK(nbs::eval::to_json(records[1]).at("scans").at("transfer_failures") == Json::parse("[0,2,0]"));
  CHECK(nbs::eval::to_json(nbs::eval::record_from_json(nbs::eval::to_json(records[1]))) ==
        nbs::eval::to_json(records[1]));
  const nbs::eval::RunOutcome o0 = nbs::eval::outcome(records[0]);
  CHECK(o0.mean_transfer_joint_rad == Approx(2.0));
  CHECK(o0.mean_transfer_sensor_m == Approx(0.4));
  CHECK(o0.mean_t_motion_s == Approx(0.02));
  const auto rows = nbs::eval::summarize_records(records);
  REQUIRE(rows.size() == 1);
  CHECK(rows[0].robot);
  CHECK(rows[0].mean_transfer_joint_rad == Approx(1.25));
  CHECK(rows[0].mean_transfer_sensor_m == Approx(0.3));
  CHECK(rows[0].mean_t_motion_s == Approx(0.0115));
  const Json js = nbs::eval::summary_json(rows);
  CHECK(js.at("C_H").at("mean_transfer_joint_rad").get<double>() == Approx(1.25));
  CHECK(js.at("C_H").at("mean_transfer_sensor_m").get<double>() == Approx(0.3));
  CHECK(js.at("C_H").at("mean_t_motion_s").get<double>() == Approx(0.0115));
  const std::string md = nbs::eval::summary_markdown(rows, 3);
  CHECK(md.find("| mean transfer / rad | mean transfer / m | mean t_motion / s |\n") != std::string::npos);
  CHECK(md.find("| 1.250 | 0.300 | 0.0115 |\n") != std::string::npos);
  // A wrong series length is refused.
  Json broken = Json::parse(lines[0]);
  broken["scans"]["t_motion_s"].erase(0);
  CHECK_THROWS(nbs::eval::record_from_json(broken));
}
