// SPDX-License-Identifier: BSD-3-Clause
// The streaming mesh on a real simulated stream: the bundled bunny scanned by the Embree scanner with the thesis LSP
// noise (Eq. 4.39). Noise of about twice R_r used to make the gap closing fill the three-edge "loop" around the back
// of a lone triangle, giving a two-face pillow (15 duplicate faces after the first scan, 43 after six).
#include "nbs_catch.hpp"

#include <numbers>

#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/invariants.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/mesh/streaming_mesh.hpp"
#include "nbs/sensor/presets.hpp"

using nbs::Vec3;

TEST_CASE("bunny stream: the streaming mesh keeps its invariants after every scan", "[mesh][embree]") {
  nbs::IndexedMesh object = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  nbs::normalize_on_pedestal(object, 0.16, nbs::UpAxis::y);
  const nbs::embree::SimulatedScanner scanner(object);
  const nbs::LaserStripeProfiler lsp = nbs::presets::dlr_lsp();
  nbs::StreamingMesh mesh;
  for (int k = 0; k < 2; ++k) {  // two vertical 160 mm scans from 0.3 m, 60° apart around the bunny's axis
    const double a = std::numbers::pi * k / 3.0;
    const auto v = nbs::Viewpoint::look_at({0.3 * std::cos(a), 0.3 * std::sin(a), 0.0}, {0, 0, 0}, Vec3::UnitZ());
    nbs::Pose start = v.pose();
    start.translation().z() = 0.0;
    const Vec3 step = 0.16 * v.y_axis() * (v.y_axis().z() > 0 ? 1.0 : -1.0);
    mesh.integrate(scanner.scan(nbs::LinearScanPath(nbs::Viewpoint(start), start.translation() + step), lsp,
                                static_cast<std::uint64_t>(k + 1)));
    const auto rep = nbs::check_invariants(mesh, mesh.settings().reduction_radius_m);
    INFO("scan " << k + 1 << ": " << rep.problems);
    CHECK(mesh.face_count() > 10000);
    REQUIRE(rep.ok());
  }
}
