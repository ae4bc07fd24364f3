// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The KDL tests' shared fixture: the bundled LWR 4 URDF (data/robots/lwr4.urdf) and a joint-vector literal.

#include <filesystem>
#include <initializer_list>

#include "nbs/kdl/urdf_robot.hpp"

namespace nbs_test {

inline const std::filesystem::path kLwrUrdf = std::filesystem::path(NBS_DATA_DIR) / "robots" / "lwr4.urdf";

/// The LWR from world to the sensor frame (base link "world", flange "lwr_flange", sensor "sensor").
inline nbs::kdl::UrdfRobot lwr() { return nbs::kdl::UrdfRobot::load(kLwrUrdf, "world", "lwr_flange", "sensor"); }

/// q = (v0, v1, …) as a JointVector.
inline nbs::JointVector joints(std::initializer_list<double> v) {
  nbs::JointVector q(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v) q[i++] = x;
  return q;
}

}  // namespace nbs_test
