// SPDX-License-Identifier: BSD-3-Clause
// Simulated scanner throughput on LSP scans of the bunny (0.16 m) against plain Embree in the same run:
//   sim.scanner_vs_raw_embree    — SimulatedScanner::scan rays/s ÷ a raw rtcIntersect1 loop over the same rays
//   sim.profile_vs_rtcintersect1 — Scene::cast_fan (packets, one profile at a time) ÷ the same rtcIntersect1 loop
#include <benchmark/benchmark.h>

#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "headline.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sensor/presets.hpp"

namespace {

struct Fixture {
  nbs::embree::SimulatedScanner scanner;
  nbs::LaserStripeProfiler sensor = nbs::presets::dlr_lsp();
  std::vector<nbs::LinearScanPath> paths;
  std::vector<nbs::Vec3> origins;            // one per profile
  std::vector<std::vector<nbs::Vec3>> dirs;  // world directions per profile
  std::size_t rays = 0;

  static nbs::IndexedMesh bunny() {
    nbs::IndexedMesh m = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
    nbs::normalize_on_pedestal(m, 0.16, nbs::UpAxis::y);
    return m;
  }

  Fixture() : scanner(bunny()) {
    // Six vertical 0.16 m paths around the bunny at 0.3 m from its axis, looking at its centre (0, 0, 0.08).
    for (int k = 0; k < 6; ++k) {
      const double a = 2.0 * std::numbers::pi * k / 6.0;
      const nbs::Vec3 pos(0.3 * std::cos(a), 0.3 * std::sin(a), 0.0);
      const auto v = nbs::Viewpoint::look_at(pos, {0, 0, 0.0}, nbs::Vec3::UnitZ());
      // Sensor y = z × x is vertical for this look_at; start at the bottom and move 0.16 m along s_y.
      const nbs::Vec3 step = 0.16 * v.y_axis() * (v.y_axis().z() > 0 ? 1.0 : -1.0);
      const nbs::Pose start = [&] {
        nbs::Pose p = v.pose();
        p.translation().z() = 0.0;
        return p;
      }();
      paths.emplace_back(nbs::Viewpoint(start), start.translation() + step);
    }
    for (const auto& path : paths)
      for (const nbs::Pose& pose : sensor.profile_poses(path)) {
        origins.push_back(pose.translation());
        dirs.push_back(sensor.profile_directions(pose));
        rays += dirs.back().size();
      }
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void set_rate(benchmark::State& state, std::size_t rays_per_iteration) {
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(rays_per_iteration),
                                                    benchmark::Counter::kIsIterationInvariantRate);
}

void BM_SimulatedScanner(benchmark::State& state) {
  auto& f = fixture();
  std::size_t points = 0;
  for (auto _ : state) {
    for (const auto& path : f.paths) points += f.scanner.scan(path, f.sensor, 7).size();
    benchmark::DoNotOptimize(points);
  }
  set_rate(state, f.rays);
}

void BM_ProfilePackets(benchmark::State& state) {
  auto& f = fixture();
  std::vector<float> out(static_cast<std::size_t>(f.sensor.points_per_profile));
  for (auto _ : state) {
    for (std::size_t k = 0; k < f.dirs.size(); ++k)
      f.scanner.scene().cast_fan(f.origins[k], f.dirs[k], f.sensor.range.max_m, out, nbs::embree::RayMode::packet);
    benchmark::DoNotOptimize(out.data());
  }
  set_rate(state, f.rays);
}

void BM_RawRtcIntersect1(benchmark::State& state) {
  auto& f = fixture();
  const RTCScene scene = f.scanner.scene().handle();
  std::vector<float> out(static_cast<std::size_t>(f.sensor.points_per_profile));
  const float far = static_cast<float>(f.sensor.range.max_m);
  for (auto _ : state) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::size_t k = 0; k < f.dirs.size(); ++k) {
      const nbs::Vec3& o = f.origins[k];
      for (std::size_t i = 0; i < f.dirs[k].size(); ++i) {
        const nbs::Vec3& d = f.dirs[k][i];
        RTCRayHit rh{};
        rh.ray.org_x = static_cast<float>(o.x());
        rh.ray.org_y = static_cast<float>(o.y());
        rh.ray.org_z = static_cast<float>(o.z());
        rh.ray.dir_x = static_cast<float>(d.x());
        rh.ray.dir_y = static_cast<float>(d.y());
        rh.ray.dir_z = static_cast<float>(d.z());
        rh.ray.tfar = far;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        out[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1.0f : rh.ray.tfar;
      }
      benchmark::DoNotOptimize(out.data());
    }
  }
  set_rate(state, f.rays);
}

BENCHMARK(BM_SimulatedScanner)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ProfilePackets)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RawRtcIntersect1)->Unit(benchmark::kMillisecond);

/// Console output plus the best rays/s of each benchmark.
class RateCapture : public benchmark::ConsoleReporter {
public:
  std::map<std::string, double> best;
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& r : runs) {
      const auto it = r.counters.find("rays_per_s");
      if (it == r.counters.end() || r.run_type != Run::RT_Iteration) continue;
      double& b = best[r.run_name.function_name];
      b = std::max(b, static_cast<double>(it->second));
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RateCapture rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  const double raw = rep.best["BM_RawRtcIntersect1"];
  if (raw > 0) {
    const auto& f = fixture();
    const std::string note = std::to_string(f.rays) + " LSP rays on the bunny, packet width " +
                             std::to_string(f.scanner.scene().packet_width());
    nbs::bench::report_headline("sim.scanner_vs_raw_embree", rep.best["BM_SimulatedScanner"] / raw, note);
    nbs::bench::report_headline("sim.profile_vs_rtcintersect1", rep.best["BM_ProfilePackets"] / raw, note);
  }
  benchmark::Shutdown();
  return 0;
}
