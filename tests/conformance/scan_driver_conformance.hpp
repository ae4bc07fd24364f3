// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::ScanDriver (include/nbs/driver/concepts.hpp). `make()` returns a fresh driver, in the
// same state every call; `paths` are paths it can serve in this order (a replay: the recorded ones). Checked:
//  - the home pose is finite and rigid; move_to(T) then current_pose() is T within `pose_tol_m` (matrix max-norm);
//  - move_to of a non-finite, a scaled (non-rigid) and a reflected pose throws InvalidArgument naming the pose and
//    leaves current_pose() as it was;
//  - acquire along each path (after move_to its start) returns a Scan that passes validate(); afterwards
//    current_pose() is path.pose_at(1) within `pose_tol_m`;
//  - a second fresh driver returns the identical scans for the same calls (replays and seeded simulations are
//    deterministic).
#include "nbs_catch.hpp"

#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "nbs/driver/concepts.hpp"
#include "scan_simulator_conformance.hpp"  // detail::same_scan

namespace nbs::conformance {

struct DriverCase {
  std::vector<LinearScanPath> paths;  ///< at least one
  double pose_tol_m = 1e-12;          ///< accuracy of move_to and of the rest pose after a scan
};

namespace detail {
inline double pose_diff(const Pose& a, const Pose& b) { return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff(); }
}  // namespace detail

template <class Make>
void check_scan_driver_conformance(Make make, const DriverCase& c) {
  using D = std::remove_cvref_t<decltype(make())>;
  static_assert(ScanDriver<D>);
  REQUIRE(!c.paths.empty());
  {
    auto d = make();
    const Pose home = d.current_pose();
    CHECK(pose_problem(home).empty());
    const Pose target = c.paths.front().pose_at(0.5);
    d.move_to(target);
    CHECK(detail::pose_diff(d.current_pose(), target) <= c.pose_tol_m);
    const Pose before = d.current_pose();
    Pose nan = target, scaled = target, mirrored = target;
    nan.translation().x() = std::numeric_limits<double>::quiet_NaN();
    scaled.linear() *= 1.01;
    mirrored.linear().col(0) *= -1.0;
    for (const Pose& bad : {nan, scaled, mirrored}) {
      try {
        d.move_to(bad);
        FAIL("move_to accepted a bad pose");
      } catch (const InvalidArgument& e) {
        CHECK(std::string(e.what()).find("pose") != std::string::npos);
      }
      CHECK(detail::pose_diff(d.current_pose(), before) == 0.0);
    }
  }
  auto a = make();
  auto b = make();
  for (std::size_t k = 0; k < c.paths.size(); ++k) {
    INFO("path " << k);
    const LinearScanPath& path = c.paths[k];
    a.move_to(path.start().pose());
    CHECK(detail::pose_diff(a.current_pose(), path.start().pose()) <= c.pose_tol_m);
    const Scan scan = a.acquire(path);
    REQUIRE_NOTHROW(scan.validate());
    CHECK(detail::pose_diff(a.current_pose(), path.pose_at(1.0)) <= c.pose_tol_m);
    b.move_to(path.start().pose());
    CHECK(detail::same_scan(b.acquire(path), scan));
  }
}

}  // namespace nbs::conformance
