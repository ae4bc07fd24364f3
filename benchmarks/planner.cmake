# SPDX-License-Identifier: BSD-3-Clause
# Planner (issue 5): bench_planner — t_nbs of C_H on the bunny at 160 mm, Tab. 4.3, 2 threads. Needs Embree.
if(TARGET nbs::embree)
  nbs_add_benchmark(planner SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_planner.cpp LIBS nbs::embree)
endif()
# nbs_diagnose: research tool (not run by scripts/bench.sh) — true gain of every candidate vs its utility.
# Its options: tools/common/options.hpp (CLI11).
if(TARGET nbs::embree AND TARGET nbs_tool_options AND NOT TARGET nbs_diagnose)
  add_executable(nbs_diagnose ${CMAKE_CURRENT_LIST_DIR}/nbs_diagnose.cpp)
  target_link_libraries(nbs_diagnose PRIVATE nbs::nbs nbs::embree nbs_tool_options)
endif()
