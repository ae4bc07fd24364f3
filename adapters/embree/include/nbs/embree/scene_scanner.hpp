// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Scanning a simulated table-top scene (nbs/scene/scene_generator.hpp) with Embree: the table and every object in
/// one SimulatedScanner, and overview frames of an area sensor with a ground-truth object label per point.

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "nbs/core/scan.hpp"
#include "nbs/core/viewpoint.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/scene/scene_generator.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/sim/mesh_distance.hpp"

namespace nbs::embree {

/// An area-sensor frame of a scene with ground-truth labels.
struct OverviewFrame {
  Scan scan;                ///< world-frame points, one profile pose (the viewpoint).
  std::vector<int> labels;  ///< per point: index of the nearest placed object's mesh, −1 if the table is nearer.
};

/// Owns the Embree scene of `scene.combined_mesh()` and the ground-truth meshes. The pedestal of the scanner is
/// 1 mm below the table top (z = table_height_m − 0.001), so hits on the table are kept whatever their rounding
/// and nothing below the table is seen. Const members are thread-safe.
class SceneScanner {
public:
  explicit SceneScanner(const scene::SimulatedScene& scene, RayMode ray_mode = RayMode::packet)
      : scanner_(scene.combined_mesh().mesh,
                 ScannerSettings{.pedestal_top_z_m = scene.settings.table_height_m - 0.001, .ray_mode = ray_mode}) {
    truth_.emplace_back(scene.table_mesh());
    for (const auto& o : scene.objects) truth_.emplace_back(o.mesh);
  }

  [[nodiscard]] const SimulatedScanner& scanner() const { return scanner_; }

  /// One area-sensor frame from `view` (SimulatedScanner::scan), seeded noise. Throws InvalidArgument for an
  /// invalid sensor.
  [[nodiscard]] Scan scan(const Viewpoint& view, const AreaSensor& sensor, std::uint64_t seed) const {
    return scanner_.scan(view, sensor, seed);
  }

  /// Ground-truth label of each point: the object whose placed mesh is nearest (exact point-to-triangle distance;
  /// ties go to the lower index), −1 when the table is nearer. `threads` as MeshDistance::distances.
  [[nodiscard]] std::vector<int> labels(std::span<const Vec3> points, unsigned threads = 0) const {
    std::vector<int> out(points.size(), -1);
    std::vector<double> best = truth_[0].distances(points, threads);
    for (std::size_t k = 1; k < truth_.size(); ++k) {
      const std::vector<double> d = truth_[k].distances(points, threads);
      for (std::size_t i = 0; i < points.size(); ++i)
        if (d[i] < best[i]) best[i] = d[i], out[i] = static_cast<int>(k - 1);
    }
    return out;
  }

  /// scan() and labels() of its points.
  [[nodiscard]] OverviewFrame overview(const Viewpoint& view, const AreaSensor& sensor, std::uint64_t seed,
                                       unsigned threads = 0) const {
    OverviewFrame f{scan(view, sensor, seed), {}};
    f.labels = labels(f.scan.points, threads);
    return f;
  }

private:
  SimulatedScanner scanner_;
  std::vector<MeshDistance> truth_;  ///< [0] the table, [k + 1] object k.
};

}  // namespace nbs::embree
