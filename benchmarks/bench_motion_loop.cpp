// SPDX-License-Identifier: BSD-3-Clause
// bench_motion, part 2 (issue 19, item 6): motion.c_a_at_10_robot_vs_free — c_a after 10 scans of C_H on the bunny
// (0.16 m, DLR LSP) with the shipped arm data/robots/lwr4.urdf (reach checks in Alg. 3 and at the choice, OMPL
// transfers between scans) ÷ the same with the free-flying sensor, same seeds, through nbs_eval's run_one (1 thread,
// the runs of nbs_eval --robot data/robots/lwr4.urdf --scans 10). --quick: 1 run (seed of run 0), else 3 runs; the
// figure is the ratio of the mean c_a over the runs. A robot run that stops early (no reachable candidate, a failed
// transfer) counts with c_a of its last scan.
#include "eval/runner.hpp"  // first: includes the planner headers

#include <cstdio>
#include <string>

#include "headline.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sensor/presets.hpp"

namespace nbs::bench {

void report_robot_vs_free(bool quick) {
  const int runs = quick ? 1 : 3, scans = 10;
  const double size_m = 0.16;
  IndexedMesh mesh = load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  normalize_on_pedestal(mesh, size_m, UpAxis::y);
  const embree::SimulatedScanner scanner(mesh);
  const Parameters params{};
  GroundTruth::Setting gts;
  gts.completeness_radius_m = params.completeness_radius_m;
  gts.seed = 1;  // as nbs_eval
  const GroundTruth truth(mesh, gts);
  tools::RobotOptions arm;
  arm.urdf = NBS_DATA_DIR "/robots/lwr4.urdf";
  const Aabb unknown = eval::unknown_area_of(mesh, size_m);
  eval::RunContext free_ctx{scanner, truth, params, presets::dlr_lsp(), unknown, scans};
  eval::RunContext robot_ctx = free_ctx;
  robot_ctx.robot = tools::load_robot(arm);
  const Method c_h = parse_method("C_H");
  double ca_free = 0.0, ca_robot = 0.0, joint = 0.0, sensor = 0.0, t_motion = 0.0;
  int transfers = 0;
  std::string robot_scans;
  for (int r = 0; r < runs; ++r) {
    const std::uint64_t seed = eval::run_seed(1, r);
    const eval::RunRecord f = eval::run_one(free_ctx, c_h, r, seed);
    const eval::RunRecord a = eval::run_one(robot_ctx, c_h, r, seed);
    ca_free += f.scans.back().c_a / runs;
    ca_robot += a.scans.back().c_a / runs;
    for (std::size_t i = 1; i < a.scans.size(); ++i, ++transfers) {
      joint += a.scans[i].transfer_joint_rad;
      sensor += a.scans[i].transfer_sensor_m;
      t_motion += a.scans[i].t_motion_s;
    }
    robot_scans += (r ? "," : "") + std::to_string(a.scans.size());
    std::printf("run %d seed %llu: free %zu scans c_a %.4f; lwr4 %zu scans (%s) c_a %.4f; unreachable per step:", r,
                static_cast<unsigned long long>(seed), f.scans.size(), f.scans.back().c_a, a.scans.size(),
                a.stop.c_str(), a.scans.back().c_a);
    for (std::size_t i = 1; i < a.scans.size(); ++i) std::printf(" %zu", a.scans[i].unreachable_candidates);
    std::printf("\n  transfers (rad / m / s):");
    for (std::size_t i = 1; i < a.scans.size(); ++i)
      std::printf(" %.2f/%.2f/%.3f", a.scans[i].transfer_joint_rad, a.scans[i].transfer_sensor_m,
                  a.scans[i].t_motion_s);
    std::printf("\n");
  }
  const double n = transfers > 0 ? static_cast<double>(transfers) : 1.0;
  char note[240];
  std::snprintf(note, sizeof note,
                "report: bunny C_H, %d run(s), c_a %.4f (lwr4, scans %s) / %.4f (free); mean transfer %.2f rad, "
                "%.2f m, %.3f s",
                runs, ca_robot, robot_scans.c_str(), ca_free, joint / n, sensor / n, t_motion / n);
  report_headline("motion.c_a_at_10_robot_vs_free", ca_free > 0.0 ? ca_robot / ca_free : 0.0, note);
}

}  // namespace nbs::bench
