// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The tests' analytic scanner: nbs::SphereOnPedestal and nbs::scan_analytic (nbs/sim/sphere_on_pedestal.hpp) under
// their old names, and the tests' fixed unknown area and lighter sensor.

#include "nbs/sensor/presets.hpp"
#include "nbs/sim/sphere_on_pedestal.hpp"

namespace nbs::test {

using nbs::scan_analytic;
using nbs::SphereOnPedestal;

/// The bounding box of the unknown area around SphereOnPedestal: pedestal plane z = 0 up to above the top.
inline Aabb sphere_box() { return {Vec3(-0.06, -0.06, 0.0), Vec3(0.06, 0.06, 0.10)}; }

/// A lighter LSP (fewer rays, 2 mm profile spacing) so that loop tests stay fast; geometry as the DLR LSP.
inline LaserStripeProfiler light_lsp(int points_per_profile = 200) {
  LaserStripeProfiler s = presets::dlr_lsp();
  s.points_per_profile = points_per_profile;
  s.profile_spacing_m = 0.002;
  return s;
}

}  // namespace nbs::test
