// SPDX-License-Identifier: BSD-3-Clause
// bench_pose_error: what a robot's pose error costs the model and how much of it the ICP wins back (issue 20).
// The bunny at 160 mm, method C_H, nbs_eval's default set-up and its run_one (benchmarks/eval/runner.hpp), so the
// figures are those of `nbs_eval --methods C_H --seed 1 --pose-error T,R --registration none|icp` on the same run
// seeds, in three configurations: exact poses; a pose error of 1 mm / 0.1° per scan path (PoseErrorSetting's
// defaults: the KR16's "millimeter range", Sec. 5.1.1) without registration; the same error with the thesis's ICP.
// ē = RMS distance of the mesh vertices to the true surface after the run's last scan (10 scans and 4 runs with
// --quick, else 30 scans and 10 runs), mean over the runs, measured in the model's frame: the vertices mapped by
// E₁⁻¹, the first scan's error, which places the whole model and which no registration to the model can see
// (runs.jsonl e_bar_rel_m; docs/evaluation.md, "Pose error and registration").
// Headlines: registration.e_bar_pose_error_icp_vs_exact (ē with error + ICP ÷ ē exact; goal <= 1.2);
// reported: registration.e_bar_pose_error_none_vs_exact (the same without ICP),
// registration.e_bar_world_icp_vs_exact (ē in the world frame, E₁ included), registration.double_surface_icp_vs_none
// (double-surface share in the model's frame with ICP ÷ without), registration.pose_residual_icp_mm and
// registration.pose_residual_icp_deg (mean residual error relative to the model's frame after the ICP).

#include "eval/runner.hpp"  // first: includes the planner headers

#include <cstdio>
#include <string>

#include "headline.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sensor/presets.hpp"

namespace {

struct Outcome {
  double e_bar_rel_m = 0.0;    ///< mean over the runs of ē in the model's frame after the last scan
  double e_bar_m = 0.0;        ///< the same in the world frame
  double double_surface = 0.0; ///< mean double_surface_share_rel
  double pose_t_mm = 0.0, pose_r_deg = 0.0;  ///< mean over the runs of the mean relative residual over scans 2…
};

Outcome measure(const nbs::eval::RunContext& ctx, int runs) {
  const nbs::Method c_h = nbs::parse_method("C_H");
  Outcome o;
  for (int r = 0; r < runs; ++r) {
    const nbs::eval::RunRecord rec = nbs::eval::run_one(ctx, c_h, r, nbs::eval::run_seed(1, r));
    o.e_bar_rel_m += rec.scans.back().e_bar_rel_m / runs;
    o.e_bar_m += rec.scans.back().e_bar_m / runs;
    o.double_surface += rec.double_surface_share_rel / runs;
    const double n = static_cast<double>(rec.scans.size() - 1);  // the first scan defines the frame
    for (std::size_t i = 1; i < rec.scans.size(); ++i) {
      o.pose_t_mm += rec.scans[i].pose_rel_t_mm / n / runs;
      o.pose_r_deg += rec.scans[i].pose_rel_r_deg / n / runs;
    }
  }
  return o;
}

}  // namespace

int main() {
  const bool quick = nbs::bench::quick_mode();
  const int runs = quick ? 4 : 10, scans = quick ? 10 : 30;
  const double size_m = 0.16;
  nbs::IndexedMesh mesh = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  nbs::normalize_on_pedestal(mesh, size_m, nbs::UpAxis::y);
  const nbs::embree::SimulatedScanner scanner(mesh);
  nbs::GroundTruth::Setting gts;
  const nbs::Parameters params{};
  gts.completeness_radius_m = params.completeness_radius_m;
  gts.seed = 1;  // as nbs_eval: the measuring instrument is the same for every run
  const nbs::GroundTruth truth(mesh, gts);

  // translation_mm / rotation_deg: the injected error per scan path (nbs_eval --pose-error T_MM,R_DEG).
  const auto run = [&](double translation_mm, double rotation_deg, nbs::RegistrationMethod reg) {
    nbs::tools::PoseErrorOptions pose;
    pose.translation_mm = translation_mm;
    pose.rotation_deg = rotation_deg;
    pose.registration = reg;
    nbs::RuntimeModels models{};
    models.registration = reg;
    const nbs::eval::RunContext ctx{scanner, truth, params, nbs::presets::dlr_lsp(), nbs::eval::unknown_area_of(mesh, size_m),
                                    scans, 0.0, nbs::PlannerSetting{}, models, pose};
    const Outcome o = measure(ctx, runs);
    std::printf("%g mm, %g deg, %-4s ē %.4f mm (world %.4f)  double surface %.2f %%  residual %.3f mm %.3f deg\n",
                translation_mm, rotation_deg, nbs::to_string(reg).data(), 1e3 * o.e_bar_rel_m, 1e3 * o.e_bar_m, 100.0 * o.double_surface, o.pose_t_mm, o.pose_r_deg);
    return o;
  };
  const Outcome exact = run(0.0, 0.0, nbs::RegistrationMethod::none);
  const Outcome none = run(1.0, 0.1, nbs::RegistrationMethod::none);
  const Outcome icp = run(1.0, 0.1, nbs::RegistrationMethod::icp);

  char note[200];
  std::snprintf(note, sizeof note, "bunny, C_H, %d runs x %d scans, 1 mm / 0.1 deg, model frame; e_bar %.4f vs %.4f mm; goal <= 1.2",
                runs, scans, 1e3 * icp.e_bar_rel_m, 1e3 * exact.e_bar_rel_m);
  nbs::bench::report_headline("registration.e_bar_pose_error_icp_vs_exact", icp.e_bar_rel_m / exact.e_bar_rel_m, note);
  std::snprintf(note, sizeof note, "report: the same without registration (e_bar %.4f mm)", 1e3 * none.e_bar_rel_m);
  nbs::bench::report_headline("registration.e_bar_pose_error_none_vs_exact", none.e_bar_rel_m / exact.e_bar_rel_m, note);
  std::snprintf(note, sizeof note, "report: e_bar in the world frame, first scan's error included (%.4f vs %.4f mm; no ICP %.4f)",
                1e3 * icp.e_bar_m, 1e3 * exact.e_bar_m, 1e3 * none.e_bar_m);
  nbs::bench::report_headline("registration.e_bar_world_icp_vs_exact", icp.e_bar_m / exact.e_bar_m, note);
  std::snprintf(note, sizeof note, "report: share of mesh vertices > 2 sigma off the surface, %.2f %% vs %.2f %% (exact %.2f %%)",
                100.0 * icp.double_surface, 100.0 * none.double_surface, 100.0 * exact.double_surface);
  nbs::bench::report_headline("registration.double_surface_icp_vs_none",
                              none.double_surface > 0.0 ? icp.double_surface / none.double_surface : 0.0, note);
  std::snprintf(note, sizeof note, "report: mean residual translation relative to the model's frame after ICP; %.3f mm without",
                none.pose_t_mm);
  nbs::bench::report_headline("registration.pose_residual_icp_mm", icp.pose_t_mm, note);
  std::snprintf(note, sizeof note, "report: the same for the rotation; %.3f deg without", none.pose_r_deg);
  nbs::bench::report_headline("registration.pose_residual_icp_deg", icp.pose_r_deg, note);
  return 0;
}
