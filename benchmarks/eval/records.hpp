// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// One evaluation run as a JSON line (runs.jsonl) and the summary files (summary.json / .md / .csv, Tab. 4.5).
/// Every number is SI (metres, seconds); coverages are fractions in [0, 1] in JSON and percent in .md / .csv.

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval/summary.hpp"
#include "nbs/planner/runtime_planner.hpp"

namespace nbs::eval {

using Json = nlohmann::json;

/// The state after one scan of a run.
struct ScanRow {
  double c_m = 0;          ///< ĉ_m, estimated mesh coverage (Eq. 4.35)
  double d_m = 0;          ///< d̄_m, mean relative point density (Eqs. 4.24–4.25)
  double c_a = 0;          ///< actual completeness of the generated mesh's vertices (non-bottom samples)
  double c_b = 0;          ///< the same over all samples (bottom included)
  double e_bar_m = 0;      ///< ē, RMS distance of the mesh vertices to the true surface
  double l_s_m = 0;        ///< l_s, summed scan path length so far
  double t_nbs_s = 0;      ///< time of the planning step that chose this scan (0 for the first scan)
  std::size_t candidates = 0;  ///< candidates scored in that planning step (0 for the first scan)
  std::string mode;        ///< "init" (first scan), "BS" or "HR": the mode the scan was planned in
  /// What ĉ_m is made of after this scan (Eq. 4.35: ĉ_m = A_filled / (A_filled + A_empty)), for replaying other
  /// stop rules: A_filled (m²), and A_empty split by the fan samples' distance d from their loop's edge
  /// (UnseenSample::edge_distance_m): all, d ≥ 5 mm, d ≥ 10 mm. Absent in files written before 2026-12-07 (read as 0).
  double a_filled_m2 = 0;
  double a_unseen_m2 = 0;
  double a_unseen_5mm_m2 = 0;
  double a_unseen_10mm_m2 = 0;
  // With --pose-error / --registration only (RunRecord::pose):
  double pose_t_mm = 0;    ///< residual pose error after registration: |R·c − c| at the true points' centroid, mm
  double pose_r_deg = 0;   ///< its rotation angle, degrees (residual_pose_error, sim/pose_error.hpp)
  /// The same relative to the model's frame, i.e. to where the first scan was placed (R · E₁⁻¹): the part a
  /// registration to the model can correct (the first scan's own error E₁ moves the whole model and is not seen by
  /// any registration). 0 for the first scan.
  double pose_rel_t_mm = 0;
  double pose_rel_r_deg = 0;
  double e_bar_rel_m = 0;  ///< ē with the vertices mapped by E₁⁻¹ into the true frame (= e_bar_m without error)
  std::string registration;  ///< the registration status (to_string(RegistrationStatus))
  double icp_s = 0;        ///< time of the registration step (RegistrationResult::t_s), seconds
  /// With --robot only (RunRecord::robot): candidates of the planning step that the arm could not fly
  /// (IterationStats::unreachable; 0 for the first scan).
  std::size_t unreachable_candidates = 0;
  /// With --robot only: the arm's transfer to this scan's start (ScanRecord::transfer; 0 for the first scan):
  double transfer_joint_rad = 0;  ///< joint-space length Σ‖Δq‖, rad
  double transfer_sensor_m = 0;   ///< the sensor's path length along it (fk), m
  double t_motion_s = 0;          ///< motion-planning time of the transfer, s
  /// Failed transfers to other candidates before this scan's (TransferRecord::failed_attempts; each excluded its
  /// candidate and the next best was tried).
  int transfer_failures = 0;
};

/// One (method, run) of the experiment.
struct RunRecord {
  std::string method;   ///< method code, e.g. "C_H"
  int run = 0;          ///< 0-based run index
  std::uint64_t seed = 0;  ///< seed of the run (initial scan, sensor noise, Random selection)
  int initial_index = 0;   ///< which of the 13 initial scan paths (Sec. 4.7.2)
  int n_abort = 30;     ///< scan limit
  int n_s = 30;         ///< first scan after which the set-up's stop rule held, else n_abort
  /// "max_scans", "no_candidates", "no_reachable_candidate", "transfer_failed" (loop ended early) or "done"
  std::string stop;
  double c_obs = 0;     ///< observability ceiling of the mesh
  /// --pose-error / --registration given: the scans carry the pose fields, the run double_surface_share.
  bool pose = false;
  /// Share of the final mesh's vertices farther than 2σ (sensor range noise at the planner's standoff) from the
  /// true surface.
  double double_surface_share = 0;
  double double_surface_share_rel = 0;  ///< the same with the vertices mapped by E₁⁻¹ (see ScanRow::pose_rel_t_mm)
  bool robot = false;   ///< --robot given: the scans carry unreachable_candidates and the transfer columns
  std::vector<ScanRow> scans;
};

[[nodiscard]] inline Json to_json(const RunRecord& r) {
  Json s = Json::object();
  const auto col = [&](const char* key, auto get) {
    Json a = Json::array();
    for (const ScanRow& row : r.scans) a.push_back(get(row));
    s[key] = std::move(a);
  };
  col("c_m", [](const ScanRow& x) { return x.c_m; });
  col("d_m", [](const ScanRow& x) { return x.d_m; });
  col("c_a", [](const ScanRow& x) { return x.c_a; });
  col("c_b", [](const ScanRow& x) { return x.c_b; });
  col("e_bar_m", [](const ScanRow& x) { return x.e_bar_m; });
  col("l_s_m", [](const ScanRow& x) { return x.l_s_m; });
  col("t_nbs_s", [](const ScanRow& x) { return x.t_nbs_s; });
  col("candidates", [](const ScanRow& x) { return x.candidates; });
  col("mode", [](const ScanRow& x) { return x.mode; });
  col("a_filled_m2", [](const ScanRow& x) { return x.a_filled_m2; });
  col("a_unseen_m2", [](const ScanRow& x) { return x.a_unseen_m2; });
  col("a_unseen_5mm_m2", [](const ScanRow& x) { return x.a_unseen_5mm_m2; });
  col("a_unseen_10mm_m2", [](const ScanRow& x) { return x.a_unseen_10mm_m2; });
  if (r.pose) {
    col("pose_t_mm", [](const ScanRow& x) { return x.pose_t_mm; });
    col("pose_r_deg", [](const ScanRow& x) { return x.pose_r_deg; });
    col("pose_rel_t_mm", [](const ScanRow& x) { return x.pose_rel_t_mm; });
    col("pose_rel_r_deg", [](const ScanRow& x) { return x.pose_rel_r_deg; });
    col("e_bar_rel_m", [](const ScanRow& x) { return x.e_bar_rel_m; });
    col("registration", [](const ScanRow& x) { return x.registration; });
    col("icp_s", [](const ScanRow& x) { return x.icp_s; });
  }
  if (r.robot) {
    col("unreachable_candidates", [](const ScanRow& x) { return x.unreachable_candidates; });
    col("transfer_joint_rad", [](const ScanRow& x) { return x.transfer_joint_rad; });
    col("transfer_sensor_m", [](const ScanRow& x) { return x.transfer_sensor_m; });
    col("t_motion_s", [](const ScanRow& x) { return x.t_motion_s; });
    col("transfer_failures", [](const ScanRow& x) { return x.transfer_failures; });
  }
  Json j{{"method", r.method}, {"run", r.run},     {"seed", r.seed}, {"initial_index", r.initial_index},
         {"n_abort", r.n_abort}, {"n_s", r.n_s},   {"stop", r.stop}, {"c_obs", r.c_obs},
         {"scans", std::move(s)}};
  if (r.pose) {
    j["double_surface_share"] = r.double_surface_share;
    j["double_surface_share_rel"] = r.double_surface_share_rel;
  }
  return j;
}

/// Parses a runs.jsonl line. Throws std::runtime_error (or a json exception) on a malformed line.
[[nodiscard]] inline RunRecord record_from_json(const Json& j) {
  RunRecord r;
  r.method = j.at("method").get<std::string>();
  r.run = j.at("run").get<int>();
  r.seed = j.at("seed").get<std::uint64_t>();
  r.initial_index = j.at("initial_index").get<int>();
  r.n_abort = j.at("n_abort").get<int>();
  r.n_s = j.at("n_s").get<int>();
  r.stop = j.at("stop").get<std::string>();
  r.c_obs = j.at("c_obs").get<double>();
  const Json& s = j.at("scans");
  const std::size_t n = s.at("c_a").size();
  for (const char* key : {"c_m", "d_m", "c_b", "e_bar_m", "l_s_m", "t_nbs_s", "candidates", "mode"})
    if (s.at(key).size() != n) throw std::runtime_error(std::string("scan series '") + key + "' has a wrong length");
  if (n == 0) throw std::runtime_error("run without scans");
  r.scans.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    ScanRow& x = r.scans[i];
    x.c_m = s["c_m"][i].get<double>();
    x.d_m = s["d_m"][i].get<double>();
    x.c_a = s["c_a"][i].get<double>();
    x.c_b = s["c_b"][i].get<double>();
    x.e_bar_m = s["e_bar_m"][i].get<double>();
    x.l_s_m = s["l_s_m"][i].get<double>();
    x.t_nbs_s = s["t_nbs_s"][i].get<double>();
    x.candidates = s["candidates"][i].get<std::size_t>();
    x.mode = s["mode"][i].get<std::string>();
  }
  // The ĉ_m parts (absent in files written before they existed: left 0).
  const bool has_parts = s.contains("a_filled_m2");
  for (const char* key : {"a_filled_m2", "a_unseen_m2", "a_unseen_5mm_m2", "a_unseen_10mm_m2"}) {
    if (s.contains(key) != has_parts)
      throw std::runtime_error(std::string("scan series '") + key + "': the four ĉ_m parts come together");
    if (has_parts && s.at(key).size() != n)
      throw std::runtime_error(std::string("scan series '") + key + "' has a wrong length");
  }
  if (has_parts)
    for (std::size_t i = 0; i < n; ++i) {
      r.scans[i].a_filled_m2 = s["a_filled_m2"][i].get<double>();
      r.scans[i].a_unseen_m2 = s.at("a_unseen_m2")[i].get<double>();
      r.scans[i].a_unseen_5mm_m2 = s.at("a_unseen_5mm_m2")[i].get<double>();
      r.scans[i].a_unseen_10mm_m2 = s.at("a_unseen_10mm_m2")[i].get<double>();
    }
  r.robot = s.contains("unreachable_candidates");
  if (r.robot) {
    if (s.at("unreachable_candidates").size() != n)
      throw std::runtime_error("scan series 'unreachable_candidates' has a wrong length");
    for (std::size_t i = 0; i < n; ++i)
      r.scans[i].unreachable_candidates = s["unreachable_candidates"][i].get<std::size_t>();
    // The transfer columns (absent in files written before they existed: left 0).
    for (const char* key : {"transfer_joint_rad", "transfer_sensor_m", "t_motion_s", "transfer_failures"})
      if (s.contains(key) && s.at(key).size() != n)
        throw std::runtime_error(std::string("scan series '") + key + "' has a wrong length");
    if (s.contains("transfer_joint_rad"))
      for (std::size_t i = 0; i < n; ++i) {
        r.scans[i].transfer_joint_rad = s["transfer_joint_rad"][i].get<double>();
        r.scans[i].transfer_sensor_m = s.at("transfer_sensor_m")[i].get<double>();
        r.scans[i].t_motion_s = s.at("t_motion_s")[i].get<double>();
      }
    if (s.contains("transfer_failures"))
      for (std::size_t i = 0; i < n; ++i) r.scans[i].transfer_failures = s["transfer_failures"][i].get<int>();
  }
  r.pose = j.contains("double_surface_share");
  if (r.pose) {
    r.double_surface_share = j.at("double_surface_share").get<double>();
    r.double_surface_share_rel = j.at("double_surface_share_rel").get<double>();
    for (const char* key : {"pose_t_mm", "pose_r_deg", "pose_rel_t_mm", "pose_rel_r_deg", "e_bar_rel_m", "registration", "icp_s"})
      if (s.at(key).size() != n) throw std::runtime_error(std::string("scan series '") + key + "' has a wrong length");
    for (std::size_t i = 0; i < n; ++i) {
      ScanRow& x = r.scans[i];
      x.pose_t_mm = s["pose_t_mm"][i].get<double>();
      x.pose_r_deg = s["pose_r_deg"][i].get<double>();
      x.pose_rel_t_mm = s["pose_rel_t_mm"][i].get<double>();
      x.pose_rel_r_deg = s["pose_rel_r_deg"][i].get<double>();
      x.e_bar_rel_m = s["e_bar_rel_m"][i].get<double>();
      x.registration = s["registration"][i].get<std::string>();
      x.icp_s = s["icp_s"][i].get<double>();
    }
  }
  return r;
}

/// First scan (1-based) after which c_a ≥ share · c_obs; n_abort + 1 when no scan reaches it.
[[nodiscard]] inline int scans_to_truth(const RunRecord& r, double share) {
  for (std::size_t i = 0; i < r.scans.size(); ++i)
    if (r.scans[i].c_a >= share * r.c_obs) return static_cast<int>(i) + 1;
  return r.n_abort + 1;
}

/// The Tab. 4.5 contribution of one run: c_a(n_s), c_a at the last scan, l_s at the last scan, mean t_nbs over the
/// planning steps (scans 2…), c_obs; and the truth-based k95, k99, l_s to k99 and n_s − k99 (RunOutcome).
[[nodiscard]] inline RunOutcome outcome(const RunRecord& r) {
  RunOutcome o;
  o.n_s = r.n_s;
  const std::size_t at = std::min<std::size_t>(static_cast<std::size_t>(std::max(r.n_s, 1)), r.scans.size()) - 1;
  o.ca_at_stop = r.scans[at].c_a;
  o.ca_at_end = r.scans.back().c_a;
  o.path_length_m = r.scans.back().l_s_m;
  double t = 0.0;
  for (std::size_t i = 1; i < r.scans.size(); ++i) t += r.scans[i].t_nbs_s;
  o.mean_t_nbs_s = r.scans.size() > 1 ? t / static_cast<double>(r.scans.size() - 1) : 0.0;
  o.c_obs = r.c_obs;
  o.k95 = scans_to_truth(r, 0.95);
  const int k99 = scans_to_truth(r, 0.99);
  o.k99 = k99;
  o.path_to_k99_m = r.scans[std::min<std::size_t>(static_cast<std::size_t>(k99), r.scans.size()) - 1].l_s_m;
  o.stop_minus_k99 = r.n_s - k99;
  o.robot = r.robot;
  if (r.robot && r.scans.size() > 1) {  // over the transfers (scans 2, 3, …)
    for (std::size_t i = 1; i < r.scans.size(); ++i) {
      o.mean_transfer_joint_rad += r.scans[i].transfer_joint_rad;
      o.mean_transfer_sensor_m += r.scans[i].transfer_sensor_m;
      o.mean_t_motion_s += r.scans[i].t_motion_s;
    }
    const auto transfers = static_cast<double>(r.scans.size() - 1);
    o.mean_transfer_joint_rad /= transfers;
    o.mean_transfer_sensor_m /= transfers;
    o.mean_t_motion_s /= transfers;
  }
  o.pose = r.pose;
  if (r.pose) {
    for (const ScanRow& x : r.scans) o.mean_pose_t_mm += x.pose_t_mm, o.mean_pose_r_deg += x.pose_r_deg;
    o.mean_pose_t_mm /= static_cast<double>(r.scans.size());
    o.mean_pose_r_deg /= static_cast<double>(r.scans.size());
    o.double_surface_share = r.double_surface_share;
  }
  return o;
}

/// Position of a method code in kAllMethods (thesis order first), for sorting.
[[nodiscard]] inline std::size_t method_rank(const std::string& code) {
  const Method m = parse_method(code);
  for (std::size_t i = 0; i < kAllMethods.size(); ++i)
    if (kAllMethods[i] == m) return i;
  return kAllMethods.size();
}

/// Sorts by (method in kAllMethods order, run).
inline void sort_records(std::vector<RunRecord>& v) {
  std::stable_sort(v.begin(), v.end(), [](const RunRecord& a, const RunRecord& b) {
    const std::size_t ra = method_rank(a.method), rb = method_rank(b.method);
    return ra != rb ? ra < rb : a.run < b.run;
  });
}

/// Summary rows, one per method present, in kAllMethods order.
[[nodiscard]] inline std::vector<MethodSummary> summarize_records(std::vector<RunRecord> v) {
  sort_records(v);
  std::vector<MethodSummary> out;
  for (std::size_t i = 0; i < v.size();) {
    std::vector<RunOutcome> o;
    std::size_t j = i;
    for (; j < v.size() && v[j].method == v[i].method; ++j) o.push_back(outcome(v[j]));
    out.push_back(summarize(v[i].method, o));
    i = j;
  }
  return out;
}

[[nodiscard]] inline Json summary_json(const std::vector<MethodSummary>& rows) {
  Json j = Json::object();
  for (const MethodSummary& s : rows) {
    j[s.method] = Json{{"runs", s.runs},
                       {"median_scans", s.median_scans},
                       {"q1_scans", s.q1_scans},
                       {"q3_scans", s.q3_scans},
                       {"notch", s.notch},
                       {"mean_ca_at_stop", s.mean_ca_at_stop},
                       {"mean_ca_at_30", s.mean_ca_at_30},
                       {"mean_path_length_m", s.mean_path_length_m},
                       {"mean_t_nbs_s", s.mean_t_nbs_s},
                       {"mean_c_obs", s.mean_c_obs},
                       {"median_k95", s.median_k95},
                       {"median_k99", s.median_k99},
                       {"mean_path_to_k99_m", s.mean_path_to_k99_m},
                       {"stop_minus_k99", s.median_stop_minus_k99}};
    if (s.pose) {  // --pose-error / --registration runs only
      j[s.method]["mean_pose_t_mm"] = s.mean_pose_t_mm;
      j[s.method]["mean_pose_r_deg"] = s.mean_pose_r_deg;
      j[s.method]["mean_double_surface_share"] = s.mean_double_surface_share;
    }
    if (s.robot) {  // --robot runs only
      j[s.method]["mean_transfer_joint_rad"] = s.mean_transfer_joint_rad;
      j[s.method]["mean_transfer_sensor_m"] = s.mean_transfer_sensor_m;
      j[s.method]["mean_t_motion_s"] = s.mean_t_motion_s;
    }
  }
  return j;
}

/// Long names of Tab. 4.5: selection ("Random", "IG", "Quality", "IG/Quality", else the peer code) and search.
[[nodiscard]] inline std::string selection_name(const Method& m) {
  if (m.search == SearchSpace::surface_edge) return "nearest view";
  switch (m.selection) {
    case Selection::random: return "Random";
    case Selection::information_gain: return "IG";
    case Selection::quality: return "Quality";
    case Selection::ig_quality: return "IG/Quality";
    default: return std::string(format_selection(m.selection));
  }
}
[[nodiscard]] inline std::string search_name(const Method& m) {
  switch (m.search) {
    case SearchSpace::sphere: return "Sphere";
    case SearchSpace::boundary: return "BS";
    case SearchSpace::boundary_hole: return "BS/HR";
    case SearchSpace::surface_edge: return "SEE frontier";
  }
  return "?";
}

namespace detail {
[[nodiscard]] inline std::string fixed(double v, int digits) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(digits) << v;
  return o.str();
}
}  // namespace detail

/// summary.md: Tab. 4.5 layout (coverages in percent), plus runs and c_obs, then the truth-based columns: median
/// k95 / k99 (scans until c_a ≥ 0.95 / 0.99 c_obs, n_abort + 1 when never), mean l_s to k99, median n_s − k99.
[[nodiscard]] inline std::string summary_markdown(const std::vector<MethodSummary>& rows, int n_abort) {
  using detail::fixed;
  std::ostringstream o;
  const std::string ab = std::to_string(n_abort);
  const bool pose = !rows.empty() && std::all_of(rows.begin(), rows.end(), [](const MethodSummary& s) { return s.pose; });
  const bool robot =
      !rows.empty() && std::all_of(rows.begin(), rows.end(), [](const MethodSummary& s) { return s.robot; });
  o << "| Method | Selection | Search | runs | median n_s | Notch | mean c_a(n_s) % | mean c_a(" << ab
    << ") % | mean l_s / m | mean t_nbs / s | c_obs % | median k95 | median k99 | mean l_s to k99 / m | n_s − k99 |"
    << (pose ? " pose t / mm | pose r / deg | double surface % |" : "")
    << (robot ? " mean transfer / rad | mean transfer / m | mean t_motion / s |" : "") << "\n";
  o << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|" << (pose ? "---:|---:|---:|" : "")
    << (robot ? "---:|---:|---:|" : "") << "\n";
  for (const MethodSummary& s : rows) {
    const Method m = parse_method(s.method);
    o << "| " << s.method << " | " << selection_name(m) << " | " << search_name(m) << " | " << s.runs << " | "
      << fixed(s.median_scans, 1) << " | ±" << fixed(s.notch, 2) << " | " << fixed(100.0 * s.mean_ca_at_stop, 2)
      << " | " << fixed(100.0 * s.mean_ca_at_30, 2) << " | " << fixed(s.mean_path_length_m, 2) << " | "
      << fixed(s.mean_t_nbs_s, 2) << " | " << fixed(100.0 * s.mean_c_obs, 2) << " | " << fixed(s.median_k95, 1)
      << " | " << fixed(s.median_k99, 1) << " | " << fixed(s.mean_path_to_k99_m, 2) << " | "
      << fixed(s.median_stop_minus_k99, 1) << " |";
    if (pose)
      o << " " << fixed(s.mean_pose_t_mm, 3) << " | " << fixed(s.mean_pose_r_deg, 3) << " | "
        << fixed(100.0 * s.mean_double_surface_share, 2) << " |";
    if (robot)
      o << " " << fixed(s.mean_transfer_joint_rad, 3) << " | " << fixed(s.mean_transfer_sensor_m, 3) << " | "
        << fixed(s.mean_t_motion_s, 4) << " |";
    o << "\n";
  }
  return o.str();
}

/// summary.csv: the same columns, full precision, coverages in percent.
[[nodiscard]] inline std::string summary_csv(const std::vector<MethodSummary>& rows) {
  std::ostringstream o;
  o << std::setprecision(10);
  o << "method,selection,search,runs,median_n_s,notch,mean_c_a_at_n_s_percent,mean_c_a_at_n_abort_percent,"
       "mean_l_s_m,mean_t_nbs_s,c_obs_percent,median_k95,median_k99,mean_path_to_k99_m,stop_minus_k99\n";
  for (const MethodSummary& s : rows) {
    const Method m = parse_method(s.method);
    o << s.method << ',' << selection_name(m) << ',' << search_name(m) << ',' << s.runs << ',' << s.median_scans
      << ',' << s.notch << ',' << 100.0 * s.mean_ca_at_stop << ',' << 100.0 * s.mean_ca_at_30 << ','
      << s.mean_path_length_m << ',' << s.mean_t_nbs_s << ',' << 100.0 * s.mean_c_obs << ',' << s.median_k95 << ','
      << s.median_k99 << ',' << s.mean_path_to_k99_m << ',' << s.median_stop_minus_k99 << '\n';
  }
  return o.str();
}

}  // namespace nbs::eval
