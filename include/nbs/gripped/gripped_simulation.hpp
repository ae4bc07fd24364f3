// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Simulating a gripped object (Sec. 5.4): the scene the simulated sensor sees (object + fingers, in O) and c_a split
/// into the finger region and the rest. Frames as gripped/gripped_object.hpp.

#include <cstddef>
#include <vector>

#include "nbs/gripped/gripped_object.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/robot/shape_mesh.hpp"
#include "nbs/sim/completeness.hpp"

namespace nbs {

/// The ground-truth scene in O: `object` (in O, metres) with the finger shapes appended as triangles (shapes_mesh;
/// per-vertex normals dropped; an object's vertex colours kept, the fingers' vertices grey 128). Throws InvalidArgument (require_object_in_tool_box: the sizes named) if the object
/// does not fit into the tool box, or if the set-up or mesh is invalid.
[[nodiscard]] inline IndexedMesh gripped_scene_mesh(const GrippedSetup& setup, const IndexedMesh& object) {
  object.validate();
  require_object_in_tool_box(setup, object.bounds());
  IndexedMesh out = object;
  out.normals.clear();
  for (const PlacedShape& f : setup.fingers) append_shape_mesh(out, f);
  if (!out.colors.empty()) out.colors.resize(out.vertices.size(), Rgb{128, 128, 128});
  return out;
}

/// c_a in two parts: the samples within `region_m` of a finger (the finger-occluded region: touched or shadowed by
/// the fingers, at most partly reachable by the sensor) and the rest. Bottom samples count in neither c_a, as in
/// count_completeness.
struct FingerRegionCompleteness {
  Completeness finger;  ///< samples with finger_distance ≤ region_m
  Completeness rest;    ///< the others
};

/// Splits `covered` (per sample of `samples`, e.g. CoverageTracker::covered()) by finger_distance ≤ region_m. Throws
/// InvalidArgument if the sizes differ or region_m is not finite and ≥ 0.
[[nodiscard]] inline FingerRegionCompleteness finger_region_completeness(const SurfaceSamples& samples,
                                                                         const std::vector<bool>& covered,
                                                                         const std::vector<PlacedShape>& fingers,
                                                                         double region_m) {
  detail::require(covered.size() == samples.size(), "finger_region_completeness: ", covered.size(),
                  " coverage flags for ", samples.size(), " samples");
  detail::require_non_negative("finger_region_completeness region_m", region_m);
  FingerRegionCompleteness out;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    Completeness& c = finger_distance(fingers, samples.points[i]) <= region_m ? out.finger : out.rest;
    const bool bottom = samples.bottom[i];
    ++c.samples;
    c.non_bottom += bottom ? 0 : 1;
    if (covered[i]) {
      ++c.covered;
      c.covered_non_bottom += bottom ? 0 : 1;
    }
  }
  return out;
}

}  // namespace nbs
