// SPDX-License-Identifier: BSD-3-Clause
// Must NOT compile: a type that is not a UtilityPolicy given to NbsPlanner. The CTest `planner_compile_fail`
// builds this file and passes only if the compiler rejects it naming the concept (docs/architecture.md shows the
// message).
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/sensor/presets.hpp"

struct NotAUtility {};  // no evaluate(paths, sensor, space, ctx, eval)

int main() {
  nbs::NbsPlanner<NotAUtility> planner({}, nbs::presets::dlr_lsp(), nbs::Aabb{nbs::Vec3::Zero(), nbs::Vec3::Ones()});
  return planner.scans();
}
