// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The gripped bunny of docs/evaluation.md "Gripped object" (Sec. 5.4), shared by tests/embree/test_gripped_run.cpp
// and the LWR measurement in tests/kdl/test_kdl_gripped.cpp: the Stanford bunny normalized to 100 mm on the palm
// plane z = 0 of O, two box fingers, the tool box around it.

#include <algorithm>
#include <cmath>
#include <limits>

#include "nbs/gripped/gripped_object.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"

namespace nbs_test {

using nbs::Vec3;

struct GrippedBunny {
  nbs::IndexedMesh object;
  nbs::GrippedSetup setup;
  GrippedBunny() : object(nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj")) {
    nbs::normalize_on_pedestal(object, 0.10, nbs::UpAxis::y);  // resting on the palm plane z = 0 of O
    const nbs::Aabb b = object.bounds();
    // Two 10 × 20 × 40 mm fingers pinching the object from ±x at grip height 35 mm, each pressed 2 mm into the
    // surface: the extreme x of the vertices in the grip slab.
    const double cy = b.center().y(), gz = 0.035;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Vec3& v : object.vertices)
      if (std::abs(v.y() - cy) < 0.01 && std::abs(v.z() - gz) < 0.02) {
        lo = std::min(lo, v.x());
        hi = std::max(hi, v.x());
      }
    const Vec3 size(0.01, 0.02, 0.04);
    for (const double x : {lo + 0.002 - 0.005, hi - 0.002 + 0.005}) {
      nbs::PlacedShape f;
      f.link = x < b.center().x() ? "finger -x" : "finger +x";
      f.shape.size = size;
      f.T_WG.translation() = Vec3(x, cy, gz);
      setup.fingers.push_back(f);
    }
    setup.tool_box = {Vec3(b.min.x() - 0.01, b.min.y() - 0.01, 0.0), b.max + Vec3::Constant(0.01)};
    setup.T_BS.translation() = Vec3(0.6, 0.0, 0.8);  // any fixed sensor pose; the planner never sees it
    setup.finger_margin_m = 0.002;
  }
};

}  // namespace nbs_test
