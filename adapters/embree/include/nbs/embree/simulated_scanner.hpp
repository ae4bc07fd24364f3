// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Simulated range scanning of a ground-truth mesh with Embree (Sec. 4.7): ray casting, working range, seeded
/// Gaussian noise along each ray (Eq. 4.39 for the thesis sensor).

#include <cstdint>
#include <numbers>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "nbs/core/scan.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/embree/scene.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/sensor/counter_gaussian.hpp"
#include "nbs/sensor/laser_stripe_profiler.hpp"
#include "nbs/sim/observability.hpp"
#include "nbs/sim/surface_color.hpp"

namespace nbs::embree {

/// Settings of SimulatedScanner.
struct ScannerSettings {
  /// z of the pedestal top (world frame, metres); std::nullopt: no pedestal (everything is scannable).
  std::optional<double> pedestal_top_z_m = 0.0;
  /// Ray tracing path for each profile / frame (the packet path is faster; `single` exists for benchmarks).
  RayMode ray_mode = RayMode::packet;
};

/// Simulates a laser stripe profiler moving along a linear scan path, or an area sensor at a viewpoint (or at the
/// start of a linear scan path), in front of a mesh. Owns its Scene. `scan` is const and thread-safe.
///
/// Measurement model, per ray with unit direction r from the sensor origin o:
/// - the first surface hit at true distance d (any distance, so nearer surfaces occlude) is measured only if
///   `range.min_m ≤ d ≤ range.max_m`;
/// - the pedestal (no geometry, the half-space z < pedestal_top_z_m) blocks the view: no point is produced
///   when the origin is below its top or the hit lies below it, so the object's bottom is not scannable;
/// - the point is o + (d + σ(d)·ε) r with ε ~ N(0, 1) drawn from CounterGaussian(seed) at (profile, ray index):
///   the same seed gives an identical scan, whatever the thread count. The noisy point may lie slightly
///   outside the working range;
/// - colour (Sec. 5.3): if the mesh has vertex colours (IndexedMesh::colors, e.g. read from PLY or
///   `procedural_colors`), every point gets the colour of the true hit point (surface_color: barycentric
///   interpolation on the hit triangle, found by a second, single ray per hit), noise-free; else the scan has no
///   colours. A scanner built from a Scene has no colours.
class SimulatedScanner {
public:
  using Settings = ScannerSettings;

  /// Largest incidence angle (between a ray and the surface normal, rad) at which a hit is measured: π/2, i.e. every
  /// hit in the working range is measured, however grazing (Sec. 4.7 names no limit; the planner's 70° of Tab. 4.3
  /// is its quality rule). Observability ceilings of scans by this scanner use it (nbs_eval's c_obs does).
  static constexpr double max_incidence_rad = std::numbers::pi / 2.0;

  /// The observability ceiling's settings (GroundTruth::observability, c_obs) for scans by this scanner with
  /// `sensor`: the sensor's working range and max_incidence_rad, `directions` per sample, `threads` workers (0:
  /// hardware concurrency); the sensor above z = 0, the default pedestal's top. Throws InvalidArgument for an invalid
  /// sensor.
  [[nodiscard]] static ObservabilitySettings observability_settings(const LaserStripeProfiler& sensor,
                                                                    int directions = 1000, unsigned threads = 0) {
    sensor.validate();
    ObservabilitySettings os;
    os.min_range_m = sensor.range.min_m;
    os.max_range_m = sensor.range.max_m;
    os.incidence_cutoff_rad = max_incidence_rad;
    os.directions = directions;
    os.threads = threads;
    os.validate();
    return os;
  }

  /// Builds the Embree scene of `mesh` (see Scene).
  explicit SimulatedScanner(const IndexedMesh& mesh, Settings settings = {})
      : SimulatedScanner(Scene(mesh), settings) {
    if (!mesh.colors.empty()) colored_ = mesh;
  }
  explicit SimulatedScanner(Scene scene, Settings settings = {}) : scene_(std::move(scene)), settings_(settings) {
    if (settings_.pedestal_top_z_m)
      nbs::detail::require(std::isfinite(*settings_.pedestal_top_z_m),
                           "SimulatedScanner.pedestal_top_z_m must be finite, got ", *settings_.pedestal_top_z_m);
  }

  /// One linear scan: a profile every ≤ profile_spacing_m from path start to end (LaserStripeProfiler::
  /// profile_poses). Throws InvalidArgument for an invalid sensor.
  [[nodiscard]] Scan scan(const LinearScanPath& path, const LaserStripeProfiler& sensor, std::uint64_t seed) const {
    sensor.validate();
    Scan out;
    out.profile_poses = sensor.profile_poses(path);
    std::vector<Vec3> local(static_cast<std::size_t>(sensor.points_per_profile));
    for (int i = 0; i < sensor.points_per_profile; ++i)
      local[static_cast<std::size_t>(i)] = sensor.ray_direction_sensor(i);
    Buffers buf(local.size());
    const CounterGaussian gauss(seed);
    for (std::size_t k = 0; k < out.profile_poses.size(); ++k)
      measure(out.profile_poses[k], local, sensor.range, sensor.noise, gauss, static_cast<std::uint32_t>(k), buf,
              out);
    return out;
  }

  /// One range image of an area sensor executing a scan path, so that the scanner models
  /// `nbs::ScanSimulator<SimulatedScanner, AreaSensor>` and `run_simulation` closes the loop with an area sensor:
  /// the image is taken at `path.start()`; the rest of a path of non-zero length (the 13 initial paths, Sec. 4.7.2)
  /// is ignored — one frame per scan, the viewpoint at which the utility evaluates a moving area sensor too
  /// (`append_candidate_rays`). Same result as `scan(path.start(), sensor, seed)`.
  [[nodiscard]] Scan scan(const LinearScanPath& path, const AreaSensor& sensor, std::uint64_t seed) const {
    return scan(path.start(), sensor, seed);
  }

  /// One range image from `view`. Throws InvalidArgument for an invalid sensor.
  [[nodiscard]] Scan scan(const Viewpoint& view, const AreaSensor& sensor, std::uint64_t seed) const {
    sensor.validate();
    std::vector<Vec3> local;
    local.reserve(sensor.ray_count());
    for (int v = 0; v < sensor.height_px; ++v)
      for (int u = 0; u < sensor.width_px; ++u) local.push_back(sensor.ray_direction_sensor(u, v));
    Scan out;
    out.profile_poses.push_back(view.pose());
    Buffers buf(local.size());
    measure(view.pose(), local, sensor.range, sensor.noise, CounterGaussian(seed), 0, buf, out);
    return out;
  }

  [[nodiscard]] const Scene& scene() const { return scene_; }
  /// True if the scans carry colours (the mesh had vertex colours).
  [[nodiscard]] bool has_colors() const { return !colored_.colors.empty(); }
  [[nodiscard]] const Settings& settings() const { return settings_; }

private:
  struct Buffers {
    explicit Buffers(std::size_t n) : world(n), distance(n) {}
    std::vector<Vec3> world;
    std::vector<float> distance;
  };

  /// Casts the rays of one profile/frame (sensor-frame directions `local`) from `pose` and appends the points.
  void measure(const Pose& pose, std::span<const Vec3> local, const WorkingRange& range, const RangeNoise& noise,
               const CounterGaussian& gauss, std::uint32_t profile, Buffers& buf, Scan& out) const {
    const Mat3 r = pose.linear();
    const Vec3 o = pose.translation();
    for (std::size_t i = 0; i < local.size(); ++i) buf.world[i] = r * local[i];
    out.rays_cast += local.size();
    const std::optional<double>& pz = settings_.pedestal_top_z_m;
    if (pz && o.z() < *pz) return;  // looking out of the pedestal: blocked
    scene_.cast_fan(o, buf.world, range.max_m, buf.distance, settings_.ray_mode);
    for (std::size_t i = 0; i < local.size(); ++i) {
      const double d = buf.distance[i];
      if (!range.contains(d)) continue;  // also drops misses (+inf)
      const Vec3& dir = buf.world[i];
      if (pz && o.z() + d * dir.z() < *pz) continue;
      const double measured = noise.is_zero() ? d : d + noise.sigma_m(d) * gauss(profile, i);
      if (!has_colors()) {
        out.add_point(o + measured * dir, profile);
        continue;
      }
      const std::optional<RayHit> hit = scene_.first_hit(o, dir);  // the hit triangle (cast_fan gives distances)
      out.add_point(o + measured * dir, profile,
                    hit ? surface_color(colored_, hit->triangle, o + hit->distance * dir) : Rgb{0, 0, 0});
    }
  }

  Scene scene_;
  Settings settings_;
  IndexedMesh colored_;  ///< the mesh with its vertex colours; empty without colour
};

}  // namespace nbs::embree
