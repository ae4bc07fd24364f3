// nbs_model — the main job. Until the NBS planner exists it scans the ground-truth object from the 13 initial scan
// paths of Sec. 4.7.2 with the simulated DLR laser stripe profiler and reports the ground-truth metrics of the
// merged point cloud (c_a, c_b, c_obs, ē, l_s; Sec. 4.7.2, Tab. 5.2). Run `nbs_model --help`.

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/core/parameters.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/io/write_ply.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/metrics.hpp"

namespace {

constexpr const char* kUsage =
    "usage: nbs_model [--mesh PATH] [--up x|y|z] [--size M] [--seed N] [--out DIR]\n"
    "  --mesh PATH  ground-truth mesh, OBJ or PLY (default: the bundled Stanford bunny)\n"
    "  --up AXIS    axis of the mesh file that points up (default y, as in the bunny OBJ)\n"
    "  --size M     largest extent of the object after normalisation, metres, > 0 (default 0.16)\n"
    "  --seed N     seed of sensor noise and ground-truth samples, unsigned integer (default 1)\n"
    "  --out DIR    output directory, created if missing (default out)\n"
    "Scans the object, standing on a pedestal at z = 0, along the 13 initial scan paths of Sec. 4.7.2 with the\n"
    "simulated DLR laser stripe profiler; writes DIR/points.ply and prints one line per scan and the metrics.\n";

struct Options {
  std::string mesh = std::string(NBS_DATA_DIR) + "/meshes/stanford-bunny.obj";
  nbs::UpAxis up = nbs::UpAxis::y;
  double size_m = nbs::Parameters{}.object_size_m;
  std::uint64_t seed = 1;
  std::string out = "out";
};

struct UsageError {
  std::string message;
};

double parse_double(std::string_view name, const std::string& s) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != s.size() || !(v > 0.0) || !std::isfinite(v))
    throw UsageError{std::string(name) + " expects a finite number > 0, got '" + s + "'"};
  return v;
}

std::uint64_t parse_seed(const std::string& s) {
  std::size_t used = 0;
  unsigned long long v = 0;
  try {
    if (!s.empty() && s[0] != '-' && s[0] != '+') v = std::stoull(s, &used, 10);
  } catch (const std::exception&) {
    used = 0;
  }
  if (s.empty() || used != s.size()) throw UsageError{"--seed expects an unsigned integer, got '" + s + "'"};
  return v;
}

/// Returns std::nullopt when --help was given.
std::optional<Options> parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") return std::nullopt;
    if (arg.rfind("--", 0) != 0) throw UsageError{"unexpected argument '" + arg + "'"};
    if (i + 1 >= argc || std::string_view(argv[i + 1]).rfind("--", 0) == 0)
      throw UsageError{"option '" + arg + "' expects a value"};
    const std::string value = argv[++i];
    if (arg == "--mesh") {
      o.mesh = value;
    } else if (arg == "--up") {
      if (value == "x") o.up = nbs::UpAxis::x;
      else if (value == "y") o.up = nbs::UpAxis::y;
      else if (value == "z") o.up = nbs::UpAxis::z;
      else throw UsageError{"--up expects x, y or z, got '" + value + "'"};
    } else if (arg == "--size") {
      o.size_m = parse_double("--size", value);
    } else if (arg == "--seed") {
      o.seed = parse_seed(value);
    } else if (arg == "--out") {
      if (value.empty()) throw UsageError{"--out expects a directory"};
      o.out = value;
    } else {
      throw UsageError{"unknown option '" + arg + "'"};
    }
  }
  return o;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int run(const Options& opt) {
  using namespace nbs;
  const auto t_start = std::chrono::steady_clock::now();
  IndexedMesh mesh;
  try {
    mesh = load_mesh(opt.mesh);
    normalize_on_pedestal(mesh, opt.size_m, opt.up);
  } catch (const Error& e) {  // a bad --mesh is a usage error
    std::cerr << "nbs_model: " << e.what() << "\n";
    return 2;
  }
  const Parameters params;
  const LaserStripeProfiler lsp = presets::dlr_lsp();
  const double standoff_m = 0.5 * (lsp.range.min_m + lsp.range.max_m);
  GroundTruth::Setting gts;
  gts.seed = opt.seed;
  gts.completeness_radius_m = params.completeness_radius_m;
  const GroundTruth truth(mesh, gts);
  const embree::SimulatedScanner scanner(mesh);
  const Aabb box = mesh.bounds();
  std::printf("object  %s: %zu vertices, %zu triangles, box %.3f x %.3f x %.3f m on the pedestal z = 0\n",
              opt.mesh.c_str(), mesh.vertices.size(), mesh.triangles.size(), box.extent().x(), box.extent().y(),
              box.extent().z());
  std::printf("truth   %zu surface samples (%zu not bottom), r = %.1f mm; sensor DLR LSP %d pts/profile, "
              "%.0f-%.0f mm, standoff %.0f mm\n",
              truth.samples().size(), truth.samples().non_bottom_count(), 1e3 * gts.completeness_radius_m,
              lsp.points_per_profile, 1e3 * lsp.range.min_m, 1e3 * lsp.range.max_m, 1e3 * standoff_m);

  const std::vector<LinearScanPath> paths = initial_scan_paths(box, standoff_m);
  CoverageTracker coverage = truth.tracker();
  std::vector<Vec3> cloud;
  const auto t_scan = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const Scan scan = scanner.scan(paths[i], lsp, detail::splitmix64(opt.seed ^ (0x5CA9ULL + i)));
    coverage.add(scan.points);
    cloud.insert(cloud.end(), scan.points.begin(), scan.points.end());
    std::printf("scan %2zu  path %2zu  length %.3f m  points %7zu  c_a %6.2f %%\n", i + 1, i, paths[i].length(),
                scan.size(), 100.0 * coverage.completeness().c_a());
  }
  const double scan_s = seconds_since(t_scan);

  std::filesystem::create_directories(opt.out);
  const std::string ply = (std::filesystem::path(opt.out) / "points.ply").string();
  write_ply_points(ply, cloud);

  const auto t_obs = std::chrono::steady_clock::now();
  ObservabilitySettings os;
  os.min_range_m = lsp.range.min_m;
  os.max_range_m = lsp.range.max_m;
  os.incidence_cutoff_rad = params.incidence_cutoff_rad;
  const Observability obs = truth.observability(scanner.scene(), os);
  const double obs_s = seconds_since(t_obs);
  const auto t_err = std::chrono::steady_clock::now();
  const double rms = cloud.empty() ? 0.0 : truth.rms_error(cloud);
  const double err_s = seconds_since(t_err);

  const Completeness c = coverage.completeness();
  std::printf("points  %zu written to %s\n", cloud.size(), ply.c_str());
  std::printf("c_a     %6.2f %%  (non-bottom samples within %.1f mm of a point)\n", 100.0 * c.c_a(),
              1e3 * gts.completeness_radius_m);
  std::printf("c_b     %6.2f %%  (all samples, bottom included)\n", 100.0 * c.c_b());
  std::printf("c_obs   %6.2f %%  (observability ceiling: range %.2f-%.2f m, incidence <= %.0f deg, above z = 0)\n",
              100.0 * obs.c_obs(), os.min_range_m, os.max_range_m, os.incidence_cutoff_rad * 180.0 / 3.141592653589793);
  std::printf("c_a/c_obs %4.2f %%\n", obs.c_obs() > 0 ? 100.0 * c.c_a() / obs.c_obs() : 0.0);
  std::printf("e_rms   %.3f mm  (RMS distance of the points to the true surface)\n", 1e3 * rms);
  std::printf("l_s     %.3f m  (13 scan paths; travel between paths %.3f m, not included)\n",
              scan_path_length(paths), travel_length(paths));
  std::printf("time    %.1f s total (scanning %.1f s, c_obs %.1f s, e_rms %.1f s)\n", seconds_since(t_start), scan_s,
              obs_s, err_s);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::optional<Options> opt;
  try {
    opt = parse(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << "nbs_model: " << e.message << "\n" << kUsage;
    return 2;
  }
  if (!opt) {
    std::cout << kUsage;
    return 0;
  }
  try {
    return run(*opt);
  } catch (const std::exception& e) {
    std::cerr << "nbs_model: error: " << e.what() << "\n";
    return 1;
  }
}
