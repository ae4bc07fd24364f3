// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The planner and loop settings the planner tests share: a PlannerSetting with a thread count, a SimulationSetting
// with a seed and n_abort (everything else default).
#include <cstdint>

#include "nbs/planner/planner_types.hpp"
#include "nbs/planner/simulation_loop.hpp"

namespace nbs::test {

inline PlannerSetting setting(unsigned threads) {
  PlannerSetting s;
  s.threads = threads;
  return s;
}

inline SimulationSetting loop_setting(std::uint64_t seed, int max_scans) {
  SimulationSetting sim;
  sim.seed = seed;
  sim.max_scans = max_scans;
  return sim;
}

}  // namespace nbs::test
