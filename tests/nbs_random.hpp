// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Test helper: random vectors drawn in a fixed order. Several draws in one expression, as in
// Vec3(u(rng), u(rng), u(rng)), are indeterminately sequenced: gcc draws z first, clang x first, so one seed would
// give each compiler other data. These draw one value per statement, in the order of the components.
#include <Eigen/Geometry>

#include "nbs/core/types.hpp"

namespace nbs_test {

/// (d(rng), d(rng), d(rng)), drawn x, y, z.
template <class Dist, class Rng>
nbs::Vec3 random_vec3(Dist& d, Rng& rng) {
  const double x = d(rng);
  const double y = d(rng);
  const double z = d(rng);
  return {x, y, z};
}

/// (g(), g(), g()) for a generator g that takes no argument, drawn x, y, z.
template <class Gen>
nbs::Vec3 random_vec3(Gen&& g) {
  const double x = g();
  const double y = g();
  const double z = g();
  return {x, y, z};
}

/// The quaternion (w, x, y, z) = (d(rng), d(rng), d(rng), d(rng)), drawn w, x, y, z; not normalised.
template <class Dist, class Rng>
Eigen::Quaterniond random_quaternion(Dist& d, Rng& rng) {
  const double w = d(rng);
  const double x = d(rng);
  const double y = d(rng);
  const double z = d(rng);
  return {w, x, y, z};
}

}  // namespace nbs_test
