// SPDX-License-Identifier: BSD-3-Clause
// Uses the installed headers: fails to compile or link if the package is broken.
#include <cstdio>

#include "nbs/core.hpp"

int main() {
  nbs::Parameters p;
  p.validate();
  const auto v = nbs::Viewpoint::look_at(nbs::Vec3(0.3, 0, 0.1), nbs::Vec3::Zero());
  std::printf("nbs downstream OK: voxel %.3f m, view dir (%.2f %.2f %.2f)\n", p.voxel_size_m,
              v.view_direction().x(), v.view_direction().y(), v.view_direction().z());
  return 0;
}
